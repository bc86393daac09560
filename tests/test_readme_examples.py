"""Every TOML example of the README loads with the reader a user would give it to: the scenario
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


def _toml_blocks() -> list[str]:
    blocks, block = [], None
    for line in README.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            if block is None:
                block = [] if line.strip() == "```toml" else False
            else:
                if block is not False:
                    blocks.append("\n".join(block))
                block = None
        elif block not in (None, False):
            block.append(line)
    return blocks


BLOCKS = _toml_blocks()


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
