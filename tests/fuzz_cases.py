"""The bad inputs of the fuzz suite (``tests/test_fuzz_inputs.py``), generated from tables.

Each :class:`tests.fuzz_files.Case` is one command line run in a fresh folder holding good copies
of the files it needs, one thing made bad, and the error it must give: the source (a path, ``{d}``
standing for the case's folder, or ``command line``) and a part of the field. The bad paths of
every file argument come from ``tests/fuzz_files.py``; this module adds the bad contents and
options. Add a command, an option or a file format by adding rows:

* :data:`SCENARIO_EDITS`, :data:`MAPPING_EDITS`, :data:`CSV_EDITS`, :data:`RESULT_EDITS`,
  :data:`TABLE_EDITS` - bad contents of each file kind, each run through the commands that read it;
* :data:`OPTION_CASES` - bad option values and repeated options, per command.

Later issues add theirs as rows: dataset specs (a ``twin dataset`` row in
``fuzz_files.INPUTS`` and a table of spec edits here), axis scenarios (more
:data:`SCENARIO_EDITS`), camera settings (:data:`OPTION_CASES`) and custom effects
(``--effects-file``: an ``INPUTS`` row and its edits).
"""

from __future__ import annotations

import os

import numpy as np

from tests.fuzz_files import (CLI, COMPARE, COMPARE_GANTRY, COMPARE_NC, DEMO, DIAGNOSE, EFFECTS_FILE, FOLDERS,
                              GANTRY_MAPPING, INPUTS, LEARN, MAPPING, OUTPUTS, REPORT, ROOM_SCENARIO, gantry_csv,
                              PLOT, SCENARIO, SIM, TEXT, Case, bad_input_paths, bad_output_folders,
                              bad_output_paths, measurement_csv, netcdf_bytes, result_dataset, swap, table_csv)


# ------------------------------------------------------------------------- bad scenario files
def _sc(old: str, new: str, count: int = 1) -> str:
    assert old in SCENARIO, old
    return SCENARIO.replace(old, new, count)


AMBIENT = '[ambient]\ntemperature = "20 degC"'
DAILY = '[ambient]\nkind = "daily"\nmean = "20 degC"\namplitude = "3 K"'
TABLE = '[ambient]\nkind = "table"\ntimes = ["0 h", "1 h"]\ntemperatures = ["20 degC", "21 degC"]'
EVENT = '\n[[ambient.events]]\nstart = "5 min"\nchange = "-9 K"\nfall = "30 min"\n'
SPEED = 'speed = "6000 rpm"'
DURATION = 'duration = "10 min"'
INTERVAL = 'sample_interval = "60 s"'

C_AXIS = '\n[[c_axis]]\nspeed = "2500 rpm"\nduration = "10 min"\non = "10 s"\ndwell = "10 s"\n'


def _c_axis(speed: str = 'speed = "2500 rpm"', duration: str = 'duration = "10 min"') -> str:
    """A [[c_axis]] step with ``speed`` and ``duration`` lines in place of the good ones."""
    return C_AXIS.replace('speed = "2500 rpm"', speed).replace('duration = "10 min"', duration)


