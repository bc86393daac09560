"""The README's Python example runs and says what the README says it prints; every TOML example of the README loads with the reader a user would give it to: the scenario
sections (camera, axis motion and interferometer, probing, ambient events) inside a minimal
scenario on the C-frame, the measurement mappings beside a three-row CSV of their columns, the
effects files on the C-frame, and the dataset spec. A renamed key or unit fails here, not for a
reader of the README."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from geometries import build_machine

README = Path(__file__).resolve().parent.parent / "README.md"
BASE = """name = "readme-example"
sample_interval = "60 s"
[ambient]
kind = "constant"
temperature = "20 degC"
[[spindle]]
speed = "0 rpm"
duration = "{duration}"
"""


def _blocks(language: str) -> list[str]:
    """The README's fenced blocks of ``language``."""
    blocks, block = [], None
    for line in README.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            if block is None:
                block = [] if line.strip() == "```" + language else False
            else:
                if block is not False:
                    blocks.append("\n".join(block))
                block = None
        elif block not in (None, False):
            block.append(line)
    return blocks


BLOCKS = _blocks("toml")


def _kind(data: dict) -> str:
    if "columns" in data:
        return "mapping"
    if "machines" in data:
        return "spec"
    if "effects" in data:
        return "effects"
    return "scenario"


def test_the_readme_has_each_kind_of_example():
    """The collector finds the README's nine examples of four kinds (a broken one would pass the rest)."""
    kinds = [_kind(tomllib.loads(b)) for b in BLOCKS]
    assert len(BLOCKS) >= 9 and set(kinds) == {"scenario", "mapping", "effects", "spec"}


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_a_readme_toml_example_loads(index, tmp_path):
    from twin.dataset.spec import spec_from_dict
    from twin.effects.custom import effects_from_dict
    from twin.io.measurement import read_measurement
    from twin.limits import check_scenario
    from twin.motion_checks import check_motions
    from twin.scenario import check_values, scenario_from_dict

    text = BLOCKS[index]
    data = tomllib.loads(text)
    kind = _kind(data)
    machine = build_machine("cframe-vmc")
    if kind == "scenario":      # long enough for every time the examples name (the winter door at 110 h)
        sc = scenario_from_dict(tomllib.loads(BASE.format(duration="160 h") + text), "README")
        check_values(sc)
        check_scenario(sc, machine)
        check_motions(sc, machine)
    elif kind == "mapping":
        columns = data["columns"]
        value = {"time": "{k}", "ambient_temperature": "20", "temperature": "20.5"}
        rows = [",".join(columns)] + [",".join(value.get(c["role"], "0").format(k=k) for c in columns.values())
                                      for k in range(3)]
        (tmp_path / "m.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
        (tmp_path / "m.toml").write_text(text, encoding="utf-8")
        ds = read_measurement(tmp_path / "m.csv")
        assert ds.sizes["time"] == 3
    elif kind == "effects":
        assert [e.name for e in effects_from_dict(data, "README", machine)] == list(data["effects"])
    else:
        assert spec_from_dict(data, "README", text=text).name == data["name"]


def test_the_readme_python_example_runs_and_its_drift_is_linear_in_the_power(capsys):
    """"From Python": the block runs as written (coarse mesh) and prints the peak Z of the default
    model and of three front-bearing powers; the drift is linear in a source's power (heat
    equation and thermoelasticity are linear, the loads proportional to P), so 100, 150, 200 W give
    equally spaced peaks (the peak's time does not move: it is the end of the heating hour), and
    150 W, the default, gives the first run's peak."""
    import re

    import numpy as np

    from twin.api import simulate

    (block,) = _blocks("python")
    names = {}
    exec(compile(block, "README.md", "exec"), names)
    out = capsys.readouterr().out
    first = float(re.search(r"peak Z (\S+) um", out).group(1))
    z = [float(v) for v in re.findall(r"^\d+ W (\S+) um$", out, re.M)]
    assert len(z) == 3 and z[1] == first
    assert "peak Z 29.0 um" in out and "200 W 36.8 um" in out        # the numbers the README quotes
    # the whole drift, not its printed peak: Z(200 W) - Z(150 W) = Z(150 W) - Z(100 W) to round-off
    series = [simulate("cframe-vmc", names["test"], settings=[f"spindle_bearings.front_power={p} W"],
                       prepared=names["prepared"])[0].drift.values for p in (100, 150, 200)]
    step = series[1] - series[0]
    np.testing.assert_allclose(series[2] - series[1], step, rtol=0, atol=1e-9 * np.abs(step).max())
    assert np.abs(step).max() > 1.0                                  # um: the power moves the drift
