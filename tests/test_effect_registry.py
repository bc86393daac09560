"""Every registered effect on every bundled machine, in one place.

For each (machine, effect): either the machine declares every role the effect needs and a short
run with it closes its energy balance, or asking for it is one clear error naming machine, effect
and role. Each effect declares its strength parameter and whether the observables' response is
linear in it; the declaration is checked both ways:

* first law over the run (theta-scheme, :mod:`twin.observe.energy`): heat in by sources + heat
  in by convection = change of stored heat, to 1e-9 of the largest term;
* linear (heat sources and fluxes): every observable is affine in the strength p, so with y(p)
  the temperature sensors and probes (or laser sensors) of the model with E at strength p, y(2 p) - 2 y(p) + y(0) = 0
  to 1e-9 of max |y(p) - y(0)|, per block (temperatures, displacements: an effect far from the
  sensors may move the tool by um while it changes a temperature by 1e-13 K), plus the round-off
  of the block's values (1e-13 of them);
* not linear (film coefficients, conductances): that second difference exceeds 1e-6 of it.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from geometries import MACHINES, build_machine
from twin.effects import EFFECTS
from twin.errors import InputError
from twin.fem.mesh import mesh_machine
from twin.model import ModelSpec, model_spec
from twin.observe import FiveProbeTestBar, HeatBalance, LaserTriangulation, RunContext, TemperatureSensors, sensor_points
from twin.physics.prepared import PreparedTwin
from twin.rotary import RotarySchedule
from twin.scenario import AirEvent, Ambient, Scenario

# 40 min at 3000 rpm (and the C axis, where there is one, at 2500 rpm half of the time), 20 min
# stopped, every 2 min; a daily room from 11:00 (the sun is up); a door opening at 10 min (the
# door_draft's schedule, and a scenario door event for door_stream) so that every scheduled effect
# acts inside the run
SCENARIO = Scenario("registry", ((2400.0, 3000.0), (1200.0, 0.0)),
                    Ambient("daily", mean=20.0, amplitude=2.0, coldest_at=6 * 3600.0, start_time_of_day=11 * 3600.0,
                            events=(AirEvent(start=600.0, change=-3.0, fall=600.0, recovery=1200.0, door=True),)),
                    120.0, c_axis=RotarySchedule(((2400.0, 2500.0, 0.5),)))
SCHEDULE = {"door_draft": {"start": 600.0}}
PAIRS = [(m, e) for m in sorted(MACHINES) for e in sorted(EFFECTS)]


@pytest.fixture(scope="module")
def twins():
    return {name: PreparedTwin(build_machine(name), mesh_machine(build_machine(name), "coarse")) for name in MACHINES}


def _spec(effects, values=None):
    params = {e: {**EFFECTS[e].defaults(), **SCHEDULE.get(e, {})} for e in effects}
    for e, v in (values or {}).items():
        params[e].update(v)
    return ModelSpec(tuple(effects), params)


def _observe(twin, spec):
    m = twin.machine
    probes = [o for o, has in ((FiveProbeTestBar(), m.probes), (LaserTriangulation(), m.lasers)) if has]
    observers = [TemperatureSensors([p for p in sensor_points(m) if p.part != "air"]), *probes, HeatBalance()]
    # the C axis turns only where the machine has one (a run refuses a C axis the machine lacks)
    scenario = SCENARIO if "c_axis_max_speed" in m.parameters else replace(SCENARIO, c_axis=None)
    loads, raw = twin.run(scenario, spec, observers, plausible=False)   # strength 0 and 2x: beyond some bounds
    blocks = [raw["temperature"]] + [raw[o.key] - raw[o.key][0] for o in probes]
    return blocks, loads, raw["energy"]


def test_every_effect_declares_roles_strength_and_linearity():
    for name, e in EFFECTS.items():
        assert e.roles, name
        assert e.strength in {p.name for p in e.parameters}, name
        assert isinstance(e.linear, bool), name


@pytest.mark.parametrize("machine,effect", PAIRS)
def test_effect_on_machine(twins, machine, effect):
    twin = twins[machine]
    m = twin.machine
    eff = EFFECTS[effect]
    if not eff.applies_to(m):
        with pytest.raises(InputError) as err:
            model_spec(m, f"+{effect}")
        missing = eff.missing_roles(m)[0]
        assert effect in str(err.value) and m.name in str(err.value) and missing in str(err.value)
        return
    base = [e for e in ("ambient_convection",) if e != effect]
    p = eff.parameter(eff.strength)
    p1 = p.default if p.default != 0 else 0.1 * p.upper
    y = {}
    for k in (0, 1, 2):
        spec = _spec(base + [effect], {effect: {eff.strength: k * p1}})
        y[k], loads, energy = _observe(twin, spec)
        if k == 1:
            ctx = RunContext(SCENARIO.times(), SCENARIO, spec, m, loads, np.random.default_rng(0))
            sources, convection, stored = HeatBalance.energy(energy, ctx)
            assert abs(sources + convection - stored) <= 1e-9 * max(abs(sources), abs(convection), abs(stored))
    # each block (temperatures [degC], displacements [m]) against its own response; a linear
    # effect's second difference may also hold the round-off of the block's values (1e-13 of them)
    scales = [np.abs(b1 - b0).max() for b0, b1 in zip(y[0], y[1])]
    assert max(scales) > 0, f"{effect} at strength {p1:g} changes nothing on {machine}'s sensors and probes"
    second = [np.abs(b2 - 2 * b1 + b0).max() for b0, b1, b2 in zip(y[0], y[1], y[2])]
    if eff.linear:
        for d, scale, b1 in zip(second, scales, y[1]):
            assert d <= 1e-9 * scale + 1e-13 * np.abs(b1).max()
    else:
        # only blocks whose response stands well clear of their round-off
        clear = [d / scale for d, scale, b1 in zip(second, scales, y[1]) if scale > 1e-7 * np.abs(b1).max()]
        assert clear and max(clear) > 1e-6


def test_every_model_value_lies_in_its_uncertain_range_on_every_machine():
    """A parameter's plausible range holds the machine's own value: the gantry's Z drive sets its
    own powers (guideways 0.6 W) below the registry's range (2-30 W), which a diagnosis could then
    never fit back to the model's value; its range is now the registry's scaled by own / registry
    default (twin.model.uncertain_range), the same relative spread."""
    from geometries import MACHINES, build_machine
    from geometries.axes import with_feed_drives
    from twin.model import uncertain_range

    for name in MACHINES:
        m = with_feed_drives(build_machine(name))
        for effect in m.default_effects:
            for u in EFFECTS[effect].uncertain:
                value = (m.effect_defaults.get(effect) or {}).get(u.name, EFFECTS[effect].parameter(u.name).default)
                lo, hi = uncertain_range(m, effect, u)
                assert lo <= value <= hi, (name, effect, u.name, value, lo, hi)
    gantry = with_feed_drives(build_machine("gantry-ram"))
    u = EFFECTS["feed_guideways_z"].uncertainty("power")
    scale = 0.6 / EFFECTS["feed_guideways_z"].parameter("power").default
    assert uncertain_range(gantry, "feed_guideways_z", u) == pytest.approx((u.lower * scale, u.upper * scale), rel=1e-12)
    assert uncertain_range(build_machine("cframe-vmc"), "feed_guideways_z", u) == (u.lower, u.upper)


def test_the_diagnosis_fits_a_machine_own_default_within_its_scaled_range():
    from geometries import build_machine
    from geometries.axes import with_feed_drives
    from twin.model import model_spec
    from validate.candidates import wrong_parameters

    gantry = with_feed_drives(build_machine("gantry-ram"))
    spec = model_spec(gantry)          # with its feed drives: the Z drive among the defaults
    c = next(c for c in wrong_parameters(spec, gantry) if c.name == "feed_guideways_z.power")
    assert c.lower < 0.6 < c.upper <= 2.0          # round the model's 0.6 W, not 0.6 .. 30 W