# (id, scenario text, field)
SCENARIO_EDITS = [
    ("ambient-below-absolute-zero", _sc('"20 degC"', '"-300 degC"'), "ambient.temperature"),
    ("ambient-1e6-degC", _sc('"20 degC"', '"1e6 degC"'), "ambient.temperature"),
    ("ambient-implausible", _sc('"20 degC"', '"85 degC"'), "ambient.temperature"),
    ("ambient-no-unit", _sc('"20 degC"', '"20"'), "ambient.temperature"),
    ("ambient-kelvin-unit", _sc('"20 degC"', '"293 K"'), "ambient.temperature"),
    ("ambient-nan", _sc('"20 degC"', '"nan degC"'), "ambient.temperature"),
    ("ambient-overflow", _sc('"20 degC"', '"1e400 degC"'), "ambient.temperature"),
    ("ambient-number", _sc('"20 degC"', '20'), "ambient.temperature"),
    ("ambient-bool", _sc('"20 degC"', 'true'), "ambient.temperature"),
    ("initial-below-absolute-zero", _sc(INTERVAL, INTERVAL + '\ninitial_temperature = "-300 degC"'), "initial_temperature"),
    ("initial-1e6", _sc(INTERVAL, INTERVAL + '\ninitial_temperature = "1e6 degC"'), "initial_temperature"),
    ("initial-no-unit", _sc(INTERVAL, INTERVAL + '\ninitial_temperature = "20"'), "initial_temperature"),
    ("daily-negative-amplitude", _sc(AMBIENT, DAILY.replace('"3 K"', '"-3 K"')), "ambient.amplitude"),
    ("daily-huge-amplitude", _sc(AMBIENT, DAILY.replace('"3 K"', '"300 K"')), "ambient.amplitude"),
    ("daily-mean-below-zero", _sc(AMBIENT, DAILY.replace('"20 degC"', '"-300 degC"')), "ambient.mean"),
    ("daily-missing-amplitude", _sc(AMBIENT, DAILY.replace('\namplitude = "3 K"', '')), "ambient.amplitude"),
    ("daily-amplitude-in-degC", _sc(AMBIENT, DAILY.replace('"3 K"', '"3 degC"')), "ambient.amplitude"),
    ("table-times-decrease", _sc(AMBIENT, TABLE.replace('"0 h", "1 h"', '"1 h", "0 h"')), "ambient.times"),
    ("table-length-mismatch", _sc(AMBIENT, TABLE.replace('"20 degC", "21 degC"', '"20 degC"')), "ambient.temperatures"),
    ("table-below-absolute-zero", _sc(AMBIENT, TABLE.replace('"21 degC"', '"-300 degC"')), "ambient.temperatures"),
    ("table-time-no-unit", _sc(AMBIENT, TABLE.replace('"1 h"', '"1"')), "ambient.times[1]"),
    ("table-times-not-a-list", _sc(AMBIENT, TABLE.replace('["0 h", "1 h"]', '"0 h"')), "ambient.times"),
    ("ambient-unknown-kind", _sc(AMBIENT, '[ambient]\nkind = "weekly"'), "ambient.kind"),
    ("ambient-unknown-key", _sc(AMBIENT, AMBIENT + '\ncolour = "red"'), "ambient.colour"),
    ("ambient-missing", _sc(AMBIENT + "\n", ""), "ambient"),
    ("ambient-not-a-table", _sc(AMBIENT + "\n", "").replace(INTERVAL, INTERVAL + '\nambient = "20 degC"'), "ambient"),
    ("speed-1e6-rpm", _sc(SPEED, 'speed = "1e6 rpm"'), "spindle[0].speed"),
    ("speed-1e300-krpm", _sc(SPEED, 'speed = "1e300 krpm"'), "spindle[0].speed"),
    ("speed-beyond-machine", _sc(SPEED, 'speed = "9001 rpm"'), "spindle[0].speed"),
    ("speed-negative", _sc(SPEED, 'speed = "-5 rpm"'), "spindle[0].speed"),
    ("speed-no-unit", _sc(SPEED, 'speed = "6000"'), "spindle[0].speed"),
    ("speed-wrong-unit", _sc(SPEED, 'speed = "6000 W"'), "spindle[0].speed"),
    ("speed-inf", _sc(SPEED, 'speed = "inf rpm"'), "spindle[0].speed"),
    ("speed-missing", _sc(SPEED + "\n", ""), "spindle[0].speed"),
    ("duration-1e300-s", _sc(DURATION, 'duration = "1e300 s"'), "spindle"),
    ("duration-zero", _sc(DURATION, 'duration = "0 s"'), "spindle[0].duration"),
    ("duration-negative", _sc(DURATION, 'duration = "-10 min"'), "spindle[0].duration"),
    ("duration-not-a-multiple", _sc(DURATION, 'duration = "90 s"'), "spindle[0].duration"),
    ("duration-missing", _sc(DURATION + "\n", ""), "spindle[0].duration"),
    ("interval-1-ns", _sc(INTERVAL, 'sample_interval = "1e-9 s"'), "sample_interval"),
    ("interval-zero", _sc(INTERVAL, 'sample_interval = "0 s"'), "sample_interval"),
    ("interval-negative", _sc(INTERVAL, 'sample_interval = "-1 s"'), "sample_interval"),
    ("interval-no-unit", _sc(INTERVAL, 'sample_interval = "60"'), "sample_interval"),
    ("unknown-top-key", _sc("sample_interval", "sampel_interval"), "sampel_interval"),
    ("unknown-step-key", _sc(SPEED, SPEED + '\nfeed = "1 m/min"'), "spindle[0].feed"),
    ("spindle-missing", SCENARIO.split("[[spindle]]")[0], "spindle"),
    ("spindle-not-steps", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + "\nspindle = 3"), "spindle"),
    ("spindle-empty", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + "\nspindle = []"), "spindle"),
    ("spindle-step-not-a-table", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + '\nspindle = ["a"]'),
     "spindle[0]"),
    ("event-missing-change", _sc(AMBIENT, AMBIENT + EVENT.replace('change = "-9 K"\n', '')), "ambient.events[0].change"),
    ("event-negative-fall", _sc(AMBIENT, AMBIENT + EVENT.replace('"30 min"', '"-30 min"')), "ambient.events[0].fall"),
    ("event-change-in-degC", _sc(AMBIENT, AMBIENT + EVENT.replace('"-9 K"', '"-9 degC"')), "ambient.events[0].change"),
    ("event-door-not-bool", _sc(AMBIENT, AMBIENT + EVENT + 'door = "yes"\n'), "ambient.events[0].door"),
    ("event-unknown-key", _sc(AMBIENT, AMBIENT + EVENT + 'colour = "red"\n'), "ambient.events[0].colour"),
    ("event-below-absolute-zero", _sc(AMBIENT, AMBIENT + EVENT.replace('"-9 K"', '"-400 K"')), "ambient.events"),
    ("events-not-tables", _sc(AMBIENT, AMBIENT + '\nevents = 3'), "ambient.events"),
    ("csv-file-not-a-string", _sc(AMBIENT, '[ambient]\nkind = "csv"\nfile = 3'), "ambient.file"),
    ("csv-file-missing-key", _sc(AMBIENT, '[ambient]\nkind = "csv"'), "ambient.file"),
    ("malformed-toml", SCENARIO.replace("[ambient]", "[ambient"), "toml"),
    ("duplicate-key", _sc(INTERVAL, INTERVAL + "\n" + INTERVAL), "toml"),
    # the C axis (twin.rotary): parsed before any machine is asked; cframe-vmc has no C axis
    ("c-axis-speed-no-unit", SCENARIO + _c_axis('speed = "2500"'), "c_axis[0].speed"),
    ("c-axis-speed-negative", SCENARIO + _c_axis('speed = "-5 rpm"'), "c_axis[0].speed"),
    ("c-axis-speed-missing", SCENARIO + C_AXIS.replace('speed = "2500 rpm"\n', ""), "c_axis[0].speed"),
    ("c-axis-duration-zero", SCENARIO + _c_axis(duration='duration = "0 s"'), "c_axis[0].duration"),
    ("c-axis-duration-not-a-multiple", SCENARIO + _c_axis(duration='duration = "90 s"'), "c_axis[0].duration"),
    ("c-axis-outlasts-run", SCENARIO + _c_axis(duration='duration = "1 h"'), "c_axis"),
    ("c-axis-on-without-dwell", SCENARIO + C_AXIS.replace('dwell = "10 s"\n', ""), "c_axis[0].dwell"),
    ("c-axis-dwell-negative", SCENARIO + C_AXIS.replace('dwell = "10 s"', 'dwell = "-10 s"'), "c_axis[0].dwell"),
    ("c-axis-on-zero", SCENARIO + C_AXIS.replace('on = "10 s"', 'on = "0 s"'), "c_axis[0].on"),
    ("c-axis-unknown-key", SCENARIO + C_AXIS + 'feed = "1 m/min"\n', "c_axis[0].feed"),
    ("c-axis-not-steps", SCENARIO.replace(INTERVAL, INTERVAL + "\nc_axis = 3"), "c_axis"),
    ("c-axis-on-a-machine-without-one", SCENARIO + C_AXIS, "c_axis"),
]

# axis motion ([[axis]], twin.motion) and the interferometer: appended to the good scenario
AXIS = ('\n[[axis]]\nname = "Y"\n[[axis.move]]\nkind = "reciprocate"\nbetween = ["0 mm", "280 mm"]\n'
        'feed = "20 mm/s"\nacceleration = "10 mm/s2"\nduration = "30 min"\n')
LASER = '\n[interferometer]\naxis = "Y"\nruns = ["0 min", "10 min"]\n'
PROBE = '\n[probing]\ntimes = ["0 min", "10 min"]\ndatums = [["100 mm", "100 mm", "50 mm"]]\n'


def _ax(old: str, new: str, tail: str = "") -> str:
    assert old in AXIS, old
    return SCENARIO + AXIS.replace(old, new) + tail


