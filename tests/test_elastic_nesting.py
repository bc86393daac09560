"""The elastic mesh coarser than the temperature mesh (twin.fem.nesting): closed forms on the
coarse mesh with the thermal load integrated on the fine one, the identities that tie it to the
one-mesh model, and its use through the prepared twin and the command line."""

from __future__ import annotations

import numpy as np
import pytest

from geometries.materials import MATERIALS
from tests.conftest import box_body
from twin.errors import InputError
from twin.fem.assembly import assemble_coupling, assemble_nested_coupling
from twin.fem.nesting import coarsen, coarser_lines, split_interval
from twin.physics.elastic import ElasticSolver
from twin.physics.options import SolverOptions

IRON = MATERIALS["grey_cast_iron"]


def _node(mm, xyz):
    return int(np.argmin(np.sum((mm.mesh.p.T - np.asarray(xyz)) ** 2, axis=1)))


def _solve_nested(mm, factor, dT):
    """Displacements (coarse nodes, 3) [m] of the fine temperature rise dT, and the coarse mesh."""
    nested = coarsen(mm, factor)
    solver = ElasticSolver.build(nested.coarse)
    return solver.solve(assemble_nested_coupling(nested, mm) @ dT).reshape(-1, 3), nested.coarse


def test_coarser_lines_keep_every_plane_and_spread_the_rest():
    """Planes stay; between two planes n fine intervals become ceil(n / factor), each a whole
    number of fine intervals (the grids nest)."""
    lines = np.array([0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65, 0.7])
    planes = np.array([0.0, 0.5, 0.7])
    out = coarser_lines(lines, planes, 2)
    assert set(planes) <= set(out)
    assert np.isin(out, lines).all()
    assert np.allclose(out, [0.0, 0.2, 0.3, 0.5, 0.6, 0.65, 0.7])   # 5 intervals -> (2, 1, 2); 3 stay 3
    assert np.array_equal(coarser_lines(lines, planes, 1), lines)


@pytest.mark.parametrize("factor", [2, 3, 4, 5])
def test_interval_splits_are_symmetric_whole_and_about_factor_wide(factor):
    """Each interval's coarse cells are whole fine intervals, mirror-symmetric about its middle
    (a symmetric machine keeps a symmetric grid), none wider than factor + 1 fine intervals."""
    for n in range(1, 40):
        cuts = split_interval(n, factor)
        widths = np.diff(cuts)
        assert cuts[0] == 0 and cuts[-1] == n and widths.min() >= 1
        assert np.array_equal(widths, widths[::-1])
        assert widths.max() <= factor + 1 and len(widths) >= np.ceil(n / factor)


def test_nested_mesh_tiles_each_coarse_cell_with_fine_cells_of_its_part():
    """Every fine cell has one coarse parent of the same part, and the fine volumes of each parent
    add up to its volume (exactly: the grids nest)."""
    mm = box_body((0.97, 0.05, 0.1), 0.0125)
    nested = coarsen(mm, 3)
    vol_f = np.prod(mm.cell_size, axis=1)
    summed = np.bincount(nested.parent, weights=vol_f, minlength=nested.coarse.ncells)
    assert np.allclose(summed, np.prod(nested.coarse.cell_size, axis=1), rtol=1e-12, atol=0)
    assert nested.coarse.nnodes < mm.nnodes / 8


def test_nested_coupling_on_the_same_grid_is_the_element_coupling():
    """Factor 1: the fine cells are the coarse cells and the nested coupling is C of
    twin.fem.assembly.assemble_coupling, to round-off."""
    mm = box_body((0.3, 0.2, 0.1), 0.05)
    C0 = assemble_coupling(mm)
    C1 = assemble_nested_coupling(coarsen(mm, 1), mm)
    assert abs(C1 - C0).max() <= 1e-13 * abs(C0).max()


