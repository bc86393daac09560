"""GNNMCI(1,N): grey neural network with convolution integral, trained by PSO on AGO data.

Thesis App. A (seed 000 L7355-7669), used in §5 (Machine C, L5651-5706) and §6 (ETVE, L6279-6301).
Steps: 1-AGO of all series -> map the GMC(1,N) time response onto a 4-layer network -> train the
weights by PSO with fitness (A.9) ``sum_k (x_hat_1^(0)(k) - x_1^(0)(k))^2`` -> 1-IAGO.

GMC(1,N) time response (A.2)-(A.5), ``G`` the convolution sum (A.3)::

    x_1^(1)(k+1) = x_1^(1)(1) e^{-b_1 k} + G
                 = [x_1^(1)(1) - x_1^(1)(1) / (1 + e^{-b_1 k}) + G / (1 + e^{-b_1 k})] (1 + e^{-b_1 k})

Network, for the input sample k (k = 0 at the first row, output = AGO response at that row):

    layer A  a = w11 k
    layer B  s = 1 / (1 + e^{-w11 k})                      (the only sigmoid layer)
    layer C  c_1 = s w21,  c_j = x_j^(1) s w2j (j = 2..N),  c_u = s w2u
    layer D  d = sum_j w3j c_j - theta,   w3j = 1 + e^{-w11 k}

and, at the first sample (k = 0), the output is ``x_1^(1)(1)`` itself: the unit step ``u(t-1)`` of
(A.2)/(A.3) switches ``G`` off there (the layer equations alone would add the ``G`` terms). The
tied weights are ``w11 = b_1``, ``w21 = -x_1^(1)(1)`` and ``w2j = d_j = f(b_j)`` (the thesis
leaves ``f`` unspecified; the ``d_j`` are trained directly).

Deviation (garbled seed): the bias (A.6) is printed ``theta = (-x_1^(1)(k+1)) (1 + e^{-b_1 k})``, which
contains the unknown output itself. The standard grey-neural-network bias uses the initial value,
``theta = -x_1^(1)(1) (1 + e^{-w11 k})``, and that is used here (notes §3.8 flag the same).

Consequence worth knowing: because ``w3j s = 1``, the network output is exactly
``x_1^(1)(1) e^{-w11 k} + sum_j w2j x_j^(1)(k) + w2u`` for k >= 1. After IAGO, from the third row
on, the prediction is a linear combination of the raw drivers plus a decaying start-up term that
vanishes when the response starts at 0, so ``w11`` only matters through the initial value. The forward pass below computes the four layers
literally; the identity is checked in the tests. The thesis's Machine C weights (L5807-5815,
w21 = 0.001 ~ -x_1^(1)(1)) are consistent with this reading.

Defaults follow the thesis (L5797-5806): 90 particles, 100 epochs, c1 = 1.5, c2 = 2, inertia weight
0.9 -> 0.4. PSO searches scaled weights (drivers divided by their max |value|, response by its
max |value|): ``w11`` in ``[0, w11_max]``, ``w2j`` and ``w2u`` in ``[-weight_bound, weight_bound]``.

Rows are time (see :mod:`learners.grey`): ``X`` (n, N-1) drivers, e.g. ΔT in °C or FBG strain;
``y`` the thermal error (µm). ``predict(X)`` treats X as a run from its own start with response
``y0`` there (``None``: first training target).
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import (MAX_ITERATIONS, MAX_PARTICLES, check_choice, check_int, check_non_negative,
                              check_positive, check_start_value, model_name)
from learners.grey import ago, check_n_features, check_runs, check_series, iago, refuse_divergence
from learners.pso import box_edges, pso_minimize
from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["gnnmci_forward", "GNNMCI"]


def gnnmci_forward(w11: float, w2, w2u: float, X_ago: np.ndarray, x1_first: float) -> np.ndarray:
    """Network output ``x_hat_1^(1)`` (n,) for AGO drivers ``X_ago`` (n, p), layers A-D of App. A."""
    k = np.arange(X_ago.shape[0], dtype=float)
    with np.errstate(over="ignore"):
        layer_a = w11 * k
        decay = np.exp(-layer_a)
    layer_b = 1.0 / (1.0 + decay)
    w21 = -x1_first
    w3 = 1.0 + decay
    theta = -x1_first * w3
    layer_c = np.column_stack([layer_b * w21, X_ago * np.asarray(w2, dtype=float) * layer_b[:, None],
                               layer_b * w2u])
    out = (w3[:, None] * layer_c).sum(axis=1) - theta
    out[0] = x1_first  # unit step u(t-1) of (A.2)/(A.3): G = 0 at the first sample
    return out


@register_learner("gnnmci")
class GNNMCI(BaseEstimator, RegressorMixin):
    """Grey neural network GNNMCI(1,N) trained by PSO on AGO data (see module docstring).

    Fitted: ``w11_`` (= b_1), ``w2_`` (driver weights d_j, data units), ``w2u_`` (u node),
    ``w21_`` (= -y at the first training row), ``y0_``, ``fitness_`` (scaled SSE),
    ``n_evaluations_``, ``n_features_in_``.
    """

    def __init__(self, y0=None, n_particles=90, n_iterations=100, variant="inertia", c1=1.5, c2=2.0,
                 w11_max=1.0, weight_bound=10.0, random_state=None):
        self.y0 = y0
        self.n_particles = n_particles
        self.n_iterations = n_iterations
        self.variant = variant
        self.c1 = c1
        self.c2 = c2
        self.w11_max = w11_max
        self.weight_bound = weight_bound
        self.random_state = random_state

    time_ordered = True   # rows are one run's samples in time order (learners.runs)

    def _check_params(self):
        check_start_value(self, self.y0)
        check_int(self, "n_particles", self.n_particles, maximum=MAX_PARTICLES)
        check_int(self, "n_iterations", self.n_iterations, minimum=0, maximum=MAX_ITERATIONS)
        check_choice(self, "variant", self.variant, ("inertia", "constriction"))
        check_non_negative(self, "c1", self.c1)
        check_non_negative(self, "c2", self.c2)
        if self.variant == "constriction" and (self.c1, self.c2) != (2.0, 2.0) and self.c1 + self.c2 <= 4.0:
            raise InputError(model_name(self), "c1", f"variant 'constriction' needs c1 + c2 > 4, got "
                                                     f"{self.c1:g} + {self.c2:g}")
        check_positive(self, "w11_max", self.w11_max)
        check_positive(self, "weight_bound", self.weight_bound)

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``: the fitness sums every run's squared error, each
        run accumulated and started from its own first value; ``y0_`` and ``w21_`` use the mean
        first value."""
        self._check_params()
        checked = check_runs(runs, model="GNNMCI(1,N)")
        Xa, ya = np.vstack([c[0] for c in checked]), np.concatenate([c[1] for c in checked])
        n, p = Xa.shape
        if n < p + 3:
            raise InputError("data", "rows", f"GNNMCI(1,N) with {p} inputs needs at least {p + 3} rows, got {n}")
        sx = np.max(np.abs(Xa), axis=0)
        sx[sx == 0.0] = 1.0
        sy = float(np.max(np.abs(ya))) or 1.0
        scaled = [(ago(x / sx), y / sy) for x, y in checked]
        start = float(np.mean([y[0] for _, y in checked]))

        def fitness(w):
            return float(sum(np.sum((iago(gnnmci_forward(w[0], w[1:-1], w[-1], xg, ys[0])) - ys) ** 2)
                             for xg, ys in scaled))

        bound = float(self.weight_bound)
        lower = np.r_[0.0, np.full(p + 1, -bound)]
        upper = np.r_[float(self.w11_max), np.full(p + 1, bound)]
        res = pso_minimize(fitness, lower, upper, n_particles=self.n_particles, n_iterations=self.n_iterations,
                           variant=self.variant, c1=self.c1, c2=self.c2, random_state=self.random_state)
        w = res.x
        self.at_bound_ = box_edges(w, lower, upper, ["w11"] + [f"w2[{j}]" for j in range(p)] + ["w2u"],
                                   free_lower=("w11",))   # w11 = 0: a model without inertia, inside its meaning
        self.w11_ = float(w[0])
        self.w2_ = w[1:-1] * sy / sx
        self.w2u_ = float(w[-1] * sy)
        self.w21_ = -start
        self.y0_ = start if self.y0 is None else float(self.y0)
        self.fitness_ = res.fun
        self.n_evaluations_ = res.n_evaluations
        self.n_features_in_ = p
        return self

    bound_subject = "its network weights"   # the leaderboard's note: "... sit at the search box's bound"

    def predict(self, X):
        Xa = check_series(X, model="GNNMCI(1,N)", min_rows=1)
        check_n_features(self, Xa)
        with np.errstate(over="ignore", invalid="ignore"):
            out = iago(gnnmci_forward(self.w11_, self.w2_, self.w2u_, ago(Xa), self.y0_))
        return refuse_divergence(out, model="GNNMCI(1,N)", field="X", coef_name="w11", coef=self.w11_)
