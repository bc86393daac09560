"""How long a plan will take, from a calibration run on this machine.

Per (machine, mesh, solver) of the plan: prepare the twin (timed: the mesh, the matrices, the
elastic factorisation and adjoints), then run the group's first case cut to ``calibration_steps``
time steps (timed, after a warm-up of the same length, so the factorisations of its operators are
done once): the cost of one step [s], which includes the observers and the packaging of the
result. A case with more distinct spindle speeds than the calibration saw costs more (one
factorisation per new operator on the direct solver); the estimate does not count them.
"""

from __future__ import annotations

import time

from threadpoolctl import threadpool_limits

from twin.dataset.plan import Case, check_cases
from twin.dataset.runner import _prepared, check_jobs, simulate_case
from twin.errors import InputError
from twin.limits import is_whole


def _steps(case: Case) -> int:
    return int(round(case.info["duration [s]"] / case.info["sample_interval [s]"]))


def estimate(cases: list[Case], jobs: int = 1, calibration_steps: int = 30) -> dict:
    """{"cases", "steps", "prepare_s" (per worker), "per_step_s" (by group), "seconds"} for
    building ``cases`` on ``jobs`` workers: each worker prepares every group it meets once,
    the steps share the workers evenly. ``jobs`` is a whole number from 1 to
    :data:`twin.dataset.runner.MAX_JOBS`, ``calibration_steps`` one >= 1 (an
    :class:`InputError` otherwise, before anything runs)."""
    cases = check_cases(cases, "estimate")
    jobs = check_jobs(jobs, "estimate")
    if not is_whole(calibration_steps) or calibration_steps < 1:
        raise InputError("estimate", "calibration_steps", f"must be a whole number of time steps >= 1, "
                                                          f"got {calibration_steps!r}")
    calibration_steps = int(calibration_steps)
    groups: dict[tuple, list[Case]] = {}
    for c in cases:
        groups.setdefault((c.record["machine"], c.record["mesh"], c.record["solver"]), []).append(c)
    prepare, per_step, seconds = 0.0, {}, 0.0
    for key, members in groups.items():
        t0 = time.perf_counter()
        with threadpool_limits(limits=1):
            _prepared(*key)
        simulate_case(members[0].record, "calibration", calibration_steps)   # warm-up: adjoints, factorisations
        t1 = time.perf_counter()
        simulate_case(members[0].record, "calibration", calibration_steps)
        t2 = time.perf_counter()
        n = min(calibration_steps, _steps(members[0]))
        per_step["/".join(key)] = (t2 - t1) / n
        prepare += t1 - t0 - (t2 - t1)
        seconds += sum(_steps(c) for c in members) * per_step["/".join(key)]
    workers = max(1, min(jobs, len(cases)))
    return {"cases": len(cases), "steps": sum(_steps(c) for c in cases), "prepare_s": prepare,
            "per_step_s": per_step, "seconds": (prepare if cases else 0.0) + seconds / workers}