@pytest.mark.parametrize("length, factor", [(1.0, 2), (1.0, 4), (0.97, 3)])
def test_free_expansion_on_a_coarser_elastic_mesh_is_exact(length, factor):
    """Uniform rise dT of a free bar: dL = alpha L dT, exact to round-off with the elasticity on
    every factor-th line (the uniform thermal strain is in the coarse element's space, and the
    nested coupling integrates it exactly)."""
    w, dT = 0.05, 10.0
    mm = box_body((length, w, 2 * w), 0.0125, material="grey_cast_iron")
    u, coarse = _solve_nested(mm, factor, np.full(mm.nheat, dT))
    a, b = _node(coarse, (0, w / 2, w)), _node(coarse, (length, w / 2, w))
    assert u[b, 0] - u[a, 0] == pytest.approx(IRON.expansion * length * dT, rel=1e-10)


@pytest.mark.parametrize("length, factor", [(1.0, 2), (0.97, 3), (0.97, 2)])
def test_thermal_bending_on_a_coarser_elastic_mesh_is_exact(length, factor):
    """T linear through the depth h (dT bottom to top), on the fine mesh: the free beam bends with
    curvature kappa = alpha dT / h, so a point at x on the axis rises kappa x (L - x) / 2 against
    the line through the ends: exact to round-off on the coarse mesh (Wilson-Taylor bricks hold
    pure bending exactly, the linear field is integrated exactly)."""
    b, h, dT = 0.05, 0.1, 10.0
    mm = box_body((length, b, h), 0.0125, material="grey_cast_iron")
    u, coarse = _solve_nested(mm, factor, dT * (mm.mesh.p[2] / h - 0.5))
    kappa = IRON.expansion * dT / h
    ends = [_node(coarse, (0.0, b / 2, h / 2)), _node(coarse, (length, b / 2, h / 2))]
    inner = _node(coarse, (0.4 * length, b / 2, h / 2))
    x = coarse.mesh.p[0, inner]
    rise = u[inner, 2] - (u[ends[0], 2] + (u[ends[1], 2] - u[ends[0], 2]) * x / length)
    assert rise == pytest.approx(kappa * x * (length - x) / 2, rel=1e-10)


def test_adjoint_rows_on_the_coarse_mesh_equal_the_forward_solve(machine):
    """q = G K^-1 C dT solved forwards on the coarse elastic mesh equals the adjoint rows
    (C^T K^-1 G^T)^T dT the prepared twin uses, to round-off (the adjoint identity, K symmetric)."""
    from twin.fem.mesh import mesh_machine
    from twin.observe import FiveProbeTestBar, ToolDrift
    from twin.physics.prepared import PreparedTwin

    mm = mesh_machine(machine, "coarse")
    twin = PreparedTwin(machine, mm, solver=SolverOptions("direct", elastic_coarsening=2))
    rng = np.random.default_rng(1)
    dT = rng.normal(0.0, 1.0, mm.nheat)
    for obs in (ToolDrift(), FiveProbeTestBar()):
        rows = twin.displacement_rows(obs, mm)
        G = obs.all_functionals(twin.elastic_mm)
        forward = G @ twin.elastic.solve(twin.coupling(mm) @ dT)
        assert np.max(np.abs(rows @ dT - forward)) <= 1e-10 * np.max(np.abs(forward))
    assert twin.elastic_mm.nnodes < mm.nnodes


