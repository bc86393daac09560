"""Measurements in the shape of a simulation result, and a scenario driven by measured inputs.

A measurement is either a twin NetCDF result (read as is) or a CSV file with a header row plus a
small TOML mapping (by default next to it, same stem, ``.toml``) naming every column's role and
unit::

    machine = "cframe-vmc"                # needed when a sensor is placed at a named site
    [columns.t]
    role = "time"                         # unit: s, min, h ...
    unit = "s"
    [columns.n]
    role = "spindle_speed"                # rpm
    unit = "rpm"
    [columns.room]
    role = "ambient_temperature"          # degC
    unit = "degC"
    [columns.T3]
    role = "temperature"                  # at a named site of the machine ...
    site = "motor"
    unit = "degC"
    [columns.T9]
    role = "temperature"                  # ... or at a position [m] (part optional), not both
    name = "column_top"                   # optional sensor name (default: the site or the column);
    x = "0.1 m"                           # non-empty, without '@', ':' or ','
    y = "0.5 m"
    z = "1.2 m"
    part = "column"
    unit = "degC"
    [columns.px1]
    role = "probe"                        # one of X1 X2 Y1 Y2 Z, a length unit (um, mm ...)
    probe = "X1"
    unit = "um"
    [columns.lz]
    role = "laser"                        # a laser triangulation sensor of the machine (Y, Z, A1, A2
    laser = "Z"                           # on gantry-ram), a length unit
    unit = "um"
    [columns.fbg1]
    role = "strain"                       # an FBG gauge of the machine, a strain unit (um/m, ppm)
    gauge = "FBG-1"
    reading = "compensated"               # or "raw" (with the grating's cross-sensitivity)
    unit = "um/m"
    [columns.c]
    role = "c_axis_speed"                 # rpm; duty = 0.5 when an on/dwell rhythm is faster than
    unit = "rpm"                          # the log (the fraction of time turning, default 1)
    [columns.ypos]
    role = "axis_position"                # a logged axis position (drives the twin's axis motion)
    axis = "Y"
    unit = "mm"
    [columns.xfeed]
    role = "axis_feed"                    # a logged signed feed of an axis (drives it like a
    axis = "X"                            # position: x(t) = start + the feed's integral, trapezoidal
    start = "100 mm"                      # between samples); an axis is logged one way only
    unit = "mm/min"

The result has the variables of :func:`twin.io.results.to_dataset`: ``time`` [s],
``spindle_speed`` [rpm], ``ambient_temperature`` [degC], ``temperature(time, sensor)`` [degC] with
``x, y, z`` [m] and ``part`` coordinates, ``probe(time, probe_id)`` [um], ``axis_position(time, axis_name)`` [mm] and, with all five
probes and a machine, ``probe_drift(time, axis)`` [um] and ``tilt(time, rotation)`` [urad];
``laser(time, laser_id)`` [um]; ``strain`` (compensated) and ``strain_raw(time, gauge)`` [um/m]
(a gauge given both ways must be given both ways for every gauge); ``c_axis_speed`` [rpm] and
``c_axis_duty`` [1] (the mapping's ``duty`` while turning, 0 at rest). Probe, laser and strain
readings are zeroed at the first sample (probes are nulled at the start, and the twin's strains
are changes from a zero-strain start); time is kept as logged. A header cell ending in a unit in
brackets (``t [min]``, mapped as ``[columns."t [min]"]``) must agree with the mapping's ``unit``
(:func:`twin.io.csv_header.unit_contradiction`). Every problem raises :class:`twin.errors.InputError`
naming file and column, and a CSV's the line an editor shows (header line 1, blank lines counted).
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np
import xarray as xr

from twin import limits
from twin.errors import InputError, describe, refuse_unknown_keys
from twin.io.axis_logs import axis_name, check_log, integrated_feed, known_axis
from twin.io.csv_header import unit_contradiction
from twin.io.csv_rows import cell_number, data_rows
from twin.io.mapping_columns import (NETCDF_BAD_NAME_CHARACTERS, check_sensor_name, check_values, duty_fraction,
                                     instrument, sensor)
from twin.io.measured_inputs import sensors_of
from twin.io.paths import NETCDF_SUFFIXES, as_path, input_file, read_text, read_toml, same_file
from twin.io.results import check_finite, check_result_layout, check_result_units, placed_sensors, read_result
from twin.io.times import check_times
from twin.observe.base import variable
from twin.observe.displacement import AXES, FIVE_PROBES, derived_from_probes
from twin.units import CANONICAL, UnitError, parse_quantity

ROLES = {"time": "time", "spindle_speed": "speed", "ambient_temperature": "temperature",
         "temperature": "temperature", "probe": "length", "axis_position": "length", "laser": "length",
         "strain": "strain", "c_axis_speed": "speed", "axis_feed": "velocity"}
_ROLE_KEYS = {"time": set(), "spindle_speed": set(), "ambient_temperature": set(),
              "temperature": {"site", "x", "y", "z", "part", "name"}, "probe": {"probe"}, "axis_position": {"axis"},
              "laser": {"laser"}, "strain": {"gauge", "reading"}, "c_axis_speed": {"duty"},
              "axis_feed": {"axis", "start"}}
_VALUES = {"time": "times", "temperature": "temperatures"}   # what a column of a dimension holds, in errors
SINGLE = ("time", "spindle_speed", "ambient_temperature", "c_axis_speed")   # one column each at most
READINGS = {"compensated": "strain", "raw": "strain_raw"}   # FBG reading -> variable


def probe_names(machine) -> list[str]:
    """The machine's displacement probes (the ISO 230-3 five-probe nest without a machine)."""
    return [p.name for p in machine.probes] if machine is not None else list(FIVE_PROBES)


