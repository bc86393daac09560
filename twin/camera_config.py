"""Thermal cameras from the user: ``--camera NAME[,NAME]`` and a scenario's ``[camera]`` section.

A scenario may hold one ``[camera]`` table or a ``[[camera]]`` list; every value carries its unit::

    [camera]
    pose = "carrier-front"              # a pose of the machine (`overview-front` works for any), or:
    # position = ["0 m", "-1.62 m", "1.325 m"]; target = [...]; up = [0, 0, 1]
    name = "carrier"                    # optional; names the variables when there are several cameras
    resolution = [320, 240]             # pixels (width, height)
    field_of_view = ["24 deg", "18 deg"]
    ifov = "1.5 mrad"
    band = ["7.5 um", "13 um"]
    frame_interval = "10 s"             # a whole multiple of the sample interval (default: every sample)
    edge_rays = 3                       # n x n rays in pixels at edges (1: centre rays only)
    store_counts = false                # also store the 14-bit counts (they are recoverable anyway)

    [camera.settings]                   # what the thermographer types into the camera
    emissivity = 0.95
    reflected_temperature = "20 degC"   # default: the room air at the start
    distance = "1.5 m"                  # default: the pose's distance to its target
    air_temperature = "20 degC"         # default: the room air at the start
    relative_humidity = "30 %"

    [camera.scene]                      # the truth the camera looks at
    room_temperature = "20 degC"        # radiant temperature of the surroundings (default: the room air)
    relative_humidity = "30 %"
    wall_distance = "5 m"

    [camera.sensor]                     # the microbolometer (defaults: FLIR ThermaCAM S65, seed 001)
    netd = "0.08 K"                     # also fixed_pattern, row_fixed, column_fixed, row_temporal,
    offset = "0.5 K"                    # column_temporal, frame_temporal, drift (K), drift_time,
    accuracy = "2 K"                    # reference_temperature, bits, range = ["-40 degC", "120 degC"]

Unknown keys, missing units and values out of range raise :class:`twin.errors.InputError` naming
the file and the key (``camera[1].settings.emissivity``), with the limit and its unit. Plausible
limits (the constants of :mod:`twin.observe.camera_checks`, each with its reason): ``position``
and ``target`` differ, ``up`` is a finite direction not along the line of sight, and the camera
stands in the air, not inside a part of the machine (checked against the machine when the camera
is set up, before the run); ``position`` lies within 100 m of the machine's origin and ``target``
within 100 m of ``position``, and ``settings.distance`` and ``scene.wall_distance`` are 0 to 100 m
(a large workshop hall; FLIR's air-path model keeps its transmission above 0.6 there and turns
negative near 290 m, :data:`~twin.observe.camera_checks.MAX_DISTANCE`); ``band`` lies within the
thermal infrared, 2 to 14 um (MWIR 3-5 um, LWIR 7.5-14 um; below 2 um a room-temperature body emits
next to nothing, :data:`~twin.observe.camera_checks.BAND`); each ``field_of_view`` angle is 2 to
120 deg (telephoto to the widest rectilinear lens) and ``ifov`` 0.01 to 100 mrad; ``resolution``
1 to 8192 px a side; ``edge_rays`` 1 to 8; ``emissivity`` above 0 and at most 1; each
``relative_humidity`` 0 to 100 %; ``air_temperature`` is room air (-40 to 60 degC,
:data:`twin.limits.AIR_RANGE`); ``reflected_temperature`` and ``room_temperature`` lie from -40 to
200 degC (what surrounds a machine tool, :data:`twin.limits.STRUCTURE_RANGE`); the sensor's
``netd`` and the other noise terms (``fixed_pattern``, ``row_fixed``, ``column_fixed``,
``row_temporal``, ``column_temporal``, ``frame_temporal``) are 0 to 1 K, ``offset``, ``drift`` and
``accuracy`` 0 to 10 K, ``drift_time`` 1 s to 7 d, ``bits`` 8 to 16, its ``range`` and
``reference_temperature`` within the twin's radiance table, -100 to 1000 degC; every temperature
above absolute zero.
"""

