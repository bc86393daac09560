"""Package a run as one xarray Dataset (CF units and long names) and write it atomically.

Schema: ``time`` [s]; the inputs ``spindle_speed`` [rpm] and ``ambient_temperature`` [degC]
(and ``c_axis_speed`` [rpm], ``c_axis_duty`` [1] when the scenario turns a C axis);
then every observer's own variables (:mod:`twin.observe`), for the standard set:
``temperature(time, sensor)`` as measured and ``temperature_true`` [degC] with sensor coordinates
``x, y, z`` [m] and ``part``; ``drift(time, axis)`` [um], the true tool-point drift (tool relative
to the table); ``probe(time, probe_id)`` [um] for X1 X2 Y1 Y2 Z and ``probe_true``;
``probe_drift(time, axis)`` [um] derived from the probe readings; ``tilt(time, rotation)`` [urad]
for A, B from the probe readings and ``tilt_true``; on machines with them, ``laser(time,
laser_id)`` [um] and ``laser_tilt`` [urad] (:mod:`twin.observe.triangulation`) and ``strain(time,
gauge)`` [um/m] with ``strain_raw`` and ``strain_true`` (:mod:`twin.observe.strain`);
``heat_power(time, effect)`` [W] into the structure. Attributes: provenance (package version, machine, scenario, effects, every parameter
with its unit, mesh, seed, time step) and the energy balance of the run.
(The probe dimension is ``probe_id`` because xarray forbids a variable named like its dimension.)
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import xarray as xr

from twin.errors import InputError, describe
from twin.io.atomic import atomic_write
from twin.io.paths import NETCDF_SUFFIXES, as_path, input_file
from twin.units import clean
from twin.observe.base import variable
from twin.scenario import recorded_source
from twin.version import package_version


def to_dataset(r, seed: int = 0, resolution: str = "", scenario_label: str = "") -> xr.Dataset:
    """Apply the instrument models (seeded) and build the result Dataset of a
    :class:`twin.simulate.RunResult`: the inputs, then each observer's variables in order.
    ``seed``: the instruments' noise seed, an integer from 0 to 2**32 - 1; ``resolution``: the
    mesh's name as the result's ``mesh`` attribute (a text)."""
    from twin import limits

    seed = limits.seed_value(seed, "command line", "seed")
    if not isinstance(resolution, str) or not isinstance(scenario_label, str):
        raise InputError("command line", "resolution", f"expected texts for resolution and scenario_label, got "
                                                       f"{resolution!r}, {scenario_label!r}")
    machine, spec, sc = r.machine, r.spec, r.scenario
    ctx = r.context(seed)
    data = {"spindle_speed": variable("time", sc.spindle_speed(r.times), "rpm", "spindle speed"),
            "ambient_temperature": variable("time", sc.ambient_temperature(r.times), "degC", "room air temperature")}
    if getattr(sc, "c_axis", None) is not None:
        data["c_axis_speed"] = variable("time", sc.c_axis.speed(r.times), "rpm", "C-axis speed while turning")
        data["c_axis_duty"] = variable("time", sc.c_axis.duty(r.times), "1", "fraction of the time the C axis turns")
    coords = {"time": ("time", r.times, {"units": "s", "long_name": "time since start"})}
    attrs = {}
    for obs in r.observers:
        raw = r.readings[obs.key]
        more, more_coords = obs.data(raw, ctx)
        data.update(more)
        coords.update(more_coords)
        attrs.update(obs.attrs(raw, ctx))
    params = {g: {p.name: f"{vals[p.name]:.6g} {p.unit}".strip() for p in spec.parameter_table(g)}
              for g, vals in spec.params.items()}
    attrs = {
        "title": f"thermal-twin simulation: {machine.name} / {sc.name}",
        "package_version": package_version(),
        "machine": machine.name,
        "scenario": scenario_label or sc.name,
        "scenario_source": recorded_source(sc.source),
        **({"moved_axes": ",".join(m.axis for m in sc.axes)} if sc.axes else {}),   # the motion is the scenario's
        "effects": ",".join(spec.effects),
        "parameters": json.dumps(params, sort_keys=True),
        "mesh": resolution,
        "mesh_nodes": r.mm.nnodes,
        "mesh_cells": r.mm.ncells,
        "seed": seed,
        "theta": r.theta,
        "time_step_s": sc.sample_interval,
        "reference_temperature_degC": clean(sc.start_temperature),
        **({"hottest_time_s": r.hottest_time} if any(o.key == "hottest" for o in r.observers) else {}),
        **attrs,
        **solver_attrs(getattr(r, "solver_info", {})),
        "Conventions": "CF-1.8",
    }
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


def solver_attrs(info: dict) -> dict:
    """What solved the run, as NetCDF attributes: scalars as they are, per-output errors
    (``solver_error_bound``, ``rom_error_estimate``, ``rom_error_bound``: {observer key: [value per
    output]} in the observer's raw SI unit, which ``solver_error_units`` gives per key: m, m/m, K,
    and for the heat balance J and K m2) as JSON. Wall times (:data:`WALL_TIMES`) are left out: a
    result is a function of its inputs, the same bytes every time (the benchmark reports them)."""
    if any(k in info for k in ERROR_KEYS) and "solver_error_units" not in info:
        raise ValueError("per-output solver errors without their units (solver_error_units)")
    return {k: (json.dumps(v, sort_keys=True) if isinstance(v, (dict, list)) else v) for k, v in info.items()
            if k not in WALL_TIMES}


# run-information keys that are wall times, never written into a result
WALL_TIMES = ("rom_offline_s", "heat_start_basis_s")

# the per-output solver errors a result may carry (in the observers' raw SI units, not the
# variables' um: ``solver_error_units`` beside them)
ERROR_KEYS = ("solver_error_bound", "rom_error_estimate", "rom_error_bound")


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike, field: str = "output") -> Path:
    """Write ``ds`` to ``path`` atomically (see :mod:`twin.io.atomic`); a Dataset with NaN or inf
    in a numeric variable is refused (:class:`twin.errors.InputError`), never written, and so
    is a path without a NetCDF suffix (``.nc``, ``.nc4``, ``.netcdf``)."""
    if not isinstance(ds, xr.Dataset):
        raise InputError(str(path), field, f"expected an xarray.Dataset to write, got {describe(ds)}")
    suffix = as_path(path, field).suffix
    if suffix.lower() not in NETCDF_SUFFIXES:
        raise InputError(str(path), field, f"a NetCDF file is named {', '.join(NETCDF_SUFFIXES)}, not "
                                           f"{suffix or 'without a suffix'}")
    check_finite(ds, str(path))
    # about the file's size: the values uncompressed, the attributes and 8 KiB of HDF5 structures
    # for the file and for each variable
    size = ds.nbytes + sum(len(str(v)) for v in ds.attrs.values()) + 8192 * (1 + len(ds.variables))
    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="h5netcdf"), field, size_hint=size)


def check_finite(ds: xr.Dataset, source: str) -> None:
    """Raise :class:`twin.errors.InputError` naming the first numeric variable or coordinate of
    ``ds`` that holds NaN or inf (and where along time). A variable whose attribute ``nan_means``
    declares what NaN stands for (a camera pixel that sees the room has no depth) may hold NaN
    there, never inf."""
    for name, var in {**ds.coords, **ds.data_vars}.items():
        values = var.values
        if values.dtype.kind not in "fc":
            continue
        allowed = np.isnan(values) if "nan_means" in var.attrs else False
        if np.all(np.isfinite(values) | allowed):
            continue
        where = ""
        if "time" in var.dims and "time" in ds.coords:
            bad = (~np.isfinite(var.transpose("time", ...).values)).reshape(len(ds.time), -1).any(axis=1)
            where = f" from t = {float(ds.time.values[np.flatnonzero(bad)[0]]):g} s"
        raise InputError(source, str(name), f"holds NaN or infinite values{where}")


# the unit each variable of a twin result is written in (its ``*_true`` twin alike); a NetCDF file
# the twin reads (a result, a measurement, a learner's table) must state these where it states one
RESULT_UNITS = {"time": "s", "temperature": "degC", "ambient_temperature": "degC", "probe": "um", "laser": "um",
                "strain": "um/m", "strain_raw": "um/m", "spindle_speed": "rpm", "c_axis_speed": "rpm",
                "axis_position": "mm", "positioning_error": "um", "drift": "um", "probe_drift": "um", "tilt": "urad",
                "laser_tilt": "urad", "heat_power": "W"}
# the dimensions a twin result gives each variable it writes (its ``_true`` twin the same): the
# readers count on them (a drift with a third dimension is not a drift); positioning_error's
# ``direction`` (forward, backward) is optional in a measurement
RESULT_DIMS = {"spindle_speed": ("time",), "ambient_temperature": ("time",), "c_axis_speed": ("time",),
               "c_axis_duty": ("time",), "temperature": ("time", "sensor"), "probe": ("time", "probe_id"),
               "laser": ("time", "laser_id"), "strain": ("time", "gauge"), "strain_raw": ("time", "gauge"),
               "drift": ("time", "axis"), "probe_drift": ("time", "axis"), "tilt": ("time", "rotation"),
               "laser_tilt": ("time",), "axis_position": ("time", "axis_name"), "heat_power": ("time", "effect"),
               "positioning_error": ("run_time", "target", "direction")}
OPTIONAL_DIMS = {"positioning_error": ("direction",)}
# dimensions that name their channels: a variable along them needs the coordinate (its names)
NAMED_DIMS = ("sensor", "probe_id", "laser_id", "gauge", "axis", "rotation", "axis_name", "target")


# a camera's variables, ``<name>`` or ``<name>_<camera>`` (twin.io.thermography)
CAMERA_UNITS = {"thermogram": "degC", "surface_temperature": "degC", "frame_time": "s", "camera_lut": "degC"}


def result_unit(var: str) -> str | None:
    """The unit a twin result holds variable ``var`` in (None for one it does not write)."""
    base = str(var).removesuffix("_true")
    if base in RESULT_UNITS:
        return RESULT_UNITS[base]
    return next((unit for name, unit in CAMERA_UNITS.items() if base == name or base.startswith(name + "_")), None)


def stated_units(ds: xr.Dataset, var: str) -> str | None:
    """The unit variable ``var`` of ``ds`` states: its ``units`` attribute, or the one xarray moved
    into its encoding while decoding (None when it states none)."""
    return ds[var].attrs.get("units", ds[var].encoding.get("units"))


def check_result_units(ds: xr.Dataset, source: str) -> None:
    """Every variable of ``ds`` a twin result writes (:func:`result_unit`) states the twin's unit,
    else one :class:`InputError` naming ``source`` and the variable: a drift in mm or a tilt in
    mrad read as um and urad would be 1000 times too small, a thermogram in K 273 K too warm, and
    a variable that states no unit cannot be told from either (a twin result states every one)."""
    for var in ds.variables:
        expected, stated = result_unit(str(var)), stated_units(ds, var)
        if expected is None:
            continue
        if stated is None:
            raise InputError(source, str(var), f"states no unit; a NetCDF file is read as a twin result, which holds "
                                               f"{var} in {expected!r} and says so (attribute units): add it, or give "
                                               "a CSV with a column mapping")
        if str(stated).strip() != expected:
            raise InputError(source, str(var), f"in {str(stated)!r}; a NetCDF file is read as a twin result, which "
                                               f"holds {var} in {expected!r}: convert it, or give a CSV with a "
                                               "column mapping (which takes any unit)")


def check_result_layout(ds: xr.Dataset, source: str) -> None:
    """Every variable of ``ds`` a twin result writes has the result's dimensions (:data:`RESULT_DIMS`,
    in any order), and each of its channel dimensions its coordinate (the channels' names), else one
    :class:`InputError` naming ``source`` and the variable: a reader would otherwise drop it, or
    fail on it, without a word."""
    for var in ds.data_vars:
        base = str(var).removesuffix("_true")
        if base not in RESULT_DIMS:
            continue
        dims, expected = set(ds[var].dims), RESULT_DIMS[base]
        required = set(expected) - set(OPTIONAL_DIMS.get(base, ()))
        if not required <= dims <= set(expected):
            raise InputError(source, str(var), f"has dimensions ({', '.join(ds[var].dims)}); a twin result holds it "
                                               f"along ({', '.join(expected)})"
                                               + (f", {' and '.join(OPTIONAL_DIMS[base])} optional" if base in OPTIONAL_DIMS
                                                  else ""))
        unnamed = [d for d in ds[var].dims if d in NAMED_DIMS and d not in ds.coords]
        if unnamed:
            raise InputError(source, str(var), f"its dimension {unnamed[0]!r} has no coordinate: the channels need "
                                               f"their names (a coordinate {unnamed[0]} of labels)")


def dataset_source(ds, default: str = "measurement") -> str:
    """The file a Dataset came from, for messages: its ``source`` attribute (a measurement read
    from a CSV), the path xarray read it from, else ``default`` (a Dataset built in Python)."""
    attrs, encoding = getattr(ds, "attrs", {}), getattr(ds, "encoding", {})
    return str(attrs.get("source") or encoding.get("source") or default)


def placed_sensors(ds: xr.Dataset, source: str) -> bool:
    """Whether ``ds`` places its temperature sensors by coordinates x, y, z [m] along ``sensor``
    (all three; a result always does); an :class:`InputError` naming ``source`` for one or two of
    them without the rest."""
    given = [c for c in ("x", "y", "z") if c in ds.coords]
    if given and len(given) < 3:
        lacking = next(c for c in ("x", "y", "z") if c not in given)
        raise InputError(source, lacking, f"missing: the sensors' positions need all three coordinates x, y, z [m] "
                                          f"along sensor (the file gives {', '.join(given)})")
    return bool(given)


def read_result(path: str | os.PathLike, field: str = "file", required: tuple[str, ...] = (),
                min_samples: int = 2) -> xr.Dataset:
    """Load a NetCDF result or measurement, checked: a readable regular file
    (:func:`twin.io.paths.input_file`), a strictly increasing ``time`` coordinate with at least
    ``min_samples`` samples, every ``required`` variable present, every variable the twin writes in
    the twin's unit where it states one (:func:`check_result_units`) and along the twin's
    dimensions with named channels (:func:`check_result_layout`), no NaN or inf anywhere
    (:class:`twin.errors.InputError` naming file and variable)."""
    if isinstance(required, str) or not all(isinstance(v, str) for v in required):
        raise InputError("command line", "required", f"expected a tuple of variable names, got {required!r}")
    if not isinstance(min_samples, int) or min_samples < 1:
        raise InputError("command line", "min_samples", f"expected an integer >= 1, got {min_samples!r}")
    path = input_file(path, field, "NetCDF file")
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except Exception as err:  # noqa: BLE001 - any reader failure is a bad file for the user
        with open(path, "rb") as f:
            magic = f.read(4)
        if magic in (b"CDF\x01", b"CDF\x02", b"CDF\x05"):
            raise InputError(str(path), field, "a NetCDF-3 (classic) file; the twin reads NetCDF-4 (HDF5): convert it, "
                                               "e.g. xarray.open_dataset(path).to_netcdf(new_path, engine='h5netcdf')"
                             ) from None
        raise InputError(str(path), field, f"not a readable NetCDF file ({type(err).__name__})") from None
    ds.encoding["source"] = str(path)     # as typed (xarray's is the absolute path), for later messages
    if "time" not in ds.coords or "time" not in ds.dims:
        raise InputError(str(path), "time", "missing time coordinate; is this a twin result?")
    if ds.sizes["time"] < min_samples:
        raise InputError(str(path), "time", f"{ds.sizes['time']} sample(s); at least {min_samples} are needed")
    t = np.asarray(ds["time"].values)
    if t.dtype.kind in "fiu" and np.any(np.diff(t) <= 0):
        i = int(np.flatnonzero(np.diff(t) <= 0)[0])
        raise InputError(str(path), "time", f"time is not increasing at sample {i + 2} ({t[i]:g} -> {t[i + 1]:g} s)")
    missing = [v for v in required if v not in ds]
    if missing:
        raise InputError(str(path), missing[0], "missing variable; is this a twin result?")
    check_result_units(ds, str(path))
    check_result_layout(ds, str(path))
    check_finite(ds, str(path))
    return ds