def mapping_path(path: str | Path, mapping: str | Path | None = None) -> Path | None:
    """The column mapping a measurement at ``path`` is read with: ``mapping``, else for a CSV the
    file beside it with the same stem and ``.toml`` (None for a NetCDF file)."""
    if mapping:
        return Path(mapping)
    return None if _is_netcdf(Path(path)) else Path(path).with_suffix(".toml")


def _is_netcdf(path: Path) -> bool:
    return path.suffix.lower() in NETCDF_SUFFIXES


def read_measurement(path: str | Path, mapping: str | Path | None = None, machine=None) -> xr.Dataset:
    """Read a twin NetCDF result as is, or a CSV with its TOML mapping (see module docstring).

    ``machine`` (a :class:`geometries.base.Machine` or a name) places named sites and evaluates
    the five probes; by default the mapping's ``machine`` key (a result's ``machine`` attribute).
    Values are checked against physical limits (:mod:`twin.limits`): temperatures above absolute
    zero and plausible, spindle speeds within the machine's maximum, sensor positions on the
    machine; a measurement needs at least one temperature, probe, laser or strain channel.
    """
    path = input_file(path, "measurement", "measurement file")
    if mapping is not None:        # a number or a list failed in pathlib with a TypeError
        mapping = as_path(mapping, "--mapping")
    if _is_netcdf(path):
        if mapping:
            raise InputError(str(mapping), "--mapping", "a NetCDF measurement has no column mapping")
        return read_checked_result(path, "measurement", machine)
    given, mapping = mapping, mapping_path(path, mapping)
    if same_file(path, mapping):
        raise InputError(str(path), "measurement", "is its own column mapping: give the CSV file (its mapping is the "
                                                   ".toml beside it, or --mapping)")
    if not given and not os.path.lexists(mapping):
        raise InputError(str(mapping), "--mapping", f"no column mapping for {path.name} (a TOML file naming each "
                                                    "column's role and unit)")
    spec, _ = read_toml(mapping, "--mapping", "column mapping")
    return _with_channels(_from_csv(path, mapping, spec, machine), str(path))


