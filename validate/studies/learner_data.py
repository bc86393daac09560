"""Train/test data for the learner studies: two twin runs observed by dense virtual surface sensors.

:func:`build_data` simulates a training and a test scenario on one machine with the machine's own
sensor sites plus a :func:`twin.observe.sensor_grid.surface_sensor_grid` of virtual sensors, caches each
run as NetCDF in the output folder (a re-run with the same settings reads the files back), and
returns the learners' matrices:

- inputs ``X`` [degC]: the *measured* temperatures (sensor model: lag, noise, quantisation; see
  :mod:`twin.observe.instruments`) as rises over each sensor's first reading, as seed 001 uses
  "temperature changes";
- targets ``y[axis]`` [um]: the *true* tool-point drift (``drift`` of the result, tool relative to
  the table), axis ``X``, ``Y`` or ``Z``.

Candidate sensors for selection (``candidates``) are the grid's names; the machine's own sites
(``sites``, e.g. ``motor``, ``spindle_boss``) are kept in the same matrices for comparisons.

Camera mode (``camera="carrier-front"``, seed 001's own pipeline): the runs carry a thermal camera
at that pose (frames at every sample, :mod:`twin.observe.camera`) instead of the grid, and the
candidates are seed 001's 525 virtual spots, averaged 5 x 5 pixel groups along 21 lines across
the pose's subject part (:mod:`twin.observe.spots`), read from the *apparent* temperatures of the
thermogram (noise, fixed pattern, banding, offset drift, emissivity and reflections included).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from twin.api import machine_by_name, simulate
from twin.io.results import write_netcdf
from twin.observe.camera import CameraConfig
from twin.observe.sensor_grid import surface_sensor_grid
from twin.observe.spots import spot_layout, spot_series
from twin.scenario import Scenario, load_scenario

__all__ = ["StudyData", "build_data", "build_camera_data", "cached_run", "temperature_rise"]

TRAIN, TEST = "spindle-heat-cool-9000", "spindle-duty-cycle"
GRID_PARTS = ("carrier", "column", "test_bar")


@dataclass
class StudyData:
    """Matrices of one train/test pair. ``X_*`` (time, sensor) [degC rise], ``y_*[axis]`` (time,) [um]."""

    names: list[str]
    candidates: list[str]
    sites: list[str]
    X_train: np.ndarray
    X_test: np.ndarray
    y_train: dict
    y_test: dict
    t_train: np.ndarray
    t_test: np.ndarray
    paths: list[Path] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def columns(self, names) -> list[int]:
        """Column indices of ``names`` in ``X_*``."""
        index = {n: i for i, n in enumerate(self.names)}
        return [index[n] for n in names]

    @property
    def candidate_columns(self) -> list[int]:
        return self.columns(self.candidates)


def temperature_rise(ds: xr.Dataset) -> np.ndarray:
    """Measured temperature minus each sensor's first measured reading [degC], (time, sensor)."""
    t = ds["temperature"].transpose("time", "sensor").values
    return t - t[0]


def _key(settings: dict) -> str:
    return hashlib.sha1(json.dumps(settings, sort_keys=True).encode()).hexdigest()[:10]


def cached_run(path: Path, machine: str, scenario: Scenario, resolution: str, seed: int, sensors: list,
               cameras: tuple = ()) -> xr.Dataset:
    """Simulate (or read back from ``path``) one run; the cache is trusted when ``path`` exists and
    its ``study_key`` attribute matches the settings (machine, scenario, mesh, seed, sensor names,
    cameras)."""
    settings = {"machine": machine, "scenario": repr(scenario.steps), "ambient": repr(scenario.ambient),
                "dt": scenario.sample_interval, "t0": scenario.initial_temperature, "mesh": resolution, "seed": seed,
                "sensors": [(p.name, p.xyz) for p in sensors], **({"cameras": repr(cameras)} if cameras else {})}
    key = _key(settings)
    if path.exists():
        with xr.open_dataset(path) as ds:
            if ds.attrs.get("study_key") == key:
                return ds.load()
    ds, _ = simulate(machine, scenario, resolution=resolution, seed=seed, sensors=sensors, cameras=list(cameras))
    ds.attrs["study_key"] = key
    path.parent.mkdir(parents=True, exist_ok=True)
    write_netcdf(ds, path)
    with xr.open_dataset(path) as stored:  # as a later run reads it (a thermogram is stored in steps
        return stored.load()               # of ~0.01 K): the same inputs whether simulated or cached


