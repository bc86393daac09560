"""Solvers at scale, verified on small meshes: iterative heat steps and AMG elastic adjoints against
the direct factorisations, the verified error bounds, the energy balance of an iterative run, the
reduced model against full runs, batched cases against single runs, and the GPU path (skipped
without CuPy and a GPU). The bounds' pieces and the reduced basis's construction on small systems are
in ``tests/test_reduced_bounds.py``. Benchmarks are a command: ``python -m validate.benchmark``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from geometries import build_machine
from geometries.cframe_vmc import SPINDLE_EFFECTS
from tests.conftest import box_body, face
from twin.fem.assembly import assemble_facets, assemble_heat
from twin.model import model_spec
from twin.observe import FiveProbeTestBar, HeatBalance, TemperatureSensors, ToolDrift, sensor_points
from twin.physics.heat import HeatSystem, integrate
from twin.physics.prepared import PreparedTwin
from twin.physics.options import SolverOptions
from twin.physics.solvers import Projection, mass_weights, output_bounds
from twin.physics.steppers import DirectStepper, IterativeStepper
from twin.scenario import Ambient, Scenario

SHORT = Scenario("short", ((1200.0, 9000.0), (900.0, 0.0)), Ambient("daily", 20.0, 2.0), 30.0)


@pytest.fixture(scope="module")
def machine():
    return build_machine("cframe-vmc")


@pytest.fixture(scope="module")
def twins(machine):
    """The coarse C-frame prepared three ways (direct, iterative, reduced), one mesh."""
    from twin.fem.mesh import mesh_machine
    mm = mesh_machine(machine, "coarse")
    return {k: PreparedTwin(machine, mm, solver=k) for k in ("direct", "iterative", "rom")}


def _observers(machine):
    return [TemperatureSensors(sensor_points(machine)), ToolDrift(), FiveProbeTestBar(), HeatBalance()]


def _cooled_slab(steps: int):
    """A steel slab heated through one face at 50 W and cooled there by h = 300 W/(m2 K) to 15 degC
    air, from 20 degC: (heat matrices, system, n, the integrate arguments for ``steps`` 30 s steps,
    observing every 7th node)."""
    mm = box_body((0.2, 0.05, 0.05), 0.01, surfaces=[("cooled", face(0, 0.2))])
    heat = assemble_heat(mm)
    fm = assemble_facets(mm, mm.facets["cooled"])
    system = HeatSystem(heat.M, heat.K, [fm.H], fm.r[:, None], (fm.r / fm.area)[:, None])
    n = mm.nnodes
    args = (np.full(n, 20.0), 30.0, steps, np.full((steps, 1), 300.0), np.full((steps, 1), 15.0),
            np.full((steps, 1), 50.0), np.eye(n)[::7])
    return heat, system, n, args


def test_pcg_steps_equal_direct_ones_within_the_verified_bound():
    """A slab cooled on one face: PCG with extrapolated start vs sparse LU, 200 CN steps. Each output
    errs by at most (27 w^T M_L^-1 w)^(1/2) sum_n rho_n (||A^-1 r||_M <= (r^T M^-1 r)^(1/2), M-contraction
    of the theta-scheme), and that bound is below ``heat_tol`` sqrt(C) times the row norm."""
    heat, system, n, args = _cooled_slab(200)
    direct = integrate(system, *args, stepper=DirectStepper())
    it = IterativeStepper(heat_tol=1e-4)
    iterative = integrate(system, *args, stepper=it)
    bound = output_bounds(np.eye(n)[::7], mass_weights(heat.M), float(it.rho_sum))
    err = np.abs(iterative - direct).max(axis=0)
    assert np.all(err <= bound) and err.max() > 0
    assert float(it.rho_sum) <= 1e-4 * np.sqrt(heat.M.sum()) * (1 + 1e-12)
    assert 0 < np.mean(it.iterations) < 30


def test_projected_start_is_no_worse_than_extrapolation_and_saves_iterations():
    """Fischer's projection: x0 = Q Q^T b with Q A-orthonormal over the recent solutions is the
    A-norm best point of a span that holds x_n and x_(n-1), so ||x0 - x||_A <= ||2 x_n - x_(n-1) - x||_A
    at every step (restarts included); on the slab's 200 steps it needs fewer PCG iterations."""
    heat, system, n, args = _cooled_slab(200)
    lhs = (system.M + 0.5 * 30.0 * (system.K + 300.0 * system.H[0])).tocsr()
    rng = np.random.default_rng(3)
    exact = np.cumsum(rng.standard_normal((12, lhs.shape[0])) * 0.1, axis=0) + 1.0   # a smooth sequence
    proj = Projection(lambda v: lhs @ v, 4)
    proj.add(exact[0])
    proj.add(exact[1])
    energy = lambda e: float(e @ (lhs @ e))
    for k in range(2, len(exact)):
        x = exact[k]
        x0 = proj.guess(lhs @ x)
        assert energy(x0 - x) <= energy(2 * exact[k - 1] - exact[k - 2] - x) * (1 + 1e-10)
        proj.add(x)
    plain, projected = IterativeStepper(heat_tol=1e-4, projection_size=0), IterativeStepper(heat_tol=1e-4)
    a, b = integrate(system, *args, stepper=plain), integrate(system, *args, stepper=projected)
    bound = output_bounds(np.eye(n)[::7], mass_weights(heat.M), float(plain.rho_sum + projected.rho_sum))
    assert np.all(np.abs(a - b).max(axis=0) <= bound)
    assert sum(projected.iterations) < sum(plain.iterations)


