"""Command line: listing, bad input (one line, exit 2, no partial output), end to end on a short run."""

from __future__ import annotations

import os

import numpy as np
import pytest
import xarray as xr

from tests.fuzz_files import SCENARIO as SHORT   # 6000 rpm for 10 min, then stopped for 20, logged every minute
from twin.cli import main
from twin.scenario import load_scenario
from twin.units import UnitError, parse_quantity


def _error(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and "Traceback" not in err
    return err


def test_list_effects_names_its_machine_option(capsys):
    """``twin list effects --machine nope`` names the option that gave the name (it said ``machine``,
    the positional argument of ``twin simulate``)."""
    err = _error(capsys, ["list", "effects", "--machine", "nope"])
    assert err == ("error: command line: --machine: unknown machine 'nope'; known: belt-vmc, cframe-vmc, "
                   "gantry-ram")


def test_version_and_a_bare_twin(capsys):
    """``twin --version`` prints the installed version, the one every result records
    (``package_version`` attribute); a bare ``twin`` names the commands in its one-line error."""
    from importlib.metadata import version

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"thermal-twin {version('thermal-twin')}"
    err = _error(capsys, [])
    assert err.startswith("error: command line: twin: give a command: list, simulate, plot, frames, dataset, ")
    assert all(c in err for c in ("compare", "demo", "diagnose", "learn", "report", "`twin -h`"))


@pytest.mark.parametrize("what", ["machines", "scenarios", "effects", "instruments"])
def test_list(capsys, what):
    assert main(["list", what]) == 0
    assert capsys.readouterr().out.strip()


def test_units_parse_and_reject():
    assert parse_quantity("2 h", "time") == 7200 and parse_quantity("8000 rpm", "speed") == 8000
    for bad in ("20", "20 K", "x s", "inf s"):
        with pytest.raises(UnitError):
            parse_quantity(bad, "time")


@pytest.mark.parametrize("text,dimension,message", [
    ("nanW", "power", "'nanW' is not a finite number"),
    ("-Infinity s", "time", "'-Infinity s': '-Infinity' is not a finite number"),
    (float("inf"), "time", "inf is not a finite number"),
    ("info", "time", "'info' is not a decimal number"),
    ("1_000 rpm", "speed", "'1_000 rpm': '1_000' is not a decimal number"),
    ("6_0W", "power", "'6_0W': '6_0' is not a decimal number"),          # no space: the unit is still known
    ("0x3cW", "power", "'0x3cW': '0x3c' is not a decimal number"),
    ("1.5.2 mm", "length", "'1.5.2 mm': '1.5.2' is not a decimal number"),
    ("3,5W", "power", "'3,5W': '3,5' is not a decimal number"),            # a decimal comma
    ("5MW", "power", "'5MW' has the wrong unit"),                         # a prefix we do not take: the unit
    ("-1 MW", "power", "'-1 MW' has the wrong unit"),
    (80, "velocity", "80 has no unit; write it like '80 mm/s'"),
    ([1, 2], "length", "got a list of 2 values; expected a quantity with a unit such as '150 mm'"),
])
def test_unit_errors_name_the_number_when_the_number_is_wrong(text, dimension, message):
    with pytest.raises(UnitError) as err:
        parse_quantity(text, dimension)
    assert str(err.value).startswith(message), str(err.value)
    assert parse_quantity("5%", "dimensionless") == 0.05 and parse_quantity("20degC", "temperature") == 20.0


def test_daily_ambient_is_coldest_in_the_morning():
    sc = load_scenario("etve-day-night")
    t = np.arange(0, 86400, 60.0)
    temp = sc.ambient_temperature(t)
    assert t[np.argmin(temp)] == 6 * 3600 and temp.max() - temp.min() == pytest.approx(5.0)


def test_a_daily_room_that_starts_at_8_h_is_read_at_its_time_of_day():
    """T(t) = mean - A cos(2 pi (t_0 + t - t_cold) / 1 d), t_0 the time of day the run starts:
    mean 20, A 3 K, coldest at 6 h, starting at 8 h: T(0) = 20 - 3 cos(2 pi 2 / 24) = 17.4019 degC,
    coldest (17.0) at t = 22 h and warmest (23.0) at t = 10 h, to round-off. (Every bundled test
    that a test reads starts at 0 h, where the sign of t_0 cannot show.)"""
    from twin.scenario import Ambient
    amb = Ambient("daily", mean=20.0, amplitude=3.0, coldest_at=6 * 3600.0, start_time_of_day=8 * 3600.0)
    t = np.array([0.0, 22 * 3600.0, 10 * 3600.0])
    np.testing.assert_allclose(amb(t), [20.0 - 3.0 * np.cos(2 * np.pi * 2 / 24), 17.0, 23.0], rtol=0, atol=1e-12)


@pytest.mark.parametrize("text,dimension,si", [
    ("1.5 kW", "power", 1500.0),                  # 1 kW = 1e3 W
    ("9 krpm", "speed", 9000.0),                  # 1 krpm = 1e3 rpm
    ("180 deg", "angle", np.pi),                  # 180 deg = pi rad
    ("1.5 mrad", "angle", 1.5e-3),
    ("250 ms", "time", 0.25),                     # 1 ms = 1e-3 s
    ("1.5 d", "time", 129600.0),                  # 1 d = 86400 s
    ("120 m/min", "velocity", 2.0),               # 1 m/min = 1/60 m/s
    ("600 mm/min", "velocity", 0.01),             # 1 mm/min = 1e-3/60 m/s
    ("11.5 um/m/K", "thermal_strain", 11.5e-6),   # 1 um/m = 1e-6
    ("2 K/mm", "temperature_gradient", 2000.0),   # 1 /mm = 1e3 /m
    ("250 mK", "temperature_difference", 0.25),
    ("40 %", "dimensionless", 0.4),
])
def test_units_convert_to_si_with_their_definitions(text, dimension, si):
    """Every prefixed spelling is its SI definition (k = 1e3, m = 1e-3, u = 1e-6, 1 min = 60 s,
    1 d = 86400 s, 1 deg = pi / 180 rad): a wrong factor would scale a heat load, a feed or a
    camera's field of view silently, since the value stays in its plausible range."""
    assert parse_quantity(text, dimension) == pytest.approx(si, rel=1e-15)


# every spelling the parser knows, held equal to another by the unit's definition (1 cm = 10 mm,
# 1 W = 1000 mW, 1 /mm = 1000 /m, 1 h = 3600 s, ...), each side written as a person would
UNIT_EQUIVALENTS = [
    ("time", ["60 s", "60 sec", "1 min", "60000 ms"]), ("time", ["1 h", "1 hr", "3600 s"]),
    ("time", ["1 d", "24 h"]),
    ("speed", ["9 krpm", "9000 rpm", "9000 1/min"]),
    ("temperature", ["21.5 degC", "21.5 °C", "21.5 C"]),
    ("temperature_difference", ["250 mK", "0.25 K"]),
    ("power", ["1.5 kW", "1500 W", "1500000 mW"]),
    ("heat_transfer_coefficient", ["8 W/m2K", "8 W/(m2 K)", "8 W/(m^2 K)", "8 W/m^2/K", "8 W/m2/K", "8 W/(m2*K)",
                                   "8 W/m^2K"]),
    ("conductance", ["3 W/K", "3.0 W/K"]),
    ("heat_flux", ["100 W/m2", "100 W/m^2"]),
    ("length", ["1.5 m", "150 cm", "1500 mm", "1500000 um"]),
    ("velocity", ["1 m/s", "1000 mm/s", "60000 mm/min", "60 m/min"]),
    ("acceleration", ["2 m/s2", "2 m/s^2", "2000 mm/s2", "2000 mm/s^2"]),
    ("temperature_gradient", ["2 K/mm", "2000 K/m"]),
    ("strain", ["5e-5 m/m", "50 um/m", "50 ppm"]),
    ("thermal_strain", ["1.15e-5 1/K", "11.5 um/m/K", "11.5 ppm/K"]),
    ("inverse_length", ["3 1/mm", "3000 1/m", "3000 /m"]),
    ("angle", ["180 deg", "3.141592653589793 rad", "3141.592653589793 mrad"]),
    ("dimensionless", ["40 %", "0.4", "0.4 1"]),
]


def test_every_unit_spelling_is_its_definition():
    """Each group above is one quantity in several spellings (k = 1e3, m = 1e-3, u = 1e-6, c =
    1e-2, ppm = 1e-6, 1 min = 60 s, 1 d = 24 h, pi rad = 180 deg): all parse to the same SI value,
    to round-off, and together the groups use every spelling the parser knows (a new spelling
    needs its group here). A wrong factor (cm as 1e-3 m, mW as 1 W) would pass every
    plausibility check."""
    from twin import units
    used = {}
    for dimension, texts in UNIT_EQUIVALENTS:
        values = [parse_quantity(t, dimension) for t in texts]
        assert values == pytest.approx([values[0]] * len(values), rel=1e-15), texts
        used.setdefault(dimension, set()).update(t.split(" ", 1)[1] if " " in t else "" for t in texts)
    assert used == {d: set(u) for d, u in units._UNITS.items()}


def test_a_quantity_whose_si_value_overflows_is_not_finite():
    """A number finite as written may overflow once converted to SI (1e306 d = 8.64e310 s, beyond
    the largest double): the parser names it as not finite (module docstring: a quantity is
    finite) rather than returning inf for a later check to misname."""
    for text, dimension in (("1e306 d", "time"), ("1e306 kW", "power"), ("-1e306 krpm", "speed")):
        with pytest.raises(UnitError, match="is not a finite number"):
            parse_quantity(text, dimension)
    assert parse_quantity("1e300 d", "time") == pytest.approx(8.64e304)


def test_a_scenario_samples_its_whole_run_from_0_to_the_end():
    """``Scenario.times()``: the instants 0, dt, 2 dt, ... up to and including the duration, n + 1
    of them for n = duration / dt steps, also where the two do not divide exactly in floating
    point: 0.3 s / 0.1 s = 2.9999999999999996, which truncation would turn into 2 steps, ending
    a run sampled at 10 Hz one sample early."""
    from twin.scenario import scenario_from_dict

    data = {"name": "s", "ambient": {"temperature": "20 degC"}, "sample_interval": "1 min",
            "spindle": [{"speed": "6000 rpm", "duration": "10 min"}]}
    t = scenario_from_dict(data, "s.toml").times()
    np.testing.assert_array_equal(t, np.arange(11) * 60.0)
    fine = scenario_from_dict({**data, "sample_interval": "0.1 s",
                               "spindle": [{"speed": "0 rpm", "duration": "0.3 s"}]}, "s.toml")
    assert len(fine.times()) == 4 and fine.times()[-1] == pytest.approx(fine.duration, rel=1e-12)


def test_each_spindle_step_holds_from_its_start_to_its_end_and_the_last_holds_on():
    """``Scenario.spindle_speed``: step k holds on [start_k, end_k) (at a step's end the next
    one's speed is read, as a result records it at its sample instants) and the last step
    holds on after the end: 8000 rpm for 60 s, 0 for 60 s, 4000 rpm for 60 s."""
    from twin.scenario import Ambient, Scenario

    sc = Scenario("s", ((60.0, 8000.0), (60.0, 0.0), (60.0, 4000.0)), Ambient("constant", mean=20.0), 60.0)
    t = np.array([0.0, 59.9, 60.0, 119.9, 120.0, 179.9, 180.0, 1e6])
    np.testing.assert_array_equal(sc.spindle_speed(t), [8000, 8000, 0, 0, 4000, 4000, 4000, 4000])
    np.testing.assert_array_equal(sc.spindle_speed(sc.times()), [8000, 0, 4000, 4000])


def test_a_daily_room_takes_times_of_day_from_0_to_24_h_excluded():
    """``coldest_at`` and ``start_time_of_day`` are times of day from 0 h to 24 h, 24 h excluded
    (it is the next day's 0 h; ``twin.ambient.check_ambient``): "24 h" is refused naming the key,
    "0 h" and "23.5 h" are taken."""
    from twin.ambient import ambient_from_toml
    from twin.errors import InputError

    daily = {"kind": "daily", "mean": "20 degC", "amplitude": "2 K"}
    for key in ("coldest_at", "start_time_of_day"):
        with pytest.raises(InputError) as err:
            ambient_from_toml({**daily, key: "24 h"}, "s.toml")
        assert err.value.field == f"ambient.{key}"
        for ok in ("0 h", "23.5 h"):
            assert getattr(ambient_from_toml({**daily, key: ok}, "s.toml"), key) == parse_quantity(ok, "time")


def test_a_table_rooms_times_increase_strictly():
    """A ``table`` ambient's times must increase strictly (``twin.ambient.check_ambient``): a
    repeated time would give the air two temperatures at one instant (a jump that linear
    interpolation hides), so it is refused naming ``ambient.times``."""
    from twin.ambient import ambient_from_toml
    from twin.errors import InputError

    table = {"kind": "table", "times": ["0 h", "1 h", "1 h", "2 h"], "temperatures": ["20 degC", "21 degC", "18 degC",
                                                                                     "19 degC"]}
    with pytest.raises(InputError) as err:
        ambient_from_toml(table, "s.toml")
    assert err.value.field == "ambient.times" and "strictly" in str(err.value)
    ambient_from_toml({**table, "times": ["0 h", "1 h", "1.5 h", "2 h"]}, "s.toml")


@pytest.mark.parametrize("argv,needle", [
    (["simulate", "no-such-machine", "spindle-duty-cycle"], "machine"),
    (["simulate", "cframe-vmc", "no-such-scenario"], "scenario"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--effects", "+warp_drive"], "warp_drive"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--set", "spindle_motor.colour=3 W"], "colour"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--set", "spindle_motor.power=3"], "no unit"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--set", "spindle_motor.power=3 K"], "wrong unit"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--set", "spindle_motor.power=-3 W"], "bounds"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--mesh", "huge"], "--mesh"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--effects", ""], "--effects: is empty"),   # not the defaults
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--effects", " , "], "--effects: ' , ' names no effect"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--solver", "direct", "--heat-start", "reduced"], "--heat-start"),
    (["simulate", "cframe-vmc", "spindle-duty-cycle", "--mesh", "coarse", "--heat-start", "projection"],
     "--heat-start: starts iterative heat steps; --solver auto factorises"),
])
def test_bad_names_and_values(capsys, tmp_path, argv, needle):
    out = tmp_path / "r.nc"
    err = _error(capsys, argv + ["-o", str(out)])
    assert needle in err
    assert not out.exists()


