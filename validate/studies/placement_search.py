"""Searching sensor sets with the truth: the best k-sensor set for least squares, by greedy forward
selection (a reference: greedy, so neither a bound nor an optimum) or by exhaustive search (the
optimum for least squares).

Both judge a set S by the test RMSE [um] of least squares with an intercept (the ``mlr`` learner)
fitted on the training rows::

    beta_S = argmin ||[1 X_tr,S] beta - y_tr||,   RMSE(S) = ||[1 X_te,S] beta_S - y_te|| / sqrt(n_te)

Exhaustive search (:func:`exhaustive_best`) scores every one of the C(p, k) sets from the normal
equations, built once on standardised inputs (train mean and standard deviation) with the
intercept column first: for the index set J = {0} u S,

    beta_J = G_tr[J, J]^-1 b_tr[J],   SSE(S) = beta_J^T G_te[J, J] beta_J - 2 beta_J^T b_te[J] + y_te^T y_te

with ``G = A^T A``, ``b = A^T y`` of each set. Sets are processed in chunks (one batched 5 x 5 solve
each for k = 4), so C(168, 4) = 31.6 million sets take about a minute; the best ``recheck`` sets are
then scored again by ``numpy.linalg.lstsq`` on the rows themselves (the normal equations square the
condition number of nearly collinear neighbouring sensors), and the best of those is returned: the
optimum for this criterion (least squares, test RMSE) over all sets to the screen's accuracy (a
set the normal equations rank below the rechecked ones is not rescored; their SSE margin is what
separates them); another learner's best set may differ.
"""

from __future__ import annotations

from itertools import combinations, islice
from math import comb

import numpy as np

from learners.metrics import rms

__all__ = ["lstsq_test_rmse", "greedy_oracle", "exhaustive_best"]


def lstsq_test_rmse(Xtr, ytr, Xte, yte) -> float:
    """Test RMSE of least squares with an intercept fitted on (Xtr, ytr) (module doc)."""
    A = np.column_stack([np.ones(len(Xtr)), Xtr])
    coef, *_ = np.linalg.lstsq(A, ytr, rcond=None)
    r = np.column_stack([np.ones(len(Xte)), Xte]) @ coef - yte
    return float(rms(r))


def greedy_oracle(Xtr, ytr, Xte, yte, candidates, k: int = 4) -> list[int]:
    """Columns chosen by forward selection, each step adding the candidate that most lowers the
    test RMSE of least squares; it uses the test truth, but greedy: not an optimum, and not a bound
    (a real selection can do better, as the exhaustive search shows)."""
    chosen: list[int] = []
    for _ in range(k):
        best, best_rmse = None, np.inf
        for c in candidates:
            if c in chosen:
                continue
            e = lstsq_test_rmse(Xtr[:, chosen + [c]], ytr, Xte[:, chosen + [c]], yte)
            if e < best_rmse:
                best, best_rmse = c, e
        chosen.append(best)
    return chosen


def exhaustive_best(Xtr, ytr, Xte, yte, candidates, k: int = 4, *, chunk: int = 200_000, recheck: int = 20,
                    max_sets: int = 50_000_000, progress=None) -> tuple[list[int], float, int]:
    """The k-set of ``candidates`` (column indices) with the least test RMSE of least squares, by
    exhaustive search (module doc). Returns ``(columns, test RMSE, number of sets scored)``;
    ``progress(done, total)`` after each chunk. More than ``max_sets`` sets is a ValueError."""
    cand = np.asarray(candidates, dtype=int)
    total = comb(len(cand), k)
    if total > max_sets:
        raise ValueError(f"exhaustive search over C({len(cand)}, {k}) = {total} sets exceeds {max_sets}; "
                         "give fewer candidates or a smaller k")
    mean, sd = Xtr[:, cand].mean(axis=0), Xtr[:, cand].std(axis=0)
    sd[sd == 0.0] = 1.0

    def design(X):
        return np.column_stack([np.ones(len(X)), (X[:, cand] - mean) / sd])

    Atr, Ate = design(Xtr), design(Xte)
    Gtr, btr = Atr.T @ Atr, Atr.T @ ytr
    Gte, bte, cte = Ate.T @ Ate, Ate.T @ yte, float(yte @ yte)
    best_sse, best_sets = np.empty(0), np.empty((0, k), dtype=int)
    it = combinations(range(1, len(cand) + 1), k)
    done = 0
    while True:
        block = np.fromiter(islice(it, chunk), dtype=np.dtype((np.int64, k)))
        if len(block) == 0:
            break
        J = np.column_stack([np.zeros(len(block), dtype=np.int64), block])
        G = Gtr[J[:, :, None], J[:, None, :]]
        with np.errstate(all="ignore"):
            beta = np.linalg.solve(G + 1e-12 * np.trace(G, axis1=1, axis2=2)[:, None, None] * np.eye(k + 1),
                                   btr[J][:, :, None])[:, :, 0]
            sse = (np.einsum("ni,nij,nj->n", beta, Gte[J[:, :, None], J[:, None, :]], beta)
                   - 2.0 * np.einsum("ni,ni->n", beta, bte[J]) + cte)
        sse = np.where(np.isfinite(sse), sse, np.inf)
        keep = np.argsort(sse, kind="stable")[:recheck]
        best_sse = np.concatenate([best_sse, sse[keep]])
        best_sets = np.vstack([best_sets, block[keep]])
        top = np.argsort(best_sse, kind="stable")[:recheck]
        best_sse, best_sets = best_sse[top], best_sets[top]
        done += len(block)
        if progress is not None:
            progress(done, total)
    scored = [(lstsq_test_rmse(Xtr[:, cand[s - 1]], ytr, Xte[:, cand[s - 1]], yte), [int(c) for c in cand[s - 1]])
              for s in best_sets]
    rmse, cols = min(scored, key=lambda t: t[0])
    return sorted(cols), rmse, done


if __name__ == "__main__":
    from validate.studies.not_a_study import not_a_command

    not_a_command("validate.studies.placement_search")