def read_checked_result(path: str | Path, field: str = "result", machine=None) -> xr.Dataset:
    """A NetCDF twin result (or measurement) read (:func:`twin.io.results.read_result`) and its
    values checked as a measurement's (:func:`check_measurement`): the machine its ``machine``
    attribute names (or ``machine``, which must agree), plausible temperatures, speeds and
    readings, distinct sensor names placed on that machine. What draws or reports a result reads
    it so: a file a comparison refuses is refused everywhere."""
    ds = read_result(path, field)
    src = str(path)
    mach = _machine(machine, {"machine": ds.attrs.get("machine")}, src, f"the {field} is of")
    return check_measurement(ds, mach, src)


CHANNEL_VARIABLES = ("temperature", "probe", "laser", "strain", "strain_raw")


def _with_channels(ds: xr.Dataset, src: str) -> xr.Dataset:
    if not any(v in ds for v in CHANNEL_VARIABLES):
        raise InputError(src, "channels", "no temperature, probe, laser or strain channel: nothing to compare the "
                                          "twin with")
    return ds


def _check_netcdf_values(ds: xr.Dataset, mach, src: str) -> None:
    """Units and physical limits of a NetCDF measurement's inputs and sensors (the CSV reader
    checks its columns as it reads them)."""
    check_result_units(ds, src)
    check_result_layout(ds, src)
    if "spindle_speed" in ds:
        limits.check_speeds(ds.spindle_speed.values, mach, src, "spindle_speed", logged=True)
    if "ambient_temperature" in ds:
        limits.check_temperatures(ds.ambient_temperature.values, src, "ambient_temperature")
    if mach is not None:    # every named instrument one the machine has (a reader would drop the rest)
        gauges = [g.name for g in mach.strain_gauges]
        for var, dim, what, known in (("probe", "probe_id", "probes", probe_names(mach)),
                                      ("laser", "laser_id", "lasers", [s.name for s in mach.lasers]),
                                      ("strain", "gauge", "strain gauges", gauges),
                                      ("strain_raw", "gauge", "strain gauges", gauges)):
            if var in ds and dim in ds.coords:
                unknown = [str(n) for n in ds[dim].values if str(n) not in known]
                if unknown:
                    raise InputError(src, f"{var}:{unknown[0]}", f"machine {mach.name} has no such instrument; its "
                                                                 f"{what}: {', '.join(known) or 'none'}")
    for var, dim in (("probe", "probe_id"), ("laser", "laser_id")):
        if var in ds and dim in ds.coords:
            um = ds[var].transpose("time", dim).values
            for i, name in enumerate(ds[dim].values):
                limits.check_displacements(um[:, i] * 1e-6, src, f"{var}:{name}")
    for var in READINGS.values():
        if var in ds and "gauge" in ds.coords:
            limits.check_strains(ds[var].transpose("time", "gauge").values * 1e-6, src, var)
    if "c_axis_speed" in ds:
        limits.check_c_axis_speeds(ds.c_axis_speed.values, mach, src, "c_axis_speed", logged=True)
    if "axis_position" in ds and "axis_name" in ds.coords:
        t = np.asarray(ds["time"].values, dtype=float)
        mm = ds.axis_position.transpose("time", "axis_name").values
        for i, axis in enumerate(ds.axis_name.values):
            field = f"axis_position:{axis}"
            check_log(known_axis(str(axis), mach, src, field), t, mm[:, i] * 1e-3, mach, src, field)
    if "sensor" in ds.coords:
        names = [check_sensor_name(str(n), src, f"sensor[{i}]", NETCDF_BAD_NAME_CHARACTERS)
                 for i, n in enumerate(ds.sensor.values)]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise InputError(src, "sensor", f"sensor {twice[0]!r} appears twice")
    if "temperature" in ds and "sensor" in ds.coords:
        from geometries.axes import with_feed_drives
        placed = with_feed_drives(mach) if mach is not None else None   # sensors on the feed drives' parts too
        temp = ds.temperature.transpose("time", "sensor").values
        located = placed_sensors(ds, src)
        if mach is not None:
            sensors_of(ds, mach, src)       # each sensor placed by x, y, z or a site of the machine
        for i, name in enumerate(ds.sensor.values):
            limits.check_temperatures(temp[:, i], src, f"temperature:{name}", "structure")
            if placed is not None and located:
                part = str(ds.part.values[i]) if "part" in ds.coords else ""
                xyz = (float(ds.x.values[i]), float(ds.y.values[i]), float(ds.z.values[i]))
                limits.check_position(placed, xyz, part, src, f"sensor {name}")


