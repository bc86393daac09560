"""The input checks of the grey models and grey selectors (time-ordered runs): one table and
target, several runs with the same inputs, a prediction table of the fitted width. Each bad input
is one :class:`twin.errors.InputError` naming ``X``, ``y``, ``rows`` or ``runs``."""

from __future__ import annotations

import numpy as np

from learners._checks import check_fitted, holds_text, refuse_constant_target, refuse_huge
from twin.errors import InputError


def _numbers(values, model: str, name: str) -> np.ndarray:
    """``values`` as a float array copy, or an :class:`InputError` naming ``name`` (text, complex
    numbers: a grey model would drop the imaginary part)."""
    if np.iscomplexobj(values):
        raise InputError("data", name, f"{model} takes real numbers, got complex ones")
    if holds_text(values):
        raise InputError("data", name, f"{model} takes numbers, got text (numbers written as text are not read)")
    try:
        return np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError("data", name, f"{model} takes numbers, got {np.asarray(values).dtype} values") from None


def check_series(X, y=None, *, model: str, min_rows: int = 4, constant_ok: bool = False):
    """Validate time-ordered inputs: ``X`` -> float (n, p) copy, ``y`` -> float (n,) copy.

    Raises :class:`InputError` for non-finite values, mismatched lengths or fewer than ``min_rows``,
    ``ValueError`` for a constant ``y`` unless ``constant_ok``.
    """
    Xa = _numbers(X, model, "X")  # copies: never mutate caller data
    if Xa.ndim == 1:               # one row of p inputs or p rows of one? scikit-learn's rule: ask
        raise InputError("data", "X", f"{model} needs a 2-D (rows, inputs) table, got a 1-D one: X[:, None] for one "
                                      "input, X[None, :] for one row")
    if Xa.ndim != 2:
        raise InputError("data", "X", f"{model} needs a 2-D input array, got {Xa.ndim}-D")
    if Xa.shape[1] == 0:
        raise InputError("data", "X", f"{model} needs at least one input column, got none")
    if not np.all(np.isfinite(Xa)):
        raise InputError("data", "X", f"{model} inputs contain NaN or infinite values")
    refuse_huge(model, "X", Xa)
    if Xa.shape[0] < min_rows:
        raise InputError("data", "rows", f"{model} needs at least {min_rows} row{'s' if min_rows > 1 else ''}, "
                                         f"got {Xa.shape[0]}")
    if y is None:
        return Xa
    ya = _numbers(y, model, "y").ravel()
    if ya.shape[0] != Xa.shape[0]:
        raise InputError("data", "y", f"{model}: X has {Xa.shape[0]} rows but y has {ya.shape[0]}")
    if not np.all(np.isfinite(ya)):
        raise InputError("data", "y", f"{model} target contains NaN or infinite values")
    refuse_huge(model, "y", ya)
    if not constant_ok:
        refuse_constant_target(ya, model)
    return Xa, ya


def check_runs(runs, *, model: str, min_rows: int = 4) -> list:
    """Validate several runs ``[(X, y), ...]`` (each its own time-ordered sequence, see
    :mod:`learners.runs`): each by :func:`check_series` with at least ``min_rows`` rows, all with
    the same inputs; the target must vary over the runs together (one run may be constant, e.g.
    a machine left idle in a steady room). Returns ``[(Xa, ya), ...]``."""
    runs = list(runs)
    if not runs:
        raise InputError("data", "runs", f"{model} needs at least one run")
    if any(y is None for _, y in runs):
        raise InputError("data", "y", f"{model} needs the target y")
    checked = [check_series(X, y, model=model, min_rows=min_rows, constant_ok=len(runs) > 1) for X, y in runs]
    if any(Xa.shape[1] != checked[0][0].shape[1] for Xa, _ in checked):
        raise InputError("data", "X", f"{model}: the runs have different numbers of inputs")
    if len(checked) > 1:
        refuse_constant_target(np.concatenate([ya for _, ya in checked]), model)
    return checked


def check_n_features(est, X):
    """Raise ``NotFittedError`` before fit, :class:`InputError` if ``X`` has another column count."""
    check_fitted(est, "n_features_in_")
    if X.shape[1] != est.n_features_in_:
        raise InputError("data", "X", f"{type(est).__name__} was fitted with {est.n_features_in_} inputs, "
                                      f"got {X.shape[1]}")
