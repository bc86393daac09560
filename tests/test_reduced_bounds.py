"""The verified error bounds' pieces and the reduced basis's construction, on small systems: the
mass bound 27 M_L^-1 behind every bound, the reduced run's bound rebuilt from each step's
full-space residual and its Gram matrix, whole blocks of moments (three at least, past the order
when one block is wide), and a travelling nut through the reduced model within its bound. The
solvers' runs against each other are in ``tests/test_scale.py``."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from tests.conftest import box_body
from tests.test_heat_steps import _cooled_slab
from tests.test_scale import _observers
from twin.fem.assembly import assemble_heat
from twin.model import model_spec
from twin.physics.heat import HeatSystem
from twin.physics.prepared import PreparedTwin
from twin.physics.solvers import mass_weights


@pytest.fixture(scope="module")
def machine():
    from geometries import build_machine
    return build_machine("cframe-vmc")


def test_consistent_mass_is_bounded_below_by_lumped_over_27():
    """Trilinear mass: the eigenvalues of M_L^-1 M lie in [1/27, 1] (the 1-D element's (h/6)[2 1; 1 2]
    against (h/2) I has 1/3 and 1, cubed for the brick), the inequality behind every bound."""
    mm = box_body((0.06, 0.04, 0.03), 0.01)
    M = assemble_heat(mm).M.toarray()
    lam = sla.eigh(M, np.diag(M.sum(axis=1)), eigvals_only=True)
    assert lam.min() >= 1 / 27 - 1e-12 and lam.max() <= 1 + 1e-12
    assert lam.min() < 1 / 27 * 1.5     # and 1/27 is nearly reached: the constant is not loose


def test_the_bound_weights_bound_the_mass_inverse_norm_and_one_brick_attains_it():
    """The weights W = diag(mass_weights(M)) = 27 M_L^-1 are what the verified bounds use:
    r^T M^-1 r <= r^T W r for every r (the largest eigenvalue of W^-1/2 M^-1 W^-1/2 is at most
    1), with equality on one trilinear brick, whose M_L^-1 M reaches 1/27 (so a smaller constant
    would break the bound and a larger one would loosen it)."""
    for dims, spacing in (((0.01, 0.01, 0.01), 0.01), ((0.06, 0.04, 0.03), 0.01)):
        M = assemble_heat(box_body(dims, spacing)).M
        w = mass_weights(M)
        Mi = np.linalg.inv(M.toarray())
        ratio = np.linalg.eigvalsh((Mi / np.sqrt(w)[:, None]) / np.sqrt(w)[None, :]).max()
        assert ratio <= 1 + 1e-10
        if M.shape[0] == 8:
            assert ratio == pytest.approx(1.0, rel=1e-10)


def test_a_block_wider_than_the_order_still_gives_three_blocks():
    """A travelling source's path basis makes the first block of moments wider than rom_order
    (seed003-exp1's screws: 61 columns on the coarse mesh against the default 48): the basis takes
    whole blocks until it has the three the error estimate needs (V M-orthonormal, V^T M V = I,
    the estimate's sub-basis the first block), and a basis that only starts full-order steps takes
    one block. (Before, both refused with an error on --rom-order that no user had set.)"""
    from twin.physics.rom import build_reduced
    heat, system, n, _ = _cooled_slab(1)
    F = np.zeros((n, 12))
    F[np.arange(0, 12 * 7, 7), np.arange(12)] = 1.0            # twelve point sources: a block 12 wide
    wide = HeatSystem(system.M, system.K, system.H, system.r, F)
    model = build_reduced(wide, [np.array([300.0])], order=6, gram=False)
    first = 13                                                 # the sources and the film's load vector
    assert model.order_estimate == first and model.order == 3 * first      # three whole blocks, none deflated
    np.testing.assert_allclose(model.V.T @ (system.M @ model.V), np.eye(model.order), atol=1e-10)
    start = build_reduced(wide, [np.array([300.0])], order=6, gram=False, blocks=1)
    assert start.order == first


def test_the_reduced_bound_sums_the_full_space_residual_of_each_step():
    """The verified bound of a reduced run is ||w||_W sum_n rho_n with rho_n = (R_n^T W R_n)^(1/2),
    R_n = M (u+ - u) + dt (K + h H) u_theta - dt (F s_n + h (T_air - T_0) r) the full-space
    residual of step n for u = V z (W = 27 M_L^-1): rebuilt here from the reduced fields step by
    step, it equals the Gram-matrix sum the run reports, up to that sum's round-off allowance
    (1e-3 here; the allowance only adds)."""
    from twin.physics.rom import build_reduced
    _, system, n, (T0, dt, steps, h, air, s, rows) = _cooled_slab(20)
    model = build_reduced(system, [np.array([300.0])], order=12).project_outputs(rows, mass_weights(system.M))
    fields = [np.zeros(n)]
    model.integrate(20.0, dt, steps, h, air, s, on_step=lambda k, T: fields.append(T - 20.0))
    _, info = model.integrate(20.0, dt, steps, h, air, s)
    w = mass_weights(system.M)
    A = (system.K + 300.0 * system.H[0]).tocsr()
    rho = 0.0
    for k in range(steps):
        u, v = fields[k], fields[k + 1]
        R = system.M @ (v - u) + dt * (A @ (0.5 * (u + v))) - dt * (system.F[:, 0] * s[k, 0]
                                                                     + h[k, 0] * (air[k, 0] - 20.0) * system.r[:, 0])
        rho += np.sqrt(R @ (w * R))
    reported = info["_bound"] / model.output_norms
    assert np.all(reported >= rho * (1 - 1e-12)) and np.all(reported <= rho * (1 + 1e-3)), (reported[:3], rho)


def test_a_travelling_nut_runs_through_the_reduced_model_within_its_bound(machine):
    """The Y axis reciprocating 20 min with its feed drive (the screws' path basis: a first block
    of moments wider than the default order): the reduced model runs (three whole blocks) and every
    output stays within its verified bound of the direct run; its basis is M-orthonormal to
    round-off (its loads, 32 columns of rank 30, kept a round-off direction of M-norm 5e-6 in the
    first block, so V^T M V was 1 off the identity, which the bound hid)."""
    from twin.motion import machine_for
    from twin.scenario import scenario_from_dict
    sc = scenario_from_dict({"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                             "spindle": [{"speed": "0 rpm", "duration": "20 min"}],
                             "axis": [{"name": "Y", "move": [{"kind": "reciprocate", "between": ["0 mm", "280 mm"],
                                                              "feed": "20 mm/s", "acceleration": "10 mm/s2",
                                                              "duration": "20 min"}]}]}, "y.toml")
    moving = machine_for(machine, sc)
    spec = model_spec(moving)
    out = {}
    for kind in ("direct", "rom"):
        twin = PreparedTwin(moving, resolution="coarse", solver=kind)
        _, out[kind] = twin.run(sc, spec, _observers(moving))
        info = twin.run_info
    assert info["rom_order"] > 48 and info["rom_estimate_order"] > 0
    M = twin.loads(sc, spec).system.M
    assert twin.reduced
    for model in twin.reduced.values():
        np.testing.assert_allclose(model.V.T @ (M @ model.V), np.eye(model.order), rtol=0, atol=1e-12)
    for key in out["direct"]:
        err = np.abs(out["rom"][key] - out["direct"][key]).max(axis=0)
        assert np.all(err <= np.asarray(info["rom_error_bound"][key])), key
    assert np.abs(out["direct"]["drift"]).max() > 0


def test_residual_gram_is_the_weighted_norm_of_the_reduced_step_residual(monkeypatch):
    """The verified bound's Gram matrix, summed over row blocks (three here), is G = Y^T W Y with
    Y = [M V, K V, H V, F, r] and W = 27 M_L^-1: for any coefficients c, c^T G c equals the
    weighted norm (Y c)^T W (Y c) of the residual Y c, to round-off; and G is exactly symmetric."""
    import twin.physics.rom as rom
    _, system, n, _ = _cooled_slab(1)
    monkeypatch.setattr(rom, "GRAM_ROWS", n // 3 + 1)
    rng = np.random.default_rng(4)
    V = rng.standard_normal((n, 5))
    G = rom.residual_gram(system, V)
    Y = np.hstack([system.M @ V, system.K @ V, system.H[0] @ V, system.F, system.r])
    w = mass_weights(system.M)
    assert G.shape == (Y.shape[1], Y.shape[1]) and np.array_equal(G, G.T)
    for _ in range(3):
        c = rng.standard_normal(Y.shape[1])
        R = Y @ c
        assert c @ G @ c == pytest.approx(R @ (w * R), rel=1e-12)
    np.testing.assert_allclose(G, Y.T @ (w[:, None] * Y), rtol=0, atol=1e-13 * np.abs(G).max())


def _two_film_box():
    """A small steel box (45 nodes) with a film on each end face and two source patterns:
    (system, n)."""
    import scipy.sparse as sp
    from tests.conftest import face
    from twin.fem.assembly import assemble_facets
    mm = box_body((0.04, 0.02, 0.02), 0.01, surfaces=[("x0", face(0, 0.0)), ("x1", face(0, 0.04))])
    heat = assemble_heat(mm)
    films = [assemble_facets(mm, mm.facets[name]) for name in ("x0", "x1")]
    F = np.random.default_rng(7).random((mm.nnodes, 2))
    system = HeatSystem(heat.M, heat.K, [sp.csr_matrix(f.H) for f in films], np.column_stack([f.r for f in films]),
                        F / F.sum(axis=0))
    return system, mm.nnodes


@pytest.mark.parametrize("theta", [1.0, 0.75])
def test_a_reduced_model_on_the_whole_space_is_the_full_theta_scheme(theta):
    """Galerkin on the whole space changes nothing: for a square V with V^T M V = I (V = L^-T,
    M = L L^T) the reduced step (I + theta dt A_r) z+ = (I - (1 - theta) dt A_r) z + dt V^T f is
    V^T times the full step, so the reduced model (K_r, H_k,r, F_r, r_k,r and the rows W V, W 1
    projected as twin.physics.rom projects them) reproduces the full theta-scheme to round-off, at
    any theta, for films that switch between steps (A_r = K_r + sum_k h_k H_k,r with every film's
    term) and for batched cases whose films differ (one small solve per case). At theta 1/2, theta
    and 1 - theta weigh alike, so this needs another theta."""
    import scipy.sparse as sp
    from twin.physics.heat import integrate
    from twin.physics.rom import ReducedModel, residual_gram
    system, n = _two_film_box()
    V = np.linalg.inv(np.linalg.cholesky(system.M.toarray())).T
    Hr = np.stack([V.T @ (Hk @ V) for Hk in system.H])
    model = ReducedModel(V, V.T @ (system.K @ V), Hr, V.T @ system.F, V.T @ system.r, n // 3, 0.0, residual_gram(system, V))
    rows = sp.csr_matrix(np.eye(n)[::4])
    model = model.project_outputs(rows, mass_weights(system.M))
    steps, dt = 24, 60.0
    h = np.column_stack([np.full(steps, 50.0), np.where((np.arange(steps) // 6) % 2 == 1, 300.0, 0.0)])
    air = np.column_stack([np.full(steps, 15.0), 25.0 + np.sin(np.arange(steps))])
    s = np.random.default_rng(8).random((steps, 2)) * 20.0
    full = integrate(system, np.full(n, 20.0), dt, steps, h, air, s, rows, theta)
    got, _ = model.integrate(20.0, dt, steps, h, air, s, theta, bound=False)
    scale = np.abs(full - 20.0).max()
    np.testing.assert_allclose(got, full, rtol=0, atol=1e-9 * scale)
    # two batched cases with different films (one small solve per case and step)
    h2 = h * np.array([0.5, 2.0])
    hc, ac, sc = (np.stack([a, b], axis=2) for a, b in ((h, h2), (air, air + 3.0), (s, 0.5 * s)))
    got, _ = model.integrate(20.0, dt, steps, hc, ac, sc, theta, bound=False)
    for j in range(2):
        full = integrate(system, np.full(n, 20.0), dt, steps, hc[:, :, j], ac[:, :, j], sc[:, :, j], rows, theta)
        np.testing.assert_allclose(got[:, :, j], full, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("theta", [1.0, 0.75])
def test_the_reduced_bound_takes_each_step_residual_at_the_schemes_theta(theta):
    """The reduced step's full-space residual is R_n = M (u+ - u) + dt A u_theta - dt f_n with the
    scheme's own u_theta = theta u+ + (1 - theta) u (module docstring of twin.physics.rom): rebuilt
    from the reduced fields at theta 1 and 3/4 (at 1/2 the two weights are alike) of a small basis
    (order 6) under inputs that change every step, so the residual dwarfs the Gram sum's round-off
    allowance, sum_n (R_n^T W R_n)^(1/2) equals the run's reported bound over ||w||_W to 1e-6."""
    from twin.physics.rom import build_reduced
    _, system, n, (T0, dt, steps, h, _, _, rows) = _cooled_slab(20)
    rng = np.random.default_rng(2)
    s, air = 100.0 * rng.random((steps, 1)), 15.0 + 5.0 * rng.random((steps, 1))
    model = build_reduced(system, [np.array([300.0])], order=6).project_outputs(rows, mass_weights(system.M))
    fields = [np.zeros(n)]
    _, info = model.integrate(20.0, dt, steps, h, air, s, theta, on_step=lambda k, T: fields.append(T - 20.0))
    w = mass_weights(system.M)
    A = (system.K + 300.0 * system.H[0]).tocsr()
    rho = 0.0
    for k in range(steps):
        u, v = fields[k], fields[k + 1]
        R = system.M @ (v - u) + dt * (A @ (theta * v + (1 - theta) * u)) - dt * (
            system.F[:, 0] * s[k, 0] + h[k, 0] * (air[k, 0] - 20.0) * system.r[:, 0])
        rho += np.sqrt(R @ (w * R))
    reported = info["_bound"] / model.output_norms
    assert np.all(reported >= rho * (1 - 1e-12)) and np.all(reported <= rho * (1 + 1e-6)), (reported[:3], rho)


def test_the_basis_is_built_from_the_extremes_of_every_case_s_films(monkeypatch):
    """reduced_basis builds the reduction from the extremes of each film coefficient over the run
    (``h`` (nsteps, ncv[, m])), over every step and every batched case, so that both the spindle
    turning and standing are spanned; from their one value when they are constant; and caches it
    per operator, source patterns and tolerance."""
    from types import SimpleNamespace

    import twin.physics.rom as rom
    calls = []
    monkeypatch.setattr(rom, "build_reduced", lambda system, refs, *a, **k: calls.append([np.array(r) for r in refs]) or "basis")
    twin = SimpleNamespace(reduced={}, options=SimpleNamespace(rom_order=48))
    loads = SimpleNamespace(operator_key=("k",), system=SimpleNamespace(F=np.zeros((4, 1))), convections=[0, 1])
    h = np.zeros((5, 2, 3))
    h[:, 0, :] = [10.0, 30.0, 20.0]                       # film 0: constant in time, another per case
    h[:, 1, :] = np.array([0.0, 150.0, 150.0, 0.0, 40.0])[:, None] * [1.0, 0.5, 2.0]   # film 1 switches
    assert rom.reduced_basis(twin, loads, h) == "basis"
    (lo, hi), = calls
    np.testing.assert_array_equal(lo, [10.0, 0.0])
    np.testing.assert_array_equal(hi, [30.0, 300.0])
    assert rom.reduced_basis(twin, loads, 2 * h) == "basis" and len(calls) == 1       # cached
    calls.clear()
    rom.reduced_basis(SimpleNamespace(reduced={}, options=twin.options), loads, np.full((5, 2), 7.0))
    (only,), = calls
    np.testing.assert_array_equal(only, [7.0, 7.0])


def test_the_error_estimate_is_the_difference_from_the_leading_blocks_model():
    """The estimate is max_t |y_r - y_(r-b)| per output, y_(r-b) the same theta-scheme on the
    basis's leading columns without its last two blocks (``order_estimate`` of them: K, H, F, R
    and the observers' rows W V restricted to them): integrated here as a model of its own, the
    difference equals the reported estimate to round-off."""
    from twin.physics.rom import ReducedModel, build_reduced
    _, system, n, (T0, dt, steps, h, air, s, rows) = _cooled_slab(30)
    model = build_reduced(system, [np.array([300.0])], order=12).project_outputs(rows, mass_weights(system.M))
    r0 = model.order_estimate
    assert 0 < r0 < model.order
    lead = ReducedModel(model.V[:, :r0], model.K[:r0, :r0], model.H[:, :r0, :r0], model.F[:r0], model.R[:r0], r0,
                        0.0, model.gram, model.outputs[:, :r0], model.ones, model.output_norms)   # gram: read, unused
    y, info = model.integrate(20.0, dt, steps, h, air, s, bound=False)
    y0, _ = lead.integrate(20.0, dt, steps, h, air, s, bound=False)
    expected = np.abs(y - y0).max(axis=0)
    assert expected.max() > 0
    np.testing.assert_allclose(info["_estimate"], expected, rtol=1e-9, atol=1e-12 * np.abs(y - 20.0).max())


def test_a_basis_wider_than_round_off_allows_is_cut_and_stays_m_orthonormal():
    """V^T M V = I is what the reduced equations assume (rom's docstring). Fifteen random sources
    and two films on a 45-node box ask for more moments than the space holds: the Gram matrix's
    eigenvalues below about 1e-16 of its largest were kept (the drop threshold was absolute,
    1e-20 of the block's scale squared), so the basis grew to 48 columns in a 45-dimensional space
    with NaN in them (a square root of a negative round-off eigenvalue). Now the basis stops at
    the space's dimension, holds no NaN and is M-orthonormal to round-off (1e-12)."""
    import warnings

    from tests.conftest import face
    from twin.fem.assembly import assemble_facets
    from twin.physics.rom import build_reduced

    mm = box_body((0.04, 0.02, 0.02), 0.01, surfaces=[("x0", face(0, 0.0)), ("x1", face(0, 0.04))])
    heat = assemble_heat(mm)
    films = [assemble_facets(mm, mm.facets[k]) for k in ("x0", "x1")]
    F = np.random.default_rng(7).random((mm.nnodes, 15))
    system = HeatSystem(heat.M, heat.K, [f.H for f in films], np.column_stack([f.r for f in films]), F / F.sum(0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")               # no sqrt of a negative eigenvalue
        V = build_reduced(system, [np.array([50.0, 150.0])]).V
    assert mm.nnodes == 45 and V.shape[1] <= mm.nnodes and np.all(np.isfinite(V))
    np.testing.assert_allclose(V.T @ (heat.M @ V), np.eye(V.shape[1]), rtol=0, atol=1e-12)
