"""Fuzzy c-means clustering (Bezdek), as used by the thesis for ANFIS rules and sensor selection.

Equations (thesis §3.10, seed 000 L2325-2424; paper seed 001 Eqs. (1)-(3), L128-L159)::

    mu_ij = 1 / sum_k (d_ij / d_kj)^(2/(m-1)),   d_ij = ||c_i - x_j||     (1) membership
    J     = sum_i sum_j mu_ij^m d_ij^2                                     (2) objective
    c_i   = sum_j mu_ij^m x_j / sum_j mu_ij^m                              (3) centres

Seed 001 prints the exponent of (1) as ``2/m-1``; the standard form ``2/(m-1)`` is used here.
The fuzzifier ``m`` is not stated in the sources; ``m = 2`` (the MATLAB default) is the default.
Initial centres are ``n_clusters`` distinct data points drawn at random (seed 001 L132), which makes
the result deterministic for a given ``random_state``. Iteration stops when the objective improves
by less than ``tol`` (relative) or after ``max_iter`` iterations.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from learners._checks import check_seed
from twin.errors import InputError
from twin.limits import is_number, is_whole

__all__ = ["FCMResult", "fuzzy_cmeans", "fcm_memberships"]


@dataclass(frozen=True)
class FCMResult:
    """Outcome of :func:`fuzzy_cmeans`.

    ``centers``: (c, n_features); ``membership``: (n_samples, c), rows sum to 1;
    ``objective``: final J of Eq. (2); ``n_iter``: iterations performed.
    """

    centers: np.ndarray
    membership: np.ndarray = field(repr=False)
    objective: float
    n_iter: int


def fcm_memberships(data, centers, m=2.0) -> np.ndarray:
    """Memberships (n_samples, c) of ``data`` to fixed ``centers`` by Eq. (1).

    A point that coincides with a centre gets membership 1 there (shared equally if it coincides
    with several centres).
    """
    data = np.asarray(data, dtype=float)
    centers = np.asarray(centers, dtype=float)
    d2 = ((data[:, None, :] - centers[None, :, :]) ** 2).sum(axis=2)
    zero = d2 <= 1e-300
    # mu_ij is proportional to d_ij^(-2/(m-1)) = (d_ij^2)^(-1/(m-1)); work in logs, scaled per row,
    # so that tiny or huge distances neither overflow nor underflow.
    logw = -np.log(np.where(zero, 1.0, d2)) / (m - 1.0)
    logw = np.where(zero, -np.inf, logw)
    with np.errstate(invalid="ignore"):
        logw -= logw.max(axis=1, keepdims=True)
        inv = np.exp(logw)
        u = inv / inv.sum(axis=1, keepdims=True)
    hit = zero.any(axis=1)
    if hit.any():
        u[hit] = zero[hit] / zero[hit].sum(axis=1, keepdims=True)
    return u


def fuzzy_cmeans(data, n_clusters, *, m=2.0, max_iter=300, tol=1e-6, random_state=None) -> FCMResult:
    """Cluster the rows of ``data`` (n_samples, n_features) into ``n_clusters`` fuzzy clusters.

    A 1-D ``data`` is treated as one feature. Raises :class:`InputError` for a bad argument
    (``n_clusters`` a whole number >= 1, ``m`` above 1, ``tol`` >= 0, ``max_iter`` >= 1) and when
    there are fewer distinct rows than clusters.
    """
    x = np.asarray(data, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    if not is_whole(n_clusters) or n_clusters < 1:
        raise InputError("fuzzy c-means", "n_clusters", f"expected a whole number >= 1, got {n_clusters!r}")
    if not is_number(m) or not 1.0 < m < 1e3:
        raise InputError("fuzzy c-means", "m", f"the fuzzifier must be a number above 1 (2: the usual), got {m!r}")
    if not is_number(tol) or not tol >= 0:
        raise InputError("fuzzy c-means", "tol", f"expected a tolerance >= 0, got {tol!r}")
    if not is_whole(max_iter) or max_iter < 1:
        raise InputError("fuzzy c-means", "max_iter", f"expected a whole number >= 1, got {max_iter!r}")
    if x.ndim != 2 or not np.all(np.isfinite(x)):
        raise InputError("data", "values", "fuzzy c-means needs a finite 2-D array")
    c = int(n_clusters)
    n_distinct = np.unique(x, axis=0).shape[0]
    if c > n_distinct:
        raise InputError("data", "rows", f"fuzzy c-means with {c} clusters needs at least {c} distinct rows, "
                                         f"got {n_distinct}")
    rng = np.random.default_rng(check_seed("fuzzy c-means", random_state))
    # Initial centres: distinct data points drawn at random.
    uniq = np.unique(x, axis=0)
    centers = uniq[np.sort(rng.choice(uniq.shape[0], size=c, replace=False))].copy()
    u = fcm_memberships(x, centers, m)
    objective = np.inf
    n_iter = 0
    for n_iter in range(1, int(max_iter) + 1):
        um = u ** m
        centers = (um.T @ x) / um.sum(axis=0)[:, None]
        d2 = ((x[:, None, :] - centers[None, :, :]) ** 2).sum(axis=2)
        u = fcm_memberships(x, centers, m)
        new_obj = float(((u ** m) * d2).sum())
        done = np.isfinite(objective) and abs(objective - new_obj) <= tol * max(abs(objective), 1e-300)
        objective = new_obj
        if done:
            break
    return FCMResult(centers=centers, membership=u, objective=objective, n_iter=n_iter)
