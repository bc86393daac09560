"""A dataset plan's draws against the keys its module docstring documents (twin.dataset.plan):
every draw comes from its own Generator ``rng(seed, *key)``, so each drawn value of a case can be
recomputed from its key alone:

* a drawn parameter p of draw i of family f: ``Dist.sample(rng(seed, f, i, p))``;
* the instrument-noise seed: ``rng(seed, f, i, "noise").integers(0, 2**32)``;
* the scenario of a generator family: ``rng(seed, f, i, "scenario")``, drawing for each spindle
  step its duration (rounded to whole sample intervals, at least one, the last cut to the
  duration), whether it idles (uniform < idle_probability) and its speed (rounded to the nearest
  multiple of speed_step);
* the split (by case): within each family, the cases ranked by
  ``rng(seed, f, i, machine, grid point, "split").uniform()``, the first round(f_1 n) to the
  first split, the next up to round((f_1 + f_2) n) to the second, the rest to the last.
"""

from __future__ import annotations

import numpy as np

from tests.dataset_files import SPEC, write_spec
from twin.dataset import load_spec, plan
from twin.dataset.plan import rng


def _spec(tmp_path, text=SPEC):
    return load_spec(write_spec(tmp_path, text))


def test_each_drawn_parameter_and_noise_seed_is_the_draw_of_its_own_key(tmp_path):
    """Two drawn parameters and three draws: each case's value of p is Dist.sample of the
    Generator keyed (f, i, p), its noise seed the integer drawn from (f, i, "noise"); the fixed
    parameter is its value."""
    text = (SPEC.replace('"ambient_convection.h" = "7 W/m2K"', '"ambient_convection.h" = { uniform = ["5 W/m2K", "9 W/m2K"] }')
            .replace("cases = 2", "cases = 3"))
    spec = _spec(tmp_path, text)
    cases = plan(spec)
    assert len(cases) == 4
    for c in cases:
        f, i = c.info["family"], c.info["draw"]
        for p, col in (("spindle_motor.power", "spindle_motor.power [W]"),
                       ("ambient_convection.h", "ambient_convection.h [W/m2K]")):
            assert c.info[col] == spec.parameters[p].sample(rng(spec.seed, f, i, p)), (f, i, p)
        assert c.info["seed"] == int(rng(spec.seed, f, i, "noise").integers(0, 2**32)) == c.record["seed"]


def _replayed_steps(spec, family, i):
    """The spindle steps [(speed rpm, duration s)] of draw i, from its documented key and draws."""
    gen = next(f for f in spec.families if f.name == family).generator
    r = rng(spec.seed, family, i, "scenario")
    dt, total = gen.sample_interval, int(round(gen.duration / gen.sample_interval))
    steps, done = [], 0
    while done < total:
        n = min(max(1, int(round(gen.step.sample(r) / dt))), total - done)
        idle = r.uniform() < gen.idle_probability
        speed = min(round(gen.speed.sample(r) / gen.speed_step) * gen.speed_step, gen.speed.upper)
        steps.append((0.0 if idle else speed, n * dt))
        done += n
    return steps


def test_a_generated_duty_cycle_is_the_replay_of_its_scenario_key(tmp_path):
    """Every draw of the generator family (here 6 draws of 30 min at 1 min, steps of 2-5 min,
    idle with probability 0.3, speeds 2000-9000 rpm rounded to 500 rpm) holds exactly the steps
    replayed from rng(seed, f, i, "scenario"); the draws differ from one another, and the steps
    add up to the duration."""
    text = SPEC.replace("cases = 2", "cases = 6").replace('duration = "10 min"', 'duration = "30 min"')
    spec = _spec(tmp_path, text)
    duty = [c for c in plan(spec) if c.info["family"] == "duty"]
    seen = []
    for c in duty:
        got = [(float(s["speed"].split()[0]), float(s["duration"].split()[0])) for s in c.record["scenario"]["spindle"]]
        assert got == _replayed_steps(spec, "duty", c.info["draw"]), c.info["draw"]
        assert sum(d for _, d in got) == 1800.0
        seen.append(got)
    assert len({tuple(s) for s in seen}) == len(seen)
    speeds = {v for s in seen for v, _ in s}
    assert 0.0 in speeds and speeds - {0.0}


