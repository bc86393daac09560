"""Small input checks shared by the learners and selectors of this package (private).

They wrap scikit-learn's ``check_X_y`` / ``check_array`` (available in every supported version)
and record ``n_features_in_`` so that ``predict`` can refuse a table with a different width.
"""

from __future__ import annotations

import numpy as np
from sklearn.utils.validation import check_array, check_is_fitted, check_X_y


def check_fit_data(estimator, X, y, *, min_samples: int = 2):
    """Validate training data: return ``(X, y)`` as float arrays (2-D, 1-D), never views to mutate.

    Sets ``estimator.n_features_in_``. Raises ``ValueError`` for NaN/inf, ragged shapes, fewer
    than ``min_samples`` rows or a constant target.
    """
    X, y = check_X_y(X, y, dtype=float, y_numeric=True, ensure_min_samples=min_samples)
    estimator.n_features_in_ = X.shape[1]
    y = np.asarray(y, dtype=float).ravel()
    refuse_constant_target(y, type(estimator).__name__)
    return X, y


def is_constant(values) -> bool:
    """Whether ``values`` hardly vary: range <= 1e-12 x max(1, max |value|)."""
    v = np.asarray(values, dtype=float)
    return bool(v.size == 0 or np.ptp(v) <= 1e-12 * max(1.0, float(np.max(np.abs(v)))))


def refuse_constant_target(y, model: str) -> None:
    """Raise ``ValueError`` for a constant target: there is nothing to learn, and every score
    relative to the target's spread (NSE, R) would be undefined."""
    if is_constant(y):
        raise ValueError(f"{model}: the target is constant ({float(np.asarray(y).ravel()[0]):g}); there is nothing "
                         "to learn")


def check_predict_data(estimator, X, fitted_attribute: str):
    """Validate prediction inputs against a fitted estimator; return a float 2-D array."""
    check_is_fitted(estimator, fitted_attribute)
    X = check_array(X, dtype=float)
    if X.shape[1] != estimator.n_features_in_:
        raise ValueError(f"X has {X.shape[1]} features, but {type(estimator).__name__} "
                         f"is expecting {estimator.n_features_in_} features as input")
    return X


def column_names(X, n_columns: int) -> list[str]:
    """Column names of a table-like ``X`` (``X.columns`` when present, else ``x0, x1, ...``)."""
    cols = getattr(X, "columns", None)
    if cols is not None and len(cols) == n_columns:
        return [str(c) for c in cols]
    return [f"x{j}" for j in range(n_columns)]


def standardise(X, mean=None, scale=None):
    """z-score ``X`` column-wise (sample sd, ddof=1); constant columns get scale 1.

    Returns ``(Z, mean, scale)``; pass ``mean``/``scale`` to reuse a fitted transform.
    """
    X = np.asarray(X, dtype=float)
    if mean is None:
        mean = X.mean(axis=0)
        scale = X.std(axis=0, ddof=1) if X.shape[0] > 1 else np.ones(X.shape[1:])
        scale = np.where(scale > 1e-12 * np.maximum(1.0, np.abs(mean)), scale, 1.0)
    return (X - mean) / scale, mean, scale
