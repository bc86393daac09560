"""Grey models: AGO/IAGO, GM(0,N) influence coefficients, GM(1,1) and GM(1,N).

Notation (thesis §3.2-3.5, seed 000 L2471-3410): ``x^(0)`` is a raw, equally spaced, time-ordered
series; ``x^(1)(k) = sum_{j<=k} x^(0)(j)`` is its 1-AGO (3.11); 1-IAGO undoes it (3.12); the
background value is ``z^(1)(k) = 0.5 x^(1)(k-1) + 0.5 x^(1)(k)``, k = 2..n. ``x_1`` is the response
(thermal error, µm) and ``x_2..x_N`` the drivers (temperature rise ΔT from the start of the run,
°C, as the thesis uses "temperature changes", L4219).

**Rows are time.** Every grey estimator treats the rows of ``X`` (and ``y``) as consecutive,
equally spaced samples of one run that starts at row 0; shuffling rows changes the model.
``predict(X)`` treats ``X`` as a complete run from its own start (row 0 is sample k = 1). The
response at the start of that run is the hyper-parameter ``y0`` (``None``: the first training target,
which makes ``predict(X_train)`` the in-sample simulation).

The convolution model GMC(1,N) and its PSO calibration live in :mod:`learners.grey_gmc`.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, RegressorMixin
from sklearn.utils.validation import check_is_fitted

from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["ago", "iago", "background", "gm0n_coefficients", "gm11_fit", "gm11_forecast", "GM11", "GM1N"]


def ago(x, axis=0) -> np.ndarray:
    """1-AGO, Eq. (3.11): ``x^(1)(k) = sum_{j=1..k} x^(0)(j)`` along ``axis``."""
    return np.cumsum(np.asarray(x, dtype=float), axis=axis)


def iago(x1, axis=0) -> np.ndarray:
    """1-IAGO, Eq. (3.12): ``x^(0)(1) = x^(1)(1)``, ``x^(0)(k) = x^(1)(k) - x^(1)(k-1)``."""
    x1 = np.asarray(x1, dtype=float)
    return np.diff(x1, axis=axis, prepend=np.zeros_like(np.take(x1, [0], axis=axis)))


def background(x1, axis=0) -> np.ndarray:
    """Background values ``z^(1)(k) = 0.5 (x^(1)(k-1) + x^(1)(k))`` for k = 2..n (length n-1)."""
    x1 = np.moveaxis(np.asarray(x1, dtype=float), axis, 0)
    return np.moveaxis(0.5 * (x1[1:] + x1[:-1]), 0, axis)


def check_series(X, y=None, *, model: str, min_rows: int = 4):
    """Validate time-ordered inputs: ``X`` -> float (n, p) copy, ``y`` -> float (n,) copy.

    Raises :class:`InputError` for non-finite values, mismatched lengths or fewer than ``min_rows``.
    """
    Xa = np.array(X, dtype=float)  # copies: never mutate caller data
    if Xa.ndim == 1:
        Xa = Xa[:, None]
    if Xa.ndim != 2:
        raise InputError("data", "X", f"{model} needs a 2-D input array, got {Xa.ndim}-D")
    if not np.all(np.isfinite(Xa)):
        raise InputError("data", "X", f"{model} inputs contain NaN or infinite values")
    if Xa.shape[0] < min_rows:
        raise InputError("data", "rows", f"{model} needs at least {min_rows} rows, got {Xa.shape[0]}")
    if y is None:
        return Xa
    ya = np.array(y, dtype=float).ravel()
    if ya.shape[0] != Xa.shape[0]:
        raise InputError("data", "y", f"{model}: X has {Xa.shape[0]} rows but y has {ya.shape[0]}")
    if not np.all(np.isfinite(ya)):
        raise InputError("data", "y", f"{model} target contains NaN or infinite values")
    return Xa, ya


def check_n_features(est, X):
    """Raise ``NotFittedError`` before fit, :class:`InputError` if ``X`` has another column count."""
    check_is_fitted(est, "n_features_in_")
    if X.shape[1] != est.n_features_in_:
        raise InputError("data", "X", f"{type(est).__name__} was fitted with {est.n_features_in_} inputs, "
                                      f"got {X.shape[1]}")


def gm0n_coefficients(X, y, alpha=0.0) -> np.ndarray:
    """GM(0,N) influence coefficients ``theta_j = b_j / a_1`` (thesis Eqs. (3.21)-(3.25), L2902-3171).

    Solves ``z_1^(1)(k) = sum_j theta_j x_j^(1)(k)``, k = 2..n, by least squares,
    ``theta = (B^T B)^-1 B^T Y`` with ``Y = [z_1^(1)(2) .. z_1^(1)(n)]`` and B rows
    ``[x_2^(1)(k) .. x_N^(1)(k)]``. Collinear sensors make ``B^T B`` singular (neighbouring
    thermography spots); ``numpy.linalg.lstsq`` gives the minimum-norm solution then.
    ``alpha > 0`` adds a ridge term ``alpha * mean(diag(B^T B)) * I`` to ``B^T B`` (not in the thesis;
    the notes advise it for collinear sensors). The influence ranking is ``|theta_j|`` (larger =
    more influential). Returns shape (p,).
    """
    Xa, ya = check_series(X, y, model="GM(0,N)", min_rows=3)
    z1 = background(ago(ya))
    B = ago(Xa)[1:]
    if alpha > 0.0:
        gram = B.T @ B
        lam = float(alpha) * np.trace(gram) / gram.shape[0]
        return np.linalg.solve(gram + lam * np.eye(gram.shape[0]), B.T @ z1)
    theta, *_ = np.linalg.lstsq(B, z1, rcond=None)
    return theta


# ----------------------------------------------------------------------------------------------
# GM(1,1)
# ----------------------------------------------------------------------------------------------


def gm11_fit(series) -> tuple[float, float]:
    """Least-squares ``(a, b)`` of GM(1,1): ``x^(0)(k) + a z^(1)(k) = b``, k = 2..n.

    ``B = [[-z^(1)(k), 1]]``, ``Y = [x^(0)(k)]`` (seed 004 §III.B, standard form; seed 000 §3.2).
    For a geometric series ``c r^(k-1)`` this is exact: ``a = 2(1-r)/(1+r)``, ``b = 2c/(1+r)``.
    """
    x0 = np.asarray(series, dtype=float).ravel()
    if x0.size < 4:
        raise InputError("data", "rows", f"GM(1,1) needs at least 4 samples, got {x0.size}")
    if not np.all(np.isfinite(x0)):
        raise InputError("data", "y", "GM(1,1) series contains NaN or infinite values")
    z = background(ago(x0))
    B = np.column_stack([-z, np.ones_like(z)])
    (a, b), *_ = np.linalg.lstsq(B, x0[1:], rcond=None)
    return float(a), float(b)


def _gm11_response(a: float, b: float, x1_first: float, k) -> np.ndarray:
    """Whitened time response (seed 004 Eq. (25)) ``x^(1)(k) = (x(1) - b/a) e^{-a(k-1)} + b/a``."""
    k = np.asarray(k, dtype=float)
    if abs(a) < 1e-12:  # a -> 0 limit: dx/dt = b, a straight line
        return x1_first + b * (k - 1.0)
    return (x1_first - b / a) * np.exp(-a * (k - 1.0)) + b / a


def gm11_simulate(a: float, b: float, first: float, n: int) -> np.ndarray:
    """Raw-series values ``x^(0)(1..n)`` of GM(1,1) by IAGO of the whitened response.

    Uses the difference of Eq. (25) at k and k-1 (seed 004's printed Eq. (26) has the factor
    ``1 - e^{-a}`` instead of ``1 - e^{a}``; the notes flag it, the difference is used here).
    """
    x1 = _gm11_response(a, b, first, np.arange(1, n + 1))
    return iago(x1)


def gm11_forecast(series, steps: int) -> np.ndarray:
    """Fit GM(1,1) on ``series`` (1-D, time-ordered) and return the next ``steps`` values."""
    x0 = np.asarray(series, dtype=float).ravel()
    a, b = gm11_fit(x0)
    steps = int(steps)
    if steps < 0:
        raise ValueError("steps must be >= 0")
    return gm11_simulate(a, b, x0[0], x0.size + steps)[x0.size:]


@register_learner("gm11")
class GM11(BaseEstimator, RegressorMixin):
    """GM(1,1) single-series grey forecaster, ``dx^(1)/dt + a x^(1) = b`` (seed 004 Eqs. (23)-(26)).

    What X means: GM(1,1) is a pure time-series model. ``fit(X, y)`` fits ``y`` (raw series,
    e.g. thermal error in µm, equally spaced in time); ``X`` only fixes the number of rows.
    ``predict(X)`` returns ``x^(0)(k)`` for k = 1..len(X) of a run that starts with value ``y0``
    (``None``: the first training value); the values in ``X`` are not used. Rows beyond the
    training length are forecasts. Use :meth:`forecast` (or :func:`gm11_forecast`) for the next
    steps after the training series.

    Fitted: ``a_`` (development coefficient, 1/sample), ``b_`` (grey input, series units),
    ``y0_``, ``n_train_``, ``n_features_in_``.
    """

    def __init__(self, y0=None):
        self.y0 = y0

    def fit(self, X, y):
        Xa, ya = check_series(X, y, model="GM(1,1)")
        self.a_, self.b_ = gm11_fit(ya)
        self.y0_ = float(ya[0]) if self.y0 is None else float(self.y0)
        self.first_train_ = float(ya[0])
        self.n_train_ = ya.size
        self.n_features_in_ = Xa.shape[1]
        return self

    def predict(self, X):
        check_is_fitted(self, "a_")
        Xa = check_series(X, model="GM(1,1)", min_rows=1)
        return gm11_simulate(self.a_, self.b_, self.y0_, Xa.shape[0])

    def forecast(self, steps: int) -> np.ndarray:
        """Values for the ``steps`` samples after the training series."""
        full = gm11_simulate(self.a_, self.b_, self.first_train_, self.n_train_ + int(steps))
        return full[self.n_train_:]


# ----------------------------------------------------------------------------------------------
# GM(1,N)
# ----------------------------------------------------------------------------------------------


@register_learner("gm1n")
class GM1N(BaseEstimator, RegressorMixin):
    """GM(1,N): ``x_1^(0)(k) + a z_1^(1)(k) = sum_{j=2..N} b_j x_j^(1)(k)`` (thesis (3.27)-(3.30)).

    Least squares ``[a, b_2..b_N] = (B^T B)^-1 B^T Y`` with ``Y = [x_1^(0)(2) .. x_1^(0)(n)]`` and
    B rows ``[-z_1^(1)(k), x_2^(1)(k), .., x_N^(1)(k)]``. The thesis prints ``+z_1^(1)`` in B (only
    the sign of ``a`` flips) and ``x_1^(1)`` in the second column (a typo for ``x_2^(1)``); the
    standard Deng/Liu form is used here.

    ``X``: (n, N-1) driver series (ΔT, °C), rows time-ordered; ``y``: response x_1^(0) (µm).

    Prediction (``response``):
      - ``"difference"`` (default): solve the grey equation itself step by step,
        ``x_1^(1)(k) = [(1 - a/2) x_1^(1)(k-1) + sum_j b_j x_j^(1)(k)] / (1 + a/2)``, then IAGO. This
        reproduces data generated by the model's own equation exactly.
      - ``"whitened"``: the classical approximate time response
        ``x_1^(1)(k) = (x_1^(0)(1) - S(k)/a) e^{-a(k-1)} + S(k)/a``, ``S(k) = sum_j b_j x_j^(1)(k)``.

    Fitted: ``a_``, ``b_`` (N-1,), ``coef_`` = ``b_`` (influence ranking, thesis L3400), ``y0_``.
    """

    def __init__(self, response="difference", y0=None):
        self.response = response
        self.y0 = y0

    def fit(self, X, y):
        Xa, ya = check_series(X, y, model="GM(1,N)")
        if self.response not in ("difference", "whitened"):
            raise InputError("parameters", "response", f"unknown GM(1,N) response {self.response!r}; "
                                                       "use 'difference' or 'whitened'")
        n, p = Xa.shape
        if n < p + 2:
            raise InputError("data", "rows", f"GM(1,N) with {p} inputs needs at least {p + 2} rows, got {n}")
        z1 = background(ago(ya))
        B = np.column_stack([-z1, ago(Xa)[1:]])
        theta, *_ = np.linalg.lstsq(B, ya[1:], rcond=None)
        self.a_ = float(theta[0])
        self.b_ = theta[1:].copy()
        self.coef_ = self.b_
        self.y0_ = float(ya[0]) if self.y0 is None else float(self.y0)
        self.n_features_in_ = p
        return self

    def predict(self, X):
        Xa = check_series(X, model="GM(1,N)", min_rows=1)
        check_n_features(self, Xa)
        drive = ago(Xa) @ self.b_
        a = self.a_
        if self.response == "whitened":
            k = np.arange(Xa.shape[0], dtype=float)
            if abs(a) < 1e-12:
                raise InputError("model", "a", "GM(1,N) whitened response needs a != 0")
            x1 = (self.y0_ - drive / a) * np.exp(-a * k) + drive / a  # equals y0 at k = 0
        elif self.response == "difference":
            x1 = np.empty(Xa.shape[0])
            x1[0] = self.y0_
            lead, lag = 1.0 + 0.5 * a, 1.0 - 0.5 * a
            for k in range(1, x1.size):
                x1[k] = (lag * x1[k - 1] + drive[k]) / lead
        else:
            raise InputError("parameters", "response", f"unknown GM(1,N) response {self.response!r}; "
                                                       "use 'difference' or 'whitened'")
        return iago(x1)
