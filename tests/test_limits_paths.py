"""The input-checking layer: physical limits (twin/limits.py) and files (twin/io/paths.py)."""

from __future__ import annotations

import os

import numpy as np
import pytest

from geometries import MACHINES, build_machine
from twin import limits
from twin.errors import InputError
from twin.io.atomic import output_folder
from twin.io.paths import Files, read_text, same_file, within


def test_absolute_zero_is_the_lowest_temperature():
    """T >= -273.15 degC (0 K); just above is still refused as implausible, not as impossible."""
    with pytest.raises(InputError, match="below absolute zero"):
        limits.check_temperatures(-273.16, "s", "f", "structure")
    with pytest.raises(InputError, match="plausible"):
        limits.check_temperatures(-273.15, "s", "f", "structure")
    assert limits.check_temperatures([-40.0, 200.0], "s", "f", "structure").tolist() == [-40.0, 200.0]
    with pytest.raises(InputError, match="kelvin"):      # 20 degC logged as 293.15 K
        limits.check_temperatures(np.array([293.15, 293.2]), "s", "f", "structure")
    with pytest.raises(InputError, match="not a finite"):
        limits.check_temperatures([20.0, np.nan], "s", "f")


def test_speed_limit_is_the_machines():
    m = build_machine("cframe-vmc")
    assert limits.max_speed(m) == 9000.0
    limits.check_speeds([0.0, 9000.0], m, "s", "f")
    limits.check_speeds(9000.0 * 1.05, m, "s", "f", logged=True)
    for bad in (9000.5, -1.0, np.inf):
        with pytest.raises(InputError):
            limits.check_speeds(bad, m, "s", "f")
    assert limits.max_speed(None) == limits.UNDECLARED_MAX_SPEED


def test_a_scenario_from_a_log_keeps_the_logs_tolerance():
    from twin.scenario import Ambient, Scenario

    m = build_machine("cframe-vmc")
    steps = ((600.0, 9400.0),)
    with pytest.raises(InputError, match="maximum of 9000 rpm"):
        limits.check_scenario(Scenario("typed", steps, Ambient("constant")), m)
    limits.check_scenario(Scenario("measured", steps, Ambient("constant"), extra={"logged": True}), m)


def test_a_c_axis_log_keeps_the_logs_tolerance_and_no_machine_sets_no_maximum():
    """C-axis speeds (``check_c_axis_speeds``): within the machine's C-axis maximum
    (``gantry-ram``: 3200 rpm), a log within it plus LOGGED_SPEED_MARGIN (5 %: 3360 rpm), as for
    the spindle; without a machine (a measurement read without one) finite and not negative only."""
    gantry = build_machine("gantry-ram")
    top = gantry.parameters["c_axis_max_speed"]
    limits.check_c_axis_speeds([0.0, top], gantry, "s", "f")
    limits.check_c_axis_speeds(top * 1.04, gantry, "s", "f", logged=True)
    for speed, logged in ((top * 1.01, False), (top * 1.06, True)):
        with pytest.raises(InputError, match="C-axis maximum"):
            limits.check_c_axis_speeds(speed, gantry, "s", "f", logged=logged)
    assert limits.check_c_axis_speeds([0.0, 2500.0, 1e5], None, "s", "f", logged=True).tolist() == [0.0, 2500.0, 1e5]
    for bad in (-1.0, np.nan):
        with pytest.raises(InputError, match="finite and not negative"):
            limits.check_c_axis_speeds([0.0, bad], None, "s", "f")


def test_probe_and_strain_readings_are_limited_on_both_sides_of_zero():
    """A probe reads within +-PROBE_RANGE (10 mm) of its zero and a strain gauge within
    +-STRAIN_RANGE (5000 um/m): a reading of -20 mm or -6000 um/m is a unit mistake as much as
    +20 mm is (thermal drift may shrink as well as grow)."""
    limits.check_displacements([-9.9e-3, 9.9e-3], "s", "f")
    limits.check_strains([-4.9e-3, 4.9e-3], "s", "f")
    for check, value in ((limits.check_displacements, -0.02), (limits.check_strains, -6e-3)):
        with pytest.raises(InputError, match="beyond"):
            check([0.0, value], "s", "f")


def test_a_cold_structure_logged_in_kelvin_gets_the_kelvin_hint():
    """The kelvin hint covers the structure range in kelvin, 233.15 K to 473.15 K (-40 to
    200 degC): a machine at -20 degC logged as 253.15 K is refused as implausible degC and told
    it looks like kelvin; a reading beyond that range is not."""
    with pytest.raises(InputError, match="looks like kelvin"):
        limits.check_temperatures(253.15, "s", "f", "structure")
    with pytest.raises(InputError) as err:
        limits.check_temperatures(500.0, "s", "f", "structure")
    assert "kelvin" not in str(err.value)


