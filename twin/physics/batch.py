"""Many cases through one prepared twin: effect strengths, ambient amplitudes, whole scenarios.

A *case* is a (scenario, model spec) pair. Cases that share the spatial patterns of their loads
(the same effects on the same regions, so the same matrices M, K, H_k, F and r_k) and the time
grid differ only in their signals h_k(t), T_air,k(t), s_j(t), and the theta-scheme is linear in
the sources and the air temperatures. So:

* **reduced model**: one reduction serves every case; the reduced states of all cases advance
  together, one (r, m) block per step (:meth:`twin.physics.rom.ReducedModel.integrate`), with a
  small solve per case where the film coefficients differ between cases;
* **full model**: cases with the same film coefficients share every step's operator and are
  solved together as multiple right-hand sides (one factorisation back-substitutes all of them;
  block PCG reads the matrix once per iteration for all of them).

Returns, per observer, readings (n_t, k, m) with the cases along the last axis, and the run
information of :meth:`twin.physics.prepared.PreparedTwin.run` with the errors per case.
"""

from __future__ import annotations

import numpy as np

from twin import limits
from twin.errors import InputError
from twin.observe.base import error_units
from twin.physics.heat import integrate
from twin.physics.loads import LoadSet, collect_loads, pattern_key
from twin.physics.solvers import mass_weights, output_bounds
from twin.signals import load_instants


def case_signals(twin, base: LoadSet, scenario, spec, t: np.ndarray):
    """(h, air, s) of one case at times ``t`` on the patterns of ``base`` (ValueError when the
    case's loads have other patterns: it needs its own run)."""
    sources, convs, _, _ = collect_loads(twin.mm, scenario, spec)
    if pattern_key(sources) != pattern_key(base.sources) or pattern_key(convs) != pattern_key(base.convections):
        raise ValueError("a batched case must place its loads where the first case does (same effects and "
                         "regions); run it separately")
    return LoadSet(base.system, sources, convs, [], [], base.areas, base.mm, base.heat).signals(t)


def run_batch(twin, cases, observers, theta: float = 0.5, progress=None, bound: bool = True) -> tuple[LoadSet, dict, dict]:
    """Integrate every (scenario, spec) of ``cases`` with ``observers`` on ``twin``; all scenarios
    must share the time grid and start temperature. Returns (loads of the first case, readings
    {key: (n_t, k, m)}, info). ``bound=False`` skips the reduced model's verified error bound
    (O(d^2) per case and step; the estimate is always computed)."""
    cases = list(cases)
    if not cases:
        raise InputError("command line", "cases", "run_batch needs at least one (scenario, spec)")
    sc0, spec0 = cases[0]
    times, T0 = sc0.times(), sc0.start_temperature
    limits.check_batch_size(len(cases), len(times), "command line", "cases")
    for i, (sc, _) in enumerate(cases):
        if len(sc.times()) != len(times) or not np.allclose(sc.times(), times) or sc.start_temperature != T0:
            raise InputError("command line", f"cases[{i}]", "batched cases share the first case's time grid (duration "
                                                            "and sample interval) and start temperature; run this one "
                                                            "in another batch")
    loads = twin.loads(sc0, spec0)
    dt = sc0.sample_interval
    nsteps = len(times) - 1
    tm = load_instants(times, theta)
    sig = [case_signals(twin, loads, sc, spec, tm) for sc, spec in cases]
    h = np.stack([g[0] for g in sig], axis=2)
    air = np.stack([g[1] for g in sig], axis=2)
    s = np.stack([g[2] for g in sig], axis=2)
    m = len(cases)
    # the rows beside the basis (the reduced model's from every case's films, the full model's
    # reduced start from the first group's, as its stepper asks)
    (outputs, bounds), _ = twin._prepare(loads, observers, {o.key: None for o in observers},
                                         h if twin.options.solver == "rom" else h[:, :, 0], nsteps, bound)
    if twin.options.solver == "rom":
        from twin.physics.rom import reduced_model
        rom = reduced_model(twin, loads, outputs, h, bound)
        out, info = rom.integrate(T0, dt, nsteps, h, air, s, theta, progress=progress, bound=bound)
        errors = {"rom_error_estimate": info.pop("_estimate"), "rom_error_bound": info.pop("_bound")}
    else:
        out = np.empty((nsteps + 1, outputs.shape[0], m))
        groups: dict[bytes, list[int]] = {}
        for j in range(m):
            groups.setdefault(np.round(h[:, :, j], 12).tobytes(), []).append(j)
        bound = np.zeros((outputs.shape[0], m))
        weights = mass_weights(loads.system.M)
        for members in groups.values():
            stepper = twin.stepper(loads, h[:, :, members[0]], nsteps)
            T = np.full((loads.mm.nheat, len(members)), T0)
            out[:, :, members] = integrate(loads.system, T, dt, nsteps, h[:, :, members[0]], air[:, :, members],
                                           s[:, :, members], outputs, theta, None, twin.factorisations,
                                           loads.operator_key, stepper)
            if stepper.method == "iterative":
                bound[:, members] = output_bounds(outputs, weights, 1.0)[:, None] * np.asarray(stepper.rho_sum)[None, :]
            if progress is not None:
                progress(members[-1] + 1, m)
        info = stepper.info()
        errors = {"solver_error_bound": bound} if stepper.method == "iterative" else {}
    for name, values in errors.items():
        info[name] = {o.key: values[a:b] for o, a, b in zip(observers, bounds[:-1], bounds[1:])}
    if errors:
        info["solver_error_units"] = error_units(observers)
    info["cases"] = m
    readings = {o.key: out[:, a:b] for o, a, b in zip(observers, bounds[:-1], bounds[1:])}
    return loads, readings, info
