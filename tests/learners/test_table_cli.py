"""Table loading (CSV and twin NetCDF) and ``twin learn`` end to end on small files in tmp_path."""

import argparse
import csv

import numpy as np
import pytest

from learners.cli import COLUMNS, add_learn_parser, run_learn
from learners.table import load_table
from twin.errors import InputError


def _series(n, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 10.0
    heat = 8.0 * (1.0 - np.exp(-t / 600.0))
    T = np.column_stack([20 + heat + 0.05 * rng.normal(size=n), 20 + 0.5 * heat + 0.05 * rng.normal(size=n),
                         20 + 0.2 * rng.normal(size=n), 20 + 0.3 * heat + 0.05 * rng.normal(size=n)])
    drift = 3.0 * (T[:, 0] - 20) - 1.5 * (T[:, 1] - 20) + 0.1 * rng.normal(size=n)
    return t, T, drift


def _write_csv(path, n=60, seed=0, edit=None):
    t, T, drift = _series(n, seed)
    rows = [["time", "T1", "T2", "T3", "T4", "drift_z"]]
    rows += [[f"{t[i]:g}", *(f"{v:.5f}" for v in T[i]), f"{drift[i]:.5f}"] for i in range(n)]
    if edit:
        edit(rows)
    with open(path, "w", newline="") as fh:
        csv.writer(fh).writerows(rows)
    return str(path)


def _args(*argv):
    parser = argparse.ArgumentParser(prog="twin")
    add_learn_parser(parser.add_subparsers(dest="command"))
    return parser.parse_args(["learn", *argv])


def test_csv_loads_with_default_inputs(tmp_path):
    time, X, y, names, unit = load_table(_write_csv(tmp_path / "a.csv"), "drift_z")
    assert names == ["T1", "T2", "T3", "T4"] and X.shape == (60, 4) and y.shape == (60,)
    assert time[1] == 10.0 and unit == ""           # a CSV does not state its columns' units
    _, X2, _, names2, _ = load_table(str(tmp_path / "a.csv"), "drift_z", inputs="T3,T1")
    assert names2 == ["T3", "T1"] and np.array_equal(X2, X[:, [2, 0]])


def test_learn_end_to_end_csv(tmp_path, capsys):
    train = _write_csv(tmp_path / "train.csv", seed=0)
    test1 = _write_csv(tmp_path / "test1.csv", seed=1)
    test2 = _write_csv(tmp_path / "test2.csv", n=40, seed=2)
    out = tmp_path / "scores.csv"
    args = _args("--train", train, "--test", test1, "--test", test2, "--target", "drift_z",
                 "--learner", "mlr,pcr,lssvm", "--select", "correlation:2", "-o", str(out), "--seed", "3")
    assert run_learn(args) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].split()[:3] == ["learner", "test", "file"]
    assert len(printed) == 2 + 6
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == COLUMNS and len(rows) == 6
    assert {r["learner"] for r in rows} == {"mlr", "pcr", "lssvm"}
    mlr = [r for r in rows if r["learner"] == "mlr"]
    assert all(float(r["nse"]) > 0.95 for r in mlr)                      # drift is linear in T1, T2
    assert all(r["inputs"] == "T1;T2" for r in rows)                        # the informative pair
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".scores-")]   # no temp file left


def _bad(tmp_path, edit, n=60):
    return _write_csv(tmp_path / "bad.csv", n=n, edit=edit)