@pytest.mark.parametrize("text,field", [
    ("name = 'x'\n[ambient\n", "toml"),
    (SHORT.replace('duration = "10 min"', 'duration = "-10 min"'), "spindle[0].duration"),
    (SHORT.replace('duration = "10 min"', 'duration = "10"'), "spindle[0].duration"),
    (SHORT.replace('speed = "6000 rpm"', 'speed = "6000 W"'), "spindle[0].speed"),
    (SHORT.replace('sample_interval', 'sampel_interval'), "sampel_interval"),
    (SHORT.replace('[ambient]', '[ambient]\ncolour = "red"'), "ambient.colour"),
])
def test_bad_scenario_files(capsys, tmp_path, text, field):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    out = tmp_path / "r.nc"
    err = _error(capsys, ["simulate", "cframe-vmc", str(path), "-o", str(out)])
    assert str(path) in err and field in err
    assert not out.exists()


AXIS = ('\n[[axis]]\nname = "Y"\n[[axis.move]]\nkind = "reciprocate"\nbetween = ["0 mm", "280 mm"]\n'
        'feed = "20 mm/s"\nacceleration = "10 mm/s2"\nduration = "10 min"\n')
PROBING = '\n[probing]\ntimes = ["0 min", "10 min"]\ndatums = [["150 mm", "100 mm", "100 mm"]]\n'


