"""The bad inputs of the fuzz suite (``tests/test_fuzz_inputs.py``), generated from tables.

Each :class:`Case` is one command line run in a fresh folder holding good copies of the files it
needs (:func:`good_files`: a scenario, a CSV measurement with its mapping, a twin result, two
learning tables), one thing made bad, and the error it must give: the source (a path, ``{d}``
standing for the case's folder, or ``command line``) and a part of the field. Add a command, an
option or a file format by adding rows:

* :data:`INPUTS` - every argument that names an input file; each gets every bad path of
  :func:`bad_input_paths` (missing, a folder, a pipe, a device, binary, empty, unreadable,
  Latin-1);
* :data:`OUTPUTS` and :data:`FOLDERS` - every argument that names an output file or folder; each
  gets every bad output of :func:`bad_output_paths` / :func:`bad_output_folders`;
* :data:`SCENARIO_EDITS`, :data:`MAPPING_EDITS`, :data:`CSV_EDITS`, :data:`RESULT_EDITS`,
  :data:`TABLE_EDITS` - bad contents of each file kind, each run through the commands that read it;
* :data:`OPTION_CASES` - bad option values and repeated options, per command.

Later issues add theirs here as rows: dataset specs (a ``twin dataset`` row in :data:`INPUTS`
and a table of spec edits), axis scenarios (more :data:`SCENARIO_EDITS`), camera settings
(:data:`OPTION_CASES`) and custom effects (``--effects-file``: an :data:`INPUTS` row and its edits).
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

CLI = "command line"
SITES = ("motor", "column_side", "bed_front")
PROBES = ("X1", "X2", "Y1", "Y2", "Z")
ROWS = 30   # one sample a minute: 29 min, within the 30-min scenario

SCENARIO = """name = "short"
sample_interval = "60 s"
[ambient]
temperature = "20 degC"
[[spindle]]
speed = "6000 rpm"
duration = "10 min"
[[spindle]]
speed = "0 rpm"
duration = "20 min"
"""


def measurement_csv(edit: Callable | None = None) -> str:
    """The good CSV measurement (``edit(cols)`` changes the columns, a dict of arrays, first)."""
    t = np.arange(ROWS) * 60.0
    rise = 1 - np.exp(-t / 900.0)
    cols = {"t_s": t, "spindle_rpm": np.where(t < 600, 6000.0, 0.0), "room_degC": 20 + 0.001 * t / 60}
    cols.update({f"T_{s}": 20 + (3 - k) * rise for k, s in enumerate(SITES)})
    cols.update({f"probe_{p}_um": (k + 1) * 2.0 * rise for k, p in enumerate(PROBES)})
    if edit:
        edit(cols)
    lines = [",".join(cols)] + [",".join(_cell(cols[c][i]) for c in cols) for i in range(len(cols["t_s"]))]
    return "\n".join(lines) + "\n"


def _cell(v) -> str:
    return v if isinstance(v, str) else f"{v:.6g}"


MAPPING = "\n".join(
    ['machine = "cframe-vmc"', '[columns.t_s]\nrole = "time"\nunit = "s"',
     '[columns.spindle_rpm]\nrole = "spindle_speed"\nunit = "rpm"',
     '[columns.room_degC]\nrole = "ambient_temperature"\nunit = "degC"']
    + [f'[columns.T_{s}]\nrole = "temperature"\nsite = "{s}"\nunit = "degC"' for s in SITES]
    + [f'[columns.probe_{p}_um]\nrole = "probe"\nprobe = "{p}"\nunit = "um"' for p in PROBES]) + "\n"


def result_dataset(n: int = ROWS):
    """A small dataset with the twin result's schema (for plot, and as a NetCDF measurement)."""
    import xarray as xr
    from geometries import build_machine

    m = build_machine("cframe-vmc")
    pts = [m.point(s) for s in SITES]
    t = np.arange(n) * 60.0
    rise = 1 - np.exp(-t / 900.0)
    temp = np.column_stack([20 + (3 - k) * rise for k in range(len(SITES))])
    probe = np.column_stack([(k + 1) * 2.0 * rise for k in range(len(PROBES))])
    drift = np.column_stack([0.1 * rise, 5 * rise, 10 * rise])
    tilt = np.column_stack([rise, -rise])

    def v(dims, a, unit):
        return dims, a, {"units": unit}

    data = {"spindle_speed": v("time", np.where(t < 600, 6000.0, 0.0), "rpm"),
            "ambient_temperature": v("time", np.full(n, 20.0), "degC"),
            "temperature": v(("time", "sensor"), temp, "degC"), "temperature_true": v(("time", "sensor"), temp, "degC"),
            "drift": v(("time", "axis"), drift, "um"), "probe": v(("time", "probe_id"), probe, "um"),
            "probe_true": v(("time", "probe_id"), probe, "um"), "probe_drift": v(("time", "axis"), drift, "um"),
            "tilt": v(("time", "rotation"), tilt, "urad"), "tilt_true": v(("time", "rotation"), tilt, "urad")}
    coords = {"time": ("time", t, {"units": "s"}), "sensor": list(SITES),
              "x": ("sensor", [p.xyz[0] for p in pts]), "y": ("sensor", [p.xyz[1] for p in pts]),
              "z": ("sensor", [p.xyz[2] for p in pts]), "part": ("sensor", [p.part for p in pts]),
              "axis": ["X", "Y", "Z"], "rotation": ["A", "B"], "probe_id": list(PROBES)}
    return xr.Dataset(data, coords, {"machine": "cframe-vmc", "title": "fuzz"})