def test_a_batch_is_limited_by_its_cases_times_samples():
    """A batch holds every reading of every case at once: cases x samples at most
    MAX_CASE_STEPS (2e7), so 1000 cases of 20000 samples fit and 1000 of 20001 do not."""
    limits.check_batch_size(1000, 20000, "s", "cases")
    with pytest.raises(InputError, match="case-samples"):
        limits.check_batch_size(1000, 20001, "s", "cases")


@pytest.mark.parametrize("name", sorted(MACHINES))
def test_every_sensor_site_and_probe_target_lies_on_its_part(name):
    """The position check accepts every point a machine names (so it refuses only what is off)."""
    m = build_machine(name)
    for p in m.points:
        limits.check_position(m, p.xyz, p.part, "s", p.name)


def test_run_size_is_steps_times_nodes():
    from twin.scenario import Ambient, Scenario

    sc = Scenario("s", ((3600.0, 0.0),), Ambient("constant"), 1.0)     # 3600 steps
    limits.check_run_size(sc, int(limits.MAX_NODE_STEPS // 3600))
    with pytest.raises(InputError, match="node-steps"):
        limits.check_run_size(sc, int(limits.MAX_NODE_STEPS // 3600) + 1)
    with pytest.raises(InputError, match="time steps"):
        limits.check_steps(2e6, 1.0, "s", "f")


def test_seed_range():
    assert limits.check_seed("0") == 0 and limits.check_seed(str(2**32 - 1)) == 2**32 - 1
    for bad in ("-1", str(2**32), "1.5", "x"):
        with pytest.raises(ValueError):
            limits.check_seed(bad)


def test_an_output_is_never_an_input_in_either_order(tmp_path):
    a = tmp_path / "a.csv"
    a.write_text("x\n")
    os.link(a, tmp_path / "b.csv")
    files = Files()
    files.output(tmp_path / "b.csv", "-o", (".csv",))
    with pytest.raises(InputError, match="never replaces an input") as err:
        files.input(a, "--train")
    assert err.value.source == str(tmp_path / "b.csv") and err.value.field == "-o"
    assert same_file(a, tmp_path / "b.csv") and not same_file(a, tmp_path / "c.csv")
    files = Files()
    files.output(tmp_path / "c.csv", "-o")
    with pytest.raises(InputError, match="also the output of -o"):
        files.output(tmp_path / "c.csv", "--json")


def test_within_a_folder_by_any_spelling(tmp_path):
    """``within(path, folder)``: the folder itself, anything below it, and the same through a
    link to the folder or a ``..`` detour; not a sibling whose name merely starts alike."""
    folder = tmp_path / "data"
    (folder / "sub").mkdir(parents=True)
    os.symlink(folder, tmp_path / "alias")
    assert within(folder, folder) and within(folder / "sub" / "x.csv", folder)
    assert within(tmp_path / "alias" / "sub" / "x.csv", folder)
    assert within(tmp_path / "other" / ".." / "data" / "x.csv", folder)
    (tmp_path / "data2").mkdir()
    assert not within(tmp_path / "data2" / "x.csv", folder) and not within(tmp_path / "x.csv", folder)


def test_within_a_bind_mounted_folder(tmp_path, monkeypatch):
    """A bind mount is a second path to the same inode that no link resolves: ``within`` must
    compare the ancestors' inodes. The kernel's answer for a mount of ``data`` on ``mnt`` is
    played by os.path.samefile (mounting needs privileges a test run may not have)."""
    (tmp_path / "data").mkdir()
    (tmp_path / "mnt" / "sub").mkdir(parents=True)
    mounted = {str(tmp_path / "data"), str(tmp_path / "mnt")}
    real = os.path.samefile
    monkeypatch.setattr(os.path, "samefile", lambda a, b: {str(a), str(b)} <= mounted or real(a, b))
    assert within(tmp_path / "mnt" / "sub" / "x.csv", tmp_path / "data")
    assert not within(tmp_path / "x.csv", tmp_path / "data")


def test_an_output_folder_is_never_an_output_file_in_either_order(tmp_path):
    """`twin diagnose --json d.json --report d.json` is refused before any work: a folder and a
    file of the same command cannot be one path, whichever is declared first."""
    files = Files()
    files.output(tmp_path / "d.json", "--json", (".json",))
    with pytest.raises(InputError, match="also the output of --json"):
        files.folder(tmp_path / "d.json", "--report", ("index.html",))
    files = Files()
    files.folder(tmp_path / "rep", "--report", ("index.html",))
    with pytest.raises(InputError, match="also the output of --report"):
        files.output(tmp_path / "rep", "--json")
    assert not (tmp_path / "d.json").exists() and not (tmp_path / "rep").exists()


def test_text_inputs_are_utf8_with_or_without_a_bom(tmp_path):
    p = tmp_path / "s.toml"
    p.write_bytes("\ufeffname = 'caf\u00e9'\n".encode("utf-8"))
    assert read_text(p) == "name = 'café'\n"
    p.write_bytes("name = 'caf\u00e9'\n".encode("latin-1"))
    with pytest.raises(InputError, match="not UTF-8 .* line 1"):
        read_text(p, "scenario")


def test_a_path_whose_bytes_are_not_utf8_is_refused_before_any_work(tmp_path, capsys):
    """A file name with bytes that are not UTF-8 (Python holds them as surrogate escapes) is one
    error naming the option, exit 2, before the run: a simulation used to run whole and then fail
    with a traceback writing the scenario's name into the result, and a diagnosis wrote the
    escape into its JSON."""
    from tests.fuzz_files import SCENARIO
    from twin.cli import main
    from twin.io.paths import as_path

    bad = os.fsdecode(b"\xff.toml")
    with pytest.raises(InputError) as err:
        as_path(bad, "scenario")
    assert err.value.field == "scenario" and "not valid UTF-8" in err.value.message
    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    for argv, field in ((["simulate", "cframe-vmc", str(tmp_path / bad), "-o", str(tmp_path / "r.nc")], "scenario"),
                        (["simulate", "cframe-vmc", str(scenario), "-o", str(tmp_path / os.fsdecode(b"\xfe.nc"))], "-o")):
        capsys.readouterr()
        assert main(argv + ["--mesh", "coarse"]) == 2
        assert f"{field}: the path" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


def test_a_netcdf3_file_is_named_as_such(tmp_path):
    """A NetCDF-3 classic file (magic bytes CDF 1, 2 or 5; what xarray's scipy engine writes) is
    readable NetCDF, but not the NetCDF-4 the twin reads: the error says which, and how to convert."""
    from tests.fuzz_files import result_dataset
    from twin.io.results import read_result

    path = tmp_path / "classic.nc"
    result_dataset().to_netcdf(path, engine="scipy")
    assert path.read_bytes()[:3] == b"CDF"
    with pytest.raises(InputError, match="a NetCDF-3 \\(classic\\) file; the twin reads NetCDF-4"):
        read_result(path, "result")
    path.write_bytes(b"CDF\x09 not netcdf at all")
    with pytest.raises(InputError, match="not a readable NetCDF file"):
        read_result(path, "result")


def test_a_made_folder_is_removed_when_the_command_fails_and_kept_when_it_existed(tmp_path):
    made = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        with output_folder(made):
            assert made.is_dir()
            raise KeyboardInterrupt
    assert not made.exists()
    made.mkdir()
    with pytest.raises(RuntimeError):
        with output_folder(made):
            raise RuntimeError
    assert made.is_dir()


def test_an_output_error_is_said_once(tmp_path):
    """A refused output names its reason once, not wrapped in a second 'cannot be used' message."""
    from twin.io.paths import output_file
    from twin.io.paths import output_folder as checked_folder

    with pytest.raises(InputError) as err:
        output_file(tmp_path / "p", "-o", (".nc",))
    assert err.value.message.startswith("unsupported suffix") and "cannot be used" not in err.value.message
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError) as err:
        checked_folder(tmp_path / "f", "--report")
    assert err.value.message == "exists and is not a folder"


def test_the_io_functions_called_from_python_name_a_bad_path_or_argument(tmp_path):
    """API audit: a number or None for a path is an InputError, not pathlib's TypeError; a
    measurement given as its own mapping says so; write_netcdf refuses a non-NetCDF name and a
    non-Dataset; read_result's ``required`` is a tuple of names, not a text read letter by letter."""
    from tests.fuzz_files import result_dataset
    from twin.errors import InputError
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement
    from twin.io.results import read_result, write_netcdf

    csv, toml = write_measurement(result_dataset(), tmp_path, "m", "cframe-vmc")
    nc = write_netcdf(result_dataset(), tmp_path / "r.nc")
    for call, field in ((lambda: read_measurement(5), "measurement"), (lambda: read_measurement(None), "measurement"),
                        (lambda: read_measurement(toml), "measurement"), (lambda: read_measurement(csv, machine=5), "machine"),
                        (lambda: write_netcdf(result_dataset(), tmp_path / "r.csv"), "output"),
                        (lambda: write_netcdf(None, tmp_path / "n.nc"), "output"),
                        (lambda: read_result(nc, required="temperature"), "required"),
                        (lambda: read_result(nc, min_samples=-3), "min_samples")):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, str(err.value)
    assert not (tmp_path / "r.csv").exists() and not (tmp_path / "n.nc").exists()
    assert read_result(nc, required=("temperature",)).sizes["time"] > 1


def test_a_full_disk_is_one_error_and_leaves_no_file(tmp_path, monkeypatch):
    """Helper audit: HDF5 crashed the process (exit 139) when the disk filled under a NetCDF write,
    and Pillow's TIFF writer left a short file under its final name without an error. A NetCDF
    file needs its size and the reserve free before it is written; any file must leave the
    reserve free after it is written (else it may be short); either way nothing is kept, not
    even the temporary file."""
    from tests.fuzz_files import result_dataset
    from twin.errors import InputError
    from twin.io import atomic
    from twin.io.atomic import atomic_write_text
    from twin.io.results import write_netcdf

    monkeypatch.setattr(atomic, "free_space", lambda folder: atomic.RESERVE + 1000)
    with pytest.raises(InputError, match="not enough free space on its disk"):
        write_netcdf(result_dataset(), tmp_path / "r.nc")
    free = iter([10 ** 12, 10])                     # enough before, the disk full after
    monkeypatch.setattr(atomic, "free_space", lambda folder: next(free))
    with pytest.raises(InputError, match="the disk is full"):
        write_netcdf(result_dataset(), tmp_path / "r.nc")
    monkeypatch.setattr(atomic, "free_space", lambda folder: 10)
    with pytest.raises(InputError, match="the disk is full"):
        atomic_write_text(tmp_path / "a.txt", "x")
    assert list(tmp_path.iterdir()) == []


def test_a_late_failure_says_which_outputs_were_written_whole(tmp_path, monkeypatch, capsys):
    """Helper audit: a report whose second file fails (a full disk) left the first without a word;
    the one error line now lists the outputs written before the error, each whole."""
    from tests.fuzz_files import result_dataset
    from twin.cli import main
    from twin.io import atomic
    from twin.io.results import write_netcdf

    nc = write_netcdf(result_dataset(), tmp_path / "r.nc")
    free = iter([10 ** 12, 10])                        # report.md written, then the disk is full
    monkeypatch.setattr(atomic, "free_space", lambda folder: next(free, 10))
    assert main(["report", "iso230-3", str(nc), "-o", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "the disk is full" in err[0]
    assert err[0].endswith(f"(written before the error, each whole: {tmp_path / 'rep' / 'report.md'})")


def test_files_refuses_a_path_that_is_no_path_naming_the_field(tmp_path):
    """Audit: Files.output, check_output and folder raised pathlib's TypeError for None or a number
    (their clash check built a Path before the path was checked), and check_output took ""."""
    files = Files()
    for declare in (files.output, files.check_output, files.folder):
        for bad in (None, 5, "", "   "):
            with pytest.raises(InputError) as err:
                declare(bad, "--out")
            assert err.value.field == "--out" and "expected a file path" in err.value.message
    assert files.outputs == [] and files.folders == []


def test_a_measurement_pair_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    """Audit: write_measurement wrote run.csv, then run.toml; a full disk at the second left the
    CSV without its mapping. Both are now written to temporaries and renamed only when both are
    whole: the failure leaves neither (nor a temporary file), and a pair written before stays."""
    from tests.fuzz_files import result_dataset
    from twin.io import atomic
    from twin.io.measurement_writer import write_measurement

    csv, toml = write_measurement(result_dataset(), tmp_path, "old", "cframe-vmc")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    free = iter([10 ** 12, 10])                     # the CSV fits, the disk is full after the mapping
    monkeypatch.setattr(atomic, "free_space", lambda folder: next(free))
    with pytest.raises(InputError, match="the disk is full") as err:
        write_measurement(result_dataset(), tmp_path, "run", "cframe-vmc")
    assert err.value.source.endswith("run.toml")
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_a_written_file_is_readable_by_everyone_not_only_its_owner(tmp_path):
    """atomic_write writes through ``tempfile.mkstemp``, which makes the file 0o600 (owner only);
    it sets 0o644 before the rename, so a result in a shared folder reads like one ``open()``
    would write under the usual umask 022 (others may read it), whatever the mkstemp default."""
    import stat

    from twin.io.atomic import atomic_write_text

    path = atomic_write_text(tmp_path / "a.txt", "x")
    assert stat.S_IMODE(path.stat().st_mode) == 0o644
    (tmp_path / "b.txt").write_text("old")
    os.chmod(tmp_path / "b.txt", 0o600)
    assert stat.S_IMODE(atomic_write_text(tmp_path / "b.txt", "new").stat().st_mode) == 0o644


def test_an_existing_read_only_output_is_refused_and_kept(tmp_path, monkeypatch):
    """An output that exists and is not writable is refused ("exists and is read-only", naming
    the field) before anything is written, and the file stays as it was; a writable one is
    accepted. The suite runs as root, for whom os.access always says writable (the fuzz suite's
    read-only cases are skipped as root), so os.access is made to say no for that one file."""
    from twin.io import paths
    from twin.io.atomic import atomic_write_text
    from twin.io.paths import output_file

    locked, free = tmp_path / "locked.csv", tmp_path / "free.csv"
    locked.write_text("kept")
    free.write_text("old")
    real = os.access

    def access(path, mode, *args, **kwargs):
        if os.path.abspath(path) == str(locked) and mode & os.W_OK:
            return False
        return real(path, mode, *args, **kwargs)

    monkeypatch.setattr(paths.os, "access", access)
    with pytest.raises(InputError) as err:
        output_file(locked, "-o")
    assert (err.value.field, err.value.message) == ("-o", "exists and is read-only")
    with pytest.raises(InputError, match="exists and is read-only"):
        atomic_write_text(locked, "replaced")
    assert locked.read_text() == "kept"
    assert output_file(free, "-o") == free
    assert sorted(p.name for p in tmp_path.iterdir()) == ["free.csv", "locked.csv"]


def test_a_result_whose_time_repeats_a_value_is_refused(tmp_path):
    """read_result needs a strictly increasing time: a repeated time (a step of 0 s, as a logger
    writes twice in one tick) is refused like a backwards one (diff <= 0, not only < 0): an
    interpolation or a time step over it would divide by zero."""
    from tests.fuzz_files import result_dataset
    from twin.io.results import read_result

    ds = result_dataset()
    t = ds.time.values.copy()
    t[2] = t[1]                                   # 0, 60, 60, 180 ...
    path = tmp_path / "r.nc"
    ds.assign_coords(time=("time", t, {"units": "s"})).to_netcdf(path, engine="h5netcdf")
    with pytest.raises(InputError) as err:
        read_result(path, "result")
    assert err.value.field == "time"
    assert err.value.message == "time is not increasing at sample 3 (60 -> 60 s)"
    t[2] = t[1] + 1e-3                            # a millisecond later is increasing
    ds.assign_coords(time=("time", t, {"units": "s"})).to_netcdf(tmp_path / "ok.nc", engine="h5netcdf")
    assert read_result(tmp_path / "ok.nc", "result").sizes["time"] == ds.sizes["time"]


def test_an_output_file_ending_in_a_separator_is_refused(tmp_path, capsys):
    """``-o out.nc/`` names a folder; pathlib dropped the slash and the run wrote the file out.nc."""
    from tests.fuzz_files import SCENARIO
    from twin.cli import main
    from twin.io.paths import output_file

    with pytest.raises(InputError) as err:
        output_file(f"{tmp_path}/out.nc/", "-o", (".nc",))
    assert err.value.field == "-o" and "ends in a path separator" in err.value.message
    assert output_file(tmp_path / "out.nc", "-o", (".nc",)) == tmp_path / "out.nc"
    (tmp_path / "s.toml").write_text(SCENARIO, encoding="utf-8")
    assert main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", f"{tmp_path}/out.nc/", "--mesh", "coarse"]) == 2
    assert "ends in a path separator" in capsys.readouterr().err
    assert not (tmp_path / "out.nc").exists()


def test_a_value_just_past_its_limit_is_written_with_the_digits_that_tell_them_apart():
    """"9000 rpm is beyond machine cframe-vmc's maximum of 9000 rpm" for 9000.0001 rpm: %g hid it."""
    m = build_machine("cframe-vmc")
    with pytest.raises(InputError, match=r"9000\.0001 rpm is beyond machine cframe-vmc's maximum of 9000 rpm"):
        limits.check_speeds([9000.0001], m, "s.toml", "speed")
    with pytest.raises(InputError, match=r" 9500 rpm is beyond"):
        limits.check_speeds([9500.0], m, "s.toml", "speed")
    assert limits.beside(2.0 + 1e-12, 2.0) == "2.000000000001" and limits.beside(3.0, 2.0) == "3"
    assert limits.beside(2.0 + 1e-17, 2.0) == repr(2.0 + 1e-17)        # equal as floats: nothing to tell