@pytest.mark.parametrize("text,message", [
    # a misspelled key is named (with the known ones), not reported as its correct sibling missing
    (SHORT.replace('speed = "6000 rpm"', 'sped = "6000 rpm"'), "spindle[0].sped: unknown key (known: duration, speed)"),
    (SHORT.replace("temperature =", "temprature ="), "ambient.temprature: unknown key (known: "),
    (SHORT.replace("[ambient]", "[ambiant]"), "ambiant: unknown key (known: "),
    (SHORT + AXIS.replace("duration =", "duraton ="), "axis[0].move[0].duraton: unknown key (known: acceleration, "
                                                      "between, count, duration, dwell, feed, kind)"),
    (SHORT + AXIS.replace('kind = "reciprocate"', 'knd = "reciprocate"'), "axis[0].move[0].knd: unknown key"),
    (SHORT + PROBING.replace("datums", "datum"), "probing.datum: unknown key (known: datums, times)"),
    (SHORT + '\n[[c_axis]]\nsped = "10 rpm"\nduration = "10 min"\n', "c_axis[0].sped: unknown key"),
    # without a misspelling, the missing key is reported as before
    (SHORT.replace('speed = "6000 rpm"\n', ""), "spindle[0].speed: missing"),
    (SHORT + AXIS.replace('duration = "10 min"\n', ""), "axis[0].move[0].duration: give exactly one of duration "
                                                         "and count"),
    # values described in the user's terms, the number's problem named, a plausible unit hinted
    (SHORT.replace('"60 s"', "1979-05-27"), "sample_interval: got a TOML date (1979-05-27); expected a quantity "
                                            "with a unit such as '10 s'"),
    (SHORT.replace('"60 s"', "true"), "sample_interval: got the boolean true; expected a quantity"),
    (SHORT.replace('"60 s"', '"0x3c s"'), "sample_interval: '0x3c s': '0x3c' is not a decimal number"),
    (SHORT.replace('"60 s"', '"6_0 s"'), "sample_interval: '6_0 s': '6_0' is not a decimal number"),
    (SHORT.replace('"20 degC"', "nan"), "ambient.temperature: nan is not a finite number"),
    (SHORT.replace('"20 degC"', '"nan degC"'), "ambient.temperature: 'nan degC': 'nan' is not a finite number"),
    (SHORT + PROBING.replace('["150 mm", "100 mm", "100 mm"]', "[150, 100, 100]"),
     "probing.datums: 150 has no unit; write it like '150 mm'"),
])
def test_scenario_errors_name_the_misspelled_key_and_speak_of_the_value(text, message):
    import tomllib

    from twin.errors import InputError
    from twin.scenario import scenario_from_dict

    with pytest.raises(InputError) as err:
        scenario_from_dict(tomllib.loads(text), "s.toml")
    assert str(err.value).startswith(f"s.toml: {message}"), str(err.value)
    assert "datetime" not in str(err.value) and "True" not in str(err.value)