def test_reduced_start_is_the_a_norm_best_point_of_its_span_and_exact_on_it():
    """ReducedStart: x0 = T + V (V^T A V)^-1 V^T (b - A T) is the Galerkin projection of the
    increment x - T on span(V), so ||x0 - x||_A <= ||T + V y - x||_A for every y, and x0 = x when
    the increment lies in span(V) (then CG needs no iteration). The passes over V run in single
    precision (a basis in single precision here, so that its span is the stored one): both hold to
    single precision's round-off of the correction, about 1e-7 of it."""
    from twin.physics.steppers import ReducedStart
    heat, system, n, args = _cooled_slab(3)
    lhs = (system.M + 0.5 * 30.0 * (system.K + 300.0 * system.H[0])).tocsr()
    rng = np.random.default_rng(5)
    V = rng.standard_normal((n, 9)).astype(np.float32).astype(float)
    start, op = ReducedStart(V), (lhs,)
    T, x = 20.0 + rng.standard_normal(n), 20.0 + rng.standard_normal(n)
    b = lhs @ x
    x0 = start.guess(op, lhs, b, T)
    energy = lambda e: float(e @ (lhs @ e))
    for y in rng.standard_normal((20, 9)):
        assert energy(x0 - x) <= energy(T + V @ y - x) * (1 + 1e-6)
    y = rng.standard_normal(9)
    inside = T + V @ y                                          # an increment the basis spans
    np.testing.assert_allclose(start.guess(op, lhs, lhs @ inside, T), inside, rtol=0, atol=1e-6 * np.abs(V @ y).max())
    X = np.column_stack([x, inside])                            # a block: the same, column by column
    np.testing.assert_allclose(start.guess(op, lhs, lhs @ X, np.column_stack([T, T]))[:, 0], x0, rtol=0,
                               atol=1e-6 * np.abs(x0 - T).max())


def test_heat_start_option_and_its_auto_rule():
    """auto starts from the reduced basis from REDUCED_START_STEPS steps on; the named starts
    always or never; an unknown name is refused naming the option."""
    from twin.errors import InputError
    from twin.physics.options import REDUCED_START_STEPS
    auto = SolverOptions("iterative")
    assert not auto.reduced_start(REDUCED_START_STEPS - 1) and auto.reduced_start(REDUCED_START_STEPS)
    assert SolverOptions("iterative", heat_start="reduced").reduced_start(1)
    assert not SolverOptions("iterative", heat_start="projection").reduced_start(10 ** 6)
    with pytest.raises(InputError, match="--heat-start"):
        SolverOptions("iterative", heat_start="fischer")


