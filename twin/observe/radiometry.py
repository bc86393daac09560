"""Radiometry of a thermal camera: band radiance, the air path, and the camera's inversion.

Band radiance of a blackbody at T [K] between wavelengths lambda_1 < lambda_2 [m] [W/(m2 sr)]:

    L(T) = int_{lambda_1}^{lambda_2} 2 h c^2 / lambda^5 / (exp(h c / (lambda k T)) - 1) d lambda,

computed in closed form by the series of Widger & Woodall (1976, Bull. Am. Meteorol. Soc. 57:1217):
with x = h c / (lambda k T), the radiance at wavelengths below lambda is

    F(lambda) = 2 k^4 T^4 / (h^3 c^2) sum_{n>=1} e^{-n x} (x^3/n + 3 x^2/n^2 + 6 x/n^3 + 6/n^4),

so L(T) = F(lambda_2) - F(lambda_1); over the whole spectrum (x -> 0: 6 zeta(4) = pi^4/15) it is
sigma T^4 / pi.

What reaches the camera from a grey, diffuse surface of emissivity e at T through an air path of
transmission tau at the air temperature T_atm, the surface reflecting surroundings at T_refl:

    W = tau e L(T) + tau (1 - e) L(T_refl) + (1 - tau) L(T_atm).

A camera turns its measured W back into an apparent object temperature with *its own* settings
(emissivity e_s, reflected apparent temperature T_refl,s, distance, air temperature, humidity):

    T_app = L^-1( (W - tau_s (1 - e_s) L(T_refl,s) - (1 - tau_s) L(T_atm,s)) / (tau_s e_s) ),

which is T when the settings are the truth, and otherwise shows the biases thermographers know
(a wrong emissivity setting, a shiny part reflecting the room).

Air transmission: FLIR's empirical two-band model (Minkina & Dudzik, *Infrared Thermography:
Errors and Uncertainties*, Wiley 2009; constants as stored in FLIR radiometric files, as in
Tattersall's Thermimage ``raw2temp``, which applies them to the two halves of the path, tau(d/2)^2 (a
little lower: 0.9915 against 0.9940 at 1.5 m, 20 degC, 30 %); here the single-path form below,
tau(d)): water vapour H = RH exp(1.5587 + 0.06939 t - 0.00027816 t^2
+ 0.00000068455 t^3) (t in degC, RH as a fraction) and

    tau(d) = X exp(-sqrt(d) (a1 + b1 sqrt(H))) + (1 - X) exp(-sqrt(d) (a2 + b2 sqrt(H))),

d in m, X = 1.9, a1 = 0.006569, a2 = 0.01262, b1 = -0.002276, b2 = -0.00667 (tau = 0.9935 at 1.5 m,
23 degC, 30 %).

Temperatures at the boundary of this module are degC; radiances W/(m2 sr).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from twin.units import clean

H_PLANCK = 6.62607015e-34   # J s
C_LIGHT = 2.99792458e8      # m/s
K_BOLTZMANN = 1.380649e-23  # J/K
SIGMA = 5.670374419e-8      # W/(m2 K4)
KELVIN = 273.15

ATM_X, ATM_A1, ATM_A2, ATM_B1, ATM_B2 = 1.9, 0.006569, 0.01262, -0.002276, -0.00667


def band_radiance(t_degc, band: tuple[float, float], terms: int = 60) -> np.ndarray:
    """Blackbody radiance [W/(m2 sr)] between ``band`` = (lambda_1, lambda_2) [m] at ``t_degc``
    (Widger-Woodall series, ``terms`` terms: converges to round-off for x > 0.5)."""
    T = np.asarray(t_degc, dtype=float) + KELVIN
    return _below(band[1], T, terms) - _below(band[0], T, terms)


def _below(lam: float, T: np.ndarray, terms: int) -> np.ndarray:
    """F(lambda) = int_0^lambda of Planck's spectral radiance [W/(m2 sr)] at T [K]."""
    if np.isinf(lam):
        return SIGMA * T ** 4 / np.pi
    x = H_PLANCK * C_LIGHT / (lam * K_BOLTZMANN * T)
    total = np.zeros_like(T)
    for n in range(1, terms + 1):
        total += np.exp(-n * x) * (x ** 3 / n + 3 * x ** 2 / n ** 2 + 6 * x / n ** 3 + 6 / n ** 4)
    return 2 * K_BOLTZMANN ** 4 * T ** 4 / (H_PLANCK ** 3 * C_LIGHT ** 2) * total


