"""ann and pso-bpnn (seeds 000-002). Known answers: backprop gradient equals a finite-difference
gradient of 1/2 MSE; both networks fit a smooth two-input law far better than its variance."""

import numpy as np
import pytest

from learners.neural import ANN, PSOBPNN, _backprop, _layer_shapes, _mse, _n_weights, _unpack, parse_shape
from twin.errors import InputError


def _law(n=120, seed=0):
    rng = np.random.default_rng(seed)
    X = 20.0 + 10.0 * rng.random((n, 2))                     # degC
    y = 8.0 * np.sin((X[:, 0] - 20.0) / 3.0) + 0.2 * (X[:, 1] - 25.0) ** 2   # um
    return X, y


def _rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def test_parse_shape_presets():
    assert parse_shape("4-10-1") == (10,)
    assert parse_shape("5-8-8-1") == (8, 8)
    with pytest.raises(ValueError):
        parse_shape("4-10-2")


def test_ann_fits_smooth_law_with_presets():
    X, y = _law()
    for kwargs, hidden in (({}, (10,)), ({"shape": "5-8-8-1"}, (8, 8)), ({"hidden_layer_sizes": (6,)}, (6,))):
        m = ANN(random_state=0, **kwargs).fit(X, y)
        assert m.hidden_layer_sizes_ == hidden
        assert _rmse(m.predict(X), y) < 0.1 * y.std()


def test_backprop_gradient_matches_finite_differences():
    # Known answer: one BP step with momentum 0 moves the weights by -lr * dE/dw, E = 1/2 MSE.
    rng = np.random.default_rng(3)
    X, t = rng.uniform(-1, 1, (15, 3)), rng.uniform(-1, 1, 15)
    for kind in ("tanh", "sigmoid"):
        shapes = _layer_shapes(3, (4, 3))
        w = rng.normal(scale=0.5, size=_n_weights(shapes))
        params = _unpack(w, shapes)
        lr = 1e-3
        new, _ = _backprop(params, X, t, kind, lr, epochs=1, goal=0.0, momentum=0.0)
        analytic = -(np.concatenate([np.concatenate([W.ravel(), b]) for W, b in new]) - w) / lr
        numeric = np.empty_like(w)
        h = 1e-6
        for i in range(len(w)):
            wp, wm = w.copy(), w.copy()
            wp[i] += h
            wm[i] -= h
            numeric[i] = (0.5 * _mse(_unpack(wp, shapes), X, t, kind) - 0.5 * _mse(_unpack(wm, shapes), X, t, kind)) / (2 * h)
        assert np.allclose(analytic, numeric, rtol=1e-5, atol=1e-8)


def test_pso_bpnn_fits_and_is_deterministic():
    X, y = _law()
    m = PSOBPNN(random_state=0).fit(X, y)
    p = m.predict(X)
    assert _rmse(p, y) < 0.35 * y.std()
    assert m.hidden_layer_sizes_ == (8, 8) and len(m.coefs_) == 3
    assert m.loss_curve_[-1] < m.loss_curve_[0] <= m.pso_fun_ + 1e-12   # BP starts at the swarm's best
    assert np.array_equal(PSOBPNN(random_state=0).fit(X, y).predict(X), p)


def test_pso_bpnn_hidden_search_stays_in_range():
    X, y = _law(80)
    m = PSOBPNN(hidden_layer_sizes=(8,), hidden_search=(3, 6), n_iterations=10, epochs=50, random_state=1).fit(X, y)
    assert len(m.hidden_layer_sizes_) == 1 and 3 <= m.hidden_layer_sizes_[0] <= 6
    assert m.coefs_[0].shape == (2, m.hidden_layer_sizes_[0])


