"""What a heat step costs with each preconditioner and start (issue 10): Jacobi-PCG started from
the projection on the last solutions, against larger projection starts, the start from the
reduced basis and a geometric two-grid preconditioner on the nested coarse grid.

    python -m validate.studies.heat_step [--spacing 40mm] [--steps 300] [--heat-tol "1e-6 K"]
                                         [--coarsening 2,3] [--quick] [-o DIR]

On ``cframe-vmc``'s ``etve-day-night`` (the temperature sensors and the heat balance observed, no
elasticity), the first ``--steps`` of the 24 h run are solved by each variant with the
per-step tolerance of the whole run (``heat_tol`` sqrt(C) / 1440, as :class:`twin.physics.
steppers.IterativeStepper` sets it), so every variant meets the same verified bound:

* ``jacobi, start on k solutions``: the twin's stepper for short runs (k = 8, the first row)
  with k = 8, 2, 16, 32 solutions kept for the projected start (:class:`twin.physics.solvers.Projection`);
* ``jacobi, start from the reduced basis``: each step started from the extrapolation
  2 T^n - T^(n-1) corrected by its Galerkin projection on the reduced model's basis
  (:class:`twin.physics.steppers.ReducedStart`; the basis's offline time is printed beside it,
  not counted in the step);
* ``two-grid, coarse grid N``: the same CG and start, preconditioned by one damped Jacobi sweep,
  the Galerkin coarse correction P (P^T A P)^-1 P^T r on the grid of every N-th line
  (:func:`twin.fem.nesting.coarsen`, P the trilinear interpolation :func:`twin.fem.nesting.
  prolongation`, the coarse operator factorised once per operator) and a second sweep: a
  symmetric multiplicative two-grid cycle, SPD, so CG stays CG. The damping is 1 / lambda_max
  of D^-1 A (power iteration).

Per variant: the mean and largest number of CG iterations a step, the wall time a step (a
shared machine inflates it; the iterations do not vary), and the largest difference of the
sensors from the first variant [K] beside the verified bound of that difference (the sum of the
two runs' bounds). Writes ``heat_step.md`` and ``.csv`` into ``validate-out/heat_step/``.
``--quick``: the coarse mesh and 60 steps (a smoke run; not with ``--spacing`` or ``--steps``).
"""

from __future__ import annotations

import sys
import time

import numpy as np
import scipy.sparse as sp

from twin.cli.options import positive_quantity
from twin.physics.lu import SymmetricLU
from twin.physics.parallel import RowBlocks
from twin.physics.steppers import IterativeStepper
from twin.signals import load_instants
from validate.studies.common import (check_output_folder, cli_parser, markdown_table, run_cli,
                                     whole_numbers, write_csv)

NAME = "heat_step"
SCENARIO = "etve-day-night"
MACHINE = "cframe-vmc"
STARTS = (8, 2, 16, 32)    # the first is the twin's default and the reference row
POWER_ITERATIONS = 30


class TwoGridStepper(IterativeStepper):
    """:class:`IterativeStepper` preconditioned by a symmetric two-grid cycle (module docstring)
    on the coarse grid given by the prolongation ``P`` (fine dofs x coarse nodes)."""

    def __init__(self, P, heat_tol: float):
        super().__init__(heat_tol)
        self.P, self.PT = P.tocsr(), P.T.tocsr()
        self.cycles = {}      # per operator (the cached op tuple lives as long as the stepper)

    def preconditioner(self, op):
        if id(op) not in self.cycles:
            self.cycles[id(op)] = self._cycle(op[0], op[2])
        return self.cycles[id(op)]

    def _cycle(self, lhs, dinv):
        """The cycle for A = ``lhs`` with inverse diagonal ``dinv``: the coarse operator P^T A P
        factorised and the damping 1 / lambda_max(D^-1 A) found once. ``lhs`` is the stepper's
        operator: a CSR matrix, or on a large model (:data:`twin.physics.parallel.SPLIT_FROM`
        stored entries) its :class:`twin.physics.parallel.RowBlocks`, which only multiplies dense
        arrays; the Galerkin product takes the blocks stacked back into one CSR matrix."""
        factor = SymmetricLU(self.PT @ (as_csr(lhs) @ self.P))
        omega = 1.0 / largest_eigenvalue(lambda v: dinv * (lhs @ v), len(dinv))

        def cycle(R):
            one = R.ndim == 1
            R = R[:, None] if one else R
            Z = omega * dinv[:, None] * R
            Z = Z + self.P @ factor.solve(np.asarray(self.PT @ (R - lhs @ Z)))
            Z = Z + omega * dinv[:, None] * (R - lhs @ Z)
            return Z[:, 0] if one else Z
        return cycle


