"""Fuzz suite: every bad input of ``tests/fuzz_cases.py`` across every subcommand is refused
cleanly - exit code 2, exactly one line ``error: <file>: <field>: <message>`` naming the expected
file and field, no traceback, and no file created, removed or modified in the case's folder
(snapshot of every file's type, size, mtime, mode and SHA-256 before and after). Cases run
in-process (``twin.cli.main``); none may reach a simulation (the prepared twin refuses to be
built while they run: a bad input must be caught before the long work). A sample runs as real
processes for the exit codes, and SIGTERM / Ctrl-C are sent to real processes.
"""

from __future__ import annotations

import hashlib
import os
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tests.fuzz_cases import all_cases
from tests.fuzz_files import good_files, result_dataset
from twin.cli import main

ROOT = Path(__file__).resolve().parent.parent
CASES = all_cases()


@pytest.fixture(scope="module")
def good():
    return good_files()


@pytest.fixture
def no_simulation(monkeypatch):
    """Bad input must be refused before any twin is prepared."""
    from twin.physics import prepared

    def refuse(*args, **kwargs):
        raise AssertionError("a bad input reached the simulation")

    monkeypatch.setattr(prepared.PreparedTwin, "__init__", refuse)


def snapshot(root: str) -> dict:
    """Every path below ``root``: files with type, size, mtime, mode and content hash; folders,
    links and pipes with their type and mode (a folder's mtime changes when a file is tried)."""
    out = {}
    for folder, dirs, files in os.walk(root):
        for name in dirs + files:
            path = os.path.join(folder, name)
            st = os.lstat(path)
            if stat.S_ISREG(st.st_mode):
                with open(path, "rb") as fh:
                    digest = hashlib.sha256(fh.read()).hexdigest()
                out[os.path.relpath(path, root)] = ("file", st.st_size, st.st_mtime_ns, st.st_mode, digest)
            else:
                out[os.path.relpath(path, root)] = (stat.S_IFMT(st.st_mode), st.st_mode)
    return out


def prepare(case, folder: Path, good: dict) -> list[str]:
    """Write the good files and the case's changes into ``folder``; return the argv."""
    for name, data in good.items():
        (folder / name).write_bytes(data)
    for name, data in case.files.items():
        if data is None:
            (folder / name).unlink()
            continue
        data = data() if callable(data) else data
        (folder / name).write_bytes(data.encode() if isinstance(data, str) else data)
    if case.setup:
        case.setup(str(folder))
    return [a.replace("{d}", str(folder)) for a in case.argv]


