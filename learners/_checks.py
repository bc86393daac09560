"""Small input checks shared by the learners and selectors of this package (private).

They wrap scikit-learn's ``check_X_y`` / ``check_array`` (available in every supported version)
and record ``n_features_in_`` so that ``predict`` can refuse a table with a different width.
"""

from __future__ import annotations

import numpy as np
from sklearn.utils.validation import check_array, check_is_fitted, check_X_y

from twin.errors import InputError
from twin.limits import is_number, is_whole


def check_fit_data(estimator, X, y, *, min_samples: int = 2):
    """Validate training data: return ``(X, y)`` as float arrays (2-D, 1-D), never views to mutate.

    Sets ``estimator.n_features_in_``. Raises :class:`twin.errors.InputError` (a ``ValueError``,
    as scikit-learn's contract asks) naming the learner and ``X`` or ``y`` for NaN/inf, ragged
    shapes, fewer than ``min_samples`` rows or a constant target.
    """
    X = _checked(check_array, estimator, "X", X, dtype=float, ensure_min_samples=min_samples)
    _refuse_text(estimator, "y", y)
    try:
        X, y = check_X_y(X, y, dtype=float, y_numeric=True, ensure_min_samples=min_samples)
        y = np.asarray(y, dtype=float).ravel()
    except (ValueError, TypeError) as err:     # X passed on its own: what is wrong is y, or y against X
        raise InputError(model_name(estimator), "y", str(err)) from None
    refuse_huge(estimator, "X", X)
    refuse_huge(estimator, "y", y)
    check_seed(estimator, getattr(estimator, "random_state", None))
    estimator.n_features_in_ = X.shape[1]
    refuse_constant_target(y, estimator)
    return X, y


def check_seed(model, value):
    """A learner's ``random_state``: None (fresh entropy) or a whole number from 0 to 2^32 - 1
    (:func:`twin.limits.seed_value`; not a bool, a float or a text), else an :class:`InputError`
    naming the learner and ``random_state``. Returns it."""
    if value is None:
        return None
    from twin.limits import seed_value
    return seed_value(value, model_name(model), "random_state")


VALUE_LIMIT = 1e12      # |value| a learner takes: any unit of a measured temperature or error stays far below


def refuse_huge(estimator, name: str, values) -> None:
    """An :class:`InputError` naming the learner and ``name`` for values beyond +-:data:`VALUE_LIMIT`:
    no unit of a machine's temperatures or errors reaches them, and their squares and products
    overflow or lose every digit inside the fits (NaN predictions, infinite scores)."""
    worst = float(np.max(np.abs(values))) if np.size(values) else 0.0
    if worst > VALUE_LIMIT:
        raise InputError(model_name(estimator), name, f"holds values up to {worst:.3g}, beyond +-{VALUE_LIMIT:g}: not a "
                                                      "measured temperature or error in any unit; rescale it")


def check_table(estimator, X):
    """``X`` as a finite 2-D float array within +-:data:`VALUE_LIMIT` (scikit-learn's
    ``check_array``), or an :class:`InputError` naming the learner and ``X``."""
    X = _checked(check_array, estimator, "X", X, dtype=float)
    refuse_huge(estimator, "X", X)
    return X


def holds_text(values) -> bool:
    """Whether ``values`` (an array, a list of rows) holds text: numpy would read '20.5' as 20.5,
    and a table of text read as numbers is a table the user did not mean to give."""
    try:
        a = np.asarray(values)
    except (TypeError, ValueError):
        return False
    return a.dtype.kind in "US" or (a.dtype.kind == "O" and any(isinstance(v, (str, bytes)) for v in a.ravel()))


def _refuse_text(estimator, name: str, values) -> None:
    if holds_text(values):
        raise InputError(model_name(estimator), name, "holds text; give numbers (numbers written as text are not "
                                                      "read)")


def _checked(check, estimator, name: str, values, **kw):
    """``check(values, **kw)`` (a scikit-learn validation), its ``ValueError`` raised again as an
    :class:`InputError` naming the learner and the argument ``name``."""
    _refuse_text(estimator, name, values)
    try:
        return check(values, **kw)
    except (ValueError, TypeError) as err:
        raise InputError(model_name(estimator), name, str(err)) from None


def refuse_constant_columns(model, X) -> None:
    """A sensor selector's inputs each vary: a constant column carries nothing to select by (its
    correlations and grey relations are undefined), so an :class:`InputError` names it."""
    X = np.asarray(X, dtype=float)
    flat = [j for j in range(X.shape[1]) if is_constant(X[:, j])]
    if flat:
        raise InputError(model_name(model), "X", f"column {flat[0]} is constant: a sensor that does not vary carries "
                                                 "nothing to select by; leave it out")


def is_constant(values) -> bool:
    """Whether ``values`` hardly vary: range <= 1e-12 x max(1, max |value|)."""
    v = np.asarray(values, dtype=float)
    return bool(v.size == 0 or np.ptp(v) <= 1e-12 * max(1.0, float(np.max(np.abs(v)))))


def refuse_constant_target(y, model) -> None:
    """Raise :class:`InputError` (naming ``model`` and ``y``) for a constant target: there is
    nothing to learn, and every score relative to the target's spread (NSE, R) would be undefined."""
    if is_constant(y):
        raise InputError(model_name(model), "y", f"the target is constant ({float(np.asarray(y).ravel()[0]):g}); "
                                                 "there is nothing to learn")


def check_fitted(estimator, attribute: str) -> None:
    """scikit-learn's ``check_is_fitted``, its NotFittedError raised as an :class:`InputError`
    naming the learner (or selector)."""
    try:
        check_is_fitted(estimator, attribute)
    except ValueError:          # NotFittedError
        raise InputError(model_name(estimator), "X", "not fitted: call fit(X, y) first") from None