def netcdf_bytes(ds) -> bytes:
    buf = io.BytesIO()
    ds.to_netcdf(buf, engine="h5netcdf")
    return buf.getvalue()


def table_csv(n: int = 40, seed: int = 0, edit: Callable | None = None) -> str:
    """A learning table: time [s], four temperatures, a drift linear in two of them
    (``edit(rows)`` changes the rows of strings, header first)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 10.0
    heat = 8.0 * (1.0 - np.exp(-t / 300.0))
    T = np.column_stack([20 + heat, 20 + 0.5 * heat, 20 + 0.2 * np.sin(t / 50), 20 + 0.3 * heat])
    T += 0.05 * rng.normal(size=T.shape)
    drift = 3.0 * (T[:, 0] - 20) - 1.5 * (T[:, 1] - 20) + 0.1 * rng.normal(size=n)
    rows = [["time", "T1", "T2", "T3", "T4", "drift_z"]]
    rows += [[f"{t[i]:g}", *(f"{v:.5f}" for v in T[i]), f"{drift[i]:.5f}"] for i in range(n)]
    if edit:
        edit(rows)
    return "\n".join(",".join(r) for r in rows) + "\n"


TEXT = {"short.toml": SCENARIO, "m.csv": measurement_csv(), "m.toml": MAPPING, "train.csv": table_csv(),
        "test.csv": table_csv(seed=1)}


def good_files() -> dict[str, bytes]:
    """The good files every case starts from (name -> bytes)."""
    return {**{k: v.encode() for k, v in TEXT.items()}, "r.nc": netcdf_bytes(result_dataset())}


@dataclass
class Case:
    """One bad command line: ``argv`` (``{d}``: the case folder); ``files`` to write over the good
    ones (name -> str, bytes or a callable returning bytes); ``setup(folder)`` for links, pipes,
    folders; the expected error's ``source`` (``{d}`` allowed) and a part of its ``field``."""

    id: str
    argv: list[str]
    source: str
    field: str
    files: dict = field(default_factory=dict)
    setup: Callable | None = None
    root_skip: bool = False   # permission cases that root does not feel


# --------------------------------------------------------------------------------- the commands
SIM = ["simulate", "cframe-vmc", "{d}/short.toml", "-o", "{d}/out.nc", "--mesh", "coarse"]
PLOT = ["plot", "{d}/r.nc", "-o", "{d}/pic.png"]
COMPARE = ["compare", "{d}/m.csv", "--mesh", "coarse"]
COMPARE_NC = ["compare", "{d}/r.nc", "--mesh", "coarse"]
DIAGNOSE = ["diagnose", "{d}/m.csv", "--json", "{d}/d.json", "--report", "{d}/report", "--error-mesh", "none"]
LEARN = ["learn", "--train", "{d}/train.csv", "--test", "{d}/test.csv", "--target", "drift_z", "--learner", "mlr",
         "-o", "{d}/scores.csv"]