def test_every_key_a_reader_reads_is_declared_known(monkeypatch):
    """The keys a table reader declares (``known=``, checked before a key is reported missing)
    hold every key it reads, over the bundled scenarios and dataset specs and the moves above: a
    key added to a reader but not to its ``known`` would be called unknown in that message."""
    import tomllib

    from twin.dataset.spec import bundled_specs, load_spec, spec_path
    from twin.io.table_reader import TableReader
    from twin.scenario import available, scenario_from_dict

    seen = []

    def finish(self, *args, _finish=TableReader.finish, **kw):
        assert self.known is None or self.used <= self.known, (self.prefix, self.used - self.known)
        seen.append(self.prefix)
        return _finish(self, *args, **kw)
    monkeypatch.setattr(TableReader, "finish", finish)
    for name in available():
        load_scenario(name)
    for name in bundled_specs():
        load_spec(spec_path(name))
    for text in (AXIS, AXIS.replace('kind = "reciprocate"', 'kind = "hold"\nposition = "0 mm"').split("between")[0]
                 + 'duration = "10 min"\n'):
        scenario_from_dict(tomllib.loads(SHORT + text + PROBING), "s.toml")
    assert {"", "ambient.", "spindle[0].", "axis[0].", "axis[0].move[0].", "probing.", "c_axis[0]."} <= set(seen)


