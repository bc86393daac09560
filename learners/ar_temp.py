"""Temperature regression plus AR(1) residual: the "time series" model of seed 004 (Section IV.B).

Fitted equations (seed 004, L203-L227)::

    x_t = C0 + Cs . T_t + r_t                       (30) trend on temperature, OLS     (L207-L215)
    r_t = phi_1 r_{t-1} + a_t                       (32) AR(1) on the residual         (L217)
    phi_1 = gamma(1) / gamma(0),                     Yule-Walker moment estimate        (L221)
    sigma_a^2 = gamma(0) (1 - phi_1^2)

    x_t = C0 (1 - phi_1) + phi_1 x_{t-1} + Cs . T_t - phi_1 Cs . T_{t-1}      (34) (L227)

with ``x`` the thermal error (um), ``T`` the temperature(s) (degC; the seed uses one sensor, here
any number of columns, ``Cs`` a vector in um/degC) and ``gamma(k)`` the lag-k autocovariance of the
OLS residual (divisor n). Seed values: C0 = 194.83, Cs = -1.762, phi_1 = 0.213,
sigma_a^2 = 1.379, hence Eq. (34) = 153.33 + 0.213 x(t-1) - 1.762 T_t + 0.375 T_(t-1)
(the seed picked order 1 by the final-prediction-error criterion; this learner is AR(1) only).

Rows of ``X`` must be consecutive, equally spaced samples in time order.

Prediction. Eq. (34) needs the previous error ``x_{t-1}``:

* :meth:`ARTemp.predict_one_step` uses the *measured* previous target ``y[t-1]`` (one-step-ahead,
  the use when the drift is measured in process): ``x^_t = C0 + Cs.T_t + phi_1 (y_{t-1} - C0 - Cs.T_{t-1})``.
* :meth:`ARTemp.predict` has no measured targets, so it runs the seed's recursive form of (34) with
  ``x^`` in place of ``x`` (the seed itself writes ``x^_AR(t-1)``). Substituting shows that the
  residual estimate then obeys ``r^_t = phi_1 r^_{t-1}``, i.e. ``x^_t = C0 + Cs.T_t + phi_1^t r^_0``:
  the AR correction decays geometrically and the free-run forecast tends to the temperature
  regression. ``r^_0`` (the residual just before the first row) is 0 with
  ``initial_residual="zero"`` (default; a new run) or the last training residual with
  ``initial_residual="last"`` (the rows continue the training record).
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import check_choice, check_fit_data, check_predict_data
from learners.registry import register_learner

__all__ = ["ARTemp"]


@register_learner("ar-temp")
class ARTemp(RegressorMixin, BaseEstimator):
    """OLS on temperature plus a Yule-Walker AR(1) on the residual (seed 004 Eqs. 30-34).

    Parameters
    ----------
    initial_residual : {"zero", "last"}, default "zero"
        Residual r^_0 that seeds the recursion of :meth:`predict` (see module docstring).

    Attributes
    ----------
    intercept_ : float            C0, um
    coef_ : ndarray (n_features,) Cs, um/degC
    phi_ : float                  phi_1 (dimensionless, |phi_1| < 1)
    innovation_variance_ : float  sigma_a^2, um^2
    rss_regression_ : float       residual sum of squares after Eq. (30) (seed: 67.21)
    rss_ar_ : float               sum of a_t^2 after the AR(1), t = 2..n (seed: 61.56)
    last_residual_ : float        r_n, the final training residual
    arx_intercept_, arx_lag_coef_, arx_temp_coef_, arx_temp_lag_coef_ :
        the four groups of coefficients of Eq. (34): C0(1-phi), phi, Cs, -phi Cs.
    """

    def __init__(self, initial_residual="zero"):
        self.initial_residual = initial_residual

    time_ordered = True   # rows are one run's samples in time order (learners.runs)

    def _check_params(self):
        check_choice(self, "initial_residual", self.initial_residual, ("zero", "last"))

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``: the regression on all rows, the lag-1
        autocorrelation of the residuals over consecutive rows of the same run only;
        ``last_residual_`` is the last run's."""
        self._check_params()
        lengths = [len(np.asarray(y_).ravel()) for _, y_ in runs]
        if len(runs) == 1:
            X, y = runs[0]
        else:
            X = np.vstack([np.asarray(X_, dtype=float) for X_, _ in runs])
            y = np.concatenate([np.asarray(y_, dtype=float).ravel() for _, y_ in runs])
        X, y = check_fit_data(self, X, y, min_samples=3)
        A = np.column_stack([np.ones(len(y)), X])
        beta = np.linalg.lstsq(A, y, rcond=None)[0]
        r = y - A @ beta
        rc = r - r.mean()
        g0 = float(rc @ rc) / len(r)
        same_run = np.ones(len(r) - 1, dtype=bool)   # pair (t-1, t) within one run
        same_run[np.cumsum(lengths)[:-1] - 1] = False
        g1 = float(rc[1:][same_run] @ rc[:-1][same_run]) / len(r)
        phi = g1 / g0 if g0 > 1e-300 else 0.0
        self.intercept_ = float(beta[0])
        self.coef_ = beta[1:].copy()
        self.phi_ = float(phi)
        self.innovation_variance_ = float(g0 * (1.0 - phi ** 2))
        self.rss_regression_ = float(r @ r)
        innov = (r[1:] - phi * r[:-1])[same_run]
        self.rss_ar_ = float(innov @ innov)
        self.last_residual_ = float(r[-1])
        self.arx_intercept_ = self.intercept_ * (1.0 - phi)
        self.arx_lag_coef_ = self.phi_
        self.arx_temp_coef_ = self.coef_.copy()
        self.arx_temp_lag_coef_ = -phi * self.coef_
        return self

    def _r0(self):
        return self.last_residual_ if self.initial_residual == "last" else 0.0

    def predict(self, X):
        """Free-run forecast by the recursive Eq. (34): x^_t = C0 + Cs.T_t + phi^t r^_0 (um)."""
        X = check_predict_data(self, X, "phi_")
        steps = np.arange(1, X.shape[0] + 1)
        return self.intercept_ + X @ self.coef_ + self._r0() * self.phi_ ** steps

    def predict_one_step(self, X, y):
        """One-step-ahead forecast with measured targets: row t uses ``y[t-1]`` (never ``y[t]``).

        Row 0 uses r^_0 as in :meth:`predict`. Returns an array of len(X), um.
        """
        X = check_predict_data(self, X, "phi_")
        y = np.asarray(y, dtype=float).ravel()
        if y.shape[0] != X.shape[0]:
            raise ValueError("y must have one value per row of X")
        trend = self.intercept_ + X @ self.coef_
        prev_res = np.concatenate(([self._r0()], y[:-1] - trend[:-1]))
        return trend + self.phi_ * prev_res