def _machine(machine, spec: dict, src: str, named_by: str = "the mapping names"):
    named = spec.get("machine")
    if named is not None and not isinstance(named, str):
        raise InputError(src, "machine", f"expected a machine name, got {describe(named)}")
    if machine is not None and not isinstance(machine, str) and not isinstance(getattr(machine, "name", None), str):
        raise InputError("command line", "machine", f"expected a machine name or a built machine, got {describe(machine)}")
    given = machine if isinstance(machine, str) or machine is None else machine.name
    if given is not None and named is not None and given != named:
        raise InputError(src, "machine", f"{named_by} machine {named!r}, the command line {given!r}")
    if machine is not None and not isinstance(machine, str):
        return machine
    name = given or named
    if name is None:
        return None
    from twin.api import machine_by_name

    try:
        return machine_by_name(name)
    except InputError as err:
        raise InputError(src, "machine", err.message) from None


def _read_csv(path: Path) -> tuple[list[str], list[int], list[list[str]]]:
    """(header, the data rows' line numbers, the data rows) of a measurement CSV."""
    text = read_text(path, "measurement", "measurement file")
    try:
        lines, rows = data_rows(text)
    except csv.Error as err:
        raise InputError(str(path), "file", f"not a readable CSV file ({err})") from None
    if len(rows) < 3:
        raise InputError(str(path), "file", "needs a header row and at least two data rows")
    header = [h.strip() for h in rows[0]]
    if "" in header:
        raise InputError(str(path), "header", f"column {header.index('') + 1} has no name (a comma at the end of "
                                              "each line makes an empty last column); name every column")
    twice = [h for h in header if header.count(h) > 1]
    if twice:
        raise InputError(str(path), twice[0], "two columns have this name")
    for line, r in zip(lines[1:], rows[1:]):
        if len(r) != len(header):
            raise InputError(str(path), f"line {line}", f"has {len(r)} fields, the header has {len(header)}")
    return header, lines[1:], rows[1:]


def _column(path: Path, lines: list[int], rows, j: int, name: str) -> np.ndarray:
    out = np.empty(len(rows))
    for i, r in enumerate(rows):
        text = r[j].strip()
        try:
            out[i] = cell_number(text) if text else np.nan
        except ValueError:
            raise InputError(str(path), name, f"line {lines[i]}: {text!r} is not a number") from None
    infinite = np.flatnonzero(np.isinf(out))
    if len(infinite):   # "inf", "-Infinity", "1e999": a value, but not a finite one
        i = int(infinite[0])
        raise InputError(str(path), name, f"line {lines[i]}: not finite ({rows[i][j].strip()})"
                                          + (f"; {len(infinite)} such value(s)" if len(infinite) > 1 else ""))
    bad = np.flatnonzero(np.isnan(out))
    if len(bad):
        raise InputError(str(path), name, f"{len(bad)} missing/NaN value(s), first at line {lines[bad[0]]}")
    return out


def _factor(value, dimension: str, src: str, key: str) -> float:
    """SI value of one unit of ``value`` (a unit string) in ``dimension``; degC is offset-free."""
    if not isinstance(value, str):
        raise InputError(src, key, f"expected a unit string like {CANONICAL[dimension]!r}")
    try:
        return parse_quantity(f"1 {value}", dimension)
    except UnitError:
        raise InputError(src, key, f"unit {value!r} does not fit role ({dimension.replace('_', ' ')}); "
                                   f"expected e.g. {CANONICAL[dimension]!r}") from None