from __future__ import annotations

from twin import limits
from twin.errors import InputError, describe
from twin.io.table_reader import TableReader
from twin.observe.camera import CameraConfig
from twin.observe.camera_checks import (BITS, EDGE_RAYS, MAX_PIXELS, NOISE_TERMS, RADIANCE_SPAN, check_camera_values,
                                        check_temperature)
from twin.observe.camera_geometry import Intrinsics
from twin.observe.microbolometer import Microbolometer
from twin.units import UnitError, parse_quantity


def cameras_from_option(text: str | None) -> list[CameraConfig]:
    """``--camera NAME[,NAME]``: cameras at the machine's named poses, default settings."""
    if text is None:
        return []
    names = [n.strip() for n in text.split(",")]
    if not all(names):
        raise InputError("command line", "--camera", f"expected NAME[,NAME], got {text!r}")
    return [CameraConfig(pose=n, source="command line", where="--camera") for n in names]


def cameras_from_toml(value, source: str) -> tuple[CameraConfig, ...]:
    """The cameras of a scenario's ``camera`` key (a table or a list of tables)."""
    if value is None:
        return ()
    tables = value if isinstance(value, list) else [value]
    if not tables:
        raise InputError(source, "camera", "expected a [camera] table or [[camera]] tables")
    many = isinstance(value, list)
    return tuple(_camera(t, source, f"camera[{i}]." if many else "camera.") for i, t in enumerate(tables))


def _camera(table, source: str, prefix: str) -> CameraConfig:
    r = TableReader(table, source, prefix)
    kw = {"source": source, "where": prefix}
    pose = r.get("pose")
    position, target = _vector(r, "position"), _vector(r, "target")
    up = r.get("up")
    if position is not None or target is not None:      # the pair, its distance and the up: check_camera_values
        if pose is not None:
            raise InputError(source, prefix + "pose", "give a pose or a position and a target, not both")
        kw.update(position=position, target=target)
        if up is not None:
            if not (isinstance(up, list) and len(up) == 3
                    and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in up)):
                raise InputError(source, prefix + "up", "expected three numbers, a direction")
            kw["up"] = tuple(float(x) for x in up)
    elif up is not None:
        raise InputError(source, prefix + "up", "goes with position and target")
    if pose is not None:
        kw["pose"] = _text(pose, source, prefix + "pose")
    name = r.get("name")
    if name is not None:
        kw["name"] = _text(name, source, prefix + "name")
    kw["intrinsics"] = _intrinsics(r, source, prefix)
    band = _pair(r, "band", "length")
    if band is not None:
        kw["band"] = band
    interval = r.positive("frame_interval", "time")
    if interval is not None:
        kw["frame_interval"] = interval
    edge = r.get("edge_rays")
    if edge is not None:
        kw["edge_rays"] = _integer(edge, source, prefix + "edge_rays", *EDGE_RAYS)
    counts = r.get("store_counts")
    if counts is not None:
        if not isinstance(counts, bool):
            raise InputError(source, prefix + "store_counts", "expected true or false")
        kw["store_counts"] = counts
    kw.update(_settings(r.get("settings"), source, prefix + "settings."))
    kw.update(_scene(r.get("scene"), source, prefix + "scene."))
    sensor = r.get("sensor")
    if sensor is not None:
        kw["sensor"] = _sensor(sensor, source, prefix + "sensor.")
    r.finish()
    config = CameraConfig(**kw)
    check_camera_values(config)          # the values' rules, one set for files and Python (camera_checks)
    return config


def _intrinsics(r, source: str, prefix: str) -> Intrinsics:
    kw = {}
    res = r.get("resolution")
    if res is not None:
        if not (isinstance(res, list) and len(res) == 2):
            raise InputError(source, prefix + "resolution", "expected [width, height] in pixels")
        kw["width"], kw["height"] = (_integer(x, source, prefix + "resolution", 1, MAX_PIXELS) for x in res)
    fov = _pair(r, "field_of_view", "angle")
    if fov is not None:
        kw["fov_h"], kw["fov_v"] = fov
    ifov = r.positive("ifov", "angle")
    if ifov is not None:
        kw["ifov"] = ifov
    return Intrinsics(**kw)


