"""Bad arguments to the Python API found by a sweep of its functions: each one
:class:`twin.errors.InputError` naming the argument, never a TypeError or AttributeError from
inside, a flag's text taken by its truthiness, or a value silently read as another."""

from __future__ import annotations

import numpy as np
import pytest

from tests.fuzz_files import result_dataset
from twin.errors import InputError
from twin.scenario import Ambient, Scenario

SHORT = Scenario("s", ((300.0, 3000.0),), Ambient("constant", mean=20.0), 60.0)


def _refused(call, field: str):
    with pytest.raises(InputError) as err:
        call()
    assert err.value.field == field, err.value
    return err.value


@pytest.fixture(scope="module")
def coarse():
    from geometries import build_machine
    from twin.physics.prepared import PreparedTwin
    machine = build_machine("cframe-vmc")
    return machine, PreparedTwin(machine, resolution="coarse")


def test_names_given_as_lists_and_machines_given_as_names():
    from learners import make_learner, make_selector
    from twin.fem.mesh import build_mesh
    from twin.model import ModelSpec
    _refused(lambda: ModelSpec((["floor"],)), "--effects")
    _refused(lambda: make_learner(["mlr"]), "learner")
    _refused(lambda: make_selector(["all"]), "selector")
    _refused(lambda: build_mesh("cframe-vmc", 0.1), "machine")
    _refused(lambda: build_mesh(None, 0.1), "machine")
    _refused(lambda: Scenario("s", ((300.0, 0.0),), Ambient(["constant"]), 60.0).check(), "ambient.kind")
    _refused(lambda: Scenario("s", ((300.0, 0.0),), Ambient("constant", mean=20.0, times=np.array([0.0, 600.0])),
                              60.0).check(), "ambient.times")


@pytest.mark.parametrize("solver", ["", 0, False, []])
def test_a_falsy_solver_is_not_auto(solver):
    from twin.physics.options import as_options
    _refused(lambda: as_options(solver), "--solver")


def test_a_runs_flags_and_hooks_are_checked_before_any_work(coarse):
    from twin.model import model_spec
    from twin.observe import standard_observers
    machine, twin = coarse
    obs = standard_observers(machine)
    draft = model_spec(machine, "+door_draft", ["door_draft.start=2 h"])
    # "no" is true in Python: it switched the refusal of an idle door draft off
    _refused(lambda: twin.run(SHORT, draft, obs, idle_effects="no"), "idle_effects")
    _refused(lambda: twin.run(SHORT, model_spec(machine), obs, plausible=3), "plausible")
    _refused(lambda: twin.run(SHORT, model_spec(machine), obs, progress=5), "progress")
    _refused(lambda: twin.run(SHORT, model_spec(machine), obs, on_step=5), "on_step")
    _refused(lambda: twin.run_batch([(SHORT, model_spec(machine))], obs, bound="no"), "bound")


def test_a_measurement_built_in_python_is_checked_as_a_file_is():
    from geometries import build_machine
    from twin.io.measurement import check_measurement
    ds = result_dataset()
    bad = ds.copy(deep=True)
    bad["drift"][2, 0] = np.nan
    assert "NaN" in _refused(lambda: check_measurement(bad, None, "m"), "drift").message
    _refused(lambda: check_measurement(ds, "cframe-vmc", "m"), "machine")
    check_measurement(ds, build_machine("cframe-vmc"), "m")
    text_times = ds.assign_coords(time=[str(t) for t in ds.time.values])
    _refused(lambda: check_measurement(text_times, None, "m"), "time")


def test_measurement_files_arguments(tmp_path):
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement
    from geometries import build_machine
    ds = result_dataset()
    _refused(lambda: write_measurement(ds, tmp_path, "m2.csv", "cframe-vmc"), "stem")
    assert "pass its name" in _refused(lambda: write_measurement(ds, tmp_path, "m1", build_machine("cframe-vmc")),
                                       "machine").message
    assert not any(tmp_path.iterdir())
    csv, _ = write_measurement(ds, tmp_path, "m1", "cframe-vmc")
    _refused(lambda: read_measurement(csv, mapping=5), "--mapping")
    _refused(lambda: read_measurement(csv, mapping=["m1.toml"]), "--mapping")


def test_an_effects_file_argument_is_named_as_its_option():
    from twin.api import simulate
    _refused(lambda: simulate("cframe-vmc", SHORT, resolution="coarse", effects_file=5), "--effects-file")
    _refused(lambda: simulate("cframe-vmc", SHORT, resolution="coarse", effects_file=""), "--effects-file")


def test_learners_refuse_text_and_a_bad_seed_when_built():
    from learners import make_learner, make_selector
    X = np.random.default_rng(0).random((20, 3))
    y = X @ [1.0, 2.0, 3.0]
    _refused(lambda: make_learner("mlr").fit(X.astype(str), y), "X")
    _refused(lambda: make_learner("mlr").fit(X, y.astype(str)), "y")
    _refused(lambda: make_learner("gm1n").fit(X.astype(str), y), "X")
    _refused(lambda: make_learner("mlr").fit(X, y).predict(X.astype(str)), "X")
    for seed in (-1, 1.0, True, "0"):
        _refused(lambda: make_learner("ann", random_state=seed), "random_state")
        _refused(lambda: make_selector("gm0n-fcm", random_state=seed), "random_state")


def test_a_diagnosis_refuses_repeats_and_inapplicable_effects_before_the_mesh(monkeypatch):
    from geometries import build_machine
    from twin.model import model_spec
    import validate.diagnose as D
    monkeypatch.setattr(D, "PreparedTwin", lambda *a, **k: (_ for _ in ()).throw(AssertionError("meshed first")))
    machine = build_machine("cframe-vmc")
    ds = result_dataset()
    sc = Scenario("s", ((1800.0, 6000.0),), Ambient("constant", mean=20.0), 60.0)
    _refused(lambda: D.diagnose(ds, machine, sc, candidates=["electrical_cabinet", "electrical_cabinet"]),
             "candidates[1]")
    _refused(lambda: D.diagnose_many([("a", ds, sc), ("a", ds, sc)], machine), "measurements[1]")
    _refused(lambda: D.diagnose_many([("a", ds, sc), ("b", ds, sc)], machine), "measurements[1]")
    _refused(lambda: D.diagnose(ds, machine, sc, candidates=["belt_drive"]), "candidates[0]")
    _refused(lambda: D.diagnose(ds, machine, sc, spec=model_spec(build_machine("belt-vmc"))), "--effects belt_drive")


def test_a_diagnosis_refuses_a_scenario_shorter_than_its_measurement_before_the_mesh(monkeypatch):
    from geometries import build_machine
    import validate.diagnose as D
    monkeypatch.setattr(D, "PreparedTwin", lambda *a, **k: (_ for _ in ()).throw(AssertionError("meshed first")))
    short = Scenario("s", ((600.0, 6000.0),), Ambient("constant", mean=20.0), 60.0)
    err = _refused(lambda: D.diagnose(result_dataset(), build_machine("cframe-vmc"), short), "time")
    assert "spans 29 min, beyond its scenario's 10 min" in err.message
