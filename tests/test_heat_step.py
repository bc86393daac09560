"""The nested grid's prolongation (trilinear interpolation onto the temperature dofs) and the
heat-step study that measures a two-grid preconditioner built on it against Jacobi-PCG."""

from __future__ import annotations

import numpy as np
import pytest

from twin.fem.mesh import mesh_machine
from twin.fem.nesting import coarsen, prolongation


def _trilinear(p: np.ndarray) -> np.ndarray:
    """A field with every trilinear term, 1 + 2x - 3y + z/2 + 4xyz (p (3, n) [m])."""
    x, y, z = p
    return 1.0 + 2.0 * x - 3.0 * y + 0.5 * z + 4.0 * x * y * z


@pytest.mark.parametrize("factor", [2, 3])
def test_prolongation_reproduces_a_trilinear_field_exactly(machine, factor):
    """Q1 interpolation is exact for fields trilinear on each coarse cell: P f(x_coarse) =
    f(x_fine) to round-off, and every row sums to 1 (a constant is kept)."""
    mm = mesh_machine(machine, "coarse")
    nested = coarsen(mm, factor)
    P = prolongation(nested, mm)
    assert P.shape == (mm.nheat, nested.coarse.nnodes)
    fine = _trilinear(mm.mesh.p)
    assert np.max(np.abs(P @ _trilinear(nested.coarse.mesh.p) - fine)) <= 1e-13 * np.max(np.abs(fine))
    assert np.max(np.abs(np.asarray(P.sum(axis=1)).ravel() - 1.0)) <= 1e-14


def test_prolongation_gives_both_copies_of_a_split_dof_the_same_value(machine):
    """On a layout split at a contact both copies of a node take the coarse field's value there."""
    mm = mesh_machine(machine, "coarse")
    split = mm.split_heat(("test_bar",), mm.facets["test_bar_seat"])
    nested = coarsen(mm, 2)
    coarse_field = _trilinear(nested.coarse.mesh.p)
    on_split = prolongation(nested, split) @ coarse_field
    assert np.max(np.abs(on_split - _trilinear(mm.mesh.p)[split.heat_node])) <= 1e-13 * np.max(np.abs(on_split))


def test_two_grid_cycle_is_symmetric_positive_definite(machine):
    """The cycle (damped Jacobi, Galerkin coarse correction, damped Jacobi) is SPD when A is, so
    CG stays CG: u^T B v = v^T B u to round-off and v^T B v > 0."""
    from twin.physics.prepared import PreparedTwin
    from twin.model import model_spec
    from twin.scenario import load_scenario
    from validate.studies.heat_step import TwoGridStepper

    mm = mesh_machine(machine, "coarse")
    twin = PreparedTwin(machine, mm, solver="iterative")
    scenario = load_scenario("etve-day-night")
    loads = twin.loads(scenario, model_spec(machine))
    h, _, _ = loads.signals(scenario.times()[:1] + 30.0)
    stepper = TwoGridStepper(prolongation(coarsen(mm, 2), loads.mm), 1e-6)
    op = stepper.operator(("k",), loads.system, 60.0, 0.5, h[0])
    cycle = stepper.preconditioner(op)
    assert stepper.preconditioner(op) is cycle          # factorised once per operator
    rng = np.random.default_rng(4)
    U, V = rng.standard_normal((2, loads.mm.nheat, 3))
    BU, BV = cycle(U), cycle(V)
    assert np.max(np.abs(V.T @ BU - (U.T @ BV).T)) <= 1e-12 * np.max(np.abs(V.T @ BU))
    assert np.all(np.einsum("ij,ij->j", V, BV) > 0)


def test_heat_step_study_keeps_every_variant_within_its_verified_bound(tmp_path, capsys):
    """``python -m validate.studies.heat_step --quick``: every variant's sensors differ from the
    first stepper's by no more than the sum of the two runs' verified bounds (the start from the
    reduced basis among them), the two-grid cycle needs fewer iterations than Jacobi, and the
    study writes its table."""
    from validate.studies.heat_step import main

    assert main(["--quick", "--coarsening", "2", "-o", str(tmp_path)]) == 0
    import csv
    rows = list(csv.DictReader(open(tmp_path / "heat_step.csv")))
    assert [r["variant"].split(",")[0] for r in rows] == ["jacobi"] * 5 + ["two-grid"]
    assert "reduced basis" in rows[4]["variant"]
    for r in rows:
        assert float(r["difference_K"]) <= float(r["bound_K"])
    assert float(rows[-1]["iterations_mean"]) < float(rows[0]["iterations_mean"])
    assert (tmp_path / "heat_step.md").read_text().startswith("# The heat step's preconditioner")


@pytest.mark.parametrize("argv", [["--heat-tol", "1e-6"], ["--spacing", "40"], ["--coarsening", "1"],
                                  ["--steps", "0"], ["--heat-tol", "-1 K"], ["--quick", "--steps", "100"],
                                  ["--quick", "--spacing", "30mm"]])
def test_heat_step_study_refuses_bad_options(argv, capsys, tmp_path):
    from validate.studies.heat_step import main

    assert main(argv + ["-o", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.startswith("error:")
    assert not (tmp_path / "out").exists()
