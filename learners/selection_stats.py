"""Statistical temperature-sensor selection: ``hier-corr``, ``fuzzy-r2``, ``correlation``, ``all``.

All are transformers: ``fit(X, y)`` chooses columns of the candidate temperature table ``X``
(degC) for the thermal error ``y`` (um), ``transform(X)`` keeps them. ``selected_`` holds the kept
column indices (ascending), ``selected_names_`` their names (``X.columns`` when present, else
``x0, x1, ...``). ``r`` below is Pearson's correlation (seed 002 Eq. 11, seed 003 Eq. 11)::

    r(u, v) = sum (u - mean u)(v - mean v) / sqrt(sum (u - mean u)^2 sum (v - mean v)^2)

A constant column has no defined correlation; it is treated as r = 0 (never preferred).

hier-corr (seed 002 Section 3.6, L261-L311): agglomerative clustering of the sensors with the
correlation distance ``d_ij = 1 - |r(T_i, T_j)|`` (``linkage`` method, default average), the tree
cut into ``n_select`` groups (MATLAB ``cluster(..., 'maxclust')``), and from each group the sensor with
the largest ``|r(T_j, y)|``. The seed uses MATLAB's ``pdist``/``linkage`` defaults on normalised
series and then takes two sensors from one group (T10, T12, L311) on the strength of a lost table;
here it is strictly one sensor per group, and if ties leave fewer groups than ``n_select`` the
remaining places go to the next best-correlated sensors.

fuzzy-r2 (seed 003 Section 3.3, L121-L147, L222-L294): the fuzzy similarity matrix is
``|r(T_i, T_j)|`` (Eq. 12; the seed's values are all positive, the absolute value makes the method
sign-blind); Prim's maximal spanning tree (L232-L240) cut at a threshold lambda gives the clusters
(Table 3); with a spanning tree, removing the k-1 weakest edges gives exactly k clusters. Each cluster
is represented by its sensor with the largest ``|r(T_j, y)|`` (Tables 4-5). The level is chosen by
the sample determination coefficient and the regression F-test (Eqs. 7-8)::

    R^2 = SSR/SST = 1 - SSE/SST,    F = (SSR/p) / (SSE/(n-p-1)) ~ F(p, n-p-1)

``n_select`` given: that level. ``n_select=None``: the seed weighs R^2 against significance by eye
(5 sensors, R^2 = 0.997, Sig. 0.008; 6 sensors, R^2 = 0.999, rejected with Sig. 0.058; Tables 6-8).
To make that automatic, among the levels whose F-test is significant at ``alpha`` the one with the
lowest Bayesian information criterion ``n ln(1 - R^2) + (p + 1) ln n`` is taken (R^2 rewards fit,
the ``ln n`` term charges each sensor); on the seed's Table 6 this gives its 5 sensors (tested).
The SPSS collinearity-tolerance screen the seed mentions (L292) is not applied.

correlation: the ``n_select`` sensors with the largest ``|r(T_j, y)|``.
all: keeps every column (a baseline).
"""

from __future__ import annotations

import numpy as np
import scipy.stats
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.spatial.distance import squareform
from sklearn.base import BaseEstimator, TransformerMixin

from learners._checks import (check_choice, check_count_fits, check_fit_data, check_fitted, check_float, check_int,
                              check_predict_data, check_table, column_names, model_name, refuse_constant_columns)
from learners.registry import register_selector
from twin.errors import InputError

__all__ = [
    "HierCorrSelector", "FuzzyR2Selector", "CorrelationSelector", "AllSelector",
    "correlation_matrix", "target_correlation", "maximal_spanning_tree", "tree_partition",
    "representatives",
]


def correlation_matrix(X) -> np.ndarray:
    """Pearson correlation between the columns of ``X``; undefined entries (constant columns) -> 0."""
    X = np.asarray(X, dtype=float)
    Xc = X - X.mean(axis=0)
    norm = np.sqrt((Xc * Xc).sum(axis=0))
    with np.errstate(invalid="ignore", divide="ignore"):
        c = (Xc.T @ Xc) / np.outer(norm, norm)
    c = np.where(np.isfinite(c), c, 0.0)
    np.fill_diagonal(c, 1.0)
    return np.clip(c, -1.0, 1.0)


def target_correlation(X, y) -> np.ndarray:
    """Pearson r of every column of ``X`` with ``y``; undefined -> 0."""
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    Xc, yc = X - X.mean(axis=0), y - y.mean()
    with np.errstate(invalid="ignore", divide="ignore"):
        r = (Xc.T @ yc) / np.sqrt((Xc * Xc).sum(axis=0) * (yc @ yc))
    return np.where(np.isfinite(r), r, 0.0)