def test_an_output_never_replaces_the_room_record_a_scenario_reads(capsys, tmp_path):
    """A scenario's `ambient.file` (kind = "csv") is an input of the command as much as the
    scenario: `-o` naming it is refused before the run and the record is unchanged."""
    room = tmp_path / "air.nc"
    room.write_text("time [min],air [degC]\n0,20\n30,21\n")
    scenario = tmp_path / "room.toml"
    scenario.write_text('name = "room"\nsample_interval = "60 s"\n[ambient]\nkind = "csv"\nfile = "air.nc"\n'
                        '[[spindle]]\nspeed = "0 rpm"\nduration = "10 min"\n')
    err = _error(capsys, ["simulate", "cframe-vmc", str(scenario), "-o", str(room), "--mesh", "coarse"])
    assert "never replaces an input" in err and "ambient.file" in err
    assert room.read_text().startswith("time [min],air [degC]")


def test_unwritable_output(capsys, tmp_path):
    err = _error(capsys, ["simulate", "cframe-vmc", "spindle-duty-cycle", "-o", str(tmp_path / "nope" / "r.nc")])
    assert "output" in err


def test_simulate_and_plot_end_to_end(capsys, tmp_path):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SHORT)
    out = tmp_path / "r.nc"
    assert main(["simulate", "cframe-vmc", str(scenario), "-o", str(out), "--mesh", "coarse",
                 "--effects=-floor", "--set", "spindle_motor.power=100 W", "--seed", "7",
                 "--field", str(tmp_path / "hot.vtu")]) == 0
    ds = xr.load_dataset(out)
    assert ds.attrs["effects"].split(",") == ["spindle_bearings", "spindle_motor", "ambient_convection",
                                              "spindle_forced_convection", "stratified_swing", "door_stream"]
    assert '"power": "100 W"' in ds.attrs["parameters"] and ds.attrs["seed"] == 7
    for name in ("time", "temperature", "probe", "drift", "tilt", "heat_power"):
        assert "units" in ds[name].attrs
    assert ds.heat_power.sel(effect="spindle_motor").values[0] == pytest.approx(100 * 6000 / 9000)
    # the result carries its energy balance (first law over the run: sources + convection = stored)
    a = ds.attrs
    assert a["energy_sources_J"] > 0 and a["energy_closure"] < 1e-9
    assert a["energy_sources_J"] + a["energy_convection_J"] == pytest.approx(a["energy_stored_J"], rel=1e-9)
    import meshio

    field = meshio.read(tmp_path / "hot.vtu")
    assert len(field.cells_dict["hexahedron"]) == ds.attrs["mesh_cells"]
    # the field's instant, the VTK field data TimeValue [s]: one of the run's samples, after the start
    (when,) = field.field_data["TimeValue"].tolist()
    assert when > 0 and when in ds.time.values.tolist()
    # the file names its parts: field data part:NAME = the index the cell data part gives it
    names = {k.removeprefix("part:"): int(v[0]) for k, v in field.field_data.items() if k.startswith("part:")}
    assert sorted(names.values()) == list(range(len(names))) and {"bed", "column", "test_bar"} <= set(names)
    assert names["test_bar"] in set(field.cell_data["part"][0].tolist())
    assert field.point_data["temperature_degC"].max() > 20.5
    png = tmp_path / "r.png"
    assert main(["plot", str(out), "-o", str(png)]) == 0 and png.stat().st_size > 10000
    assert [f for f in os.listdir(tmp_path) if f.startswith(".twin-")] == []


