"""twin/dataset behaviour that no test held (mutation audit of twin/dataset/): spec checks that
turned into silent acceptance, index and card columns, the hash's definition, the attributes and
encoding of a built case file, and the time estimate of a plan smaller than its workers.

Each test names the behaviour it protects; all run on the tiny spec of :mod:`tests.dataset_files`
(one case built, with a camera, on the coarse C-frame mesh)."""

from __future__ import annotations

import hashlib
import inspect
import json

import h5py
import pandas as pd
import pytest
import xarray as xr

from tests.dataset_files import SPEC, fake_estimate_clock, write_spec
from twin.dataset import build, load_spec, plan, write_index
from twin.errors import InputError

CASE_SPLITS = 'by = "case"\ntrain = 0.5\ntest = 0.5'
REFERENCE = '\n[[scenarios]]\nfamily = "reference"'
AXIS = '\n[[scenarios.axis]]\nname = "Y"\nrange = ["0 mm", "280 mm"]\nfeed = ["5 mm/s", "30 mm/s"]\n'


def _spec(tmp_path, text=SPEC):
    return load_spec(write_spec(tmp_path, text))


def _refused(tmp_path, text, field, message):
    """load_spec of ``text`` raises one InputError naming the spec file and ``field``."""
    assert text != SPEC
    path = write_spec(tmp_path, text)
    with pytest.raises(InputError) as err:
        load_spec(path)
    assert (err.value.source, err.value.field) == (str(path), field), str(err.value)
    assert message in err.value.message, str(err.value)


# --- spec checks ---------------------------------------------------------------------------------

def test_a_machine_named_twice_is_refused(tmp_path):
    """``machines = ["cframe-vmc", "cframe-vmc"]`` is an error on ``machines``: accepted, the
    machine's cases were planned twice under the same hashes (one file for two index rows)."""
    _refused(tmp_path, SPEC.replace('machines = ["cframe-vmc"]', 'machines = ["cframe-vmc", "cframe-vmc"]'),
             "machines", "named twice")


def test_splits_by_family_must_place_every_family_exactly_once(tmp_path):
    """``by = "family"``: a family in no split is refused on ``splits`` when the spec is read (it
    was a KeyError in the plan), and a family in two splits is refused (it landed silently in
    the last one, so a test family could be trained on)."""
    _refused(tmp_path, SPEC.replace(CASE_SPLITS, 'by = "family"\ntrain = ["duty"]'), "splits",
             "family 'reference' is in no split")
    _refused(tmp_path, SPEC.replace(CASE_SPLITS, 'by = "family"\ntrain = ["duty", "reference"]\ntest = ["reference"]'),
             "splits", "family 'reference' is in more than one split")


def test_the_case_limit_counts_every_grid_point(tmp_path):
    """The plan's size is machines x grid points x draws: (50 000 + 1 reference) draws x a 3-point
    grid = 150 003 cases exceed MAX_CASES = 100 000 and are refused when the spec is read, before
    any plan (without the grid factor the spec passed as 50 001 cases)."""
    text = (SPEC.replace("cases = 2", "cases = 50000")
            .replace('"7 W/m2K"', '{ grid = ["6 W/m2K", "8 W/m2K", "10 W/m2K"] }'))
    _refused(tmp_path, text, "scenarios", "the plan has 150003 cases; at most 100000")


def test_a_grid_value_given_twice_is_refused(tmp_path):
    """``{ grid = ["6 W/m2K", "6 W/m2K"] }`` is an error: accepted, it planned every draw twice
    with identical records, hashes and files."""
    _refused(tmp_path, SPEC.replace('"7 W/m2K"', '{ grid = ["6 W/m2K", "6 W/m2K"] }'),
             "parameters.ambient_convection.h.grid", "a grid value is given twice")


def test_a_log_uniform_range_must_be_positive(tmp_path):
    """``log_uniform = ["0 W", "80 W"]`` (within the power's bounds) is refused when the spec is
    read, naming the field; accepted, the plan failed with a bare 'math domain error'."""
    _refused(tmp_path, SPEC.replace('{ uniform = ["40 W", "80 W"] }', '{ log_uniform = ["0 W", "80 W"] }'),
             "parameters.spindle_motor.power.log_uniform", "must be positive")


