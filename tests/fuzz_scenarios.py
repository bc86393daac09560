"""The fuzz suite's bad scenario files: the rows of :data:`SCENARIO_EDITS` (every machine's
scenario keys, ambient kinds and events, the C axis, axis moves, the interferometer and probing)
and :data:`GANTRY_AXIS_EDITS`, each a scenario text with one thing made bad and the field its
error must name. :mod:`tests.fuzz_cases` runs them through every command that reads a scenario.
"""

from __future__ import annotations

from tests.fuzz_files import SCENARIO


# ------------------------------------------------------------------------- bad scenario files
def edited(old: str, new: str, count: int = 1) -> str:
    """The good scenario with ``old`` replaced by ``new`` (``old`` must be in it)."""
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


def c_axis_scenario(speed: str = 'speed = "2500 rpm"', duration: str = 'duration = "10 min"') -> str:
    """A [[c_axis]] step with ``speed`` and ``duration`` lines in place of the good ones."""
    return C_AXIS.replace('speed = "2500 rpm"', speed).replace('duration = "10 min"', duration)


# (id, scenario text, field)
SCENARIO_EDITS = [
    ("ambient-below-absolute-zero", edited('"20 degC"', '"-300 degC"'), "ambient.temperature"),
    ("ambient-1e6-degC", edited('"20 degC"', '"1e6 degC"'), "ambient.temperature"),
    ("ambient-implausible", edited('"20 degC"', '"85 degC"'), "ambient.temperature"),
    ("ambient-no-unit", edited('"20 degC"', '"20"'), "ambient.temperature"),
    ("ambient-kelvin-unit", edited('"20 degC"', '"293 K"'), "ambient.temperature"),
    ("ambient-nan", edited('"20 degC"', '"nan degC"'), "ambient.temperature"),
    ("ambient-overflow", edited('"20 degC"', '"1e400 degC"'), "ambient.temperature"),
    ("ambient-number", edited('"20 degC"', '20'), "ambient.temperature"),
    ("ambient-bool", edited('"20 degC"', 'true'), "ambient.temperature"),
    ("initial-below-absolute-zero", edited(INTERVAL, INTERVAL + '\ninitial_temperature = "-300 degC"'), "initial_temperature"),
    ("initial-1e6", edited(INTERVAL, INTERVAL + '\ninitial_temperature = "1e6 degC"'), "initial_temperature"),
    ("initial-no-unit", edited(INTERVAL, INTERVAL + '\ninitial_temperature = "20"'), "initial_temperature"),
    ("daily-negative-amplitude", edited(AMBIENT, DAILY.replace('"3 K"', '"-3 K"')), "ambient.amplitude"),
    ("daily-huge-amplitude", edited(AMBIENT, DAILY.replace('"3 K"', '"300 K"')), "ambient.amplitude"),
    ("daily-mean-below-zero", edited(AMBIENT, DAILY.replace('"20 degC"', '"-300 degC"')), "ambient.mean"),
    ("daily-missing-amplitude", edited(AMBIENT, DAILY.replace('\namplitude = "3 K"', '')), "ambient.amplitude"),
    ("daily-amplitude-in-degC", edited(AMBIENT, DAILY.replace('"3 K"', '"3 degC"')), "ambient.amplitude"),
    ("table-times-decrease", edited(AMBIENT, TABLE.replace('"0 h", "1 h"', '"1 h", "0 h"')), "ambient.times"),
    ("table-length-mismatch", edited(AMBIENT, TABLE.replace('"20 degC", "21 degC"', '"20 degC"')), "ambient.temperatures"),
    ("table-below-absolute-zero", edited(AMBIENT, TABLE.replace('"21 degC"', '"-300 degC"')), "ambient.temperatures"),
    ("table-starts-after-the-run", edited(AMBIENT, TABLE.replace('"0 h", "1 h"', '"5 min", "1 h"')), "ambient.times"),
    ("table-ends-before-the-run", edited(AMBIENT, TABLE.replace('"0 h", "1 h"', '"0 h", "5 min"')), "ambient.times"),
    ("daily-coldest-at-30-h", edited(AMBIENT, DAILY + '\ncoldest_at = "30 h"'), "ambient.coldest_at"),
    ("daily-start-before-midnight", edited(AMBIENT, DAILY + '\nstart_time_of_day = "-3 h"'), "ambient.start_time_of_day"),
    ("table-time-no-unit", edited(AMBIENT, TABLE.replace('"1 h"', '"1"')), "ambient.times[1]"),
    ("table-times-not-a-list", edited(AMBIENT, TABLE.replace('["0 h", "1 h"]', '"0 h"')), "ambient.times"),
    ("ambient-unknown-kind", edited(AMBIENT, '[ambient]\nkind = "weekly"'), "ambient.kind"),
    ("ambient-unknown-key", edited(AMBIENT, AMBIENT + '\ncolour = "red"'), "ambient.colour"),
    ("ambient-missing", edited(AMBIENT + "\n", ""), "ambient"),
    ("ambient-not-a-table", edited(AMBIENT + "\n", "").replace(INTERVAL, INTERVAL + '\nambient = "20 degC"'), "ambient"),
    ("speed-1e6-rpm", edited(SPEED, 'speed = "1e6 rpm"'), "spindle[0].speed"),
    ("speed-1e300-krpm", edited(SPEED, 'speed = "1e300 krpm"'), "spindle[0].speed"),
    ("speed-beyond-machine", edited(SPEED, 'speed = "9001 rpm"'), "spindle[0].speed"),
    ("speed-negative", edited(SPEED, 'speed = "-5 rpm"'), "spindle[0].speed"),
    ("speed-no-unit", edited(SPEED, 'speed = "6000"'), "spindle[0].speed"),
    ("speed-wrong-unit", edited(SPEED, 'speed = "6000 W"'), "spindle[0].speed"),
    ("speed-inf", edited(SPEED, 'speed = "inf rpm"'), "spindle[0].speed"),
    ("speed-missing", edited(SPEED + "\n", ""), "spindle[0].speed"),
    ("duration-1e300-s", edited(DURATION, 'duration = "1e300 s"'), "spindle"),
    ("duration-zero", edited(DURATION, 'duration = "0 s"'), "spindle[0].duration"),
    ("duration-negative", edited(DURATION, 'duration = "-10 min"'), "spindle[0].duration"),
    ("duration-not-a-multiple", edited(DURATION, 'duration = "90 s"'), "spindle[0].duration"),
    ("duration-missing", edited(DURATION + "\n", ""), "spindle[0].duration"),
    ("interval-1-ns", edited(INTERVAL, 'sample_interval = "1e-9 s"'), "sample_interval"),
    ("interval-zero", edited(INTERVAL, 'sample_interval = "0 s"'), "sample_interval"),
    ("interval-negative", edited(INTERVAL, 'sample_interval = "-1 s"'), "sample_interval"),
    ("interval-no-unit", edited(INTERVAL, 'sample_interval = "60"'), "sample_interval"),
    ("unknown-top-key", edited("sample_interval", "sampel_interval"), "sampel_interval"),
    ("unknown-step-key", edited(SPEED, SPEED + '\nfeed = "1 m/min"'), "spindle[0].feed"),
    ("spindle-missing", SCENARIO.split("[[spindle]]")[0], "spindle"),
    ("spindle-not-steps", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + "\nspindle = 3"), "spindle"),
    ("spindle-empty", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + "\nspindle = []"), "spindle"),
    ("spindle-step-not-a-table", SCENARIO.split("[[spindle]]")[0].replace(INTERVAL, INTERVAL + '\nspindle = ["a"]'),
     "spindle[0]"),
    ("event-missing-change", edited(AMBIENT, AMBIENT + EVENT.replace('change = "-9 K"\n', '')), "ambient.events[0].change"),
    ("event-negative-fall", edited(AMBIENT, AMBIENT + EVENT.replace('"30 min"', '"-30 min"')), "ambient.events[0].fall"),
    ("event-after-the-run", edited(AMBIENT, AMBIENT + EVENT.replace('"5 min"', '"5 h"')), "ambient.events[0].start"),
    # times near the float's limit: their sums overflowed in the air's check (warnings, "not a finite number")
    ("event-start-1e308-s", edited(AMBIENT, AMBIENT + EVENT.replace('"5 min"', '"1e308 s"')), "ambient.events[0].start"),
    ("event-recovery-1e308-s", edited(AMBIENT, AMBIENT + EVENT + 'recovery = "1e308 s"\n'), "ambient.events[0].recovery"),
    ("name-not-text", edited('name = "short"', 'name = 3'), "name"),
    ("name-line-break", edited('name = "short"', 'name = "a\\nb"'), "name"),
    ("description-not-text", edited('name = "short"', 'name = "short"\ndescription = 5'), "description"),
    ("event-change-in-degC", edited(AMBIENT, AMBIENT + EVENT.replace('"-9 K"', '"-9 degC"')), "ambient.events[0].change"),
    ("event-door-not-bool", edited(AMBIENT, AMBIENT + EVENT + 'door = "yes"\n'), "ambient.events[0].door"),
    ("event-unknown-key", edited(AMBIENT, AMBIENT + EVENT + 'colour = "red"\n'), "ambient.events[0].colour"),
    ("event-below-absolute-zero", edited(AMBIENT, AMBIENT + EVENT.replace('"-9 K"', '"-400 K"')), "ambient.events"),
    # a spike without hold or recovery jumps back at its peak: the air just before it is checked
    ("step-shorter-than-a-sample", edited(DURATION, 'duration = "1e-5 s"'), "spindle[0].duration"),
    ("event-spike-below-plausible-air", edited(AMBIENT, AMBIENT + EVENT.replace('"-9 K"', '"-100 K"')
                                               .replace('"30 min"', '"9.5 s"')), "ambient.events"),
    ("events-not-tables", edited(AMBIENT, AMBIENT + '\nevents = 3'), "ambient.events"),
    ("csv-file-not-a-string", edited(AMBIENT, '[ambient]\nkind = "csv"\nfile = 3'), "ambient.file"),
    ("csv-file-missing-key", edited(AMBIENT, '[ambient]\nkind = "csv"'), "ambient.file"),
    ("malformed-toml", SCENARIO.replace("[ambient]", "[ambient"), "toml"),
    ("duplicate-key", edited(INTERVAL, INTERVAL + "\n" + INTERVAL), "toml"),
    # the C axis (twin.rotary): parsed before any machine is asked; cframe-vmc has no C axis
    ("c-axis-speed-no-unit", SCENARIO + c_axis_scenario('speed = "2500"'), "c_axis[0].speed"),
    ("c-axis-speed-negative", SCENARIO + c_axis_scenario('speed = "-5 rpm"'), "c_axis[0].speed"),
    ("c-axis-speed-missing", SCENARIO + C_AXIS.replace('speed = "2500 rpm"\n', ""), "c_axis[0].speed"),
    ("c-axis-duration-zero", SCENARIO + c_axis_scenario(duration='duration = "0 s"'), "c_axis[0].duration"),
    ("c-axis-duration-not-a-multiple", SCENARIO + c_axis_scenario(duration='duration = "90 s"'), "c_axis[0].duration"),
    ("c-axis-outlasts-run", SCENARIO + c_axis_scenario(duration='duration = "1 h"'), "c_axis"),
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
    ("interferometer-spacing-below-a-millimetre", _ax("", "", LASER + 'spacing = "1e-6 mm"\n'), "interferometer.spacing"),
    # the last target 0.5 mm after the one before it: [0, 0.5 mm], and [0, 10, 10.5 mm] at 10 mm spacing
    ("interferometer-targets-half-a-millimetre", _ax("", "", LASER + 'targets = ["0 mm", "0.5 mm"]\n'),
     "interferometer.targets"),
    ("interferometer-last-target-too-close", _ax("", "", LASER + 'targets = ["0 mm", "10.5 mm"]\n'),
     "interferometer.targets"),
    ("probing-not-cold-first", _ax("", "", PROBE.replace('"0 min", ', '')), "probing.times"),
    ("probing-off-grid", _ax("", "", PROBE.replace('"10 min"', '"90 s"')), "probing.times"),
    ("probing-datum-outside-travel", _ax("", "", PROBE.replace('[["100 mm"', '[["600 mm"')), "probing.datums[0]"),
    ("probing-datum-repeated", _ax("", "", PROBE.replace('"50 mm"]]', '"50 mm"], ["100 mm", "100 mm", "0.05 m"]]')),
     "probing.datums[1]"),
    ("probing-datum-two-coordinates", _ax("", "", PROBE.replace(', "50 mm"]]', ']]')), "probing.datums"),
    ("probing-datum-no-unit", _ax("", "", PROBE.replace('"50 mm"]]', '"50"]]')), "probing.datums"),
    ("probing-unknown-key", _ax("", "", PROBE + 'stylus = "50 mm"\n'), "probing.stylus"),
    # a semi-closed axis's interferometer needs the axis's motion (its screw); closed-form durations; limits
    ("interferometer-axis-never-moved", SCENARIO + LASER, "interferometer.axis"),
    ("axis-count-1e9-longer-than-scenario", _ax('duration = "30 min"', 'count = 1000000000'), "axis[0].move"),
    ("axis-feed-1000-m-per-s", _ax('"20 mm/s"', '"1000 m/s"'), "axis[0].move[0].feed"),
    ("axis-acceleration-1e9", _ax('"10 mm/s2"', '"1e9 m/s2"'), "axis[0].move[0].acceleration"),
    ("axis-move-feed-beyond-limit", _ax('"30 min"', '"20 min"', '[[axis.move]]\nkind = "move"\nto = "100 mm"\n'
                                                             'feed = "3 m/s"\nacceleration = "1 m/s2"\n'),
     "axis[0].move[1].feed"),
    ("axis-table-280-m-per-s", SCENARIO + '\n[[axis]]\nname = "Y"\n[[axis.move]]\nkind = "table"\n'
                                          'times = ["0 s", "1 ms"]\npositions = ["0 mm", "280 mm"]\n',
     "axis[0].move[0].positions"),
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
    # on the machine that has a C axis (on cframe-vmc the same text is refused for having none,
    # whose field also names c_axis: the rule itself was not reached there)
    ("c-axis-outlasts-run-on-a-c-axis", edited(SPEED, 'speed = "3000 rpm"') + c_axis_scenario(duration='duration = "1 h"'),
     "c_axis"),
]

# the scenario edits also run through compare/diagnose --scenario (a sample: they share the reader)
SCENARIO_EDITS_VIA_MEASUREMENT = ["ambient-below-absolute-zero", "speed-beyond-machine", "speed-1e300-krpm",
                                  "interval-1-ns", "duration-1e300-s", "malformed-toml", "unknown-top-key"]
