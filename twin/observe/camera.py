"""The virtual thermal camera: an observer that takes radiometric frames of the machine.

Per frame (every ``frame_interval``, coordinate ``frame_time``), for each pixel:

1. geometry (:mod:`twin.observe.camera_geometry`): the rays of the pixel hit the outer surface
   (or the room); the twin records the true surface temperature at every hit (sparse rows built
   once per pose and temperature layout), only at the frame instants (:meth:`sample_steps`);
2. radiometry (:mod:`twin.observe.radiometry`): each ray carries
   W = tau e L(T) + tau (1 - e) L(T_room) + (1 - tau) L(T_air) (tau over its own depth, the room's
   walls at the air temperature unless ``room_temperature`` says otherwise, seen at
   ``wall_distance``), and the pixel averages its rays' W;
3. the sensor chain (:mod:`twin.observe.microbolometer`): 3-D noise, offset drift, 14-bit counts;
4. the camera's own inversion with *its* object settings (emissivity, reflected apparent
   temperature, distance, air temperature, humidity: what a thermographer types in), a look-up
   table from counts to apparent temperature: ``thermogram = lut[counts]``.

Steps 2-4 are nonlinear and run in :meth:`ThermalCamera.data` on the raw frame block. The result
holds ``thermogram(frame_time, v, u)`` [degC apparent], the truth layers (true surface temperature
per frame; emissivity, part, facet, depth, view angle, coverage per pixel) and ``camera_lut(count)``
[degC]; the counts are ``camera_counts(ds)`` (:mod:`twin.io.thermography`): the thermogram is
stored as 16-bit integers fine enough that lut^-1 recovers every count exactly, since two noisy
14-bit records of every frame would not fit the file budget. ``store_counts`` also stores them.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field

import numpy as np

from geometries.base import CameraPose
from twin.errors import InputError
from twin.observe.base import Observer, RunContext
from twin.units import clean
from twin.observe.camera_geometry import Intrinsics, temperature_rows, view_machine
from twin.observe.microbolometer import Microbolometer, SensorChain
from twin.observe.radiometry import ObjectSettings, RadianceTable, air_transmission, scene_radiance
from twin.units import format_quantity

OVERVIEW = "overview-front"
BLOCK = 32  # frames processed at a time in data()


@dataclass(frozen=True)
class CameraConfig:
    """One camera of a run (SI units; from ``--camera`` or a scenario's ``[[camera]]``).

    ``pose`` names a pose of the machine (or ``overview-front``, built for any machine from its
    bounding box), unless ``position`` and ``target`` [m] are given. The object settings are the
    camera's: ``emissivity``, ``reflected_temperature`` and ``air_temperature`` [degC] (None: the
    room air at the start, as a thermographer measures and types it), ``distance`` [m] (None: the
    pose's distance to its target), ``relative_humidity`` [fraction]. The scene's truth: the
    surroundings' radiant ``room_temperature`` [degC] (None: the room air at each frame), the
    room's ``room_humidity``, the walls at ``wall_distance`` [m]. ``edge_rays``: n x n rays in
    pixels at edges. ``source`` names where the settings came from (for error messages).
    """

    pose: str = "carrier-front"
    position: tuple | None = None
    target: tuple | None = None
    up: tuple = (0.0, 0.0, 1.0)
    name: str = ""
    intrinsics: Intrinsics = Intrinsics()
    band: tuple = (7.5e-6, 13e-6)
    frame_interval: float | None = None
    emissivity: float = 0.95
    reflected_temperature: float | None = None
    distance: float | None = None
    air_temperature: float | None = None
    relative_humidity: float = 0.30
    room_temperature: float | None = None
    room_humidity: float = 0.30
    wall_distance: float = 5.0
    air_path: bool = True
    sensor: Microbolometer = field(default_factory=Microbolometer)
    edge_rays: int = 3
    backend: str = "auto"
    store_counts: bool = False
    source: str = "command line"
    where: str = "camera."

    def field(self, key: str) -> str:
        """The field an error about ``key`` names: ``camera.<key>`` (``camera[i].<key>``) in a
        scenario file, the option itself (``--camera``) on the command line."""
        return self.where + key if self.where.endswith(".") else self.where

    def check(self, scenario) -> None:
        """Raise :class:`InputError` unless the frame interval is a whole multiple of the
        scenario's sample interval and no longer than the run (a camera with one frame, the cold
        one at t = 0, would record nothing), after every value of the configuration
        (:func:`twin.observe.camera_checks.check_camera_values`: one built in Python never met
        the scenario reader)."""
        from twin.observe.camera_checks import check_camera_values

        check_camera_values(self)
        if self.frame_interval is None:
            return
        if self.frame_interval > scenario.duration * (1 + 1e-9):
            raise InputError(self.source, self.field("frame_interval"),
                             f"{format_quantity(self.frame_interval, 'time')} is longer than the run "
                             f"({format_quantity(scenario.duration, 'time')}): the camera would take only the frame "
                             "at the start")
        ratio = self.frame_interval / scenario.sample_interval
        if ratio < 1 - 1e-9 or abs(ratio - round(ratio)) > 1e-6:
            raise InputError(self.source, self.field("frame_interval"),
                             f"{self.frame_interval:g} s must be a whole multiple of the scenario's sample interval "
                             f"({scenario.sample_interval:g} s)")

    @property
    def label(self) -> str:
        return self.name or (self.pose if self.position is None else "camera")

    def resolve_pose(self, machine) -> CameraPose:
        """The :class:`geometries.base.CameraPose` this camera stands at on ``machine``."""
        if self.position is not None:
            self._check_in_air(machine)
            return CameraPose(self.label, tuple(self.position), tuple(self.target), tuple(self.up))
        if self.pose == OVERVIEW:
            return overview_pose(machine, self.intrinsics)
        try:
            return machine.camera_pose(self.pose)
        except KeyError:
            known = [p.name for p in machine.camera_poses] + [OVERVIEW]
            raise InputError(self.source, self.field("pose"), f"machine {machine.name} has no camera pose {self.pose!r}; "
                                                          f"known: {', '.join(known)}") from None


    def _check_in_air(self, machine) -> None:
        """A camera at ``position`` stands in the air: raise :class:`InputError` (naming
        ``camera.position``) when it lies inside a part of ``machine``, before the run starts."""
        p = np.asarray(self.position, dtype=float)
        for part in machine.parts:
            for box in part.boxes:
                if box.contains(p[None, :])[0]:
                    where = ", ".join(f"{c:g} m" for c in p)
                    raise InputError(self.source, self.field("position"),
                                     f"({where}) is inside part {part.name!r} of machine {machine.name}; a camera "
                                     "stands in the air round the machine")


def overview_pose(machine, intr: Intrinsics) -> CameraPose:
    """``overview-front``: from the front (-y), far enough that the machine's bounding box fits
    the field of view with a 10 % margin, aimed at the box's centre."""
    lo = np.min([b.lo for p in machine.parts for b in p.boxes], axis=0)
    hi = np.max([b.hi for p in machine.parts for b in p.boxes], axis=0)
    centre = 0.5 * (lo + hi)
    size = hi - lo
    d = 1.1 * max(size[0] / (2 * math.tan(intr.fov_h / 2)), size[2] / (2 * math.tan(intr.fov_v / 2))) + size[1] / 2
    return CameraPose(OVERVIEW, (float(centre[0]), float(centre[1] - d), float(centre[2])), tuple(map(float, centre)),
                      description="the whole machine from the front (built from its bounding box)")


