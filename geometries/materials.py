"""Bundled materials (SI units), each with its source.

Values are typical handbook values at room temperature; a machine's castings vary by grade,
so they are plausible defaults, not a measured machine.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Material:
    """An isotropic linear thermoelastic solid.

    conductivity k [W/(m K)], density rho [kg/m3], specific_heat c [J/(kg K)],
    youngs_modulus E [Pa], poisson_ratio nu [-], expansion alpha [1/K].

    ``expansion_band`` [-]: the plausible relative spread of alpha for this material as built
    (grade, casting, temperature range), with its source in ``expansion_band_source``; a
    diagnosis may move alpha only within alpha (1 +- band) (:mod:`validate.fit`).
    """

    name: str
    conductivity: float
    density: float
    specific_heat: float
    youngs_modulus: float
    poisson_ratio: float
    expansion: float
    source: str
    expansion_band: float = 0.10
    expansion_band_source: str = ""

    @property
    def volumetric_heat_capacity(self) -> float:
        """rho * c [J/(m3 K)]."""
        return self.density * self.specific_heat

    @property
    def lame(self) -> tuple[float, float]:
        """Lame constants (lambda, mu) [Pa]: lambda = E nu / ((1+nu)(1-2nu)), mu = E / (2(1+nu))."""
        e, nu = self.youngs_modulus, self.poisson_ratio
        return e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))

    def scaled(self, **factors: float) -> "Material":
        """A copy with named properties multiplied by factors (for perturbed 'truth' models)."""
        values = {f: getattr(self, f) * factors.pop(f, 1.0) for f in
                  ("conductivity", "density", "specific_heat", "youngs_modulus", "expansion")}
        if factors:
            raise KeyError(f"unknown material properties {sorted(factors)}")
        return Material(self.name, poisson_ratio=self.poisson_ratio, source=self.source + " (scaled)",
                        expansion_band=self.expansion_band, expansion_band_source=self.expansion_band_source, **values)


_HANDBOOK = "typical room-temperature handbook values (e.g. ASM Handbook vol. 1; VDI Heat Atlas)"

# Plausible spread of the expansion coefficient near room temperature (what a diagnosis may fit):
_BANDS = {
    "grey_cast_iron": (0.10, "grey iron grades EN-GJL-150 to -350 and their castings span about 9.5-11.5e-6 /K "
                             "near room temperature (EN 1561 informative data; ASM Handbook vol. 1): +-10 %"),
    "steel": (0.08, "carbon and low-alloy steels (C45, 42CrMo4, 100Cr6) span about 10.6-12.4e-6 /K near room "
                    "temperature (ASM Handbook vol. 1): +-8 %"),
    "granite": (0.20, "natural granites span about 5.5-8.5e-6 /K by mineral content (handbook data): +-20 %"),
    "polymer_concrete": (0.15, "mineral castings span about 12-16e-6 /K by filler and resin content: +-15 %"),
    "aluminium": (0.05, "wrought aluminium alloys span about 22-24e-6 /K (ASM Handbook vol. 2): +-5 %"),
}

MATERIALS: dict[str, Material] = {
    m.name: m
    for m in [
        Material("grey_cast_iron", 50.0, 7200.0, 460.0, 110e9, 0.26, 10.5e-6, "EN-GJL-250; " + _HANDBOOK,
                 *_BANDS["grey_cast_iron"]),
        Material("steel", 45.0, 7850.0, 460.0, 210e9, 0.30, 11.5e-6, "C45 / 42CrMo4; " + _HANDBOOK, *_BANDS["steel"]),
        Material("granite", 3.0, 2700.0, 800.0, 50e9, 0.25, 7.0e-6, _HANDBOOK, *_BANDS["granite"]),
        Material("polymer_concrete", 1.5, 2400.0, 900.0, 35e9, 0.25, 14.0e-6, "mineral casting; " + _HANDBOOK,
                 *_BANDS["polymer_concrete"]),
        Material("aluminium", 150.0, 2700.0, 900.0, 70e9, 0.33, 23.0e-6, "EN AW-6082; " + _HANDBOOK,
                 *_BANDS["aluminium"]),
    ]
}
