"""Build a plan's cases: one task per case on a local process pool, in this process, or on a Dask
distributed cluster, all through :func:`build_case` and a ``concurrent.futures`` executor.

Each worker (a process, or a thread of a Dask worker) keeps one
:class:`twin.physics.prepared.PreparedTwin` per (machine, mesh, solver) and reuses it for every
case it runs: the mesh, the assembled matrices, the factorisations and the elastic adjoints are
built once per worker, not once per case.

Each case is written atomically (:func:`twin.io.results.write_netcdf`) to ``cases/<hash>.nc``; a
finished case is a whole file whose ``case_hash`` attribute is its name, so a rerun skips it and
an interrupted run leaves only whole files (and a temporary ``.twin-*`` file at most, which the
next run removes).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import json
import re
import threading
import time
from pathlib import Path

from twin import limits
from twin.dataset.plan import Case, check_cases, moved_axes
from twin.dataset.plan import case_hash as hash_of
from twin.errors import InputError, describe
from twin.io.paths import as_path, output_folder

CASES = "cases"   # the folder of the case files inside a dataset folder
MAX_JOBS = 1024   # the most workers a build takes (as the command's --jobs)
COMPRESSION = {"zlib": True, "complevel": 4, "shuffle": True}   # deterministic (gzip), lossless
_local = threading.local()


def _prepared(machine_name: str, mesh: str, solver: str, axes: tuple[str, ...] = ()):
    """This worker's PreparedTwin of (machine, mesh, solver), with the feed drives of ``axes``
    (the axes a scenario moves, :func:`geometries.axes.with_feed_drives`), built on first use
    (call it under the thread limits of :func:`simulate_case`)."""
    cache = _local.__dict__.setdefault("twins", {})
    key = (machine_name, mesh, solver, axes)
    if key not in cache:
        from geometries import build_machine
        from geometries.axes import with_feed_drives
        from twin.physics.prepared import PreparedTwin

        machine = build_machine(machine_name)
        cache[key] = PreparedTwin(with_feed_drives(machine, set(axes)) if axes else machine, resolution=mesh,
                                  solver=solver)
    return cache[key]


def simulate_case(record: dict, case_hash: str = "", max_steps: int | None = None):
    """:func:`_simulate_case` with BLAS, OpenMP and the twin's own helper thread
    (:mod:`twin.physics.parallel`) held to one thread: a case computes the same bits on every
    worker (a pool process, a Dask worker that sets its own thread counts, this process), and the
    workers of a pool do not oversubscribe the cores."""
    from threadpoolctl import threadpool_limits

    from twin.physics.parallel import limited

    with threadpool_limits(limits=1), limited(1):
        return _simulate_case(record, case_hash, max_steps)


def _simulate_case(record: dict, case_hash: str = "", max_steps: int | None = None):
    """Run one case record (:mod:`twin.dataset.plan`) on this worker's prepared twin; returns
    (Dataset, RunResult). The Dataset carries ``case_hash``, ``dataset_family`` and
    ``dataset_draw`` attributes and a scalar ``case`` coordinate (the hash), so that
    ``xarray.open_mfdataset(..., combine="nested", concat_dim="case")`` labels the cases.
    ``max_steps`` cuts the scenario after that many time steps (for a calibration run). Wall
    times (:data:`twin.io.results.WALL_TIMES`) are left out of the attributes, so that the same record always gives
    the same bytes; numeric variables are written gzip-compressed (:data:`COMPRESSION`)."""
    from twin import limits
    from twin.io.results import to_dataset
    from twin.model import model_spec
    from twin.observe import sensor_points, standard_observers
    from twin.observe.camera import cameras as camera_observers
    from twin.observe.sensor_grid import surface_sensor_grid
    from twin.motion_checks import check_motions
    from twin.scenario import scenario_from_dict
    from twin.simulate import run

    check_record(record)
    if max_steps is not None and (not limits.is_whole(max_steps) or max_steps < 1):
        raise InputError("simulate_case", "max_steps", f"expected a whole number of time steps >= 1, got {max_steps!r}")
    family = record["family"]
    data = json.loads(json.dumps(record["scenario"]))
    cams = [{"pose": p} for p in record["observers"]["cameras"]]
    if cams:
        own = data.get("camera", [])
        data["camera"] = (own if isinstance(own, list) else [own]) + cams
    sc = scenario_from_dict(data, f"dataset:{family}", default_name=family)
    twin = _prepared(record["machine"], record["mesh"], record["solver"], moved_axes(sc))
    # the reduced basis is built from the film coefficients of the run that first needs it and then
    # cached (twin.physics.rom.reduced_basis): a case must not reuse another's, or its numbers would
    # depend on which case its worker ran before (--jobs 1 and --jobs 2 gave different files)
    twin.reduced.clear()
    machine = twin.machine
    check_motions(sc, machine)
    if max_steps is not None:
        sc = _truncated(sc, max_steps)
    spec = model_spec(machine, record["effects"], record["settings"])
    limits.check_scenario(sc, machine)
    limits.check_run_size(sc, twin.mm.nheat)
    grid = record["observers"]["surface_grid"]
    sensors = None
    if grid:
        sensors = sensor_points(machine) + surface_sensor_grid(machine, tuple(grid["parts"]), grid["spacing"])
    for c in sc.cameras:
        c.check(sc)
    observers = standard_observers(machine, sensors) + camera_observers(machine, list(sc.cameras))
    # a calibration's few steps (max_steps) are no whole run: its checks were the plan's (twin.dataset.plan)
    result = run(machine, sc, spec, theta=record["theta"], prepared=twin, observers=observers,
                 idle_effects=max_steps is not None)
    ds = to_dataset(result, record["seed"], record["mesh"])
    ds.attrs.update(case_hash=case_hash, dataset_family=family, dataset_draw=record["draw"])
    ds = ds.assign_coords(case=((), case_hash, {"long_name": "case hash (the file's name)"}))
    for var in ds.data_vars.values():
        if var.dtype.kind in "fiu" and var.ndim >= 1:
            var.encoding.update(COMPRESSION)
    return ds, result


RECORD_KEYS = ("family", "draw", "scenario", "observers", "machine", "mesh", "solver", "effects", "settings", "theta", "seed")


def check_record(record) -> None:
    """A case record as a plan makes it (:func:`twin.dataset.plan.plan`): a dict with at least
    :data:`RECORD_KEYS`, of a registered machine; an :class:`InputError` naming the key otherwise."""
    from geometries import MACHINES

    if not isinstance(record, dict):
        raise InputError("case record", "record", f"expected a plan's case record (a dict), got {describe(record)}")
    missing = [k for k in RECORD_KEYS if k not in record]
    if missing:
        raise InputError("case record", missing[0], "missing: not a record of twin.dataset.plan.plan")
    if not isinstance(record["machine"], str) or record["machine"] not in MACHINES:
        raise InputError("case record", "machine", f"unknown machine {record['machine']!r}; known: "
                                                   f"{', '.join(sorted(MACHINES))}")


def _truncated(sc, max_steps: int):
    """``sc`` cut after ``max_steps`` time steps [of its sample interval]."""
    from dataclasses import replace

    left, steps = max_steps * sc.sample_interval, []
    for duration, speed in sc.steps:
        if left <= 0:
            break
        steps.append((min(duration, left), speed))
        left -= duration
    return replace(sc, steps=tuple(steps))


def build_case(record: dict, case_hash: str, folder: str) -> dict:
    """Simulate one case and write ``folder/<hash>.nc`` atomically; returns {hash, bytes,
    seconds, steps} (``seconds``: wall time of this case on its worker)."""
    from twin.io.results import write_netcdf

    if not isinstance(record, dict) or not isinstance(case_hash, str) or case_hash != hash_of(record):
        raise InputError("build_case", "case_hash", f"{describe(case_hash)} is not the hash of the record "
                                                    "(twin.dataset.plan.case_hash): a case's file is named by it")
    folder = as_path(folder, "folder")          # before the run: a number here failed after it
    if not folder.is_dir():
        raise InputError(str(folder), "folder", "is not a folder: give the dataset's cases folder")
    t0 = time.perf_counter()
    ds, result = simulate_case(record, case_hash)
    path = write_netcdf(ds, folder / f"{case_hash}.nc", "case")
    return {"hash": case_hash, "bytes": path.stat().st_size, "seconds": time.perf_counter() - t0,
            "steps": int(result.timings["steps"])}


def is_whole(path: Path, case_hash: str) -> bool:
    """Whether ``path`` is a finished case file: readable NetCDF whose ``case_hash`` is its name."""
    if not path.is_file():
        return False
    try:
        import h5py

        with h5py.File(path, "r") as f:
            value = f.attrs.get("case_hash")
    except Exception:  # noqa: BLE001 - any unreadable file is not a finished case
        return False
    if isinstance(value, bytes):
        value = value.decode()
    return str(value) == case_hash


# the temporary name an interrupted case write leaves (twin.io.atomic: mkstemp's ".twin-" + 8
# characters + the case file's suffix); nothing else in the folder is a leftover of ours
TEMPORARY = re.compile(r"^\.twin-[a-z0-9_]{8}\.nc$")


def remove_temporaries(folder: Path) -> list[Path]:
    """Remove the temporary case files (:data:`TEMPORARY`) an interrupted run left in the cases
    folder (one run per dataset folder at a time); returns them. Any other file, such as a
    user's own ``.twin-notes.toml`` that the spec may even read, is kept."""
    gone = sorted(p for p in folder.iterdir() if TEMPORARY.match(p.name) and p.is_file()
                  and not p.is_symlink()) if folder.is_dir() else []
    for p in gone:
        p.unlink(missing_ok=True)
    return gone