DEMO = ["demo", "-o", "{d}/demo-out", "--no-story", "--mesh", "coarse"]


def swap(argv: list[str], old: str, new: str) -> list[str]:
    assert old in argv, (old, argv)
    return [new if a == old else a for a in argv]


def _mkdir(name):
    return lambda d: os.mkdir(os.path.join(d, name))


def _fifo(name):
    return lambda d: os.mkfifo(os.path.join(d, name))


def _chmod(name, mode):
    return lambda d: os.chmod(os.path.join(d, name), mode)


def _symlink(target, name):
    return lambda d: os.symlink(os.path.join(d, target), os.path.join(d, name))


def _hardlink(target, name):
    return lambda d: os.link(os.path.join(d, target), os.path.join(d, name))


def _plain(name):
    def make(d):
        with open(os.path.join(d, name), "w") as fh:
            fh.write("not a folder\n")
    return make


def _locked(name):
    return lambda d: (os.mkdir(os.path.join(d, name)), os.chmod(os.path.join(d, name), 0o555))


def _latin1(name: str) -> bytes:
    """The good text file with a Latin-1 character (a degree sign) on its first line."""
    first, rest = TEXT[name].split("\n", 1)
    return (first + ("  # \xb0C" if name.endswith(".toml") else "\xb0C") + "\n" + rest).encode("latin-1")


# ---------------------------------------------------------------------------- bad input paths
# every argument naming an input file: (id, argv, its value in argv, the good file, text?)
INPUTS = [
    ("simulate.scenario", SIM, "{d}/short.toml", "short.toml", True),
    ("plot.result", PLOT, "{d}/r.nc", "r.nc", False),
    ("compare.measurement", COMPARE, "{d}/m.csv", "m.csv", True),
    ("compare.mapping", COMPARE + ["--mapping", "{d}/m.toml"], "{d}/m.toml", "m.toml", True),
    ("compare.scenario", COMPARE + ["--scenario", "{d}/short.toml"], "{d}/short.toml", "short.toml", True),
    ("compare.netcdf", COMPARE_NC, "{d}/r.nc", "r.nc", False),
    ("diagnose.measurement", DIAGNOSE, "{d}/m.csv", "m.csv", True),
    ("diagnose.scenario", DIAGNOSE + ["--scenario", "{d}/short.toml"], "{d}/short.toml", "short.toml", True),
    ("learn.train", LEARN, "{d}/train.csv", "train.csv", True),
    ("learn.test", LEARN, "{d}/test.csv", "test.csv", True),
]


def bad_input_paths(cid, argv, arg, good, text) -> list[Case]:
    """Every way an input path can be bad, for one argument."""
    suffix = os.path.splitext(good)[1]
    miss, folder, pipe = f"{{d}}/missing{suffix}", f"{{d}}/folder{suffix}", f"{{d}}/pipe{suffix}"
    out = [Case(f"{cid}:missing", swap(argv, arg, miss), miss, ""),
           Case(f"{cid}:folder", swap(argv, arg, folder), folder, "", setup=_mkdir(f"folder{suffix}")),
           Case(f"{cid}:pipe", swap(argv, arg, pipe), pipe, "", setup=_fifo(f"pipe{suffix}")),
           Case(f"{cid}:device", swap(argv, arg, "/dev/null"), "/dev/null", ""),
           Case(f"{cid}:name-too-long", swap(argv, arg, f"{{d}}/{'n' * 300}{suffix}"), f"{{d}}/{'n' * 300}{suffix}", ""),
           Case(f"{cid}:below-a-file", swap(argv, arg, f"{{d}}/{good}/x{suffix}"), f"{{d}}/{good}/x{suffix}", ""),
           Case(f"{cid}:binary", argv, arg, "", files={good: bytes(range(256)) * 4}),
           Case(f"{cid}:empty", argv, arg, "", files={good: b""}),
           Case(f"{cid}:unreadable", argv, arg, "", setup=_chmod(good, 0), root_skip=True)]
    if text:
        out.append(Case(f"{cid}:latin-1", argv, arg, "", files={good: _latin1(good)}))
    return out


