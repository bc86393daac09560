"""The bad inputs of the fuzz suite (``tests/test_fuzz_inputs.py``), generated from tables.

Each :class:`tests.fuzz_files.Case` is one command line run in a fresh folder holding good copies
of the files it needs, one thing made bad, and the error it must give: the source (a path, ``{d}``
standing for the case's folder, or ``command line``) and a part of the field. The bad paths of
every file argument come from ``tests/fuzz_files.py``; this module adds the bad contents and
options. Add a command, an option or a file format by adding rows:

* :data:`tests.fuzz_scenarios.SCENARIO_EDITS`, :data:`tests.fuzz_measurements.MAPPING_EDITS` and
  :data:`~tests.fuzz_measurements.CSV_EDITS`, :data:`RESULT_EDITS`,
  :data:`TABLE_EDITS` - bad contents of each file kind, each run through the commands that read it;
* :data:`OPTION_CASES` - bad option values and repeated options, per command;
* :data:`tests.fuzz_axis_logs.AXIS_LOG_EDITS` - bad logged axis positions and feeds in a measurement.

Later issues add theirs as rows: dataset specs (a ``twin dataset`` row in
``fuzz_files.INPUTS`` and a table of spec edits here), axis scenarios (more
:data:`SCENARIO_EDITS`), camera settings (:data:`OPTION_CASES`) and custom effects
(``--effects-file``: an ``INPUTS`` row and its edits).
"""

from __future__ import annotations

import os

import numpy as np

from tests.fuzz_axis_logs import AXIS_LOG_EDITS
from tests.fuzz_measurements import (CSV_EDITS, CSV_EDITS_VIA_DIAGNOSE, GANTRY_CSV_EDITS, GANTRY_MAPPING_EDITS,
                                     INPUTS_ONLY_CSV, INPUTS_ONLY_MAPPING, MAPPING_EDITS)
from tests.fuzz_scenarios import (GANTRY_AXIS_EDITS, SCENARIO_EDITS, SCENARIO_EDITS_VIA_MEASUREMENT, SPEED,
                                  c_axis_scenario, edited)
from tests.fuzz_files import (CLI, COMPARE, COMPARE_GANTRY, COMPARE_NC, DEMO, DIAGNOSE, EFFECTS_FILE, FOLDERS, INPUTS,
                              LEARN, OUTPUTS, PLOT, REPORT, ROOM_SCENARIO, SCENARIO, SIM, Case, bad_input_paths,
                              bad_output_folders, bad_output_paths, netcdf_bytes, result_dataset, swap, table_csv)


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
    # the columns swapped: said so (it was "header unit [degC]: '1 degC' has the wrong unit")
    ("columns-swapped", {"room.csv": "air [degC],time [min]\n20,0\n21,30\n"}, ROOM, "header"),
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


def _sensor_names(names):
    return lambda ds: ds.assign_coords(sensor=list(names))


def _axis_log(mm, axis="Y"):
    """The result with a logged ``axis`` position [mm] per sample (``mm(t)``, t in s)."""
    def edit(ds):
        t = ds.time.values
        return ds.assign({"axis_position": (("time", "axis_name"), np.asarray(mm(t), float)[:, None], {"units": "mm"})}
                         ).assign_coords(axis_name=[axis])
    return edit