def check_measurement(ds, machine, src: str = "measurement") -> xr.Dataset:
    """A measurement given as a Dataset in Python (to :func:`validate.compare.compare` or a
    diagnosis) checked as :func:`read_measurement` checks a NetCDF file: a Dataset with two or
    more samples at finite, increasing times, the twin's units, finite and plausible values,
    sensors with distinct names on ``machine`` (a :class:`geometries.base.Machine`), and at
    least one channel to compare."""
    if not isinstance(ds, xr.Dataset):
        raise InputError(src, "measurement", f"expected an xarray.Dataset (read_measurement), got {describe(ds)}")
    if machine is not None:
        limits.check_machine(machine, src)
    if "time" not in ds.variables:
        raise InputError(src, "time", "missing: a measurement has a time coordinate [s]")
    if ds["time"].values.dtype.kind not in "fiu":
        raise InputError(src, "time", f"expected times in seconds (numbers), got values of type "
                                      f"{ds['time'].values.dtype}")
    check_times(np.asarray(ds["time"].values, dtype=float), src, "time")
    _check_netcdf_values(ds, machine, src)      # each channel by name first
    check_finite(ds, src)        # then the rest, as a NetCDF file is read (read_result): NaN would score as NaN
    return _with_channels(ds, src)


def check_named_machine(ds, name: str, src: str, against: str = "not") -> None:
    """The Dataset ``ds`` names no machine (its ``machine`` attribute) or the machine ``name``:
    'the measurement is of machine X, {against} Y' otherwise."""
    named = getattr(ds, "attrs", {}).get("machine") if isinstance(ds, xr.Dataset) else None
    if named is not None and str(named) != name:
        raise InputError(src, "machine", f"the measurement is of machine {named!r}, {against} {name!r}")


