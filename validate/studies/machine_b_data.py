"""The seed's Machine B tests on ``belt-vmc``: Tests I-VI simulated once (cached) with the 77
temperature points, as the learner matrices of the Machine B studies.

Inputs: the *measured* temperatures T1..T77 (sensor model: lag, noise, quantisation; air points
read the model's air) as rises over each sensor's first reading [K]; target: the true tool-point
drift Y [um] (the seed's reference is the NCDT Y displacement; the probes' Y is within their
0.1 um resolution of it). Runs are cached as NetCDF in the study's folder
(:func:`validate.studies.learner_data.cached_run`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from geometries.belt_vmc import TEMPERATURE_POINTS
from twin.api import machine_by_name
from twin.observe import sensor_points
from twin.scenario import load_scenario
from validate.studies.learner_data import cached_run, temperature_rise

MACHINE = "belt-vmc"
TESTS = {"I": "belt-test-1", "II": "belt-test-2", "III": "belt-test-3", "IV": "belt-test-4",
         "V": "belt-test-5", "VI": "belt-test-6"}
# Table 4-4's groups (thesis L4457-4490); group 5 is "other" (air, bed, table)
GROUPS = {1: [1, 2, 3, 4, 5, 6, 7, 70, 71, 72], 2: list(range(8, 34)), 3: list(range(34, 63)), 4: [63, 64, 65],
          5: [66, 67, 68, 69, 73, 74, 75, 76, 77]}


@dataclass
class MachineBRun:
    """One test: time [s], temperature rises (n_t, 77) [K], true drift Y and Z [um]."""

    name: str
    scenario: str
    time: np.ndarray
    X: np.ndarray
    y: np.ndarray
    z: np.ndarray
    path: Path


def load_tests(outdir, resolution: str = "default", seed: int = 0, tests=tuple(TESTS)) -> dict[str, MachineBRun]:
    """Simulate (or read back) the seed's Tests I-VI on belt-vmc; the k-th test of :data:`TESTS` gets
    noise seed ``seed + k`` whichever tests are asked for."""
    m = machine_by_name(MACHINE)
    sensors = sensor_points(m)
    assert [p.name for p in sensors] == list(TEMPERATURE_POINTS)
    out = {}
    for name in tests:
        k = list(TESTS).index(name)
        sc = load_scenario(TESTS[name])
        path = Path(outdir) / f"{TESTS[name]}_{resolution}.nc"
        ds = cached_run(path, MACHINE, sc, resolution, seed + k, sensors)
        out[name] = MachineBRun(name, TESTS[name], ds["time"].values.copy(), temperature_rise(ds),
                                ds["drift"].sel(axis="Y").values.copy(), ds["drift"].sel(axis="Z").values.copy(), path)
    return out


def column(name: str) -> int:
    """Column of sensor ``name`` ("T5" or 5) in the 77-point matrices."""
    return TEMPERATURE_POINTS.index(name if isinstance(name, str) else f"T{name}")


if __name__ == "__main__":
    from validate.studies.not_a_study import not_a_command

    not_a_command("validate.studies.machine_b_data")
