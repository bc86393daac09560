"""The fuzz suite's bad measurements: the rows of :data:`MAPPING_EDITS` (column mappings),
:data:`CSV_EDITS` (measurement CSVs) and the gantry's :data:`GANTRY_MAPPING_EDITS` and
:data:`GANTRY_CSV_EDITS` (lasers, FBG strain, C axis), each a file with one thing made bad and the
field its error must name. :mod:`tests.fuzz_cases` runs them through the commands that read them.
"""

from __future__ import annotations

import numpy as np

from tests.fuzz_files import GANTRY_MAPPING, MAPPING, TEXT, gantry_csv, measurement_csv


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
    ("site-a-list", _map('site = "motor"', 'site = ["motor"]'), "columns.T_motor.site"),
    ("position-outside-machine", _map(MOTOR, _at("5 m", "5 m", "5 m")), "columns.T_motor"),
    ("position-unknown-part", _map(MOTOR, _at("0 m", "0 m", "0.2 m", "plinth")), "columns.T_motor"),
    ("position-not-on-part", _map(MOTOR, _at("0 m", "0 m", "0.2 m", "motor")), "columns.T_motor"),
    ("position-missing-z", _map(MOTOR, _at("0 m", "0 m", "0.2 m").replace('\nz = "0.2 m"', "")), "columns.T_motor.z"),
    ("position-no-unit", _map(MOTOR, _at("0", "0 m", "0.2 m")), "columns.T_motor"),
    ("probe-unknown", _map('probe = "X1"', 'probe = "W1"'), "columns.probe_X1_um.probe"),
    ("probe-twice", _map('probe = "X2"', 'probe = "X1"'), "columns.probe_X2_um.probe"),
    # two columns of one sensor name: the error names the second column (and its message the first)
    ("sensor-name-twice", _map(MOTOR, MOTOR + '\nname = "column_side"'), "columns.T_column_side"),
    ("column-not-in-csv", MAPPING + '[columns.ghost]\nrole = "temperature"\nsite = "motor"\nunit = "degC"\n',
     "columns.ghost"),
    ("second-time-column", _map('role = "ambient_temperature"\nunit = "degC"', 'role = "time"\nunit = "s"'),
     "columns.room_degC"),
    ("column-not-a-table", _map('[columns.t_s]\nrole = "time"\nunit = "s"', '[columns]\nt_s = "time"'), "columns.t_s"),
    ("malformed-toml", MAPPING.replace("[columns.t_s]", "[columns.t_s"), "toml"),
    # a site and a position (or a part) contradict each other
    ("site-and-x", _map('site = "column_side"', 'site = "column_side"\nx = "0 m"'), "columns.T_column_side.x"),
    ("site-and-y", _map('site = "column_side"', 'site = "column_side"\ny = "0 m"'), "columns.T_column_side.y"),
    ("site-and-z", _map('site = "column_side"', 'site = "column_side"\nz = "1 m"'), "columns.T_column_side.z"),
    ("site-and-part", _map('site = "column_side"', 'site = "column_side"\npart = "bed"'),
     "columns.T_column_side.part"),
    # the sensor name becomes a channel name: a non-empty string without '@' (measurement suffix), ':' or ','
    ("name-empty", _map('site = "column_side"', 'site = "column_side"\nname = ""'), "columns.T_column_side.name"),
    ("name-blank", _map('site = "column_side"', 'site = "column_side"\nname = "  "'), "columns.T_column_side.name"),
    ("name-not-a-string", _map('site = "column_side"', 'site = "column_side"\nname = 3'),
     "columns.T_column_side.name"),
    ("name-with-at", _map('site = "column_side"', 'site = "column_side"\nname = "a@b.csv"'),
     "columns.T_column_side.name"),
    ("name-with-colon", _map('site = "column_side"', 'site = "column_side"\nname = "a:b"'),
     "columns.T_column_side.name"),
    ("name-with-comma", _map('site = "column_side"', 'site = "column_side"\nname = "a,b"'),
     "columns.T_column_side.name"),
    ("name-at-position", _map(MOTOR, _at("0 m", "0 m", "0.2 m") + '\nname = "m@x"'), "columns.T_motor.name"),
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
    # a probe column on a machine without probes: said so (it listed "known: " and nothing)
    ("probe-on-machine-without", _gmap('role = "laser"\nlaser = "Y"', 'role = "probe"\nprobe = "X1"'),
     "columns.laser_Y_um.probe"),
    ("laser-unit-not-length", _gmap('laser = "Y"\nunit = "um"', 'laser = "Y"\nunit = "um/m"'), "columns.laser_Y_um.unit"),
    ("laser-on-machine-without", _gmap('"gantry-ram"', '"cframe-vmc"'), "columns.c_rpm"),
    ("gauge-unknown", _gmap('gauge = "FBG-1"', 'gauge = "FBG-9"'), "columns.FBG-1_comp.gauge"),
    ("gauge-twice", _gmap('gauge = "FBG-4"\nreading = "compensated"', 'gauge = "FBG-1"\nreading = "compensated"'),
     "columns.FBG-4_comp.gauge"),
    ("reading-missing", _gmap('reading = "compensated"\n', ''), "columns.FBG-1_comp.reading"),
    ("reading-unknown", _gmap('reading = "compensated"', 'reading = "corrected"'), "columns.FBG-1_comp.reading"),
    # a list or a table: a TypeError (unhashable) before the check named the field
    ("reading-a-list", _gmap('reading = "compensated"', 'reading = ["compensated"]'), "columns.FBG-1_comp.reading"),
    ("reading-a-table", _gmap('reading = "compensated"', 'reading = {}'), "columns.FBG-1_comp.reading"),
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
