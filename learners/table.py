"""Load a measurement table (CSV or twin result NetCDF) into ``(time, X, y, input_names)``.

CSV: a header row, a time column in seconds (``time_column``, default "time"), one column per
signal; every column must be numeric and finite, used or not (a column of labels, or one of NaN,
is refused naming it and the line: drop it from the file). Inputs default to every column but
time and the target.

NetCDF (a twin result, :mod:`xarray` Dataset): the file is read and checked as ``twin plot``,
``twin report`` and ``twin compare`` read a result (:func:`twin.io.measurement.read_checked_result`:
the twin's units, time in s without gaps of more than 3 median steps, no NaN or inf in any variable
or coordinate, a known machine, spindle speeds within its maximum, sensors on it, ...), whichever
of its variables are used. Inputs are ``temperature(time, sensor)`` [degC], one column per
``sensor`` coordinate value, named by it. Targets (and extra inputs) are addressed as
``"<variable>:<label>"``, selecting ``label`` along the variable's one non-time dimension, whatever
its name, e.g. ``drift:Z`` -> ``drift.sel(axis="Z")`` [um], ``probe:Y1`` -> the probe reading
``Y1`` [um], ``tilt:A`` -> ``tilt.sel(rotation="A")`` [urad], or as a bare variable name for a
variable that depends on time only. Time is returned in seconds (a twin result's ``time`` is in
``s``; ``time_column`` may name another variable, read in the time unit it states).

Every problem raises :class:`twin.errors.InputError` ``(path, column, message)``: missing file,
missing column/variable/label, non-numeric value, NaN or infinite value, time not strictly
increasing, fewer than ``min_rows`` rows.
"""

from __future__ import annotations

import csv
import math
from typing import NamedTuple

import numpy as np

from learners._checks import VALUE_LIMIT, is_constant as _is_constant
from twin.errors import InputError
from twin.io.csv_rows import cell_number, data_rows
from twin.io.results import result_unit, stated_units
from twin.io.paths import input_file, read_text
from twin.limits import check_displacements, check_strains, check_temperatures
from twin.units import UnitError, parse_quantity

__all__ = ["Table", "load_table", "check_problem", "MIN_ROWS"]

MIN_ROWS = 3
_NETCDF_EXT = (".nc", ".nc4", ".netcdf", ".cdf", ".h5", ".hdf5")
# what a value in these units must be (a machine's temperatures, errors and strains: twin.limits)
_PLAUSIBLE = {"degC": lambda v, src, f: check_temperatures(v, src, f, "structure"),
              "um": lambda v, src, f: check_displacements(v * 1e-6, src, f),
              "um/m": lambda v, src, f: check_strains(v * 1e-6, src, f)}


# [the unit] a target in a twin unit varying by no more than this is constant: a millionth of the
# finest instrument step (0.01 K sensors, 0.1 um probes, 0.5 um/m gratings), far above the solvers'
# round-off (a result at rest varies by about 1e-12 um)
ROUND_OFF = {"degC": 1e-6, "K": 1e-6, "um": 1e-6, "um/m": 1e-6, "urad": 1e-6}


class Table(NamedTuple):
    """A loaded table: ``time`` (n,) s, ``X`` (n, p), ``y`` (n,), ``input_names`` (p names),
    ``target_unit`` (the target variable's ``units`` attribute in a NetCDF file; "" for a CSV
    column, whose unit the file does not state)."""

    time: np.ndarray
    X: np.ndarray
    y: np.ndarray
    input_names: list
    target_unit: str = ""


