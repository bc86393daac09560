"""Plausible limits of ``--effects-file`` values (twin.effects.custom): impossible or absurd
strengths, offsets, schedules and tables are one clear error naming the file and the dotted field,
refused before the run starts; values just inside the limits still load."""

from __future__ import annotations

import numpy as np
import pytest

from twin.cli import main
from twin.effects.custom import MAX_AIR_OFFSET, MAX_FLUX, MAX_H, MAX_POWER, effects_from_dict, unregister_custom
from twin.effects.custom_schedule import MAX_FACTOR
from twin.errors import InputError
from twin.scenario import Ambient, Scenario

SC = Scenario("c", ((600.0, 6000.0),), Ambient("constant", mean=20.0), 60.0)


@pytest.fixture(autouse=True)
def clean_registry():
    yield
    unregister_custom()


def _one(machine, folder=".", **spec):
    return effects_from_dict({"effects": {"pump": spec}}, "fx.toml", machine, folder)[0]


def _refused(machine, field, match=None, folder=".", **spec):
    with pytest.raises(InputError) as err:
        _one(machine, folder, **spec)
    assert (err.value.source, err.value.field) == ("fx.toml", field), str(err.value)
    if match:
        assert match in err.value.message, err.value.message
    return err.value


SOURCE = {"kind": "heat_source", "region": "saddle"}
FLUX = {"kind": "heat_flux", "region": "column.+x"}
CONV = {"kind": "convection", "region": "saddle"}


@pytest.mark.parametrize("spec,field,match", [
    ({**SOURCE, "power": "-1e9 W"}, "effects.pump.power", "100 kW"),
    ({**SOURCE, "power": "150 kW"}, "effects.pump.power", "100 kW"),
    ({**SOURCE, "power": "-101 kW"}, "effects.pump.power", "100 kW"),
    ({**FLUX, "power": "200 kW"}, "effects.pump.power", "100 kW"),
    ({**FLUX, "flux": "-20 kW"}, "effects.pump.flux", "wrong unit"),
    ({**FLUX, "flux": "20000 W/m2"}, "effects.pump.flux", "10 kW/m2"),
    ({**FLUX, "flux": "-20000 W/m2"}, "effects.pump.flux", "10 kW/m2"),
    ({**CONV, "h": "20000 W/m2K"}, "effects.pump.h", "10000 W/m2K"),
    ({**CONV, "h": "0 W/m2K"}, "effects.pump.h", "positive"),
    ({**CONV, "h": "15 W/m2K", "air_offset": "-500 K"}, "effects.pump.air_offset", "absolute zero"),
    ({**CONV, "h": "15 W/m2K", "air_offset": "101 K"}, "effects.pump.air_offset", "100 K"),
    ({**SOURCE, "power": "80 W", "range": ["0 W", "1e9 W"]}, "effects.pump.range", "100 kW"),
    ({**SOURCE, "power": "-80 W", "range": ["-1 MW", "0 W"]}, "effects.pump.range", "wrong unit"),
    ({**SOURCE, "power": "-80 W", "range": ["-200 kW", "0 W"]}, "effects.pump.range", "100 kW"),
    ({**CONV, "h": "15 W/m2K", "range": ["1 W/m2K", "1e5 W/m2K"]}, "effects.pump.range", "10000 W/m2K"),
    ({**SOURCE, "power": "80 W", "schedule": "speed", "reference_speed": "9000 rpm", "exponent": -3},
     "effects.pump.exponent", "0 to 3"),
    ({**SOURCE, "power": "80 W", "schedule": "speed", "reference_speed": "9000 rpm", "exponent": 3.5},
     "effects.pump.exponent", "0 to 3"),
    ({**SOURCE, "power": "80 W", "schedule": "speed", "reference_speed": "1 rpm"},
     "effects.pump.reference_speed", "100 to 60000 rpm"),
    ({**SOURCE, "power": "80 W", "schedule": "speed", "reference_speed": "1e6 rpm"},
     "effects.pump.reference_speed", "100 to 60000 rpm"),
    # the strength is plausible, the schedule's largest factor (at the machine's 9000 rpm) is not
    ({**SOURCE, "power": "80 kW", "schedule": "speed", "reference_speed": "3000 rpm", "exponent": 2},
     "effects.pump.power", "factor 9 at machine cframe-vmc's maximum of 9000 rpm"),
    ({**SOURCE, "power": "80 W", "schedule": "windows", "windows": [["-1 h", "2 min"]]},
     "effects.pump.windows[0]", "before the run's start"),
    # windows sharing a time: s is 1 inside any window, so the shared time is not loaded twice
    ({**SOURCE, "power": "80 W", "schedule": "windows", "windows": [["0 h", "0.1 h"], ["0 h", "0.1 h"]]},
     "effects.pump.windows[1]", '["0 h", "0.1 h"] repeats windows[0] ["0 h", "0.1 h"]: the factor is 1 inside any '
                                "window, so a shared time is not loaded twice"),
    ({**SOURCE, "power": "80 W", "schedule": "windows", "windows": [["0 h", "0.1 h"], ["0 min", "6 min"]]},
     "effects.pump.windows[1]", '["0 min", "6 min"] repeats windows[0]'),     # the same window, other units
    ({**SOURCE, "power": "80 W", "schedule": "windows", "windows": [["0 h", "1 h"], ["30 min", "2 h"]]},
     "effects.pump.windows[1]", '["30 min", "2 h"] overlaps windows[0] ["0 h", "1 h"]'),
    ({**SOURCE, "power": "80 W", "schedule": "windows", "windows": [["3 h", "4 h"], ["0 h", "5 h"]]},
     "effects.pump.windows[1]", '["0 h", "5 h"] overlaps windows[0] ["3 h", "4 h"]'),      # one inside the other
    ({**SOURCE, "power": "80 W", "schedule": "windows",
      "windows": [["0 h", "5 h"], ["6 h", "7 h"], ["4 h", "4.5 h"]]},                       # not in order
     "effects.pump.windows[2]", '["4 h", "4.5 h"] overlaps windows[0] ["0 h", "5 h"]'),
    ({**SOURCE, "power": "80 W", "doc": 3}, "effects.pump.doc", "expected text"),
    ({"kind": ["heat_source"], "region": "saddle", "power": "80 W"}, "effects.pump.kind", "unknown kind"),
    # a region named twice: the union holds it once, not the doubled power the list seems to ask
    ({**SOURCE, "region": ["saddle", "table", "saddle"], "power": "80 W"}, "effects.pump.region",
     "'saddle' named more than once"),
])
def test_implausible_values_are_refused(machine, spec, field, match):
    _refused(machine, field, match, **spec)


