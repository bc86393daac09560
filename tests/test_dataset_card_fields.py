"""twin/dataset fields no test read (mutation audit, item 12): a calibration run cut after its
``max_steps`` time steps, the dataset card's counts, mean case size, variable roles and solver
errors on hand-made index rows, and the index column ``ambient_coldest_at [s]``."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from tests.dataset_files import SPEC, write_spec
from twin.dataset import load_spec, plan


# --- the calibration run is cut short (runner._truncated) ----------------------------------------

def test_truncated_cuts_inside_the_step_where_max_steps_ends():
    """Steps 2 min at 1000 rpm and 5 min at 2000 rpm sampled at 60 s, cut after 3 steps (180 s):
    the first step whole (120 s), the second cut to the 60 s left; cut after 1 step, the first
    alone, cut to 60 s. Uncut, the calibration ran a whole 5-min step."""
    from twin.dataset.runner import _truncated
    from twin.scenario import scenario_from_dict

    sc = scenario_from_dict({"sample_interval": "60 s", "ambient": {"kind": "constant", "temperature": "20 degC"},
                             "spindle": [{"speed": "1000 rpm", "duration": "2 min"},
                                         {"speed": "2000 rpm", "duration": "5 min"}]}, "test")
    assert [tuple(s) for s in _truncated(sc, 3).steps] == [(120.0, 1000.0), (60.0, 2000.0)]
    assert [tuple(s) for s in _truncated(sc, 1).steps] == [(60.0, 1000.0)]
    assert [tuple(s) for s in _truncated(sc, 7).steps] == [(120.0, 1000.0), (300.0, 2000.0)]


def test_a_calibration_run_of_three_steps_has_four_samples(tmp_path):
    """The tiny spec's reference case is one 10-min step sampled at 60 s (11 samples whole):
    simulate_case with max_steps = 3 runs 3 steps, samples at 0, 60, 120, 180 s."""
    from twin.dataset.runner import simulate_case

    (ref,) = [c for c in plan(load_spec(write_spec(tmp_path))) if c.info["family"] == "reference"]
    ds, _ = simulate_case(ref.record, ref.hash, max_steps=3)
    assert ds.sizes["time"] == 4
    np.testing.assert_array_equal(ds.time.values, [0.0, 60.0, 120.0, 180.0])


# --- the dataset card (twin.dataset.card) ---------------------------------------------------------

def _case_file(path, errors: dict) -> None:
    """A stand-in case file: one ``temperature_true`` variable and ``rom_error_estimate`` ``errors``
    ({group: [value per output]}, SI) as a JSON attribute, as a reduced-model case carries it."""
    ds = xr.Dataset({"temperature_true": (("time",), np.zeros(2), {"units": "degC"})},
                    coords={"time": ("time", [0.0, 60.0], {"units": "s"})},
                    attrs={"rom_error_estimate": json.dumps(errors)})
    ds.to_netcdf(path, engine="h5netcdf")


@pytest.fixture
def card_of_three(tmp_path):
    """card() of three hand-made index rows: duty/train built (100 bytes), duty/test not built,
    reference/test built (300 bytes); the built files report rom_error_estimate
    a: drift [1e-6, -3e-6] m, probes [2e-6] m, temperature [0.02] K;
    b: drift [2e-6] m, probes [-4e-6, 1e-6] m, temperature [0.01] K."""
    from twin.dataset.card import card

    spec = load_spec(write_spec(tmp_path))
    (tmp_path / "cases").mkdir()
    _case_file(tmp_path / "cases" / "a.nc", {"drift": [1e-6, -3e-6], "probes": [2e-6], "temperature": [0.02]})
    _case_file(tmp_path / "cases" / "b.nc", {"drift": [2e-6], "probes": [-4e-6, 1e-6], "temperature": [0.01]})
    rows = [{"hash": "a", "file": "cases/a.nc", "split": "train", "built": True, "bytes": 100, "family": "duty"},
            {"hash": "n", "file": "cases/missing.nc", "split": "test", "built": False, "bytes": 0, "family": "duty"},
            {"hash": "b", "file": "cases/b.nc", "split": "test", "built": True, "bytes": 300, "family": "reference"}]
    return card(spec, rows, tmp_path)


def test_card_counts_built_cases_per_split_and_family(card_of_three):
    """planned counts every row, built only the rows whose file is whole: duty 2 planned, 1 built;
    reference 1 and 1; train 1 and 1; test 2 and 1; in all 3 planned, 2 built."""
    counts = card_of_three["counts"]
    assert (counts["planned"], counts["built"]) == (3, 2)
    assert counts["by_family"] == {"duty": {"planned": 2, "built": 1}, "reference": {"planned": 1, "built": 1}}
    assert counts["by_split"] == {"train": {"planned": 1, "built": 1}, "test": {"planned": 2, "built": 1}}


def test_card_mean_case_size_is_over_the_built_cases(card_of_three):
    """bytes = 100 + 300 = 400 over the 2 built cases: 200 per case (over all 3 rows it would be 133)."""
    assert card_of_three["sizes"] == {"bytes": 400, "mean_case_bytes": 200}


def test_card_solver_error_is_the_largest_magnitude_over_cases_in_its_unit(card_of_three):
    """Per group the largest |value| over every output of every built case: drift max(1, 3, 2) um
    = 1e6 x 3e-6 m (not the sum 3 + 2 over the cases), probes max(2, 4, 1) um = 1e6 x 4e-6 m
    (a probe error in m would read 4e-6), temperature max(0.02, 0.01) K (factor 1)."""
    est = card_of_three["solver_error"]["rom_error_estimate"]
    assert set(card_of_three["solver_error"]) == {"rom_error_estimate"}
    assert est["drift"] == {"max": pytest.approx(1e6 * 3e-6, rel=1e-12), "units": "um"}
    assert est["probes"] == {"max": pytest.approx(1e6 * 4e-6, rel=1e-12), "units": "um"}
    assert est["temperature"] == {"max": 0.02, "units": "K"}


def test_variables_ending_in_true_are_truth():
    """The card's rule (TRUTH_NOTE): *_true variables, drift and heat_power are truth; the inputs
    spindle_speed and ambient_temperature are inputs; the instruments' readings are measured."""
    from twin.dataset.card import role

    assert [role(n) for n in ("temperature_true", "probe_true", "tilt_true", "drift", "heat_power")] == ["truth"] * 5
    assert [role(n) for n in ("spindle_speed", "ambient_temperature")] == ["input"] * 2
    assert [role(n) for n in ("temperature", "probe", "probe_drift", "tilt")] == ["measured"] * 4