def test_generator_speeds_are_bounded_by_the_slowest_machine(tmp_path):
    """Two machines (C-frame up to 9000 rpm, belt VMC up to 8000 rpm): a generator's speeds of
    2000-9000 rpm are refused on ``spindle.speed``, as every drawn step must run on every machine
    (the faster machine's top let 9000 rpm steps through to the belt VMC)."""
    _refused(tmp_path, SPEC.replace('machines = ["cframe-vmc"]', 'machines = ["cframe-vmc", "belt-vmc"]'),
             "scenarios[0].spindle.speed", "maximum spindle speed")


def test_a_daily_room_whose_swing_leaves_the_plausible_air_is_refused(tmp_path):
    """A daily room of mean 50-55 degC and amplitude up to 10 K reaches 65 degC, beyond the
    plausible room air (-40 to 60 degC): refused on ``ambient.amplitude`` (the mean alone is
    within it)."""
    text = SPEC.replace('mean = ["18 degC", "22 degC"]\namplitude = ["0 K", "3 K"]',
                        'mean = ["50 degC", "55 degC"]\namplitude = ["0 K", "10 K"]')
    _refused(tmp_path, text, "scenarios[0].ambient.amplitude", "plausible room air")


def test_a_reversed_or_empty_axis_range_is_refused(tmp_path):
    """An axis duty cycle's ``range`` must have hi > lo (module doc: reversed ranges are errors):
    ["280 mm", "0 mm"] and ["100 mm", "100 mm"] are refused on ``axis[0].range``."""
    for ends in ('["280 mm", "0 mm"]', '["100 mm", "100 mm"]'):
        text = SPEC.replace(REFERENCE, AXIS.replace('["0 mm", "280 mm"]', ends) + REFERENCE)
        _refused(tmp_path, text, "scenarios[0].axis[0].range", "hi > lo")


def test_an_axis_duty_cycle_accelerates_at_100_mm_s2_by_default(tmp_path):
    """``acceleration`` is optional, 100 mm/s2 by default (spec module doc): the family holds
    0.1 m/s2 and every drawn reciprocation says so."""
    spec = _spec(tmp_path, SPEC.replace("cases = 2", "cases = 4").replace(REFERENCE, AXIS + REFERENCE))
    assert spec.families[0].generator.axes[0].acceleration == pytest.approx(0.1, rel=1e-12)
    moves = [m for c in plan(spec) if c.info["family"] == "duty" for m in c.record["scenario"]["axis"][0]["move"]
             if m["kind"] == "reciprocate"]
    assert moves and {m["acceleration"] for m in moves} == {"0.1 m/s2"}


# --- the plan and its index columns --------------------------------------------------------------

def test_without_splits_every_case_is_train(tmp_path):
    """No ``[splits]`` table: every case in "train" (the spec's documented default)."""
    cases = plan(_spec(tmp_path, SPEC.replace("[splits]\n" + CASE_SPLITS + "\n", "")))
    assert len(cases) == 3 and {c.split for c in cases} == {"train"}


def test_the_grid_point_column_numbers_each_cases_grid_point(tmp_path):
    """The index's ``grid_point`` is the case's place in the grid: h = 6 W/m2K is point 0 and
    10 W/m2K point 1, for every draw of every family."""
    cases = plan(_spec(tmp_path, SPEC.replace('"7 W/m2K"', '{ grid = ["6 W/m2K", "10 W/m2K"] }')))
    assert len(cases) == 6
    assert {(c.info["ambient_convection.h [W/m2K]"], c.info["grid_point"]) for c in cases} == {(6.0, 0), (10.0, 1)}