def test_values_at_the_limits_still_load(machine):
    """The limits refuse only what is beyond them: a 100 kW source, a 100 kW sink, 10 kW/m2,
    h 10000 W/m2K with a 100 K offset, exponent 0 and 3; the default diagnosis range (10 x the
    strength) is clipped to the limit instead of refusing a large strength."""
    big = _one(machine, **SOURCE, power=f"{MAX_POWER:g} W")
    assert big.defaults()["power"] == MAX_POWER and big.uncertain[0].upper == MAX_POWER
    sink = _one(machine, **SOURCE, power=f"-{MAX_POWER:g} W")
    assert sink.uncertain[0].lower == -MAX_POWER and sink.uncertain[0].upper == 0
    assert _one(machine, **SOURCE, power="80 W").uncertain[0].upper == 800     # unchanged below the limit
    assert _one(machine, **FLUX, flux=f"{MAX_FLUX:g} W/m2").defaults()["flux"] == MAX_FLUX
    conv = _one(machine, **CONV, h=f"{MAX_H:g} W/m2K", air_offset=f"-{MAX_AIR_OFFSET:g} K")
    assert conv.air_offset == -MAX_AIR_OFFSET and conv.uncertain[0].upper == MAX_H
    for x in (0, 3):
        e = _one(machine, **SOURCE, power="80 W", schedule="speed", reference_speed="9000 rpm", exponent=x)
        assert e.schedule.exponent == x
    # windows that only touch (one's end the next's start), in any order, share no time
    e = _one(machine, **SOURCE, power="80 W", schedule="windows",
             windows=[["1 h", "2 h"], ["0 h", "1 h"], ["3 h", "4 h"]])
    assert e.schedule.windows == ((3600.0, 7200.0), (0.0, 3600.0), (10800.0, 14400.0))
    e = _one(machine, **SOURCE, power="80 W", schedule="windows", windows=[["0 d", "1.1 d"], ["26.4 h", "30 h"]])
    assert e.schedule.windows[0][1] > e.schedule.windows[1][0]      # touching, 1e-11 s apart in floating point


def _write_table(tmp_path, text):
    (tmp_path / "f.csv").write_text(text)
    return {**SOURCE, "power": "80 W", "schedule": "table", "table": {"file": "f.csv", "time_unit": "min"}}