class InlineExecutor(cf.Executor):
    """Runs each task in this process when its result is asked for (``jobs=1``): the same
    tasks as a pool, no pool; :func:`build` runs them one after the other."""

    def submit(self, fn, /, *args, **kwargs):
        future = cf.Future()
        future.task = (fn, args, kwargs)
        return future


_ADDRESS = re.compile(r"^((tcp|tls|ucx|ws|wss)://)?(\[[0-9a-fA-F:.]+\]|[A-Za-z0-9_.-]+):\d{1,5}$")


def check_scheduler(scheduler: str | None) -> None:
    """Refuse a ``--scheduler`` that is neither ``local``, ``local-threads`` nor a scheduler
    address ``[protocol://]host:port`` before anything runs (:class:`twin.errors.InputError`)."""
    if scheduler is None or scheduler in ("local", "local-threads"):
        return
    if not isinstance(scheduler, str) or not _ADDRESS.match(scheduler):
        raise InputError("command line", "--scheduler", f"{scheduler!r} is not 'local', 'local-threads' or a Dask "
                                                        "scheduler address such as tcp://host:8786")


def _connect(scheduler: str):
    """A Dask client of the scheduler at ``scheduler``; one that cannot be reached is an
    :class:`twin.errors.InputError` on ``--scheduler``."""
    from distributed import Client

    try:
        return Client(scheduler, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as err:
        raise InputError("command line", "--scheduler", f"cannot reach the Dask scheduler at {scheduler} "
                                                        f"({type(err).__name__}: {err})") from None


CONNECT_TIMEOUT = "10s"     # how long a dataset waits for a remote Dask scheduler to answer


def check_jobs(jobs, source: str = "executor", field: str = "jobs") -> int:
    """``jobs`` as an int if it is a whole number of workers from 1 to :data:`MAX_JOBS` (the
    range of ``twin dataset --jobs``); an :class:`InputError` otherwise (0, negative numbers,
    2.5, True: never taken as "in this process")."""
    if not limits.is_whole(jobs):
        raise InputError(source, field, f"expected a whole number of workers from 1 to {MAX_JOBS}, got {jobs!r}")
    n = int(jobs)
    if not 1 <= n <= MAX_JOBS:
        raise InputError(source, field, f"must be from 1 to {MAX_JOBS} workers, got {n}")
    return n


def executor(scheduler: str | None = None, jobs: int = 1):
    """A ``concurrent.futures`` executor: ``scheduler=None``: a process pool of ``jobs``
    workers (in this process when ``jobs == 1``); ``"local"``: a Dask LocalCluster of ``jobs``
    single-thread worker processes; ``"local-threads"``: one in this process (``jobs`` threads);
    any other text: the address of a Dask scheduler (``tcp://host:8786``), whose workers must
    have thermal-twin installed. Dask needs the ``distributed`` package. ``jobs`` is a whole
    number from 1 to :data:`MAX_JOBS` (:func:`check_jobs`), ``scheduler`` is checked by
    :func:`check_scheduler`; both when it is called, before anything starts (use it in a
    ``with`` statement)."""
    jobs = check_jobs(jobs)
    check_scheduler(scheduler)
    return _executor(scheduler, jobs)


@contextlib.contextmanager
def _executor(scheduler: str | None, jobs: int):
    if scheduler is None:
        if jobs == 1:
            yield InlineExecutor()
            return
        import multiprocessing

        pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn"))
        try:
            yield pool
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
        return
    from distributed import Client, LocalCluster

    if scheduler in ("local", "local-threads"):
        threads = scheduler == "local-threads"
        cluster = LocalCluster(n_workers=1 if threads else jobs, threads_per_worker=jobs if threads else 1,
                               processes=not threads, dashboard_address=None)
        client = Client(cluster)
    else:
        cluster, client = None, _connect(scheduler)
    try:
        yield client.get_executor(pure=False)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def build(cases: list[Case], folder: Path, pool=None, progress=None) -> dict:
    """Build the ``cases`` not yet whole in ``folder/cases`` on the executor ``pool`` (default
    in this process); ``progress(done, total)`` after each case. Returns {hash: result of
    :func:`build_case`} of the cases built now. A failing case stops the build (cancelling the
    cases not started) and its error is raised; finished files stay. ``folder`` is a folder or
    can be made in an existing one (:func:`twin.io.paths.output_folder`: an
    :class:`InputError` otherwise, before anything is built); the other arguments are checked
    before the folder is made."""
    check_cases(cases, "build")
    if pool is not None and not callable(getattr(pool, "submit", None)):
        raise InputError("build", "pool", f"expected an executor (twin.dataset.executor), got {describe(pool)}")
    limits.check_progress(progress, "build")
    folder = output_folder(folder, "folder")
    out_dir = folder / CASES
    if folder.is_dir():
        output_folder(out_dir, "folder")   # a file named "cases" there is refused too
    made_folder = not folder.exists()
    created = not out_dir.exists()
    folder.mkdir(exist_ok=True)
    out_dir.mkdir(exist_ok=True)
    remove_temporaries(out_dir)
    todo = [c for c in cases if not is_whole(out_dir / c.file, c.hash)]
    done: dict[str, dict] = {}
    pool = pool or InlineExecutor()
    if progress is not None:
        progress(0, len(todo))
    futures = [pool.submit(build_case, c.record, c.hash, str(out_dir)) for c in todo]
    try:
        for r in _results(pool, futures):
            done[r["hash"]] = r
            if progress is not None:
                progress(len(done), len(todo))
    except BaseException:
        for f in futures:
            f.cancel()
        _stop(pool)
        if created and not any(out_dir.iterdir()):
            out_dir.rmdir()
            if made_folder and not any(folder.iterdir()):
                folder.rmdir()
        raise
    return done


def _stop(pool) -> None:
    """Stop a process pool's workers now (an interrupt or a failed case): a case being written
    leaves at most a temporary file, removed by the next run."""
    if isinstance(pool, cf.ProcessPoolExecutor):
        for p in list((getattr(pool, "_processes", None) or {}).values()):   # no public way to stop them
            p.terminate()
        pool.shutdown(wait=False, cancel_futures=True)


def _results(pool, futures):
    """The futures' results as they finish (in order, one at a time, for the inline executor)."""
    if isinstance(pool, InlineExecutor):
        for f in futures:
            fn, args, kwargs = f.task
            yield fn(*args, **kwargs)
        return
    for f in cf.as_completed(futures):
        yield f.result()
