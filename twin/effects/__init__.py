"""Registered effects (``twin list effects``) and the default set."""

from twin.effects import belt, drives, environment, feed, rotary, room, spindle, workshop  # noqa: F401  (registration)
from twin.effects.base import (EFFECTS, ContactConductance, Convection, Effect, HeatSource, Parameter, SurfaceHeatFlux,
                               Uncertain, first_order_lag, register_effect, speed_power_law)

__all__ = ["EFFECTS", "ContactConductance", "Convection", "Effect", "HeatSource", "Parameter", "SurfaceHeatFlux",
           "Uncertain", "first_order_lag", "register_effect", "speed_power_law"]
