"""A spec expanded into cases, each a plain record named by the hash of its content.

Cases: every machine x every grid point of the parameters x every draw ``i`` of every family, in
that order within a family (families in the spec's order). Every draw comes from its own numpy
Generator, seeded by the spec's ``seed`` and a key of names, never by position in the plan:

* the scenario of draw ``i`` of family ``f``: key (``f``, ``i``, "scenario");
* a drawn parameter ``p``: key (``f``, ``i``, ``p``);
* the instrument-noise seed: key (``f``, ``i``, "noise");
* the split rank (``by = "case"``): key (``f``, ``i``, machine, grid point, "split").

So draw ``i`` of a family is the same scenario and the same parameter draws for every machine
and grid point (a grid compares like with like), and changing one family, one parameter or the
number of draws changes only the cases it touches: the others keep their records and hashes.

A case record holds everything that defines its result file (machine, mesh, solver, effects,
settings with units, the scenario as TOML data with units, observers, noise seed, package and
format version); its hash is the SHA-256 of the record's canonical JSON (first 16 hex digits).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from dataclasses import dataclass

import numpy as np

from twin.dataset.families import AxisDuty, DutyCycle
from twin.dataset.spec import DatasetSpec
from twin.errors import InputError, describe
from twin.version import package_version
from twin.scenario import scenario_from_dict
from twin.motion import stroke_time
from twin.units import CANONICAL, parse_quantity

FORMAT = 1   # the dataset format: a change to what a case file holds bumps it (and every hash)


@dataclass(frozen=True)
class Case:
    """One planned case: its ``record`` (what defines the file), its ``hash``, the index row
    ``info`` (parameters in SI with the unit in the column name) and its ``split``."""

    record: dict
    hash: str
    info: dict
    split: str
    spec_key: str = ""   # the plan's spec (:func:`spec_key`): an index never mixes two specs' cases

    @property
    def file(self) -> str:
        """The case's file name inside the dataset's ``cases/`` folder."""
        return f"{self.hash}.nc"


def rng(seed: int, *key) -> np.random.Generator:
    """A Generator seeded by ``seed`` and the names in ``key`` (stable across runs and platforms)."""
    words = [int.from_bytes(hashlib.sha256(str(k).encode()).digest()[:4], "little") for k in key]
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=words)))


def case_hash(record: dict) -> str:
    """The first 16 hex digits of the SHA-256 of ``record``'s canonical JSON."""
    text = json.dumps(record, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _q(value: float, dimension: str) -> str:
    """An SI value as an exact quantity string ("1234.5 s") for the scenario data."""
    return f"{float(value)!r} {CANONICAL[dimension]}"


def rounded_speed(speed: float, dist, step: float) -> float:
    """``speed`` [rpm] rounded to the nearest multiple of ``step`` that lies within the family's
    speeds ``dist.low .. dist.high`` (and the machines' top, ``dist.upper``): 2300 rpm drawn from
    2000-2400 rpm with a 500 rpm step is 2000, not 2500 (the family's check guarantees one such
    multiple)."""
    lo = math.ceil(max(dist.low, 0.0) / step - 1e-9)
    hi = math.floor(min(dist.high, dist.upper) / step + 1e-9)
    return float(min(max(round(speed / step), lo), hi) * step)


def duty_cycle(gen: DutyCycle, name: str, r: np.random.Generator) -> dict:
    """Scenario TOML data drawn from a generator family: steps of drawn duration (whole sample
    intervals, the last one cut to the duration) and speed (0 rpm with ``idle_probability``,
    rounded to ``speed_step``), and a drawn room."""
    dt, total = gen.sample_interval, int(round(gen.duration / gen.sample_interval))
    steps, done = [], 0
    while done < total:
        n = min(max(1, int(round(gen.step.sample(r) / dt))), total - done)
        idle = r.uniform() < gen.idle_probability
        speed = gen.speed.sample(r)
        if gen.speed_step:
            speed = rounded_speed(speed, gen.speed, gen.speed_step)
        steps.append({"speed": _q(0.0 if idle else max(speed, 0.0), "speed"), "duration": _q(n * dt, "time")})
        done += n
    ambient = {"kind": gen.ambient_kind, **(gen.room or {})}
    for key in sorted(gen.ambient):
        dist = gen.ambient[key]
        ambient[key] = _q(dist.sample(r), dist.dimension)
    if gen.events:   # drawn after the room, so families without events draw as before
        ambient["events"] = [{key: value if key == "door" else _q(value.sample(r), value.dimension)
                              for key, value in event.items()} for event in gen.events]
    data = {"name": name, "sample_interval": _q(dt, "time"), "ambient": ambient, "spindle": steps}
    if gen.axes:   # drawn after the spindle and the room, so families without axes draw as before
        data["axis"] = [axis_duty(a, steps, r) for a in gen.axes]
    return data


def axis_duty(a: AxisDuty, steps: list[dict], r: np.random.Generator) -> dict:
    """One axis's ``[[axis]]`` table following the spindle ``steps``: from the middle of its
    range, while the spindle runs a reciprocation between where the axis is and a drawn end at a
    drawn feed (whole strokes, then a dwell; a hold when not one stroke fits the step), while it
    stands a hold."""
    lo, hi = a.range
    x = round(0.5 * (lo + hi), 6)
    moves = []
    for st in steps:
        dur = parse_quantity(st["duration"], "time")
        end, feed = round(float(r.uniform(lo, hi)), 6), a.feed.sample(r)   # drawn on every step: stable streams
        running = parse_quantity(st["speed"], "speed") > 0
        if running and abs(end - x) > 1e-3 and stroke_time(abs(end - x), feed, a.acceleration) <= dur:
            n = int(np.floor(dur / stroke_time(abs(end - x), feed, a.acceleration) + 1e-9))
            moves.append({"kind": "reciprocate", "between": [_q(x, "length"), _q(end, "length")],
                          "feed": _q(feed, "velocity"), "acceleration": _q(a.acceleration, "acceleration"),
                          "duration": st["duration"]})
            x = end if n % 2 else x
        else:
            moves.append({"kind": "hold", "position": _q(x, "length"), "duration": st["duration"]})
    return {"name": a.name, "start": _q(round(0.5 * (lo + hi), 6), "length"), "move": moves}


def record_scenario(record: dict):
    """The :class:`twin.scenario.Scenario` of a case record (its ``scenario`` table, named by its family)."""
    return scenario_from_dict(json.loads(json.dumps(record["scenario"])), f"dataset:{record['family']}",
                              default_name=record["family"])


def moved_axes(scenario) -> tuple[str, ...]:
    """The axes a scenario moves, sorted: the feed drives its prepared twin carries."""
    return tuple(sorted({m.axis for m in scenario.axes}))


def _room_descriptors(a, duration: float) -> tuple[float, float]:
    """(mean [degC], amplitude [K]) of the room's base air (events left out, as the nominal mean and
    amplitude of a constant or daily room leave them out); a table or measured room: the time
    average over the run [0, duration] of the piecewise-linear record and half its range there."""
    if a.kind != "table":
        return a.mean, a.amplitude
    t = np.union1d([0.0, duration], [x for x in a.times if 0.0 < x < duration])
    air = a.base(t)
    mean = float(np.sum(0.5 * (air[1:] + air[:-1]) * np.diff(t)) / duration) if duration > 0 else float(air[0])
    return mean, 0.5 * float(air.max() - air.min())


def _scenario_info(data: dict) -> dict:
    """Index columns that describe a scenario (SI, from its TOML data)."""
    sc = scenario_from_dict(json.loads(json.dumps(data)), "plan")
    d = np.array([s[0] for s in sc.steps])
    v = np.array([s[1] for s in sc.steps])
    a = sc.ambient
    mean, amplitude = _room_descriptors(a, sc.duration)
    return {"duration [s]": sc.duration, "sample_interval [s]": sc.sample_interval, "steps": len(sc.steps),
            "mean_speed [rpm]": float(np.sum(d * v) / np.sum(d)), "max_speed [rpm]": float(v.max()),
            "running_fraction": float(np.sum(d[v > 0]) / np.sum(d)), "ambient": a.kind,
            "ambient_mean [degC]": mean, "ambient_amplitude [K]": amplitude,
            "ambient_coldest_at [s]": a.coldest_at if a.kind == "daily" else 0.0}


def check_cases(cases, source: str) -> list[Case]:
    """``cases``: a list of :class:`Case` (a plan's, :func:`plan`), or an :class:`InputError`."""
    if not isinstance(cases, (list, tuple)) or not all(isinstance(c, Case) for c in cases):
        raise InputError(source, "cases", f"expected a list of twin.dataset.plan.Case (twin.dataset.plan.plan), got "
                                          f"{describe(cases)}")
    return list(cases)


def spec_key(spec: DatasetSpec) -> str:
    """The first 16 hex digits of the SHA-256 of the spec's values (its repr: every field but the
    file's text), stamped on each planned :class:`Case`."""
    return hashlib.sha256(repr(spec).encode()).hexdigest()[:16]


def plan(spec: DatasetSpec) -> list[Case]:
    """Every case of ``spec`` in plan order (module doc)."""
    if not isinstance(spec, DatasetSpec):
        raise InputError("plan", "spec", f"expected a dataset spec (twin.dataset.load_spec), got {describe(spec)}")
    grid_keys = [k for k, d in spec.parameters.items() if d.kind == "grid"]
    grid = list(itertools.product(*(spec.parameters[k].values for k in grid_keys)))
    observers = {"sensors": "machine", "surface_grid": spec.surface_grid, "cameras": list(spec.cameras)}
    cases = []
    for family in spec.families:
        draws = []
        for i in range(family.cases):
            if family.generator is not None:
                scenario = duty_cycle(family.generator, f"{family.name}-{i:04d}", rng(spec.seed, family.name, i, "scenario"))
            else:
                scenario = json.loads(json.dumps(family.data))   # a deep copy
            params = {k: d.sample(rng(spec.seed, family.name, i, k)) for k, d in spec.parameters.items()
                      if d.kind != "grid"}
            noise = int(rng(spec.seed, family.name, i, "noise").integers(0, 2**32))
            draws.append((i, scenario, params, noise, _scenario_info(scenario)))
        for machine in spec.machines:
            for g, point in enumerate(grid):
                for i, scenario, params, noise, sc_info in draws:
                    values = {**params, **dict(zip(grid_keys, point))}
                    settings = [f"{k}={values[k]!r} {CANONICAL[spec.parameters[k].dimension]}" for k in sorted(values)]
                    record = {"format": FORMAT, "package_version": package_version(), "machine": machine,
                              "mesh": spec.mesh, "solver": spec.solver, "theta": 0.5, "effects": spec.effects,
                              "settings": settings, "family": family.name, "draw": i, "scenario": scenario,
                              "observers": observers, "seed": noise}
                    info = {"machine": machine, "family": family.name, "draw": i, "grid_point": g, "seed": noise,
                            "scenario": scenario.get("name", family.file), **sc_info,
                            **{f"{k} [{CANONICAL[spec.parameters[k].dimension]}]": values[k] for k in sorted(values)}}
                    cases.append((record, info))
    check_effects_act(spec, [rec for rec, _ in cases])
    splits = assign_splits(spec, [c[1] for c in cases])
    key = spec_key(spec)
    return [Case(rec, case_hash(rec), info, split, key) for (rec, info), split in zip(cases, splits)]


def check_effects_act(spec: DatasetSpec, records: list[dict]) -> None:
    """Every effect switched on in each planned case can act in that case's whole run
    (:meth:`twin.effects.base.Effect.refusal`: a door draft opening after the run's end would do
    nothing), else an :class:`InputError` naming the spec file, the effect and the family: before
    any case is built or timed (a dry run's calibration runs a few steps of a case, not all of it)."""
    from geometries import build_machine
    from geometries.axes import with_feed_drives
    from twin.model import check_refusals, model_spec

    family_index = {f.name: i for i, f in enumerate(spec.families)}
    machines, seen = {}, set()
    for r in records:
        key = json.dumps([r["machine"], r["scenario"], r["effects"], r["settings"]], sort_keys=True)
        if key in seen:
            continue
        seen.add(key)
        sc = record_scenario(r)
        axes = moved_axes(sc)
        if (r["machine"], axes) not in machines:
            machine = build_machine(r["machine"])
            machines[(r["machine"], axes)] = with_feed_drives(machine, set(axes)) if axes else machine
        model = model_spec(machines[(r["machine"], axes)], r["effects"], r["settings"])
        try:
            check_refusals(model, sc)
        except InputError as err:     # the run's rule, named as the spec gives it
            raise InputError(spec.source, "effects", f"{err.field} in scenarios[{family_index[r['family']]}] "
                                                     f"(family {r['family']}, draw {r['draw']}): {err.message}") from None


def assign_splits(spec: DatasetSpec, infos: list[dict]) -> list[str]:
    """The split of every case: by family (the spec's lists), or by case: within each family the
    cases ranked by a seeded uniform key, the first ``round(fraction n)`` (halves to even, as
    ``numpy.round``) to the first split and so on (exact counts per family; a split is metadata,
    never part of a case's hash)."""
    if spec.split_by == "family":
        where = {f: name for name, fams in spec.splits.items() for f in fams}
        return [where[i["family"]] for i in infos]
    out = [""] * len(infos)
    by_family: dict[str, list[int]] = {}
    for j, i in enumerate(infos):
        by_family.setdefault(i["family"], []).append(j)
    names = list(spec.splits)
    fractions = np.cumsum([spec.splits[n] for n in names])
    for fam, members in by_family.items():
        keys = [rng(spec.seed, fam, infos[j]["draw"], infos[j]["machine"], infos[j]["grid_point"], "split").uniform()
                for j in members]
        order = [members[k] for k in np.argsort(keys, kind="stable")]
        bounds = np.round(fractions * len(order)).astype(int)
        for rank, j in enumerate(order):
            out[j] = names[int(np.searchsorted(bounds, rank, side="right"))]
    return out