@pytest.mark.parametrize("text,field,match", [
    ("0,1\n30,0.5\n60,0.2\n", "header", "needs a header row"),
    ("t,factor\n0,1\n", "table", "at least two data rows"),
    ("0,1\n30,0.5\n", "table", "at least two data rows"),
    ("t,factor\n0,1\n30,-1e9\n", "factor", "outside 0 to 100"),
    ("t,factor\n0,1\n30,101\n", "factor", "outside 0 to 100"),
    ("t,factor\n0,1\n30,nan\n", "factor", "not a finite number"),
    ("t,factor\n0,1\n30,x\n", "factor", "not a number"),
    ("t,factor\n-5,1\n30,1\n", "time", "must start at 0"),
    ("t,factor\n5,1\n30,1\n", "time", "must start at 0"),
    ("t,factor\n0,1\n0,1\n", "time", "increase strictly"),
    ("t,factor\n0,1\n30,1,2\n", "line 3", "has 3 fields"),
    # the header names the time first, the factor second; a unit only on the time, in brackets
    ("factor,time\n0,1\n30,1\n", "header", "column 1 is 'factor'; the header names the time first, then the "
                                          "factor: 'time,factor' or 'time [min],factor' (the columns are swapped)"),
    ("time,time\n0,1\n30,1\n", "header", "column 2 is 'time'"),
    ("minutes,factor\n0,1\n30,1\n", "header", "column 1 is 'minutes'"),
    ("time,scale\n0,1\n30,1\n", "header", "column 2 is 'scale'"),
    ("time [,factor\n0,1\n30,1\n", "header", "column 1: 'time [' is not a name with its unit in brackets"),
    ("time [],factor\n0,1\n30,1\n", "header", "column 1: 'time []' is not a name with its unit in brackets"),
    ("time [min] [s],factor\n0,1\n30,1\n", "header", "column 1: 'time [min] [s]' is not a name"),
    ("time [kg],factor\n0,1\n30,1\n", "time", "header unit [kg]: 'kg' is not a unit of time"),
    ("time [degC],factor\n0,1\n30,1\n", "time", "'degC' is a temperature unit"),
    ("time [min],factor [%]\n0,1\n30,1\n", "factor", "the factor is a plain number"),
])
def test_bad_schedule_tables_are_refused(machine, tmp_path, text, field, match):
    spec = _write_table(tmp_path, text)
    with pytest.raises(InputError) as err:
        _one(machine, tmp_path, **spec)
    assert (err.value.source, err.value.field) == (str(tmp_path / "f.csv"), field), str(err.value)
    assert match in err.value.message, err.value.message


@pytest.mark.parametrize("header,time_unit,seconds", [
    ("t,factor", "min", 60.0),               # the header without units: time_unit gives the unit (as ever)
    ("time,factor", "h", 3600.0),
    ("Time,Factor", "s", 1.0),               # names in any case
    ("time [min],factor", None, 60.0),       # the header's unit, time_unit left out
    ("time [s],factor", "s", 1.0),           # both, the same unit
    ("time [hr],factor", "h", 3600.0),       # both, two spellings of one unit
    (" time [ min ] , factor ", None, 60.0),
])
def test_the_time_unit_comes_from_the_header_or_time_unit(machine, tmp_path, header, time_unit, seconds):
    (tmp_path / "f.csv").write_text(header + "\n0,1\n10,0.5\n")
    table = {"file": "f.csv"} if time_unit is None else {"file": "f.csv", "time_unit": time_unit}
    e = _one(machine, tmp_path, **SOURCE, power="80 W", schedule="table", table=table)
    np.testing.assert_array_equal(e.schedule.table[0], [0.0, 10 * seconds])
    np.testing.assert_array_equal(e.schedule.table[1], [1.0, 0.5])


@pytest.mark.parametrize("header,time_unit,match", [
    # the audit's file: seconds in the header, minutes in fx.toml, read as minutes before
    ("time [s],factor", "min", "'min' contradicts the header of {csv}, 'time [s]' (times in s); give the time's "
                               "unit once: leave time_unit out or make the two agree"),
    ("time [h],factor", "s", "'s' contradicts the header of {csv}, 'time [h]' (times in h)"),
    # neither gives the unit
    ("time,factor", None, "missing: the header of {csv} gives the time no unit ('time'); write time_unit = \"min\" "
                          "here or the unit in the header, 'time [min]'"),
])
def test_a_missing_or_contradicting_time_unit_is_refused(machine, tmp_path, header, time_unit, match):
    (tmp_path / "f.csv").write_text(header + "\n0,1\n600,0.5\n1800,1\n")
    table = {"file": "f.csv"} if time_unit is None else {"file": "f.csv", "time_unit": time_unit}
    _refused(machine, "effects.pump.table.time_unit", match.format(csv=tmp_path / "f.csv"), tmp_path,
             **SOURCE, power="80 W", schedule="table", table=table)


