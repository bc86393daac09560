"""The values of a thermal camera's configuration checked as the scenario reader checks them, for
a :class:`twin.observe.camera.CameraConfig` (and its :class:`Intrinsics` and
:class:`Microbolometer`) built in Python: a NaN emissivity or an 0-bit ADC wrote a thermogram of
NaN, a 40-bit ADC asked for terabytes, a camera at its own target divided by zero. Each bad value
is one :class:`twin.errors.InputError` naming the field as a scenario file would
(``camera.settings.emissivity``, ``camera.sensor.bits``)."""

from __future__ import annotations

import math

import numpy as np

from twin import limits
from twin.errors import InputError
from twin.observe.camera_geometry import Intrinsics
from twin.observe.microbolometer import Microbolometer
from twin.observe.radiometry import RadianceTable
from twin.observe.raycast import BACKENDS

RADIANCE_SPAN = (RadianceTable.lo, RadianceTable.hi)   # degC: where the twin's radiance table holds
NOISE_TERMS = ("netd", "fixed_pattern", "row_fixed", "column_fixed", "row_temporal", "column_temporal",
               "frame_temporal", "offset", "drift", "accuracy")    # [K], each finite and not negative
MAX_PIXELS = 8192          # per side
BITS = (8, 16)             # an infrared camera's ADC
EDGE_RAYS = (1, 8)         # n x n rays in a pixel at an edge


def check_up(up: np.ndarray, sight: np.ndarray, source: str, field: str) -> None:
    """``up`` must be a finite, non-zero direction not along the line of sight ``sight``."""
    if not np.all(np.isfinite(up)):
        raise InputError(source, field, f"{list(up)} is not a finite direction")
    norm = float(np.linalg.norm(up))
    if norm == 0:
        raise InputError(source, field, "[0, 0, 0] is no direction; give the image's up, e.g. [0, 0, 1]")
    if np.linalg.norm(np.cross(sight / np.linalg.norm(sight), up / norm)) < 1e-6:
        raise InputError(source, field, f"{[float(x) for x in up]} is along the line of sight from position to "
                                        "target, so the image has no up; choose a direction across it")


def check_camera_values(c) -> None:
    """Every value of the camera configuration ``c`` within what the scenario reader accepts."""
    src, f = c.source, c.field
    if not isinstance(c.pose, str) or not c.pose.strip():
        raise InputError(src, f("pose"), f"expected a pose name, got {c.pose!r}")
    if c.name and not limits.is_file_name(c.name):
        raise InputError(src, f("name"), f"{c.name!r} cannot name a file: the camera's frames are exported into a "
                                         "folder of its name (no '/', '\\', '.', '..' or control characters)")
    if (c.position is None) != (c.target is None):
        raise InputError(src, f("target" if c.target is None else "position"), "position and target go together")
    if c.position is not None:
        ends = [_vector(v, src, f(key)) for key, v in (("position", c.position), ("target", c.target))]
        sight = ends[1] - ends[0]
        if np.linalg.norm(sight) < 1e-6:
            raise InputError(src, f("target"), "equals position; the camera looks from position towards target, "
                                              "so they must differ")
        check_up(_numbers(c.up, 3, src, f("up"), finite=False), sight, src, f("up"))
    _check_intrinsics(c.intrinsics, src, f)
    band = _numbers(c.band, 2, src, f("band"))
    if not 0 < band[0] < band[1]:
        raise InputError(src, f("band"), "needs 0 < lower < upper wavelength [m]")
    if c.frame_interval is not None:
        _positive(c.frame_interval, src, f("frame_interval"))
    if not limits.is_finite_number(c.emissivity) or not 0 < c.emissivity <= 1:
        raise InputError(src, f("settings.emissivity"), f"expected a fraction above 0 and at most 1, got {c.emissivity!r}")
    for key, value in (("settings.relative_humidity", c.relative_humidity), ("scene.relative_humidity", c.room_humidity)):
        if not limits.is_finite_number(value) or not 0 <= value <= 1:
            raise InputError(src, f(key), f"expected a fraction from 0 to 1, got {value!r}")
    for key, value, kind in (("settings.reflected_temperature", c.reflected_temperature, "structure"),
                             ("settings.air_temperature", c.air_temperature, "air"),
                             ("scene.room_temperature", c.room_temperature, "structure")):
        if value is not None:
            limits.finite_number(value, src, f(key))
            limits.check_temperatures(value, src, f(key), kind)
    for key, value in (("settings.distance", c.distance), ("scene.wall_distance", c.wall_distance)):
        if value is not None and (not limits.is_finite_number(value) or value < 0):
            raise InputError(src, f(key), f"expected a finite distance >= 0 [m], got {value!r}")
    _whole(c.edge_rays, *EDGE_RAYS, src, f("edge_rays"))
    if c.backend not in BACKENDS:
        raise InputError(src, f("backend"), f"unknown ray-casting backend {c.backend!r}; known: {', '.join(BACKENDS)}")
    for key in ("air_path", "store_counts"):
        if not isinstance(getattr(c, key), bool):
            raise InputError(src, f(key), f"expected true or false, got {getattr(c, key)!r}")
    _check_sensor(c.sensor, src, f)