def test_a_speed_is_rounded_to_the_nearest_step_not_down():
    """duty_cycle: a drawn speed is rounded to the nearest multiple of speed_step. Speeds drawn
    from [2000, 3000] rpm with a 1000 rpm step are 2000 below 2500 and 3000 above, so of 40 steps
    drawn (never idle) both occur, in the proportions of the draw; a floor would give 2000 only."""
    from twin.dataset.families import DutyCycle
    from twin.dataset.fields import Dist
    from twin.dataset.plan import duty_cycle
    gen = DutyCycle(duration=2400.0, sample_interval=60.0, step=Dist("fixed", (60.0,), "time"),
                    speed=Dist("uniform", (2000.0, 3000.0), "speed", 0.0, 3000.0), speed_step=1000.0,
                    idle_probability=0.0, ambient_kind="constant", ambient={})
    r, s = np.random.default_rng(4), np.random.default_rng(4)
    data = duty_cycle(gen, "x", r)
    speeds = [float(st["speed"].split()[0]) for st in data["spindle"]]
    assert len(speeds) == 40
    drawn = []
    for _ in range(40):
        s.uniform()                       # the idle draw
        drawn.append(s.uniform(2000.0, 3000.0))
    assert speeds == [2000.0 if v < 2500.0 else 3000.0 for v in drawn]
    assert {2000.0, 3000.0} == set(speeds)


def test_a_rounded_speed_stays_within_the_familys_speeds():
    """speed_step rounds to the nearest multiple *within* the family's speeds (spec: "one must lie
    in the range"): from 2000-2400 rpm with a 500 rpm step every running step is 2000 rpm (2300
    was rounded to 2500, beyond the range); from 2100-3400 rpm with 1000 rpm, every step is 3000
    (2100-2499 went to 2000, below it)."""
    from twin.dataset.families import DutyCycle
    from twin.dataset.fields import Dist
    from twin.dataset.plan import duty_cycle
    for (lo, hi, q), only in (((2000.0, 2400.0, 500.0), 2000.0), ((2100.0, 3400.0, 1000.0), 3000.0)):
        gen = DutyCycle(duration=2400.0, sample_interval=60.0, step=Dist("fixed", (60.0,), "time"),
                        speed=Dist("uniform", (lo, hi), "speed", 0.0, 9000.0), speed_step=q,
                        idle_probability=0.0, ambient_kind="constant", ambient={})
        speeds = {float(st["speed"].split()[0]) for st in duty_cycle(gen, "x", np.random.default_rng(2))["spindle"]}
        assert speeds == {only}, (lo, hi, q, speeds)


def _expected_splits(spec, infos):
    names = list(spec.splits)
    cum = np.cumsum([spec.splits[n] for n in names])
    out = {}
    for fam in dict.fromkeys(i["family"] for i in infos):
        members = [i for i in infos if i["family"] == fam]
        keys = [rng(spec.seed, fam, i["draw"], i["machine"], i["grid_point"], "split").uniform() for i in members]
        ranked = [members[k] for k in np.argsort(keys)]
        ends = [int(round(c * len(ranked))) for c in cum]
        for rank, i in enumerate(ranked):
            out[(fam, i["draw"], i["machine"], i["grid_point"])] = names[next(j for j, e in enumerate(ends) if rank < e)]
    return out


def test_each_cases_split_is_its_rank_by_the_split_key(tmp_path):
    """Splits 0.6 / 0.2 / 0.2 over a family of 5 draws x 2 grid points (10 cases): the 6 cases of
    the lowest keys rng(seed, f, i, machine, grid point, "split").uniform() are train, the next 2
    validation, the last 2 test, case by case (the grid point is part of the key: the two grid
    points of one draw are ranked apart); the one-case reference family x 2 grid points:
    round(0.6 x 2) = 1 train, round(0.8 x 2) = 2: 1 validation, no test."""
    text = (SPEC.replace('"7 W/m2K"', '{ grid = ["6 W/m2K", "10 W/m2K"] }').replace("cases = 2", "cases = 5")
            .replace("train = 0.5\ntest = 0.5", "train = 0.6\nvalidation = 0.2\ntest = 0.2"))
    spec = _spec(tmp_path, text)
    cases = plan(spec)
    assert len(cases) == 12
    want = _expected_splits(spec, [c.info for c in cases])
    got = {(c.info["family"], c.info["draw"], c.info["machine"], c.info["grid_point"]): c.split for c in cases}
    assert got == want
    duty = [c.split for c in cases if c.info["family"] == "duty"]
    assert (duty.count("train"), duty.count("validation"), duty.count("test")) == (6, 2, 2)
    ref = sorted(c.split for c in cases if c.info["family"] == "reference")
    assert ref == ["train", "validation"]