def test_pso_bpnn_hidden_search_fits_on_the_first_rows_and_chooses_the_size_on_the_held_out_tail():
    """The structure search's hold-out is held out: the swarm's fitness is the scaled MSE on the rows
    before the last round(0.25 n) = 20 (pso_fun_ of the particle back-propagation starts from; with
    epochs = 0 the network is that particle), the chosen size is the one whose best particle has the
    least scaled MSE on those 20 rows (validation_mse_, the least of hidden_scores_), and the tail's
    targets never enter the swarm: shuffling the first 60 targets (the scaling unchanged) changes
    the fit, shuffling the last 20 changes no size's best particle's fit. Scaled residual:
    2 (prediction - y) / span(y)."""
    X, y = _law(80)
    kw = dict(hidden_layer_sizes=(8,), hidden_search=(3, 8), n_iterations=8, epochs=0,
              validation_fraction=0.25, random_state=1)
    m = PSOBPNN(**kw).fit(X, y)
    scaled = 2.0 * (m.predict(X) - y) / np.ptp(y)
    assert m.pso_fun_ == pytest.approx(np.mean(scaled[:60] ** 2), rel=1e-9)
    assert m.validation_mse_ == pytest.approx(np.mean(scaled[60:] ** 2), rel=1e-9)
    assert m.validation_mse_ == min(m.hidden_scores_.values())
    assert m.hidden_scores_[m.hidden_layer_sizes_] == m.validation_mse_ and len(m.hidden_scores_) > 1
    rng = np.random.default_rng(5)
    tail = y.copy()
    tail[60:] = rng.permutation(y[60:])
    head = y.copy()
    head[:60] = rng.permutation(y[:60])
    assert np.ptp(tail) == np.ptp(head) == np.ptp(y)
    t = PSOBPNN(**kw).fit(X, tail)
    assert set(t.hidden_scores_) == set(m.hidden_scores_)
    # the same swarm: each size's best particle is the same network, so its head MSE is
    for h in m.hidden_scores_:
        assert PSOBPNN(**{**kw, "hidden_search": (h[0], h[0])}).fit(X, tail).pso_fun_ == \
            PSOBPNN(**{**kw, "hidden_search": (h[0], h[0])}).fit(X, y).pso_fun_
    assert PSOBPNN(**kw).fit(X, head).pso_fun_ != m.pso_fun_
    with pytest.raises(InputError, match="validation_fraction: leaves no rows before the hold-out of 2 of 2"):
        PSOBPNN(**{**kw, "validation_fraction": 0.9}).fit(X[:2], y[:2])


def test_backprop_momentum_step_is_m_times_the_last_step_minus_lr_times_the_gradient():
    """Gradient descent with momentum (traingdm): v_k = m v_(k-1) - lr grad E(w_(k-1)), w_k = w_(k-1) + v_k,
    v_0 = 0, so w1 - w0 = -lr grad E(w0) and w_(k+1) - w_k = m (w_k - w_(k-1)) - lr grad E(w_k), with
    m = 0.9, lr = 0.05 and E = 1/(2N) sum (o - t)^2 of a 3-4-3-1 tanh network written out here (weights
    packed layer by layer, W row-major then b). grad E by the complex step, Im E(w + i h e_j) / h,
    exact to rounding; the steps are read from runs of 1, 2 and 3 epochs. Rounding of the O(1) weights only: 1e-14."""
    rng = np.random.default_rng(11)
    X, t = rng.uniform(-1, 1, (15, 3)), rng.uniform(-1, 1, 15)
    sizes = (3, 4, 3, 1)
    shapes = _layer_shapes(3, (4, 3))
    w0 = rng.normal(scale=0.5, size=_n_weights(shapes))
    m, lr = 0.9, 0.05

    def loss(w):
        h, k = X.astype(w.dtype), 0
        for i in range(len(sizes) - 1):
            a, b = sizes[i], sizes[i + 1]
            W, bias = w[k:k + a * b].reshape(a, b), w[k + a * b:k + a * b + b]
            k += a * b + b
            h = h @ W + bias
            if i < len(sizes) - 2:
                h = np.tanh(h)
        return np.sum((h[:, 0] - t) ** 2) / (2 * len(t))

    def grad(w):
        step = 1e-30
        return np.array([loss(w + 1j * step * e).imag / step for e in np.eye(w.size)])

    def after(epochs):
        params, curve = _backprop(_unpack(w0, shapes), X, t, "tanh", lr, epochs=epochs, goal=0.0, momentum=m)
        assert len(curve) == epochs
        return np.concatenate([np.concatenate([W.ravel(), b]) for W, b in params])

    w1, w2, w3 = after(1), after(2), after(3)
    np.testing.assert_allclose(w1 - w0, -lr * grad(w0), rtol=0, atol=1e-14)
    np.testing.assert_allclose(w2 - w1, m * (w1 - w0) - lr * grad(w1), rtol=0, atol=1e-14)
    np.testing.assert_allclose(w3 - w2, m * (w2 - w1) - lr * grad(w2), rtol=0, atol=1e-14)
    assert np.abs(m * (w2 - w1)).max() > 1e-3                  # the momentum term is far above the tolerance