@pytest.mark.parametrize("suffix", [".pdf", ".svg", ".eps", ".ps", ".svgz"])
def test_a_figure_is_the_same_bytes_each_time_it_is_written(tmp_path, suffix):
    """The same figure written twice gives the same file: no time of writing (PDF/EPS
    CreationDate, SVG date) and no random SVG ids (a fixed hash salt)."""
    import time

    from twin.plotting import _pyplot, save_figure

    plt = _pyplot()
    written = []
    for k in range(2):
        fig, ax = plt.subplots()
        ax.plot([0, 1, 2], [0, 1, 0.5], label="drift")
        ax.legend()
        path = tmp_path / f"figure{k}{suffix}"          # another name too: none is written into the file
        save_figure(fig, path)
        plt.close(fig)
        written.append(path.read_bytes())
        if k == 0:
            time.sleep(1.1)     # a time stamp has seconds
    assert written[0] == written[1]


def test_the_demo_never_writes_over_its_effects_file(capsys, tmp_path):
    """`twin demo -o OUT --effects-file OUT/measurement/spindle-test.toml`: the effects file is an
    input, refused as an output before the run (exit 2), left unchanged."""
    effects = tmp_path / "out" / "measurement" / "spindle-test.toml"
    effects.parent.mkdir(parents=True)
    text = '[effects.pump]\nkind = "heat_source"\nregion = "saddle"\npower = "80 W"\n'
    effects.write_text(text)
    err = _error(capsys, ["demo", "-o", str(tmp_path / "out"), "--mesh", "coarse", "--effects-file", str(effects)])
    assert "never replaces an input" in err and effects.read_text() == text


