"""Nothing lost in the house move: a short C-frame run held to gold values recorded from main
before the move (commit 9a2f06f), to 1e-9 relative of each quantity's range.

The run: ``cframe-vmc`` on the coarse mesh with two effects (spindle bearings, ambient
convection), 30 min at 9000 rpm then 20 min stopped, the room air rising linearly from 20 to
21.5 degC over 50 min, one step a minute. Gold file: ``tests/data/gold_cframe_coarse.json``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

GOLD = json.loads((Path(__file__).parent / "data" / "gold_cframe_coarse.json").read_text())


@pytest.fixture(scope="module")
def gold_run():
    from geometries import build_machine
    from twin.model import ModelSpec
    from twin.scenario import Ambient, Scenario
    from twin.simulate import run

    sc = GOLD["scenario"]
    times, temps = sc["ambient_table"]
    scenario = Scenario("gold-short", tuple(tuple(s) for s in sc["steps"]),
                        Ambient("table", times=tuple(times), temperatures=tuple(temps)), sc["sample_interval_s"])
    return run(build_machine(GOLD["machine"]), scenario, ModelSpec(tuple(GOLD["effects"])), resolution=GOLD["mesh"])


def _close(new, gold):
    new, gold = np.asarray(new, float), np.asarray(gold, float)
    assert new.shape == gold.shape
    scale = max(float(np.ptp(gold)), float(np.abs(gold).max()) * 1e-3, 1e-300)
    assert np.max(np.abs(new - gold)) <= 1e-9 * scale


def test_mesh_is_unchanged(gold_run):
    assert gold_run.mm.nnodes == GOLD["nodes"]
    assert [p.name for p in gold_run.sensors] == GOLD["sensors"]


@pytest.mark.parametrize("quantity", ["sensor_true_degC", "drift_m", "probe_m", "stored_heat_J"])
def test_outputs_equal_the_gold_values(gold_run, quantity):
    new = {"sensor_true_degC": gold_run.sensor_true, "drift_m": gold_run.drift, "probe_m": gold_run.probe,
           "stored_heat_J": gold_run.stored_heat}[quantity]
    _close(new, GOLD[quantity])
