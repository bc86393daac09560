"""Mutation audit of the effect library (twin/effects, twin/ambient.py, twin/signals.py): each test
here kills a mutation that every other test let through, against a closed form or the documented
rule. Coarse meshes only (the session's C-frame, one belt-vmc mesh)."""

from __future__ import annotations

import numpy as np
import pytest

from twin.effects import EFFECTS
from twin.effects.base import Effect, Parameter, Uncertain, check_declarations, register_effect
from twin.errors import InputError
from twin.fem.regions import cell_centres, exterior_facets, facet_centres, facing, role_facets
from twin.scenario import AirEvent, Ambient, Scenario

HOUR = 3600.0


def _scenario(hours=2.0, speed=9000.0, tod=0.0):
    return Scenario("audit", ((hours * HOUR, speed),), Ambient("constant", mean=20.0, start_time_of_day=tod), 60.0)


# ---- where each source and film lies --------------------------------------------------------------

def test_the_cabinets_flux_is_P_over_the_columns_left_side(mm):
    """electrical_cabinet: q = P / A_side, uniform on the column's left (-x) side, x = -0.25 m,
    A_side = 0.45 m x (1.90 - 0.35) m (README: "onto the column's left side face"): the load's facets
    are that face, its load vector is (P / A_side) int N dA over it (round-off). On the rear faces,
    the same 40 W passed every energy balance and the P / (h A_skin) test."""
    from twin.fem.assembly import assemble_facets
    from twin.physics.loads import source_pattern

    p = EFFECTS["electrical_cabinet"].defaults()
    (load,) = EFFECTS["electrical_cabinet"].loads(mm, _scenario(speed=0.0), p)
    side = facing(mm, exterior_facets(mm, ("column",)), "-x")
    area = 0.45 * (1.90 - 0.35)
    assert np.array_equal(np.sort(load.facets), np.sort(side))
    assert np.allclose(facet_centres(mm, load.facets)[:, 0], -0.25, rtol=0, atol=1e-12)
    assert mm.facet_area(load.facets) == pytest.approx(area, rel=1e-12)
    power = float(load.power(np.array([0.0]))[0])
    assert power == p["power"] == 40.0
    b = source_pattern(mm, load) * power
    expected = power / area * assemble_facets(mm, side, np.ones(len(side))).r
    np.testing.assert_allclose(b, expected, rtol=1e-12, atol=1e-15)


def test_the_z_holding_losses_heat_the_columns_top_band(mm):
    """z_axis_holding: P_hold = 25 W spread uniformly over the column's top 0.2 m (``z_drive.top``,
    where the Z motor and brake sit): the load's cells are exactly the column's cells whose centres
    lie in [1.90 - 0.2, 1.90] m, and its volume is the column's cross-section 0.5 x 0.45 m times
    the height of those cell layers. In the spindle motor's cells it passed every test."""
    from twin.physics.loads import source_pattern

    (load,) = EFFECTS["z_axis_holding"].loads(mm, _scenario(speed=0.0), EFFECTS["z_axis_holding"].defaults())
    column = mm.cells_of("column")
    z = cell_centres(mm, column)[:, 2]
    band = column[(z >= 1.70) & (z <= 1.90)]
    assert len(band) and np.array_equal(np.sort(load.cells), np.sort(band))
    lo = mm.mesh.p[2, mm.mesh.t[:, band]].min()
    assert mm.volume_of(load.cells) == pytest.approx(0.5 * 0.45 * (1.90 - lo), rel=1e-12)
    assert 1.90 - 0.2 - 0.1 < lo <= 1.70 + 0.1
    assert load.power(np.array([0.0, 7000.0])).tolist() == [25.0, 25.0]
    assert source_pattern(mm, load).sum() == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("effect,label,part,volume", [
    ("spindle_motor", "spindle_motor", "motor", 0.22 * 0.22 * 0.25),
    ("spindle_bearings", "spindle_bearings.front_bearing", "front_bearing", 0.15 * 0.15 * 0.06),
    ("spindle_bearings", "spindle_bearings.rear_bearing", "rear_bearing", 0.15 * 0.15 * 0.06),
])
def test_each_spindle_source_fills_its_own_part(mm, effect, label, part, volume):
    """Each spindle source heats the cells of its own part, whose volume is its box's (the motor
    0.22 x 0.22 x 0.25 m, each bearing zone 0.15 x 0.15 x 0.06 m; round-off): the motor's losses in
    the rear bearing passed the gold regression (whose run has no motor) and every balance."""
    loads = {ld.label: ld for ld in EFFECTS[effect].loads(mm, _scenario(), EFFECTS[effect].defaults())}
    cells = loads[label].cells
    assert np.array_equal(np.sort(cells), np.sort(mm.cells_of(part)))
    assert mm.volume_of(cells) == pytest.approx(volume, rel=1e-12)


