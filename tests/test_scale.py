"""Solvers at scale, verified on small meshes: iterative heat steps and AMG elastic adjoints against
the direct factorisations, the verified error bounds, the energy balance of an iterative run, the
reduced model against full runs, batched cases against single runs, and the GPU path (skipped
without CuPy and a GPU). The bounds' pieces and the reduced basis's construction on small systems are
in ``tests/test_reduced_bounds.py``, the heat steps and their starts on a small slab in
``tests/test_heat_steps.py``. Benchmarks are a command: ``python -m validate.benchmark``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from geometries import build_machine
from geometries.cframe_vmc import SPINDLE_EFFECTS
from twin.model import model_spec
from twin.observe import FiveProbeTestBar, HeatBalance, TemperatureSensors, ToolDrift, sensor_points
from twin.physics.prepared import PreparedTwin
from twin.physics.options import ROM_ORDER, SolverOptions
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
    # needs the default basis of two operators (order 48 in all: Y off by up to 28 % of its peak,
    # 96, the default: 0.35 %; README "Scale")
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


def test_rom_order_on_the_command_line_and_the_printed_error_estimate(tmp_path, capsys):
    """--rom-order R sets the reduced model's basis (whole blocks of moments until R is reached),
    a larger basis leaves a smaller estimated error, and the summary line prints the result's own
    estimate per axis in um (rom_error_estimate, m); without it the basis is 48 per reference
    operator; --rom-order beside any solver but rom changes nothing and is refused before anything
    is written."""
    from twin.cli import main
    import xarray as xr
    toml = tmp_path / "s.toml"
    toml.write_text('name = "s"\nsample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
                    '[[spindle]]\nspeed = "6000 rpm"\nduration = "20 min"\n[[spindle]]\nspeed = "0 rpm"\n'
                    'duration = "20 min"\n')
    estimates = {}
    for order in (24, 72):
        out = tmp_path / f"r{order}.nc"
        capsys.readouterr()
        assert main(["simulate", "cframe-vmc", str(toml), "-o", str(out), "--mesh", "coarse", "--solver", "rom",
                     "--rom-order", str(order)]) == 0
        ds = xr.open_dataset(out)
        assert order <= ds.attrs["rom_order"] < order + 30
        estimates[order] = 1e6 * np.asarray(json.loads(ds.attrs["rom_error_estimate"])["drift"])
        line = next(x for x in capsys.readouterr().out.splitlines() if "reduced model" in x)
        assert f"order {ds.attrs['rom_order']}:" in line
        assert ", ".join(f"{a} {e:.2f} um" for a, e in zip("XYZ", estimates[order])) in line
    assert np.all(estimates[72][1:] < estimates[24][1:])
    # the default: ROM_ORDER (48) per reference operator; the films switch here, so two operators
    # (the spindle turning and standing), twice the basis of a run whose films hold
    out = tmp_path / "default.nc"
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(out), "--mesh", "coarse", "--solver", "rom"]) == 0
    assert 2 * ROM_ORDER <= xr.open_dataset(out).attrs["rom_order"] < 2 * ROM_ORDER + 30
    still = tmp_path / "still.toml"
    still.write_text(toml.read_text().replace('"0 rpm"', '"6000 rpm"'))
    assert main(["simulate", "cframe-vmc", str(still), "-o", str(out), "--mesh", "coarse", "--solver", "rom"]) == 0
    assert ROM_ORDER <= xr.open_dataset(out).attrs["rom_order"] < ROM_ORDER + 30
    assert main(["simulate", "cframe-vmc", str(toml), "-o", str(tmp_path / "x.nc"), "--mesh", "coarse",
                 "--rom-order", "72"]) == 2
    assert "--rom-order: sets the reduced model's order; --solver auto runs no reduced model" in capsys.readouterr().err
    assert not (tmp_path / "x.nc").exists()


def test_the_printed_error_share_leaves_out_an_axis_that_does_not_drift():
    """rom_error_line's share: the largest estimate / peak over the axes whose peak is at least a
    thousandth of the largest; X of the symmetric C-frame peaks at round-off (1e-10 um), where
    any estimate would read as a huge share."""
    import xarray as xr
    from twin.cli.cmd_simulate import rom_error_line
    ds = xr.Dataset(coords={"axis": ["X", "Y", "Z"]},
                    attrs={"rom_order": 48, "rom_error_estimate": json.dumps({"drift": [2e-9, 5.5e-7, 8.2e-7]})})
    peak = xr.DataArray([1e-10, 16.5, 41.0], coords={"axis": ["X", "Y", "Z"]}, dims="axis")
    line = rom_error_line(ds, peak)
    assert "X 0.00 um, Y 0.55 um, Z 0.82 um" in line
    assert f"up to {100 * 0.55 / 16.5:.2g} % of the peak" in line


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
