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
from tests.test_scale import _cooled_slab, _observers
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
    output stays within its verified bound of the direct run."""
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
