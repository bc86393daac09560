"""The second core: a large model's independent work done on two threads, with the same numbers
as on one.

Most of a large run is limited by reading memory (sparse products, passes over long vectors),
and one core does not use all of a machine's memory bandwidth: on the 2-core development machine
two concurrent products of the 200 k-node heat matrix finish in 1.7-1.96 times the time of one,
and one product split in two row blocks takes 4.6-5.3 ms instead of 7.7-8.0 (validate/SCALE.md).
Three kinds of work are split here:

* **independent tasks** (:func:`concurrently`): the elastic chain (assembly, multigrid, adjoints,
  the observers' rows) beside the heat basis of the reduced model or the reduced start;
* **row blocks** (:class:`RowBlocks`, :func:`rows_product`, :func:`transposed_product`): a
  product A X of a large matrix computed as [A_1 X; A_2 X] over :data:`PARTS` row blocks of
  about equal stored entries; and the compiled vector passes of a one-column CG
  (:func:`twin.physics.solvers.pcg`) over :func:`even_blocks`, with :func:`map_blocks`;
* **column halves** of an AMG V-cycle on several right-hand sides
  (:func:`twin.physics.solvers.amg_cycle`, through :func:`on_idle_helper`): split only when the
  helper is idle at that moment, with the same arithmetic per column either way.

**The numbers do not depend on the threads.** The row blocks depend on the matrix alone, never
on how many threads run them; each row of A X is the same sum as in A X unsplit, and the
reductions split here (V^T r, :func:`transposed_product`, and CG's dot products) add their
blocks' partial sums in a fixed order. So a run gives the same bits with one thread or two; what the threads change is only which
core computes which block, and when.

**How many threads** (:func:`threads`): at most :data:`PARTS`, no more than the cores this
process may use, and no more than ``OMP_NUM_THREADS`` when that is set (the usual way to ask a
process for one thread per core of a pool); :func:`limited` lowers it for the calling thread
(the dataset runner holds each case to one). A helper thread takes a block only when it is idle:
work is never queued behind a busy helper (a task running on the helper that splits a product
computes both blocks itself), so nothing waits on anything but its own blocks. While work runs
on two threads, BLAS is held to one thread (:func:`single_blas`): OpenBLAS's own threads would
otherwise spin on the second core (measured: a split run's steps 6 ms slower with them). It is
held so whether or not a helper runs (the callers decide by size alone), since OpenBLAS's sums
depend on its thread count: the numbers stay the same with one thread or two.
"""

from __future__ import annotations

import contextlib
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp

from twin.physics import kernels

PARTS = 2                   # row blocks of a split product (fixed: the numbers never depend on the threads)
SPLIT_FROM = 500_000        # stored entries (or n x columns of a dense block) from which a product is split
CONCURRENT_FROM = 30_000    # temperature dofs from which a run builds its rows and its basis concurrently

_local = threading.local()
_lock = threading.Lock()
_pool: ThreadPoolExecutor | None = None
_idle: threading.BoundedSemaphore | None = None


def processors() -> int:
    """The processors this process may run on: its CPU affinity (the CPU count where the platform
    has none)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def cores() -> int:
    """The threads this process may use: its CPU affinity (:func:`processors`), capped by
    ``OMP_NUM_THREADS`` when set to a whole number >= 1."""
    n = processors()
    text = os.environ.get("OMP_NUM_THREADS", "").strip()
    if text.isdigit() and int(text) >= 1:
        n = min(n, int(text))
    return max(1, n)


def threads() -> int:
    """Threads the calling thread's work may use: min(:data:`PARTS`, :func:`cores`, the
    :func:`limited` cap)."""
    return max(1, min(PARTS, cores(), getattr(_local, "cap", PARTS)))


@contextlib.contextmanager
def limited(n: int):
    """Hold the calling thread's work to ``n`` threads (1: all of it in this thread) inside the block."""
    if n < 1:
        raise ValueError(f"at least one thread, got {n}")
    old = getattr(_local, "cap", None)
    _local.cap = n
    try:
        yield
    finally:
        if old is None:
            del _local.cap
        else:
            _local.cap = old


def _helper():
    """The helper pool (PARTS - 1 threads, started on first use) and its idle-slot semaphore."""
    global _pool, _idle
    with _lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(max_workers=PARTS - 1, thread_name_prefix="twin-helper")
            _idle = threading.BoundedSemaphore(PARTS - 1)
    return _pool, _idle


def on_idle_helper(fn, *args):
    """A future of fn(*args) on an idle helper thread, or None (no helper allowed or idle): for
    work that is worth splitting only when a second core is free now (the caller otherwise does
    it whole, its own way)."""
    if threads() < 2:
        return None
    pool, idle = _helper()
    if not idle.acquire(blocking=False):
        return None

    def run():
        try:
            return fn(*args)
        finally:
            idle.release()

    return pool.submit(run)


_BLAS: dict = {"controller": None, "depth": 0, "limit": None}   # one process-wide hold (see single_blas)
_BLAS_LOCK = threading.Lock()