def test_run_started_from_the_reduced_basis_equals_direct_within_its_bound(twins, machine, runs, monkeypatch):
    """The coarse C-frame's spindle run with every iterative step started from the reduced basis
    (its films switch, so the start's V^T A V is formed for each operator): every output within
    its verified bound of the direct run (the start changes the iterations, never the tolerance);
    two batched cases (multiple right-hand sides from the same start) equal their single runs within
    the sum of their bounds."""
    from dataclasses import replace
    _, ref, _, _ = runs["direct"]
    twin = twins["iterative"]
    monkeypatch.setattr(twin, "options", replace(twin.options, heat_start="reduced"))
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    _, got = twin.run(SHORT, spec, _observers(machine))
    info = dict(twin.run_info)
    assert info["heat_start"] == "reduced" and info["heat_start_order"] >= 40
    for key, bound in info["solver_error_bound"].items():
        assert np.all(np.abs(got[key] - ref[key]).max(axis=0) <= np.asarray(bound)), key
    cases = [(SHORT, spec), (replace(SHORT, ambient=Ambient("daily", 20.0, 3.0)), spec)]
    obs = [TemperatureSensors(sensor_points(machine)), ToolDrift()]
    _, batch, binfo = twin.run_batch(cases, obs)
    assert binfo["heat_start"] == "reduced"
    for j, (sc, sp_) in enumerate(cases):
        _, single = twin.run(sc, sp_, obs)
        for key in single:
            bound = np.asarray(binfo["solver_error_bound"][key])[:, j] + np.asarray(twin.run_info["solver_error_bound"][key])
            assert np.all(np.abs(batch[key][:, :, j] - single[key]).max(axis=0) <= bound), key


def test_amg_adjoints_equal_direct_ones(twins, machine):
    """Drift influence rows by AMG-CG (rigid-body modes as near-null space) vs SuperLU: the
    relative residual 1e-8 gives rows equal to about that relative accuracy (measured 7.6e-10 for
    the drift, 1.2e-9 for the probes; held to 1e-8)."""
    d, i = twins["direct"], twins["iterative"]
    assert i.elastic.method == "amg" and d.elastic.method == "direct"
    for obs in (ToolDrift(), FiveProbeTestBar()):
        a, b = d.displacement_rows(obs, d.mm), i.displacement_rows(obs, i.mm)
        assert np.max(np.abs(a - b)) <= 1e-8 * np.max(np.abs(a))


@pytest.fixture(scope="module")
def runs(twins, machine):
    # the spindle tests' five effects: on this daily room the C-frame's default stratified_swing
    # needs a larger basis (order 48: Y off by up to 28 % of its peak, 64: 2.4 %; README "Scale")
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    out = {}
    for k, twin in twins.items():
        obs = _observers(machine)
        loads, readings = twin.run(SHORT, spec, obs)
        out[k] = (loads, readings, dict(twin.run_info), obs)
    return out


def test_iterative_run_equals_direct_within_its_reported_bound(runs):
    """Every output of the iterative run (PCG heat steps, AMG elastic adjoints) differs from the
    direct run's by at most its reported bound (w^T W w)^(1/2) sum_n rho_n, w the output's row, W
    the weights 27 / m_L of the lumped capacity, rho_n each heat step's final residual norm
    (twin.physics.solvers; the AMG rows' own error, about 1e-9 relative, is far inside it:
    test_amg_adjoints_equal_direct_ones); and the drift, in fact, by under 1e-6 of its range."""
    _, ref, _, _ = runs["direct"]
    _, got, info, _ = runs["iterative"]
    assert info["solver_method"] == "iterative" and "AMG" in info["solver_elastic"]
    for key, bound in info["solver_error_bound"].items():
        err = np.abs(got[key] - ref[key]).max(axis=0)
        assert np.all(err <= np.asarray(bound)), key
    # the solver's tolerance, not the bound's pessimism, is what the drift sees
    assert np.abs(got["drift"] - ref["drift"]).max() < 1e-6 * np.abs(ref["drift"] - ref["drift"][0]).max()


def test_energy_balance_of_an_iterative_run_closes_to_the_solver_tolerance(runs):
    """Summing the steps' first law with residuals r_n: |stored - sources - convection| =
    |sum_n 1^T r_n| <= sqrt(1^T M 1) sum_n rho_n (Cauchy-Schwarz in the M norm)."""
    from twin.observe import RunContext
    loads, readings, info, obs = runs["iterative"]
    ctx = RunContext(SHORT.times(), SHORT, None, None, loads, np.random.default_rng(0))
    sources, convection, stored = HeatBalance.energy(readings["energy"], ctx)
    capacity = float(loads.system.M.sum())
    assert abs(sources + convection - stored) <= np.sqrt(capacity) * info["heat_residual_sum"]
    assert abs(sources + convection - stored) < 1e-6 * abs(sources)