def _check_intrinsics(i, src: str, f) -> None:
    if not isinstance(i, Intrinsics):
        raise InputError(src, f("resolution"), f"expected a twin.observe.camera_geometry.Intrinsics, got {i!r}")
    _whole(i.width, 1, MAX_PIXELS, src, f("resolution"))
    _whole(i.height, 1, MAX_PIXELS, src, f("resolution"))
    for value in (i.fov_h, i.fov_v):
        if not limits.is_finite_number(value) or not 0 < value < math.pi:
            raise InputError(src, f("field_of_view"), f"each angle must lie between 0 and 180 deg, got {value!r} rad")
    _positive(i.ifov, src, f("ifov"))


def _check_sensor(s, src: str, f) -> None:
    if not isinstance(s, Microbolometer):
        raise InputError(src, f("sensor"), f"expected a twin.observe.microbolometer.Microbolometer, got {s!r}")
    for key in NOISE_TERMS:
        value = getattr(s, key)
        if not limits.is_finite_number(value) or value < 0:
            raise InputError(src, f(f"sensor.{key}"), f"expected a finite value >= 0 [K], got {value!r}")
    _positive(s.drift_time, src, f("sensor.drift_time"))
    _in_span(s.reference_temperature, src, f("sensor.reference_temperature"))
    _whole(s.bits, *BITS, src, f("sensor.bits"))
    span = _numbers(s.range, 2, src, f("sensor.range"))
    for i, t in enumerate(span):
        _in_span(t, src, f(f"sensor.range[{i}]"))
    if not span[0] < span[1]:
        raise InputError(src, f("sensor.range"), "needs the lower temperature first (low end below high end)")


def _positive(value, src: str, field: str) -> None:
    if limits.finite_number(value, src, field) <= 0:
        raise InputError(src, field, f"must be positive, got {value!r}")


def _whole(value, low: int, high: int, src: str, field: str) -> None:
    if not limits.is_whole(value) or not low <= value <= high:
        raise InputError(src, field, f"expected a whole number from {low} to {high}, got {value!r}")


def check_temperature(value, span: tuple, what: str, src: str, field: str) -> float:
    """``value`` [degC] finite, above absolute zero and within ``span``, the plausible range of
    ``what`` (the scenario reader's check of each camera temperature, and this module's)."""
    value = limits.finite_number(value, src, field)
    if value < limits.ABSOLUTE_ZERO:
        raise InputError(src, field, f"{value:g} degC is below absolute zero ({limits.ABSOLUTE_ZERO} degC)")
    lo, hi = span
    if not lo <= value <= hi:
        raise InputError(src, field, f"{value:g} degC is outside the plausible range of {what} ({lo:g} to {hi:g} degC)")
    return value


def _in_span(value, src: str, field: str) -> None:
    check_temperature(value, RADIANCE_SPAN, "the twin's radiance table", src, field)


def _numbers(values, n: int, src: str, field: str, finite: bool = True) -> np.ndarray:
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        v = None
    if v is None or v.shape != (n,) or (finite and not np.all(np.isfinite(v))):
        raise InputError(src, field, f"expected {n} {'finite ' if finite else ''}numbers, got {values!r}")
    return v


def _vector(values, src: str, field: str) -> np.ndarray:
    return _numbers(values, 3, src, field)
