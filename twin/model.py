"""The model a user simulates: a set of effects with parameter values, and its heat system.

``--effects`` takes ``+name,-name`` to change the default set, or plain ``a,b,c`` for an exact
set; ``--set effect.param=VALUE UNIT`` sets a parameter (effects and instruments alike). Unknown
names and wrong units raise :class:`twin.errors.InputError`; nothing is ignored.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from twin.fem.assembly import assemble_facets, assemble_heat, assemble_interface, volume_vector
from twin.effects import DEFAULT_EFFECTS, EFFECTS, ContactConductance, Convection, HeatSource, SurfaceHeatFlux
from twin.errors import InputError
from twin.observe.instruments import INSTRUMENTS
from twin.physics.heat import HeatSystem
from twin.units import UnitError, parse_quantity


@dataclass
class ModelSpec:
    """Effects switched on and all parameter values (SI), effects' and instruments'."""

    effects: tuple[str, ...] = DEFAULT_EFFECTS
    params: dict[str, dict[str, float]] = field(default_factory=dict)

    def __post_init__(self):
        for name in self.effects:
            if name not in EFFECTS:
                raise InputError("--effects", name, f"unknown effect; known: {', '.join(sorted(EFFECTS))}")
        full = {name: EFFECTS[name].defaults() for name in self.effects}
        full.update({name: {p.name: p.default for p in params} for name, params in INSTRUMENTS.items()})
        for group, values in self.params.items():
            if group not in full:
                raise InputError("--set", group, "is not an effect that is switched on, nor an instrument")
            for key, value in values.items():
                if key not in full[group]:
                    raise InputError("--set", f"{group}.{key}", f"unknown parameter; known: {', '.join(full[group])}")
                full[group][key] = float(value)
        self.params = full

    def parameter_table(self, group: str):
        return EFFECTS[group].parameters if group in EFFECTS else INSTRUMENTS[group]


def parse_effects(text: str | None, base: tuple[str, ...] = DEFAULT_EFFECTS) -> tuple[str, ...]:
    """``"+a,-b"`` edits ``base``; ``"a,b"`` replaces it; None keeps it."""
    if not text:
        return tuple(base)
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not any(i[0] in "+-" for i in items):
        chosen = items
    else:
        chosen = list(base)
        for item in items:
            sign, name = (item[0], item[1:]) if item[0] in "+-" else ("+", item)
            if sign == "+" and name not in chosen:
                chosen.append(name)
            elif sign == "-":
                if name not in chosen:
                    raise InputError("--effects", name, "cannot remove an effect that is not in the model")
                chosen.remove(name)
    for name in chosen:
        if name not in EFFECTS:
            raise InputError("--effects", name, f"unknown effect; known: {', '.join(sorted(EFFECTS))}")
    return tuple(dict.fromkeys(chosen))


def parse_settings(items: list[str] | None, effects: tuple[str, ...]) -> dict[str, dict[str, float]]:
    """Parse ``["effect.param=VALUE UNIT", ...]`` into SI values, checking names and units."""
    out: dict[str, dict[str, float]] = {}
    for item in items or []:
        if "=" not in item or "." not in item.split("=", 1)[0]:
            raise InputError("--set", item, "expected effect.param=VALUE UNIT, e.g. spindle_motor.power=300W")
        key, value = item.split("=", 1)
        group, name = key.strip().split(".", 1)
        if group in EFFECTS:
            if group not in effects:
                raise InputError("--set", key, f"effect {group!r} is not switched on (add it with --effects +{group})")
            table = EFFECTS[group].parameters
        elif group in INSTRUMENTS:
            table = INSTRUMENTS[group]
        else:
            raise InputError("--set", key, f"unknown effect or instrument {group!r}")
        param = next((p for p in table if p.name == name), None)
        if param is None:
            raise InputError("--set", key, f"unknown parameter; known: {', '.join(p.name for p in table)}")
        try:
            v = parse_quantity(value.strip(), param.dimension)
        except UnitError as err:
            raise InputError("--set", key, str(err)) from None
        if not param.lower <= v <= param.upper:
            raise InputError("--set", key, f"{value.strip()} is outside the bounds {param.describe()}")
        out.setdefault(group, {})[name] = v
    return out


@dataclass
class LoadSet:
    """A heat system plus the signals that drive it and the effect each load belongs to.

    ``mm`` is the mesh the temperatures live on (split at contact interfaces when an effect asks
    for it) and ``heat`` its conduction and capacity matrices.
    """

    system: HeatSystem
    sources: list          # HeatSource / SurfaceHeatFlux, columns of F
    convections: list      # Convection / ContactConductance, columns of r / entries of H
    source_effect: list[str]
    convection_effect: list[str]
    areas: np.ndarray      # (ncv,) [m2]; 0 for contacts, which exchange heat inside the structure
    mm: object = None
    heat: object = None

    def signals(self, t: np.ndarray):
        """(h, air, s) arrays of shape (len(t), ncv|ncv|nsrc) at times t [s]."""
        t = np.asarray(t, dtype=float)
        zero = np.zeros(len(t))
        h = np.column_stack([c.h(t) for c in self.convections]) if self.convections else np.zeros((len(t), 0))
        air = (np.column_stack([c.air(t) if isinstance(c, Convection) else zero for c in self.convections])
               if self.convections else np.zeros((len(t), 0)))
        s = np.column_stack([src.power(t) for src in self.sources]) if self.sources else np.zeros((len(t), 0))
        return h, air, s


def build_loads(mm, scenario, spec: ModelSpec, heat=None, materials: dict | None = None) -> LoadSet:
    """Collect every effect's loads and assemble their patterns once.

    When an effect returns a :class:`ContactConductance`, the temperature field is split at its
    facets first (``mm.split_heat``) and ``heat`` is assembled on the split mesh; otherwise
    ``heat`` (assembled with ``materials`` when None) is used as given.
    """
    sources, convs, s_eff, c_eff = [], [], [], []
    for name in spec.effects:
        for load in EFFECTS[name].loads(mm, scenario, spec.params[name]):
            if isinstance(load, (Convection, ContactConductance)):
                convs.append(load)
                c_eff.append(name)
            elif isinstance(load, (HeatSource, SurfaceHeatFlux)):
                sources.append(load)
                s_eff.append(name)
            else:
                raise TypeError(f"effect {name} returned an unknown load {load!r}")
    for c in convs:
        if isinstance(c, ContactConductance):
            mm = mm.split_heat(c.parts, c.facets)
    if heat is None or heat.M.shape[0] != mm.nheat:
        heat = assemble_heat(mm, materials)
    n = mm.nheat
    F = np.zeros((n, len(sources)))
    for j, src in enumerate(sources):
        if isinstance(src, HeatSource):
            b = volume_vector(mm, src.cells)
        else:
            b = assemble_facets(mm, src.facets).r
        F[:, j] = b / b.sum()
    H, r, areas = [], np.zeros((n, len(convs))), np.zeros(len(convs))
    for j, c in enumerate(convs):
        if isinstance(c, ContactConductance):
            H.append(assemble_interface(mm, c.facets))
        else:
            f = assemble_facets(mm, c.facets)
            H.append(f.H)
            r[:, j], areas[j] = f.r, f.area
    system = HeatSystem(heat.M, heat.K, H, r, F)
    return LoadSet(system, sources, convs, s_eff, c_eff, areas, mm, heat)