def test_reduced_model_error_is_below_its_bound_and_estimate(runs):
    """ROM vs the direct full model on a run whose spindle starts and stops (the forced-convection
    film switches from 150 to 0 W/(m2 K) on the same reduction): every output's error is below its
    verified bound; the drift outputs' errors are below the estimate |y_r - y_(r-b)|."""
    _, ref, _, _ = runs["direct"]
    _, got, info, _ = runs["rom"]
    assert info["rom_order"] >= 40 and info["rom_estimate_order"] < info["rom_order"]
    for key in ref:
        err = np.abs(got[key] - ref[key]).max(axis=0)
        assert np.all(err <= np.asarray(info["rom_error_bound"][key])), key
    for key in ("drift", "probes"):
        peak = np.abs(ref[key] - ref[key][0]).max(axis=0)
        moving = peak > 1e-3 * peak.max()
        err = np.abs(got[key] - ref[key]).max(axis=0)
        assert np.all(err[moving] <= np.asarray(info["rom_error_estimate"][key])[moving]), key
        assert np.all(err[moving] < 0.02 * peak[moving])


def test_batched_cases_equal_single_runs(twins, machine):
    """Three cases (source strengths, room amplitude, and a different film) through one prepared
    twin: the reduced model vectorised and the direct model with multiple right-hand sides equal
    their single runs (to round-off)."""
    from dataclasses import replace
    base = model_spec(machine)
    cases = [(SHORT, base),
             (replace(SHORT, ambient=Ambient("daily", 20.0, 3.0)), model_spec(machine, settings=["spindle_bearings.front_power=90W"])),
             (SHORT, model_spec(machine, settings=["ambient_convection.h=12W/m2K"]))]
    for kind in ("rom", "direct"):
        twin = twins[kind]
        obs = [TemperatureSensors(sensor_points(machine)), ToolDrift()]
        _, batch, info = twin.run_batch(cases, obs)
        assert info["cases"] == 3
        for j, (sc, spec) in enumerate(cases):
            _, single = twin.run(sc, spec, obs)
            for key in single:
                np.testing.assert_allclose(batch[key][:, :, j], single[key], rtol=1e-9,
                                           atol=1e-9 * np.abs(single[key]).max())


def test_contact_split_runs_through_the_reduced_model(twins, machine):
    """test_bar_contact splits the temperature layout: the reduction is built on the split layout
    (the contact is one more H_k with r_k = 0) and stays within its bound of the direct model."""
    spec = model_spec(machine, "+test_bar_contact", ["test_bar_contact.conductance=5W/K"])
    obs = lambda: [TemperatureSensors(sensor_points(machine)), ToolDrift()]  # noqa: E731
    _, ref = twins["direct"].run(SHORT, spec, obs())
    _, got = twins["rom"].run(SHORT, spec, obs())
    info = twins["rom"].run_info
    for key in ref:
        assert np.all(np.abs(got[key] - ref[key]).max(axis=0) <= np.asarray(info["rom_error_bound"][key]))


def test_amg_cycle_is_pyamgs_v_cycle_to_round_off():
    """amg_cycle(ml) R is the operator of pyamg's aspreconditioner(cycle="V") (the same smoothing,
    restriction, coarse solve and prolongation, without its residual norms): equal to round-off,
    and symmetric, u^T B v = v^T B u, for the symmetric and the forward/backward smoothers; a block's
    column (the block cycle of :mod:`twin.physics.kernels`) is the vector's cycle to round-off."""
    import pyamg
    import scipy.sparse as sp
    from twin.physics.solvers import amg_cycle
    A = (pyamg.gallery.poisson((12, 12, 12), format="csr") + 1e-3 * sp.eye(12 ** 3)).tocsr()
    u, v = np.random.default_rng(0).standard_normal((2, A.shape[0]))
    for smoothers in ({}, {"presmoother": ("gauss_seidel", {"sweep": "forward"}),
                           "postsmoother": ("gauss_seidel", {"sweep": "backward"})}):
        ml = pyamg.smoothed_aggregation_solver(A, symmetry="hermitian", max_coarse=50, coarse_solver="splu",
                                               **smoothers)
        assert len(ml.levels) >= 3
        cycle, ref = amg_cycle(ml), ml.aspreconditioner(cycle="V")
        assert np.abs(cycle(v) - ref @ v).max() <= 1e-13 * np.abs(ref @ v).max()
        np.testing.assert_allclose(cycle(np.column_stack([u, v]))[:, 1], cycle(v), rtol=0,
                                   atol=1e-13 * np.abs(cycle(v)).max())   # a block: the kernels' cycle
        assert abs(u @ cycle(v) - v @ cycle(u)) <= 1e-12 * abs(u @ cycle(v))


