"""The fuzz suite's good files, its commands and the bad paths (``tests/fuzz_cases.py`` holds
the bad contents and options, ``tests/test_fuzz_inputs.py`` runs them).

Every case starts from good copies of :func:`good_files` (a scenario, a CSV measurement with its
mapping, a twin result, two learning tables) in a fresh folder. Every argument that names a file
is a row: :data:`INPUTS` (each gets every bad path of :func:`bad_input_paths`: missing, a folder, a
pipe, a device, a name too long, below a file, binary, empty, unreadable, Latin-1),
:data:`OUTPUTS` (:func:`bad_output_paths`: an input, a link or hard link to one, a folder, a
pipe, a device or a link to one, no folder, a file as folder, a wrong suffix, a name too long, a
loop of links, read-only) and :data:`FOLDERS` (:func:`bad_output_folders`). A new command's file
argument is one row here.
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


EFFECTS_FILE = '[effects.pump]\nkind = "heat_source"\nregion = "saddle"\npower = "80 W"\n'

LASERS = ("Y", "Z", "A1", "A2")
GAUGES = ("FBG-1", "FBG-4")


def gantry_csv(edit: Callable | None = None) -> str:
    """The good gantry measurement: C-axis speed (its rhythm's duty in the mapping), room air, T1,
    the four laser triangulation sensors and two FBG gauges (compensated and raw)."""
    t = np.arange(ROWS) * 60.0
    rise = 1 - np.exp(-t / 900.0)
    cols = {"t_s": t, "c_rpm": np.where(t < 600, 2500.0, 0.0), "room_degC": 20 + 0.001 * t / 60,
            "T1": 20 + 3 * rise}
    cols.update({f"laser_{p}_um": -(k + 1) * 3.0 * rise for k, p in enumerate(LASERS)})
    cols.update({f"{g}_comp": (k + 1) * 5.0 * rise for k, g in enumerate(GAUGES)})
    cols.update({f"{g}_raw": (k + 1) * 5.0 * rise + 8.64 * 3 * rise for k, g in enumerate(GAUGES)})
    if edit:
        edit(cols)
    lines = [",".join(cols)] + [",".join(_cell(cols[c][i]) for c in cols) for i in range(len(cols["t_s"]))]
    return "\n".join(lines) + "\n"


GANTRY_MAPPING = "\n".join(
    ['machine = "gantry-ram"', '[columns.t_s]\nrole = "time"\nunit = "s"',
     '[columns.c_rpm]\nrole = "c_axis_speed"\nduty = 0.5\nunit = "rpm"',
     '[columns.room_degC]\nrole = "ambient_temperature"\nunit = "degC"',
     '[columns.T1]\nrole = "temperature"\nsite = "T1"\nunit = "degC"']
    + [f'[columns.laser_{p}_um]\nrole = "laser"\nlaser = "{p}"\nunit = "um"' for p in LASERS]
    + [f'[columns.{g}_{k}]\nrole = "strain"\ngauge = "{g}"\nreading = "{r}"\nunit = "um/m"'
       for g in GAUGES for k, r in (("comp", "compensated"), ("raw", "raw"))]) + "\n"

DATASET_SPEC = ('name = "tiny"\nmachines = ["cframe-vmc"]\nmesh = "coarse"\nseed = 1\n[parameters]\n'
                '"spindle_motor.power" = { uniform = ["40 W", "80 W"] }\n[[scenarios]]\nfamily = "ref"\n'
                'file = "short.toml"\ncases = 2\n')

# a scenario whose room air is a measured record (twin/io/room_csv.py), and the record
ROOM_CSV = "time [min],air [degC]\n0,20\n10,20.5\n20,21\n30,20.8\n"
ROOM_SCENARIO = SCENARIO.replace('[ambient]\ntemperature = "20 degC"', '[ambient]\nkind = "csv"\nfile = "room.csv"')

TEXT = {"room.csv": ROOM_CSV, "room.toml": ROOM_SCENARIO, "short.toml": SCENARIO, "ds.toml": DATASET_SPEC, "m.csv": measurement_csv(), "m.toml": MAPPING, "train.csv": table_csv(),
        "test.csv": table_csv(seed=1), "fx.toml": EFFECTS_FILE, "g.csv": gantry_csv(), "g.toml": GANTRY_MAPPING}


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
COMPARE_GANTRY = ["compare", "{d}/g.csv", "--mesh", "coarse"]
DIAGNOSE = ["diagnose", "{d}/m.csv", "--json", "{d}/d.json", "--report", "{d}/report", "--error-mesh", "none"]
LEARN = ["learn", "--train", "{d}/train.csv", "--test", "{d}/test.csv", "--target", "drift_z", "--learner", "mlr",
         "-o", "{d}/scores.csv"]
DEMO = ["demo", "-o", "{d}/demo-out", "--no-story", "--mesh", "coarse"]
DATASET = ["dataset", "{d}/ds.toml", "-o", "{d}/ds-out", "--dry-run"]
REPORT = ["report", "iso230-3", "{d}/r.nc", "-o", "{d}/rep"]
REPORT_CSV = ["report", "iso230-3", "{d}/m.csv", "-o", "{d}/rep"]


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
    ("compare.gantry-mapping", COMPARE_GANTRY + ["--mapping", "{d}/g.toml"], "{d}/g.toml", "g.toml", True),
    ("diagnose.scenario", DIAGNOSE + ["--scenario", "{d}/short.toml"], "{d}/short.toml", "short.toml", True),
    ("simulate.effects-file", SIM + ["--effects-file", "{d}/fx.toml"], "{d}/fx.toml", "fx.toml", True),
    ("compare.effects-file", COMPARE + ["--effects-file", "{d}/fx.toml"], "{d}/fx.toml", "fx.toml", True),
    ("diagnose.effects-file", DIAGNOSE + ["--effects-file", "{d}/fx.toml"], "{d}/fx.toml", "fx.toml", True),
    ("dataset.spec", DATASET, "{d}/ds.toml", "ds.toml", True),
    ("learn.train", LEARN, "{d}/train.csv", "train.csv", True),
    ("learn.test", LEARN, "{d}/test.csv", "test.csv", True),
    ("report.result", REPORT, "{d}/r.nc", "r.nc", False),
    ("report.measurement", REPORT_CSV, "{d}/m.csv", "m.csv", True),
    ("report.mapping", REPORT_CSV + ["--mapping", "{d}/m.toml"], "{d}/m.toml", "m.toml", True),
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
    ("learn.o-md", LEARN + ["-o", "{d}/board.md"], "{d}/board.md", ".md", "train.csv"),
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
    ("report.o", REPORT, "{d}/rep"),
]


def bad_output_folders(cid, argv, arg) -> list[Case]:
    def at(name):
        return swap(argv, arg, f"{{d}}/{name}")

    an_input = {"diagnose": "m.csv", "report": "r.nc"}.get(cid.split(".")[0], "short.toml")
    content = "drift.png" if cid.startswith("demo") else "index.html"
    return [
        Case(f"{cid}:is-a-file", at("plain"), "{d}/plain", "", setup=_plain("plain")),
        Case(f"{cid}:is-an-input", at(an_input), f"{{d}}/{an_input}", ""),
        Case(f"{cid}:no-parent", at("nope/out"), "{d}/nope/out", ""),
        Case(f"{cid}:device", swap(argv, arg, "/dev/null"), "/dev/null", ""),
        Case(f"{cid}:pipe", at("pipe"), "{d}/pipe", "", setup=_fifo("pipe")),
        Case(f"{cid}:content-is-a-folder", at("out"), f"{{d}}/out/{content}", "",
             setup=lambda d: os.makedirs(os.path.join(d, "out", content))),
        Case(f"{cid}:read-only", at("locked"), "{d}/locked", "", setup=_locked("locked"), root_skip=True),
    ]