def test_forced_convection_acts_on_the_test_bar_and_the_spindle_nose(mm):
    """spindle_forced_convection on ``spindle.rotating``: the test bar's free faces (its four sides
    w x L and its tip w^2, w = 40 mm, L = 0.27 m) and the spindle's nose (0.15 m square at
    z = 0.95 m less the bar's w^2 seat), A = 4 w L + 0.15^2 = 0.0657 m2 (round-off), every face at
    or below the nose. On the open front the film passed every test (only A > 0 was checked)."""
    (load,) = EFFECTS["spindle_forced_convection"].loads(mm, _scenario(), EFFECTS["spindle_forced_convection"].defaults())
    w, length = 0.04, 0.27
    assert mm.facet_area(load.facets) == pytest.approx(4 * w * length + 0.15 ** 2, rel=1e-12)
    assert np.all(facet_centres(mm, load.facets)[:, 2] <= 0.95 + 1e-12)
    assert np.array_equal(np.sort(load.facets), np.sort(role_facets(mm, "spindle.rotating")))


def test_the_belt_heat_enters_through_the_pulleys_rim():
    """belt_drive on belt-vmc: P_ref (n / n_ref)^x as a uniform flux on the pulley's rim, its four
    lateral faces 0.12 m wide and 0.06 m high (z 1.40-1.46 m), A = 4 x 0.12 x 0.06 = 0.0288 m2
    (round-off), every face 0.06 m from the spindle axis; at n_ref = 8000 rpm P = 50 W. On the
    rotating bar's faces it stayed inside the calibration bands."""
    from geometries import build_machine
    from twin.fem.mesh import mesh_machine

    mb = mesh_machine(build_machine("belt-vmc"), "coarse")
    p = EFFECTS["belt_drive"].defaults()
    (load,) = EFFECTS["belt_drive"].loads(mb, _scenario(speed=8000.0), p)
    assert mb.facet_area(load.facets) == pytest.approx(4 * 0.12 * 0.06, rel=1e-12)
    c = facet_centres(mb, load.facets)
    assert np.all((c[:, 2] > 1.40) & (c[:, 2] < 1.46))
    np.testing.assert_allclose(np.max(np.abs(c[:, :2]), axis=1), 0.06, rtol=0, atol=1e-12)
    assert float(load.power(np.array([0.0]))[0]) == pytest.approx(50.0, rel=1e-12)


# ---- the sun's schedule ---------------------------------------------------------------------------

def test_the_sun_rises_again_every_day(mm):
    """solar_load: q(t) = q_peak sin(pi (tod - t_rise) / (t_set - t_rise)) by day, tod the time of
    day (mod 24 h): a run starting at 06:00 sees q A at 13:00 on every day (t = 7 h, 31 h, 55 h),
    q A sin(pi/4) at 10:00 of the second day, 0 at 21:00 and 03:00 (round-off). Without the modulo
    the sun shone only on the first day, and the 24 h test (its last instant 07:00 of day 2) passed."""
    p = EFFECTS["solar_load"].defaults()
    (load,) = EFFECTS["solar_load"].loads(mm, _scenario(hours=72.0, speed=0.0, tod=6 * HOUR), p)
    qa = p["flux"] * mm.facet_area(role_facets(mm, "structure.rear"))
    clock = np.array([13.0, 37.0, 61.0, 34.0, 45.0, 51.0]) * HOUR      # hours since midnight of day 1
    power = load.power(clock - 6 * HOUR)
    np.testing.assert_allclose(power, qa * np.array([1.0, 1.0, 1.0, np.sqrt(0.5), 0.0, 0.0]), rtol=1e-12, atol=1e-9)


def test_a_sunset_before_sunrise_means_no_sun(mm):
    """``daylight``: sunset <= sunrise means no sun (its docstring). With sunrise 19:00 and sunset
    07:00 the load is 0 at every minute of the day; the phase divided by the signed day length
    (t_set - t_rise < 0) gave the 07:00-19:00 half-sine back."""
    p = {**EFFECTS["solar_load"].defaults(), "sunrise": 19 * HOUR, "sunset": 7 * HOUR}
    (load,) = EFFECTS["solar_load"].loads(mm, _scenario(hours=24.0, speed=0.0), p)
    assert np.all(load.power(np.arange(0.0, 24 * HOUR, 60.0)) == 0.0)


# ---- declarations and registration ----------------------------------------------------------------

def _effect_class(**attrs):
    base = dict(name="audit_dummy", roles=("structure.skin",), strength="power", linear=True,
                parameters=(Parameter("power", "power", 10.0, 0.0, 100.0, "a power"),))
    return type("AuditDummy", (Effect,), {**base, **attrs})


@pytest.mark.parametrize("attrs,message", [
    ({"strength": "flux"}, "strength 'flux' is not one of its parameters"),
    ({"uncertain": (Uncertain("power", 20.0, 50.0, "x"),)}, "must contain the default 10"),
    ({"uncertain": (Uncertain("power", 5.0, 200.0, "x"),)}, "lie within [0, 100]"),
    ({"uncertain": (Uncertain("flux", 5.0, 50.0, "x"),)}, "uncertain 'flux' is not one of its parameters"),
])
def test_an_effects_declarations_must_fit_its_parameters(attrs, message):
    """check_declarations: the strength must be a parameter, and each Uncertain range must name a
    parameter and satisfy lower_p <= lower_u <= default <= upper_u <= upper_p (the diagnosis starts
    its fit at the default inside that range); a range without the default, or a strength that
    names nothing, passed before."""
    check_declarations(_effect_class(uncertain=(Uncertain("power", 5.0, 50.0, "x"),)))
    with pytest.raises(RuntimeError) as err:
        check_declarations(_effect_class(**attrs))
    assert message in str(err.value)