def maximal_spanning_tree(similarity) -> list[tuple[int, int, float]]:
    """Prim's maximal spanning tree from node 0 (seed 003 L232-L240): edges ``(inside, new, weight)``.

    At each step the heaviest edge from the tree to a node outside it is added (ties: lowest index).
    """
    s = np.asarray(similarity, dtype=float)
    n = s.shape[0]
    in_tree = np.zeros(n, dtype=bool)
    in_tree[0] = True
    best = s[0].copy()
    parent = np.zeros(n, dtype=int)
    edges = []
    for _ in range(n - 1):
        cand = np.where(in_tree, -np.inf, best)
        j = int(np.argmax(cand))
        edges.append((int(parent[j]), j, float(s[parent[j], j])))
        in_tree[j] = True
        better = (~in_tree) & (s[j] > best)
        best[better] = s[j][better]
        parent[better] = j
    return edges


def tree_partition(edges, n_nodes: int, n_clusters: int) -> list[list[int]]:
    """Clusters left after removing the ``n_clusters - 1`` weakest tree edges (a lambda-cut).

    Returns the clusters as sorted index lists, ordered by their smallest member.
    """
    keep = sorted(edges, key=lambda e: -e[2])[: max(0, n_nodes - n_clusters)]
    root = list(range(n_nodes))

    def find(i):
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for a, b, _ in keep:
        root[find(a)] = find(b)
    groups: dict[int, list[int]] = {}
    for i in range(n_nodes):
        groups.setdefault(find(i), []).append(i)
    return sorted(groups.values(), key=lambda g: g[0])


def representatives(clusters, r_target) -> list[int]:
    """The member of each cluster with the largest ``|r_target|`` (ties: lowest index), sorted."""
    a = np.abs(np.asarray(r_target, dtype=float))
    return sorted(int(g[int(np.argmax(a[g]))]) for g in clusters)


def choose_level(r2, p_values, n_samples, alpha=0.05) -> int:
    """Number of clusters (1-based level) chosen from per-level R^2 and F-test p-values.

    Lowest ``n ln(1 - R^2) + (k + 1) ln n`` among levels with ``p < alpha``; level 1 if none is.
    """
    r2 = np.asarray(r2, dtype=float)
    ok = np.flatnonzero(np.asarray(p_values, dtype=float) < alpha)
    if ok.size == 0:
        return 1
    k = ok + 1
    bic = n_samples * np.log(np.clip(1.0 - r2[ok], 1e-300, None)) + (k + 1) * np.log(n_samples)
    return int(k[np.argmin(bic)])


def _regression_test(X, y):
    """R^2 and the F-test p-value of an OLS of ``y`` on the columns of ``X`` (seed 003 Eqs. 7-8)."""
    n, p = X.shape
    A = np.column_stack([np.ones(n), X])
    fit = A @ np.linalg.lstsq(A, y, rcond=None)[0]
    sst = float(((y - y.mean()) ** 2).sum())
    sse = float(((y - fit) ** 2).sum())
    if sst <= 0:
        return 0.0, np.nan, 1.0
    r2 = 1.0 - sse / sst
    dof = n - p - 1
    if dof <= 0:
        return r2, np.nan, 1.0
    if sse <= 1e-300:
        return r2, np.inf, 0.0
    f = ((sst - sse) / p) / (sse / dof)
    return r2, float(f), float(scipy.stats.f.sf(f, p, dof))


class _Selector(TransformerMixin, BaseEstimator):
    """Shared fit/transform plumbing; subclasses implement ``_choose(X, y) -> indices``."""

    needs_target = True     # fit ranks sensors against y (all but AllSelector)

    def _check_params(self):
        """Check the hyper-parameters (:mod:`learners._checks`); ``n_select`` against the columns at fit."""
        if "n_select" in self.get_params(deep=False) and self.n_select is not None:
            check_int(self, "n_select", self.n_select)

    def fit(self, X, y=None):
        self._check_params()
        names_source = X
        if y is None:
            if self.needs_target:
                raise InputError(model_name(self), "y", "this selector ranks the sensors by their relation to the "
                                                        "target: give y")
            X = check_table(self, X)
            self.n_features_in_ = X.shape[1]
        else:
            X, y = check_fit_data(self, X, y)
        refuse_constant_columns(self, X)
        idx = sorted(int(i) for i in self._choose(X, y))
        self.selected_ = idx
        names = column_names(names_source, X.shape[1])
        self.selected_names_ = [names[i] for i in idx]
        return self

    def _check_n_select(self, n_features):
        """``n_select`` as an int: an integer from 1 to the number of columns (more is refused, not
        cut down)."""
        k = check_int(self, "n_select", self.n_select)
        return check_count_fits(self, "n_select", k, n_features)

    def transform(self, X):
        frame = X if hasattr(X, "iloc") else None
        X = check_predict_data(self, X, "selected_")
        return frame.iloc[:, self.selected_] if frame is not None else X[:, self.selected_]

    def get_support(self, indices=False):
        """Boolean mask (or the indices) of the kept columns, as in scikit-learn's selectors."""
        check_fitted(self, "selected_")
        if indices:
            return np.array(self.selected_, dtype=int)
        mask = np.zeros(self.n_features_in_, dtype=bool)
        mask[self.selected_] = True
        return mask