def test_table_factor_times_strength_is_bounded_and_file_keys_are_typed(machine, tmp_path):
    spec = _write_table(tmp_path, "t,factor\n0,0\n10,50\n")
    _refused(machine, "effects.pump.power", "the table's largest factor 50", tmp_path, **{**spec, "power": "5 kW"})
    e = _one(machine, tmp_path, **{**spec, "power": "2 kW"})        # 2 kW x 50 = 100 kW: allowed
    # the default range is clipped: 10 x 2 kW at factor 50 would peak at 1 MW
    assert e.uncertain[0].upper == pytest.approx(MAX_POWER / 50)
    _refused(machine, "effects.pump.table.file", "expected the path", tmp_path,
             **{**spec, "table": {"file": 3, "time_unit": "min"}})
    _refused(machine, "effects.pump.table.time_unit", "time unit", tmp_path,
             **{**spec, "table": {"file": "f.csv", "time_unit": 60}})
    assert MAX_FACTOR == 100


def test_a_table_must_reach_the_end_of_the_run(machine, mm, tmp_path):
    """Like a room-air record or an ambient table, a schedule table that ends before the run is refused when the run
    starts (the effects file does not know the run's length), naming the effects file, the field
    and the table; one that reaches the end loads, linear in between."""
    short = _one(machine, tmp_path, **_write_table(tmp_path, "t,factor\n0,0\n5,1\n"))
    with pytest.raises(InputError) as err:
        short.loads(mm, SC, short.defaults())
    assert (err.value.source, err.value.field) == ("fx.toml", "effects.pump.table")
    assert "f.csv ends at 0.0833333 h, before the scenario's 0.166667 h; it must cover" in err.value.message
    ok = _one(machine, tmp_path, **_write_table(tmp_path, "t,factor\n0,0\n10,1\n"))
    (load,) = ok.loads(mm, SC, ok.defaults())
    np.testing.assert_allclose(load.power(np.array([0.0, 300.0, 600.0])), [0.0, 40.0, 80.0])


SCENARIO = ('name = "s"\nsample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
            '[[spindle]]\nspeed = "6000 rpm"\nduration = "10 min"\n')


@pytest.mark.parametrize("effect,field", [
    ('kind = "heat_source"\nregion = "saddle"\npower = "-1e9 W"\n', "effects.pump.power"),
    ('kind = "convection"\nregion = "saddle"\nh = "15 W/m2K"\nair_offset = "-500 K"\n', "effects.pump.air_offset"),
    ('kind = "heat_source"\nregion = "saddle"\npower = "80 W"\nschedule = "speed"\nreference_speed = "9000 rpm"\n'
     'exponent = -3\n', "effects.pump.exponent"),
    ('kind = "heat_source"\nregion = "saddle"\npower = "80 W"\nschedule = "table"\n'
     'table = { file = "f.csv", time_unit = "min" }\n', "effects.pump.table"),     # ends at 5 min of 10
    ('kind = "heat_source"\nregion = "saddle"\npower = "80 W"\nschedule = "windows"\n'
     'windows = [["2 min", "4 min"], ["10 h", "11 h"]]\n', "effects.pump.windows[1]"),  # opens after the 10 min run
    ('kind = "heat_source"\nregion = "saddle"\npower = "80 W"\nschedule = "windows"\n'
     'windows = [["0 h", "0.1 h"], ["0 h", "0.1 h"]]\n', "effects.pump.windows[1]"),     # one window twice
    ('kind = "heat_source"\nregion = "saddle."\npower = "80 W"\n', "effects.pump.region"),   # no direction after '.'
    ('kind = "heat_flux"\nregion = ["saddle", "saddle.+x"]\npower = "80 W"\n', "effects.pump.region"),
    ('kind = "heat_source"\nregion = "saddle"\npower = "80 W"\nschedule = "table"\n'
     'table = { file = "f.csv", time_unit = "s" }\n', "effects.pump.table.time_unit"),   # f.csv's 'time [min]'
])
def test_cli_refuses_with_exit_2_and_no_output(tmp_path, capsys, effect, field):
    (tmp_path / "s.toml").write_text(SCENARIO)
    header = "time [min],factor" if 'time_unit = "s"' in effect else "t,factor"     # the contradiction's table
    (tmp_path / "f.csv").write_text(header + "\n0,1\n5,0.5\n")
    (tmp_path / "fx.toml").write_text("[effects.pump]\n" + effect)
    out = tmp_path / "out.nc"
    assert main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(out), "--mesh", "coarse",
                 "--effects-file", str(tmp_path / "fx.toml")]) == 2
    err = capsys.readouterr().err
    assert f"fx.toml: {field}: " in err and "Traceback" not in err, err
    assert not out.exists()


