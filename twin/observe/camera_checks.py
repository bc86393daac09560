"""The values of a thermal camera's configuration checked as the scenario reader checks them, for
a :class:`twin.observe.camera.CameraConfig` (and its :class:`Intrinsics` and
:class:`Microbolometer`) built in Python: a NaN emissivity or an 0-bit ADC wrote a thermogram of
NaN, a 40-bit ADC asked for terabytes, a camera at its own target divided by zero; a visible-light
band read -101 degC everywhere, a wall 1e300 m away a constant -46.9 degC. Each bad value is one
:class:`twin.errors.InputError` naming the field as a scenario file would
(``camera.settings.emissivity``, ``camera.sensor.bits``), with the plausible limit (the constants
below, each with its reason) and its unit."""

from __future__ import annotations

import math

import numpy as np

from twin import limits
from twin.errors import InputError, describe
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
# m: the thermal infrared, where a thermographic camera works (MWIR 3-5 um, LWIR 7.5-14 um). Below
# 2 um a body at room temperature emits next to nothing (0.4-0.7 um: 1e-45 W/(m2 sr) at -100 degC,
# count 0 at 20 degC, a thermogram of -101 degC); beyond 14 um the air absorbs (CO2 at 15 um), FLIR's
# air-path model is fitted to the 3-5 and 7.5-14 um windows only, and the radiance series needs
# lambda < 22.6 um at the table's 1000 degC.
BAND = (2e-6, 14e-6)
# rad, each of field_of_view's two angles: from a long-range telephoto lens (2 deg: 3.5 m across at
# MAX_DISTANCE; common cameras' narrowest lenses are 6-7 deg) to the widest rectilinear
# infrared lenses (80-110 deg); wider is a fisheye, which the pinhole model does not describe.
FIELD_OF_VIEW = (math.radians(2.0), math.radians(120.0))
# rad: a detector's instantaneous field of view, from a 15 um pixel behind a 1.5 m telephoto
# (0.01 mrad) to a 32 x 24 thermopile array behind a 110 deg lens (60 mrad); the S65's is 1.5 mrad.
IFOV = (1e-5, 0.1)
# m: settings.distance, scene.wall_distance, position from the machine's origin (its coordinates'
# origin lies under the machine) and from target: the length of a large workshop hall. FLIR's
# air-path model, fitted for short paths, keeps tau >= 0.6 up to 100 m in any room air (-40 to
# 60 degC, 0-100 %) but falls to 0.29 at 200 m and below 0 near 290 m (a thermogram of NaN).
MAX_DISTANCE = 100.0
# K, the most of each sensor term (NOISE_TERMS): the 3-D noise standard deviations at most 1 K (an
# uncooled microbolometer's NETD is 0.02-0.1 K, 0.08 K on the S65; the cheapest cores' 0.25 K, their
# banding and fixed pattern less); the offset, its drift and the accuracy bound that clips their sum
# at most 10 K (specs: +-2 K or 2 % of reading, +-5 K for the cheapest cores; beyond 10 K a
# thermogram measures nothing).
NOISE_LIMITS = {**{key: 1.0 for key in NOISE_TERMS[:7]}, "offset": 10.0, "drift": 10.0, "accuracy": 10.0}
_WHAT = {"netd": "NETD (0.08 K on the S65)", "fixed_pattern": "fixed-pattern noise", "row_fixed": "fixed row banding",
         "column_fixed": "fixed column banding", "row_temporal": "temporal row banding",
         "column_temporal": "temporal column banding", "frame_temporal": "frame flicker",
         "offset": "initial offset", "drift": "offset drift", "accuracy": "accuracy bound (+-2 K on the S65)"}
# s: the offset's drift time constant: from 1 s (faster is the frame-to-frame noise, not a drift)
# to 7 days (an uncooled camera's offset follows its housing over minutes to hours, 30 min by
# default; a drift slower than a week is a constant offset over any run).
DRIFT_TIME = (1.0, 7 * 86400.0)


def check_up(up: np.ndarray, sight: np.ndarray, source: str, field: str) -> None:
    """``up`` must be a finite, non-zero direction not along the line of sight ``sight``."""
    if not np.all(np.isfinite(up)):
        raise InputError(source, field, f"{_listed(up)} is not a finite direction")
    norm = float(np.linalg.norm(up))
    if norm == 0:
        raise InputError(source, field, "[0, 0, 0] is no direction; give the image's up, e.g. [0, 0, 1]")
    if np.linalg.norm(np.cross(sight / np.linalg.norm(sight), up / norm)) < 1e-6:
        raise InputError(source, field, f"{_listed(up)} is along the line of sight from position to "
                                        "target, so the image has no up; choose a direction across it")