SCENARIO_EDITS += [
    ("axis-feed-zero", _ax('"20 mm/s"', '"0 mm/s"'), "axis[0].move[0].feed"),
    ("axis-feed-negative", _ax('"20 mm/s"', '"-20 mm/s"'), "axis[0].move[0].feed"),
    ("axis-feed-no-unit", _ax('"20 mm/s"', '"20"'), "axis[0].move[0].feed"),
    ("axis-feed-wrong-unit", _ax('"20 mm/s"', '"20 mm"'), "axis[0].move[0].feed"),
    ("axis-acceleration-zero", _ax('"10 mm/s2"', '"0 mm/s2"'), "axis[0].move[0].acceleration"),
    ("axis-unknown", _ax('name = "Y"', 'name = "W"'), "axis[0].name"),
    ("axis-outside-travel", _ax('"280 mm"]', '"500 mm"]'), "axis[0].move"),
    ("axis-longer-than-scenario", _ax('"30 min"', '"40 min"'), "axis[0].move"),
    ("axis-unknown-kind", _ax('"reciprocate"', '"wobble"'), "axis[0].move[0].kind"),
    ("axis-unknown-key", _ax('duration', 'speed = "1 mm/s"\nduration'), "axis[0].move[0].speed"),
    ("axis-duration-and-count", _ax('duration', 'count = 3\nduration'), "axis[0].move[0].duration"),
    ("axis-count-not-whole", _ax('duration = "30 min"', 'count = 2.5'), "axis[0].move[0].count"),
    ("axis-one-end", _ax('["0 mm", "280 mm"]', '["0 mm"]'), "axis[0].move[0].between"),
    ("axis-move-elsewhere", _ax('"30 min"', '"20 min"', '[[axis.move]]\nkind = "hold"\nposition = "100 mm"\n'
                                                      'duration = "1 min"\n'), "axis[0].move[1]"),
    ("axis-twice", SCENARIO + AXIS + AXIS, "axis[1].name"),
    ("interferometer-off-grid", _ax("", "", LASER.replace('"10 min"', '"90 s"')), "interferometer.runs"),
    ("interferometer-not-cold-first", _ax("", "", LASER.replace('"0 min", ', '')), "interferometer.runs"),
    ("interferometer-unknown-axis", _ax("", "", LASER.replace('axis = "Y"', 'axis = "W"')), "interferometer.axis"),
    ("probing-not-cold-first", _ax("", "", PROBE.replace('"0 min", ', '')), "probing.times"),
    ("probing-off-grid", _ax("", "", PROBE.replace('"10 min"', '"90 s"')), "probing.times"),
    ("probing-datum-outside-travel", _ax("", "", PROBE.replace('[["100 mm"', '[["600 mm"')), "probing.datums[0]"),
    ("probing-datum-two-coordinates", _ax("", "", PROBE.replace(', "50 mm"]]', ']]')), "probing.datums"),
    ("probing-datum-no-unit", _ax("", "", PROBE.replace('"50 mm"]]', '"50"]]')), "probing.datums"),
    ("probing-unknown-key", _ax("", "", PROBE + 'stylus = "50 mm"\n'), "probing.stylus"),
]

# the gantry's linear axes (geometries.gantry_ram.axes: X 0-2500, Y 0-1200, Z 0-700 mm, closed loop, no
# scale mounting modelled): run through `twin simulate gantry-ram`, a good 3000 rpm scenario plus one Z move
GANTRY_SCENARIO = SCENARIO.replace('"6000 rpm"', '"3000 rpm"')
GANTRY_AXIS = ('\n[[axis]]\nname = "Z"\n[[axis.move]]\nkind = "reciprocate"\nbetween = ["0 mm", "700 mm"]\n'
               'feed = "70 m/min"\nacceleration = "3 m/s2"\ndwell = "1 s"\nduration = "20 min"\n')


def _gz(old: str, new: str, tail: str = "") -> str:
    assert old in GANTRY_AXIS, old
    return GANTRY_SCENARIO + GANTRY_AXIS.replace(old, new) + tail


GANTRY_AXIS_EDITS = [
    ("z-beyond-travel", _gz('"700 mm"]', '"800 mm"]'), "axis[0].move"),
    ("z-below-travel", _gz('["0 mm"', '["-10 mm"'), "axis[0].move"),
    ("x-beyond-travel", _gz('name = "Z"', 'name = "X"').replace('"700 mm"]', '"2600 mm"]'), "axis[0].move"),
    ("y-beyond-travel", _gz('name = "Z"', 'name = "Y"').replace('"700 mm"]', '"1300 mm"]'), "axis[0].move"),
    ("c-as-linear-axis", _gz('name = "Z"', 'name = "C"'), "axis[0].name"),
    ("z-feed-no-unit", _gz('"70 m/min"', '"70"'), "axis[0].move[0].feed"),
    ("z-interferometer-scale-not-modelled", _gz("", "", LASER.replace('axis = "Y"', 'axis = "Z"')),
     "interferometer.axis"),
]

# the scenario edits also run through compare/diagnose --scenario (a sample: they share the reader)
SCENARIO_EDITS_VIA_MEASUREMENT = ["ambient-below-absolute-zero", "speed-beyond-machine", "speed-1e300-krpm",
                                  "interval-1-ns", "duration-1e300-s", "malformed-toml", "unknown-top-key"]

# ------------------------------------------------------------- bad room-air records (CSV ambient)
ROOM = "{d}/room.csv"
SIM_ROOM = swap(SIM, "{d}/short.toml", "{d}/room.toml")
SIM_GANTRY = swap(SIM, "cframe-vmc", "gantry-ram")


def _room(rows: str) -> str:
    return "time [min],air [degC]\n" + rows


# (id, files to write, source, field): the scenario room.toml names room.csv
ROOM_EDITS = [
    ("no-unit", {"room.csv": "time,air\n0,20\n30,21\n"}, ROOM, "header"),
    ("three-columns", {"room.csv": "time [min],air [degC],x [degC]\n0,20,1\n30,21,1\n"}, ROOM, "header"),
    ("unit-kelvin", {"room.csv": "time [min],air [K]\n0,293\n30,294\n"}, ROOM, "air"),
    ("unit-wrong-kind", {"room.csv": "time [degC],air [degC]\n0,20\n30,21\n"}, ROOM, "time"),
    ("nan", {"room.csv": _room("0,20\n10,nan\n30,21\n")}, ROOM, "air"),
    ("inf", {"room.csv": _room("0,20\n10,inf\n30,21\n")}, ROOM, "air"),
    ("empty-cell", {"room.csv": _room("0,20\n10,\n30,21\n")}, ROOM, "air"),
    ("not-a-number", {"room.csv": _room("0,20\n10,warm\n30,21\n")}, ROOM, "air"),
    ("below-absolute-zero", {"room.csv": _room("0,20\n10,-300\n30,21\n")}, ROOM, "air"),
    ("implausible-air", {"room.csv": _room("0,20\n10,95\n30,21\n")}, ROOM, "air"),
    ("times-not-increasing", {"room.csv": _room("0,20\n10,20\n10,21\n30,21\n")}, ROOM, "time"),
    ("times-decrease", {"room.csv": _room("0,20\n20,20\n10,21\n30,21\n")}, ROOM, "time"),
    ("short-row", {"room.csv": _room("0,20\n10\n30,21\n")}, ROOM, "line 3"),
    ("one-row", {"room.csv": _room("0,20\n")}, ROOM, "ambient.file"),
    ("ends-before-the-scenario", {"room.csv": _room("0,20\n20,21\n")}, "{d}/room.toml", "ambient.file"),
    ("latin-1", {"room.csv": "time [min],air [\xb0C]\n0,20\n30,21\n".encode("latin-1")}, ROOM, "ambient.file"),
    ("binary", {"room.csv": bytes(range(256)) * 4}, ROOM, "ambient.file"),
    ("empty", {"room.csv": b""}, ROOM, "ambient.file"),
    ("missing", {"room.csv": None}, ROOM, "ambient.file"),
]