def build_data(outdir, resolution: str = "default", machine: str = "cframe-vmc", train: str | Scenario = TRAIN,
               test: str | Scenario = TEST, parts=GRID_PARTS, spacing: float = 0.05, seed: int = 0) -> StudyData:
    """Simulate (or reuse) the train and test runs with dense sensors; return :class:`StudyData`.

    ``spacing`` [m] is the grid pitch on the exterior faces of ``parts``; ``seed`` seeds the
    instrument noise (the test run uses ``seed + 1`` so the two noise draws differ).
    """
    outdir = Path(outdir)
    m = machine_by_name(machine)
    grid = surface_sensor_grid(m, parts=parts, spacing=spacing)
    sites = [m.point(n) for n in m.sensor_sites]
    sensors = sites + grid
    runs = []
    for role, sc, s in (("train", train, seed), ("test", test, seed + 1)):
        sc = sc if isinstance(sc, Scenario) else load_scenario(sc)
        path = outdir / f"{role}_{sc.name}_{resolution}.nc"
        runs.append((cached_run(path, machine, sc, resolution, s, sensors), path))
    (tr, p_tr), (te, p_te) = runs
    names = [p.name for p in sensors]
    return StudyData(
        names=names, candidates=[p.name for p in grid], sites=[p.name for p in sites],
        X_train=temperature_rise(tr), X_test=temperature_rise(te),
        y_train={a: tr["drift"].sel(axis=a).values.copy() for a in "XYZ"},
        y_test={a: te["drift"].sel(axis=a).values.copy() for a in "XYZ"},
        t_train=tr["time"].values.copy(), t_test=te["time"].values.copy(), paths=[p_tr, p_te],
        info={"machine": machine, "mesh": resolution, "train": tr.attrs["scenario"], "test": te.attrs["scenario"],
              "n_grid": len(grid), "spacing_m": spacing, "mesh_nodes": int(tr.attrs["mesh_nodes"]), "seed": seed},
    )


def build_camera_data(outdir, resolution: str = "default", machine: str = "cframe-vmc", train: str | Scenario = TRAIN,
                      test: str | Scenario = TEST, pose: str = "carrier-front", lines: int = 21, per_line: int = 25,
                      size: int = 5, seed: int = 0) -> StudyData:
    """Seed 001's pipeline from camera frames: simulate (or reuse) the train and test runs with a
    camera at ``pose`` and the machine's own sensor sites, lay ``lines`` x ``per_line`` spots of
    ``size`` x ``size`` pixels on the pose's subject part, and return :class:`StudyData` whose
    candidates are the spots' apparent-temperature rises [degC] (first frame subtracted)."""
    outdir = Path(outdir)
    m = machine_by_name(machine)
    sites = [m.point(n) for n in m.sensor_sites]
    camera = CameraConfig(pose=pose)
    subject = camera.resolve_pose(m).subject
    runs = []
    for role, sc, s in (("train", train, seed), ("test", test, seed + 1)):
        sc = sc if isinstance(sc, Scenario) else load_scenario(sc)
        path = outdir / f"{role}_{sc.name}_{resolution}_camera-{pose}.nc"
        runs.append((cached_run(path, machine, sc, resolution, s, sites, (camera,)), path))
    (tr, p_tr), (te, p_te) = runs
    parts = tr["part_true"].attrs["flag_meanings"].split()
    spots = spot_layout(tr["part_true"].values, parts.index(subject), lines, per_line, size)

    def inputs(ds):
        if not np.array_equal(ds["frame_time"].values, ds["time"].values):
            raise ValueError("the study needs a frame at every sample")
        s_ = spot_series(ds["thermogram"].values, spots)
        return np.column_stack([temperature_rise(ds), s_ - s_[0]])

    return StudyData(
        names=[p.name for p in sites] + [s_.name for s_ in spots], candidates=[s_.name for s_ in spots],
        sites=[p.name for p in sites], X_train=inputs(tr), X_test=inputs(te),
        y_train={a: tr["drift"].sel(axis=a).values.copy() for a in "XYZ"},
        y_test={a: te["drift"].sel(axis=a).values.copy() for a in "XYZ"},
        t_train=tr["time"].values.copy(), t_test=te["time"].values.copy(), paths=[p_tr, p_te],
        info={"machine": machine, "mesh": resolution, "train": tr.attrs["scenario"], "test": te.attrs["scenario"],
              "n_grid": len(spots), "mesh_nodes": int(tr.attrs["mesh_nodes"]), "seed": seed, "mode": "camera",
              "pose": pose, "subject": subject, "spot_size_px": size, "lines": lines, "per_line": per_line,
              "spots": spots},
    )


if __name__ == "__main__":
    from validate.studies.not_a_study import not_a_command

    not_a_command("validate.studies.learner_data")
