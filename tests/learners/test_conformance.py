"""One scikit-learn contract check over every registered learner and selector.

For each name in ``learners.LEARNERS`` / ``learners.SELECTORS``: ``clone``; ``fit`` returns self and
leaves the hyper-parameters alone; ``predict`` gives (n,) finite values (``transform`` gives
(n, k), 1 <= k <= p); same ``random_state`` -> identical output; inputs are not mutated;
``get_params`` round-trips through the constructor and ``set_params``.
"""

import numpy as np
import pytest
from sklearn.base import clone

import learners
from learners.runs import is_time_ordered

N_ROWS, N_COLS = 60, 6


def smooth_data():
    """60 time-ordered rows of 6 smooth temperature series (°C) and an error (µm) from 2 of them."""
    t = np.arange(N_ROWS, dtype=float)
    rng = np.random.default_rng(42)
    taus = [8.0, 15.0, 25.0, 40.0, 60.0, 90.0]
    X = np.column_stack([20 + (2 + j) * (1 - np.exp(-t / tau)) + 0.3 * np.sin(t / (5 + j))
                         for j, tau in enumerate(taus)])
    X += rng.normal(0.0, 0.02, X.shape)
    y = 3.0 * (X[:, 1] - X[0, 1]) - 1.5 * (X[:, 4] - X[0, 4]) + 0.5 * np.sin(t / 7)
    return X, y


def same(a, b):
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.array_equal(np.asarray(a), np.asarray(b))
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return a is b or a == b


def same_params(p, q):
    return p.keys() == q.keys() and all(same(p[k], q[k]) for k in p)


def seeded(est):
    if "random_state" in est.get_params():
        est.set_params(random_state=0)
    return est


CASES = [("learner", name) for name in sorted(learners.LEARNERS)] + \
        [("selector", name) for name in sorted(learners.SELECTORS)]


@pytest.mark.parametrize("kind,name", CASES, ids=[f"{k}:{n}" for k, n in CASES])
def test_sklearn_contract(kind, name):
    make = learners.make_learner if kind == "learner" else learners.make_selector
    est = seeded(make(name))
    X, y = smooth_data()
    X_before, y_before = X.copy(), y.copy()

    # get_params round trip: constructor and set_params
    params = est.get_params()
    assert same_params(type(est)(**params).get_params(), params)
    assert same_params(clone(est).set_params(**params).get_params(), params)

    a = clone(est)
    assert a.fit(X, y) is a
    assert same_params(a.get_params(), params), "fit changed hyper-parameters"
    if kind == "learner":
        out_a = a.predict(X)
        assert out_a.shape == (N_ROWS,)
        assert np.all(np.isfinite(out_a))
    else:
        out_a = a.transform(X)
        assert out_a.ndim == 2 and out_a.shape[0] == N_ROWS and 1 <= out_a.shape[1] <= N_COLS
        assert len(a.selected_) == out_a.shape[1]
        assert all(isinstance(int(j), int) and 0 <= j < N_COLS for j in a.selected_)
        assert len(a.selected_names_) == len(a.selected_)
        assert all(isinstance(s, str) for s in a.selected_names_)
    np.testing.assert_array_equal(X, X_before)
    np.testing.assert_array_equal(y, y_before)

    b = clone(est).fit(X, y)
    out_b = b.predict(X) if kind == "learner" else b.transform(X)
    np.testing.assert_array_equal(out_a, out_b)
    np.testing.assert_array_equal(X, X_before)


POOLED = sorted(n for n in learners.LEARNERS if not is_time_ordered(learners.LEARNERS[n]()))
SMALL = {"anfis-grid": {"n_mfs": 2, "epochs": 3}, "anfis-fcm": {"epochs": 3},
         "pso-bpnn": {"n_iterations": 3, "epochs": 10}}


@pytest.mark.parametrize("name", POOLED)
def test_a_pooled_learners_prediction_of_a_row_does_not_depend_on_the_other_rows(name):
    """Every learner that treats rows as independent scales new rows with the statistics of its
    training rows, never of the rows it predicts: one row predicted alone, and a batch of the last
    20 rows (whose mean and range differ from the training set's), read what the whole set reads."""
    X, y = smooth_data()
    est = seeded(learners.make_learner(name, **SMALL.get(name, {}))).fit(X, y)
    full = est.predict(X)
    for i in (0, 17, N_ROWS - 1):
        np.testing.assert_allclose(est.predict(X[i:i + 1]), full[i:i + 1], rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(est.predict(X[40:]), full[40:], rtol=1e-10, atol=1e-10)