def air_transmission(distance, air_degc, relative_humidity) -> np.ndarray:
    """Transmission [-] of an air path of ``distance`` [m] at ``air_degc`` and
    ``relative_humidity`` (a fraction, 0.3 for 30 %), FLIR's two-band model (module docstring)."""
    t = np.asarray(air_degc, dtype=float)
    h2o = relative_humidity * np.exp(1.5587 + 0.06939 * t - 0.00027816 * t ** 2 + 0.00000068455 * t ** 3)
    root_d = np.sqrt(np.maximum(np.asarray(distance, dtype=float), 0.0))
    return (ATM_X * np.exp(-root_d * (ATM_A1 + ATM_B1 * np.sqrt(h2o)))
            + (1 - ATM_X) * np.exp(-root_d * (ATM_A2 + ATM_B2 * np.sqrt(h2o))))


@dataclass(frozen=True)
class RadianceTable:
    """L(T) tabulated every ``step`` K on [lo, hi] degC for fast forward and inverse look-ups by
    linear interpolation: relative error at most L'' h^2 / (8 L) for a step h, with h = 0.05 K
    1.4e-7 over a camera's -40 to 120 degC (7.5e-8 above 0 degC, 4.7e-7 at -100 degC), under
    1e-5 K in temperature."""

    band: tuple[float, float]
    lo: float = -100.0
    hi: float = 1000.0
    step: float = 0.05

    def __post_init__(self):
        t = np.arange(self.lo, self.hi + 0.5 * self.step, self.step)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "L", band_radiance(t, self.band))

    def radiance(self, t_degc) -> np.ndarray:
        """L(T) [W/(m2 sr)] at ``t_degc`` (clamped to the table's range)."""
        x = (np.clip(np.asarray(t_degc, dtype=float), self.lo, self.hi) - self.lo) / self.step
        i = np.minimum(x.astype(np.int64), len(self.t) - 2)
        f = x - i
        return self.L[i] * (1 - f) + self.L[i + 1] * f

    def temperature(self, radiance) -> np.ndarray:
        """L^-1: the blackbody temperature [degC] of ``radiance`` (clamped to the table's range)."""
        return np.interp(radiance, self.L, self.t)

    def slope(self, t_degc: float) -> float:
        """dL/dT [W/(m2 sr K)] at ``t_degc`` (central difference on the series)."""
        return float((band_radiance(t_degc + 0.01, self.band) - band_radiance(t_degc - 0.01, self.band)) / 0.02)


def scene_radiance(table: RadianceTable, t_surface, emissivity, t_reflected, tau, t_air) -> np.ndarray:
    """W = tau e L(T) + tau (1 - e) L(T_refl) + (1 - tau) L(T_atm) [W/(m2 sr)] (module docstring)."""
    e = np.asarray(emissivity, dtype=float)
    return (tau * (e * table.radiance(t_surface) + (1 - e) * table.radiance(t_reflected))
            + (1 - tau) * table.radiance(t_air))


@dataclass(frozen=True)
class ObjectSettings:
    """What a thermographer types into the camera: ``emissivity`` [-], ``reflected_temperature``
    [degC] (reflected apparent temperature), ``distance`` [m], ``air_temperature`` [degC] and
    ``relative_humidity`` [fraction]. Defaults: seed 001 Table 2 (0.95, 1.5 m, 23 degC, 30 %)."""

    emissivity: float = 0.95
    reflected_temperature: float = 23.0
    distance: float = 1.5
    air_temperature: float = 23.0
    relative_humidity: float = 0.30

    @property
    def transmission(self) -> float:
        return float(air_transmission(self.distance, self.air_temperature, self.relative_humidity))

    def object_temperature(self, table: RadianceTable, measured) -> np.ndarray:
        """T_app [degC] of ``measured`` radiance W [W/(m2 sr)] with these settings (the inverse
        in the module docstring)."""
        tau, e = self.transmission, self.emissivity
        L_obj = ((np.asarray(measured, dtype=float) - tau * (1 - e) * table.radiance(self.reflected_temperature)
                  - (1 - tau) * table.radiance(self.air_temperature)) / (tau * e))
        return table.temperature(L_obj)

    def as_dict(self) -> dict:
        return {"emissivity": clean(self.emissivity), "reflected_temperature_degC": clean(self.reflected_temperature),
                "distance_m": clean(self.distance), "air_temperature_degC": clean(self.air_temperature),
                "relative_humidity_fraction": clean(self.relative_humidity),
                "air_transmission": clean(self.transmission)}