@contextlib.contextmanager
def single_blas(active: bool = True):
    """BLAS held to one thread inside the block when ``active`` (module docstring); cheap enough
    (about 10 us) to wrap a single sparse solve.

    BLAS's thread count is one setting of the process, so the hold is counted, not stacked: the
    first block entered (in any thread) sets one thread, the last one left restores the count.
    Stacked holds restore out of order when two threads overlap (a helper's sparse solve ending
    inside the main thread's block gave its BLAS two threads back, and the run other bits)."""
    if not active:
        yield
        return
    with _BLAS_LOCK:
        if _BLAS["controller"] is None:
            from threadpoolctl import ThreadpoolController
            _BLAS["controller"] = ThreadpoolController()   # finding the libraries takes 0.5 ms: once
        if _BLAS["depth"] == 0:
            _BLAS["limit"] = _BLAS["controller"].limit(limits=1, user_api="blas")
        _BLAS["depth"] += 1
    try:
        yield
    finally:
        with _BLAS_LOCK:
            _BLAS["depth"] -= 1
            if _BLAS["depth"] == 0:
                _BLAS["limit"].restore_original_limits()
                _BLAS["limit"] = None


def concurrently(*tasks) -> list:
    """Run the callables ``tasks`` (no arguments) and return their results in order: the first in
    this thread, the others on an idle helper when there is one (else here, after it). An
    exception of any task is raised here once all have finished; an interrupt (Ctrl-C, or the
    CLI's SIGTERM) at once, the helper finishing its task alone (the process exits when it has)."""
    with single_blas():     # held before a helper starts: its own holds nest inside this one
        futures = [None] + [on_idle_helper(t) for t in tasks[1:]]
        results, errors = [], []
        for task, future in zip(tasks, futures):
            try:
                results.append(task() if future is None else None)
            except Exception as err:            # finish the others first: no task left running
                errors.append(err)
                results.append(None)
        for i, future in enumerate(futures):
            if future is not None:
                try:
                    results[i] = future.result()
                except Exception as err:
                    errors.append(err)
    if errors:
        raise errors[0]
    return results


def row_blocks(indptr: np.ndarray) -> list[slice]:
    """:data:`PARTS` row slices of a CSR matrix with row pointer ``indptr`` holding about equal
    stored entries (every row in exactly one)."""
    n, nnz = len(indptr) - 1, int(indptr[-1])
    cuts = [0] + [int(np.searchsorted(indptr, nnz * k / PARTS)) for k in range(1, PARTS)] + [n]
    cuts = np.minimum(np.maximum.accumulate(cuts), n)
    return [slice(int(a), int(b)) for a, b in zip(cuts[:-1], cuts[1:])]


def even_blocks(n: int) -> list[slice]:
    """:data:`PARTS` row slices of about equal length covering range(n)."""
    cuts = [n * k // PARTS for k in range(PARTS + 1)]
    return [slice(a, b) for a, b in zip(cuts[:-1], cuts[1:])]


def map_blocks(fn, blocks: list) -> list:
    """[fn(b) for b in blocks], the later blocks on an idle helper when there is one (else here)."""
    futures = [None] + [on_idle_helper(fn, b) for b in blocks[1:]]
    out = [fn(blocks[0])]
    for b, f in zip(blocks[1:], futures[1:]):
        out.append(fn(b) if f is None else f.result())
    return out


class RowBlocks:
    """A CSR matrix held as its :func:`row_blocks` (the blocks only: not the whole matrix beside
    them), whose products A X (X (n,) or (n, m)) are computed block by block, concurrently where
    a helper is idle: the same numbers as ``A @ X`` (each row is scipy's sum of that row)."""

    def __init__(self, A: sp.spmatrix):
        A = sp.csr_matrix(A)
        self.shape = A.shape
        self.rows = row_blocks(A.indptr)
        self.blocks = [A[s] for s in self.rows]

    def __matmul__(self, X):
        if np.ndim(X) == 1:         # one vector: each block's rows straight into the result
            out = np.empty(self.shape[0])
            map_blocks(lambda k: kernels.vector_product(self.blocks[k], X, out[self.rows[k]]), range(len(self.rows)))
            return out
        return np.concatenate(map_blocks(lambda A: A @ X, self.blocks), axis=0)


def split_matrix(A: sp.spmatrix):
    """``A`` as :class:`RowBlocks` when it is large enough to gain (:data:`SPLIT_FROM` stored
    entries), else itself."""
    return RowBlocks(A) if sp.issparse(A) and A.nnz >= SPLIT_FROM else A


def rows_product(V: np.ndarray, c: np.ndarray) -> np.ndarray:
    """V c for a dense V (n, r) over row blocks when large (:data:`SPLIT_FROM`): each row the same
    product as unsplit."""
    if V.shape[0] * V.shape[1] < SPLIT_FROM:
        return V @ c
    out = np.empty(V.shape[:1] + np.shape(c)[1:], dtype=np.result_type(V, c))
    map_blocks(lambda s: np.matmul(V[s], c, out=out[s]), even_blocks(V.shape[0]))
    return out


def transposed_product(V: np.ndarray, r: np.ndarray) -> np.ndarray:
    """V^T r for a dense V (n, k) over row blocks when large: the blocks' partial sums added in
    block order (a fixed order: the same numbers with one thread or two)."""
    if V.shape[0] * V.shape[1] < SPLIT_FROM:
        return V.T @ r
    parts = map_blocks(lambda s: V[s].T @ r[s], even_blocks(V.shape[0]))
    return sum(parts[1:], parts[0])