def test_a_library_name_cannot_be_registered_twice():
    """register_effect refuses a second effect under a registered name ("floor") and leaves the
    registry's effect as it was (a second registration silently replaced the library's)."""
    before = EFFECTS["floor"]
    try:
        with pytest.raises(RuntimeError, match="registered twice"):
            register_effect(_effect_class(name="floor", strength="conductance",
                                          parameters=(Parameter("conductance", "heat_transfer_coefficient", 20.0,
                                                                0.0, 1000.0, "h"),)))
        assert EFFECTS["floor"] is before
    finally:
        EFFECTS["floor"] = before


# ---- an effects file's range ----------------------------------------------------------------------

@pytest.mark.parametrize("spec,field,message", [
    # a range of one value leaves the diagnosis nothing to fit
    ({"kind": "heat_source", "region": "saddle", "power": "80 W", "range": ["80 W", "80 W"]},
     "effects.pump.range", "must contain the strength"),
    # a film coefficient is never negative, nor is any value the diagnosis may fit it to
    ({"kind": "convection", "region": "saddle", "h": "15 W/m2K", "range": ["-5 W/m2K", "30 W/m2K"]},
     "effects.pump.range", "a film coefficient cannot be negative"),
    # each end of the range times the schedule's largest factor (9 at 9000 rpm for 3000 rpm, x = 2):
    # 20 kW x 9 = 180 kW, beyond 100 kW though 20 kW alone is plausible
    ({"kind": "heat_source", "region": "saddle", "power": "80 W", "schedule": "speed",
      "reference_speed": "3000 rpm", "exponent": 2, "range": ["0 W", "20 kW"]},
     "effects.pump.range", "factor 9 at machine cframe-vmc's maximum of 9000 rpm"),
])
def test_an_effects_files_range_is_refused_where_the_fit_could_leave_the_plausible(machine, spec, field, message):
    from twin.effects.custom import effects_from_dict, unregister_custom

    try:
        with pytest.raises(InputError) as err:
            effects_from_dict({"effects": {"pump": spec}}, "fx.toml", machine)
        assert (err.value.source, err.value.field) == ("fx.toml", field)
        assert message in err.value.message, err.value.message
    finally:
        unregister_custom()


# ---- the room air ---------------------------------------------------------------------------------

@pytest.mark.parametrize("times", [(300.0, 3600.0), (0.0, 3000.0)])
def test_a_table_room_must_cover_the_run_from_its_start(times):
    """A ``table`` room must cover 0 to the run's end (nothing is extrapolated: np.interp would hold
    its first value before 5 min): a table from 5 min, or one ending at 50 min of a 60 min run, is
    refused naming ambient.times, from a scenario file and from a Scenario built in Python."""
    from twin.scenario import check_values, scenario_from_dict

    table = {"kind": "table", "times": [f"{t:g} s" for t in times], "temperatures": ["20 degC", "21 degC"]}
    data = {"name": "s", "sample_interval": "1 min", "spindle": [{"speed": "0 rpm", "duration": "1 h"}],
            "ambient": table}
    with pytest.raises(InputError) as err:
        scenario_from_dict(data, "s.toml")
    assert err.value.field == "ambient.times" and "must cover the scenario's 0 to 1 h" in err.value.message
    sc = Scenario("s", ((HOUR, 0.0),), Ambient("table", times=times, temperatures=(20.0, 21.0)), 60.0)
    with pytest.raises(InputError) as err:
        check_values(sc)
    assert err.value.field == "ambient.times"
    ok = Scenario("s", ((HOUR, 0.0),), Ambient("table", times=(0.0, HOUR), temperatures=(20.0, 21.0)), 60.0)
    check_values(ok)


def test_a_door_open_from_the_start_leaves_the_layered_swing_at_zero():
    """layered_swing = T_air(t) - T_air(0) without the door events (room.py): in a constant 20 degC
    room with a door open from t = 0 (fall 0, change -9 K) it is 0 at every instant, as for the
    same door opened 1 s later (a reference T_air(0) that kept the door read +9 K throughout, and
    stratified_swing then put about 177 W into the C-frame's skin in a constant room)."""
    from twin.effects.room import layered_swing

    t = np.array([0.0, 1800.0, 3600.0, 7200.0])
    for start in (0.0, 1.0):
        door = AirEvent(start=start, change=-9.0, fall=0.0, hold=1800.0, recovery=1800.0, door=True)
        sc = Scenario("d", ((2 * HOUR, 0.0),), Ambient("constant", mean=20.0, events=(door,)), 60.0)
        assert layered_swing(sc, t).tolist() == [0.0, 0.0, 0.0, 0.0], start