def _settings(table, source: str, prefix: str) -> dict:
    if table is None:
        return {}
    r = TableReader(table, source, prefix)
    kw = {"emissivity": _fraction(r, "emissivity", positive=True),
          "reflected_temperature": _temperature(r, "reflected_temperature", limits.STRUCTURE_RANGE,
                                                "what a machine-tool surface reflects"),
          "distance": _non_negative(r, "distance", "length"),
          "air_temperature": _temperature(r, "air_temperature", limits.AIR_RANGE, "room air"),
          "relative_humidity": _fraction(r, "relative_humidity")}
    r.finish()
    return {k: v for k, v in kw.items() if v is not None}


def _scene(table, source: str, prefix: str) -> dict:
    if table is None:
        return {}
    r = TableReader(table, source, prefix)
    kw = {"room_temperature": _temperature(r, "room_temperature", limits.STRUCTURE_RANGE,
                                           "the surroundings of a machine tool"),
          "room_humidity": _fraction(r, "relative_humidity"),
          "wall_distance": _non_negative(r, "wall_distance", "length")}
    r.finish()
    return {k: v for k, v in kw.items() if v is not None}


def _sensor(table, source: str, prefix: str) -> Microbolometer:
    r = TableReader(table, source, prefix)
    kw = {k: _non_negative(r, k, "temperature_difference") for k in NOISE_TERMS}
    kw["drift_time"] = r.positive("drift_time", "time")
    kw["reference_temperature"] = _temperature(r, "reference_temperature", RADIANCE_SPAN, "the twin's radiance table")
    bits = r.get("bits")
    kw["bits"] = None if bits is None else _integer(bits, source, prefix + "bits", *BITS)
    kw["range"] = _pair(r, "range", "temperature")        # within the radiance table, in order: camera_checks
    r.finish()
    return Microbolometer(**{k: v for k, v in kw.items() if v is not None})


def _fraction(r, key: str, positive: bool = False):
    value = r.get(key, "dimensionless")
    if value is not None and not (0 < value <= 1 if positive else 0 <= value <= 1):
        raise InputError(r.source, r.prefix + key, f"must lie in {'(0' if positive else '[0'}, 1] (or 0-100 %), "
                                                   f"got {describe(r.table[key])}")
    return value


def _temperature(r, key: str, span: tuple, what: str):
    """A temperature [degC] key, above absolute zero and within ``span`` (the plausible range of ``what``)."""
    value = r.get(key, "temperature")
    if value is not None:
        check_temperature(value, span, what, r.source, r.prefix + key)
    return value


def _non_negative(r, key: str, dimension: str):
    value = r.get(key, dimension)
    if value is not None and value < 0:
        raise InputError(r.source, r.prefix + key, f"must not be negative, got {describe(r.table[key])}")
    return value


def _vector(r, key: str):
    value = r.get(key)
    if value is None:
        return None
    if not (isinstance(value, list) and len(value) == 3):
        raise InputError(r.source, r.prefix + key, "expected three lengths, e.g. [\"0 m\", \"-1.5 m\", \"1.3 m\"]")
    return tuple(_quantity(v, "length", r.source, f"{r.prefix}{key}[{i}]") for i, v in enumerate(value))


def _pair(r, key: str, dimension: str):
    value = r.get(key)
    if value is None:
        return None
    if not (isinstance(value, list) and len(value) == 2):
        raise InputError(r.source, r.prefix + key, "expected two quantities")
    return tuple(_quantity(v, dimension, r.source, f"{r.prefix}{key}[{i}]") for i, v in enumerate(value))


def _quantity(value, dimension: str, source: str, field: str) -> float:
    try:
        return parse_quantity(value, dimension)
    except UnitError as err:
        raise InputError(source, field, str(err)) from None


def _integer(value, source: str, field: str, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise InputError(source, field, f"expected a whole number from {lo} to {hi}, got {describe(value)}")
    return int(value)


def _text(value, source: str, field: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise InputError(source, field, "expected a name")
    return value