def _room_folder(d):
    os.remove(os.path.join(d, "room.csv"))
    os.mkdir(os.path.join(d, "room.csv"))


# ------------------------------------------------------------------ bad measurement mappings
def _map(old: str, new: str) -> str:
    assert old in MAPPING, old
    return MAPPING.replace(old, new, 1)


MOTOR = '[columns.T_motor]\nrole = "temperature"\nsite = "motor"\nunit = "degC"'


def _at(x, y, z, part=None):
    return MOTOR.replace('site = "motor"', f'x = "{x}"\ny = "{y}"\nz = "{z}"' + (f'\npart = "{part}"' if part else ""))


# (id, mapping text, field); the source is the mapping
MAPPING_EDITS = [
    ("unknown-machine", _map('"cframe-vmc"', '"vmc-9000"'), "machine"),
    ("machine-not-a-name", _map('"cframe-vmc"', '3'), "machine"),
    ("unknown-top-key", "colour = 'red'\n" + MAPPING, "colour"),
    ("no-columns", 'machine = "cframe-vmc"\n', "columns"),
    ("unknown-role", _map('role = "spindle_speed"', 'role = "speeed"'), "columns.spindle_rpm.role"),
    ("unit-missing", _map('role = "time"\nunit = "s"', 'role = "time"'), "columns.t_s.unit"),
    ("unit-wrong", _map(MOTOR, MOTOR.replace('"degC"', '"rpm"')), "columns.T_motor.unit"),
    ("unit-kelvin", _map(MOTOR, MOTOR.replace('"degC"', '"K"')), "columns.T_motor.unit"),
    ("unit-not-a-string", _map(MOTOR, MOTOR.replace('"degC"', '1')), "columns.T_motor.unit"),
    ("unknown-column-key", _map(MOTOR, MOTOR + '\ncolour = "red"'), "columns.T_motor.colour"),
    ("site-not-a-sensor-site", _map('site = "motor"', 'site = "tool"'), "columns.T_motor.site"),
    ("site-unknown", _map('site = "motor"', 'site = "nowhere"'), "columns.T_motor.site"),
    ("position-outside-machine", _map(MOTOR, _at("5 m", "5 m", "5 m")), "columns.T_motor"),
    ("position-unknown-part", _map(MOTOR, _at("0 m", "0 m", "0.2 m", "plinth")), "columns.T_motor"),
    ("position-not-on-part", _map(MOTOR, _at("0 m", "0 m", "0.2 m", "motor")), "columns.T_motor"),
    ("position-missing-z", _map(MOTOR, _at("0 m", "0 m", "0.2 m").replace('\nz = "0.2 m"', "")), "columns.T_motor.z"),
    ("position-no-unit", _map(MOTOR, _at("0", "0 m", "0.2 m")), "columns.T_motor"),
    ("probe-unknown", _map('probe = "X1"', 'probe = "W1"'), "columns.probe_X1_um.probe"),
    ("probe-twice", _map('probe = "X2"', 'probe = "X1"'), "columns.probe_X2_um.probe"),
    ("column-not-in-csv", MAPPING + '[columns.ghost]\nrole = "temperature"\nsite = "motor"\nunit = "degC"\n',
     "columns.ghost"),
    ("second-time-column", _map('role = "ambient_temperature"\nunit = "degC"', 'role = "time"\nunit = "s"'),
     "columns.room_degC"),
    ("column-not-a-table", _map('[columns.t_s]\nrole = "time"\nunit = "s"', '[columns]\nt_s = "time"'), "columns.t_s"),
    ("malformed-toml", MAPPING.replace("[columns.t_s]", "[columns.t_s"), "toml"),
]

# ----------------------------------------------------------------------- bad measurement CSVs
def _set(col: str, value, rows=slice(5, 6)):
    def edit(cols):
        a = np.array(cols[col], dtype=object)
        a[rows] = value
        cols[col] = a
    return edit


def _add(col: str, delta: float):
    def edit(cols):
        cols[col] = cols[col] + delta
    return edit


def _csv(edit) -> str:
    return measurement_csv(edit)


def _lines(fn) -> str:
    lines = TEXT["m.csv"].splitlines()
    return "\n".join(fn(lines)) + "\n"


# (id, CSV text, field); the source is the CSV
CSV_EDITS = [
    ("speed-negative", _csv(_set("spindle_rpm", -100.0)), "spindle_rpm"),
    ("speed-absurd", _csv(_set("spindle_rpm", 1e6)), "spindle_rpm"),
    ("speed-1e300", _csv(_set("spindle_rpm", 1e300)), "spindle_rpm"),
    ("speed-beyond-machine", _csv(_set("spindle_rpm", 12000.0)), "spindle_rpm"),
    ("temperature-1e300", _csv(_set("T_motor", 1e300)), "T_motor"),
    ("temperature-below-absolute-zero", _csv(_set("T_motor", -300.0)), "T_motor"),
    ("temperature-in-kelvin", _csv(_add("T_motor", 273.15)), "T_motor"),
    ("room-implausible", _csv(_set("room_degC", 85.0)), "room_degC"),
    ("nan-cell", _csv(_set("T_motor", "nan")), "T_motor"),
    ("empty-cell", _csv(_set("T_motor", "")), "T_motor"),
    ("inf-cell", _csv(_set("T_motor", "inf")), "T_motor"),
    ("overflow-cell", _csv(_set("T_motor", "1e400")), "T_motor"),
    ("non-numeric", _csv(_set("T_motor", "warm")), "T_motor"),
    ("time-not-increasing", _csv(_set("t_s", 60.0, slice(5, 6))), "t_s"),
    ("time-gap", _csv(lambda c: c.__setitem__("t_s", np.where(c["t_s"] > 600, c["t_s"] + 3600, c["t_s"]))), "t_s"),
    ("probe-beyond-range", _csv(_set("probe_X1_um", 1e6)), "probe_X1_um"),
    ("one-data-row", _lines(lambda ls: ls[:2]), "file"),
    ("header-only", _lines(lambda ls: ls[:1]), "file"),
    ("ragged-row", _lines(lambda ls: ls[:4] + [ls[4] + ",1"] + ls[5:]), "line 5"),
    ("unmapped-column", _lines(lambda ls: [ls[0] + ",junk"] + [x + ",0" for x in ls[1:]]), "junk"),
    ("duplicate-column", _lines(lambda ls: [ls[0] + ",T_motor"] + [x + ",20" for x in ls[1:]]), "T_motor"),
]
CSV_EDITS_VIA_DIAGNOSE = ["speed-negative", "temperature-in-kelvin", "nan-cell", "time-gap", "duplicate-column"]