# (id, make bytes, field for plot, field for compare or None): plot reads a result as compare does
# (twin.io.measurement.read_checked_result), so it refuses the same values (it drew them once)
RESULT_EDITS = [
    ("nan-temperature", _nc(_put("temperature", np.nan)), "temperature", "temperature"),
    ("inf-drift", _nc(_put("drift", np.inf)), "drift", "drift"),
    ("missing-drift", _nc(lambda ds: ds.drop_vars("drift")), "drift", None),
    ("one-sample", _nc(lambda ds: ds.isel(time=[0])), "time", "time"),
    ("no-time", _nc(lambda ds: ds.isel(time=0)), "time", "time"),
    ("time-backwards", _nc(lambda ds: ds.assign_coords(time=ds.time.values[::-1].copy())), "time", "time"),
    ("inputs-only", _nc(lambda ds: ds[["spindle_speed", "ambient_temperature"]]), "channels", "channels"),
    ("unknown-machine", _nc(lambda ds: ds.assign_attrs(machine="vmc-9000")), "machine", "machine"),
    ("machine-a-number", _nc(lambda ds: ds.assign_attrs(machine=7)), "machine", "machine"),
    ("temperature-1e300", _nc(_put("temperature", 1e300)), "temperature:motor", "temperature:motor"),
    ("speed-negative", _nc(_put("spindle_speed", -10.0, 3)), "spindle_speed", "spindle_speed"),
    ("sensor-outside-machine", _nc(_shift_sensor), "sensor motor", "sensor motor"),
    ("probe-unit-mistake", _nc(_put("probe", 5e4)), "probe:X1", "probe:X1"),
    ("not-netcdf", lambda: b"time,T\n0,20\n", "result", "measurement"),
    ("netcdf-3-classic", lambda: result_dataset().to_netcdf(engine="scipy"), "result", "measurement"),
    ("sensor-name-with-at", _nc(_sensor_names(["motor@1", "column_side", "bed_front"])), "sensor[0]", "sensor[0]"),
    ("sensor-name-twice", _nc(_sensor_names(["motor", "motor", "bed_front"])), "sensor", "sensor"),
    ("axis-log-outside-travel", _nc(_axis_log(lambda t: np.full(len(t), 900.0))), "axis_position:Y",
     "axis_position:Y"),
    # 200 mm back and forth every 60 ms (a log in ms written as s): 3.3 m/s
    ("axis-log-too-fast", _nc(lambda ds: _axis_log(lambda t: 100.0 + 200.0 * (np.arange(len(t)) % 2))(
        ds.assign_coords(time=("time", ds.time.values * 1e-3, {"units": "s"})))), "axis_position:Y",
     "axis_position:Y"),
    ("axis-log-unknown-axis", _nc(_axis_log(lambda t: np.full(len(t), 100.0), "W")), "axis_position:W",
     "axis_position:W"),
    # the sensors placed in part (compare used to fail on the missing coordinate with a traceback)
    ("sensor-position-partial", _nc(lambda ds: ds.drop_vars("x")), "x", "x"),
    # a sensor that is neither placed nor a site: refused when read, naming the file as typed
    ("sensor-unplaced", _nc(lambda ds: ds.drop_vars(["x", "y", "z"]).assign_coords(
        sensor=["s1", "column_side", "bed_front"])), "sensor s1", "sensor s1"),
    # temperatures without sensor names (compare used to drop them without a word)
    ("temperature-unnamed", _nc(lambda ds: ds.drop_vars(["x", "y", "z", "part", "sensor"])), "temperature",
     "temperature"),
    # a probe the machine lacks (compare used to drop it, and the machine's Z with it, without a word)
    ("probe-unknown", _nc(lambda ds: ds.assign_coords(probe_id=["X1", "X2", "Y1", "Y2", "Q"])), "probe:Q", "probe:Q"),
    # a drift with a third dimension (plot used to fail with a traceback, compare and report to pass)
    ("drift-third-dimension", _nc(lambda ds: ds.assign(drift=ds.drift.expand_dims(extra=[0, 1]).transpose(
        "time", "axis", "extra"))), "drift", "drift"),
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
    ("simulate:scenario-empty", swap(SIM, "{d}/short.toml", ""), CLI, "scenario"),   # was the working folder
    ("simulate:unknown-effect", SIM + ["--effects", "+warp_drive"], CLI, "--effects warp_drive"),
    ("simulate:remove-absent-effect", SIM + ["--effects=-electrical_cabinet"], CLI, "--effects electrical_cabinet"),
    ("simulate:add-effect-already-on", SIM + ["--effects", "+floor"], CLI, "--effects +floor"),   # changes nothing
    ("simulate:c-axis-beyond-machine", swap(SIM, "cframe-vmc", "gantry-ram"), "{d}/short.toml", "c_axis[0].speed"),
    ("simulate:fbg-cross-sensitivity-no-unit", swap(SIM, "cframe-vmc", "gantry-ram") + ["--set", "fbg.cross_sensitivity=8.64"],
     CLI, "--set fbg.cross_sensitivity"),
    ("simulate:effects-empty", SIM + ["--effects", ","], CLI, "--effects"),
    # an empty value read as "not given": no output, no message (twin.cli._Once)
    ("simulate:field-empty", SIM + ["--field", ""], CLI, "--field"),
    ("simulate:effects-file-empty", SIM + ["--effects-file", " "], CLI, "--effects-file"),
    ("compare:mapping-empty", COMPARE + ["--mapping", ""], CLI, "--mapping"),
    ("compare:scenario-empty", COMPARE + ["--scenario", ""], CLI, "--scenario"),
    ("diagnose:json-empty", swap(DIAGNOSE, "{d}/d.json", ""), CLI, "--json"),
    ("diagnose:report-empty", swap(DIAGNOSE, "{d}/report", ""), CLI, "--report"),
    ("report:mapping-empty", REPORT + ["--mapping", ""], CLI, "--mapping"),
    ("simulate:elastic-coarsening-beyond-8", SIM + ["--elastic-coarsening", "100000"], CLI, "--elastic-coarsening"),
    ("simulate:effects-twice", SIM + ["--effects=-floor", "--effects=-floor"], CLI, "--effects"),
    ("simulate:effect-added-and-removed", SIM + ["--effects=+floor_lag,-floor_lag"], CLI, "--effects +floor_lag,-floor_lag"),
    ("simulate:effect-named-twice", SIM + ["--effects=+floor_lag,+floor_lag"], CLI, "--effects +floor_lag,+floor_lag"),
    ("simulate:effects-set-mixed-with-edits", SIM + ["--effects", "spindle_motor,+floor"], CLI,
     "--effects spindle_motor,+floor"),
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
    ("diagnose:seed-does-nothing", DIAGNOSE + ["--seed", "1"], CLI, "twin"),   # true values: no noise to seed
    ("diagnose:set-unknown", DIAGNOSE + [_SET, "spindle_motor.colour=1W"], CLI, "--set spindle_motor.colour"),
    # learn
    ("learn:train-twice", LEARN + ["--train", "{d}/train.csv"], "{d}/train.csv", "--train"),   # a run once
    ("learn:test-twice", LEARN + ["--test", "{d}/test.csv"], "{d}/test.csv", "--test"),
    ("learn:target-missing", LEARN[:5] + LEARN[7:], CLI, "twin learn"),
    ("learn:unknown-learner", swap(LEARN, "mlr", "mlr,nope"), CLI, "learner"),
    ("learn:learner-empty", swap(LEARN, "mlr", ","), CLI, "--learner"),
    ("learn:inputs-all-beside-a-name", LEARN + ["--inputs", "all,T1"], CLI, "--inputs"),   # blamed train.csv
    ("learn:split-is-the-train-split", ["learn", "--dataset", "{d}", "--split", "train", "--train-split", "train",
                                        "--target", "drift_z", "--learner", "mlr"], CLI, "--split"),
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
    # an effects file's effects are always on where the twin runs them: removing one is refused saying so
    ("simulate:effects-file-removed", SIM + ["--effects-file", "{d}/fx.toml", "--effects=-pump"], CLI,
     "--effects -pump"),
    ("compare:effects-file-removed", COMPARE + ["--effects-file", "{d}/fx.toml", "--effects=-pump"], CLI,
     "--effects -pump"),
    ("diagnose:measurement-twice", DIAGNOSE[:2] + ["{d}/m.csv"] + DIAGNOSE[2:], "{d}/m.csv", "measurement"),
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
    ("report:segment-below-the-sampling", REPORT + ["--segment", "1 ms"], CLI, "--segment"),
    ("report:segment-tiny", REPORT + ["--segment", "1e-9 s"], CLI, "--segment"),
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
    ("no-tables", 'kind = "heat_source"\n', "kind"),   # an effect's key without [effects.NAME] above it
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
    "simulate:c-axis-beyond-machine": {"short.toml": edited(SPEED, 'speed = "3000 rpm"') + c_axis_scenario('speed = "4000 rpm"')},
    "compare:scenario-shorter": {"short.toml": SCENARIO.replace('duration = "20 min"', 'duration = "10 min"')},
    "compare:inputs-only": {"m.csv": INPUTS_ONLY_CSV, "m.toml": INPUTS_ONLY_MAPPING},
    "learn:too-few-rows-for-learner": {"train.csv": table_csv(n=5)},
}


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
    # the same measurement by a hard link (with its own mapping beside it): the same file, given twice
    cases.append(Case("diagnose:measurement-by-a-hard-link", DIAGNOSE[:2] + ["{d}/m-link.csv"] + DIAGNOSE[2:],
                      "{d}/m-link.csv", "measurement", setup=_hard_link_measurement))
    # a byte copy of it under another name: another file, the same run, which a joint fit weighed twice
    cases.append(Case("diagnose:measurement-copied", DIAGNOSE[:2] + ["{d}/m-copy.csv"] + DIAGNOSE[2:],
                      "{d}/m-copy.csv", "measurement", setup=_copied_measurement))
    return cases


def _copied_measurement(folder: str) -> None:
    import shutil

    for suffix in (".csv", ".toml"):
        shutil.copyfile(os.path.join(folder, "m" + suffix), os.path.join(folder, "m-copy" + suffix))


def _hard_link_measurement(folder: str) -> None:
    for suffix in (".csv", ".toml"):
        os.link(os.path.join(folder, "m" + suffix), os.path.join(folder, "m-link" + suffix))