@pytest.mark.parametrize("case, column", [
    ("missing_file", "file"),
    ("missing_target", "drift_z"),
    ("non_numeric", "T2"),
    ("nan", "T3"),
    ("empty_cell", "T1"),
    ("time_not_increasing", "time"),
    ("too_few_rows", "rows"),
])
def test_bad_tables_raise_input_error_naming_file_and_column(tmp_path, case, column):
    good = _write_csv(tmp_path / "good.csv")
    edits = {
        "missing_target": lambda r: [row.pop() for row in r],
        "non_numeric": lambda r: r[5].__setitem__(2, "warm"),
        "nan": lambda r: r[7].__setitem__(3, "nan"),
        "empty_cell": lambda r: r[9].__setitem__(1, ""),
        "time_not_increasing": lambda r: r[4].__setitem__(0, "5"),
    }
    if case == "missing_file":
        path = str(tmp_path / "nope.csv")
    elif case == "too_few_rows":
        path = _bad(tmp_path, None, n=2)
    else:
        path = _bad(tmp_path, edits[case])
    with pytest.raises(InputError) as err:
        load_table(path, "drift_z")
    assert err.value.source == path and err.value.field == column
    # the CLI surfaces the same error, whichever side the bad table is on (a missing file is named
    # by the option that gave it)
    with pytest.raises(InputError) as err2:
        run_learn(_args("--train", good, "--test", path, "--target", "drift_z", "--learner", "mlr"))
    assert err2.value.source == path and err2.value.field == ("--test" if column == "file" else column)


def test_unknown_names_and_missing_input(tmp_path):
    good, other = _write_csv(tmp_path / "good.csv"), _write_csv(tmp_path / "other.csv", seed=1)
    for argv in (["--learner", "mlr,nope"], ["--learner", "mlr", "--select", "nope:2"],
                 ["--learner", "mlr", "--select", "correlation:x"], ["--learner", "mlr", "--select", "all:2"]):
        with pytest.raises(InputError):
            run_learn(_args("--train", good, "--test", other, "--target", "drift_z", *argv))
    with pytest.raises(InputError) as err:
        run_learn(_args("--train", good, "--test", other, "--target", "drift_z", "--learner", "mlr",
                        "--inputs", "T1,T9"))
    assert err.value.field == "T9"


def test_learner_refusing_the_data_is_an_input_error(tmp_path):
    short = _write_csv(tmp_path / "short.csv", n=5)          # combination needs >= 7 rows
    other = _write_csv(tmp_path / "other.csv", n=5, seed=1)
    with pytest.raises(InputError) as err:
        run_learn(_args("--train", short, "--test", other, "--target", "drift_z", "--learner", "combination"))
    assert err.value.source == short and err.value.field == "combination"


def _write_netcdf(path, n=50, seed=0):
    xr = pytest.importorskip("xarray")
    t, T, drift = _series(n, seed)
    ds = xr.Dataset(
        {"temperature": (("time", "sensor"), T, {"units": "degC"}),
         "drift": (("time", "axis"), np.column_stack([0.1 * drift, 0.5 * drift, drift]), {"units": "um"}),
         "probe": (("time", "probe_id"), np.column_stack([drift, drift + 1.0]), {"units": "um"}),
         "tilt": (("time", "rotation"), np.column_stack([0.2 * drift, -0.2 * drift]), {"units": "urad"}),
         "spindle_speed": (("time",), np.full(n, 8000.0), {"units": "rpm"}),
         "load": (("time",), 100.0 + drift, {"units": "N"})},
        coords={"time": ("time", t, {"units": "s"}), "sensor": ["S1", "S2", "S3", "S4"],
                "axis": ["X", "Y", "Z"], "probe_id": ["Y1", "Y2"], "rotation": ["A", "B"]})
    ds.to_netcdf(path)
    return str(path)


def test_netcdf_targets_and_learn(tmp_path, capsys):
    train = _write_netcdf(tmp_path / "train.nc", seed=0)
    test = _write_netcdf(tmp_path / "test.nc", seed=1)
    time, X, y, names, unit = load_table(train, "drift:Z")
    assert names == ["S1", "S2", "S3", "S4"] and X.shape == (50, 4)
    assert unit == "um" and load_table(train, "tilt:A").target_unit == "urad"   # the variable's units attribute
    assert np.allclose(load_table(train, "probe:Y2").y, y + 1.0)
    assert np.allclose(load_table(train, "tilt:A").y, 0.2 * y)
    assert np.allclose(load_table(train, "spindle_speed").y, 8000.0)
    with pytest.raises(InputError) as err:
        load_table(train, "drift:W")
    assert err.value.source == train and err.value.field == "drift:W"
    with pytest.raises(InputError):
        load_table(train, "drift")                  # needs an axis label
    assert run_learn(_args("--train", train, "--test", test, "--target", "drift:Z",
                           "--learner", "mlr,ar-temp", "--select", "hier-corr:2")) == 0
    assert "S1" in capsys.readouterr().out