# --------------------------------------------------------------------------- bad output paths
# every argument naming an output file: (id, argv, its value in argv, its suffix, an input of the command)
OUTPUTS = [
    ("simulate.o", SIM, "{d}/out.nc", ".nc", "short.toml"),
    ("simulate.field", SIM + ["--field", "{d}/hot.vtu"], "{d}/hot.vtu", ".vtu", "short.toml"),
    ("plot.o", PLOT, "{d}/pic.png", ".png", "r.nc"),
    ("diagnose.json", DIAGNOSE, "{d}/d.json", ".json", "m.csv"),
    ("learn.o", LEARN, "{d}/scores.csv", ".csv", "train.csv"),
]


def bad_output_paths(cid, argv, arg, suffix, an_input) -> list[Case]:
    """Every way an output path can be bad, for one argument."""
    def at(name):
        return swap(argv, arg, f"{{d}}/{name}")

    return [
        Case(f"{cid}:is-input", at(an_input), f"{{d}}/{an_input}", ""),
        Case(f"{cid}:link-to-input", at(f"link{suffix}"), f"{{d}}/link{suffix}", "", setup=_symlink(an_input, f"link{suffix}")),
        Case(f"{cid}:hardlink-to-input", at(f"hard{suffix}"), f"{{d}}/hard{suffix}", "",
             setup=_hardlink(an_input, f"hard{suffix}")),
        Case(f"{cid}:folder", at(f"folder{suffix}"), f"{{d}}/folder{suffix}", "", setup=_mkdir(f"folder{suffix}")),
        Case(f"{cid}:pipe", at(f"pipe{suffix}"), f"{{d}}/pipe{suffix}", "", setup=_fifo(f"pipe{suffix}")),
        Case(f"{cid}:device", swap(argv, arg, "/dev/null"), "/dev/null", ""),
        Case(f"{cid}:link-to-device", at(f"dev{suffix}"), f"{{d}}/dev{suffix}", "",
             setup=lambda d: os.symlink("/dev/null", os.path.join(d, f"dev{suffix}"))),
        Case(f"{cid}:no-folder", at(f"nope/out{suffix}"), f"{{d}}/nope/out{suffix}", ""),
        Case(f"{cid}:folder-is-a-file", at(f"plain/out{suffix}"), f"{{d}}/plain/out{suffix}", "", setup=_plain("plain")),
        Case(f"{cid}:suffix", at("out.xyz"), "{d}/out.xyz", ""),
        Case(f"{cid}:name-too-long", at("n" * 300 + suffix), f"{{d}}/{'n' * 300}{suffix}", ""),
        Case(f"{cid}:link-loop", at(f"loop{suffix}"), f"{{d}}/loop{suffix}", "",
             setup=lambda d: os.symlink(os.path.join(d, f"loop{suffix}"), os.path.join(d, f"loop{suffix}"))),
        Case(f"{cid}:the-folder-itself", swap(argv, arg, "{d}/"), "{d}", ""),
        Case(f"{cid}:read-only", argv, arg, "", setup=_chmod_new(arg, 0o444), root_skip=True),
        Case(f"{cid}:read-only-folder", at(f"locked/out{suffix}"), f"{{d}}/locked/out{suffix}", "",
             setup=_locked("locked"), root_skip=True),
    ]


def _chmod_new(arg: str, mode: int):
    name = arg.removeprefix("{d}/")

    def make(d):
        _plain(name)(d)
        os.chmod(os.path.join(d, name), mode)
    return make


# every argument naming an output folder: (id, argv, its value in argv)
FOLDERS = [
    ("diagnose.report", DIAGNOSE, "{d}/report"),
    ("demo.o", DEMO, "{d}/demo-out"),
]