def test_learn_refuses_the_time_column_as_target_and_segments_without_scores(capsys, tmp_path):
    """`twin learn --target time` (the time column) and `--segments` so many that a segment holds
    fewer than three rows (NSE and R undefined: printed NaN) are each one error, exit 2."""
    from tests.fuzz_files import table_csv

    (tmp_path / "train.csv").write_text(table_csv())
    (tmp_path / "test.csv").write_text(table_csv(seed=1))
    common = ["learn", "--train", str(tmp_path / "train.csv"), "--test", str(tmp_path / "test.csv"), "--learner", "mlr"]
    assert "--target" in _error(capsys, common + ["--target", "time"])
    err = _error(capsys, common + ["--target", "drift_z", "--segments", "30", "-o", str(tmp_path / "s.csv")])
    assert "--segments" in err and "at least 3" in err and not (tmp_path / "s.csv").exists()
    err = _error(capsys, common + ["--target", "drift_z", "--interval", "400 s"])
    assert "--interval" in err and "keeps 1 row(s)" in err
    assert main(common + ["--target", "drift_z", "--segments", "4"]) == 0
    assert "nan" not in capsys.readouterr().out.lower()


def test_a_command_builds_only_its_own_parser():
    """``twin simulate ...`` loads no registered command's module (the learners import
    scikit-learn); ``twin --help`` and an unknown word build every command, so both list them all."""
    import subprocess
    import sys
    probe = ("import sys; from twin.cli import build_parser; p = build_parser({argv!r}); "
             "print(sorted(p._subparsers._group_actions[0].choices), 'sklearn' in sys.modules)")
    run = lambda argv: subprocess.run([sys.executable, "-c", probe.format(argv=argv)], capture_output=True,
                                      text=True, check=True).stdout.strip()
    assert run(["simulate", "cframe-vmc"]) == "['simulate'] False"
    assert run(["learn", "x.csv"]) == "['learn'] True"
    everything = "['compare', 'dataset', 'demo', 'diagnose', 'frames', 'learn', 'list', 'plot', 'report', 'simulate'] True"
    assert run(["--help"]) == everything and run(["simulat"]) == everything