def test_learn_writes_the_targets_unit_and_refuses_files_in_different_units(tmp_path, capsys):
    """A tilt target is scored in urad: the Markdown headings and the CSV's unit column say so;
    a test file whose tilt is not in a twin result's urad is refused, and so is one whose target
    (a variable no twin result holds) is in another unit than the training file's."""
    import xarray as xr

    train = _write_netcdf(tmp_path / "train.nc", seed=0)
    test = _write_netcdf(tmp_path / "test.nc", seed=1)
    md, table = tmp_path / "b.md", tmp_path / "b.csv"
    assert run_learn(_args("--train", train, "--test", test, "--target", "tilt:A", "--learner", "mlr",
                           "--select", "hier-corr:2", "-o", str(md), "-o", str(table))) == 0
    assert "RMSE urad" in md.read_text() and "um" not in md.read_text().split("\n## ")[1].splitlines()[2]
    header, row = table.read_text().splitlines()[:2]
    assert row.split(",")[header.split(",").index("unit")] == "urad"
    ds = xr.load_dataset(test)
    ds["tilt"].attrs["units"] = "mrad"
    ds["load"].attrs["units"] = "kN"
    ds.to_netcdf(tmp_path / "mrad.nc")
    with pytest.raises(InputError, match="in 'mrad'; a NetCDF file is read as a twin result, which holds tilt in "
                                         "'urad'"):
        run_learn(_args("--train", train, "--test", str(tmp_path / "mrad.nc"), "--target", "tilt:A",
                        "--learner", "mlr", "--select", "hier-corr:2"))
    ds["tilt"].attrs["units"] = "urad"          # the file is refused whatever the target: only load in kN now
    ds.to_netcdf(tmp_path / "kN.nc")
    with pytest.raises(InputError, match="different units"):      # a variable no twin result holds
        run_learn(_args("--train", train, "--test", str(tmp_path / "kN.nc"), "--target", "load",
                        "--learner", "mlr", "--select", "hier-corr:2"))


def test_time_ordered_learners_need_one_sample_interval(tmp_path, capsys):
    """Runs sampled at 10 s and 20 s: refused for gm1n (its coefficients are per sample) unless
    --interval thins them to one; a pooled learner takes them as they are."""
    train = _write_csv(tmp_path / "train.csv", n=80)
    test = _write_csv(tmp_path / "test.csv", n=40, seed=1, edit=lambda rows: [r.__setitem__(0, f"{2 * float(r[0]):g}")
                                                                               for r in rows[1:]])
    common = ["--train", train, "--test", test, "--target", "drift_z"]
    with pytest.raises(InputError, match="every 10, 20 s") as err:
        run_learn(_args(*common, "--learner", "mlr,gm1n"))
    assert err.value.field == "--interval"
    assert run_learn(_args(*common, "--learner", "mlr")) == 0
    assert run_learn(_args(*common, "--learner", "mlr,gm1n", "--interval", "20 s")) == 0
    assert "gm1n" in capsys.readouterr().out


