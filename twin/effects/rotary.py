"""The C axis (a rotary axis about z): its motor's losses and its bearing's friction."""

from __future__ import annotations

import numpy as np

from twin.effects.base import Effect, HeatSource, Parameter, Uncertain, power_law, register_effect
from twin.fem.regions import role_cells


def c_axis_power(scenario, reference_speed: float, exponent: float, scale: float):
    """Signal P(t) = scale d(t) (n(t) / n_ref)^x [W] of the scenario's C-axis schedule (speed n
    [rpm] while turning, duty d, :mod:`twin.rotary`); 0 without a schedule or at rest."""
    schedule = getattr(scenario, "c_axis", None)

    def signal(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if schedule is None:
            return np.zeros(t.shape)
        return scale * schedule.duty(t) * power_law(schedule.speed(t), reference_speed, exponent)

    return signal


@register_effect
class CAxisDrive(Effect):
    """Heat of the C axis turning: its torque motor and its bearing, inside the ram's lower end.

        P_motor(t) = d(t) P_m,ref (n/n_ref)^x_m,   P_bearing(t) = d(t) P_b,ref (n/n_ref)^x_b,

    n(t) the C-axis speed while turning and d(t) the duty fraction of its on/dwell rhythm
    (:mod:`twin.rotary`: the cycle mean, the rhythm being seconds long against the structure's
    minutes), each spread uniformly over the ``c_axis.motor`` and ``c_axis.bearing`` regions.
    Idle-running motor losses (iron, friction) grow about linearly with speed (x_m = 1); bearing
    friction as Palmgren's viscous term, n^(5/3) (x_b). Reference powers at 2500 rpm calibrated to
    the seed's C-axis test (T1 +5-9 K near the motor after 2 h, README): plausible, not measured.
    """

    name = "c_axis_drive"
    strength = "motor_power"
    linear = True
    summary = "C-axis motor and bearing losses in the ram, P = d P_ref (n/n_ref)^x while the C axis turns"
    reference = "seed 000 L6042-6059 (C-axis heating: motor and bearings inside the ram); Harris (Palmgren)"
    roles = ("c_axis.motor", "c_axis.bearing")
    parameters = (
        Parameter("motor_power", "power", 300.0, 0.0, 5000.0, "motor losses into the ram at the reference speed"),
        Parameter("bearing_power", "power", 400.0, 0.0, 2000.0, "bearing friction at the reference speed"),
        Parameter("reference_speed", "speed", 2500.0, 10.0, 10000.0, "speed at which the reference powers hold"),
        Parameter("motor_exponent", "dimensionless", 1.0, 0.0, 3.0, "speed exponent of the motor losses"),
        Parameter("bearing_exponent", "dimensionless", 5.0 / 3.0, 0.5, 3.0, "speed exponent of the bearing friction"),
    )
    uncertain = (
        Uncertain("motor_power", 75.0, 1200.0, "a torque motor's idle losses and the share its cooling (if any) "
                  "carries off: a factor of 4 either way", linear=True),
        Uncertain("bearing_power", 100.0, 1600.0, "bearing type, preload and lubricant: a factor of 3-4", linear=True),
    )

    def loads(self, mm, scenario, p):
        ref = p["reference_speed"]
        return [HeatSource(f"{self.name}.motor", role_cells(mm, "c_axis.motor"),
                           c_axis_power(scenario, ref, p["motor_exponent"], p["motor_power"])),
                HeatSource(f"{self.name}.bearing", role_cells(mm, "c_axis.bearing"),
                           c_axis_power(scenario, ref, p["bearing_exponent"], p["bearing_power"]))]