# the measurement holds no channel: only time, spindle speed and room air (CSV and mapping)
INPUTS_ONLY_CSV = _lines(lambda ls: [",".join(x.split(",")[:3]) for x in ls])
INPUTS_ONLY_MAPPING = MAPPING.split("[columns.T_")[0]

# --------------------------------------------- bad gantry measurements (lasers, FBG strain, C axis)
def _gmap(old: str, new: str) -> str:
    assert old in GANTRY_MAPPING, old
    return GANTRY_MAPPING.replace(old, new, 1)


# (id, mapping text, field); the source is the mapping
GANTRY_MAPPING_EDITS = [
    ("laser-unknown", _gmap('laser = "Y"', 'laser = "X"'), "columns.laser_Y_um.laser"),
    ("laser-twice", _gmap('laser = "Z"', 'laser = "Y"'), "columns.laser_Z_um.laser"),
    ("laser-unit-not-length", _gmap('laser = "Y"\nunit = "um"', 'laser = "Y"\nunit = "um/m"'), "columns.laser_Y_um.unit"),
    ("laser-on-machine-without", _gmap('"gantry-ram"', '"cframe-vmc"'), "columns.c_rpm"),
    ("gauge-unknown", _gmap('gauge = "FBG-1"', 'gauge = "FBG-9"'), "columns.FBG-1_comp.gauge"),
    ("gauge-twice", _gmap('gauge = "FBG-4"\nreading = "compensated"', 'gauge = "FBG-1"\nreading = "compensated"'),
     "columns.FBG-4_comp.gauge"),
    ("reading-missing", _gmap('reading = "compensated"\n', ''), "columns.FBG-1_comp.reading"),
    ("reading-unknown", _gmap('reading = "compensated"', 'reading = "corrected"'), "columns.FBG-1_comp.reading"),
    ("strain-unit-length", _gmap('reading = "compensated"\nunit = "um/m"', 'reading = "compensated"\nunit = "um"'),
     "columns.FBG-1_comp.unit"),
    ("raw-and-compensated-differ", _gmap('gauge = "FBG-4"\nreading = "raw"', 'gauge = "FBG-5"\nreading = "raw"'),
     "columns"),
    ("strain-unknown-key", _gmap('reading = "raw"', 'reading = "raw"\nfibre = "x"'), "columns.FBG-1_raw.fibre"),
    ("c-axis-unit-wrong", _gmap('duty = 0.5\nunit = "rpm"', 'duty = 0.5\nunit = "degC"'), "columns.c_rpm.unit"),
    ("c-axis-duty-zero", _gmap("duty = 0.5", "duty = 0"), "columns.c_rpm.duty"),
    ("c-axis-duty-above-one", _gmap("duty = 0.5", "duty = 1.5"), "columns.c_rpm.duty"),
    ("c-axis-duty-string", _gmap("duty = 0.5", 'duty = "half"'), "columns.c_rpm.duty"),
    ("second-c-axis-column", _gmap('role = "ambient_temperature"', 'role = "c_axis_speed"'), "columns.room_degC"),
]


def _gcsv(col: str, value) -> str:
    def edit(cols):
        a = np.array(cols[col], dtype=object)
        a[5] = value
        cols[col] = a
    return gantry_csv(edit)


# (id, CSV text, field); the source is the CSV
GANTRY_CSV_EDITS = [
    ("laser-beyond-range", _gcsv("laser_Z_um", 5e4), "laser_Z_um"),
    ("strain-beyond-range", _gcsv("FBG-1_comp", 2e4), "FBG-1_comp"),
    ("strain-nan", _gcsv("FBG-1_raw", "nan"), "FBG-1_raw"),
    ("c-axis-negative", _gcsv("c_rpm", -10.0), "c_rpm"),
    ("c-axis-beyond-machine", _gcsv("c_rpm", 4000.0), "c_rpm"),
]

# ------------------------------------------------------------------- bad results (NetCDF)
def _nc(edit):
    """A callable giving the NetCDF bytes of the good result after ``edit(ds) -> ds``."""
    return lambda: netcdf_bytes(edit(result_dataset()))


def _put(var, value, index=(3, 0)):
    def edit(ds):
        a = ds[var].values.copy()
        a[index] = value
        ds[var] = (ds[var].dims, a, ds[var].attrs)
        return ds
    return edit


def _shift_sensor(ds):
    ds = ds.assign_coords(x=("sensor", [5.0, 0.0, 0.0]))
    return ds


# (id, make bytes, field for plot or None when plot accepts it, field for compare or None)
RESULT_EDITS = [
    ("nan-temperature", _nc(_put("temperature", np.nan)), "temperature", "temperature"),
    ("inf-drift", _nc(_put("drift", np.inf)), "drift", "drift"),
    ("missing-drift", _nc(lambda ds: ds.drop_vars("drift")), "drift", None),
    ("one-sample", _nc(lambda ds: ds.isel(time=[0])), "time", "time"),
    ("no-time", _nc(lambda ds: ds.isel(time=0)), "time", "time"),
    ("time-backwards", _nc(lambda ds: ds.assign_coords(time=ds.time.values[::-1].copy())), "time", "time"),
    ("inputs-only", _nc(lambda ds: ds[["spindle_speed", "ambient_temperature"]]), "drift", "channels"),
    ("unknown-machine", _nc(lambda ds: ds.assign_attrs(machine="vmc-9000")), None, "machine"),
    ("temperature-1e300", _nc(_put("temperature", 1e300)), None, "temperature:motor"),
    ("speed-negative", _nc(_put("spindle_speed", -10.0, 3)), None, "spindle_speed"),
    ("sensor-outside-machine", _nc(_shift_sensor), None, "sensor motor"),
    ("probe-unit-mistake", _nc(_put("probe", 5e4)), None, "probe:X1"),
    ("not-netcdf", lambda: b"time,T\n0,20\n", "result", "measurement"),
]

# ------------------------------------------------------------------------- bad learning tables
def _row(i, j, value):
    return lambda rows: rows[i].__setitem__(j, value)


def _column(j, value):
    def edit(rows):
        for r in rows[1:]:
            r[j] = value
    return edit


