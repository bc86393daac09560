"""Parametric machine builders, addressed by name (``twin list machines``)."""

from __future__ import annotations

from geometries import belt_vmc, cframe_vmc, gantry_ram
from geometries.base import Box, Machine, Part, Point, Probe, StrainGauge, Surface

MACHINES = {cframe_vmc.NAME: cframe_vmc.build, belt_vmc.NAME: belt_vmc.build, gantry_ram.NAME: gantry_ram.build}


def build_machine(name: str) -> Machine:
    """Build the machine registered as ``name`` (KeyError when unknown)."""
    if name not in MACHINES:
        raise KeyError(name)
    return MACHINES[name]()


__all__ = ["MACHINES", "build_machine", "Box", "Machine", "Part", "Point", "Probe", "StrainGauge", "Surface"]
