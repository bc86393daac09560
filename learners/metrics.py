"""Validation metrics of the thermal-error literature.

``Z`` is the measured thermal error (µm), ``P`` the prediction (µm), residual ``e = Z - P``.

- ``rmse``: sqrt(sum (Z-P)^2 / n)                          thesis Eq. (3.31), seed 001 Eq. (11)
- ``nse``: 1 - sum (Z-P)^2 / sum (Z - mean Z)^2              thesis Eq. (3.32), seed 001 Eq. (12)
- ``correlation``: Pearson R between Z and P                 thesis §3.8 (L3483-3584)
- ``max_abs_residual``: max |Z - P|, the "±x µm residual" of the tables
- ``improvement``: 100 * (1 - max|Z-P| / max|Z|) in %. The thesis quotes "% improvement" without a
  formula; this reading reproduces its numbers (±4 µm against 64 µm gives 93.75 %, "up to 94 %").
- ``mean_relative_error``: 100 * (1/n) sum |a_i / r_i| in %, a = P - Z, r = Z (seed 002 Eq. (13),
  L355-L365). Samples with Z exactly 0 are left out (the ratio is undefined there); the seed's
  definition blows up near zero drift, so use it only on windows where the drift is large.

All functions take 1-D array-likes of equal length and return a float; :func:`score_all` refuses
non-finite values (``InputError``) rather than scoring them as NaN.
"""

from __future__ import annotations

import numpy as np

from learners._checks import refuse_huge
from twin.errors import InputError

__all__ = ["rms", "rmse", "nse", "correlation", "max_abs_residual", "abs_residual_percentile", "improvement", "mean_relative_error", "score_all"]


def _pair(y_true, y_pred):
    try:
        z = np.asarray(y_true, dtype=float).ravel()
        p = np.asarray(y_pred, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InputError("data", "y_true, y_pred", "expected numbers (measured values and predictions)") from None
    if z.shape != p.shape:
        raise InputError("data", "rows", f"measured and predicted differ in length: {z.size} vs {p.size}")
    if z.size == 0:
        raise InputError("data", "rows", "metrics need at least one sample")
    return z, p


def rms(residual, axis=None):
    """Root mean square sqrt(mean r^2) of residuals, over ``axis`` (None: all of them). The one
    implementation behind every RMSE of the package (per channel: ``axis=0``)."""
    r = np.asarray(residual, dtype=float)
    return np.sqrt(np.mean(r * r, axis=axis))


def rmse(y_true, y_pred) -> float:
    """Root-mean-square error, Eq. (3.31) (units of the data, µm)."""
    z, p = _pair(y_true, y_pred)
    return float(rms(z - p))


def nse(y_true, y_pred) -> float:
    """Nash-Sutcliffe efficiency, Eq. (3.32); 1 is perfect, range (-inf, 1]. NaN for constant Z."""
    z, p = _pair(y_true, y_pred)
    den = float(np.sum((z - z.mean()) ** 2))
    if den == 0.0:
        return float("nan")
    return float(1.0 - np.sum((z - p) ** 2) / den)


def correlation(y_true, y_pred) -> float:
    """Pearson correlation coefficient R; NaN if either series is constant."""
    z, p = _pair(y_true, y_pred)
    dz, dp = z - z.mean(), p - p.mean()
    den = float(np.sqrt(np.sum(dz * dz) * np.sum(dp * dp)))
    if den == 0.0:
        return float("nan")
    return float(np.sum(dz * dp) / den)


def max_abs_residual(y_true, y_pred) -> float:
    """Largest absolute residual max|Z - P| (the "±x µm" of the thesis tables)."""
    z, p = _pair(y_true, y_pred)
    return float(np.max(np.abs(z - p)))


def abs_residual_percentile(y_true, y_pred, q: float = 95.0) -> float:
    """The ``q``-th percentile of |Z - P| (linear interpolation; units of the data, µm): a
    residual bound that one outlier does not set, beside :func:`max_abs_residual`."""
    z, p = _pair(y_true, y_pred)
    return float(np.percentile(np.abs(z - p), q))


def improvement(y_true, y_pred) -> float:
    """Compensation improvement in %: 100 * (1 - max|Z - P| / max|Z|); NaN if Z is all zero."""
    z, p = _pair(y_true, y_pred)
    worst = float(np.max(np.abs(z)))
    if worst == 0.0:
        return float("nan")
    return float(100.0 * (1.0 - np.max(np.abs(z - p)) / worst))


def mean_relative_error(y_true, y_pred) -> float:
    """Mean relative error in %, seed 002 Eq. (13): 100/n * sum |(P_i - Z_i) / Z_i| over Z_i != 0."""
    z, p = _pair(y_true, y_pred)
    keep = z != 0.0
    if not keep.any():
        return float("nan")
    return float(100.0 * np.mean(np.abs((p[keep] - z[keep]) / z[keep])))


def _refuse_non_finite(values: np.ndarray, field: str, what: str) -> None:
    bad = ~np.isfinite(values)
    if bad.any():
        raise InputError("data", field, f"{int(bad.sum())} of the {values.size} {what} are not finite (NaN or inf; "
                                        f"the first at index {int(np.argmax(bad))}); scores of them would be NaN")


def score_all(y_true, y_pred) -> dict:
    """All metrics: keys ``rmse, nse, r, max_abs_residual, improvement_pct, mre_pct``.

    A NaN or infinite measured value (``y_true``) or prediction (``y_pred``) is an
    :class:`InputError` naming which, never a table of NaN scores. (NSE and R of a constant
    target, R of a constant prediction stay NaN: undefined, see :func:`nse`, :func:`correlation`.)"""
    z, p = _pair(y_true, y_pred)
    _refuse_non_finite(z, "y_true", "measured values")
    _refuse_non_finite(p, "y_pred", "predictions")
    refuse_huge("data", "y_true", z)      # squares beyond 1e24 would overflow or lose every digit
    refuse_huge("data", "y_pred", p)
    return {
        "rmse": rmse(y_true, y_pred),
        "nse": nse(y_true, y_pred),
        "r": correlation(y_true, y_pred),
        "max_abs_residual": max_abs_residual(y_true, y_pred),
        "improvement_pct": improvement(y_true, y_pred),
        "mre_pct": mean_relative_error(y_true, y_pred),
    }