def slug(name: str) -> str:
    """A name fit for variable names: lower case, runs of other characters as one underscore."""
    return re.sub(r"[^0-9a-zA-Z]+", "_", name).strip("_").lower() or "camera"


class ThermalCamera(Observer):
    """A thermal camera on ``machine`` configured by ``config``; ``suffix`` is appended to its
    variable and dimension names (``""`` when it is the run's only camera, see :func:`cameras`)."""

    raw_dtype = np.float32

    def __init__(self, machine, config: CameraConfig, suffix: str = ""):
        self.machine, self.config, self.suffix = machine, config, suffix
        self.pose = config.resolve_pose(machine)
        self.key = "camera" + suffix
        self.view = None
        self._mesh = None

    def cache_key(self) -> tuple:
        c = self.config
        return (type(self).__name__, self.key, self.pose, c.intrinsics, c.edge_rays, c.backend)

    def check(self, scenario, machine) -> None:
        """Its configuration's values and frame interval against the run (:meth:`CameraConfig.check`)."""
        self.config.check(scenario)

    def name(self, base: str) -> str:
        return base + self.suffix

    def geometry(self, mm):
        """The :class:`twin.observe.camera_geometry.View` of ``mm``'s mesh (cast once per mesh)."""
        if self.view is None or self._mesh is not mm.mesh:
            self.view = view_machine(mm, self.machine, self.pose, self.config.intrinsics, self.config.edge_rays,
                                     self.config.backend)
            self._mesh = mm.mesh
        return self.view

    def rows(self, twin, loads):
        return temperature_rows(self.geometry(loads.mm), loads.mm)

    def sample_steps(self, times: np.ndarray) -> np.ndarray:
        """Every N-th output instant, N = frame_interval / output interval (an integer >= 1);
        every instant when the frame interval is None."""
        if len(times) < 2 or self.config.frame_interval is None:
            return np.arange(len(times))
        return np.arange(0, len(times), max(1, int(round(self.config.frame_interval / (times[1] - times[0])))))

    def settings(self, scenario) -> ObjectSettings:
        """The camera's object settings, the room defaults resolved against ``scenario``."""
        c = self.config
        room = float(scenario.ambient_temperature(np.array([0.0]))[0])
        return ObjectSettings(c.emissivity, room if c.reflected_temperature is None else c.reflected_temperature,
                              self.pose.distance if c.distance is None else c.distance,
                              room if c.air_temperature is None else c.air_temperature, c.relative_humidity)

    def frames(self, raw: np.ndarray, ctx: RunContext):
        """(frame times [s], thermogram (n, H, W) [degC] float32, counts uint16, true surface
        temperature float32 [degC], look-up table (2^bits,) [degC], settings) of ``raw``."""
        c, view = self.config, self.geometry(ctx.loads.mm)  # rows may come from the twin's cache
        H, W = c.intrinsics.shape
        t = ctx.times[self.sample_steps(ctx.times)]
        air = np.asarray(ctx.scenario.ambient_temperature(t), dtype=float)
        room = air if c.room_temperature is None else np.full_like(air, c.room_temperature)
        table = RadianceTable(c.band)
        settings = self.settings(ctx.scenario)
        chain = SensorChain(c.sensor, table, (H, W), t, np.random.default_rng(ctx.rng.integers(2 ** 63)))
        lut = settings.object_temperature(table, chain.radiance_of(np.arange(chain.top + 1)))
        hit = view.hit
        A, ones = view.pixel_sum(hit), np.ones(len(hit))
        cover, bg = A @ ones, view.room_weight
        eps, depth = view.ray_emissivity[hit], view.ray_depth[hit]
        thermo = np.empty((len(t), H, W), np.float32)
        true = np.empty((len(t), H, W), np.float32)
        counts = np.empty((len(t), H, W), np.uint16)
        for a in range(0, len(t), BLOCK):
            b = slice(a, min(a + BLOCK, len(t)))
            T = np.asarray(raw[b], dtype=float)
            tau = air_transmission(depth[None, :], air[b, None], c.room_humidity) if c.air_path else 1.0
            tau_wall = air_transmission(c.wall_distance, air[b], c.room_humidity) if c.air_path else 1.0
            w_rays = scene_radiance(table, T, eps[None, :], room[b, None], tau, air[b, None])
            w_wall = scene_radiance(table, room[b], 1.0, room[b], tau_wall, air[b])
            signal = (A @ w_rays.T).T + bg[None, :] * w_wall[:, None]
            counts[b] = chain.counts(signal.reshape(-1, H, W))
            thermo[b] = lut[counts[b]]
            with np.errstate(invalid="ignore", divide="ignore"):
                surf = np.where(cover[None, :] > 0, (A @ T.T).T / cover[None, :], air[b, None])
            true[b] = surf.reshape(-1, H, W)
        return t, thermo, counts, true, lut, settings

    def data(self, raw, ctx):
        from twin.observe.camera_output import camera_variables

        t, thermo, counts, true, lut, _ = self.frames(raw, ctx)
        return camera_variables(self, t, thermo, counts, true, lut)

    def attrs(self, raw, ctx) -> dict:
        c, p = self.config, self.pose
        info = {"name": c.label, "suffix": self.suffix,
                "pose": {"name": p.name, "position_m": list(p.position), "target_m": list(p.target), "up": list(p.up),
                         "description": p.description, "subject": p.subject},
                "intrinsics": c.intrinsics.as_dict(), "band_um": [clean(c.band[0] * 1e6), clean(c.band[1] * 1e6)],
                "frame_interval_s": float(np.diff(ctx.times[self.sample_steps(ctx.times)][:2]).sum()),
                "settings": self.settings(ctx.scenario).as_dict(),
                "scene": {"room_temperature_degC": clean(c.room_temperature), "room_humidity_fraction": clean(c.room_humidity),
                          "wall_distance_m": clean(c.wall_distance), "air_path": c.air_path},
                "sensor": c.sensor.as_dict(), "edge_rays": c.edge_rays, "rays": int(len(self.view.ray_pixel)),
                "counts_stored": bool(getattr(self, "_counts_stored", c.store_counts))}
        return {self.name("camera"): json.dumps(info)}


def cameras(machine, configs) -> list[ThermalCamera]:
    """The camera observers of a run: one per config; with more than one, each gets the suffix
    ``_<label>`` on its variable names (labels must then differ)."""
    configs = list(configs)
    if len(configs) <= 1:
        return [ThermalCamera(machine, c) for c in configs]
    labels = [slug(c.label) for c in configs]
    if len(set(labels)) != len(labels):
        raise InputError(configs[0].source, configs[0].field("name"), f"cameras need distinct names, got {', '.join(labels)} "
                                                      "(set name = \"...\" on each)")
    return [ThermalCamera(machine, c, "_" + s) for c, s in zip(configs, labels)]


__all__ = ["CameraConfig", "ThermalCamera", "cameras", "overview_pose", "OVERVIEW"]