def test_netcdf_units_are_stated_and_values_plausible(tmp_path):
    """A NetCDF table is read as a twin result (twin.io.measurement.read_checked_result, as plot,
    report and compare read it): every variable a twin result holds states the result's unit, time
    in s (a time in min, once converted here, is refused as plot refuses it), a variable only
    learn reads (load) states one, and temperatures, errors and strains are a machine's
    (twin.limits): a drift in metres written as um, or 293 'degC' that were kelvin, are refused
    naming file and variable."""
    import xarray as xr

    path = _write_netcdf(tmp_path / "t.nc")
    base = xr.load_dataset(path)
    cases = [("temperature", lambda d: d["temperature"].attrs.pop("units"), "drift:Z", "temperature",
              "states no unit"),
             ("temperature", lambda d: d["temperature"].attrs.update(units="K"), "drift:Z", "temperature",
              "holds temperature in 'degC'"),
             ("drift", lambda d: d["drift"].attrs.update(units="furlong"), "drift:Z", "drift", "in 'furlong'"),
             ("time", lambda d: d["time"].attrs.update(units="fortnights"), "drift:Z", "time", "in 'fortnights'"),
             ("time", lambda d: d["time"].attrs.pop("units"), "drift:Z", "time", "states no unit"),
             ("load", lambda d: d["load"].attrs.pop("units"), "load", "load", "'load' states no units"),
             ("temperature", lambda d: d["temperature"].__setitem__(slice(None), d["temperature"].values + 400.0),
              "drift:Z", "temperature:S1", "structure"),
             ("drift", lambda d: d["drift"].__setitem__(slice(None), d["drift"].values * 1e6), "drift:Z", "drift:Z",
              "beyond")]
    for k, (_, change, target, field, needle) in enumerate(cases):
        ds = base.copy(deep=True)
        change(ds)
        bad = tmp_path / f"bad{k}.nc"
        ds.to_netcdf(bad)
        with pytest.raises(InputError, match=needle) as err:
            load_table(str(bad), target)
        assert err.value.source == str(bad) and err.value.field == field, str(err.value)
    ds = base.copy(deep=True)
    ds["time"] = ds["time"] / 60.0
    ds["time"].attrs["units"] = "min"
    ds.to_netcdf(tmp_path / "min.nc")
    with pytest.raises(InputError, match="in 'min'; a NetCDF file is read as a twin result, which holds time in "
                                         "'s'") as err:
        load_table(str(tmp_path / "min.nc"), "drift:Z")
    assert err.value.field == "time"


def test_a_grid_sensor_the_test_file_lacks_is_named_as_a_missing_sensor(tmp_path):
    """Surface-grid sensor names hold ':' (part:face:u:v); one the file lacks is a missing input
    sensor, not an address of a variable 'carrier' that does not exist."""
    train = _write_netcdf(tmp_path / "train.nc", seed=0)
    with pytest.raises(InputError) as err:
        load_table(train, "drift:Z", inputs=["S1", "carrier:-x:0.015:1.175"])
    assert err.value.field == "carrier:-x:0.015:1.175" and "missing input sensor" in err.value.message
    assert np.allclose(load_table(train, "drift:Z", inputs=["S1", "probe:Y2"]).X[:, 1],
                       load_table(train, "probe:Y2").y)     # an address still reads its variable


def test_a_file_given_twice_by_another_spelling_or_a_link_and_two_outputs_of_one_format_are_refused(tmp_path,
                                                                                                       monkeypatch):
    """Helper audit: ``--train a.csv --train ./a.csv`` (or an absolute path, a symlink, a hard
    link) trained on the same run twice, and ``-o s1.csv -o s2.csv`` wrote the same table twice."""
    import os

    monkeypatch.chdir(tmp_path)
    train = _write_csv(tmp_path / "a.csv", seed=0)
    test = _write_csv(tmp_path / "b.csv", seed=1)
    os.link(train, tmp_path / "hard.csv")
    os.symlink(train, tmp_path / "soft.csv")
    common = ("--target", "drift_z", "--learner", "mlr")
    for again in ("./a.csv", str(tmp_path / "a.csv"), "hard.csv", "soft.csv"):
        with pytest.raises(InputError, match="is the same file as") as err:
            run_learn(_args("--train", "a.csv", "--train", again, "--test", test, *common))
        assert err.value.field == "--train"
    with pytest.raises(InputError, match="is the same file as"):
        run_learn(_args("--train", train, "--test", "b.csv", "--test", "./b.csv", *common))
    for outputs in (("s1.csv", "s2.csv"), ("s1.md", "s2.MD")):
        with pytest.raises(InputError, match="one file per format") as err:
            run_learn(_args("--train", train, "--test", test, *common, "-o", outputs[0], "-o", outputs[1]))
        assert err.value.field == "-o"
    assert not any(tmp_path.glob("s[12].*"))


