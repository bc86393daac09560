"""Grey sensor selection with fuzzy c-means: ``gm0n-fcm`` (thesis Machine A) and ``gra-fcm`` (Machine B).

Both score every candidate sensor (column of ``X``, temperatures in °C, rows time-ordered) against
the thermal error ``y`` (µm), cluster the scalar scores with fuzzy c-means into ``n_select`` groups
(:func:`learners.fcm.fuzzy_cmeans`, hard assignment by largest membership) and keep the best-scoring
sensor of each group (thesis §3.1 steps 3-5, L2009-2019, L4301-4303, L4601-4605). If some group is
empty after the hard assignment, or the scores have fewer distinct values than ``n_select``, the
remaining places go to the best-scoring sensors not yet kept, so exactly ``n_select`` columns
are kept (``n_select`` larger than the number of columns ``p`` is refused).

gm0n-fcm score: ``|theta_j|`` of GM(0,N) (:func:`learners.grey.gm0n_coefficients`, thesis
Eqs. (3.21)-(3.25), L2902-3171, L4219-4243). With ``temperature_rise=True`` (default) each sensor's
first reading is subtracted first, because the thesis works on "temperature changes" (L4219); the
coefficients are in µm per °C (per accumulated sample) and are not scale free. Neighbouring sensors
are nearly collinear, which makes plain least squares swing their coefficients to large opposite
values; ``alpha`` (default 1e-5, relative to the mean diagonal of ``B^T B``) adds a tiny ridge term
against that (a deviation from the thesis, advised by the notes §3.4; ``alpha=0`` is the thesis's
plain least squares).

gra-fcm score (``measure``):
  - ``"similitude"`` (default; thesis §4.5.2 Steps 1-5, L4515-4605, Eq. (4.1)): Liu's similitude
    degree with zero-initial images ``x_i^0(k) = x_i(k) - x_i(1)``::

        |s_0 - s_m| = | sum_{k=2..n-1} (x_0^0(k) - x_m^0(k)) + 0.5 (x_0^0(n) - x_m^0(n)) |
        eps_0m      = 1 / (1 + |s_0 - s_m|)

    It compares µm with °C directly, as the thesis does (no normalisation), so it depends on units.
  - ``"deng"``: Deng's grey relational grade (seed 002 Eqs. (7)-(10), L195-219) on min-max
    normalised series ``g``, ``Delta_q(k) = |g_0(k) - g_q(k)|`` (the seed's printed Eq. (9) mixes raw
    and normalised values and drops the absolute value; the standard form is used),
    ``xi_q(k) = (Delta_min + rho Delta_max) / (Delta_q(k) + rho Delta_max)`` with ``rho = 0.5`` and
    Delta_min/max over all sensors and samples, grade ``= mean_k xi_q(k)``. A constant series
    normalises to zeros.

Several runs (``fit_runs([(X, y), ...])``, :mod:`learners.runs`): GM(0,N) takes each run's rise
from its own first reading and accumulates each run from its own start, the regression rows of all
runs stacked; the grey relational scores are the mean of each run's score.

Fitted: ``scores_`` (p,), ``labels_`` (p,) cluster of each sensor, ``selected_`` (kept column indices,
ascending), ``selected_names_`` (``X.columns`` when present, else ``x0, x1, ...``),
``n_features_in_``.
"""

from __future__ import annotations

import numpy as np
from sklearn.base import BaseEstimator, TransformerMixin

from learners._checks import (check_bool, check_choice, check_count_fits, check_float, check_int, check_non_negative,
                              refuse_constant_columns)
from learners.fcm import fuzzy_cmeans
from learners.grey import check_n_features, check_runs, check_series, gm0n_coefficients_runs
from learners.registry import register_selector
from twin.errors import InputError

__all__ = ["similitude_degree", "deng_grade", "fcm_representatives", "GM0NFCMSelector", "GRAFCMSelector"]


def _column_names(X, p: int) -> list[str]:
    cols = getattr(X, "columns", None)
    if cols is None:
        cols = getattr(X, "feature_names_in_", None)
    if cols is not None and len(cols) == p:
        return [str(c) for c in cols]
    return [f"x{j}" for j in range(p)]


def similitude_degree(reference, X) -> np.ndarray:
    """Liu's similitude degree ``eps_0m`` (thesis Eq. (4.1)) of each column of ``X`` to ``reference``."""
    r = np.asarray(reference, dtype=float).ravel()
    Xa = np.asarray(X, dtype=float).reshape(r.size, -1)
    d = (r - r[0])[:, None] - (Xa - Xa[0])
    s = d[1:-1].sum(axis=0) + 0.5 * d[-1]
    return 1.0 / (1.0 + np.abs(s))


def deng_grade(reference, X, rho=0.5) -> np.ndarray:
    """Deng's grey relational grade of each column of ``X`` to ``reference`` (min-max normalised)."""

    def minmax(a):
        lo, hi = a.min(axis=0), a.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        return (a - lo) / span

    r = minmax(np.asarray(reference, dtype=float).reshape(-1, 1))
    g = minmax(np.asarray(X, dtype=float).reshape(r.shape[0], -1))
    delta = np.abs(r - g)
    dmin, dmax = delta.min(), delta.max()
    if dmax == 0.0:
        return np.ones(g.shape[1])
    return ((dmin + rho * dmax) / (delta + rho * dmax)).mean(axis=0)


