"""Least-squares support vector machine (LS-SVM) regression with an RBF kernel (seed 004 Section II.B).

Model, seed 004 Eq. (4) (L61)::

    y(x) = sum_i a_i K(x, x_i) + b

RBF kernel, Eq. (6) (L71), written for vector inputs with the squared Euclidean distance::

    K(x_i, x_j) = exp(-||x_i - x_j||^2 / (2 sigma^2))

Training solves the (n+1) x (n+1) KKT linear system of Eq. (5) (L67)::

    [ 0   1^T           ] [ b ]   [ 0 ]
    [ 1   Omega + I/gamma ] [ a ] = [ y ],     Omega_ij = K(x_i, x_j)

whose first row forces ``sum_i a_i = 0``. ``gamma`` (dimensionless) is the regularisation: large
gamma interpolates the data, small gamma smooths. ``sigma`` is the kernel width in the units of the
inputs (degC for temperatures). Defaults are the seed's fitted values, Eq. (28) (L195):
gamma = 56.2 and sigma^2 = 71.4, i.e. sigma = sqrt(71.4) = 8.45. The seed chooses them by an
unspecified "dynamically adaptive algorithm" (L73); here they are plain hyper-parameters.

``standardize=True`` z-scores the inputs first (sigma is then in standard deviations); the default
``False`` keeps the seed's raw-unit kernel. The dense system costs O(n^3) time and O(n^2) memory, so
when the training set has more than ``max_samples`` rows an evenly spaced subset of that many rows
(deterministic, first and last kept) is used; ``n_support_`` reports how many.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import check_bool, check_fit_data, check_int, check_positive, check_predict_data, standardise
from learners.registry import register_learner

__all__ = ["LSSVM", "rbf_kernel", "lssvm_system"]


def rbf_kernel(A, B, sigma):
    """RBF kernel matrix K[i, j] = exp(-||A_i - B_j||^2 / (2 sigma^2)) (seed 004 Eq. 6)."""
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    d2 = (A * A).sum(axis=1)[:, None] + (B * B).sum(axis=1)[None, :] - 2.0 * A @ B.T
    return np.exp(-np.clip(d2, 0.0, None) / (2.0 * sigma ** 2))


def lssvm_system(X, y, gamma, sigma):
    """Build the KKT matrix and right-hand side of seed 004 Eq. (5); unknowns are ``[b, a_1..a_n]``."""
    n = X.shape[0]
    A = np.empty((n + 1, n + 1))
    A[0, 0] = 0.0
    A[0, 1:] = 1.0
    A[1:, 0] = 1.0
    A[1:, 1:] = rbf_kernel(X, X, sigma)
    A[1:, 1:][np.diag_indices(n)] += 1.0 / gamma
    rhs = np.concatenate(([0.0], y))
    return A, rhs


@register_learner("lssvm")
class LSSVM(RegressorMixin, BaseEstimator):
    """LS-SVM regression with RBF kernel, solved from its (n+1)x(n+1) KKT system (seed 004 Eq. 5).

    Parameters
    ----------
    gamma : float, default 56.2
        Regularisation (seed 004 Eq. 28). Must be > 0.
    sigma : float, default sqrt(71.4) ~= 8.45
        RBF width in input units (degC), seed 004 Eq. (28) gives sigma^2 = 71.4.
    standardize : bool, default False
        z-score the inputs before the kernel.
    max_samples : int >= 2, default 3000
        Largest training set solved densely; longer sets are thinned evenly.

    Attributes
    ----------
    dual_coef_ : ndarray (n_support_,)   the a_i (sum to zero)
    intercept_ : float                   b, units of y
    support_vectors_ : ndarray           training inputs used (after optional scaling)
    n_support_ : int
    """

    def __init__(self, gamma=56.2, sigma=float(np.sqrt(71.4)), standardize=False, max_samples=3000):
        self.gamma = gamma
        self.sigma = sigma
        self.standardize = standardize
        self.max_samples = max_samples

    def _check_params(self):
        check_positive(self, "gamma", self.gamma)
        check_positive(self, "sigma", self.sigma)
        check_bool(self, "standardize", self.standardize)
        return check_int(self, "max_samples", self.max_samples, minimum=2)

    def fit(self, X, y):
        max_samples = self._check_params()
        X, y = check_fit_data(self, X, y)
        n = X.shape[0]
        self.thinned_ = ""
        if n > max_samples:
            keep = np.unique(np.round(np.linspace(0, n - 1, max_samples)).astype(int))
            X, y = X[keep], y[keep]
            self.thinned_ = (f"trained on {len(keep)} evenly spaced of its {n} training rows (max_samples: its "
                             "kernel system grows as the rows squared)")
        if self.standardize:
            X, self.x_mean_, self.x_scale_ = standardise(X)
        else:
            self.x_mean_, self.x_scale_ = np.zeros(X.shape[1]), np.ones(X.shape[1])
        A, rhs = lssvm_system(X, y, self.gamma, self.sigma)
        sol = scipy.linalg.solve(A, rhs, assume_a="sym")
        self.intercept_ = float(sol[0])
        self.dual_coef_ = sol[1:]
        self.support_vectors_ = X.copy()
        self.n_support_ = X.shape[0]
        return self

    def predict(self, X):
        X = check_predict_data(self, X, "dual_coef_")
        Z = (X - self.x_mean_) / self.x_scale_
        return rbf_kernel(Z, self.support_vectors_, self.sigma) @ self.dual_coef_ + self.intercept_