def test_dataset_takes_a_bundled_spec_by_name(capsys, tmp_path, monkeypatch):
    """``twin dataset spindle-ambient-100`` works from any folder, as a scenario name does; an
    unknown name is one error listing the bundled specs; ``twin list scenarios`` names them."""
    monkeypatch.chdir(tmp_path)
    assert main(["dataset", "spindle-ambient-100", "-o", "sa", "--dry-run", "--jobs", "1"]) == 0
    assert "100 case" in capsys.readouterr().out and not (tmp_path / "sa").exists()
    assert main(["dataset", "spindle-ambient-10", "-o", "sa", "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("error: spindle-ambient-10: spec: no such dataset spec; bundled: spindle-ambient-100 "
                   "(or a path to a .toml file)")
    assert main(["list", "scenarios"]) == 0
    assert "spindle-ambient-100 (dataset spec, twin dataset spindle-ambient-100 -o DIR)" in capsys.readouterr().out


def test_a_file_named_like_a_bundled_scenario_is_ambiguous(tmp_path, monkeypatch, capsys):
    """A file in the working folder named ``spindle-duty-cycle`` shadowed the bundled scenario without
    a word; now the bare name is refused (which was meant cannot be told) and ``./NAME`` reads the file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "spindle-duty-cycle").write_text(SHORT, encoding="utf-8")
    err = _error(capsys, ["simulate", "cframe-vmc", "spindle-duty-cycle", "-o", "x.nc", "--mesh", "coarse"])
    assert "both a bundled scenario and a file here" in err and "./spindle-duty-cycle" in err
    assert not (tmp_path / "x.nc").exists()
    local = load_scenario("./spindle-duty-cycle")
    assert local.duration == load_scenario(tmp_path / "spindle-duty-cycle").duration == 1800.0   # the file's 30 min
    (tmp_path / "spindle-duty-cycle").unlink()
    assert load_scenario("spindle-duty-cycle").duration > local.duration        # no file: the bundled one


def test_a_bundled_scenario_is_recorded_by_name_not_by_its_install_path(tmp_path, monkeypatch):
    """A result's ``scenario_source`` is ``bundled:NAME`` for a scenario shipped with the package
    (its absolute install path made the same run's bytes differ between installs), and a user's
    file as typed, even when it is a byte copy of a bundled one."""
    from twin.scenario import recorded_source, scenario_path
    monkeypatch.chdir(tmp_path)
    bundled = load_scenario("spindle-duty-cycle")
    assert recorded_source(bundled.source) == "bundled:spindle-duty-cycle"
    (tmp_path / "mine.toml").write_bytes(scenario_path("spindle-duty-cycle").read_bytes())
    assert recorded_source(load_scenario("mine.toml").source) == "mine.toml"
    assert recorded_source("test.toml") == "test.toml"          # not a file: as given


@pytest.mark.parametrize("effects", ["+floor_lag,,-floor", "spindle_motor,", ",spindle_motor"])
def test_an_empty_effect_between_commas_is_refused(effects, tmp_path, capsys):
    """``--effects +a,,-b`` dropped the empty item without a word (an effect left out by mistake)."""
    (tmp_path / "s.toml").write_text(SHORT, encoding="utf-8")
    err = _error(capsys, ["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(tmp_path / "x.nc"),
                          "--mesh", "coarse", "--effects", effects])
    assert err == f"error: command line: --effects: an empty effect in {effects!r}: write the effects " \
                  "comma-separated, each once"
