"""Bad input to the learners and to the dataset Python API: one clear :class:`InputError` naming the
parameter, before any work, never a NaN result or a silently clipped count (issues 11, 12, 13, 17)."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from sklearn.base import clone

from learners import LEARNERS, make_learner, make_selector
from learners.grey import gm11_forecast
from learners.metrics import score_all
from twin.errors import InputError


def _data(n=30, p=3, seed=0):
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(n, p)).cumsum(axis=0) + 20.0
    return X, X @ np.arange(1.0, p + 1.0) + 0.1 * rng.normal(size=n)


def _refused(call, field, match=None):
    with pytest.raises(InputError, match=match) as err:
        call()
    assert err.value.field == field, str(err.value)
    return err.value


# --- issue 11: a dataset spec's surface grid --------------------------------------------------------------------

SPEC = {"name": "t", "machines": ["cframe-vmc"], "mesh": "coarse",
        "observers": {"surface_grid": {"parts": ["carrier"], "spacing": "150 mm"}},
        "scenarios": [{"family": "f", "duration": "10 min", "sample_interval": "60 s",
                       "spindle": {"step": ["2 min", "5 min"], "speed": ["1000 rpm", "2000 rpm"]},
                       "ambient": {"kind": "constant", "temperature": "20 degC"}}]}


@pytest.mark.parametrize("observers, field, match", [
    ({"surface_grid": {"parts": ["carrier", "carrier"], "spacing": "150 mm"}}, "observers.surface_grid.parts",
     "'carrier' is named more than once"),
    ({"surface_grid": {"parts": [], "spacing": "150 mm"}}, "observers.surface_grid.parts", "names no part"),
    ({"surface_grid": {"parts": [3], "spacing": "150 mm"}}, "observers.surface_grid.parts[0]", "part name"),
    ({"cameras": ["carrier-front", "carrier-front"]}, "observers.cameras", "more than once"),
])
def test_spec_refuses_a_repeated_or_empty_grid_part_list(observers, field, match):
    from twin.dataset.spec import spec_from_dict

    spec = copy.deepcopy(SPEC)
    spec["observers"] = observers
    err = _refused(lambda: spec_from_dict(spec, "spec.toml"), field, match)
    assert err.source == "spec.toml"


# --- issue 12: grey models and scores never return NaN --------------------------------------------------------------

def test_grey_models_refuse_nan_starts_bad_horizons_and_overflow():
    k = np.arange(20.0)
    gm = make_learner("gm11").fit(np.zeros((20, 1)), np.exp(0.5 * k) + 1.0)
    err = _refused(lambda: gm.predict(np.zeros((5000, 1))), "X", "diverges over this horizon")
    assert "at most" in err.message
    assert np.all(np.isfinite(gm.predict(np.zeros((50, 1)))))          # a shorter horizon is fine
    for steps in (-5, 0, 2.7, True):
        _refused(lambda: gm.forecast(steps), "steps")
        _refused(lambda: gm11_forecast(np.exp(0.5 * k) + 1.0, steps), "steps")
    _refused(lambda: gm.forecast(3000), "steps", "diverges")
    assert gm.forecast(2).shape == (2,)

    X, y = _data(20, 2)
    for name, y0 in (("gm11", np.nan), ("gm1n", np.nan), ("gmc1n", np.inf), ("gmc1n-pso", -np.inf), ("gnnmci", np.nan)):
        _refused(lambda: make_learner(name, y0=y0), "y0")
        est = make_learner(name).set_params(y0=y0)                  # set_params skips the constructor: fit checks
        _refused(lambda: est.fit(X, y), "y0")


def test_score_all_refuses_non_finite_predictions_and_targets():
    y = np.arange(1.0, 6.0)
    bad = y.copy()
    bad[2] = np.nan
    _refused(lambda: score_all(y, bad), "y_pred", "not finite")
    _refused(lambda: score_all(np.where(y == 4.0, np.inf, y), y), "y_true", "not finite")
    assert all(np.isfinite(v) for v in score_all(y, y + 0.1).values())


# --- issue 13: hyper-parameters --------------------------------------------------------------------------------------

@pytest.mark.parametrize("name, params, field", [
    ("mlr", {"foo": 1}, "foo"),
    ("mlr", {"alpha": np.nan}, "alpha"),
    ("mlr", {"alpha": -1.0}, "alpha"),
    ("pcr", {"n_components": 1.5}, "n_components"),
    ("combination", {"degree": -1}, "degree"),
    ("combination", {"members": ("mlr", "nosuch")}, "members[1]"),
    ("lssvm", {"max_samples": 0}, "max_samples"),
    ("lssvm", {"sigma": np.inf}, "sigma"),
    ("anfis-fcm", {"learning_rate": np.nan}, "learning_rate"),
    ("anfis-grid", {"epochs": 2.5}, "epochs"),
    ("pso-bpnn", {"hidden_layer_sizes": (0,)}, "hidden_layer_sizes"),
    ("pso-bpnn", {"epochs": -5}, "epochs"),
    ("pso-bpnn", {"validation_fraction": 1.0}, "validation_fraction"),
    ("ann", {"shape": "3-0-1"}, "shape"),
    ("gmc1n-pso", {"n_particles": 0}, "n_particles"),
    ("gnnmci", {"variant": "bogus"}, "variant"),
    ("ar-temp", {"initial_residual": "bogus"}, "initial_residual"),
])
def test_learner_hyper_parameters_are_checked_when_built_and_at_fit(name, params, field):
    err = _refused(lambda: make_learner(name, **params), field)
    assert err.source == name
    if field in make_learner(name).get_params():
        est = make_learner(name).set_params(**params)        # stored unchanged (scikit-learn contract) ...
        kept = clone(est).get_params()[field]
        assert kept is params[field] or kept == params[field]
        X, y = _data()
        _refused(lambda: est.fit(X, y), field)               # ... and refused at fit, before any work


@pytest.mark.parametrize("name", sorted(LEARNERS))
def test_bad_training_and_prediction_tables_name_x_or_y(name):
    """NaN in X, a y of another length, a constant y and a prediction table of another width are
    each one InputError (a ValueError, as scikit-learn's contract asks) naming X or y, never
    scikit-learn's or numpy's own error from inside the fit."""
    X, y = _data(30, 3)
    nan_x = X.copy()
    nan_x[3, 1] = np.nan
    _refused(lambda: make_learner(name).fit(nan_x, y), "X")
    _refused(lambda: make_learner(name).fit(X, y[:-2]), "y")
    _refused(lambda: make_learner(name).fit(X, np.r_[np.nan, y[1:]]), "y")
    _refused(lambda: make_learner(name).fit(X, np.full(30, 1.5)), "y", "constant")
    if name != "gm11":                      # GM(1,1) forecasts its one series from the time axis alone
        fitted = make_learner(name).fit(X, y)
        _refused(lambda: fitted.predict(X[:, :2]), "X")


def test_unknown_parameter_lists_the_known_ones():
    err = _refused(lambda: make_learner("mlr", foo=1), "foo")
    assert "known: alpha" in err.message
    _refused(lambda: make_selector("all", n_select=4), "n_select", "known: none")


def test_counts_larger_than_the_columns_are_refused_not_clipped():
    X, y = _data(30, 3)
    _refused(lambda: make_learner("pcr", n_components=10).fit(X, y), "n_components", "only 3 input columns")
    assert make_learner("pcr", n_components=3).fit(X, y).n_components_ == 3
    for name in ("correlation", "fuzzy-r2", "hier-corr", "gm0n-fcm", "gra-fcm"):
        _refused(lambda: make_selector(name, n_select=10).fit(X, y), "n_select", "only 3 input columns")
        _refused(lambda: make_selector(name, n_select=0), "n_select")
        assert len(make_selector(name, n_select=3).fit(X, y).selected_) == 3


# --- issue 17: the dataset Python API -----------------------------------------------------------------------------

def test_dataset_api_refuses_bad_jobs_steps_and_folders(tmp_path):
    from twin.dataset import build, estimate, executor

    for steps in (0, -3, 2.5):
        _refused(lambda: estimate([], calibration_steps=steps), "calibration_steps")
    for length in (10, 2.5, "600"):                  # fewer than the 30 calibration steps, not whole
        _refused(lambda: estimate([], length_steps=length), "length_steps")
    for jobs in (0, -2, 2.5, True):
        _refused(lambda: executor(None, jobs), "jobs")
        _refused(lambda: estimate([], jobs=jobs), "jobs")
    with executor(None, 1) as pool:
        assert build([], tmp_path / "new", pool) == {}
    assert (tmp_path / "new" / "cases").is_dir()          # a folder that can be made in an existing one is made
    _refused(lambda: build([], tmp_path / "missing" / "deeper"), "folder", "does not exist")
    a_file = tmp_path / "file.txt"
    a_file.write_text("x")
    _refused(lambda: build([], a_file), "folder", "not a folder")
    for bad, field in (({"cases": None}, "cases"), ({"cases": [{"machine": "cframe-vmc"}]}, "cases"),
                       ({"pool": "x"}, "pool"), ({"progress": 5}, "progress")):
        args = {"cases": [], "folder": tmp_path / "not-made", **bad}
        _refused(lambda: build(**args), field)
        assert not (tmp_path / "not-made").exists()      # checked before the folder is made


def test_a_case_file_is_named_by_its_records_hash_only(tmp_path):
    """build_case writes ``<hash>.nc``: a hash that is not the record's (``../evil`` wrote outside
    the folder) is refused before the case runs."""
    from twin.dataset.plan import case_hash
    from twin.dataset.runner import build_case

    record = {"machine": "cframe-vmc"}
    for bad in ("../evil", case_hash({"machine": "belt-vmc"}), 5):
        _refused(lambda: build_case(record, bad, str(tmp_path)), "case_hash")
    assert not any(tmp_path.parent.glob("evil*")) and not any(tmp_path.iterdir())


def test_a_learner_built_by_name_is_seeded_unless_told():
    """make_learner gives a random-start learner random_state 0 (the API audit found anfis-fcm,
    ann, pso-bpnn, gnnmci and gmc1n-pso differing between identical fits): two builds fit alike;
    an explicit random_state, None included, is kept."""
    import numpy as np
    from learners import make_learner

    X = np.random.default_rng(0).standard_normal((60, 3))
    y = X @ np.array([1.0, 2.0, 3.0]) + 0.1
    for name in ("anfis-fcm", "ann"):
        assert make_learner(name).get_params()["random_state"] == 0
        np.testing.assert_array_equal(make_learner(name).fit(X, y).predict(X), make_learner(name).fit(X, y).predict(X))
    assert make_learner("ann", random_state=None).get_params()["random_state"] is None


def test_a_netcdf_table_naming_a_sensor_twice_is_refused(tmp_path, capsys):
    """Two temperature columns under one sensor name: which is the input cannot be told (the first
    was fed in twice, 'motor;motor;...'); refused as compare refuses it."""
    from tests.fuzz_files import result_dataset
    from twin.cli import main

    good = result_dataset()
    good.to_netcdf(tmp_path / "b.nc", engine="h5netcdf")
    twice = good.assign_coords(sensor=["motor", "motor", "bed_front"])
    twice.to_netcdf(tmp_path / "dup.nc", engine="h5netcdf")
    code = main(["learn", "--train", str(tmp_path / "dup.nc"), "--test", str(tmp_path / "b.nc"), "--target", "drift:Z",
                 "--learner", "mlr"])
    err = capsys.readouterr().err
    assert code == 2 and err == f"error: {tmp_path / 'dup.nc'}: sensor: sensor 'motor' appears twice\n"


@pytest.mark.parametrize("value, words", [(np.int64(7), "7"), (np.float32(0.5), "0.5"), (np.bool_(True), "the boolean true"),
                                          (np.zeros(3), "an array of 3 values"), (2.0, "2.0"), (np.float64(3.0), "3.0"),
                                          (1e300, "1e+300")])
def test_numpy_values_are_described_in_the_users_terms(value, words):
    """A NetCDF attribute comes back as a numpy scalar: described as the number, not its type
    ('expected a machine name, got int64'); a whole float keeps its point ('expected an integer,
    got 2' read as a contradiction)."""
    from twin.errors import describe
    assert describe(value) == words