def check_camera_values(c) -> None:
    """Every value of the camera configuration ``c`` within what the scenario reader accepts."""
    src, f = c.source, c.field
    if not isinstance(c.pose, str) or not c.pose.strip():
        raise InputError(src, f("pose"), f"expected a pose name, got {describe(c.pose)}")
    if c.name and not limits.is_file_name(c.name):
        raise InputError(src, f("name"), f"{c.name!r} cannot name a file: the camera's frames are exported into a "
                                         "folder of its name (no '/', '\\', '.', '..' or control characters)")
    if (c.position is None) != (c.target is None):
        raise InputError(src, f("target" if c.target is None else "position"), "position and target go together")
    if c.position is not None:
        ends = [_vector(v, src, f(key)) for key, v in (("position", c.position), ("target", c.target))]
        _check_distance(math.hypot(*ends[0]), src, f("position"), "stands {} from the machine's origin")
        _check_distance(math.hypot(*(ends[1] - ends[0])), src, f("target"), "lies {} from position (the default "
                        "settings.distance)")
        sight = ends[1] - ends[0]
        if np.linalg.norm(sight) < 1e-6:
            raise InputError(src, f("target"), "equals position; the camera looks from position towards target, "
                                              "so they must differ")
        check_up(_numbers(c.up, 3, src, f("up"), finite=False), sight, src, f("up"))
    _check_intrinsics(c.intrinsics, src, f)
    band = _numbers(c.band, 2, src, f("band"))
    if not 0 < band[0] < band[1]:
        raise InputError(src, f("band"), "needs 0 < lower < upper wavelength [m]")
    for i, wavelength in enumerate(band):
        if not _within(wavelength, *BAND):
            raise InputError(src, f(f"band[{i}]"), f"{wavelength * 1e6:g} um is outside the thermal infrared a "
                                                   f"thermographic camera and the twin's radiance model cover "
                                                   f"({BAND[0] * 1e6:g} to {BAND[1] * 1e6:g} um: MWIR 3-5 um, "
                                                   "LWIR 7.5-14 um)")
    if c.frame_interval is not None:
        _positive(c.frame_interval, src, f("frame_interval"))
    if not limits.is_finite_number(c.emissivity) or not 0 < c.emissivity <= 1:
        raise InputError(src, f("settings.emissivity"), f"expected a fraction above 0 and at most 1, got "
                                                        f"{describe(c.emissivity)}")
    for key, value in (("settings.relative_humidity", c.relative_humidity), ("scene.relative_humidity", c.room_humidity)):
        if not limits.is_finite_number(value) or not 0 <= value <= 1:
            raise InputError(src, f(key), f"expected a fraction from 0 to 1, got {describe(value)}")
    for key, value, kind in (("settings.reflected_temperature", c.reflected_temperature, "structure"),
                             ("settings.air_temperature", c.air_temperature, "air"),
                             ("scene.room_temperature", c.room_temperature, "structure")):
        if value is not None:
            limits.finite_number(value, src, f(key))
            limits.check_temperatures(value, src, f(key), kind)
    for key, value in (("settings.distance", c.distance), ("scene.wall_distance", c.wall_distance)):
        if value is not None and (not limits.is_finite_number(value) or value < 0):
            raise InputError(src, f(key), f"expected a finite distance >= 0 [m], got {describe(value)}")
        if value is not None:
            _check_distance(value, src, f(key), "{}")
    _whole(c.edge_rays, *EDGE_RAYS, src, f("edge_rays"))
    if c.backend not in BACKENDS:
        raise InputError(src, f("backend"), f"unknown ray-casting backend {describe(c.backend)}; known: "
                                            f"{', '.join(BACKENDS)}")
    for key in ("air_path", "store_counts"):
        if not isinstance(getattr(c, key), bool):
            raise InputError(src, f(key), f"expected true or false, got {describe(getattr(c, key))}")
    _check_sensor(c.sensor, src, f)