def fcm_representatives(scores, n_select: int, *, m=2.0, random_state=None):
    """Cluster scalar ``scores`` by FCM into ``n_select`` groups; best score per group.

    Returns ``(selected, labels)``: sorted kept indices and the hard cluster label of every score
    (-1 where no clustering was possible). Fills up with the next-best scores when a group is empty.
    """
    scores = np.asarray(scores, dtype=float)
    p = scores.size
    k = min(int(n_select), p)
    labels = np.full(p, -1)
    chosen: list[int] = []
    if np.unique(scores).size >= k:
        res = fuzzy_cmeans(scores[:, None], k, m=m, random_state=random_state)
        labels = res.membership.argmax(axis=1)
        for c in range(k):
            members = np.flatnonzero(labels == c)
            if members.size:
                chosen.append(int(members[np.argmax(scores[members])]))
    for j in np.argsort(-scores, kind="stable"):
        if len(chosen) >= k:
            break
        if int(j) not in chosen:
            chosen.append(int(j))
    return np.array(sorted(chosen), dtype=int), labels


class _GreyFCMSelector(BaseEstimator, TransformerMixin):
    """Score, cluster by FCM, keep one sensor per cluster; subclasses provide ``_scores``."""

    _name = "grey selector"

    def _check_params(self):
        """Check the hyper-parameters (:mod:`learners._checks`); subclasses add their own."""
        check_int(self, "n_select", self.n_select)
        check_float(self, "m", self.m, 1.0, above=True)

    def fit(self, X, y):
        return self.fit_runs([(X, y)])

    def fit_runs(self, runs):
        """Pick sensors on several runs ``[(X, y), ...]``, each its own time-ordered sequence."""
        self._check_params()
        checked = check_runs(runs, model=self._name, min_rows=3)
        refuse_constant_columns(self._name, np.vstack([Xa for Xa, _ in checked]))
        check_count_fits(self, "n_select", self.n_select, checked[0][0].shape[1])
        self.scores_ = self._scores_runs(checked)
        self.selected_, self.labels_ = fcm_representatives(self.scores_, self.n_select, m=self.m,
                                                           random_state=self.random_state)
        p = checked[0][0].shape[1]
        names = _column_names(runs[0][0], p)
        self.selected_names_ = [names[j] for j in self.selected_]
        self.n_features_in_ = p
        return self

    def _scores_runs(self, runs):
        """Scores from several runs: the mean of each run's (subclasses may do better)."""
        return np.mean([self._scores(Xa, ya) for Xa, ya in runs], axis=0)

    def transform(self, X):
        Xa = check_series(X, model=self._name, min_rows=1)
        check_n_features(self, Xa)
        return Xa[:, self.selected_]

    def get_feature_names_out(self, input_features=None):
        return np.asarray(self.selected_names_, dtype=object)


@register_selector("gm0n-fcm")
class GM0NFCMSelector(_GreyFCMSelector):
    """GM(0,N) influence ``|theta_j|`` clustered by FCM, best sensor per cluster (module docstring)."""

    _name = "gm0n-fcm"

    def __init__(self, n_select=4, temperature_rise=True, alpha=1e-5, m=2.0, random_state=0):
        self.n_select = n_select
        self.temperature_rise = temperature_rise
        self.alpha = alpha
        self.m = m
        self.random_state = random_state

    def _check_params(self):
        super()._check_params()
        check_bool(self, "temperature_rise", self.temperature_rise)
        check_non_negative(self, "alpha", self.alpha)

    def _scores(self, X, y):
        return self._scores_runs([(X, y)])

    def _scores_runs(self, runs):
        rises = [(X - X[0] if self.temperature_rise else X, y) for X, y in runs]
        return np.abs(gm0n_coefficients_runs(rises, alpha=self.alpha))


@register_selector("gra-fcm")
class GRAFCMSelector(_GreyFCMSelector):
    """Grey relational scores (Liu similitude or Deng grade) clustered by FCM (module docstring)."""

    _name = "gra-fcm"

    def __init__(self, n_select=5, measure="similitude", rho=0.5, m=2.0, random_state=0):
        self.n_select = n_select
        self.measure = measure
        self.rho = rho
        self.m = m
        self.random_state = random_state

    def _check_params(self):
        super()._check_params()
        check_choice(self, "measure", self.measure, ("similitude", "deng"))
        check_float(self, "rho", self.rho, 0.0, 1.0, above=True)

    def _scores(self, X, y):
        if self.measure == "similitude":
            return similitude_degree(y, X)
        if self.measure == "deng":
            return deng_grade(y, X, rho=self.rho)
        raise InputError("parameters", "measure", f"unknown measure {self.measure!r}; use 'similitude' or 'deng'")