def test_card_schema_labels_a_true_variable_truth(card_of_three):
    """The schema is read from the first built case file (a.nc): its temperature_true is truth."""
    schema = {s["name"]: s for s in card_of_three["schema"]}
    assert schema["temperature_true"]["role"] == "truth" and schema["temperature_true"]["units"] == "degC"
    assert schema["time"]["role"] == "coordinate"


# --- the index column ambient_coldest_at (twin.dataset.plan) --------------------------------------

def test_index_ambient_coldest_at_is_the_daily_rooms_coldest_time_of_day(tmp_path):
    """A daily room with coldest_at = "7 h": every duty case's index row says 7 x 3600 = 25200 s;
    drawn from ["0 h", "24 h"] (the tiny spec), each row holds its case's own drawn time; the
    reference case's constant room has no coldest time: 0."""
    from twin.units import parse_quantity

    fixed = load_spec(write_spec(tmp_path, SPEC.replace('coldest_at = ["0 h", "24 h"]', 'coldest_at = "7 h"')))
    cases = plan(fixed)
    assert [(c.info["family"], c.info["ambient_coldest_at [s]"]) for c in cases] == [
        ("duty", 25200.0), ("duty", 25200.0), ("reference", 0.0)]
    drawn = [c for c in plan(load_spec(write_spec(tmp_path))) if c.info["family"] == "duty"]
    for c in drawn:
        assert c.info["ambient_coldest_at [s]"] == parse_quantity(c.record["scenario"]["ambient"]["coldest_at"], "time")
    assert len({c.info["ambient_coldest_at [s]"] for c in drawn}) == 2
    assert all(0.0 < c.info["ambient_coldest_at [s]"] < 86400.0 for c in drawn)
