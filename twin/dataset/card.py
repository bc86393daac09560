"""The index and the dataset card of a dataset folder.

``index.csv`` and ``index.parquet``: one row per planned case, in plan order: ``hash``, ``file``
(relative to the folder), ``split``, ``built`` (its file is whole), ``bytes``, then the case's
machine, family, draw, grid point, noise seed, scenario descriptors and parameter values (SI, the
unit in the column name, e.g. ``spindle_motor.power [W]``).

``card.json`` and ``README.md``: the spec as written, the package and format version, counts per
split and family, sizes, the schema of a case file (every variable with its dimensions, unit and
role), what is truth and what is measured, and the solver's reported error (:func:`solver_error`).
"""

from __future__ import annotations

import json
from pathlib import Path

from twin.dataset.plan import FORMAT, Case, check_cases, spec_key
from twin.dataset.spec import DatasetSpec
from twin.dataset.runner import CASES, is_whole
from twin.errors import InputError, describe
from twin.io.atomic import atomic_write_all, check_writable, text_writer
from twin.io.paths import output_folder
from twin.version import package_version

INDEX_FILES = ("index.csv", "index.parquet", "card.json", "README.md")
INPUTS = ("spindle_speed", "ambient_temperature")
TRUTH_NOTE = ("Truth is what the model computed, noise-free: variables ending in _true, the tool-point drift "
              "(drift) and the heat into the structure (heat_power). Measured is what a virtual instrument "
              "recorded (seeded noise, lag, quantisation, bias): temperature, probe, probe_drift, tilt and "
              "camera frames. Inputs are what drives the machine: spindle_speed and ambient_temperature.")


# the solver's error attributes of a result ({observer group: [value per output]} in SI, m or degC)
ERROR_ATTRS = {"rom_error_bound": "verified bound of the reduced model (guaranteed, pessimistic)",
               "rom_error_estimate": "estimate of the reduced model (against the model without its last two "
                                     "blocks; not guaranteed)",
               "solver_error_bound": "verified bound of the iterative solver (guaranteed, pessimistic)"}
ERROR_UNITS = {"drift": ("um", 1e6), "probes": ("um", 1e6), "temperature": ("K", 1.0)}
ERROR_NOTE = ("Largest over the built cases and the group's outputs. The reduced model's bound holds for any "
              "input; measured once on the C-frame's test cases (README, 'Scale', not on this dataset) it was "
              "pessimistic by about 1e4 on temperatures, and the estimate was within a factor 1-15 of the true "
              "error on the drift outputs but underestimated single temperature sensors by up to 1.6x. The "
              "direct solver reports nothing: it is exact to round-off.")


def solver_error(folder: Path, rows: list[dict]) -> dict:
    """{attribute: {group: {"max": value, "units": u}}} of :data:`ERROR_ATTRS` over the built cases
    (drift and probes in um, temperature in K; other groups left out); empty for the direct solver."""
    import h5py

    out: dict = {}
    for r in rows:
        if not r["built"]:
            continue
        with h5py.File(Path(folder) / r["file"], "r") as f:
            attrs = {k: f.attrs[k] for k in ERROR_ATTRS if k in f.attrs}
        for key, text in attrs.items():
            for group, values in json.loads(text if isinstance(text, str) else text.decode()).items():
                if group not in ERROR_UNITS or not values:
                    continue
                unit, factor = ERROR_UNITS[group]
                entry = out.setdefault(key, {}).setdefault(group, {"max": 0.0, "units": unit})
                entry["max"] = max(entry["max"], factor * max(abs(float(v)) for v in values))
    return out


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


def check_dataset_folder(folder: Path, field: str = "-o") -> None:
    """An existing output ``folder`` holding one of :data:`INDEX_FILES` must hold a twin dataset
    (a ``card.json`` of one: a JSON object with this module's ``format`` and ``spec``), whose
    index and card a build rewrites; else :class:`InputError`: a user's own ``README.md`` or
    ``index.csv`` in ``-o .`` was replaced without notice."""
    folder = Path(folder)
    present = [name for name in INDEX_FILES if (folder / name).exists()]
    if not present:
        return
    try:
        ours = json.loads((folder / "card.json").read_text(encoding="utf-8"))
        ours = isinstance(ours, dict) and "format" in ours and "spec" in ours
    except (OSError, ValueError):
        ours = False
    if not ours:
        raise InputError(str(folder / present[0]), field, "exists and is not a twin dataset's (no dataset card.json "
                                                         "beside it): a build would replace it; choose an empty "
                                                         "folder or an earlier build of a dataset")


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
            "solver_error": solver_error(folder, rows), "solver_error_note": ERROR_NOTE,
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
              "## Truth and measured", "", c["truth_and_measured"], "", "## Solver error", ""]
    if c["solver_error"]:
        lines += ["| reported | " + " | ".join(ERROR_UNITS) + " |", "|---|" + "---:|" * len(ERROR_UNITS)]
        for key, groups in c["solver_error"].items():
            cells = [f"{groups[g]['max']:.3g} {groups[g]['units']}" if g in groups else "" for g in ERROR_UNITS]
            lines.append(f"| `{key}`: {ERROR_ATTRS[key]} | " + " | ".join(cells) + " |")
        lines += ["", c["solver_error_note"]]
    else:
        lines += ["None reported (the direct solver is exact to round-off; or no case built yet)."]
    lines += ["", "## Schema of a case file", ""]
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
    returns the index rows. ``cases`` are of ``spec``'s plan (:func:`twin.dataset.plan.plan`,
    all or some: a card never mixes a spec with another's cases); the four files are checked before any is
    written and renamed into place only when all four are whole (:func:`twin.io.atomic.atomic_write_all`),
    so a failure (a full disk at the third) leaves the set as it was."""
    import pandas as pd

    cases = check_cases(cases, "write_index")
    if not isinstance(spec, DatasetSpec):
        raise InputError("write_index", "spec", f"expected a dataset spec (twin.dataset.load_spec), got {describe(spec)}")
    key = spec_key(spec)
    if any(c.spec_key != key for c in cases):   # planned from this spec (replanning it took 3 ms a case)
        raise InputError("write_index", "cases", f"are not of the plan of spec {spec.name!r} (twin.dataset.plan.plan(spec))")
    folder = output_folder(folder, "folder")
    for name in INDEX_FILES:
        check_writable(folder / name, "index")
    rows = index_rows(cases, folder)
    c = card(spec, rows, folder, last_build)
    frame = pd.DataFrame(rows)
    atomic_write_all([(folder / "index.csv", lambda tmp: frame.to_csv(tmp, index=False)),
                      (folder / "index.parquet", lambda tmp: frame.to_parquet(tmp, index=False, engine="pyarrow")),
                      (folder / "card.json", text_writer(json.dumps(c, indent=2, sort_keys=False) + "\n")),
                      (folder / "README.md", text_writer(markdown(c)))], "index")
    return rows
