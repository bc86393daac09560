"""Observers (virtual instruments) and the standard set a run records."""

from twin.observe.base import Observer, RunContext, variable
from twin.observe.displacement import ExpansionSensitivity, FiveProbeTestBar, ToolDrift, derived_from_probes
from twin.observe.energy import HeatBalance
from twin.observe.snapshot import HottestField
from twin.observe.strain import StrainGauges
from twin.observe.temperature import TemperatureSensors
from twin.observe.triangulation import LaserTriangulation


def sensor_points(machine) -> list:
    """The machine's temperature-sensor sites, glued ones and those in the air, in the order of
    the machine's points (a machine lists them in its own numbering)."""
    names = set(machine.sensor_sites) | set(machine.air_sites)
    return [p for p in machine.points if p.name in names]


def standard_observers(machine, sensors: list | None = None) -> list[Observer]:
    """What a simulation records: temperature sensors (``sensors``, default the machine's sites),
    the tool-point drift, the five-probe test bar (when the machine has probes), its laser
    triangulation sensors and FBG strain gauges (when it has them), the heat balance and the
    hottest field. The order fixes the instrument-noise draws (temperatures, probes, lasers, FBG)."""
    observers = [TemperatureSensors(sensors if sensors is not None else sensor_points(machine)), ToolDrift()]
    if machine.probes:
        observers.append(FiveProbeTestBar())
    if machine.lasers:
        observers.append(LaserTriangulation())
    if machine.strain_gauges:
        observers.append(StrainGauges(machine.strain_gauges))
    return observers + [HeatBalance(), HottestField()]


__all__ = ["Observer", "RunContext", "variable", "ExpansionSensitivity", "FiveProbeTestBar", "ToolDrift",
           "derived_from_probes", "HeatBalance", "HottestField", "LaserTriangulation", "StrainGauges", "TemperatureSensors", "sensor_points",
           "standard_observers"]