def test_a_target_that_varies_by_round_off_only_is_constant(tmp_path):
    """A machine at rest gives a drift that varies by about 1e-12 um, the solvers' round-off:
    scored as a test target it gave NSE -7e22. A target in a twin unit (um, K, um/m, urad) varying
    by no more than 1e-6 of it is constant, and refused naming the file and the target; one that
    varies by 1e-3 um (a hundredth of a probe's step) is kept."""
    from learners.table import check_problem

    xr = pytest.importorskip("xarray")
    path = _write_netcdf(tmp_path / "still.nc")
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    wobble = np.sin(np.arange(ds.sizes["time"]))
    for spread, refused in ((2e-12, True), (1e-3, False)):
        ds["drift"].values[:, 2] = 3.0 + 0.5 * spread * wobble
        ds.to_netcdf(path)
        table = load_table(path, "drift:Z")
        if refused:
            with pytest.raises(InputError, match="round-off") as err:
                check_problem(table, path, "drift:Z", training=False)
            assert err.value.source == path and err.value.field == "drift:Z"
        else:
            check_problem(table, path, "drift:Z", training=False)


def test_a_temperature_target_is_left_out_of_the_default_inputs(tmp_path):
    """The default inputs are every sensor but the target: with a temperature as the target the
    command refused its own default ('the target temperature:S2 is also an input')."""
    from learners.table import check_problem

    path = _write_netcdf(tmp_path / "t.nc")
    table = load_table(path, "temperature:S2")
    assert table.input_names == ["S1", "S3", "S4"]
    check_problem(table, path, "temperature:S2")
    with pytest.raises(InputError, match="also an input"):
        check_problem(load_table(path, "temperature:S2", inputs=["S1", "S2"]), path, "temperature:S2")


def test_a_repeated_time_is_not_strictly_increasing(tmp_path):
    """Times 0, 60, 60, 120: diff = [60, 0, 60], the first diff <= 0 is between data rows 2 and 3,
    so load_table refuses on the time column at the line an editor shows, line 4 (the header is
    line 1), line 5 with a blank line before it (a repeat, diff = 0, is refused as well as a step
    back)."""
    path = tmp_path / "repeat.csv"
    for text, line in (("time,T1,drift\n0,20.0,0.0\n60,20.5,1.0\n60,21.0,2.5\n120,21.4,3.1\n", 4),
                       ("time,T1,drift\n0,20.0,0.0\n\n60,20.5,1.0\n60,21.0,2.5\n120,21.4,3.1\n", 5)):
        path.write_text(text)
        with pytest.raises(InputError) as err:
            load_table(str(path), "drift")
        assert err.value.field == "time"
        assert f"not strictly increasing at line {line} (60 s then 60 s)" in err.value.message


# --- audit: every column, evenly spaced runs, result files as plot reads them, the dataset index ------------------

def _with_column(path, name, value, blank_at=None):
    """A copy of a table with one more column ``name`` holding ``value`` on every row (a blank line
    inserted before data row ``blank_at``, as an editor shows it)."""
    lines = open(path).read().splitlines()
    lines = [lines[0] + f",{name}"] + [line + f",{value}" for line in lines[1:]]
    if blank_at is not None:
        lines.insert(blank_at, "")
    return lines


@pytest.mark.parametrize("value, words", [("abc", "non-numeric value 'abc'"), ("nan", "NaN value"),
                                          ("", "missing value")])