def _from_csv(path: Path, mapping: Path, spec: dict, machine) -> xr.Dataset:
    src, msrc = str(path), str(mapping)
    refuse_unknown_keys(spec, ("machine", "columns"), msrc, "")
    cols = spec.get("columns")
    if not isinstance(cols, dict) or not cols:
        raise InputError(msrc, "columns", "expected [columns.NAME] tables naming each CSV column's role and unit")
    header, lines, rows = _read_csv(path)
    missing = [c for c in cols if c not in header]
    if missing:
        raise InputError(msrc, f"columns.{missing[0]}", f"no such column in {path.name} (columns: {', '.join(header)})")
    unmapped = [h for h in header if h not in cols]
    if unmapped:
        raise InputError(src, unmapped[0], f"column is not mapped in {mapping.name} (add a [columns.{unmapped[0]}] table)")
    mach = _machine(machine, spec, msrc)

    single: dict[str, np.ndarray] = {}
    sensors: list[tuple[str, tuple[float, float, float], str, np.ndarray]] = []
    sensor_columns: list[str] = []      # the mapping key of each sensor's column
    probes: dict[str, np.ndarray] = {}
    positions: dict[str, np.ndarray] = {}
    position_columns: dict[str, str] = {}                       # axis -> its position column
    feeds: dict[str, tuple[np.ndarray, dict, str, str]] = {}   # axis -> (feed [m/s], entry, key, column)
    lasers: dict[str, np.ndarray] = {}
    strains: dict[str, dict[str, np.ndarray]] = {"strain": {}, "strain_raw": {}}
    duty = 1.0
    for name, entry in cols.items():
        key = f"columns.{name}"
        if not isinstance(entry, dict):
            raise InputError(msrc, key, f"expected a table with role and unit, got {describe(entry)}")
        if "role" not in entry:   # a misspelled key first (rol = "time"), then the missing role
            refuse_unknown_keys(entry, {"role", "unit"}.union(*_ROLE_KEYS.values()), msrc, key + ".")
            raise InputError(msrc, key + ".role", f"missing; give one of {', '.join(ROLES)}")
        role = entry["role"]
        if not isinstance(role, str) or role not in ROLES:
            raise InputError(msrc, key + ".role", f"unknown role {describe(role)}; known: {', '.join(ROLES)}")
        extra = sorted(set(entry) - {"role", "unit"} - _ROLE_KEYS[role])
        if extra:
            raise InputError(msrc, f"{key}.{extra[0]}", f"unknown key for role {role} (known: "
                                                        f"{', '.join(sorted({'role', 'unit'} | _ROLE_KEYS[role]))})")
        if "unit" not in entry:
            raise InputError(msrc, key + ".unit", "missing")
        factor = _factor(entry["unit"], ROLES[role], msrc, key + ".unit")
        conflict = unit_contradiction(name, entry["unit"], factor, ROLES[role], src, _VALUES.get(ROLES[role], "values"))
        if conflict:        # 't [min]' read as seconds: a log 60 times too short, silently
            raise InputError(msrc, key + ".unit", f"{conflict}; give the column one unit in both files")
        if role == "c_axis_speed" and not (getattr(mach, "parameters", None) or {}).get("c_axis_max_speed"):
            raise InputError(msrc, key, "a C-axis speed needs a machine with a C axis (top-level machine = "
                                        f"\"...\"; {'none named' if mach is None else mach.name + ' has none'})")
        values = _column(path, lines, rows, header.index(name), name) * factor
        check_values(values, role, mach, src, name, lines)
        if role in SINGLE:
            if role in single:
                raise InputError(msrc, key, f"a second column with role {role}")
            single[role] = values
            if role == "c_axis_speed":
                duty = duty_fraction(entry.get("duty", 1.0), msrc, key + ".duty")
        elif role == "laser":
            lid = instrument(entry, "laser", [p.name for p in mach.lasers] if mach is not None else None,
                              lasers, msrc, key)
            lasers[lid] = (values - values[0]) * 1e6  # m -> um, nulled at the start
        elif role == "strain":
            reading = entry.get("reading")
            if not isinstance(reading, str) or reading not in READINGS:   # a list or table is not hashable
                got = f"got {describe(entry['reading'])}" if "reading" in entry else "missing"
                raise InputError(msrc, key + ".reading", f"{got}; expected \"compensated\" (with the nearest "
                                                         f"temperature sensor) or \"raw\" (the grating's reading)")
            var = READINGS[reading]
            gid = instrument(entry, "gauge", [g.name for g in mach.strain_gauges] if mach is not None else None,
                              strains[var], msrc, key)
            strains[var][gid] = (values - values[0]) * 1e6  # m/m -> um/m, nulled at the start
        elif role == "probe":
            pid = entry.get("probe")
            known = probe_names(mach)
            if pid not in known:
                raise InputError(msrc, key + ".probe", ("missing" if pid is None else f"unknown probe {describe(pid)}")
                                 + (f"; known: {', '.join(known)}" if known else
                                    f"; machine {mach.name} has no displacement probes"))
            if pid in probes:
                raise InputError(msrc, key + ".probe", f"probe {pid} mapped twice")
            probes[pid] = (values - values[0]) * 1e6  # m -> um, nulled at the start
        elif role == "axis_position":
            axis = axis_name(entry, {**positions, **feeds}, mach, msrc, key)
            positions[axis], position_columns[axis] = values, name
        elif role == "axis_feed":
            feeds[axis_name(entry, {**positions, **feeds}, mach, msrc, key)] = (values, entry, key, name)
        else:
            sensors.append(sensor(entry, name, values, mach, msrc, key))
            sensor_columns.append(key)
    if "time" not in single:
        raise InputError(msrc, "columns", "no column has role = \"time\"")
    t = single["time"]
    check_times(t, src, next(c for c, e in cols.items() if e.get("role") == "time"), lines)
    for axis, x in positions.items():
        check_log(axis, t, x, mach, src, position_columns[axis], lines)
    for axis, (feed, entry, key, column) in feeds.items():
        positions[axis] = integrated_feed(t, feed, entry, mach, msrc, src, key, column, lines)
    names = [s[0] for s in sensors]
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:
        keys = [k for k, n in zip(sensor_columns, names) if n == twice]
        raise InputError(msrc, keys[-1], f"gives sensor name {twice!r}, as {keys[0]} does: two temperature columns "
                                         "have the same sensor name (give one of them name = \"...\")")
    if strains["strain"] and strains["strain_raw"] and set(strains["strain"]) != set(strains["strain_raw"]):
        raise InputError(msrc, "columns", "FBG gauges given both compensated and raw must be the same gauges "
                                          f"(compensated: {', '.join(strains['strain'])}; raw: "
                                          f"{', '.join(strains['strain_raw'])})")
    return _dataset(t, single, sensors, probes, mach, src, positions, lasers, strains, duty)