def test_reduced_model_with_amg_basis_solves_stays_within_its_bound(twins, machine, monkeypatch):
    """The basis of a large layout is built by AMG-CG started from the Galerkin projection on the
    basis so far, to BASIS_RTOL (1e-6) of that start's residual, dropping directions new by less
    than 10 x BASIS_RTOL, not by LU. Forced on the coarse mesh, the spindle run stays within the
    verified bound on every output, and the tool's Z (the largest drift) within 1 % of its peak
    (measured 0.6 %; the LU-built model 1.3 %)."""
    import twin.physics.rom as rom
    from twin.physics.prepared import PreparedTwin
    monkeypatch.setattr(rom, "DIRECT_LIMIT", 0)
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    obs = lambda: [TemperatureSensors(sensor_points(machine)), ToolDrift()]  # noqa: E731
    _, ref = twins["direct"].run(SHORT, spec, obs())
    amg = PreparedTwin(machine, twins["rom"].mm, solver="rom")
    _, got = amg.run(SHORT, spec, obs())
    info = amg.run_info
    assert info["rom_order"] >= 40
    for key in ref:
        assert np.all(np.abs(got[key] - ref[key]).max(axis=0) <= np.asarray(info["rom_error_bound"][key])), key
    peak = np.abs(ref["drift"] - ref["drift"][0]).max(axis=0)
    assert np.argmax(peak) == 2 and np.abs(got["drift"] - ref["drift"]).max(axis=0)[2] < 0.01 * peak[2]


def test_start_basis_solved_to_its_looser_tolerance_costs_few_iterations(twins, machine, monkeypatch):
    """The basis that only starts full-order steps is solved to START_BASIS_RTOL (1e-5), not the
    reduced model's BASIS_RTOL (1e-6), and cached apart from it: CG corrects what its span misses,
    so the run stays within its verified bound of the direct one, and (AMG basis solves forced on the
    coarse mesh) its steps need at most a quarter more iterations than from the tighter basis."""
    from dataclasses import replace

    import twin.physics.rom as rom
    from twin.physics.prepared import PreparedTwin
    monkeypatch.setattr(rom, "DIRECT_LIMIT", 0)
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    obs = lambda: [TemperatureSensors(sensor_points(machine)), ToolDrift()]  # noqa: E731
    _, ref = twins["direct"].run(SHORT, spec, obs())
    options = replace(twins["iterative"].options, heat_start="reduced")
    iterations = {}
    for rtol in (rom.START_BASIS_RTOL, rom.BASIS_RTOL):
        monkeypatch.setattr(rom, "START_BASIS_RTOL", rtol)
        twin = PreparedTwin(machine, twins["iterative"].mm, solver=options)
        _, got = twin.run(SHORT, spec, obs())
        assert [key[-2:] for key in twin.reduced] == [(rtol, 1)]     # its tolerance, one block at least
        for key in ref:
            assert np.all(np.abs(got[key] - ref[key]).max(axis=0) <= np.asarray(twin.run_info["solver_error_bound"][key]))
        iterations[rtol] = twin.run_info["heat_iterations_mean"]
    loose, tight = iterations.values()
    assert loose <= 1.25 * tight + 0.1


def test_cli_writes_the_solver_and_its_errors_into_the_result(tmp_path):
    from twin.cli import main
    import xarray as xr
    toml = tmp_path / "s.toml"
    toml.write_text('name = "s"\nsample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
                    '[[spindle]]\nspeed = "6000 rpm"\nduration = "20 min"\n')
    out = tmp_path / "r.nc"
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(out), "--mesh", "coarse", "--solver", "rom"]) == 0
    ds = xr.open_dataset(out)
    assert ds.attrs["solver"] == "rom" and ds.attrs["rom_order"] >= 40
    assert "rom_offline_s" not in ds.attrs      # a wall time: the result is the same bytes every run
    again = tmp_path / "again.nc"
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(again), "--mesh", "coarse", "--solver", "rom"]) == 0
    assert again.read_bytes() == out.read_bytes()
    bound = json.loads(ds.attrs["rom_error_bound"])
    assert len(bound["drift"]) == 3 and all(b >= 0 for b in bound["drift"])
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(tmp_path / "x.nc"), "--solver", "magic"]) == 2
    assert not (tmp_path / "x.nc").exists()
    started = tmp_path / "i.nc"
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(started), "--mesh", "coarse", "--solver", "iterative",
                 "--heat-start", "reduced"]) == 0
    ds = xr.open_dataset(started)
    assert ds.attrs["heat_start"] == "reduced" and ds.attrs["heat_start_order"] >= 40
    assert "heat_start_basis_s" not in ds.attrs
    assert "reduced basis" in ds.attrs["solver_heat"]