def test_every_csv_column_is_checked_used_or_not(tmp_path, value, words):
    """`time,T1,...,drift_z,note` with note = abc or nan on every row passed, as a test file and
    as a training file whose --inputs leave note out: every column of every table is numeric and
    finite, named with the file, the column and the line an editor shows (blank lines counted)."""
    train, test = _write_csv(tmp_path / "train.csv"), _write_csv(tmp_path / "test.csv", seed=1)
    bad = tmp_path / "note.csv"
    bad.write_text("\n".join(_with_column(test, "note", value, blank_at=1)) + "\n")   # data from line 3
    for argv in (["--train", train, "--test", str(bad)],
                 ["--train", str(bad), "--test", train, "--inputs", "T1,T2"]):
        with pytest.raises(InputError, match=f"line 3: {words}") as err:
            run_learn(_args(*argv, "--target", "drift_z", "--learner", "mlr"))
        assert (err.value.source, err.value.field) == (str(bad), "note")
        assert "even one the command does not use" in err.value.message
    good = tmp_path / "more.csv"                    # a numeric column not used is read and left out
    good.write_text("\n".join(_with_column(test, "spare", "1.5")) + "\n")
    assert run_learn(_args("--train", train, "--test", str(good), "--target", "drift_z", "--learner", "mlr",
                           "--inputs", "T1,T2")) == 0


def test_time_ordered_learners_refuse_a_run_with_a_gap(tmp_path, capsys):
    """A run at 10 s steps with a jump from 290 s to 86700 s passed ar-temp and gm1n (they count
    in samples: the gap read as one step) though --interval called it not equally spaced: refused
    for them on either side, naming the file and its time column; pooled learners take it."""
    train = _write_csv(tmp_path / "train.csv")

    def jump(rows):
        for r in rows[31:]:
            r[0] = f"{float(r[0]) + 86400:g}"

    gap = _write_csv(tmp_path / "gap.csv", seed=1, edit=jump)
    for name in ("ar-temp", "gm1n", "mlr,gnnmci"):
        for argv in (["--train", gap, "--test", train], ["--train", train, "--test", gap]):
            with pytest.raises(InputError, match="290 s then 86700 s.*split the run") as err:
                run_learn(_args(*argv, "--target", "drift_z", "--learner", name))
            assert (err.value.source, err.value.field) == (gap, "time"), str(err.value)
    assert run_learn(_args("--train", gap, "--test", train, "--target", "drift_z", "--learner", "mlr,pcr")) == 0
    wobble = _write_csv(tmp_path / "wobble.csv", seed=2,       # within 1e-6 of the step, as --interval allows
                        edit=lambda rows: rows[5].__setitem__(0, f"{float(rows[5][0]) + 1e-7:.7f}"))
    assert run_learn(_args("--train", train, "--test", wobble, "--target", "drift_z", "--learner", "ar-temp")) == 0


def _result_edits():
    def coord(name, index, value):
        def edit(ds):
            values = ds[name].values.copy()
            values[index] = value
            ds.coords[name] = ("sensor", values)
        return edit

    return [("nan-in-drift-X", lambda ds: ds["drift"].values.__setitem__((3, 0), np.nan), "drift", "from t = 180 s"),
            ("extra-all-nan", lambda ds: ds.__setitem__("junk", ("time", np.full(ds.sizes["time"], np.nan),
                                                                   {"units": "1"})), "junk", "NaN or infinite"),
            ("unknown-machine", lambda ds: ds.attrs.__setitem__("machine", "nosuch"), "machine", "unknown machine"),
            ("speed-beyond", lambda ds: ds["spindle_speed"].values.__setitem__(0, 12000.0), "spindle_speed",
             "12000 rpm is beyond"),
            ("sensor-x-nan", coord("x", 0, np.nan), "x", "NaN or infinite"),
            ("sensor-x-50-m", coord("x", 0, 50.0), "sensor motor", "is not on part motor")]


