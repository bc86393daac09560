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

**Long, densely sampled records.** The classical least-squares fit of GM(1,N)/GMC(1,N)
(``fit_method="equation"``) minimises the residual of the grey *equation* one step at a time,
with the accumulated (AGO) series as regressors. Their magnitude grows with the record length, so on
a long record (e.g. 1141 samples at 10 s) any development coefficient of order one leaves residuals
of accumulated size and the fit drives ``a`` towards 0, where its sign is set by noise; a negative
``a`` of -0.05 per sample then grows the simulated response by ``e^{0.05 * 1140} ~ 1e24``. The
seeds fit grey models on a handful of samples (the thesis's GNNMCI: the first 5 readings; its
LS-based GMC(1,N) has b_1 = 1.75 per sample, Table 6-3), where this does not arise. The default
``fit_method="response"`` therefore fits what ``predict`` computes: least squares of the simulated
response against the data (the fitness (3.17) that the thesis's PSO minimises) by variable
projection: for a fixed development coefficient the response is linear in the driving
coefficients (and ``u``), so those are exact linear least squares, and a 1-D search over ``a > 0``
(a stable, dissipative response: a log grid of 49 values refined by bounded Brent between the best
one's neighbours) picks the development coefficient: the global minimum to the grid's resolution,
not proven beyond it (a minimum narrower than a grid step could be missed). The equation fit is
still available; it refuses (``InputError``) a fitted model whose response would grow by more than
a factor ``1e3`` over the record, instead of returning numbers of order 1e26.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter
from sklearn.base import BaseEstimator, RegressorMixin

from learners._checks import check_choice, check_fitted, check_int, check_start_value
from learners.grey_checks import check_n_features, check_runs, check_series  # noqa: F401 (re-exported)
from learners.registry import register_learner
from twin.errors import InputError

__all__ = ["ago", "iago", "background", "gm0n_coefficients", "gm0n_coefficients_runs", "gm11_fit", "gm11_fit_runs",
           "gm11_forecast", "response_ls_fit", "check_growth", "check_runs", "refuse_divergence", "gm1n_simulate",
           "GM11", "GM1N"]

FIT_METHODS = ("response", "equation")
MAX_GROWTH = 1e3  # largest growth of a fitted grey response over a record before fit/predict refuse it


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
    return gm0n_coefficients_runs([(X, y)], alpha)


def gm0n_coefficients_runs(runs, alpha=0.0) -> np.ndarray:
    """GM(0,N) influence coefficients from several runs ``[(X, y), ...]``: each run accumulated from
    its own start, the rows ``z_1^(1)(k) = sum_j theta_j x_j^(1)(k)`` (k = 2..n of each run) stacked
    (:func:`gm0n_coefficients` for one run)."""
    checked = [check_series(X, y, model="GM(0,N)", min_rows=3, constant_ok=len(runs) > 1) for X, y in runs]
    z1 = np.concatenate([background(ago(ya)) for _, ya in checked])
    B = np.vstack([ago(Xa)[1:] for Xa, _ in checked])
    if alpha > 0.0:
        gram = B.T @ B
        lam = float(alpha) * np.trace(gram) / gram.shape[0]
        return np.linalg.solve(gram + lam * np.eye(gram.shape[0]), B.T @ z1)
    theta, *_ = np.linalg.lstsq(B, z1, rcond=None)
    return theta


A_MIN = 1e-6   # the response fit's smallest development coefficient per sample (a stable response)


def response_ls_fit(simulate, y, n_coef: int, a_max: float, a_min: float = A_MIN, n_grid: int = 49, start=None):
    """Least squares of a simulated grey response, by variable projection over the development coefficient.

    ``simulate(a, coef, y0)`` returns the predicted raw series (length n) and must be affine in
    ``(coef, y0)`` for fixed ``a`` (true of every grey response here). For each ``a`` the
    coefficients solve the linear least-squares problem ``min ||r0 + A coef - y||`` with
    ``r0 = simulate(a, 0, y[0])`` and ``A[:, j] = simulate(a, e_j, 0)``; the SSE is then minimised
    over ``log a`` in ``[log a_min, log a_max]``: a log-spaced grid of ``n_grid`` values, refined by
    bounded Brent between the neighbours of the best grid point. Returns ``(a, coef, sse)``.
    ``start``: the initial value(s) given to ``simulate`` for ``r0`` (default ``y[0]``; an array
    of each run's first value when ``y`` holds several runs).
    """
    from scipy.optimize import minimize_scalar

    y = np.asarray(y, dtype=float)
    eye = np.eye(n_coef)

    def solve(log_a):
        a = float(np.exp(log_a))
        with np.errstate(over="ignore", invalid="ignore"):
            r0 = simulate(a, np.zeros(n_coef), y[0] if start is None else start)
            A = np.column_stack([simulate(a, e, 0.0) for e in eye])
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(r0))):
            return a, np.zeros(n_coef), np.inf
        coef, *_ = np.linalg.lstsq(A, y - r0, rcond=None)
        return a, coef, float(np.sum((r0 + A @ coef - y) ** 2))

    grid = np.linspace(np.log(a_min), np.log(a_max), int(n_grid))
    sse = np.array([solve(g)[2] for g in grid])
    i = int(np.argmin(sse))
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    best = solve(grid[i])
    if hi > lo:
        res = minimize_scalar(lambda g: solve(g)[2], bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-10})
        cand = solve(res.x)
        if cand[2] <= best[2]:
            best = cand
    return best