def test_gpu_option_needs_the_iterative_path():
    from twin.errors import InputError
    with pytest.raises(InputError, match="--device"):
        SolverOptions("direct", "gpu")
    with pytest.raises(InputError, match="reduced model"):   # it would run on the CPU under a "gpu" label
        SolverOptions("rom", "gpu")
    assert SolverOptions("auto", "gpu").resolve(100) == "iterative"
    assert SolverOptions("auto").resolve(100) == "direct" and SolverOptions("auto").resolve(10**6) == "iterative"


def test_a_result_says_the_units_of_its_solver_errors(runs):
    """The per-output errors are in each observer's raw SI unit (m for displacements, K for
    temperatures; the heat balance's rows J and K m2), not the variables' um: a run reports the
    unit of every key it reports an error for, and errors without units are refused."""
    from twin.io.results import solver_attrs
    for kind, errors in (("iterative", ("solver_error_bound",)), ("rom", ("rom_error_bound", "rom_error_estimate"))):
        info = runs[kind][2]
        units = info["solver_error_units"]
        for name in errors:
            assert set(info[name]) == set(units), (kind, name)
        assert units["drift"] == units["probes"] == "m" and units["temperature"] == "K"
        assert "J" in units["energy"] and "K m2" in units["energy"]
        assert json.loads(solver_attrs(info)["solver_error_units"]) == units
    assert "solver_error_units" not in solver_attrs({"solver": "direct"})
    with pytest.raises(ValueError, match="units"):
        solver_attrs({"solver": "rom", "rom_error_estimate": {"drift": [1e-7]}})


def test_amg_set_up_is_reproducible_and_leaves_numpy_random_alone():
    """pyamg draws the start of its spectral-radius estimate from numpy's global generator: two
    set-ups of one matrix gave cycles differing by 1e-11 of the load (adjoints by 1e-19 m) until
    the set-up was seeded; the caller's generator state is restored."""
    import scipy.sparse as sparse

    from twin.physics.solvers import amg_cycle, smoothed_aggregation

    n = 40
    A = sparse.diags([-np.ones(n * n - 1), 4.0 * np.ones(n * n), -np.ones(n * n - 1)], [-1, 0, 1]) \
        - sparse.eye(n * n, k=n) - sparse.eye(n * n, k=-n)
    b = np.random.default_rng(3).random(n * n)
    np.random.seed(123)
    before = np.random.get_state()[1].copy()
    cycles = [amg_cycle(smoothed_aggregation(sparse.csr_matrix(A), max_coarse=10)) for _ in range(2)]
    assert np.array_equal(np.random.get_state()[1], before)
    assert np.array_equal(cycles[0](b), cycles[1](b))


def test_benchmark_cases_share_the_start_temperature_a_batch_needs():
    """``validate.benchmark --cases N`` scales the room's amplitude; a room away from its mean at
    t = 0 (etve-training starts at 08:00) must not give each case another start temperature, which
    run_batch refuses: every case starts from case 0's, and case 0 is the scenario itself."""
    from twin.api import machine_by_name
    from twin.model import default_spec
    from twin.scenario import load_scenario
    from validate.benchmark import vary_cases
    sc = load_scenario("etve-training")
    assert sc.ambient_temperature(np.array([0.0]))[0] != pytest.approx(sc.ambient.mean)
    cases = vary_cases(sc, default_spec(machine_by_name("cframe-vmc")), 4, seed=0)
    assert {c.start_temperature for c, _ in cases} == {sc.start_temperature}
    assert cases[0][0].ambient == sc.ambient
    amps = [c.ambient.amplitude / sc.ambient.amplitude for c, _ in cases[1:]]
    assert all(0.5 <= a <= 1.5 for a in amps) and len(set(amps)) == 3


