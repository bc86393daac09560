"""How long a plan will take, from a calibration run on this machine.

Per (machine, mesh, solver, axes moved) of the plan (a case that moves axes runs on a twin with
their feed drives, :func:`twin.dataset.runner._prepared`): prepare that twin (timed: the mesh,
the matrices, the elastic factorisation and adjoints), then run the group's first case cut to
``calibration_steps``
time steps (a warm-up, so the factorisations of its operators are done once) and again cut to
``length_steps`` (20 times as many by default, or the whole case when shorter), timed: the cost of
one step [s], which includes the observers, the packaging of the result and the case's own
set-up spread over its steps (the reduced model builds a basis for each case, 0.1-0.3 s on the
coarse mesh: timed over 30 steps it read 2-3 ms a step where a 1000-step case spends 0.6 ms, and
the bundled 100-case example was estimated 3-5 times too slow). A case with more distinct spindle
speeds than the calibration saw costs more (one factorisation per new operator on the direct
solver); the estimate does not count them.
"""

from __future__ import annotations

import time

from threadpoolctl import threadpool_limits

from twin.dataset.plan import Case, check_cases, moved_axes, record_scenario
from twin.dataset.runner import _prepared, check_jobs, simulate_case
from twin.errors import InputError
from twin.limits import is_whole


def _steps(case: Case) -> int:
    return int(round(case.info["duration [s]"] / case.info["sample_interval [s]"]))


def estimate(cases: list[Case], jobs: int = 1, calibration_steps: int = 30, length_steps: int | None = None,
             cores: int | None = None) -> dict:
    """{"cases", "steps", "prepare_s" (per worker), "per_step_s" (by group), "seconds"} for
    building ``cases`` on ``jobs`` workers: each worker prepares every group it meets once,
    the steps share the workers evenly (module docstring; ``length_steps`` defaults to 20
    ``calibration_steps``), and no more of them run at once than ``cores`` (the processors the
    workers share: two workers on one core take as long as one; None: as many as ``jobs``). The
    cores are taken as free: other work beside the build slows it. ``jobs`` is a whole number from 1 to
    :data:`twin.dataset.runner.MAX_JOBS`, ``calibration_steps`` one >= 1 (an
    :class:`InputError` otherwise, before anything runs)."""
    cases = check_cases(cases, "estimate")
    jobs = check_jobs(jobs, "estimate")
    if not is_whole(calibration_steps) or calibration_steps < 1:
        raise InputError("estimate", "calibration_steps", f"must be a whole number of time steps >= 1, "
                                                          f"got {calibration_steps!r}")
    calibration_steps = int(calibration_steps)
    length_steps = 20 * calibration_steps if length_steps is None else length_steps
    if not is_whole(length_steps) or length_steps < calibration_steps:
        raise InputError("estimate", "length_steps", f"must be a whole number of time steps >= calibration_steps "
                                                     f"({calibration_steps}), got {length_steps!r}")
    groups: dict[tuple, list[Case]] = {}
    for c in cases:
        key = (c.record["machine"], c.record["mesh"], c.record["solver"], moved_axes(record_scenario(c.record)))
        groups.setdefault(key, []).append(c)
    prepare, per_step, seconds = 0.0, {}, 0.0
    for key, members in groups.items():
        name = "/".join(key[:3]) + (f" (axes {', '.join(key[3])})" if key[3] else "")
        t0 = time.perf_counter()
        with threadpool_limits(limits=1):
            _prepared(*key)
        simulate_case(members[0].record, "calibration", calibration_steps)   # warm-up: adjoints, factorisations
        t1 = time.perf_counter()
        n = min(int(length_steps), _steps(members[0]))
        simulate_case(members[0].record, "calibration", n)
        t2 = time.perf_counter()
        per_step[name] = (t2 - t1) / n
        prepare += t1 - t0 - min(calibration_steps, n) * per_step[name]     # less the warm-up's steps
        seconds += sum(_steps(c) for c in members) * per_step[name]
    lanes = jobs if cores is None else min(jobs, check_jobs(cores, "estimate"))   # workers running at once
    workers = max(1, min(lanes, len(cases)))
    return {"cases": len(cases), "steps": sum(_steps(c) for c in cases), "prepare_s": prepare,
            "per_step_s": per_step, "seconds": (prepare if cases else 0.0) + seconds / workers}