def search_bound(value: float, a_max: float, a_min: float = A_MIN) -> str:
    """'' when the response fit's development coefficient ``value`` lies inside its search range,
    else which end it sits at (within 1e-6 of the range in log): reported by the learners'
    ``at_bound_`` so that a coefficient pinned at the range's end is not read as a fitted one."""
    span = np.log(a_max) - np.log(a_min)
    if np.log(value) - np.log(a_min) <= 1e-6 * span:
        return f"at the search range's lower end {a_min:g} per sample"
    if np.log(a_max) - np.log(value) <= 1e-6 * span:
        return f"at the search range's upper end {a_max:g} per sample"
    return ""


def check_growth(retention: float, n: int, *, model: str, coef_name: str, coef: float, fit_method: str) -> None:
    """Raise :class:`InputError` if a response with per-sample retention factor ``retention`` grows by more
    than :data:`MAX_GROWTH` over ``n`` samples (``|retention| > 1``: an unstable development coefficient)."""
    r = abs(float(retention))
    if not np.isfinite(r) or r <= 1.0:
        return
    log10_growth = (n - 1) * np.log10(r)
    if log10_growth > np.log10(MAX_GROWTH):
        raise InputError(
            "model", coef_name,
            f"{model} {fit_method}-fit development coefficient {coef_name} = {coef:.4g} per sample is unstable: "
            f"its response grows by a factor 1e{log10_growth:.0f} over {n} samples. The least-squares fit of "
            "the grey equation on accumulated series is poorly conditioned on long, densely sampled records; "
            "use fit_method='response' (least squares of the simulated response, a >= 0) or a few samples "
            "(the seeds fit grey models on 5-40 readings)")


def refuse_divergence(values, *, model: str, field: str, coef_name: str, coef: float) -> np.ndarray:
    """Return ``values`` (a simulated grey response) if every one is finite; otherwise raise
    :class:`InputError` on ``field`` (``"X"``: the rows asked for, ``"steps"``: a forecast
    horizon): the model diverges over that horizon, its response overflows at the first
    non-finite sample. Never a NaN or inf passed off as a prediction."""
    values = np.asarray(values, dtype=float)
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError("model", field,
                         f"{model} diverges over this horizon: with {coef_name} = {coef:.4g} per sample its response "
                         f"overflows at sample {i + 1} of {values.size}; ask for at most {i} samples "
                         "(or refit on a record that keeps the model stable)")
    return values


# ----------------------------------------------------------------------------------------------
# GM(1,1)
# ----------------------------------------------------------------------------------------------