# (id, which table, text, field)
TABLE_EDITS = [
    ("constant-target", "train.csv", table_csv(edit=_column(5, "1.5")), "drift_z"),
    ("constant-target-in-test", "test.csv", table_csv(seed=1, edit=_column(5, "1.5")), "drift_z"),
    ("constant-input", "train.csv", table_csv(edit=_column(3, "20.0")), "T3"),
    ("nan", "train.csv", table_csv(edit=_row(7, 3, "nan")), "T3"),
    ("inf", "train.csv", table_csv(edit=_row(7, 3, "inf")), "T3"),
    ("non-numeric", "train.csv", table_csv(edit=_row(5, 2, "warm")), "T2"),
    ("empty-cell", "test.csv", table_csv(seed=1, edit=_row(5, 1, "")), "T1"),
    ("time-not-increasing", "train.csv", table_csv(edit=_row(4, 0, "5")), "time"),
    ("too-few-rows", "train.csv", table_csv(n=2), "rows"),
    ("missing-target", "train.csv", table_csv(edit=lambda rows: [r.pop() for r in rows]), "drift_z"),
    ("duplicate-column", "train.csv", table_csv(edit=lambda rows: rows[0].__setitem__(2, "T1")), "T1"),
    ("test-missing-input", "test.csv", table_csv(seed=1, edit=lambda rows: [r.pop(2) for r in rows]), "T2"),
    ("ragged-row", "train.csv", table_csv(edit=lambda rows: rows[6].append("1")), "line 7"),
    ("header-only", "train.csv", "time,T1,T2,T3,T4,drift_z\n", "rows"),
]

