"""Package a run as one xarray Dataset (CF units and long names) and write it atomically.

Schema: ``time`` [s]; ``spindle_speed`` [rpm]; ``ambient_temperature`` [degC];
``temperature(time, sensor)`` as measured and ``temperature_true`` [degC] with sensor coordinates
``x, y, z`` [m] and ``part``; ``probe(time, probe_id)`` [um] for X1 X2 Y1 Y2 Z and ``probe_true``;
``probe_drift(time, axis)`` [um] derived from the probe readings; ``drift(time, axis)`` [um], the
true tool-point drift (tool relative to the table); ``tilt(time, rotation)`` [urad] for A, B from
the probe readings and ``tilt_true``; ``heat_power(time, effect)`` [W] into the structure.
(The probe dimension is ``probe_id`` because xarray forbids a variable named like its dimension.)
"""

from __future__ import annotations

import json
import os
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np
import xarray as xr

from twin.io.atomic import atomic_write
from twin.observe.instruments import probe_reading, temperature_reading
from twin.simulate import AXES, RunResult


def package_version() -> str:
    try:
        return version("thermal-twin")
    except PackageNotFoundError:  # running from a source tree
        return "0+unknown"


def _var(dims, data, units, long_name):
    return (dims, np.asarray(data), {"units": units, "long_name": long_name})


def probe_geometry(machine) -> tuple[float, float, float]:
    """(z of the X1/Y1 probes, z of X2/Y2, z of the tool point) [m]."""
    return machine.point("X1").xyz[2], machine.point("X2").xyz[2], machine.point(machine.tool_point).xyz[2]


def derived_from_probes(probe_um: np.ndarray, names: list[str], machine) -> tuple[np.ndarray, np.ndarray]:
    """ISO 230-3 five-probe evaluation: drift at the tool point [um] and tilts A, B [urad].

    A (about X) = (Y1 - Y2) / d, B (about Y) = (X2 - X1) / d, d the probe spacing [m]; X and Y are
    extrapolated linearly from the two heights to the tool point, Z is the end probe.
    """
    col = {n: probe_um[:, i] for i, n in enumerate(names)}
    z1, z2, zt = probe_geometry(machine)
    d = z2 - z1
    ext = (z1 - zt) / d
    x = col["X1"] + (col["X1"] - col["X2"]) * ext
    y = col["Y1"] + (col["Y1"] - col["Y2"]) * ext
    tilt = np.column_stack([(col["Y1"] - col["Y2"]) / d, (col["X2"] - col["X1"]) / d])
    return np.column_stack([x, y, col["Z"]]), tilt


def to_dataset(r: RunResult, seed: int = 0, resolution: str = "", scenario_label: str = "") -> xr.Dataset:
    """Apply the instrument models (seeded) and build the result Dataset."""
    machine, spec, sc = r.mm.machine, r.spec, r.scenario
    rng = np.random.default_rng(seed)
    dt = sc.sample_interval
    sensors = r.sensors
    names = [p.name for p in machine.probes]
    temp_meas = temperature_reading(r.sensor_true, dt, spec.params["temperature_sensor"], rng)
    probe_true = r.probe * 1e6
    probe_meas = probe_reading(probe_true, spec.params["probe"], rng)
    pdrift, tilt = derived_from_probes(probe_meas, names, machine)
    _, tilt_true = derived_from_probes(probe_true, names, machine)

    src, conv = r.heat_flows()
    effects = list(spec.effects)
    power = np.zeros((len(r.times), len(effects)))
    for j, e in enumerate(r.loads.source_effect):
        power[:, effects.index(e)] += src[:, j]
    for j, e in enumerate(r.loads.convection_effect):
        power[:, effects.index(e)] += conv[:, j]

    params = {g: {p.name: f"{vals[p.name]:.6g} {p.unit}".strip() for p in spec.parameter_table(g)}
              for g, vals in spec.params.items()}
    ds = xr.Dataset(
        data_vars={
            "spindle_speed": _var("time", sc.spindle_speed(r.times), "rpm", "spindle speed"),
            "ambient_temperature": _var("time", sc.ambient_temperature(r.times), "degC", "room air temperature"),
            "temperature": _var(("time", "sensor"), temp_meas, "degC", "temperature as measured (sensor model)"),
            "temperature_true": _var(("time", "sensor"), r.sensor_true, "degC", "true temperature at the sensor site"),
            "probe": _var(("time", "probe_id"), probe_meas, "um", "ISO 230-3 probe reading as measured"),
            "probe_true": _var(("time", "probe_id"), probe_true, "um", "true probe reading"),
            "probe_drift": _var(("time", "axis"), pdrift, "um", "tool-point drift derived from the probe readings"),
            "drift": _var(("time", "axis"), r.drift * 1e6, "um", "true tool-point drift, tool relative to table"),
            "tilt": _var(("time", "rotation"), tilt, "urad", "test-bar tilt from the probe readings (A about X, B about Y)"),
            "tilt_true": _var(("time", "rotation"), tilt_true, "urad", "true test-bar tilt"),
            "heat_power": _var(("time", "effect"), power, "W", "heat flow into the structure per effect"),
        },
        coords={
            "time": ("time", r.times, {"units": "s", "long_name": "time since start"}),
            "sensor": ("sensor", [p.name for p in sensors], {"long_name": "temperature sensor site"}),
            "x": ("sensor", [p.xyz[0] for p in sensors], {"units": "m", "long_name": "sensor x"}),
            "y": ("sensor", [p.xyz[1] for p in sensors], {"units": "m", "long_name": "sensor y"}),
            "z": ("sensor", [p.xyz[2] for p in sensors], {"units": "m", "long_name": "sensor z"}),
            "part": ("sensor", [p.part for p in sensors], {"long_name": "part carrying the sensor"}),
            "probe_id": ("probe_id", names, {"long_name": "ISO 230-3 probe"}),
            "axis": ("axis", list(AXES), {"long_name": "machine axis"}),
            "rotation": ("rotation", ["A", "B"], {"long_name": "rotation about X (A) and Y (B)"}),
            "effect": ("effect", effects, {"long_name": "physical effect"}),
        },
        attrs={
            "title": f"thermal-twin simulation: {machine.name} / {sc.name}",
            "package_version": package_version(),
            "machine": machine.name,
            "scenario": scenario_label or sc.name,
            "scenario_source": sc.source,
            "effects": ",".join(effects),
            "parameters": json.dumps(params, sort_keys=True),
            "mesh": resolution,
            "mesh_nodes": r.mm.nnodes,
            "mesh_cells": r.mm.ncells,
            "seed": seed,
            "theta": r.theta,
            "time_step_s": dt,
            "reference_temperature_degC": sc.start_temperature,
            "hottest_time_s": r.hottest_time,
            "Conventions": "CF-1.8",
        },
    )
    return ds


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Write ``ds`` to ``path`` atomically (see :mod:`twin.io.atomic`)."""
    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf"))