def _check_intrinsics(i, src: str, f) -> None:
    if not isinstance(i, Intrinsics):
        raise InputError(src, f("resolution"), f"expected a twin.observe.camera_geometry.Intrinsics, got {describe(i)}")
    _whole(i.width, 1, MAX_PIXELS, src, f("resolution"))
    _whole(i.height, 1, MAX_PIXELS, src, f("resolution"))
    lo, hi = FIELD_OF_VIEW
    for value in (i.fov_h, i.fov_v):
        if not limits.is_finite_number(value) or not _within(value, lo, hi):
            shown = f"{math.degrees(value):g} deg" if limits.is_finite_number(value) else describe(value)
            raise InputError(src, f("field_of_view"), f"each angle must lie from {math.degrees(lo):g} to "
                                                      f"{math.degrees(hi):g} deg (a thermographic camera's lenses, "
                                                      f"telephoto to wide angle), got {shown}")
    lo, hi = IFOV
    if not limits.is_finite_number(i.ifov) or not _within(i.ifov, lo, hi):
        shown = f"{i.ifov * 1e3:g} mrad" if limits.is_finite_number(i.ifov) else describe(i.ifov)
        raise InputError(src, f("ifov"), f"must lie from {lo * 1e3:g} to {hi * 1e3:g} mrad (a thermal camera "
                                         f"pixel's instantaneous field of view; 1.5 mrad on the S65), got {shown}")


def _check_sensor(s, src: str, f) -> None:
    if not isinstance(s, Microbolometer):
        raise InputError(src, f("sensor"), f"expected a twin.observe.microbolometer.Microbolometer, got {describe(s)}")
    for key in NOISE_TERMS:
        value = getattr(s, key)
        if not limits.is_finite_number(value) or value < 0:
            raise InputError(src, f(f"sensor.{key}"), f"expected a finite value >= 0 [K], got {describe(value)}")
        if not _within(value, 0.0, NOISE_LIMITS[key]):
            raise InputError(src, f(f"sensor.{key}"), f"{value:g} K is above {NOISE_LIMITS[key]:g} K, the most a "
                                                      f"microbolometer's {_WHAT[key]} plausibly reaches")
    _positive(s.drift_time, src, f("sensor.drift_time"))
    lo, hi = DRIFT_TIME
    if not _within(s.drift_time, lo, hi):
        raise InputError(src, f("sensor.drift_time"), f"{s.drift_time:g} s is outside {lo:g} s to {hi:g} s "
                                                      f"({hi / 86400:g} d), the time constant of a camera "
                                                      "offset's drift")
    _in_span(s.reference_temperature, src, f("sensor.reference_temperature"))
    _whole(s.bits, *BITS, src, f("sensor.bits"))
    span = _numbers(s.range, 2, src, f("sensor.range"))
    for i, t in enumerate(span):
        _in_span(t, src, f(f"sensor.range[{i}]"))
    if not span[0] < span[1]:
        raise InputError(src, f("sensor.range"), "needs the lower temperature first (low end below high end)")


def _check_distance(value: float, src: str, field: str, what: str) -> None:
    """A distance ``value`` [m] at most :data:`MAX_DISTANCE`, what a workshop holds; ``what`` says
    it, ``{}`` standing for the distance."""
    if not _within(value, 0.0, MAX_DISTANCE):
        raise InputError(src, field, f"{what.format(f'{value:g} m')}: more than {MAX_DISTANCE:g} m, the length of a "
                                     "large workshop hall (and the short air paths FLIR's transmission model is "
                                     "fitted for)")


def _within(value: float, lo: float, hi: float) -> bool:
    """``lo <= value <= hi``, a limit written in another unit (``"14 um"``, ``"2 deg"``) held to round-off."""
    return lo * (1 - 1e-12) <= value <= hi * (1 + 1e-12)


def _positive(value, src: str, field: str) -> None:
    if limits.finite_number(value, src, field) <= 0:
        raise InputError(src, field, f"must be positive, got {describe(value)}")


def _whole(value, low: int, high: int, src: str, field: str) -> None:
    if not limits.is_whole(value) or not low <= value <= high:
        raise InputError(src, field, f"expected a whole number from {low} to {high}, got {describe(value)}")


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
        raise InputError(src, field, f"expected {n} {'finite ' if finite else ''}numbers, got {_listed(values)}")
    return v


def _listed(values) -> str:
    """A few numbers as a scenario writes them, ``[0, 0, inf]`` (not numpy's reprs); anything else
    as :func:`twin.errors.describe` words it."""
    if isinstance(values, (list, tuple, np.ndarray)) and np.ndim(values) == 1 and 0 < len(values) <= 8 \
            and all(limits.is_number(x) for x in values):
        return "[" + ", ".join(f"{float(x):g}" for x in values) + "]"
    return describe(values)


def _vector(values, src: str, field: str) -> np.ndarray:
    return _numbers(values, 3, src, field)