@pytest.mark.parametrize("case, edit, field, words", _result_edits(), ids=[c[0] for c in _result_edits()])
def test_a_result_file_is_read_as_plot_report_and_compare_read_it(tmp_path, capsys, case, edit, field, words):
    """A NaN in a variable learn does not read (drift:X beside the target drift:Z), an all-NaN
    extra variable, an unknown machine, 12000 rpm on a 9000 rpm machine, a sensor at x NaN or
    50 m: twin plot refused these files and twin learn read them. Both read a result with
    twin.io.measurement.read_checked_result now: the same error, exit status 2."""
    from tests.fuzz_files import result_dataset
    from twin.cli import main

    good, other = tmp_path / "good.nc", tmp_path / "other.nc"
    ds = result_dataset(40)
    ds.to_netcdf(good, engine="h5netcdf")
    ds["drift"].values[:, 2] += 0.01 * np.arange(40)
    ds.to_netcdf(other, engine="h5netcdf")
    bad = result_dataset(40)
    edit(bad)
    bad.to_netcdf(tmp_path / "bad.nc", engine="h5netcdf")
    common = ["--target", "drift:Z", "--learner", "mlr"]
    assert main(["learn", "--train", str(good), "--test", str(other), *common]) == 0
    capsys.readouterr()
    for argv in (["--train", str(good), "--test", str(tmp_path / "bad.nc")],
                 ["--train", str(tmp_path / "bad.nc"), "--test", str(other)]):
        assert main(["learn", *argv, *common]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"error: {tmp_path / 'bad.nc'}: {field}: ") and words in err, err
    assert main(["plot", str(tmp_path / "bad.nc"), "-o", str(tmp_path / "p.png")]) == 2
    assert capsys.readouterr().err == err              # word for word what plot says
    assert not (tmp_path / "p.png").exists()


def _dataset(folder, index_text):
    folder.mkdir()
    for name, seed in (("a", 0), ("b", 1), ("c", 2)):
        _write_csv(folder / f"{name}.csv", seed=seed)
    (folder / "index.csv").write_text(index_text)
    return folder


def test_a_dataset_index_is_read_as_twin_dataset_writes_it(tmp_path, capsys):
    """index.csv: a built other than True/False (true, maybe) dropped its case without a word, and
    a file outside the folder (../x.csv, an absolute path) was read: refused naming index.csv, the
    column and the line. What twin dataset writes (pandas' True/False, cases/<hash>.nc) is read."""
    import pandas as pd
    from twin.cli import main

    (tmp_path / "outside.csv").write_text(open(_write_csv(tmp_path / "o.csv", seed=3)).read())
    head = "file,split,built,family\na.csv,train,True,f\nb.csv,test,True,f\n\n"     # line 4 blank
    cases = [("c.csv,test,true,f\n", "built", "line 5: 'true' is neither True nor False"),
             ("c.csv,test,maybe,f\n", "built", "line 5: 'maybe' is neither True nor False"),
             ("c.csv,test,,f\n", "built", "line 5: '' is neither"),
             ("../outside.csv,test,True,f\n", "file", "line 5: '../outside.csv' is not a file inside the dataset"),
             (f"{tmp_path / 'outside.csv'},test,True,f\n", "file", "line 5: "),
             ("cases/../../outside.csv,test,True,f\n", "file", "line 5: 'cases/../../outside.csv' is not"),
             ("c.csv,test,True\n", "line 5", "3 fields, header has 4")]
    for k, (row, field, words) in enumerate(cases):
        folder = _dataset(tmp_path / f"ds{k}", head + row)
        assert main(["learn", "--dataset", str(folder), "--target", "drift_z", "--learner", "mlr"]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"error: {folder / 'index.csv'}: {field}: {words}"), err
    # the writer's own index (twin.dataset.card.write_index: pandas.DataFrame.to_csv of bool built)
    folder = tmp_path / "written"
    (folder / "cases").mkdir(parents=True)
    rows = []
    for name, split, built, seed in (("a", "train", True, 0), ("b", "test", True, 1), ("c", "test", False, 2)):
        if built:
            _write_csv(folder / "cases" / f"{name}.csv", seed=seed)
        rows.append({"hash": name, "file": f"cases/{name}.csv", "split": split, "built": built, "bytes": 1})
    pd.DataFrame(rows).to_csv(folder / "index.csv", index=False)
    assert main(["learn", "--dataset", str(folder), "--target", "drift_z", "--learner", "mlr"]) == 0
    assert "[test: 1 runs]" in capsys.readouterr().out