def _dataset(t, single, sensors, probes, mach, src, positions=None, lasers=None, strains=None, duty=1.0) -> xr.Dataset:
    data, coords = {}, {"time": ("time", t, {"units": "s", "long_name": "time since start"})}
    if "spindle_speed" in single:
        data["spindle_speed"] = variable("time", single["spindle_speed"], "rpm", "spindle speed")
    if "ambient_temperature" in single:
        data["ambient_temperature"] = variable("time", single["ambient_temperature"], "degC", "room air temperature")
    if sensors:
        data["temperature"] = variable(("time", "sensor"), np.column_stack([s[3] for s in sensors]), "degC",
                                   "temperature as measured")
        coords.update({
            "sensor": ("sensor", [s[0] for s in sensors], {"long_name": "temperature sensor site"}),
            "x": ("sensor", [s[1][0] for s in sensors], {"units": "m", "long_name": "sensor x"}),
            "y": ("sensor", [s[1][1] for s in sensors], {"units": "m", "long_name": "sensor y"}),
            "z": ("sensor", [s[1][2] for s in sensors], {"units": "m", "long_name": "sensor z"}),
            "part": ("sensor", [s[2] for s in sensors], {"long_name": "part carrying the sensor"})})
    if probes:
        ids = [p for p in probe_names(mach) if p in probes]
        arr = np.column_stack([probes[p] for p in ids])
        data["probe"] = variable(("time", "probe_id"), arr, "um", "ISO 230-3 probe reading as measured")
        coords["probe_id"] = ("probe_id", ids, {"long_name": "ISO 230-3 probe"})
        if mach is not None and set(FIVE_PROBES) <= set(ids):
            drift, tilt = derived_from_probes(arr, ids, mach)
            data["probe_drift"] = variable(("time", "axis"), drift, "um", "tool-point drift derived from the probe readings")
            data["tilt"] = variable(("time", "rotation"), tilt, "urad", "test-bar tilt from the probe readings (A about X, B about Y)")
            coords["axis"] = ("axis", list(AXES), {"long_name": "machine axis"})
            coords["rotation"] = ("rotation", ["A", "B"], {"long_name": "rotation about X (A) and Y (B)"})
    if positions:
        names = sorted(positions)
        data["axis_position"] = variable(("time", "axis_name"), np.column_stack([positions[a] for a in names]) * 1e3,
                                         "mm", "logged axis position")
        coords["axis_name"] = ("axis_name", names, {"long_name": "linear axis"})
    if lasers:
        ids = [p.name for p in mach.lasers if p.name in lasers]
        data["laser"] = variable(("time", "laser_id"), np.column_stack([lasers[i] for i in ids]), "um",
                                 "laser triangulation reading as measured")
        coords["laser_id"] = ("laser_id", ids, {"long_name": "laser triangulation sensor"})
    given = {var: g for var, g in (strains or {}).items() if g}
    if given:
        gauges = [g.name for g in mach.strain_gauges if any(g.name in v for v in given.values())]
        what = {"strain": "FBG strain compensated with the nearest temperature sensor, as measured",
                "strain_raw": "FBG reading with the grating's temperature cross-sensitivity, as measured"}
        for var, g in given.items():
            data[var] = variable(("time", "gauge"), np.column_stack([g[n] for n in gauges]), "um/m", what[var])
        coords["gauge"] = ("gauge", gauges, {"long_name": "FBG strain gauge"})
    if "c_axis_speed" in single:
        speed = single["c_axis_speed"]
        data["c_axis_speed"] = variable("time", speed, "rpm", "C-axis speed while turning")
        data["c_axis_duty"] = variable("time", np.where(speed > 0, duty, 0.0), "1", "fraction of the time the C axis turns")
    attrs = {"title": f"measurement {Path(src).name}", "source": src, "kind": "measurement"}
    if mach is not None:
        attrs["machine"] = mach.name
    return xr.Dataset(data, coords, attrs)
