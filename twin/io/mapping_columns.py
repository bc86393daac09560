"""One column entry of a measurement's column mapping (:mod:`twin.io.measurement`): the sensor a
temperature column names (a site of the machine, or a position with its part, and the sensor's
name), the laser or gauge an instrument column names, the C axis's duty, and the physical limits
of a column's values in SI units. Every problem raises :class:`twin.errors.InputError` naming the
mapping file and the key (``columns.T9.name``) or the CSV file and the column.
"""

from __future__ import annotations

import numpy as np

from twin import limits
from twin.errors import InputError, describe
from twin.units import UnitError, parse_quantity


def instrument(entry: dict, kind: str, known: list[str] | None, seen: dict, msrc: str, key: str) -> str:
    """The ``kind`` (laser, gauge) a column names: one of the machine's, given once."""
    if known is None:
        raise InputError(msrc, f"{key}.{kind}", f"a {kind} column needs the machine (top-level machine = \"...\")")
    name = entry.get(kind)
    if not isinstance(name, str) or name not in known:
        raise InputError(msrc, f"{key}.{kind}", ("missing" if name is None else f"unknown {kind} {describe(name)}")
                         + f"; known: {', '.join(known) or 'none'}")
    if name in seen:
        raise InputError(msrc, f"{key}.{kind}", f"{kind} {name} mapped twice")
    return name


def duty_fraction(value, msrc: str, key: str) -> float:
    """The C axis's duty (fraction of the time turning, 0 < d <= 1)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 1:
        raise InputError(msrc, key, f"expected a fraction of the time turning, 0 < duty <= 1, got {describe(value)}")
    return float(value)


def check_values(values: np.ndarray, role: str, mach, src: str, column: str, lines=None) -> None:
    """Physical limits of one CSV column in SI units (:mod:`twin.limits`); ``lines``: the file's
    line number of each value, which an error names."""
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        where = f"line {lines[bad[0]]}: " if lines is not None else ""
        raise InputError(src, column, f"{where}a value overflows its unit's range")
    if role == "spindle_speed":
        limits.check_speeds(values, mach, src, column, logged=True, lines=lines)
    elif role == "ambient_temperature":
        limits.check_temperatures(values, src, column, "air", lines=lines)
    elif role == "temperature":
        limits.check_temperatures(values, src, column, "structure", lines=lines)
    elif role in ("probe", "laser"):
        limits.check_displacements(values, src, column, lines=lines)
    elif role == "strain":
        limits.check_strains(values, src, column, lines=lines)
    elif role == "c_axis_speed":
        limits.check_c_axis_speeds(values, mach, src, column, logged=True, lines=lines)


BAD_NAME_CHARACTERS = "@:,"   # '@' suffixes a channel with its measurement, ':' parts group from name, ',' lists names
NETCDF_BAD_NAME_CHARACTERS = "@,"   # a result's surface-grid sensors are named part:face:u:v (twin.observe.sensor_grid)


def sensor_name(entry: dict, default: str, msrc: str, key: str) -> str:
    """The sensor name of a temperature column: ``name`` if given (a non-empty string without
    '@', ':' or ','), else ``default`` (its site, or the column's name)."""
    if "name" not in entry:
        bad = [c for c in BAD_NAME_CHARACTERS if c in default]
        if bad:
            raise InputError(msrc, key, f"the sensor name {default!r} (from the column) may not contain "
                             f"{bad[0]!r}; give name = \"...\"")
        return default
    return check_sensor_name(entry["name"], msrc, key + ".name")


def check_sensor_name(name, src: str, field: str, forbidden: str = BAD_NAME_CHARACTERS) -> str:
    """A sensor's name as given (in a mapping or a NetCDF measurement): a non-empty, printable
    string without leading or trailing spaces and without the ``forbidden`` characters (a
    mapping's names: '@', ':' and ','; a NetCDF file's: '@' and ',', since the twin's own surface
    grid names its points ``part:face:u:v``, which a channel name ``temperature:<name>`` keeps
    whole)."""
    if not isinstance(name, str):
        raise InputError(src, field, f"expected a sensor name (a string), got {describe(name)}")
    if not name.strip():
        raise InputError(src, field, "the sensor name is empty")
    bad = [c for c in forbidden if c in name]
    if bad or any(not c.isprintable() for c in name) or name != name.strip():
        raise InputError(src, field, f"sensor name {name!r} may not contain "
                         + (f"{bad[0]!r}" if bad else "control characters or leading/trailing spaces")
                         + f" (names must not contain {', '.join(repr(c) for c in forbidden)})")
    return name


def sensor(entry: dict, name: str, values: np.ndarray, mach, msrc: str, key: str):
    if "site" in entry:
        both = [c for c in ("x", "y", "z", "part") if c in entry]
        if both:
            raise InputError(msrc, f"{key}.{both[0]}", "a sensor is placed at a named site or at a position "
                             "(x, y, z, part), not both; give either site or a position")
        if mach is None:
            raise InputError(msrc, key + ".site", "a named site needs a machine (top-level machine = \"...\")")
        site = entry["site"]
        if not isinstance(site, str):
            raise InputError(msrc, key + ".site", f"expected a sensor site's name such as \"motor\", got {describe(site)}")
        from geometries.axes import with_feed_drives
        mach = with_feed_drives(mach)   # the feed drives' sites (seed 003's) are sites too
        sites = list(mach.sensor_sites) + list(mach.air_sites)
        if site not in sites:
            raise InputError(msrc, key + ".site", f"machine {mach.name} has no sensor site {site!r}; known: {', '.join(sites)}")
        p = mach.point(site)
        return (sensor_name(entry, str(site), msrc, key), tuple(p.xyz), p.part, values)
    try:
        xyz = tuple(parse_quantity(entry[c], "length") for c in "xyz")
    except KeyError as err:
        raise InputError(msrc, f"{key}.{err.args[0]}", "a temperature column needs site = NAME or x, y, z") from None
    except UnitError as err:
        raise InputError(msrc, key, str(err)) from None
    part = str(entry.get("part", ""))
    if mach is not None:
        limits.check_position(mach, xyz, part, msrc, key)
    return (sensor_name(entry, name, msrc, key), xyz, part, values)
