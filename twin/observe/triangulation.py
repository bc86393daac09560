"""Laser triangulation sensors on a test bar (seed 000, Machine C: Y, Z and a tilt pair; no X).

Each sensor is a :class:`geometries.base.Probe` of ``Machine.lasers``: fixed to the workpiece side,
it reads the displacement of its target on the test bar along its direction relative to the
fixture, q = d . (u_target - u_fixture), a linear functional of u (one adjoint solve), as the
ISO 230-3 probes do (:class:`twin.observe.displacement.FiveProbeTestBar`). The tilt about X from
the pair A1 (lower) and A2, ``spacing`` apart along z:

    A = (q_A1 - q_A2) / spacing   [urad],

the sign of :func:`twin.observe.displacement.derived_from_probes` (top moving +y: negative A).
Variables ``laser``/``laser_true(time, laser_id)`` [um] and ``laser_tilt``/``laser_tilt_true``
(time) [urad]; the instrument model is the probe's (resolution, Gaussian noise) with the
``laser_triangulation`` parameters.
"""

from __future__ import annotations

from twin.observe.base import variable
from twin.observe.displacement import FiveProbeTestBar

TILT_PAIR = ("A1", "A2")


class LaserTriangulation(FiveProbeTestBar):
    """The machine's laser triangulation sensors (``Machine.lasers``)."""

    key = "lasers"
    instrument = "laser_triangulation"
    name, dim, long_name = "laser", "laser_id", "laser triangulation sensor"

    def sensors(self, machine) -> list:
        return machine.lasers

    def derived(self, meas, true, names, machine):
        if not set(TILT_PAIR) <= set(names):
            return {}, {}
        a1, a2 = names.index(TILT_PAIR[0]), names.index(TILT_PAIR[1])
        spacing = machine.point(TILT_PAIR[1]).xyz[2] - machine.point(TILT_PAIR[0]).xyz[2]
        return {"laser_tilt": variable("time", (meas[:, a1] - meas[:, a2]) / spacing, "urad",
                                       "test-bar tilt about X from the laser pair A1, A2, as measured"),
                "laser_tilt_true": variable("time", (true[:, a1] - true[:, a2]) / spacing, "urad",
                                            "true test-bar tilt about X from the laser pair")}, {}