def test_a_case_hash_is_the_first_16_hex_digits_of_its_records_sha256(tmp_path):
    """README: a case file is named by the first 16 hex digits of the SHA-256 of its record's
    canonical JSON (sorted keys, no spaces, ASCII), which a cluster's worker recomputes."""
    for c in plan(_spec(tmp_path)):
        text = json.dumps(c.record, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
        assert c.hash == hashlib.sha256(text.encode()).hexdigest()[:16]
        assert c.file == f"{c.hash}.nc" and len(c.hash) == 16


def test_a_new_package_or_format_version_changes_every_hash(tmp_path, monkeypatch):
    """The record holds the package and the dataset format version (README: "package and format
    version"), so a rerun after an upgrade rebuilds every case rather than mixing files of two
    versions."""
    import importlib

    P = importlib.import_module("twin.dataset.plan")    # the package re-exports the function by this name
    spec = _spec(tmp_path)
    base = [c.hash for c in plan(spec)]
    monkeypatch.setattr(P, "package_version", lambda: "0.0.0+other")
    other = plan(spec)
    assert all(c.record["package_version"] == "0.0.0+other" for c in other)
    assert not {c.hash for c in other} & set(base)
    monkeypatch.undo()
    monkeypatch.setattr(P, "FORMAT", P.FORMAT + 1)
    assert not {c.hash for c in plan(spec)} & set(base)


def _table_room_infos(tmp_path, times, temperatures):
    room = (f'kind = "table"\ntimes = [{", ".join(repr(t) for t in times)}]\n'
            f'temperatures = [{", ".join(repr(t) for t in temperatures)}]').replace("'", '"')
    text = SPEC.replace('kind = "daily"\nmean = ["18 degC", "22 degC"]\namplitude = ["0 K", "3 K"]\n'
                        'coldest_at = ["0 h", "24 h"]', room)
    return [c.info for c in plan(_spec(tmp_path, text)) if c.info["family"] == "duty"]


def test_a_table_rooms_index_mean_and_amplitude_are_those_of_the_run(tmp_path):
    """A generator room given as a table: the index's ``ambient_mean [degC]`` is the time average
    of the piecewise-linear air over the run [0, duration] and ``ambient_amplitude [K]`` half its
    range there. 20 -> 22 degC over the 10 minutes: 21 and 1 (the first value was the mean once,
    and the amplitude always 0). A record running past the case's end (20, 20 at 10 min, 40 at
    24 h) describes the 10 minutes of the case: 20 and 0 (the mean of all samples read 26.7).
    20 -> 24 degC over 20 min, a 10-minute case: the air 20 -> 22 over the run, mean 21, amplitude 1."""
    for times, temps, mean, amplitude in ((["0 min", "10 min"], ["20 degC", "22 degC"], 21.0, 1.0),
                                          (["0 min", "10 min", "24 h"], ["20 degC", "20 degC", "40 degC"], 20.0, 0.0),
                                          (["0 min", "20 min"], ["20 degC", "24 degC"], 21.0, 1.0)):
        infos = _table_room_infos(tmp_path, times, temps)
        assert [i["ambient"] for i in infos] == ["table"] * 2
        for i in infos:
            assert i["ambient_mean [degC]"] == pytest.approx(mean, abs=1e-12), (times, temps)
            assert i["ambient_amplitude [K]"] == pytest.approx(amplitude, abs=1e-12), (times, temps)


# --- a built case, its index and its card ---------------------------------------------------------

@pytest.fixture(scope="module")
def one_built(tmp_path_factory):
    """The tiny spec with a thermal camera; of its 3 planned cases only the duty family's draw 1
    built, then the index and card written: (folder, cases, the built case)."""
    root = tmp_path_factory.mktemp("mut")
    spec = load_spec(write_spec(root, SPEC.replace("seed = 3", 'seed = 3\n[observers]\ncameras = ["carrier-front"]')))
    cases = plan(spec)
    case = cases[1]
    assert (case.info["family"], case.info["draw"]) == ("duty", 1)
    out = root / "out"
    build([case], out)
    write_index(spec, cases, out)
    return out, cases, case


def test_a_case_file_names_its_family_and_draw(one_built):
    """README "Output": a case file carries ``dataset_family`` and ``dataset_draw``: draw 1 of
    the duty family says 1 (not 0), so the files of a folder can be matched to their draws."""
    out, _, case = one_built
    with xr.open_dataset(out / "cases" / case.file, engine="h5netcdf") as ds:
        assert (ds.attrs["dataset_family"], int(ds.attrs["dataset_draw"])) == ("duty", 1)
        assert ds.attrs["case_hash"] == case.hash


def test_a_case_runs_with_the_default_time_integration_of_twin_simulate(one_built):
    """A dataset case is the run ``twin simulate`` would make of its scenario: the same theta
    (Crank-Nicolson), which the file records."""
    from twin.simulate import run

    out, _, case = one_built
    with xr.open_dataset(out / "cases" / case.file, engine="h5netcdf") as ds:
        assert float(ds.attrs["theta"]) == inspect.signature(run).parameters["theta"].default == 0.5


def test_numeric_case_variables_are_gzip_compressed(one_built):
    """runner: numeric variables are written gzip-compressed (deterministic, lossless): each
    numeric variable of one or more dimensions in the file, drift and temperature among them."""
    out, _, case = one_built
    with xr.open_dataset(out / "cases" / case.file, engine="h5netcdf") as ds:
        names = [n for n, v in ds.data_vars.items() if v.dtype.kind in "fiu" and v.ndim >= 1]
    assert {"drift", "temperature"} <= set(names)
    with h5py.File(out / "cases" / case.file, "r") as f:
        assert {n: f[n].compression for n in names} == {n: "gzip" for n in names}


def test_a_specs_cameras_record_frames_in_each_case(one_built):
    """``[observers] cameras = ["carrier-front"]``: each case file holds the camera's thermogram
    (a measured variable), not just the machine's sensors."""
    out, _, case = one_built
    with xr.open_dataset(out / "cases" / case.file, engine="h5netcdf") as ds:
        assert "thermogram" in ds.data_vars and ds["thermogram"].sizes["frame_time"] >= 1


def test_the_index_and_card_give_the_built_files_sizes(one_built):
    """index.csv's ``bytes`` is the size of each built file (0 for one not built) and the card's
    total is their sum, over the one built case (mean per built case the same)."""
    out, cases, case = one_built
    size = (out / "cases" / case.file).stat().st_size
    index = pd.read_csv(out / "index.csv")
    assert dict(zip(index["hash"], index["bytes"])) == {c.hash: size if c is case else 0 for c in cases}
    card = json.loads((out / "card.json").read_text())
    assert card["sizes"] == {"bytes": size, "mean_case_bytes": size}


def test_the_readme_counts_table_reads_planned_then_built(one_built):
    """README.md's tables are ``| split | planned | built |`` and ``| family | planned | built |``:
    each row matches the index (one of three cases built, so the two columns differ)."""
    out, _, _ = one_built
    index = pd.read_csv(out / "index.csv")
    text = (out / "README.md").read_text()
    for key in ("split", "family"):
        for name, group in index.groupby(key):
            assert f"| {name} | {len(group)} | {int(group['built'].sum())} |" in text, (key, name)
    assert "| duty | 2 | 1 |" in text


def test_a_card_json_without_a_spec_is_no_dataset_card(tmp_path):
    """A folder's README.md is only rewritten beside a twin dataset's card.json, a JSON object
    with both ``format`` and ``spec``: ``{"format": 1}`` alone is someone else's file."""
    from twin.dataset.card import check_dataset_folder

    (tmp_path / "README.md").write_text("my notes\n", encoding="utf-8")
    (tmp_path / "card.json").write_text('{"format": 1}', encoding="utf-8")
    with pytest.raises(InputError) as err:
        check_dataset_folder(tmp_path)
    assert "is not a twin dataset's" in err.value.message
    (tmp_path / "card.json").write_text('{"format": 1, "spec": ""}', encoding="utf-8")
    check_dataset_folder(tmp_path)


# --- the estimate ---------------------------------------------------------------------------------

def test_the_estimate_of_one_case_is_not_shared_among_workers(tmp_path, monkeypatch):
    """One case on two workers runs on one of them: on a clock where preparing takes 2 s and a
    run of n steps 0.3 s + 2 ms n, the estimate is prepare + rate x steps, not half the steps'
    time (workers = min(jobs, cores, cases))."""
    E, _ = fake_estimate_clock(monkeypatch)
    case = plan(_spec(tmp_path))[:1]
    steps = E._steps(case[0])
    assert steps == 10
    e = E.estimate(case, jobs=2, calibration_steps=3)
    rate = (0.3 + 0.002 * steps) / steps
    assert e["seconds"] == pytest.approx(e["prepare_s"] + rate * steps, rel=1e-12)
    assert e["seconds"] == pytest.approx(E.estimate(case, jobs=1, calibration_steps=3)["seconds"], rel=1e-12)


def test_the_estimate_prepares_the_twin_a_case_runs_on(tmp_path, monkeypatch):
    """A case that moves the Y axis runs on the twin with Y's feed drive
    (``runner._prepared(machine, mesh, solver, ("Y",))``): the dry run prepares and times that
    twin, once per set of moved axes, and names the group by its axes; it prepared the plain
    twin, which the build never uses, and timed a group of mixed axis sets with one of them."""
    E, keys = fake_estimate_clock(monkeypatch)
    cases = plan(_spec(tmp_path, SPEC.replace(REFERENCE, AXIS + REFERENCE)))
    assert [c.info["family"] for c in cases] == ["duty", "duty", "reference"]
    e = E.estimate(cases, jobs=1, calibration_steps=3)
    group = ("cframe-vmc", "coarse", cases[0].record["solver"])
    assert keys == [group + (("Y",),), group + ((),)]
    assert sorted(e["per_step_s"]) == ["/".join(group), "/".join(group) + " (axes Y)"]
