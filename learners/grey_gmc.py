"""GMC(1,N), the grey model with convolution integral (Tien), fitted by least squares or by PSO.

Model (thesis §3.6, Eq. (3.13) with delay r = 0; App. A Eq. (A.1), seed 000 L2576-2789, L7381-7426)::

    d x_1^(1)/dt + b_1 x_1^(1)(t) = b_2 x_2^(1)(t) + ... + b_N x_N^(1)(t) + u

``b_1``: development coefficient (1/sample); ``b_j``: driving coefficients (µm per °C per sample
when x_1 is in µm and the drivers are ΔT in °C); ``u``: grey control parameter (µm per sample).

Time response, ``f(tau) = sum_j b_j x_j^(1)(tau) + u`` (App. A Eq. (A.2), Tien's form)::

    x_1^(1)(k) = x_1^(1)(1) e^{-b_1 (k-1)} + sum_{tau=2..k} e^{-b_1 (k - tau + 1/2)} (f(tau) + f(tau-1)) / 2

i.e. the convolution integral evaluated with the midpoint rule on each sample interval, and
computed recursively as ``x(k) = e^{-b_1} x(k-1) + e^{-b_1/2} (f(k) + f(k-1))/2``. The seed prints
(A.2) with the sum over tau = 1..k of ``f(tau) + f(tau-1)`` for output k+1, which references the
undefined ``f(0)``; the index shift to tau = 2..k for output k is the standard Tien form. The
trapezoidal form (3.14) is a different quadrature of the same integral; its last term is printed as
``1/2 f(tau)`` and is read as ``1/2 f(t)`` (notes §3.6). Then IAGO (3.18):
``x_1^(0)(k) = x_1^(1)(k) - x_1^(1)(k-1)``.

Least squares, two ways (``fit_method`` of :class:`GMC1N`; see :mod:`learners.grey` on long records):

- ``"equation"``: Tien's least squares of the grey equation (thesis Table 6-3 "LS-based Grey model"):
  for k = 2..n, ``x_1^(0)(k) = -b_1 z_1^(1)(k) + sum_j b_j z_j^(1)(k) + u`` with background values
  ``z``. On a long densely sampled record ``b_1`` comes out near 0 with a noise-set sign; a
  negative one makes the response grow as ``e^{-b_1 k}`` (1e14 to 1e16 on the seed-001 twin
  run), so a fitted response that would grow more than 1e3-fold over the record is refused.
- ``"response"`` (default): least squares of the simulated response itself, the fitness (3.17),
  by variable projection: for fixed ``b_1`` the response is linear in ``(b_j, u)`` (exact linear
  least squares); ``b_1`` in ``(0, 20]`` by a log grid refined by bounded Brent
  (:func:`learners.grey.response_ls_fit`: the global minimum to the grid's resolution). The PSO
  variant searches the same fitness stochastically.

PSO (thesis §3.6 steps 1-6, §6.3.2: 90 particles, c1 = c2 = 2, inertia 0.9 -> 0.4, 100 epochs)
minimises the fitness (3.17) ``sum_k (x_hat_1^(0)(k) - x_1^(0)(k))^2`` over (b_1, b_j, u).

``response="difference"`` replaces the convolution by the exact solution of the LS grey equation,
``x(k) = [(1 - b_1/2) x(k-1) + (f(k) + f(k-1))/2] / (1 + b_1/2)``, so the model reproduces data
generated from its own least-squares equation exactly (used by the tests).

Rows are time (see :mod:`learners.grey`): ``X`` is (n, N-1) drivers, ``y`` the response.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import MAX_ITERATIONS, MAX_PARTICLES, check_choice, check_int, check_positive, check_start_value
from learners.grey import FIT_METHODS, ago, background, check_growth, check_n_features, check_runs, check_series, \
    iago, refuse_divergence, response_ls_fit, search_bound
from learners.pso import box_edges, pso_minimize
from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["gmc_simulate", "gmc_ls_fit", "gmc_ls_fit_runs", "GMC1N", "GMC1NPSO"]

_RESPONSES = ("convolution", "difference")


def gmc_simulate(b1: float, b, u: float, X_ago: np.ndarray, y0: float, response="convolution") -> np.ndarray:
    """Response ``x_1^(0)(1..n)`` of GMC(1,N) for AGO drivers ``X_ago`` (n, N-1) and start ``y0``."""
    f = X_ago @ np.asarray(b, dtype=float) + u
    g = 0.5 * (f[1:] + f[:-1])
    if response == "convolution":
        decay, gain = np.exp(-b1), np.exp(-0.5 * b1)
    elif response == "difference":
        lead = 1.0 + 0.5 * b1
        if lead == 0.0:
            return np.full(X_ago.shape[0], np.inf)
        decay, gain = (1.0 - 0.5 * b1) / lead, 1.0 / lead
    else:
        raise InputError("parameters", "response", f"unknown GMC response {response!r}; use {_RESPONSES}")
    x1 = np.empty(X_ago.shape[0])
    x1[0] = y0
    if g.size:
        # x(k) = decay * x(k-1) + gain * g(k): a first-order recursive filter started at y0.
        x1[1:], _ = lfilter([gain], [1.0, -decay], g, zi=[decay * y0])
    return iago(x1)


def gmc_ls_fit(X, y):
    """Least-squares ``(b1, b, u)`` of GMC(1,N) on raw drivers ``X`` (n, p) and response ``y``."""
    return gmc_ls_fit_runs([(X, y)])


def gmc_ls_fit_runs(runs):
    """Least-squares ``(b1, b, u)`` of GMC(1,N) on several runs ``[(X, y), ...]``: each run
    accumulated from its own start, the equation rows (k = 2..n of each run) stacked."""
    rows, targets = [], []
    for X, y in runs:
        z1 = background(ago(y))
        rows.append(np.column_stack([-z1, background(ago(X)), np.ones_like(z1)]))
        targets.append(y[1:])
    theta, *_ = np.linalg.lstsq(np.vstack(rows), np.concatenate(targets), rcond=None)
    return float(theta[0]), theta[1:-1].copy(), float(theta[-1])


def gmc_retention(b1: float, response: str) -> float:
    """Per-sample factor of the homogeneous GMC(1,N) response (|.| > 1: grows without bound)."""
    if response == "convolution":
        return float(np.exp(-b1))
    lead = 1.0 + 0.5 * b1
    return np.inf if lead == 0.0 else (1.0 - 0.5 * b1) / lead


class _GMCBase(BaseEstimator, RegressorMixin):
    """Shared validation and prediction of the GMC(1,N) estimators.

    ``fit(X, y)`` is ``fit_runs([(X, y)])``; with several runs (:mod:`learners.runs`) each run is
    accumulated and simulated from its own first value and the squared errors of all runs are
    summed; ``y0_`` is then the mean first value."""
    time_ordered = True   # rows are one run's samples in time order (learners.runs)

    _name = "GMC(1,N)"

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def _check_params(self):
        check_choice(self, "response", self.response, _RESPONSES)
        check_start_value(self, self.y0)

    def _check_fit(self, runs):
        self._check_params()
        checked = check_runs(runs, model=self._name)
        p = checked[0][0].shape[1]
        n = sum(Xa.shape[0] for Xa, _ in checked)
        if n < p + 3:
            raise InputError("data", "rows", f"{self._name} with {p} inputs needs at least {p + 3} rows, got {n}")
        return checked, p

    def _store(self, b1, b, u, starts, p):
        self.b1_ = float(b1)
        self.b_ = np.asarray(b, dtype=float)
        self.u_ = float(u)
        self.coef_ = self.b_
        self.y0_ = float(np.mean(starts)) if self.y0 is None else float(self.y0)
        self.n_features_in_ = p

    def predict(self, X):
        Xa = check_series(X, model=self._name, min_rows=1)
        check_n_features(self, Xa)
        check_growth(gmc_retention(self.b1_, self.response), Xa.shape[0], model=self._name, coef_name="b1",
                     coef=self.b1_, fit_method=getattr(self, "fit_method", "PSO"))
        with np.errstate(over="ignore", invalid="ignore"):
            out = gmc_simulate(self.b1_, self.b_, self.u_, ago(Xa), self.y0_, self.response)
        return refuse_divergence(out, model=self._name, field="X", coef_name="b1", coef=self.b1_)


@register_learner("gmc1n")
class GMC1N(_GMCBase):
    """GMC(1,N) calibrated by least squares (module docstring for the equations).

    Parameters: ``response`` ("convolution": Tien's time response (A.2), as in the thesis;
    "difference": exact solution of the LS grey equation); ``y0``: response at the start of a
    predicted run (``None``: first training target); ``fit_method`` ("response", default: least
    squares of the simulated response with ``0 < b_1 <= 20``; "equation": Tien's least squares of the
    grey equation, refused with :class:`InputError` when its response would grow more than 1e3-fold
    over the record).

    Fitted: ``b1_``, ``b_`` (N-1,), ``u_``, ``coef_`` (= ``b_``), ``y0_``, ``n_features_in_``.
    """

    def __init__(self, response="convolution", y0=None, fit_method="response"):
        self.response = response
        self.y0 = y0
        self.fit_method = fit_method

    def _check_params(self):
        super()._check_params()
        check_choice(self, "fit_method", self.fit_method, FIT_METHODS)

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``, each its own time-ordered sequence."""
        checked, p = self._check_fit(runs)
        starts = np.array([ya[0] for _, ya in checked])
        if self.fit_method == "equation":
            b1, b, u = gmc_ls_fit_runs(checked)
            self.at_bound_ = ""
            check_growth(gmc_retention(b1, self.response), max(ya.size for _, ya in checked), model=self._name,
                         coef_name="b1", coef=b1, fit_method="equation")
        else:
            X_agos = [ago(Xa) for Xa, _ in checked]

            def simulate(b1_, th, y0):
                firsts = np.broadcast_to(y0, starts.shape)
                return np.concatenate([gmc_simulate(b1_, th[:-1], th[-1], Xg, s, self.response)
                                       for Xg, s in zip(X_agos, firsts)])

            b1, theta, _ = response_ls_fit(simulate, np.concatenate([ya for _, ya in checked]), p + 1, a_max=20.0,
                                           start=starts)
            b, u = theta[:-1], theta[-1]
            self.at_bound_ = search_bound(b1, 20.0)   # b_1 at an end of the search range ('' inside it)
        self._store(b1, b, u, starts, p)
        return self