# ---------------------------------------------------------------------- bad options per command
_SET = "--set"
# (id, argv, source, field)
OPTION_CASES = [
    # simulate
    ("simulate:unknown-machine", swap(SIM, "cframe-vmc", "vmc-9000"), CLI, "machine"),
    ("simulate:unknown-scenario", swap(SIM, "{d}/short.toml", "no-such-scenario"), CLI, "scenario"),
    ("simulate:unknown-effect", SIM + ["--effects", "+warp_drive"], CLI, "--effects warp_drive"),
    ("simulate:remove-absent-effect", SIM + ["--effects=-electrical_cabinet"], CLI, "--effects electrical_cabinet"),
    ("simulate:c-axis-beyond-machine", swap(SIM, "cframe-vmc", "gantry-ram"), "{d}/short.toml", "c_axis[0].speed"),
    ("simulate:fbg-cross-sensitivity-no-unit", swap(SIM, "cframe-vmc", "gantry-ram") + ["--set", "fbg.cross_sensitivity=8.64"],
     CLI, "--set fbg.cross_sensitivity"),
    ("simulate:effects-empty", SIM + ["--effects", ","], CLI, "--effects"),
    ("simulate:effects-twice", SIM + ["--effects=-floor", "--effects=-floor"], CLI, "--effects"),
    ("simulate:set-malformed", SIM + [_SET, "power"], CLI, "--set power"),
    ("simulate:set-unknown-parameter", SIM + [_SET, "spindle_motor.colour=3W"], CLI, "--set spindle_motor.colour"),
    ("simulate:set-unknown-effect", SIM + [_SET, "warp.x=1W"], CLI, "--set warp.x"),
    ("simulate:set-no-unit", SIM + [_SET, "spindle_motor.power=3"], CLI, "--set spindle_motor.power"),
    ("simulate:set-wrong-unit", SIM + [_SET, "spindle_motor.power=3 K"], CLI, "--set spindle_motor.power"),
    ("simulate:set-below-bounds", SIM + [_SET, "spindle_motor.power=-3 W"], CLI, "--set spindle_motor.power"),
    ("simulate:set-nan", SIM + [_SET, "spindle_motor.power=nan W"], CLI, "--set spindle_motor.power"),
    ("simulate:set-inf", SIM + [_SET, "spindle_motor.power=inf W"], CLI, "--set spindle_motor.power"),
    ("simulate:set-overflow", SIM + [_SET, "spindle_motor.power=1e400 W"], CLI, "--set spindle_motor.power"),
    ("simulate:set-effect-off", SIM + [_SET, "electrical_cabinet.power=50W"], CLI, "--set electrical_cabinet.power"),
    ("simulate:set-twice", SIM + [_SET, "spindle_motor.power=100W", _SET, "spindle_motor.power=200W"], CLI,
     "--set spindle_motor.power"),
    ("simulate:seed-negative", SIM + ["--seed", "-1"], CLI, "--seed"),
    ("simulate:seed-huge", SIM + ["--seed", str(2**40)], CLI, "--seed"),
    ("simulate:seed-not-integer", SIM + ["--seed", "1.5"], CLI, "--seed"),
    ("simulate:seed-twice", SIM + ["--seed", "1", "--seed", "2"], CLI, "--seed"),
    ("simulate:mesh-unknown", swap(SIM, "coarse", "huge"), CLI, "--mesh"),
    ("simulate:mesh-twice", SIM + ["--mesh", "default"], CLI, "--mesh"),
    ("simulate:o-twice", SIM + ["-o", "{d}/other.nc"], CLI, "-o"),
    ("simulate:field-twice", SIM + ["--field", "{d}/a.vtu", "--field", "{d}/b.vtu"], CLI, "--field"),
    ("simulate:field-is-output", SIM + ["--field", "{d}/out.nc"], "{d}/out.nc", "--field"),
    ("simulate:o-missing", SIM[:3], CLI, "twin simulate"),
    ("simulate:unknown-option", SIM + ["--frobnicate"], CLI, "twin"),
    # plot
    ("plot:o-twice", PLOT + ["-o", "{d}/b.png"], CLI, "-o"),
    ("plot:o-missing", PLOT[:2], CLI, "twin plot"),
    ("plot:pgf-needs-latex", swap(PLOT, "{d}/pic.png", "{d}/pic.pgf"), "{d}/pic.pgf", "-o"),
    # compare
    ("compare:conflicting-machine", COMPARE + ["--machine", "vmc-9000"], "{d}/m.toml", "machine"),
    ("compare:mesh-unknown", swap(COMPARE, "coarse", "huge"), CLI, "--mesh"),
    ("compare:unknown-effect", COMPARE + ["--effects", "+warp"], CLI, "--effects warp"),
    ("compare:set-twice", COMPARE + [_SET, "spindle_motor.power=1W", _SET, "spindle_motor.power=2W"], CLI,
     "--set spindle_motor.power"),
    ("compare:seed-negative", COMPARE + ["--seed", "-1"], CLI, "--seed"),
    ("compare:mapping-twice", COMPARE + ["--mapping", "{d}/m.toml", "--mapping", "{d}/m.toml"], CLI, "--mapping"),
    ("compare:mapping-missing", COMPARE, "{d}/m.toml", "--mapping"),   # files: m.toml removed
    ("compare:unknown-scenario", COMPARE + ["--scenario", "no-such-scenario"], CLI, "scenario"),
    ("compare:scenario-shorter", COMPARE + ["--scenario", "{d}/short.toml"], "{d}/short.toml", "duration"),
    ("compare:netcdf-with-mapping", COMPARE_NC + ["--mapping", "{d}/m.toml"], "{d}/m.toml", "--mapping"),
    ("compare:inputs-only", COMPARE, "{d}/m.csv", "channels"),
    # diagnose
    ("diagnose:error-mesh-same", swap(DIAGNOSE, "none", "coarse"), CLI, "--error-mesh"),
    ("diagnose:error-mesh-unknown", swap(DIAGNOSE, "none", "huge"), CLI, "--error-mesh"),
    ("diagnose:json-twice", DIAGNOSE + ["--json", "{d}/e.json"], CLI, "--json"),
    ("diagnose:report-twice", DIAGNOSE + ["--report", "{d}/r2"], CLI, "--report"),
    ("diagnose:json-in-report", swap(DIAGNOSE, "{d}/d.json", "{d}/report/index.json"), "{d}/report/index.json", "--json"),
    ("diagnose:seed-huge", DIAGNOSE + ["--seed", str(2**33)], CLI, "--seed"),
    ("diagnose:set-unknown", DIAGNOSE + [_SET, "spindle_motor.colour=1W"], CLI, "--set spindle_motor.colour"),
    # learn
    ("learn:train-twice", LEARN + ["--train", "{d}/train.csv"], "{d}/train.csv", "--train"),   # a run once
    ("learn:test-twice", LEARN + ["--test", "{d}/test.csv"], "{d}/test.csv", "--test"),
    ("learn:target-missing", LEARN[:5] + LEARN[7:], CLI, "twin learn"),
    ("learn:unknown-learner", swap(LEARN, "mlr", "mlr,nope"), CLI, "learner"),
    ("learn:learner-empty", swap(LEARN, "mlr", ","), CLI, "--learner"),
    ("learn:unknown-selector", LEARN + ["--select", "nope:2"], CLI, "--select"),
    ("learn:select-count-not-integer", LEARN + ["--select", "correlation:x"], CLI, "--select"),
    ("learn:select-count-zero", LEARN + ["--select", "correlation:0"], CLI, "--select"),
    ("learn:select-takes-no-count", LEARN + ["--select", "all:2"], CLI, "--select"),
    ("learn:select-more-than-inputs", LEARN + ["--select", "correlation:9"], CLI, "--select"),
    ("learn:unknown-input", LEARN + ["--inputs", "T1,T9"], "{d}/train.csv", "T9"),
    ("learn:target-among-inputs", LEARN + ["--inputs", "T1,drift_z"], CLI, "--inputs"),
    ("learn:unknown-time-column", LEARN + ["--time-column", "clock"], "{d}/train.csv", "clock"),
    ("learn:seed-negative", LEARN + ["--seed", "-1"], CLI, "--seed"),
    ("learn:select-twice", LEARN + ["--select", "all", "--select", "all"], CLI, "--select"),
    ("learn:too-few-rows-for-learner", swap(LEARN, "mlr", "combination"), "{d}/train.csv", "combination"),
    ("learn:output-twice", LEARN + ["-o", "{d}/scores.csv"], "{d}/scores.csv", "-o"),
    ("learn:output-unknown-format", LEARN + ["-o", "{d}/scores.txt"], "{d}/scores.txt", "-o"),
    ("learn:interval-no-unit", LEARN + ["--interval", "60"], CLI, "--interval"),
    ("learn:interval-wrong-unit", LEARN + ["--interval", "60 K"], CLI, "--interval"),
    ("learn:interval-zero", LEARN + ["--interval", "0 s"], CLI, "--interval"),
    ("learn:interval-not-a-multiple", LEARN + ["--interval", "25 s"], "{d}/train.csv", "--interval"),
    ("diagnose:effects-file-twice", DIAGNOSE + ["--effects-file", "{d}/fx.toml", "--effects-file", "{d}/fx.toml"], CLI,
     "--effects-file"),
    ("diagnose:measurement-twice", DIAGNOSE[:2] + ["{d}/m.csv"] + DIAGNOSE[2:], CLI, "measurements"),
    ("diagnose:mapping-with-two", DIAGNOSE[:2] + ["{d}/r.nc"] + DIAGNOSE[2:] + ["--mapping", "{d}/m.toml"], CLI,
     "--mapping"),
    # report
    ("report:test-unknown", REPORT + ["--test", "thermal"], CLI, "--test"),
    ("report:axis-without-positioning", REPORT + ["--test", "axis"], "{d}/r.nc", "--test"),
    ("report:kind-unknown", swap(REPORT, "iso230-3", "iso230-2"), CLI, "kind"),
    ("report:segment-no-unit", REPORT + ["--segment", "6"], CLI, "--segment"),
    ("report:segment-zero", REPORT + ["--segment", "0 h"], CLI, "--segment"),
    ("report:segment-negative", REPORT + ["--segment=-1 h"], CLI, "--segment"),
    ("report:segment-nan", REPORT + ["--segment", "nan h"], CLI, "--segment"),
    ("report:segment-twice", REPORT + ["--segment", "1 h", "--segment", "2 h"], CLI, "--segment"),
    ("report:output-missing", REPORT[:3], CLI, "twin report"),   # argparse: "required: -o/--output"
    ("report:mapping-with-netcdf", REPORT + ["--mapping", "{d}/m.toml"], "{d}/m.toml", "--mapping"),
    # demo
    ("demo:bad-set", DEMO + [_SET, "spindle_motor.power=3"], CLI, "--set spindle_motor.power"),
    ("demo:unknown-effect", DEMO + ["--effects", "+warp"], CLI, "--effects warp"),
    ("demo:seed-negative", DEMO + ["--seed", "-1"], CLI, "--seed"),
    ("demo:mesh-unknown", swap(DEMO, "coarse", "huge"), CLI, "--mesh"),
    ("demo:o-twice", DEMO + ["-o", "{d}/other"], CLI, "-o"),
    # list
    ("list:unknown-what", ["list", "gizmos"], CLI, "what"),
    ("list:machine-without-effects", ["list", "machines", "--machine", "cframe-vmc"], CLI, "--machine"),
    ("list:unknown-machine", ["list", "effects", "--machine", "vmc-9000"], CLI, "machine"),
    ("top:unknown-command", ["frobnicate"], CLI, "command"),
]

# ---------------------------------------------------------------------- bad custom-effect files
_FX = SIM + ["--effects-file", "{d}/fx.toml"]


def _fx(old: str, new: str) -> str:
    assert old in EFFECTS_FILE, old
    return EFFECTS_FILE.replace(old, new)


