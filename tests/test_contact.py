"""Finite contact conductance across a split interface: the jump q / h_c and energy conservation."""

from __future__ import annotations

import numpy as np

from geometries.base import Box, Machine, Part, Surface
from tests.conftest import face
from twin.fem.assembly import assemble_facets, assemble_heat, assemble_interface
from geometries.materials import MATERIALS
from twin.physics.heat import HeatSystem, steady_state
from twin.fem.mesh import mesh_machine


def _two_part_bar(L=0.2, w=0.02, spacing=0.01):
    steel = MATERIALS["steel"]
    parts = [Part("a", steel, (Box((0, 0, 0), (L / 2, w, w)),)), Part("b", steel, (Box((L / 2, 0, 0), (L, w, w)),))]
    surfaces = [Surface("seat", ("b",), interface_with=("a",)), Surface("hot", ("a",), within=face(0, 0.0)),
                Surface("cold", ("b",), within=face(0, L))]
    return mesh_machine(Machine("bar2", parts, surfaces, [], [], "", "", [], {"test": spacing}), "test")


def test_steady_jump_across_a_contact_is_q_over_hc():
    """1-D series conduction, P into x = 0, convection h at x = L, contact h_c at L/2:
    T(L) = T_air + P/(h A); slope -P/(k A) in each half; jump at the seat P/(h_c A)."""
    L, w, P, h, hc = 0.2, 0.02, 2.0, 500.0, 2000.0
    mm = _two_part_bar(L, w).split_heat(("b",), _two_part_bar(L, w).facets["seat"])
    assert mm.nheat == mm.nnodes + 9  # 3 x 3 seat nodes copied for part b
    heat = assemble_heat(mm)
    hot, cold = assemble_facets(mm, mm.facets["hot"]), assemble_facets(mm, mm.facets["cold"])
    seat = assemble_interface(mm, mm.facets["seat"])
    system = HeatSystem(heat.M, heat.K, [cold.H, seat], np.column_stack([cold.r, np.zeros(mm.nheat)]),
                        (hot.r / hot.area)[:, None])
    T = steady_state(system, np.array([h, hc]), np.array([20.0, 0.0]), np.array([P]))
    x = mm.mesh.p[0, mm.heat_node]
    k, A = MATERIALS["steel"].conductivity, w * w
    side_b = np.zeros(mm.nheat, dtype=bool)
    side_b[np.unique(mm.heat_t[:, mm.cells_of("b")])] = True
    exact = 20 + P / (h * A) + P / (k * A) * (L - x) + np.where(side_b, 0.0, P / (hc * A))
    assert np.allclose(T, exact, rtol=1e-9, atol=1e-9 * exact.max())


def test_contact_effect_conserves_energy_and_tends_to_perfect_contact():
    """test_bar_contact on the machine: the theta-scheme energy balance closes to round-off, and a
    very large G reproduces the bonded model's drift (h_c -> infinity)."""
    from twin.api import simulate
    from twin.scenario import Ambient, Scenario

    sc = Scenario("short", ((1200.0, 9000.0), (600.0, 0.0)), Ambient("constant", 20.0), 30.0)
    bonded, _ = simulate("cframe-vmc", sc, resolution="coarse")
    stiff, _ = simulate("cframe-vmc", sc, effects="+test_bar_contact", settings=["test_bar_contact.conductance=1000 W/K"],
                        resolution="coarse")
    loose, r = simulate("cframe-vmc", sc, effects="+test_bar_contact", settings=["test_bar_contact.conductance=2 W/K"],
                        resolution="coarse")
    heat_in, convected, stored = r.step_energy()
    assert abs(heat_in + convected - stored) < 1e-9 * heat_in
    zb, zs, zl = (d.drift.sel(axis="Z").values for d in (bonded, stiff, loose))
    assert np.max(np.abs(zs - zb)) < 0.01 * np.max(np.abs(zb))
    bar = lambda d: d.temperature_true.sel(sensor="test_bar").values[-1]  # noqa: E731
    assert bar(loose) < bar(bonded) - 0.1  # a poor seat keeps the bar cooler