@pytest.mark.parametrize("header,field", [
    ("time [s],factor", "fx.toml: effects.pump.table.time_unit: 'min' contradicts the header of {csv}"),
    ("factor,time", "{csv}: header: column 1 is 'factor'"),
])
def test_cli_refuses_a_table_header_it_cannot_trust(tmp_path, capsys, header, field):
    """The audit's files: a header in seconds read as minutes (time_unit = "min"), and the columns
    swapped, both ran to exit 0; now exit 2 naming the file and field or column, and no output."""
    (tmp_path / "s.toml").write_text(SCENARIO)
    (tmp_path / "f.csv").write_text(header + "\n0,1\n600,0.5\n1800,1\n")
    (tmp_path / "fx.toml").write_text('[effects.pump]\nkind = "heat_source"\nregion = "saddle"\npower = "80 W"\n'
                                      'schedule = "table"\ntable = { file = "f.csv", time_unit = "min" }\n')
    out = tmp_path / "out.nc"
    assert main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(out), "--mesh", "coarse",
                 "--effects-file", str(tmp_path / "fx.toml")]) == 2
    err = capsys.readouterr().err
    assert field.format(csv=tmp_path / "f.csv") in err and "Traceback" not in err, err
    assert not out.exists()


def test_a_window_inside_a_later_reaching_one_is_refused(machine):
    """Windows must not share a time, also where a window lies inside an earlier-starting one that
    reaches past a later one: [0-1 h], [2-5 h], [3-4 h] is refused naming windows[2] and windows[1]."""
    from twin.effects.custom import effects_from_dict
    spec = {"kind": "heat_source", "region": "saddle", "power": "80 W", "schedule": "windows",
            "windows": [["0 h", "1 h"], ["2 h", "5 h"], ["3 h", "4 h"]]}
    with pytest.raises(InputError) as err:
        effects_from_dict({"effects": {"pump": spec}}, "fx.toml", machine)
    assert err.value.field == "effects.pump.windows[2]"
    assert '["3 h", "4 h"] overlaps windows[1] ["2 h", "5 h"]' in err.value.message


def test_a_tables_largest_factor_bounds_the_strength_wherever_it_lies(machine, tmp_path):
    """The strength times the schedule's largest factor stays within the plausible limit: 5 kW x 50
    (the table's peak in its middle row) exceeds 100 kW, refused on the power naming the factor."""
    from twin.effects.custom import effects_from_dict
    (tmp_path / "f.csv").write_text("t,factor\n0,0\n5,50\n10,1\n")
    spec = {"kind": "heat_source", "region": "saddle", "power": "5 kW", "schedule": "table",
            "table": {"file": "f.csv", "time_unit": "min"}}
    with pytest.raises(InputError) as err:
        effects_from_dict({"effects": {"pump": spec}}, "fx.toml", machine, tmp_path)
    assert err.value.field == "effects.pump.power" and "the table's largest factor 50" in err.value.message


def test_a_window_opening_at_the_runs_end_is_refused(machine, mm):
    """A window that opens at the end of a 10 min run would do nothing: refused naming it."""
    from twin.effects.custom import effects_from_dict, unregister_custom
    spec = {"kind": "heat_source", "region": "saddle", "power": "80 W", "schedule": "windows",
            "windows": [["2 min", "4 min"], ["10 min", "11 min"]]}
    (e,) = effects_from_dict({"effects": {"pump": spec}}, "fx.toml", machine)
    sc = Scenario("c", ((600.0, 6000.0),), Ambient("constant", mean=20.0), 60.0)
    with pytest.raises(InputError) as err:
        e.loads(mm, sc, e.defaults())
    assert err.value.field == "effects.pump.windows[1]" and "at or after the end" in err.value.message
    unregister_custom()