EFFECTS_EDITS = [   # (id, text, field)
    ("unknown-key", EFFECTS_FILE + 'colour = "red"\n', "effects.pump.colour"),
    ("no-unit", _fx('"80 W"', "80"), "effects.pump.power"),
    ("wrong-unit", _fx('"80 W"', '"80 K"'), "effects.pump.power"),
    ("nan", _fx('"80 W"', '"nan W"'), "effects.pump.power"),
    ("unknown-kind", _fx('"heat_source"', '"laser"'), "effects.pump.kind"),
    ("unknown-part", _fx('"saddle"', '"gearbox"'), "effects.pump.region"),
    ("unknown-direction", _fx('"saddle"', '"column.+w"'), "effects.pump.region"),
    ("library-name", _fx("pump", "spindle_motor"), "effects.spindle_motor"),
    ("bad-name", _fx("pump", '"2pump"'), "effects"),
    ("no-tables", 'kind = "heat_source"\n', "effects"),
    ("malformed", EFFECTS_FILE + "[[[\n", "toml"),
    ("unknown-schedule", EFFECTS_FILE + 'schedule = "sometimes"\n', "effects.pump.schedule"),
    ("window-backwards", EFFECTS_FILE + 'schedule = "windows"\nwindows = [["2 h", "1 h"]]\n', "effects.pump.windows"),
    ("range-without-strength", EFFECTS_FILE + 'range = ["100 W", "200 W"]\n', "effects.pump.range"),
    ("table-missing", EFFECTS_FILE + 'schedule = "table"\ntable = { file = "none.csv", time_unit = "min" }\n',
     "file"),
]

# files an option case needs changed (id -> files)
OPTION_FILES = {
    "compare:mapping-missing": {"m.toml": None},
    "simulate:c-axis-beyond-machine": {"short.toml": _sc(SPEED, 'speed = "3000 rpm"') + _c_axis('speed = "4000 rpm"')},
    "compare:scenario-shorter": {"short.toml": SCENARIO.replace('duration = "20 min"', 'duration = "10 min"')},
    "compare:inputs-only": {"m.csv": INPUTS_ONLY_CSV, "m.toml": INPUTS_ONLY_MAPPING},
    "learn:too-few-rows-for-learner": {"train.csv": table_csv(n=5)},
}


# logged axis positions (role axis_position): a good CSV column y_mm with a bad mapping or values
YPOS = '[columns.y_mm]\nrole = "axis_position"\naxis = "Y"\nunit = "mm"\n'


def _ypos(value):
    def edit(cols):
        cols["y_mm"] = np.where(np.arange(len(cols["t_s"])) == 5, value, 140.0)
    return measurement_csv(edit)


# (id, CSV text, mapping text, source file, field)
AXIS_LOG_EDITS = [
    ("axis-position-unknown-axis", _ypos(140.0), MAPPING + YPOS.replace('"Y"', '"W"'), "m.toml", "columns.y_mm.axis"),
    ("axis-position-no-axis", _ypos(140.0), MAPPING + YPOS.replace('axis = "Y"\n', ''), "m.toml",
     "columns.y_mm.axis"),
    ("axis-position-outside-travel", _ypos(900.0), MAPPING + YPOS, "m.csv", "y_mm"),
    ("axis-position-wrong-unit", _ypos(140.0), MAPPING + YPOS.replace('"mm"', '"mm/s"'), "m.toml",
     "columns.y_mm.unit"),
]


def all_cases() -> list[Case]:
    """Every case of the tables above."""
    cases = [c for row in INPUTS for c in bad_input_paths(*row)]
    cases += [c for row in OUTPUTS for c in bad_output_paths(*row)]
    cases += [c for row in FOLDERS for c in bad_output_folders(*row)]
    for cid, text, fld in SCENARIO_EDITS:
        cases.append(Case(f"simulate.scenario:{cid}", SIM, "{d}/short.toml", fld, files={"short.toml": text}))
        if cid in SCENARIO_EDITS_VIA_MEASUREMENT:
            for name, argv in (("compare", COMPARE), ("diagnose", DIAGNOSE)):
                cases.append(Case(f"{name}.scenario:{cid}", argv + ["--scenario", "{d}/short.toml"], "{d}/short.toml",
                                  fld, files={"short.toml": text}))
    for cid, text, fld in GANTRY_AXIS_EDITS:
        cases.append(Case(f"simulate.gantry-axis:{cid}", SIM_GANTRY, "{d}/short.toml", fld, files={"short.toml": text}))
    for cid, files, source, fld in ROOM_EDITS:
        cases.append(Case(f"simulate.room-csv:{cid}", SIM_ROOM, source, fld, files=files))
    cases.append(Case("simulate.room-csv:folder", SIM_ROOM, ROOM, "ambient.file", setup=_room_folder))
    cases.append(Case("simulate.room-csv:device", SIM_ROOM, "/dev/null", "ambient.file",
                      files={"room.toml": ROOM_SCENARIO.replace('"room.csv"', '"/dev/null"')}))
    for cid, text, fld in MAPPING_EDITS:
        cases.append(Case(f"compare.mapping:{cid}", COMPARE, "{d}/m.toml", fld, files={"m.toml": text}))
    for cid, text, fld in CSV_EDITS:
        cases.append(Case(f"compare.csv:{cid}", COMPARE, "{d}/m.csv", fld, files={"m.csv": text}))
        if cid in CSV_EDITS_VIA_DIAGNOSE:
            cases.append(Case(f"diagnose.csv:{cid}", DIAGNOSE, "{d}/m.csv", fld, files={"m.csv": text}))
    for cid, csv_text, mapping, bad, fld in AXIS_LOG_EDITS:
        cases.append(Case(f"compare.axis-log:{cid}", COMPARE, "{d}/" + bad, fld,
                          files={"m.csv": csv_text, "m.toml": mapping}))
    for cid, text, fld in GANTRY_MAPPING_EDITS:
        cases.append(Case(f"compare.gantry-mapping:{cid}", COMPARE_GANTRY, "{d}/g.toml", fld, files={"g.toml": text}))
    for cid, text, fld in GANTRY_CSV_EDITS:
        cases.append(Case(f"compare.gantry-csv:{cid}", COMPARE_GANTRY, "{d}/g.csv", fld, files={"g.csv": text}))
    for cid, make, plot_field, compare_field in RESULT_EDITS:
        if plot_field is not None:
            cases.append(Case(f"plot.result:{cid}", PLOT, "{d}/r.nc", plot_field, files={"r.nc": make}))
        if compare_field is not None:   # twin report reads a result through the measurement reader, too
            cases.append(Case(f"compare.netcdf:{cid}", COMPARE_NC, "{d}/r.nc", compare_field, files={"r.nc": make}))
            cases.append(Case(f"report.result:{cid}", REPORT, "{d}/r.nc", compare_field, files={"r.nc": make}))
    for cid, name, text, fld in TABLE_EDITS:
        cases.append(Case(f"learn.table:{cid}", LEARN, f"{{d}}/{name}", fld, files={name: text}))
    for cid, text, fld in EFFECTS_EDITS:
        cases.append(Case(f"simulate.effects-file:{cid}", _FX, "{d}/none.csv" if cid == "table-missing" else
                          "{d}/fx.toml", fld, files={"fx.toml": text}))
    for cid, argv, source, fld in OPTION_CASES:
        cases.append(Case(cid, argv, source, fld, files=OPTION_FILES.get(cid, {})))
    return cases