def bad_output_folders(cid, argv, arg) -> list[Case]:
    def at(name):
        return swap(argv, arg, f"{{d}}/{name}")

    return [
        Case(f"{cid}:is-a-file", at("plain"), "{d}/plain", "", setup=_plain("plain")),
        Case(f"{cid}:is-an-input", at("m.csv" if "diagnose" in cid else "short.toml"),
             "{d}/m.csv" if "diagnose" in cid else "{d}/short.toml", ""),
        Case(f"{cid}:no-parent", at("nope/out"), "{d}/nope/out", ""),
        Case(f"{cid}:device", swap(argv, arg, "/dev/null"), "/dev/null", ""),
        Case(f"{cid}:pipe", at("pipe"), "{d}/pipe", "", setup=_fifo("pipe")),
        Case(f"{cid}:content-is-a-folder", at("out"), "{d}/out/index.html" if "diagnose" in cid
             else "{d}/out/drift.png", "", setup=lambda d: os.makedirs(
                 os.path.join(d, "out", "index.html" if "diagnose" in cid else "drift.png"))),
        Case(f"{cid}:read-only", at("locked"), "{d}/locked", "", setup=_locked("locked"), root_skip=True),
    ]


# ------------------------------------------------------------------------- bad scenario files
def _sc(old: str, new: str, count: int = 1) -> str:
    assert old in SCENARIO, old
    return SCENARIO.replace(old, new, count)


AMBIENT = '[ambient]\ntemperature = "20 degC"'
DAILY = '[ambient]\nkind = "daily"\nmean = "20 degC"\namplitude = "3 K"'
TABLE = '[ambient]\nkind = "table"\ntimes = ["0 h", "1 h"]\ntemperatures = ["20 degC", "21 degC"]'
SPEED = 'speed = "6000 rpm"'
DURATION = 'duration = "10 min"'
INTERVAL = 'sample_interval = "60 s"'

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
    ("malformed-toml", SCENARIO.replace("[ambient]", "[ambient"), "toml"),
    ("duplicate-key", _sc(INTERVAL, INTERVAL + "\n" + INTERVAL), "toml"),
]

# the scenario edits also run through compare/diagnose --scenario (a sample: they share the reader)
SCENARIO_EDITS_VIA_MEASUREMENT = ["ambient-below-absolute-zero", "speed-beyond-machine", "speed-1e300-krpm",
                                  "interval-1-ns", "duration-1e300-s", "malformed-toml", "unknown-top-key"]

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
    ("learn:train-twice", LEARN + ["--train", "{d}/test.csv"], CLI, "--train"),
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

# files an option case needs changed (id -> files)
OPTION_FILES = {
    "compare:mapping-missing": {"m.toml": None},
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
    for cid, text, fld in MAPPING_EDITS:
        cases.append(Case(f"compare.mapping:{cid}", COMPARE, "{d}/m.toml", fld, files={"m.toml": text}))
    for cid, text, fld in CSV_EDITS:
        cases.append(Case(f"compare.csv:{cid}", COMPARE, "{d}/m.csv", fld, files={"m.csv": text}))
        if cid in CSV_EDITS_VIA_DIAGNOSE:
            cases.append(Case(f"diagnose.csv:{cid}", DIAGNOSE, "{d}/m.csv", fld, files={"m.csv": text}))
    for cid, make, plot_field, compare_field in RESULT_EDITS:
        if plot_field is not None:
            cases.append(Case(f"plot.result:{cid}", PLOT, "{d}/r.nc", plot_field, files={"r.nc": make}))
        if compare_field is not None:
            cases.append(Case(f"compare.netcdf:{cid}", COMPARE_NC, "{d}/r.nc", compare_field, files={"r.nc": make}))
    for cid, name, text, fld in TABLE_EDITS:
        cases.append(Case(f"learn.table:{cid}", LEARN, f"{{d}}/{name}", fld, files={name: text}))
    for cid, argv, source, fld in OPTION_CASES:
        cases.append(Case(cid, argv, source, fld, files=OPTION_FILES.get(cid, {})))
    return cases