def test_benchmark_rom_error_names_the_outputs_it_compared(capsys):
    """With --heat-only there is no drift output: the reduced model's error is measured on the
    temperature sensors and the JSON says so (it reported 0.0, an empty maximum, before)."""
    import json

    from validate import benchmark
    assert benchmark.main(["--mesh", "coarse", "--scenario", "etve-training", "--solver", "rom", "--heat-only",
                           "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["max_rel_error_of"] == ["temperature"] and 0.0 < out["max_rel_error"] < 1e-2


def _uniformly_heated_slab():
    """The slab of :func:`_cooled_slab` without its film, heated by P = 100 W spread as its
    capacity (F = M 1 / C): K 1 = 0, so T^n = T_0 + P t_n / C exactly, a field linear in time, at any
    theta: (system, n, C)."""
    heat, _, n, _ = _cooled_slab(1)
    capacity = float(heat.M.sum())
    uniform = HeatSystem(heat.M, heat.K, [], np.zeros((n, 0)), (np.asarray(heat.M.sum(axis=1)).ravel() / capacity)[:, None])
    return uniform, n, capacity


@pytest.mark.parametrize("start", ["extrapolation", "reduced"])
def test_the_starts_are_exact_for_a_field_linear_in_time(start, monkeypatch):
    """For a field linear in time the extrapolation E = 2 T^n - T^(n-1) is the next step's solution
    itself, and so is the reduced start E + V (V^T A V)^-1 V^T (b - A E), since b - A E = 0 there
    (b - A E formed from the images A T^n and A T^(n-1) kept from the last two solves). A slab heated
    uniformly (T = T_0 + P t / C): from the second step on, every start CG receives is the exact
    field to 1e-9 of a step's rise (the solves' own error, heat_tol 1e-10 K, is far below that)."""
    import twin.physics.steppers as steppers
    system, n, capacity = _uniformly_heated_slab()
    steps, dt, P = 8, 30.0, 100.0
    starts = []
    real = steppers.pcg
    monkeypatch.setattr(steppers, "pcg", lambda apply, b, x0, *a, **k: starts.append(np.array(x0)) or real(apply, b, x0, *a, **k))
    stepper = IterativeStepper(heat_tol=1e-10, projection_size=0)
    if start == "reduced":
        stepper.start = steppers.ReducedStart(np.random.default_rng(2).standard_normal((n, 5)))
    out = integrate(system, np.full(n, 20.0), dt, steps, np.zeros((steps, 0)), np.zeros((steps, 0)),
                    np.full((steps, 1), P), np.eye(n)[::7], stepper=stepper)
    rise = P * dt / capacity
    np.testing.assert_allclose(out[-1], 20.0 + steps * rise, rtol=0, atol=1e-9 * rise)
    assert len(starts) == steps
    for k in range(1, steps):
        assert np.abs(starts[k] - (20.0 + (k + 1) * rise)).max() <= 1e-9 * rise, k


def test_each_operator_gets_its_own_galerkin_start(monkeypatch):
    """The starts are Galerkin projections in the energy norm of the step's own operator: after a
    film changes A (a new operator), the reduced start uses (V^T A V)^-1 of the new A, not the one
    formed for the first, so an increment that V spans is again reproduced exactly; and the
    projection start (Fischer) rebuilds its A-orthonormal basis from the last two solutions, so a
    solution in their span, 2 T^n - T^(n-1), is its start exactly. (A start built on the old
    operator would be a worse start, not a wrong answer: CG would still converge.)"""
    import twin.physics.steppers as steppers
    _, system, n, _ = _cooled_slab(1)
    rng = np.random.default_rng(6)
    V = rng.standard_normal((n, 9)).astype(np.float32).astype(float)
    start = steppers.ReducedStart(V)
    T = 20.0 + rng.standard_normal(n)
    for h in (300.0, 30.0, 300.0):
        lhs = (system.M + 0.5 * 30.0 * (system.K + h * system.H[0])).tocsr()
        inside = T + V @ rng.standard_normal(9)
        np.testing.assert_allclose(start.guess((lhs,), lhs, lhs @ inside, T), inside, rtol=0,
                                   atol=1e-6 * np.abs(inside - T).max())
    # the projection start across an operator change
    starts = []
    real = steppers.pcg
    monkeypatch.setattr(steppers, "pcg", lambda apply, b, x0, *a, **k: starts.append(np.array(x0)) or real(apply, b, x0, *a, **k))
    stepper = IterativeStepper(heat_tol=1e-10)
    stepper.begin(10, system)
    first, second = (stepper.operator(("slab", h), system, 30.0, 0.5, np.array([h])) for h in (300.0, 30.0))
    solutions = [np.full(n, 20.0)]
    for k in range(1, 4):                                  # three steps on the first operator
        x = 20.0 + 0.01 * k * np.cumsum(rng.standard_normal(n))
        solutions.append(stepper.solve(first, first[0] @ x, solutions[-1]))
    target = 2.0 * solutions[-1] - solutions[-2]           # in the span of the last two solutions
    stepper.solve(second, second[0] @ target, solutions[-1])
    np.testing.assert_allclose(starts[-1], target, rtol=0, atol=1e-9 * np.abs(target - solutions[-1]).max())


@pytest.mark.parametrize("heat_tol", [1e-4, 1e-3])
def test_each_step_stops_within_its_share_of_the_run_tolerance(heat_tol):
    """The verified tolerance is split evenly over the run: CG stops step n once its residual norm
    rho_n = (27 r^T M_L^-1 r)^(1/2) <= heat_tol sqrt(C) / N (N the run's steps, C = 1^T M 1), so
    that sum_n rho_n <= heat_tol sqrt(C) (twin.physics.solvers). Each step's rho_n, read from the
    stepper's running sum after the step, is within that share on two-step runs of the cooled slab
    (where one share more, heat_tol sqrt(C) / (N - 1), would let the final iterate stop above it)."""
    heat, system, n, (T0, dt, _, h, air, s, rows) = _cooled_slab(2)
    share = heat_tol * np.sqrt(float(heat.M.sum())) / 2
    stepper = IterativeStepper(heat_tol=heat_tol, projection_size=0)
    rho = []
    integrate(system, T0, dt, 2, h[:2], air[:2], s[:2], rows, stepper=stepper,
              on_step=lambda k, T: rho.append(float(stepper.rho_sum) - sum(rho)))
    assert len(rho) == 2 and max(rho) > 0.3 * share
    assert all(r <= share * (1 + 1e-12) for r in rho), np.array(rho) / share


def test_batched_cases_whose_films_part_later_equal_single_runs_at_theta_one(twins, machine):
    """The full model batches as multiple right-hand sides only the cases whose film coefficients
    are equal at every step: two spindle schedules that start alike and stop at different times
    (their films equal at the first step, apart later) are two groups, each equal to its single
    run to round-off; and the batch evaluates every signal at t_n + theta dt as a single run does,
    here at theta 1 (implicit Euler) in a daily room."""
    from dataclasses import replace
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    late = replace(SHORT, steps=((600.0, 9000.0), (1500.0, 0.0)))
    cases = [(SHORT, spec), (late, spec)]
    twin = twins["direct"]
    obs = [TemperatureSensors(sensor_points(machine))]
    _, batch, _ = twin.run_batch(cases, obs, theta=1.0)
    for j, (sc, sp_) in enumerate(cases):
        _, single = twin.run(sc, sp_, obs, theta=1.0)
        for key in single:
            np.testing.assert_allclose(batch[key][:, :, j], single[key], rtol=1e-9, atol=1e-9 * np.abs(single[key]).max())


def test_a_batch_without_its_bound_builds_no_gram_matrix_and_a_model_without_one_says_so(monkeypatch):
    """run_batch(bound=False) skips the verified bound (README "Scale": the bound costs O(d^2) per
    case and step): it built the residual Gram matrix all the same, and a model built without one
    (build_reduced(gram=False)) failed in integrate(bound=False) with numpy's 'Input must be 1- or
    2-d'. Now the batch builds none, its bounds are NaN (not computed) while its estimate is
    there, and a bound asked of a model without the matrix is one InputError naming it."""
    import twin.physics.rom as rom
    from twin.errors import InputError

    machine = build_machine("cframe-vmc")
    twin = PreparedTwin(machine, resolution="coarse", solver="rom")

    def no_gram(*args, **kwargs):
        raise AssertionError("the residual Gram matrix was built for a run without its bound")

    monkeypatch.setattr(rom, "residual_gram", no_gram)
    spec = model_spec(machine, ",".join(SPINDLE_EFFECTS))
    _, batch, info = twin.run_batch([(SHORT, spec), (SHORT, spec)], [ToolDrift()], bound=False)
    assert batch["drift"].shape[2] == 2 and np.all(np.isnan(info["rom_error_bound"]["drift"]))
    assert np.all(np.isfinite(info["rom_error_estimate"]["drift"]))
    model = next(iter(twin.reduced.values()))        # the basis, cached for the next run
    assert model.gram is None
    with pytest.raises(InputError, match="the verified bound needs the residual Gram matrix"):
        model.integrate(20.0, 30.0, 2, np.full((2, len(model.H)), 8.0), np.full((2, model.R.shape[1]), 20.0),
                        np.zeros((2, model.F.shape[1])))