def gm11_fit(series) -> tuple[float, float]:
    """Least-squares ``(a, b)`` of GM(1,1): ``x^(0)(k) + a z^(1)(k) = b``, k = 2..n.

    ``B = [[-z^(1)(k), 1]]``, ``Y = [x^(0)(k)]`` (seed 004 §III.B, standard form; seed 000 §3.2).
    For a geometric series ``c r^(k-1)`` this is exact: ``a = 2(1-r)/(1+r)``, ``b = 2c/(1+r)``.
    """
    return gm11_fit_runs([series])


def gm11_fit_runs(series_list) -> tuple[float, float]:
    """Least-squares ``(a, b)`` of GM(1,1) on several series, each accumulated from its own start:
    the equation rows ``x^(0)(k) + a z^(1)(k) = b`` (k = 2..n of each series) stacked; exact when
    every series is ``c r^(k-1)`` with the same ``c`` and ``r`` (whatever their lengths)."""
    rows, targets = [], []
    for series in series_list:
        x0 = np.asarray(series, dtype=float).ravel()
        if x0.size < 4:
            raise InputError("data", "rows", f"GM(1,1) needs at least 4 samples, got {x0.size}")
        if not np.all(np.isfinite(x0)):
            raise InputError("data", "y", "GM(1,1) series contains NaN or infinite values")
        z = background(ago(x0))
        rows.append(np.column_stack([-z, np.ones_like(z)]))
        targets.append(x0[1:])
    (a, b), *_ = np.linalg.lstsq(np.vstack(rows), np.concatenate(targets), rcond=None)
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
    """Fit GM(1,1) on ``series`` (1-D, time-ordered) and return the next ``steps`` values.

    ``steps`` is an integer >= 1; a forecast that overflows (a growing series over a long horizon)
    is an :class:`InputError` (:func:`refuse_divergence`), never NaN."""
    steps = check_int("gm11", "steps", steps)
    x0 = np.asarray(series, dtype=float).ravel()
    a, b = gm11_fit(x0)
    return _gm11_values(a, b, x0[0], x0.size, steps, "steps")


def _gm11_values(a: float, b: float, first: float, start: int, count: int, field: str) -> np.ndarray:
    """Samples ``start + 1 .. start + count`` of the GM(1,1) raw series from ``first``; an
    overflow is refused on ``field`` (:func:`refuse_divergence`)."""
    with np.errstate(over="ignore", invalid="ignore"):
        values = gm11_simulate(a, b, first, start + count)[start:]
    return refuse_divergence(values, model="GM(1,1)", field=field, coef_name="a", coef=a)