@register_learner("gmc1n-pso")
class GMC1NPSO(_GMCBase):
    """GMC(1,N) calibrated by particle swarm optimisation of the fitness (3.17).

    The search runs on scaled data (each driver divided by its largest |value|, the response by its
    largest |value|) so one box fits all units: ``b_1`` in ``[0, b1_max]``, scaled driving
    coefficients and ``u`` in ``[-coef_bound, coef_bound]``; results are returned in data units.
    Defaults follow the thesis (§6.3.2, L6735-6742): 90 particles, 100 epochs, c1 = c2 = 2,
    inertia weight 0.9 -> 0.4. ``b_1`` and the driving coefficients are strongly correlated in the
    fitness, so 100 iterations give an approximate fit; ``variant="constriction"`` with 200-300
    iterations reaches the least-squares optimum to about 0.01 on the test data.

    Fitted: as :class:`GMC1N`, plus ``fitness_`` (final SSE in scaled units) and
    ``n_evaluations_``.
    """

    _name = "GMC(1,N)-PSO"

    bound_subject = "its coefficients"     # the leaderboard's note: "... sit at the search box's bound"

    def __init__(self, response="convolution", y0=None, n_particles=90, n_iterations=100, variant="inertia",
                 b1_max=2.0, coef_bound=10.0, random_state=None):
        self.response = response
        self.y0 = y0
        self.n_particles = n_particles
        self.n_iterations = n_iterations
        self.variant = variant
        self.b1_max = b1_max
        self.coef_bound = coef_bound
        self.random_state = random_state

    def _check_params(self):
        super()._check_params()
        check_int(self, "n_particles", self.n_particles, maximum=MAX_PARTICLES)
        check_int(self, "n_iterations", self.n_iterations, minimum=0, maximum=MAX_ITERATIONS)
        check_choice(self, "variant", self.variant, ("inertia", "constriction"))
        check_positive(self, "b1_max", self.b1_max)
        check_positive(self, "coef_bound", self.coef_bound)

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``: the fitness sums every run's squared error."""
        checked, p = self._check_fit(runs)
        sx = np.max(np.abs(np.vstack([Xa for Xa, _ in checked])), axis=0)
        sx[sx == 0.0] = 1.0
        sy = float(np.max(np.abs(np.concatenate([ya for _, ya in checked])))) or 1.0
        scaled = [(ago(Xa / sx), ya / sy) for Xa, ya in checked]

        def fitness(theta):
            return float(sum(np.sum((gmc_simulate(theta[0], theta[1:-1], theta[-1], xg, ys[0], self.response) - ys)
                                    ** 2) for xg, ys in scaled))

        lower = np.r_[0.0, np.full(p + 1, -float(self.coef_bound))]
        upper = np.r_[float(self.b1_max), np.full(p + 1, float(self.coef_bound))]
        with np.errstate(over="ignore", invalid="ignore"):
            res = pso_minimize(fitness, lower, upper, n_particles=self.n_particles, n_iterations=self.n_iterations,
                               variant=self.variant, random_state=self.random_state)
        theta = res.x
        self._store(theta[0], theta[1:-1] * sy / sx, theta[-1] * sy, [ya[0] for _, ya in checked], p)
        self.at_bound_ = box_edges(theta, lower, upper, ["b1"] + [f"b[{j}]" for j in range(p)] + ["u"])
        self.fitness_ = res.fun
        self.n_evaluations_ = res.n_evaluations
        return self
