"""Point temperature sensors: glued to a part (trilinear interpolation of the field) or in the air.

A sensor whose site is on a part reads T at its point through the sensor model of
:func:`twin.observe.instruments.temperature_reading` (first-order lag, bias, noise, quantisation).
A sensor in the air (``part == "air"``, a machine's ``air_sites``) reads the air temperature the
model assumes there: the room air T_air(t) plus what the model's effects add to it at the
sensor's height (:meth:`twin.effects.base.Effect.air_change`: g (z - z_ref) of
``ambient_stratification``, s (z - z_ref) (T_air(t) - T_air(0)) of ``stratified_swing``). Its rows
are zero: the model's air does not depend on the structure's temperature.
"""

from __future__ import annotations

import numpy as np

from twin import limits
from twin.effects import EFFECTS
from twin.errors import InputError
from twin.fem.points import interpolation_matrix
from twin.observe.base import Observer, RunContext, variable
from twin.observe.instruments import temperature_reading

AIR = "air"
RECORDED = "temperature_recorded"   # RunContext.extra key: {sensor name: its readings [degC]}


def air_temperature(points, ctx: RunContext) -> np.ndarray:
    """(n_t, n_points) the model's air temperature [degC] at ``points`` over the run."""
    air = np.asarray(ctx.scenario.ambient_temperature(ctx.times), float)[:, None]
    z = np.array([p.xyz[2] for p in points], float)
    out = np.repeat(air, len(points), axis=1)
    for name in ctx.spec.effects:
        change = EFFECTS[name].air_change(z, np.asarray(ctx.times, float), ctx.scenario, ctx.spec.params[name])
        if change is not None:
            out = out + change
    return out


def check_points(points, machine, source: str, field: str = "sensors") -> list:
    """``points``: a list of :class:`geometries.base.Point` s with distinct names a measurement
    file can hold (printable, without '@' or ','), each three finite coordinates [m] on its part of
    ``machine`` (anywhere on it when the part is empty) or in the air near it
    (:func:`twin.limits.check_position`; not checked without a machine, None); an
    :class:`InputError` naming ``field[i]`` otherwise."""
    from geometries.base import Point
    from twin.io.mapping_columns import NETCDF_BAD_NAME_CHARACTERS, check_sensor_name

    if isinstance(points, (str, bytes)) or not isinstance(points, (list, tuple)):
        raise InputError(source, field, f"expected a list of geometries.base.Point, got {points!r}")
    seen = set()
    for i, p in enumerate(points):
        if not isinstance(p, Point):
            raise InputError(source, f"{field}[{i}]", f"expected a geometries.base.Point(name, (x, y, z) [m], part), "
                                                      f"got {p!r}")
        # the name a measurement file can hold (twin.io.measurement_writer, read back by read_measurement)
        check_sensor_name(p.name, source, f"{field}[{i}]", NETCDF_BAD_NAME_CHARACTERS)
        where = f"{field}[{i}] {p.name}"
        if p.name in seen:
            raise InputError(source, where, "named twice: sensors need distinct names")
        seen.add(p.name)
        if not isinstance(p.part, str):
            raise InputError(source, where, f"a sensor's part is a part name (or 'air'), got {p.part!r}")
        try:
            xyz = np.asarray(p.xyz, dtype=float)
        except (TypeError, ValueError):
            xyz = None
        if xyz is None or xyz.shape != (3,):
            raise InputError(source, where, f"a position is three numbers (x, y, z) [m], got {p.xyz!r}")
        if machine is not None:
            limits.check_position(machine, xyz, p.part, source, where)
    return list(points)


class TemperatureSensors(Observer):
    """Temperature sensors at ``points`` (:class:`geometries.base.Point`); variables
    ``temperature`` (as measured) and ``temperature_true`` (time, sensor) [degC] with the sensor
    coordinates ``x, y, z`` [m] and ``part``."""

    key = "temperature"
    raw_unit = "K"

    def __init__(self, points):
        self.points = check_points(points, None, "TemperatureSensors", "points")   # their machine: at rows()
        self.air = np.array([p.part == AIR for p in self.points], bool)

    def cache_key(self) -> tuple:
        return (type(self).__name__, tuple((p.name, tuple(p.xyz), p.part) for p in self.points))

    def rows(self, twin, loads):
        check_points(self.points, twin.machine, "TemperatureSensors", "points")   # built in Python: checked here
        layout = loads.mm
        rows = np.zeros((len(self.points), layout.nheat))
        glued = np.flatnonzero(~self.air)
        if len(glued):
            pts = [self.points[i] for i in glued]
            rows[glued] = interpolation_matrix(layout, [p.xyz for p in pts], [p.name for p in pts]).toarray()
        return rows

    def true_values(self, raw: np.ndarray, ctx: RunContext) -> np.ndarray:
        """(n_t, n_sensor) true temperatures [degC]: the field at glued sites, the air elsewhere."""
        out = np.array(raw, dtype=float, copy=True)
        if self.air.any():
            out[:, self.air] = air_temperature([p for p, a in zip(self.points, self.air) if a], ctx)
        return out

    def data(self, raw, ctx):
        true = self.true_values(raw, ctx)
        meas = temperature_reading(true, ctx.scenario.sample_interval, ctx.spec.params["temperature_sensor"], ctx.rng)
        pts = self.points
        # what each sensor recorded, for instruments compensated with it (FBG gauges, twin.observe.strain)
        ctx.extra.setdefault(RECORDED, {}).update({p.name: meas[:, i] for i, p in enumerate(pts)})
        data = {"temperature": variable(("time", "sensor"), meas, "degC", "temperature as measured (sensor model)"),
                "temperature_true": variable(("time", "sensor"), true, "degC", "true temperature at the sensor site")}
        coords = {
            "sensor": ("sensor", [p.name for p in pts], {"long_name": "temperature sensor site"}),
            "x": ("sensor", [p.xyz[0] for p in pts], {"units": "m", "long_name": "sensor x"}),
            "y": ("sensor", [p.xyz[1] for p in pts], {"units": "m", "long_name": "sensor y"}),
            "z": ("sensor", [p.xyz[2] for p in pts], {"units": "m", "long_name": "sensor z"}),
            "part": ("sensor", [p.part for p in pts], {"long_name": "part carrying the sensor (air: in the air)"}),
        }
        return data, coords
