"""Film-coefficient correlations the effect tests check the defaults against, air at 20 degC."""

from __future__ import annotations

import numpy as np

AIR_20C = {"nu": 1.51e-5, "k": 0.0257, "prandtl": 0.71}   # kinematic viscosity m2/s, conductivity W/(m K), Pr
ROOM_K = 293.15                                           # the room at 20 degC [K]
SIGMA = 5.670374419e-8                                    # Stefan-Boltzmann [W/(m2 K4)]


def plate_film(speed, length, turbulent):
    """Flat-plate forced convection [W/(m2 K)], Re = v L / nu: laminar Nu = 0.664 Re^0.5 Pr^(1/3),
    turbulent (tripped) Nu = 0.037 Re^0.8 Pr^(1/3)."""
    re = speed * length / AIR_20C["nu"]
    nusselt = (0.037 * re ** 0.8 if turbulent else 0.664 * re ** 0.5) * AIR_20C["prandtl"] ** (1 / 3)
    return nusselt * AIR_20C["k"] / length


def becker_film(rpm, diameter):
    """Becker's rotating cylinder in still air [W/(m2 K)], Nu = 0.133 Re^(2/3) Pr^(1/3) with
    Re = omega D^2 / nu."""
    re = rpm * 2 * np.pi / 60 * diameter ** 2 / AIR_20C["nu"]
    return 0.133 * re ** (2 / 3) * AIR_20C["prandtl"] ** (1 / 3) * AIR_20C["k"] / diameter