def as_csr(A) -> sp.csr_matrix:
    """``A`` (a sparse matrix or a :class:`twin.physics.parallel.RowBlocks`) as one CSR matrix."""
    return sp.vstack(A.blocks, format="csr") if isinstance(A, RowBlocks) else sp.csr_matrix(A)


def largest_eigenvalue(apply, n: int) -> float:
    """lambda_max of ``apply`` (similar to an SPD matrix) by power iteration from a seeded start."""
    v = np.random.default_rng(0).standard_normal(n)
    lam = 1.0
    for _ in range(POWER_ITERATIONS):
        v = apply(v)
        lam = float(np.linalg.norm(v))
        v /= lam
    return lam


def variants(mm, coarsenings: list[int], heat_tol: float, basis=None) -> list[tuple[str, IterativeStepper]]:
    """The steppers compared; ``basis`` (a :class:`twin.physics.rom.ReducedModel`) adds the
    reduced-basis start."""
    from twin.fem.nesting import coarsen, prolongation
    from twin.physics.steppers import ReducedStart

    out = [(f"jacobi, start on {k} solutions", IterativeStepper(heat_tol, projection_size=k)) for k in STARTS]
    if basis is not None:
        reduced = IterativeStepper(heat_tol)
        reduced.start = ReducedStart(basis.V, built_s=basis.offline_s)
        out.append((f"jacobi, start from the reduced basis (order {basis.order}, built in {basis.offline_s:.1f} s)",
                    reduced))
    for n in coarsenings:
        nested = coarsen(mm, n)
        P = prolongation(nested, mm)
        out.append((f"two-grid, coarse grid N = {n} ({nested.coarse.nnodes} nodes), start on 8",
                    TwoGridStepper(P, heat_tol)))
    return out


def rows_for(spacing: float | None, steps: int, heat_tol: float, coarsenings: list[int], progress=print) -> list[dict]:
    from twin.api import machine_by_name
    from twin.fem.mesh import build_mesh, mesh_machine
    from twin.model import model_spec
    from twin.observe import TemperatureSensors, sensor_points
    from twin.physics.heat import integrate
    from twin.physics.solvers import mass_weights, output_bounds
    from twin.scenario import load_scenario
    from twin.physics.prepared import PreparedTwin

    machine, scenario = machine_by_name(MACHINE), load_scenario(SCENARIO)
    mm = build_mesh(machine, spacing) if spacing is not None else mesh_machine(machine, "coarse")
    twin = PreparedTwin(machine, mm, solver="iterative")
    loads = twin.loads(scenario, model_spec(machine))
    sensors = TemperatureSensors(sensor_points(machine))
    outputs, _ = twin.output_rows([sensors], loads)
    dt, theta, total = scenario.sample_interval, 0.5, len(scenario.times()) - 1
    h, air, s = loads.signals(load_instants(scenario.times(), theta))
    weights = mass_weights(loads.system.M)
    rows, first = [], None
    # the steppers spread their tolerance over the steps they run: scaled so that each step gets
    # the whole run's heat_tol sqrt(C) / 1440
    from twin.physics.rom import start_basis

    basis = start_basis(twin, loads, h)      # the basis the iterative solver starts from
    for name, stepper in variants(loads.mm, coarsenings, heat_tol * steps / total, basis):
        t0 = time.perf_counter()
        y = integrate(loads.system, np.full(loads.mm.nheat, scenario.start_temperature), dt, steps, h, air, s,
                      outputs, theta, stepper=stepper, operator_key=loads.operator_key)
        wall = time.perf_counter() - t0
        bound = output_bounds(outputs, weights, float(stepper.rho_sum))
        if first is None:
            first = (y, bound)
        its = np.asarray(stepper.iterations)
        row = {"variant": name, "nodes": int(loads.mm.nheat), "steps": steps, "run_steps": total, "iterations_mean": float(its.mean()),
               "iterations_max": int(its.max()), "step_ms": 1e3 * wall / steps,
               "difference_K": float(np.abs(y - first[0]).max()), "bound_K": float((bound + first[1]).max())}
        progress(f"  {name}: {row['iterations_mean']:.2f} iterations a step, {row['step_ms']:.1f} ms")
        rows.append(row)
    return rows