@register_learner("gm11")
class GM11(BaseEstimator, RegressorMixin):
    """GM(1,1) single-series grey forecaster, ``dx^(1)/dt + a x^(1) = b`` (seed 004 Eqs. (23)-(26)).

    What X means: GM(1,1) is a pure time-series model. ``fit(X, y)`` fits ``y`` (raw series,
    e.g. thermal error in µm, equally spaced in time); ``X`` only fixes the number of rows.
    ``predict(X)`` returns ``x^(0)(k)`` for k = 1..len(X) of a run that starts with value ``y0``
    (``None``: the first training value); the values in ``X`` are not used. Rows beyond the
    training length are forecasts. Use :meth:`forecast` (or :func:`gm11_forecast`) for the next
    steps after the training series. A growing model (``a < 0``) overflows on a long enough
    horizon: that is an :class:`InputError` naming the last sample it can give, never NaN.

    Fitted: ``a_`` (development coefficient, 1/sample), ``b_`` (grey input, series units),
    ``y0_``, ``n_train_``, ``n_features_in_``.

    Several runs (:meth:`fit_runs`): each run is accumulated from its own start and the equation
    rows of all runs are fitted together (:func:`gm11_fit_runs`); ``y0_`` is then the mean first
    value, and :meth:`forecast` continues the last run.
    """

    time_ordered = True   # rows are one run's samples in time order (learners.runs)
    uses_inputs = False   # the leaderboard says so beside the inputs its row lists

    def __init__(self, y0=None):
        self.y0 = y0

    def _check_params(self):
        check_start_value(self, self.y0)

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``, each its own time-ordered sequence."""
        self._check_params()
        checked = check_runs(runs, model="GM(1,1)")
        self.a_, self.b_ = gm11_fit_runs([ya for _, ya in checked])
        starts = [float(ya[0]) for _, ya in checked]
        self.y0_ = float(np.mean(starts)) if self.y0 is None else float(self.y0)
        self.first_train_ = starts[-1]
        self.n_train_ = checked[-1][1].size
        self.n_features_in_ = checked[0][0].shape[1]
        return self

    def predict(self, X):
        check_fitted(self, "a_")
        Xa = check_series(X, model="GM(1,1)", min_rows=1)
        check_n_features(self, Xa)        # its rows only set the horizon; the width must still be the fit's
        return _gm11_values(self.a_, self.b_, self.y0_, 0, Xa.shape[0], "X")

    def forecast(self, steps: int) -> np.ndarray:
        """Values for the ``steps`` samples after the training series (``steps`` an integer >= 1;
        a forecast that overflows is an :class:`InputError`, never NaN)."""
        steps = check_int(self, "steps", steps)
        check_fitted(self, "a_")
        return _gm11_values(self.a_, self.b_, self.first_train_, self.n_train_, steps, "steps")


# ----------------------------------------------------------------------------------------------
# GM(1,N)
# ----------------------------------------------------------------------------------------------


def gm1n_simulate(a: float, b, X_ago: np.ndarray, y0: float, response: str = "difference") -> np.ndarray:
    """Raw response ``x_1^(0)(1..n)`` of GM(1,N) for AGO drivers ``X_ago`` (n, N-1), starting at ``y0``."""
    drive = X_ago @ np.asarray(b, dtype=float)
    if response == "whitened":
        if abs(a) < 1e-12:
            raise InputError("model", "a", "GM(1,N) whitened response needs a != 0")
        k = np.arange(X_ago.shape[0], dtype=float)
        x1 = (y0 - drive / a) * np.exp(-a * k) + drive / a  # equals y0 at k = 0
    elif response == "difference":
        lead = 1.0 + 0.5 * a
        if lead == 0.0:
            return np.full(X_ago.shape[0], np.inf)
        retention = (1.0 - 0.5 * a) / lead
        x1 = np.empty(X_ago.shape[0])
        x1[0] = y0
        if x1.size > 1:
            # x1(k) = retention * x1(k-1) + drive(k) / lead, started at y0.
            x1[1:], _ = lfilter([1.0 / lead], [1.0, -retention], drive[1:], zi=[retention * y0])
    else:
        raise InputError("parameters", "response", f"unknown GM(1,N) response {response!r}; "
                                                   "use 'difference' or 'whitened'")
    return iago(x1)


def gm1n_retention(a: float, response: str) -> float:
    """Per-sample factor of the homogeneous GM(1,N) response (|.| > 1: grows without bound)."""
    if response == "whitened":
        return float(np.exp(-a))
    lead = 1.0 + 0.5 * a
    return np.inf if lead == 0.0 else (1.0 - 0.5 * a) / lead


@register_learner("gm1n")
class GM1N(BaseEstimator, RegressorMixin):
    """GM(1,N): ``x_1^(0)(k) + a z_1^(1)(k) = sum_{j=2..N} b_j x_j^(1)(k)`` (thesis (3.27)-(3.30)).

    ``X``: (n, N-1) driver series (ΔT, °C), rows time-ordered; ``y``: response x_1^(0) (µm).

    Calibration (``fit_method``):
      - ``"response"`` (default): least squares of the simulated response (what ``predict``
        returns) against ``y``, over ``a >= 0`` (a stable response) by variable projection
        (:func:`response_ls_fit`). Use this on long, densely sampled records (module docstring).
      - ``"equation"``: the classical least squares of the grey equation,
        ``[a, b_2..b_N] = (B^T B)^-1 B^T Y`` with ``Y = [x_1^(0)(2) .. x_1^(0)(n)]`` and B rows
        ``[-z_1^(1)(k), x_2^(1)(k), .., x_N^(1)(k)]``. The thesis prints ``+z_1^(1)`` in B (only the
        sign of ``a`` flips) and ``x_1^(1)`` in the second column (a typo for ``x_2^(1)``); the
        standard Deng/Liu form is used here. Raises :class:`InputError` when the fitted response
        would grow by more than ``1e3`` over the training record (or, at predict, over ``X``).

    Prediction (``response``):
      - ``"difference"`` (default): solve the grey equation itself step by step,
        ``x_1^(1)(k) = [(1 - a/2) x_1^(1)(k-1) + sum_j b_j x_j^(1)(k)] / (1 + a/2)``, then IAGO. This
        reproduces data generated by the model's own equation exactly. ``fit_method="response"``
        searches ``0 < a <= 2`` here (``a = 2``: the static limit; larger ``a`` alternates in sign).
      - ``"whitened"``: the classical approximate time response
        ``x_1^(1)(k) = (x_1^(0)(1) - S(k)/a) e^{-a(k-1)} + S(k)/a``, ``S(k) = sum_j b_j x_j^(1)(k)``
        (``fit_method="response"`` searches ``0 < a <= 20``).

    Fitted: ``a_``, ``b_`` (N-1,), ``coef_`` = ``b_`` (influence ranking, thesis L3400), ``y0_``.

    Several runs (:meth:`fit_runs`): each run is accumulated and simulated from its own first
    value, the residuals of all runs are fitted together; ``y0_`` is then the mean first value.
    """

    time_ordered = True   # rows are one run's samples in time order (learners.runs)

    def __init__(self, response="difference", y0=None, fit_method="response"):
        self.response = response
        self.y0 = y0
        self.fit_method = fit_method

    def _check_params(self):
        check_choice(self, "response", self.response, ("difference", "whitened"))
        check_choice(self, "fit_method", self.fit_method, FIT_METHODS)
        check_start_value(self, self.y0)

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Fit on several runs ``[(X, y), ...]``, each its own time-ordered sequence."""
        self._check_params()
        checked = check_runs(runs, model="GM(1,N)")
        p = checked[0][0].shape[1]
        n = sum(Xa.shape[0] for Xa, _ in checked)
        if n < p + 2:
            raise InputError("data", "rows", f"GM(1,N) with {p} inputs needs at least {p + 2} rows, got {n}")
        X_agos = [ago(Xa) for Xa, _ in checked]
        starts = np.array([ya[0] for _, ya in checked])
        if self.fit_method == "equation":
            B = np.vstack([np.column_stack([-background(ago(ya)), Xg[1:]]) for (_, ya), Xg in zip(checked, X_agos)])
            theta, *_ = np.linalg.lstsq(B, np.concatenate([ya[1:] for _, ya in checked]), rcond=None)
            a, b = float(theta[0]), theta[1:].copy()
            check_growth(gm1n_retention(a, self.response), max(Xa.shape[0] for Xa, _ in checked), model="GM(1,N)",
                         coef_name="a", coef=a, fit_method="equation")
        else:
            a_max = 2.0 if self.response == "difference" else 20.0

            def simulate(a_, b_, y0):
                firsts = np.broadcast_to(y0, starts.shape)
                return np.concatenate([gm1n_simulate(a_, b_, Xg, s, self.response) for Xg, s in zip(X_agos, firsts)])

            a, b, _ = response_ls_fit(simulate, np.concatenate([ya for _, ya in checked]), p, a_max=a_max,
                                      start=starts)
        # the development coefficient at an end of the response fit's search range ('' inside it)
        self.at_bound_ = search_bound(a, a_max) if self.fit_method != "equation" else ""
        self.a_ = float(a)
        self.b_ = np.asarray(b, dtype=float)
        self.coef_ = self.b_
        self.y0_ = float(np.mean(starts)) if self.y0 is None else float(self.y0)
        self.n_features_in_ = p
        return self

    def predict(self, X):
        Xa = check_series(X, model="GM(1,N)", min_rows=1)
        check_n_features(self, Xa)
        check_growth(gm1n_retention(self.a_, self.response), Xa.shape[0], model="GM(1,N)", coef_name="a",
                     coef=self.a_, fit_method=self.fit_method)
        with np.errstate(over="ignore", invalid="ignore"):
            out = gm1n_simulate(self.a_, self.b_, ago(Xa), self.y0_, self.response)
        return refuse_divergence(out, model="GM(1,N)", field="X", coef_name="a", coef=self.a_)