@register_selector("hier-corr")
class HierCorrSelector(_Selector):
    """Hierarchical clustering by correlation distance, best |r| with y per group (seed 002).

    Parameters: ``n_select`` (int, default 5 as in seed 002 L311), ``linkage`` (scipy method name
    for the distance 1 - |r|: "average", "single", "complete", "weighted"; default "average").
    Attributes: ``selected_``, ``selected_names_``, ``labels_`` (group of each column, 1-based),
    ``scores_`` (|r| of each column with y).
    """

    def __init__(self, n_select=5, linkage="average"):
        self.n_select = n_select
        self.linkage = linkage

    def _check_params(self):
        super()._check_params()
        check_choice(self, "linkage", self.linkage, ("average", "single", "complete", "weighted"))

    def _choose(self, X, y):
        d = X.shape[1]
        k = self._check_n_select(d)
        score = np.abs(target_correlation(X, y))
        self.scores_ = score
        if d == 1:
            self.labels_ = np.ones(1, dtype=int)
            return [0]
        dist = 1.0 - np.abs(correlation_matrix(X))
        dist = np.clip((dist + dist.T) / 2.0, 0.0, None)
        np.fill_diagonal(dist, 0.0)
        tree = linkage(squareform(dist, checks=False), method=self.linkage)
        labels = fcluster(tree, t=k, criterion="maxclust")
        self.labels_ = labels
        chosen = representatives([np.flatnonzero(labels == g) for g in np.unique(labels)], score)
        for j in np.argsort(-score, kind="stable"):
            if len(chosen) >= k:
                break
            if int(j) not in chosen:
                chosen.append(int(j))
        return chosen


@register_selector("fuzzy-r2")
class FuzzyR2Selector(_Selector):
    """Maximal-tree fuzzy clustering with R^2 / F-test level choice (seed 003 Section 3.3).

    Parameters: ``n_select`` (int or None: None chooses the level by R^2 and BIC among F-significant
    levels, see :func:`choose_level`), ``alpha`` (F-test significance level, default 0.05).
    Attributes: ``selected_``, ``selected_names_``, ``tree_`` (Prim edges), ``combinations_``
    (representatives for 1..n_features clusters), ``r2_``, ``p_values_`` (per level),
    ``n_selected_``, ``scores_`` (|r| with y).
    """

    def __init__(self, n_select=None, alpha=0.05):
        self.n_select = n_select
        self.alpha = alpha

    def _check_params(self):
        super()._check_params()
        check_float(self, "alpha", self.alpha, 0.0, 1.0, above=True, below=True)

    def _choose(self, X, y):
        d = X.shape[1]
        k = self._check_n_select(d) if self.n_select is not None else None
        score = np.abs(target_correlation(X, y))
        self.scores_ = score
        self.tree_ = maximal_spanning_tree(np.abs(correlation_matrix(X)))
        combos = [representatives(tree_partition(self.tree_, d, k), score) for k in range(1, d + 1)]
        tests = [_regression_test(X[:, c], y) for c in combos]
        self.combinations_ = combos
        self.r2_ = np.array([t[0] for t in tests])
        self.p_values_ = np.array([t[2] for t in tests])
        if k is None:
            k = choose_level(self.r2_, self.p_values_, X.shape[0], self.alpha)
        self.n_selected_ = k
        return combos[k - 1]


@register_selector("correlation")
class CorrelationSelector(_Selector):
    """The ``n_select`` columns with the largest |r| with y (default 5). ``scores_`` = |r|."""

    def __init__(self, n_select=5):
        self.n_select = n_select

    def _choose(self, X, y):
        k = self._check_n_select(X.shape[1])
        self.scores_ = np.abs(target_correlation(X, y))
        return np.argsort(-self.scores_, kind="stable")[:k]


@register_selector("all")
class AllSelector(_Selector):
    """Keeps every column (no selection); ``y`` is accepted and ignored."""

    needs_target = False

    def _choose(self, X, y):
        return range(X.shape[1])