def markdown(rows: list[dict], command: str) -> str:
    cols = ["variant", "iterations_mean", "iterations_max", "step_ms", "difference_K", "bound_K"]
    heads = ["variant", "CG iterations a step (mean)", "largest", "wall time a step [ms]",
             "sensors' largest difference from the first row [K]", "verified bound of it [K]"]
    r = rows[0]
    rows = [{**x, "difference_K": f"{x['difference_K']:.2e}", "bound_K": f"{x['bound_K']:.2e}"} for x in rows]
    return "\n".join([
        "# The heat step's preconditioner and start (issue 10)", "",
        f"Command: `{command}`; `{MACHINE}`, `{SCENARIO}`, {r['nodes']} temperature dofs, the first {r['steps']} "
        f"of {r['run_steps']} steps at the whole run's per-step tolerance. One CG iteration is one product with the "
        "heat matrix; a two-grid iteration is three and a coarse solve.", "",
        markdown_table(rows, cols, heads), ""])


DEFAULT_OUTPUT = f"validate-out/{NAME}"


def _parser():
    from twin.cli.options import whole_number

    p = cli_parser(f"python -m validate.studies.{NAME}", __doc__)
    p.add_argument("--spacing", type=positive_quantity("length"), help="cell size with its unit (default 40mm)")
    p.add_argument("--steps", type=whole_number("steps", 1, 1440), help="steps solved by each variant, 1 to 1440 "
                                                                        "(default 300)")
    p.add_argument("--heat-tol", type=positive_quantity("temperature_difference"), default="1e-6 K",
                   help="the run's verified tolerance with its unit (default 1e-6 K)")
    p.add_argument("--coarsening", type=whole_numbers("grid lines", 2), default="2,3",
                   help="two-grid coarse grids: every N-th line (N >= 2), comma-separated (default 2,3)")
    p.add_argument("--quick", action="store_true", help="the coarse mesh and 60 steps (a smoke run)")
    p.add_argument("-o", "--output", default=DEFAULT_OUTPUT, help=f"output folder (default {DEFAULT_OUTPUT})")
    return p


def main(argv=None) -> int:
    return run_cli(_parser().parse_args, argv, lambda args: _run(args, argv))


def _run(args, argv) -> int:
    from twin.errors import InputError
    from twin.io.atomic import atomic_write_text

    if args.quick and (args.spacing is not None or args.steps is not None):
        raise InputError("command line", "--quick", "sets the mesh (coarse) and the steps (60): leave out --spacing "
                                                    "and --steps")
    steps = 60 if args.quick else (300 if args.steps is None else args.steps)
    spacing = None if args.quick else (0.04 if args.spacing is None else args.spacing)
    out = check_output_folder(args.output, (f"{NAME}.csv", f"{NAME}.md"), default=DEFAULT_OUTPUT)
    rows = rows_for(spacing, steps, args.heat_tol, args.coarsening)
    out.mkdir(parents=True, exist_ok=True)
    command = "python -m validate.studies.heat_step " + " ".join(argv if argv is not None else sys.argv[1:])
    text = markdown(rows, command.strip())
    write_csv(out / f"{NAME}.csv", rows)
    atomic_write_text(out / f"{NAME}.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
