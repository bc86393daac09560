"""The tiny dataset spec the ``twin dataset`` tests share (``tests/test_dataset.py``,
``tests/test_dataset_plan.py``): two random duty cycles and a reference scenario on the coarse
C-frame mesh, 10 minutes sampled once a minute; and the comparison of two built datasets' case
files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

SPEC = """\
name = "tiny"
description = "two random duty cycles and a reference scenario"
machines = ["cframe-vmc"]
mesh = "coarse"
seed = 3

[parameters]
"spindle_motor.power" = { uniform = ["40 W", "80 W"] }
"ambient_convection.h" = "7 W/m2K"

[[scenarios]]
family = "duty"
cases = 2
duration = "10 min"
sample_interval = "60 s"
[scenarios.spindle]
step = ["2 min", "5 min"]
speed = ["2000 rpm", "9000 rpm"]
speed_step = "500 rpm"
idle_probability = 0.3
[scenarios.ambient]
kind = "daily"
mean = ["18 degC", "22 degC"]
amplitude = ["0 K", "3 K"]
coldest_at = ["0 h", "24 h"]

[[scenarios]]
family = "reference"
file = "ref.toml"

[splits]
by = "case"
train = 0.5
test = 0.5
"""

REF = """\
name = "ref"
sample_interval = "60 s"
[ambient]
kind = "constant"
temperature = "20 degC"
[[spindle]]
speed = "6000 rpm"
duration = "10 min"
"""


def write_spec(folder: Path, text: str = SPEC) -> Path:
    (folder / "ref.toml").write_text(REF)
    path = folder / "tiny.toml"
    path.write_text(text)
    return path


def file_bytes(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted((folder / "cases").glob("*.nc"))}


def assert_same_cases(folder: Path, reference: Path, label: str = "") -> None:
    """The case files of ``folder`` are those of ``reference``: the same names, and each file
    byte-identical, or else (one CI run saw one file differ, not reproducible here: a last-bit
    difference of a vectorised reduction is the suspect) the same attributes exactly and every
    variable equal to 1e-12 of its largest value; the assertion names the variable that differs."""
    got, want = file_bytes(folder), file_bytes(reference)
    assert sorted(got) == sorted(want), label
    for name in want:
        if got[name] == want[name]:
            continue
        with xr.open_dataset(folder / "cases" / name, engine="h5netcdf") as a, \
                xr.open_dataset(reference / "cases" / name, engine="h5netcdf") as b:
            assert a.attrs == b.attrs, f"{label} {name}: attributes differ"
            assert sorted(a.variables) == sorted(b.variables), f"{label} {name}"
            for v in b.variables:
                x, y = a[v].values, b[v].values
                if y.dtype.kind not in "fc":
                    assert np.array_equal(x, y), f"{label} {name}: {v} differs"
                    continue
                scale = float(np.nanmax(np.abs(y))) if np.isfinite(y).any() else 0.0
                assert np.allclose(x, y, rtol=0.0, atol=1e-12 * scale, equal_nan=True), \
                    f"{label} {name}: {v} differs by {float(np.nanmax(np.abs(x - y)))} (largest {scale})"


def fake_estimate_clock(monkeypatch, prepare_s: float = 2.0, start_s: float = 0.3, step_s: float = 0.002):
    """:mod:`twin.dataset.estimate` on a fake clock: preparing a twin takes ``prepare_s`` and a run
    of n steps ``start_s + step_s n``. Returns (the module, the list of the keys it prepared)."""
    import importlib

    module = importlib.import_module("twin.dataset.estimate")   # the package re-exports the function by this name
    clock, keys = [0.0], []

    class Clock:
        @staticmethod
        def perf_counter():
            return clock[0]

    def prepared(*key):
        keys.append(key)
        clock[0] += prepare_s

    def simulate_case(record, name, steps):
        clock[0] += start_s + step_s * steps

    monkeypatch.setattr(module, "time", Clock)
    monkeypatch.setattr(module, "_prepared", prepared)
    monkeypatch.setattr(module, "simulate_case", simulate_case)
    return module, keys
