"""The index and the dataset card of a dataset folder.

``index.csv`` and ``index.parquet``: one row per planned case, in plan order: ``hash``, ``file``
(relative to the folder), ``split``, ``built`` (its file is whole), ``bytes``, then the case's
machine, family, draw, grid point, noise seed, scenario descriptors and parameter values (SI, the
unit in the column name, e.g. ``spindle_motor.power [W]``).

``card.json`` and ``README.md``: the spec as written, the package and format version, counts per
split and family, sizes, the schema of a case file (every variable with its dimensions, unit and
role) and what is truth and what is measured.
"""

from __future__ import annotations

import json
from pathlib import Path

from twin.dataset.plan import FORMAT, Case
from twin.dataset.runner import CASES, is_whole
from twin.io.atomic import atomic_write, atomic_write_text
from twin.io.results import package_version

INDEX_FILES = ("index.csv", "index.parquet", "card.json", "README.md")
INPUTS = ("spindle_speed", "ambient_temperature")
TRUTH_NOTE = ("Truth is what the model computed, noise-free: variables ending in _true, the tool-point drift "
              "(drift) and the heat into the structure (heat_power). Measured is what a virtual instrument "
              "recorded (seeded noise, lag, quantisation, bias): temperature, probe, probe_drift, tilt and "
              "camera frames. Inputs are what drives the machine: spindle_speed and ambient_temperature.")


def role(name: str) -> str:
    """``input``, ``truth`` or ``measured`` for a case-file variable (the rule of :data:`TRUTH_NOTE`)."""
    if name in INPUTS:
        return "input"
    if name.endswith("_true") or name in ("drift", "heat_power"):
        return "truth"
    return "measured"


def index_rows(cases: list[Case], folder: Path) -> list[dict]:
    """One row per case (module doc); ``built`` and ``bytes`` from the files now in ``folder``."""
    rows = []
    for c in cases:
        path = Path(folder) / CASES / c.file
        whole = is_whole(path, c.hash)
        rows.append({"hash": c.hash, "file": f"{CASES}/{c.file}", "split": c.split, "built": whole,
                     "bytes": path.stat().st_size if whole else 0, **c.info})
    return rows


def schema(path: Path | None) -> list[dict]:
    """The variables of one case file: name, dims, units, long_name, role (empty without a file)."""
    if path is None:
        return []
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        out = []
        for name, var in {**ds.coords, **ds.data_vars}.items():
            out.append({"name": str(name), "kind": "coordinate" if name in ds.coords else "variable",
                        "dims": list(var.dims), "units": str(var.attrs.get("units", "")),
                        "long_name": str(var.attrs.get("long_name", "")),
                        "role": "coordinate" if name in ds.coords else role(str(name))})
    return out


def card(spec, rows: list[dict], folder: Path, last_build: dict | None = None) -> dict:
    """The dataset card as a JSON-ready dict (the schema read from the first built case in ``folder``)."""
    def counts(key):
        out = {}
        for r in rows:
            c = out.setdefault(r[key], {"planned": 0, "built": 0})
            c["planned"] += 1
            c["built"] += int(r["built"])
        return out

    built = [r for r in rows if r["built"]]
    total = sum(r["bytes"] for r in built)
    return {"name": spec.name, "description": spec.description, "package_version": package_version(),
            "format": FORMAT, "spec_file": Path(spec.source).name, "spec": spec.text,
            "machines": list(spec.machines), "mesh": spec.mesh, "solver": spec.solver, "seed": spec.seed,
            "counts": {"planned": len(rows), "built": len(built), "by_split": counts("split"),
                       "by_family": counts("family")},
            "sizes": {"bytes": total, "mean_case_bytes": total // len(built) if built else 0},
            "files": {"cases": f"{CASES}/<hash>.nc (one NetCDF per case, named by the hash of its content)",
                      "index": "index.csv, index.parquet (one row per case)", "card": "card.json, README.md"},
            "schema": schema(Path(folder) / built[0]["file"] if built else None),
            "truth_and_measured": TRUTH_NOTE,
            "last_build": last_build or {}}


def markdown(c: dict) -> str:
    """The card as README.md."""
    lines = [f"# Dataset {c['name']}", "", c["description"] or "(no description)", "",
             f"Built by thermal-twin {c['package_version']} (dataset format {c['format']}) from `{c['spec_file']}` "
             f"(below): machines {', '.join(c['machines'])}, mesh {c['mesh']}, solver {c['solver']}, seed {c['seed']}.",
             "", "## Counts", "",
             f"{c['counts']['built']} of {c['counts']['planned']} cases built, {c['sizes']['bytes'] / 1e6:.2f} MB "
             f"({c['sizes']['mean_case_bytes'] / 1e3:.0f} kB per case).", "",
             "| split | planned | built |", "|---|---:|---:|"]
    lines += [f"| {k} | {v['planned']} | {v['built']} |" for k, v in c["counts"]["by_split"].items()]
    lines += ["", "| family | planned | built |", "|---|---:|---:|"]
    lines += [f"| {k} | {v['planned']} | {v['built']} |" for k, v in c["counts"]["by_family"].items()]
    lines += ["", "## Layout", "",
              "- `cases/<hash>.nc`: one NetCDF file per case, named by the hash of everything that defines it",
              "- `index.csv`, `index.parquet`: one row per case (hash, file, split, built, parameters with units)",
              "- `card.json`, `README.md`: this card", "",
              "Read all cases: `xarray.open_mfdataset(\"cases/*.nc\", combine=\"nested\", concat_dim=\"case\")`; "
              "rebuild or resume: `twin dataset SPEC.toml -o DIR` (finished cases are skipped).", "",
              "## Truth and measured", "", c["truth_and_measured"], "", "## Schema of a case file", ""]
    if c["schema"]:
        lines += ["| name | kind | dims | units | role | long name |", "|---|---|---|---|---|---|"]
        lines += [f"| {s['name']} | {s['kind']} | {', '.join(s['dims'])} | {s['units']} | {s['role']} | "
                  f"{s['long_name']} |" for s in c["schema"]]
    else:
        lines += ["(no case built yet)"]
    lines += ["", "## Spec", "", "```toml", c["spec"].rstrip(), "```", ""]
    return "\n".join(lines)


def write_index(spec, cases: list[Case], folder: Path, last_build: dict | None = None) -> list[dict]:
    """Write index.csv, index.parquet, card.json and README.md into ``folder`` (atomically, each);
    returns the index rows."""
    import pandas as pd

    folder = Path(folder)
    rows = index_rows(cases, folder)
    c = card(spec, rows, folder, last_build)
    frame = pd.DataFrame(rows)
    atomic_write(folder / "index.csv", lambda tmp: frame.to_csv(tmp, index=False), "index")
    atomic_write(folder / "index.parquet", lambda tmp: frame.to_parquet(tmp, index=False, engine="pyarrow"), "index")
    atomic_write_text(folder / "card.json", json.dumps(c, indent=2, sort_keys=False) + "\n", "card")
    atomic_write_text(folder / "README.md", markdown(c), "card")
    return rows