def check_one_error_line(err: str, source: str, field: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, f"expected one line on stderr, got:\n{err}"
    line = lines[0]
    assert line.startswith("error: ") and "Traceback" not in err
    assert line.startswith(f"error: {source}: "), f"expected the source {source!r} in: {line}"
    rest = line[len(f"error: {source}: "):]
    named, sep, message = rest.partition(": ")
    assert sep and named and message, f"no '<field>: <message>' in: {line}"
    assert field in named, f"expected the field {field!r}, got {named!r} in: {line}"
    return line


def test_the_suite_is_large_and_covers_every_command():
    commands = {c.argv[0] for c in CASES}
    assert commands >= {"simulate", "plot", "compare", "diagnose", "learn", "demo", "list"}
    assert len(CASES) >= 200
    assert len({c.id for c in CASES}) == len(CASES)


# seconds one in-process case may take: the slowest takes under 1 s (first imports included)
CASE_TIMEOUT_S = 20


@pytest.fixture
def case_timeout():
    """Fail a case that runs longer than :data:`CASE_TIMEOUT_S` instead of hanging the suite: a
    pipe case (``:pipe``, a FIFO with no writer) blocks in open() for ever if a command ever
    opens it before checking it is a regular file; SIGALRM interrupts the blocked call and the
    handler's failure ends the case (pytest.fail's exception is no InputError or OSError, so
    no handler of the command turns it into a clean refusal)."""
    def expired(signum, frame):
        pytest.fail(f"the case ran over {CASE_TIMEOUT_S} s (blocked opening a pipe or device?)", pytrace=False)

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(CASE_TIMEOUT_S)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_is_refused_cleanly(case, tmp_path, good, no_simulation, capsys, case_timeout):
    if case.root_skip and os.geteuid() == 0:
        pytest.skip("root is not stopped by permission bits")
    argv = prepare(case, tmp_path, good)
    before = snapshot(str(tmp_path))
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, f"exit code {code}; stderr:\n{err}"
    assert "Traceback" not in out
    check_one_error_line(err, case.source.replace("{d}", str(tmp_path)), case.field)
    assert snapshot(str(tmp_path)) == before, "the command created, removed or changed a file"


# --------------------------------------------------------------------- real processes (a sample)
SAMPLE = ["simulate.scenario:speed-1e300-krpm", "simulate.o:link-to-input", "compare.csv:temperature-in-kelvin",
          "learn:train-twice"]
READY = """
import signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)   # as at a terminal, even when pytest runs in a background job
import twin.cli as cli
inner = cli._main
def ready(argv):       # "ready" from inside main's handler: a loaded machine cannot deliver Ctrl-C before it
    print("ready", flush=True)
    return inner(argv)
cli._main = ready
sys.exit(cli.main(sys.argv[1:]))
"""
SLOW_WRITE = """
import sys, time
import xarray
def slow(self, path, *args, **kwargs):
    with open(path, "wb") as fh:
        fh.write(b"partial")
    print("writing", flush=True)
    time.sleep(120)
xarray.Dataset.to_netcdf = slow
from twin.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _env():
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}


@pytest.fixture(scope="module")
def processes(tmp_path_factory, good):
    """Start every real process at once (each pays the interpreter's imports), then wait."""
    procs = {}
    by_id = {c.id: c for c in CASES}
    for cid in SAMPLE:
        folder = tmp_path_factory.mktemp("proc")
        argv = prepare(by_id[cid], folder, good)
        procs[cid] = (folder, by_id[cid], snapshot(str(folder)), subprocess.Popen(
            [sys.executable, "-m", "twin.cli", *argv], env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True))
    folder = tmp_path_factory.mktemp("sigterm")
    (folder / "short.toml").write_bytes(good["short.toml"])
    term = subprocess.Popen([sys.executable, "-c", SLOW_WRITE, "simulate", "cframe-vmc", str(folder / "short.toml"),
                             "-o", str(folder / "out.nc"), "--mesh", "coarse"],
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    early_folder = tmp_path_factory.mktemp("sigint")
    (early_folder / "short.toml").write_bytes(good["short.toml"])
    early = subprocess.Popen([sys.executable, "-c", READY, "simulate", "cframe-vmc", str(early_folder / "short.toml"),
                              "-o", str(early_folder / "out.nc"), "--mesh", "coarse"],
                             env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert early.stdout.readline().strip() == "ready"
    time.sleep(0.3)   # main() is loading the commands (or preparing the twin): Ctrl-C now
    early.send_signal(signal.SIGINT)
    results = {cid: (folder, case, before, *p.communicate(timeout=300), p.returncode)
               for cid, (folder, case, before, p) in procs.items()}
    results["early"] = (early_folder, *early.communicate(timeout=120), early.returncode)
    line = term.stdout.readline()      # wait until it writes (or ends)
    if line.strip() == "writing":
        term.send_signal(signal.SIGTERM)
    out, err = term.communicate(timeout=120)
    results["sigterm"] = (folder, line + out, err, term.returncode)
    return results


@pytest.mark.parametrize("cid", SAMPLE)
def test_real_process_exit_code_and_one_line(processes, cid):
    folder, case, before, out, err, code = processes[cid]
    assert code == 2, err
    check_one_error_line(err, case.source.replace("{d}", str(folder)), case.field)
    assert snapshot(str(folder)) == before


def test_sigterm_while_writing_leaves_no_file(processes):
    folder, out, err, code = processes["sigterm"]
    assert "writing" in out, err
    assert code == 143, err
    assert err.strip().splitlines()[-1] == "interrupted: no output written"
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert sorted(p.name for p in folder.iterdir()) == ["short.toml"]   # no .twin-* temporary, no out.nc


def test_ctrl_c_in_the_first_second_is_one_line(processes):
    folder, out, err, code = processes["early"]
    assert "Traceback" not in err
    assert code == 130 and err.strip() == "interrupted: no output written", err
    assert sorted(p.name for p in folder.iterdir()) == ["short.toml"]


# ------------------------------------------------------------------------- interrupts in-process
def test_an_interrupt_swallowed_by_a_finaliser_still_stops_the_command(monkeypatch, capsys):
    """Ctrl-C (or SIGTERM) that lands inside a finaliser or a weakref callback (the import system's
    module locks have one) is an "unraisable" exception: Python printed "Exception ignored in ..."
    with a traceback, swallowed it, and the command ran on. main() hands it back to the main thread:
    one line, exit code 130 (143 for SIGTERM), nothing after it runs."""
    import signal

    import twin.cli as cli

    class Dying:
        def __init__(self, exc):
            self.exc = exc

        def __del__(self):
            raise self.exc

    ran_on = []

    def command(exc):
        def run(argv):
            Dying(exc)                  # dropped at once: __del__ raises into the unraisable hook
            time.sleep(0.3)             # the interrupt is tripped 10 ms later, raised when the sleep returns
            ran_on.append(exc)
            return 0
        return run

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        for exc, code in ((KeyboardInterrupt(), 130), (cli.Terminated(), 143)):
            monkeypatch.setattr(cli, "_main", command(exc))
            assert cli.main([]) == code
            assert capsys.readouterr().err.strip() == "interrupted: no output written"
    finally:
        signal.signal(signal.SIGINT, old)
    assert ran_on == []


def test_interrupt_names_the_outputs_that_are_complete(tmp_path, capsys, monkeypatch):
    """The result is written, then Ctrl-C during the second output: the first is whole and said
    so, the second leaves neither its name nor a temporary file."""
    from twin.cli import cmd_simulate
    from twin.io import fields

    (tmp_path / "s.toml").write_text(good_files()["short.toml"].decode())
    ds = result_dataset()
    fake = SimpleNamespace(mm=SimpleNamespace(nnodes=1, nheat=1), hottest_field=np.zeros(1), hottest_time=0.0)
    monkeypatch.setattr(cmd_simulate, "simulate_with_progress", lambda *a: (ds, fake))

    def interrupted(mm, field, path, time_s):
        Path(path).write_bytes(b"partial")
        raise KeyboardInterrupt

    monkeypatch.setattr(fields, "write_temperature_field", interrupted)
    code = main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(tmp_path / "r.nc"),
                 "--field", str(tmp_path / "hot.vtu")])
    err = capsys.readouterr().err
    assert code == 130
    assert err.strip() == f"interrupted: {tmp_path / 'r.nc'} complete, nothing else written"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.nc", "s.toml"]


def test_atomic_write_never_replaces_a_device():
    from twin.errors import InputError
    from twin.io.atomic import atomic_write

    with pytest.raises(InputError, match="device"):
        atomic_write("/dev/null", lambda tmp: Path(tmp).write_text("x"))
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_a_run_with_nan_readings_fails_and_writes_nothing(tmp_path, capsys, monkeypatch):
    """A result never passes NaN off as a number: the readings are checked before anything is
    written (here the integrator is made to diverge)."""
    import numpy as np

    from twin.physics import prepared

    real = prepared.integrate

    def diverging(*args, **kwargs):
        out = real(*args, **kwargs)
        out[len(out) // 2:] = np.nan
        return out

    monkeypatch.setattr(prepared, "integrate", diverging)
    (tmp_path / "s.toml").write_text(good_files()["short.toml"].decode())
    code = main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(tmp_path / "r.nc"), "--mesh", "coarse"])
    err = capsys.readouterr().err
    assert code == 2 and "NaN or infinite" in err and "from t = " in err
    check_one_error_line(err, str(tmp_path / "s.toml"), "")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
