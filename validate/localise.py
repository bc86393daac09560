"""Where on the machine is the missing heat? A generic heat input on each region of a fixed
partition of the machine, fitted to the residual.

Partition (:func:`geometries.regions.partition`): every part's cells (``"saddle"``, a volume
source) and every part's outer faces by direction (``"column.+x"``, a surface flux); regions
with no cells or faces on the mesh are dropped. Schedules: ``constant``, ``spindle_on`` (while
the spindle turns), when the measurements run the spindle at more than one speed, ``speed``
(proportional to n / n_max), and ``c_axis_on`` (the fraction of time the C axis turns, its
duty) when a measurement turns the C axis. The observables are those of the diagnosis
(:meth:`validate.signatures.Engine.readings`); sensors in the air do not respond. A region j with schedule s puts P s(t) watts into the
structure; the observables respond linearly, y = P u_js, so each (region, schedule) costs one
column u_js, and all columns come from one integration with J right-hand sides
(:meth:`twin.physics.prepared.PreparedTwin.responses`): the operator changes with the spindle
(forced convection), which rules out one adjoint solve per channel and lag, and there are
fewer regions x schedules than channels x samples.

Each column is fitted alone, with the bounded nuisance, to the residual (:mod:`validate.fit`):

    P_js = argmin || w (r - P u_js - N c) ||^2,   explained_js = 1 - SSE_js / SSE_0,

and the regions are ranked by their best schedule's explained share. It runs on the machine's
coarsest mesh with implicit Euler on a time grid of at most ``max_steps`` steps (a map, not a
calibration: the fitted powers are good to the coarse mesh's accuracy, some %).
"""

from __future__ import annotations

import numpy as np

from geometries.regions import partition
from twin.effects import HeatSource, SurfaceHeatFlux
from twin.fem.regions import region_cells, region_facets
from twin.physics.prepared import PreparedTwin
from validate.channels import resampler

POWER_LIMIT = 5000.0   # W, either sign: a generic heat input (a cooler is a negative one)


def partition_sources(mm) -> list[tuple[str, str, np.ndarray]]:
    """(name, kind, cells or facets) of every non-empty region of the machine's partition."""
    out = []
    for name, (kind, region) in partition(mm.machine).items():
        where = region_cells(mm, region) if kind == "volume" else region_facets(mm, region)
        if len(where):
            out.append((name, kind, where))
    return out


def shaped_load(name: str, kind: str, where: np.ndarray, shape, scenario):
    """A generic heat input of 1 W times ``shape(scenario, t)`` on a region's cells or facets."""
    power = lambda t: shape(scenario, t)
    return HeatSource(name, where, power) if kind == "volume" else SurfaceHeatFlux(name, where, power)


def schedules(scenarios) -> dict[str, object]:
    """name -> s(scenario, t) [-] of the generic heat input's time shapes (see module doc)."""
    speeds = {float(s) for sc in scenarios for _, s in sc.steps if s > 0}
    out = {"constant": lambda sc, t: np.ones(np.shape(t))}
    if speeds:
        out["spindle_on"] = lambda sc, t: (np.abs(sc.spindle_speed(t)) > 0).astype(float)
    if len(speeds) > 1:
        top = max(speeds)
        out["speed"] = lambda sc, t: np.abs(sc.spindle_speed(t)) / top
    if any(_turns_c(sc) for sc in scenarios):
        out["c_axis_on"] = lambda sc, t: (_c_duty(sc, t) if _turns_c(sc) else np.zeros(np.shape(t)))
    return out


def _turns_c(sc) -> bool:
    c = getattr(sc, "c_axis", None)
    return c is not None and any(n > 0 and d > 0 for _, n, d in c.steps)


def _c_duty(sc, t) -> np.ndarray:
    """The C axis's duty [-] at t [s] where it turns (0 at rest)."""
    return np.where(sc.c_axis.speed(t) > 0, sc.c_axis.duty(t), 0.0)


def localisation_twin(evidence, machine) -> PreparedTwin:
    """The prepared twin on the machine's coarsest mesh (the evidence's own when it is that one)."""
    twin = evidence.records[0].engine.twin
    coarsest = max(machine.resolutions, key=lambda r: machine.resolutions[r])
    if abs(twin.mm.spacing - machine.resolutions[coarsest]) < 1e-12 and not twin.materials:
        return twin
    return PreparedTwin(machine, resolution=coarsest)


def region_columns(evidence, spec, twin: PreparedTwin, max_steps: int = 100):
    """The columns u_js (flat, per watt) of every (region, schedule) over every record, and their
    labels [(region, kind, schedule)]."""
    sources = partition_sources(twin.mm)
    shapes = schedules([r.scenario for r in evidence.records])
    labels = [(name, kind, s) for name, kind, _ in sources for s in shapes]
    blocks = []
    for rec in evidence.records:
        sc = rec.scenario
        dt = sc.sample_interval * max(1, int(np.ceil(len(sc.times()) / max_steps)))
        n = int(np.ceil(rec.times[-1] / dt - 1e-9)) if len(rec.times) > 1 else 1
        grid = np.arange(max(n, 1) + 1) * dt
        loads = [shaped_load(name, kind, where, shapes[s], sc) for name, kind, where in sources for s in shapes]
        eng = rec.engine
        raw = twin.responses(sc, spec, eng.observers(), loads, times=grid)
        air = eng.temperature.air
        interp = resampler(grid, rec.times)
        block = []
        for j in range(len(loads)):
            one = {k: v[:, :, j] for k, v in raw.items()}
            one["temperature"] = np.where(air[None, :], 0.0, one["temperature"])   # the air is the room's
            y = eng.readings(one, spec, dt, bias=False)
            block.append(interp(y[:, rec.columns]))
        blocks.append(np.stack(block, axis=0))   # (J, n_t, n_ch)
    cols = np.concatenate([b.reshape(b.shape[0], -1) for b in blocks], axis=1)   # (J, N)
    return cols, labels


def localise(evidence, fitter, spec, machine, top: int = 8, max_steps: int = 100, twin=None) -> list[dict]:
    """Regions ranked by the share of the (nuisance-fitted) residual a generic heat input there
    explains: [{region, kind, schedule, power_W, explained}], best first, ``top`` of them.
    ``explained`` is over every channel group (the weighted residual of all groups), not the
    significance share over the groups above noise (:class:`validate.verdict.Share`): the
    diagnosis's message states each share's base."""
    twin = twin or localisation_twin(evidence, machine)
    cols, labels = region_columns(evidence, spec, twin, max_steps)
    sse0 = fitter.sse(np.zeros_like(fitter.r))
    best: dict[str, dict] = {}
    for u, (name, kind, sched) in zip(cols, labels):
        if not np.any(u):
            continue
        x, _, sse = fitter.solve(u[:, None], [-POWER_LIMIT], [POWER_LIMIT])
        explained = 1 - sse / sse0 if sse0 > 0 else 0.0
        if name not in best or explained > best[name]["explained"]:
            best[name] = {"region": name, "kind": kind, "schedule": sched, "power_W": float(x[0]),
                          "explained": float(explained)}
    ranked = sorted(best.values(), key=lambda d: -d["explained"])
    return ranked[:top]
