"""Surface finishes: the emissivity a thermal camera sees, each value with its source.

Emissivities are long-wave (8-14 um) or total values near room temperature from the emissivity
table of FLIR's camera user manuals (materials x specification x temperature x band), and the
seeds' masking tape. A finish is bound to the exterior of parts (optionally inside a box) by
:class:`geometries.base.Finish`; a part no finish covers is painted (``MACHINE_PAINT``).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Emissivity:
    """A grey, diffuse emissivity [-] of a surface finish, with its source."""

    name: str
    value: float
    source: str

    def __post_init__(self):
        if not 0.0 < self.value <= 1.0:
            raise ValueError(f"emissivity {self.name!r} must lie in (0, 1], got {self.value}")


_FLIR = "FLIR camera user's manual, emissivity table"
MACHINE_PAINT = Emissivity("machine_paint", 0.90, f"{_FLIR}: lacquer sprayed on iron 0.87 (shiny black) to "
                                                  "0.92-0.94 (LW, three colours); machine-tool enamel ~0.9")
MASKING_TAPE = Emissivity("masking_tape", 0.95, "seed 000 L3776 / seed 001 L118: masking tape of known emissivity "
                                                "0.95 on the machine")
GROUND_STEEL = Emissivity("ground_steel", 0.24, f"{_FLIR}: iron and steel, freshly worked with emery, 20 degC, "
                                                "0.24 (polished 0.07, rolled freshly 0.24)")
POLISHED_STEEL = Emissivity("polished_steel", 0.07, f"{_FLIR}: iron and steel, polished, 0.07")

FINISHES = {e.name: e for e in (MACHINE_PAINT, MASKING_TAPE, GROUND_STEEL, POLISHED_STEEL)}
DEFAULT = MACHINE_PAINT