def test_a_run_with_a_coarser_elastic_mesh_reports_it_and_stays_close(machine):
    """The drift of the coarse C-frame's spindle test with the elasticity on every second line
    differs from the one-mesh drift by a discretisation error (measured 0.4-0.5 % of the peak on the
    default mesh, 0.44 % on this coarse one; held to 1 %, about twice that), and the result says
    which elastic mesh solved it."""
    from twin.scenario import load_scenario
    from twin.simulate import run

    sc = load_scenario("spindle-heat-cool-9000")
    one = run(machine, sc, resolution="coarse", solver=SolverOptions("direct"))
    two = run(machine, sc, resolution="coarse", solver=SolverOptions("direct", elastic_coarsening=2))
    d1, d2 = one.drift - one.drift[0], two.drift - two.drift[0]
    assert np.max(np.abs(d2 - d1)) <= 0.01 * np.max(np.abs(d1))
    assert np.max(np.abs(d2 - d1)) > 0.0                       # a different mesh, not the same numbers
    # the C-frame is symmetric about x = 0 and so is the coarse grid: X stays at round-off
    assert np.max(np.abs(d2[:, 0])) <= 1e-9 * np.max(np.abs(d1)) + np.max(np.abs(d1[:, 0]))
    assert two.solver_info["elastic_coarsening"] == 2
    assert two.solver_info["elastic_nodes"] < one.solver_info["elastic_nodes"] == one.mm.nnodes


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "2"])
def test_elastic_coarsening_must_be_a_whole_number_of_at_least_one(bad):
    with pytest.raises(InputError, match="--elastic-coarsening"):
        SolverOptions("auto", elastic_coarsening=bad)


def test_cli_refuses_a_bad_elastic_coarsening(tmp_path, capsys):
    """One line naming the option, exit 2, nothing written."""
    from twin.cli import main

    out = tmp_path / "r.nc"
    rc = main(["simulate", "cframe-vmc", "spindle-heat-cool-9000", "-o", str(out), "--elastic-coarsening", "0"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "--elastic-coarsening" in err
    assert not out.exists()


def test_nested_coupling_follows_a_split_temperature_layout(machine):
    """On a layout split at a contact (the test bar's seat), the nested coupling of factor 1 is the
    element coupling of that layout, and any factor's coupling of a field continuous across the
    split equals that of the unsplit field (the split copies carry the same temperatures)."""
    from twin.fem.mesh import mesh_machine

    mm = mesh_machine(machine, "coarse")
    split = mm.split_heat(("test_bar",), mm.facets["test_bar_seat"])
    assert split.nheat > mm.nheat
    C0 = assemble_coupling(split)        # groups cells by their sizes rounded to 1e-12 m: 1e-11 relative
    assert abs(assemble_nested_coupling(coarsen(split, 1), split) - C0).max() <= 1e-10 * abs(C0).max()
    nested = coarsen(mm, 2)
    T = np.random.default_rng(2).normal(size=mm.nnodes)
    same = assemble_nested_coupling(nested, split) @ T[split.heat_node]
    whole = assemble_nested_coupling(nested, mm) @ T
    assert np.max(np.abs(same - whole)) <= 1e-12 * np.max(np.abs(whole))


def test_benchmark_reports_the_coarser_elastic_mesh_and_its_error(capsys):
    """``python -m validate.benchmark --elastic-coarsening 2`` prints the elastic mesh's nodes and
    the drift's largest difference from the one-mesh elasticity on the same temperatures."""
    import json

    from validate.benchmark import main

    assert main(["--mesh", "coarse", "--elastic-coarsening", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["elastic_coarsening"] == 2 and out["elastic_nodes"] < out["nodes"]
    assert 0.0 < out["elastic_rel_error"] < 0.05
    assert set(out["prepare_s"]) == {"mesh", "heat_assembly", "elastic_assembly", "adjoints", "rows"}
    assert out["prepare_concurrent"] is False      # a small layout: one stage after the other
    assert main(["--mesh", "coarse", "--elastic-coarsening", "2", "--prepare-only", "--json"]) == 0
    prep = json.loads(capsys.readouterr().out)
    assert "step_ms" not in prep and prep["elastic_nodes"] == out["elastic_nodes"]
    # every printed time is rounded to 1 ms, so the five stages' sum may exceed the rounded total by
    # up to six half-milliseconds
    assert prep["preparation_s"] >= sum(prep["prepare_s"].values()) - 6 * 0.5e-3
