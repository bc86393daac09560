"""Variable-weight combination of two learners with GM(1,1)-forecast weights (seed 004 Section III).

Combination, seed 004 Eq. (1) (L35-L39) and Eq. (27) (L169)::

    x^(t) = alpha(t) x^_1(t) + beta(t) x^_2(t),      beta(t) = 1 - alpha(t)

with ``x^_1`` the temperature-regression + AR(1) model (``ar-temp``) and ``x^_2`` the LS-SVM
(``lssvm``) by default; ``t`` is the sample index (the seed also calls it "temperature", L39, which
the notes flag; it is used as time in Section III).

Weights as polynomials in t, Eqs. (8)-(13) (L87-L107), degree p = 2 (L91)::

    alpha(t) = alpha_0 + alpha_1 t + alpha_2 t^2,   beta(t) = beta_0 + beta_1 t + beta_2 t^2
    min sum_t (x_t - alpha(t) x_1t - beta(t) x_2t)^2   s.t.  alpha(t) + beta(t) = 1

The seed solves it with the constrained least-squares formula of Eq. (22) (L141),
``k^ = k* - (K^T K)^-1 T0^T [T0 (K^T K)^-1 T0^T]^-1 (T0 k* - R3)``. The constraint is equivalent to
beta_i = delta_i0 - alpha_i, which turns the problem into the ordinary least squares
``x_t - x_2t = alpha(t) (x_1t - x_2t)`` for (alpha_0..alpha_p); that reduced form is used here (the
tests check it against Eq. 22). A single global quadratic cannot give the seed's printed weight
sequence {0.67, 0.72, 0.65, ..., 0.58} (Eq. 35, L233; see the notes), so, as L147 suggests, the
weight sequence is built recursively: for every N the quadratic is fitted on samples 1..N (expanding
window, from N = p + 2) and alpha(N) is its value at t = N. Each alpha(N) is clipped to [0, 1]
(the seed stresses the weights' non-negativity, L147), which also makes every combined value lie
between the two members' predictions.

Forecast, Eqs. (23)-(26) (L145-L169): the next weights come from GM(1,1) on the sequence alpha(N)
(:func:`learners.grey.gm11_forecast`), clipped to [0, 1] (a forecast that overflows on a long
horizon saturates: it keeps its last finite value before the clipping). ``predict(X)`` treats the rows of ``X`` as
the samples that follow the training record, so row i gets alpha(n_train + i + 1); the members'
own predictions for those rows are combined with these weights.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin, clone

from learners._checks import check_fit_data, check_int, check_predict_data, model_name
from learners.grey import gm11_fit, gm11_simulate
from learners.registry import LEARNERS, make_learner, register_learner
from twin.errors import InputError

__all__ = ["Combination", "variable_weight_coefficients", "rolling_alpha"]


def _design(x1, x2, degree, n_scale, t=None):
    t = (np.arange(1, len(x1) + 1) if t is None else np.asarray(t, dtype=float)) / n_scale
    powers = t[:, None] ** np.arange(degree + 1)
    return (x1 - x2)[:, None] * powers, powers


def variable_weight_coefficients(y, x1, x2, degree=2, t=None):
    """Constrained LS weight polynomials over all samples: returns ``(alpha_coefs, beta_coefs)``.

    Coefficients of ``alpha(t) = sum_i alpha_i t^i`` with t = 1..n (unscaled, as in seed 004
    Eq. 14; ``t``: each row's sample index in its own run when the rows hold several runs),
    solved in the reduced form ``y - x2 = alpha(t) (x1 - x2)``; ``beta = [1, 0, ..] - alpha``.
    """
    y, x1, x2 = (np.asarray(v, dtype=float).ravel() for v in (y, x1, x2))
    A, _ = _design(x1, x2, degree, 1.0, t)
    alpha = np.linalg.lstsq(A, y - x2, rcond=None)[0]
    beta = -alpha
    beta[0] += 1.0
    return alpha, beta


def rolling_alpha(y, x1, x2, degree=2, start=None, t=None):
    """alpha(N) for N = start..max(t) from expanding-window fits on samples t = 1..N (seed 004 L147).

    ``t``: each row's sample index (1, 2, ...) in its own run; default 1..n (one run). With several
    runs the window N holds every run's samples 1..N, so each run's weights are read on its own
    clock. Uses running sums of the normal equations (one 3x3 solve per N). Returns
    ``(alpha, start)``; values are clipped to [0, 1]; an undetermined fit (members agree on the
    window) gives 0.5.
    """
    y, x1, x2 = (np.asarray(v, dtype=float).ravel() for v in (y, x1, x2))
    t = np.arange(1, len(y) + 1) if t is None else np.asarray(t, dtype=int).ravel()
    order = np.argsort(t, kind="stable")
    y, x1, x2, t = y[order], x1[order], x2[order], t[order]
    start = degree + 2 if start is None else int(start)
    A, powers = _design(x1, x2, degree, float(t[-1]), t)
    last = np.r_[t[1:] != t[:-1], True] & (t >= start)       # the last row of each window N >= start
    gram = np.cumsum(A[:, :, None] * A[:, None, :], axis=0)[last]
    rhs = np.cumsum(A * (y - x2)[:, None], axis=0)[last]
    powers = powers[last]
    scale = np.trace(gram, axis1=1, axis2=2)
    alpha = np.full(len(gram), 0.5)
    ok = scale > 1e-300
    if ok.any():
        reg = gram[ok] + (1e-12 * scale[ok])[:, None, None] * np.eye(degree + 1)
        coef = np.linalg.solve(reg, rhs[ok][:, :, None])[:, :, 0]
        alpha[ok] = (coef * powers[ok]).sum(axis=1)
    return np.clip(alpha, 0.0, 1.0), start


def _weight_forecast(seq, steps: int) -> np.ndarray:
    """The next ``steps`` values of the weight sequence ``seq`` by GM(1,1) (what
    :func:`learners.grey.gm11_forecast` computes). That function refuses a forecast that overflows;
    here a GM(1,1) that grows without bound over a long horizon only saturates the weight, which
    is clipped to [0, 1] anyway: the values after the overflow keep the last finite one."""
    seq = np.asarray(seq, dtype=float)
    a, b = gm11_fit(seq)
    with np.errstate(over="ignore", invalid="ignore"):
        alpha = gm11_simulate(a, b, float(seq[0]), seq.size + int(steps))[seq.size:]
    finite = np.isfinite(alpha)
    if not finite.all():
        if not finite[0]:
            alpha[0], finite[0] = float(seq[-1]), True
        last = np.maximum.accumulate(np.where(finite, np.arange(alpha.size), 0))
        alpha = alpha[last]
    return alpha


@register_learner("combination")
class Combination(RegressorMixin, BaseEstimator):
    """Seed 004's variable-weight combination of two learners, weights forecast by GM(1,1).

    Parameters
    ----------
    members : pair of learner names or estimators, default ("ar-temp", "lssvm")
        x^_1 and x^_2; names are built with the registry, estimators are cloned.
    degree : int, default 2
        Degree p of the weight polynomials (seed 004 L91).
    random_state : int or None
        Passed to members that take one.

    Attributes: ``estimators_`` (fitted members), ``alpha_train_`` (alpha(N), N = ``window_start_``..n),
    ``alpha_coefs_``/``beta_coefs_`` (global fit over the training set, t = 1..n), ``n_train_``.

    Several runs (:meth:`fit_runs`): the members are fitted on the runs (each time-ordered member
    on each run's own sequence, :func:`learners.runs.fit_runs`) and predict each run from its
    start; the weight polynomials take t as the sample index within each run, the window N holding
    every run's samples 1..N (:func:`rolling_alpha`); ``n_train_`` is the longest run's length,
    and ``predict`` continues from there as after one run.
    """
    time_ordered = True   # rows are one run's samples in time order (learners.runs)

    def __init__(self, members=("ar-temp", "lssvm"), degree=2, random_state=None):
        self.members = members
        self.degree = degree
        self.random_state = random_state

    def _build(self, spec):
        est = make_learner(spec) if isinstance(spec, str) else clone(spec)
        if self.random_state is not None and "random_state" in est.get_params(deep=False):
            est.set_params(random_state=self.random_state)
        return est

    def _check_params(self):
        members = self.members
        if isinstance(members, str) or not hasattr(members, "__len__") or len(members) != 2:
            n = "one name" if isinstance(members, str) else \
                (f"{len(members)}" if hasattr(members, "__len__") else repr(members))
            raise InputError(model_name(self), "members", f"needs exactly two members (learner names or estimators), "
                                                          f"got {n}")
        for i, spec in enumerate(members):
            if isinstance(spec, str):
                if spec not in LEARNERS:
                    raise InputError(model_name(self), f"members[{i}]", f"unknown learner {spec!r}; known: "
                                                                        f"{', '.join(sorted(LEARNERS))}")
            elif not (hasattr(spec, "fit") and hasattr(spec, "predict") and hasattr(spec, "get_params")):
                raise InputError(model_name(self), f"members[{i}]", f"expected a learner name or a scikit-learn "
                                                                    f"regressor, got {spec!r}")
        return check_int(self, "degree", self.degree, minimum=0)

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``, each its own time-ordered sequence (class doc)."""
        from learners.runs import fit_runs

        degree = self._check_params()
        checked = [check_fit_data(self, X, y, min_samples=degree + 5) for X, y in runs]
        if any(X.shape[1] != checked[0][0].shape[1] for X, _ in checked):
            raise ValueError("combination: the runs have different numbers of inputs")
        self.n_features_in_ = checked[0][0].shape[1]
        self.estimators_ = [fit_runs(self._build(spec), checked, str(spec)) for spec in self.members]
        y = np.concatenate([y_ for _, y_ in checked])
        x1, x2 = (np.concatenate([est.predict(X) for X, _ in checked]) for est in self.estimators_)
        t = np.concatenate([np.arange(1, len(y_) + 1) for _, y_ in checked])
        self.alpha_train_, self.window_start_ = rolling_alpha(y, x1, x2, degree, t=t)
        self.alpha_coefs_, self.beta_coefs_ = variable_weight_coefficients(y, x1, x2, degree, t=t)
        self.n_train_ = int(t.max())
        return self

    def predict_weights(self, X):
        """(alpha, beta) for the rows of ``X``, forecast by GM(1,1) beyond the training record."""
        X = check_predict_data(self, X, "alpha_train_")
        seq = self.alpha_train_
        if np.ptp(seq) <= 1e-12:
            alpha = np.full(X.shape[0], float(seq[-1]))
        else:
            alpha = _weight_forecast(seq, X.shape[0])
        alpha = np.clip(alpha, 0.0, 1.0)
        return alpha, 1.0 - alpha

    def predict(self, X):
        X = check_predict_data(self, X, "alpha_train_")
        alpha, beta = self.predict_weights(X)
        x1, x2 = (est.predict(X) for est in self.estimators_)
        return alpha * x1 + beta * x2