def check_predict_data(estimator, X, fitted_attribute: str):
    """Validate prediction inputs against a fitted estimator; return a float 2-D array (an
    :class:`InputError` naming the learner and ``X`` when it is not one of the fitted width)."""
    check_fitted(estimator, fitted_attribute)
    X = check_table(estimator, X)
    if X.shape[1] != estimator.n_features_in_:
        raise InputError(model_name(estimator), "X", f"X has {X.shape[1]} features, but {type(estimator).__name__} "
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


# ------------------------------------------------------------------------------------------------
# Hyper-parameter checks. Each raises :class:`twin.errors.InputError` ``(model, name, message)``
# naming the learner (its registry name) and the parameter, and returns the value as a plain
# Python number. Learners store their parameters unchanged (scikit-learn's get_params/set_params/
# clone contract) and call these at the start of ``fit`` through ``_check_params``;
# :func:`learners.registry.make_learner` calls ``_check_params`` too, so a bad value given by name
# fails when the learner is built.
# ------------------------------------------------------------------------------------------------


def model_name(model) -> str:
    """The name errors give a learner or selector: its registry name, else its class name (a
    string is used as it is)."""
    if isinstance(model, str):
        return model
    return getattr(model, "registry_name", None) or type(model).__name__


def _refuse(model, name: str, message: str):
    raise InputError(model_name(model), name, message)


# the most training work a hyper-parameter may ask for: 100 to 1000 times the seeds' settings (50
# epochs, 90 particles, 100 PSO iterations), hours on a laptop; beyond them a typo (1e9) would run
# for days or ask for terabytes
MAX_EPOCHS = 100_000
MAX_PARTICLES = 10_000
MAX_ITERATIONS = 100_000


def check_int(model, name: str, value, minimum: int = 1, maximum: int | None = None) -> int:
    """``value`` as an ``int`` if it is an integer (``int`` or numpy integer, not a bool) from
    ``minimum`` to ``maximum`` (None: no upper limit); an :class:`InputError` otherwise."""
    if not is_whole(value):
        _refuse(model, name, f"must be an integer >= {minimum}, got {value!r}")
    v = int(value)
    if v < minimum or (maximum is not None and v > maximum):
        bounds = f"from {minimum} to {maximum}" if maximum is not None else f">= {minimum}"
        _refuse(model, name, f"must be an integer {bounds}, got {v}")
    return v


def check_float(model, name: str, value, minimum: float | None = None, maximum: float | None = None, *,
                above: bool = False, below: bool = False) -> float:
    """``value`` as a ``float`` if it is a finite real number (not a bool) with ``minimum <= value
    <= maximum``; ``above``/``below`` make the bounds strict (``value > minimum``, ``value <
    maximum``). An :class:`InputError` otherwise (NaN and inf included)."""
    if not is_number(value):
        _refuse(model, name, f"must be a finite number, got {value!r}")
    v = float(value)
    low = "" if minimum is None else f"{'>' if above else '>='} {minimum:g}"
    high = "" if maximum is None else f"{'<' if below else '<='} {maximum:g}"
    want = " and ".join(b for b in (low, high) if b)
    want = f"a finite number {want}" if want else "a finite number"
    if not np.isfinite(v) or (minimum is not None and (v <= minimum if above else v < minimum)) \
            or (maximum is not None and (v >= maximum if below else v > maximum)):
        _refuse(model, name, f"must be {want}, got {value!r}")
    return v


def check_positive(model, name: str, value) -> float:
    """A finite number > 0 (:func:`check_float`)."""
    return check_float(model, name, value, 0.0, above=True)


def check_non_negative(model, name: str, value) -> float:
    """A finite number >= 0 (:func:`check_float`)."""
    return check_float(model, name, value, 0.0)


def check_fraction(model, name: str, value, *, zero: bool = True, maximum: float = 1.0) -> float:
    """A fraction in ``[0, maximum)`` (``zero=False``: ``(0, maximum)``), by :func:`check_float`."""
    return check_float(model, name, value, 0.0, maximum, above=not zero, below=True)


def check_choice(model, name: str, value, choices) -> str:
    """``value`` if it is one of ``choices``; an :class:`InputError` listing them otherwise."""
    if not isinstance(value, str) or value not in choices:
        _refuse(model, name, f"unknown {name} {value!r}; known: {', '.join(map(str, choices))}")
    return value


def check_bool(model, name: str, value) -> bool:
    """``value`` if it is a bool (True/False); an :class:`InputError` otherwise."""
    if not isinstance(value, (bool, np.bool_)):
        _refuse(model, name, f"must be True or False, got {value!r}")
    return bool(value)


def check_start_value(model, value, name: str = "y0"):
    """A grey model's start value: ``None`` (the first training target) or a finite number."""
    return None if value is None else check_float(model, name, value)


def check_sizes(model, name: str, value) -> tuple[int, ...]:
    """Hidden-layer sizes: a non-empty sequence of integers >= 1."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        _refuse(model, name, f"must be a sequence of layer sizes (integers >= 1), got {value!r}")
    sizes = tuple(value)
    if not sizes:
        _refuse(model, name, "names no layer; give one or more sizes (integers >= 1)")
    for h in sizes:
        if not is_whole(h) or h < 1:
            _refuse(model, name, f"every layer size must be an integer >= 1, got {value!r}")
    return tuple(int(h) for h in sizes)


def check_count_fits(model, name: str, count: int, n_features: int, what: str = "input columns") -> int:
    """Refuse a count (components, sensors to select) larger than the ``n_features`` there are."""
    if count > n_features:
        _refuse(model, name, f"asks for {count}, but the data have only {n_features} {what}")
    return count
