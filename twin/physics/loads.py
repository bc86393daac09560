"""A model's loads on a mesh: every effect's heat sources, fluxes, convection and contacts
assembled once into a :class:`twin.physics.heat.HeatSystem`, with the signals that drive them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from twin.effects import EFFECTS, ContactConductance, Convection, HeatSource, SurfaceHeatFlux
from twin.fem.assembly import assemble_facets, assemble_heat, assemble_interface, volume_vector
from twin.physics.heat import HeatSystem


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

    @property
    def operator_key(self) -> tuple:
        """Identifies the operators M, K, H_k of this load set: the temperature layout and each
        convection load's label and facets (two load sets with equal keys share factorisations)."""
        return (layout_key(self.mm),) + tuple((c.label, hash(np.asarray(c.facets).tobytes())) for c in self.convections)

    def signals(self, t: np.ndarray):
        """(h, air, s) arrays of shape (len(t), ncv|ncv|nsrc) at times t [s]."""
        t = np.asarray(t, dtype=float)
        zero = np.zeros(len(t))
        h = np.column_stack([c.h(t) for c in self.convections]) if self.convections else np.zeros((len(t), 0))
        air = (np.column_stack([c.air(t) if isinstance(c, Convection) else zero for c in self.convections])
               if self.convections else np.zeros((len(t), 0)))
        s = np.column_stack([src.power(t) for src in self.sources]) if self.sources else np.zeros((len(t), 0))
        return h, air, s


def source_pattern(mm, src) -> np.ndarray:
    """The load vector b (n_heat,) of a :class:`HeatSource` (uniform over its cells) or a
    :class:`SurfaceHeatFlux` (uniform over its facets, or weighted), normalised to sum 1 so that
    b s(t) puts s(t) watts into the structure."""
    b = (volume_vector(mm, src.cells) if isinstance(src, HeatSource)
         else assemble_facets(mm, src.facets, src.weights).r)
    return b / b.sum()


def layout_key(mm) -> tuple:
    """Identifies a temperature layout: the number of temperature dofs and the cells' dof map."""
    return (mm.nheat, hash(np.ascontiguousarray(mm.heat_t).tobytes()))


def collect_loads(mm, scenario, spec) -> tuple[list, list, list, list]:
    """Every effect's load objects (patterns and signals, nothing assembled): (sources,
    convections and contacts, the effect of each source, the effect of each convection)."""
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
    return sources, convs, s_eff, c_eff


def pattern_key(loads: list) -> tuple:
    """Identifies the spatial patterns of a list of loads (label and cells or facets of each)."""
    return tuple((type(x).__name__, x.label, hash(np.asarray(getattr(x, "cells", getattr(x, "facets", ()))).tobytes()))
                 for x in loads)


def build_loads(mm, scenario, spec, heat=None, materials: dict | None = None,
                heat_cache: dict | None = None) -> LoadSet:
    """Collect every effect's loads and assemble their patterns once.

    When an effect returns a :class:`ContactConductance`, the temperature field is split at its
    facets first (``mm.split_heat``) and the heat matrices are assembled on the split mesh (or
    taken from ``heat_cache``, keyed by :func:`layout_key`, and stored there); otherwise
    ``heat`` (assembled with ``materials`` when None) is used as given.
    """
    sources, convs, s_eff, c_eff = collect_loads(mm, scenario, spec)
    for c in convs:
        if isinstance(c, ContactConductance):
            mm = mm.split_heat(c.parts, c.facets)
    if heat is None or heat.M.shape[0] != mm.nheat:
        key = layout_key(mm)
        if heat_cache is not None and key in heat_cache:
            heat = heat_cache[key]
        else:
            heat = assemble_heat(mm, materials)
            if heat_cache is not None:
                heat_cache[key] = heat
    n = mm.nheat
    F = np.zeros((n, len(sources)))
    for j, src in enumerate(sources):
        F[:, j] = source_pattern(mm, src)
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
