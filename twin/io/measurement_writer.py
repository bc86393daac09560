"""A twin result (or a measurement Dataset) written as a measurement: ``stem.csv`` with its column
mapping ``stem.toml``, the pair :func:`twin.io.measurement.read_measurement` reads back.

Columns: ``t_s`` [s], ``spindle_rpm`` [rpm], ``room_degC`` [degC], one ``T_<sensor>`` [degC] per
temperature sensor (at its named site of the machine when it is one, else at its position
``x, y, z`` [m] on its ``part`` with its ``name``), one ``probe_<id>_um`` [um] per ISO 230-3
probe, one ``laser_<id>_um`` [um] per laser triangulation sensor, one ``strain_<gauge>_um_m`` /
``strain_raw_<gauge>_um_m`` [um/m] per FBG gauge and reading, ``c_axis_rpm`` [rpm] with the
mapping's ``duty`` (one value while turning, as a mapping holds it) and one ``<axis>_mm`` [mm]
per logged axis position: every reading the measurement reader takes from a CSV. Readings a CSV
measurement cannot hold (the interferometer's runs, the probing cycles: a NetCDF measurement's)
are refused, never dropped. The Dataset is checked first as a measurement
(:func:`twin.io.measurement.check_measurement`:
finite, plausible values at two or more increasing times) and every sensor name must be one a
mapping can hold; nothing is written when a check fails, and each file appears whole
(:mod:`twin.io.atomic`).
"""

from __future__ import annotations

import csv
import io
import json
import re
from pathlib import Path

import numpy as np
import xarray as xr

from geometries import MACHINES, build_machine
from twin.errors import InputError, describe
from twin.io.atomic import atomic_write_all, output_folder, text_writer
from twin.io.mapping_columns import check_sensor_name
from twin.io.measurement import check_measurement, check_named_machine
from twin.io.paths import output_folder as checked_folder
from twin.units import clean

SOURCE = "write_measurement"
REQUIRED = ("spindle_speed", "ambient_temperature")
NOT_IN_CSV = ("positioning_error", "probing_error")     # readings only a NetCDF measurement holds


def write_measurement(ds, folder, stem: str, machine: str) -> tuple[Path, Path]:
    """Write ``ds`` as ``stem.csv`` + ``stem.toml`` in ``folder`` (created if missing, its parent
    must exist) for ``machine`` (a registered name, the Dataset's own when it names one); returns
    (csv path, toml path). Times are written to 1e-6 s, temperatures to 1e-4 K, probes and lasers to
    0.01 um, strains to 1e-3 um/m, axis positions to 1e-6 mm."""
    if not isinstance(machine, str):
        raise InputError(SOURCE, "machine", f"expected a machine's name ({', '.join(sorted(MACHINES))}), got "
                                            + (f"the built machine {machine.name!r}: pass its name"
                                               if isinstance(getattr(machine, "name", None), str) else describe(machine)))
    if machine not in MACHINES:
        raise InputError(SOURCE, "machine", f"unknown machine {machine!r}; known: {', '.join(sorted(MACHINES))}")
    mach = build_machine(machine)
    check_named_machine(ds, mach.name, SOURCE)
    if not isinstance(stem, str) or not stem.strip() or stem != Path(stem).name or stem.startswith("."):
        raise InputError(SOURCE, "stem", f"expected a file name without folders or a leading dot, got {describe(stem)}")
    if Path(stem).suffix.lower() in (".csv", ".toml"):       # m2.csv wrote m2.csv.csv and m2.csv.toml
        raise InputError(SOURCE, "stem", f"{stem!r} ends in {Path(stem).suffix}: give the name without it "
                                         f"({Path(stem).stem!r} writes {Path(stem).stem}.csv and {Path(stem).stem}.toml)")
    check_measurement(ds, mach, SOURCE)
    elsewhere = [v for v in NOT_IN_CSV if v in ds]
    if elsewhere:
        raise InputError(SOURCE, elsewhere[0], "a CSV measurement cannot hold it (a NetCDF measurement can): write "
                                               "the Dataset with to_netcdf, or drop the variable to write the rest")
    missing = [v for v in REQUIRED if v not in ds]
    if missing:
        raise InputError(SOURCE, missing[0], "missing: a measurement file holds the spindle speed and the room air")
    folder = checked_folder(folder, "folder")   # an existing folder, or one its parent can take
    columns, mapping = _columns(ds, mach, stem)
    csv_path, toml_path = folder / f"{stem}.csv", folder / f"{stem}.toml"
    with output_folder(folder):                 # made for the writes, removed again if they fail empty
        csv_text, toml_text = _csv_text(columns, len(ds.time)), "\n".join(mapping) + "\n"
        atomic_write_all([(csv_path, text_writer(csv_text)), (toml_path, text_writer(toml_text))])  # never half a pair
    return csv_path, toml_path