def load_table(path, target, *, inputs=None, time_column="time", min_rows=MIN_ROWS, field="file") -> Table:
    """Read ``path`` (CSV or NetCDF) and return :class:`Table` for ``target``.

    ``inputs``: None or "all" for every available input, else a list (or comma-separated string)
    of input names. ``field``: the option that named the file (for errors about the file itself).
    """
    path = str(input_file(path, field, "table"))
    if str(target).strip() == time_column:
        raise InputError("command line", "--target", f"{target!r} is the time column: choose a measured quantity "
                                                     "(a drift, a probe, a temperature)")
    if isinstance(inputs, str):
        inputs = None if inputs.strip() in ("", "all") else [s.strip() for s in inputs.split(",") if s.strip()]
    unit = ""
    if _is_netcdf(path):
        time, X, y, names, unit = _load_netcdf(path, target, inputs, time_column, field)
    else:
        time, X, y, names = _load_csv(path, target, inputs, time_column, field)
    if len(time) < min_rows:
        raise InputError(path, "rows", f"{len(time)} data rows; at least {min_rows} are needed")
    bad = np.flatnonzero(np.diff(time) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise InputError(path, time_column, f"time is not strictly increasing at sample {i + 1} "
                                            f"({time[i - 1]:g} s then {time[i]:g} s)")
    if not names:
        raise InputError(path, "inputs", "no input columns")
    return Table(time, X, y, names, unit)


def check_problem(table: Table, path, target: str, *, training: bool = True, n_select: int | None = None) -> None:
    """Refuse a degenerate learning problem with :class:`InputError`: the target among the inputs,
    a constant target (nothing to learn; NSE undefined), and on a training table a constant input
    (no information, NaN correlations) or a selector asking for more inputs than there are."""
    names = list(table.input_names)
    var, _, label = str(target).partition(":")
    if target in names or (var == "temperature" and label in names):
        raise InputError("command line", "--inputs", f"the target {target} is also an input")
    spread = float(np.ptp(table.y))
    if _is_constant(table.y) or (table.target_unit in ROUND_OFF and spread <= ROUND_OFF[table.target_unit]):
        what = (f"{table.y[0]:g}" if spread == 0 else f"{table.y[0]:g}, varying by {spread:.2g} {table.target_unit}"
                + (": round-off" if table.target_unit in ROUND_OFF else ""))
        raise InputError(str(path), target, f"the target is constant ({what}): nothing to learn, and "
                                            "NSE and R are undefined")
    if not training:
        return
    for j, name in enumerate(names):
        if _is_constant(table.X[:, j]):
            raise InputError(str(path), name, f"input is constant ({table.X[0, j]:g}): it carries no "
                                              "information; leave it out with --inputs")
    if n_select is not None and n_select > len(names):
        raise InputError("command line", "--select", f"asks for {n_select} inputs, the training table has "
                                                     f"{len(names)} ({', '.join(names)})")


def _is_netcdf(path):
    if path.lower().endswith(_NETCDF_EXT):
        return True
    with open(path, "rb") as fh:
        head = fh.read(8)
    return head.startswith(b"\x89HDF") or head.startswith(b"CDF")


# ----------------------------------------------------------------------------------------------- CSV


# said of a bad value in a column the command does not read: it is checked all the same
_UNUSED = "; every column of a table must be numeric, even one the command does not use: remove the column"


def _parse(path, column, line, text, note=""):
    try:
        value = cell_number(text)   # plain ASCII numbers: float() also reads 6_0 and Unicode digits
    except ValueError:
        raise InputError(path, column, f"line {line}: non-numeric value {text.strip()!r}{note}") from None
    if math.isnan(value) or math.isinf(value):
        raise InputError(path, column, f"line {line}: {'NaN' if math.isnan(value) else 'infinite'} value{note}")
    if abs(value) > VALUE_LIMIT:
        raise InputError(path, column, f"line {line}: {text.strip()} is beyond +-{VALUE_LIMIT:g}: not a measured time, "
                                       "temperature or error in any unit")
    return value


def _load_csv(path, target, inputs, time_column, field="file"):
    try:
        lines, rows = data_rows(read_text(path, field, "table"))
    except csv.Error as exc:
        raise InputError(path, "file", f"cannot read CSV: {exc}") from None
    if not rows:
        raise InputError(path, "header", "empty file")
    header = [h.strip() for h in rows[0]]
    if "" in header:
        raise InputError(path, "header", f"column {header.index('') + 1} has no name; name every column")
    if len(set(header)) != len(header):
        dup = sorted({h for h in header if header.count(h) > 1})
        raise InputError(path, dup[0], "duplicate column name")
    for name, what in ((time_column, "time column"), (target, "target column")):
        if name not in header:
            raise InputError(path, name, f"missing {what}; columns: {', '.join(header)}")
    if inputs is None:
        inputs = [h for h in header if h not in (time_column, target)]
    for name in inputs:
        if name not in header:
            raise InputError(path, name, f"missing input column; columns: {', '.join(header)}")
    used = [time_column, target, *inputs]
    notes = ["" if name in used else _UNUSED for name in header]
    data = np.empty((len(rows) - 1, len(header)))
    for i, (line, row) in enumerate(zip(lines[1:], rows[1:])):
        if len(row) != len(header):
            raise InputError(path, f"line {line}", f"{len(row)} fields, header has {len(header)}")
        for j, (name, cell) in enumerate(zip(header, row)):     # every column, used or not
            if not cell.strip():
                raise InputError(path, name, f"line {line}: missing value (NaN){notes[j]}")
            data[i, j] = _parse(path, name, line, cell, notes[j])
    data = data[:, [header.index(c) for c in used]]
    back = np.flatnonzero(np.diff(data[:, 0]) <= 0)
    if back.size:          # named by the line an editor shows (load_table checks a NetCDF's samples)
        i = int(back[0]) + 1
        raise InputError(path, time_column, f"time is not strictly increasing at line {lines[1:][i]} "
                                            f"({data[i - 1, 0]:g} s then {data[i, 0]:g} s)")
    return data[:, 0], data[:, 2:], data[:, 1], list(inputs)


# ------------------------------------------------------------------------------------------- NetCDF


def _open_dataset(path, field="file"):
    """The result file at ``path`` read and checked as ``twin plot``, ``report`` and ``compare``
    read one (:func:`twin.io.measurement.read_checked_result`): every variable and coordinate, used
    by the learners or not."""
    from twin.io.measurement import read_checked_result

    return read_checked_result(path, field)


def _time_seconds(path, ds, time_column):
    name = time_column
    if name not in ds.variables:      # never another one silently
        raise InputError(path, time_column, f"missing time coordinate; coordinates: {', '.join(map(str, ds.coords))}")
    t = ds[name].values
    if np.issubdtype(t.dtype, np.datetime64):
        return (t - t[0]) / np.timedelta64(1, "s"), name
    if np.issubdtype(t.dtype, np.timedelta64):
        return t / np.timedelta64(1, "s"), name
    try:
        t = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise InputError(path, name, "time is not numeric") from None
    stated = stated_units(ds, name)
    if stated is None or not str(stated).strip():
        raise InputError(path, name, "states no units: a numeric time needs them (s, min or h, as a twin result's "
                                     "'s')")
    try:
        factor = parse_quantity(f"1 {str(stated).strip()}", "time")
    except UnitError as err:
        raise InputError(path, name, f"in {str(stated)!r}: {err}") from None
    return t * factor, name


def _finite(path, column, values):
    try:
        values = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(path, column, "non-numeric values") from None
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise InputError(path, column, f"NaN or infinite value at time index {int(bad[0])}")
    huge = np.flatnonzero(np.abs(values) > VALUE_LIMIT)
    if huge.size:
        raise InputError(path, column, f"{values.ravel()[huge[0]]:.3g} at time index {int(huge[0])} is beyond "
                                       f"+-{VALUE_LIMIT:g}: not a measured time, temperature or error in any unit")
    return values


def variable_unit(path, ds, var: str, address: str) -> str:
    """The unit ``var`` states (its ``units`` attribute): required, and a variable a twin result
    holds (:func:`twin.io.results.result_unit`) must state the result's unit (a drift in mm read as um would be
    1000 times too small), else an :class:`InputError` naming the file and ``address``."""
    stated = stated_units(ds, var)
    stated = "" if stated is None else str(stated).strip()
    expected = result_unit(var)
    if not stated:
        raise InputError(path, address, f"{var!r} states no units"
                         + (f" (a twin result holds it in {expected!r})" if expected else "")
                         + ": a NetCDF table is read as a twin result, whose variables carry them")
    if expected is not None and stated != expected:
        raise InputError(path, address, f"{var!r} is in {stated!r}; a twin result holds it in {expected!r}: convert "
                                        "it, or give a CSV table")
    return stated


def _series(path, ds, address, tname):
    """1-D values over time of ``var`` or ``var:label``, in their stated unit (checked, and
    plausible where it is a temperature, an error or a strain)."""
    var, _, label = address.partition(":")
    if var not in ds.variables or var == tname:
        raise InputError(path, address, f"no variable {var!r}; variables: {', '.join(map(str, ds.data_vars))}")
    return _plausible(path, address, variable_unit(path, ds, var, address), _values(path, ds, address, tname))


def _plausible(path, address, unit, values):
    if unit in _PLAUSIBLE:
        _PLAUSIBLE[unit](values, path, address)
    return values


def _values(path, ds, address, tname):
    var, _, label = address.partition(":")
    da = ds[var]
    if tname not in da.dims:
        raise InputError(path, address, f"variable {var!r} does not depend on {tname!r}")
    others = [d for d in da.dims if d != tname]
    if not label:
        if others:
            raise InputError(path, address, f"variable {var!r} also depends on {', '.join(others)}; "
                                            f"address one entry as {var}:<label>")
        return _finite(path, address, da.values)
    if len(others) != 1:
        raise InputError(path, address, f"variable {var!r} must have exactly one dimension besides time")
    dim = others[0]
    labels = [str(v) for v in da[dim].values]
    if label not in labels:
        raise InputError(path, address, f"no {dim} {label!r}; available: {', '.join(labels)}")
    if labels.count(label) > 1:     # which of them is the input? the first would be taken silently
        raise InputError(path, f"{dim}", f"{dim} {label!r} appears twice")
    return _finite(path, address, da.isel({dim: labels.index(label)}).transpose(tname).values)


def _load_netcdf(path, target, inputs, time_column, field="file"):
    ds = _open_dataset(path, field)
    time, tname = _time_seconds(path, ds, time_column)
    sensors = []
    if "temperature" in ds.data_vars and "sensor" in ds["temperature"].dims:
        sensors = [str(v) for v in ds["temperature"]["sensor"].values]
    if inputs is None:      # every sensor but the target (a temperature may be the target)
        var, _, label = str(target).partition(":")
        inputs = [s for s in sensors if not (var == "temperature" and s == label)]
        if not inputs:
            raise InputError(path, "temperature", "no temperature(time, sensor) variable to use as inputs"
                             + (f" besides the target {target}" if sensors else ""))
    columns = []
    for name in inputs:
        if name in sensors:
            columns.append(_series(path, ds, f"temperature:{name}", tname))
        elif name.partition(":")[0] in ds.variables:      # an address var or var:label
            columns.append(_series(path, ds, name, tname))
        else:   # a sensor this file lacks (a surface-grid sensor's name holds ':' too)
            raise InputError(path, name, f"missing input sensor; this file's sensors: {', '.join(sensors) or 'none'}")
    y = _series(path, ds, target, tname)
    X = np.column_stack(columns) if columns else np.empty((len(time), 0))
    unit = variable_unit(path, ds, target.partition(":")[0], target)
    return _finite(path, tname, time), X, y, list(inputs), unit


def target_unit(tables, target: str) -> str:
    """The target's unit, stated by the NetCDF files that hold it ("" when none does); files that
    state different units are refused (their scores would mix them)."""
    units = sorted({t.target_unit for t in tables if t.target_unit})
    if len(units) > 1:
        raise InputError("command line", "--target", f"{target} is in different units in the training and test "
                                                     f"files ({', '.join(units)})")
    return units[0] if units else ""