def _columns(ds: xr.Dataset, mach, stem: str) -> tuple[list, list[str]]:
    """The CSV's columns [(name, values, format)] and the mapping's lines."""
    columns = [("t_s", ds.time.values, "%.6f"), ("spindle_rpm", ds.spindle_speed.values, "%.0f"),
               ("room_degC", ds.ambient_temperature.values, "%.4f")]
    mapping = [f"# column mapping of {stem}.csv (see twin/io/measurement.py)", f"machine = {_text(mach.name)}", "",
               "[columns.t_s]", 'role = "time"', 'unit = "s"', "",
               "[columns.spindle_rpm]", 'role = "spindle_speed"', 'unit = "rpm"', "",
               "[columns.room_degC]", 'role = "ambient_temperature"', 'unit = "degC"']
    if "temperature" in ds:
        from geometries.axes import with_feed_drives
        sites = {p.name: p for p in with_feed_drives(mach).points}
        temp = ds.temperature.transpose("time", "sensor")
        placed = {"x", "y", "z"} <= set(ds.coords)
        for i, s in enumerate(str(n) for n in ds.sensor.values):
            check_sensor_name(s, SOURCE, f"sensor[{i}]")      # a mapping's names: no '@', ':' or ','
            name = f"T_{s}_degC"
            columns.append((name, temp.values[:, i], "%.4f"))
            mapping += ["", f"[columns.{_key(name)}]", 'role = "temperature"', 'unit = "degC"']
            xyz = np.array([float(ds[c].values[i]) for c in "xyz"]) if placed else None
            if s in sites and (xyz is None or np.allclose(xyz, sites[s].xyz, atol=1e-9)):
                mapping.append(f"site = {_text(s)}")
            elif xyz is None:
                raise InputError(SOURCE, f"sensor {s}", f"is no site of machine {mach.name} and the Dataset gives no "
                                                        "position (coordinates x, y, z [m])")
            else:
                part = str(ds.part.values[i]) if "part" in ds.coords else ""
                mapping += [f"name = {_text(s)}", *(f'{c} = "{clean(v)!r} m"' for c, v in zip("xyz", xyz.tolist())),
                            f"part = {_text(part)}"]
    for var, dim, role, key, fmt in (("probe", "probe_id", "probe", "probe", "%.2f"),
                                     ("laser", "laser_id", "laser", "laser", "%.2f")):
        if var in ds:
            values = ds[var].transpose("time", dim)
            for i, p in enumerate(str(n) for n in ds[dim].values):
                name = f"{var}_{p}_um"
                columns.append((name, values.values[:, i], fmt))
                mapping += ["", f"[columns.{_key(name)}]", f'role = "{role}"', f"{key} = {_text(p)}", 'unit = "um"']
    for var, reading in (("strain", "compensated"), ("strain_raw", "raw")):
        if var in ds:
            values = ds[var].transpose("time", "gauge")
            for i, g in enumerate(str(n) for n in ds.gauge.values):
                name = f"{var}_{g}_um_m"
                columns.append((name, values.values[:, i], "%.3f"))
                mapping += ["", f"[columns.{_key(name)}]", 'role = "strain"', f"gauge = {_text(g)}",
                            f'reading = "{reading}"', 'unit = "um/m"']
    if "c_axis_speed" in ds:
        columns.append(("c_axis_rpm", ds.c_axis_speed.values, "%.3f"))
        mapping += ["", "[columns.c_axis_rpm]", 'role = "c_axis_speed"', 'unit = "rpm"',
                    f"duty = {clean(_c_axis_duty(ds))!r}"]
    if "axis_position" in ds:
        values = ds.axis_position.transpose("time", "axis_name")
        for i, a in enumerate(str(n) for n in ds.axis_name.values):
            name = f"{a}_mm"
            columns.append((name, values.values[:, i], "%.6f"))
            mapping += ["", f"[columns.{_key(name)}]", 'role = "axis_position"', f"axis = {_text(a)}", 'unit = "mm"']
    return columns, mapping


def _c_axis_duty(ds: xr.Dataset) -> float:
    """The one duty a mapping gives the C axis while it turns (1 when it never turns or no
    ``c_axis_duty`` is given); a duty that changes while turning cannot be written."""
    if "c_axis_duty" not in ds:
        return 1.0
    duty = np.asarray(ds.c_axis_duty.values, dtype=float)[np.asarray(ds.c_axis_speed.values, dtype=float) > 0]
    if duty.size and np.ptp(duty) > 1e-12:
        raise InputError(SOURCE, "c_axis_duty", f"changes while the C axis turns ({duty.min():g} .. {duty.max():g}): "
                                                "a measurement mapping holds one duty")
    return float(duty[0]) if duty.size else 1.0


def _csv_text(columns: list, rows: int) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow([c[0] for c in columns])
    for k in range(rows):
        writer.writerow([fmt % float(values[k]) for _, values, fmt in columns])
    return out.getvalue()


def _text(value: str) -> str:
    """``value`` as a TOML basic string (JSON's escapes are TOML's)."""
    return json.dumps(value, ensure_ascii=False)


def _key(name: str) -> str:
    """``name`` as a TOML key: bare when it can be, else quoted (a sensor named ``a.b``)."""
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else _text(name)
