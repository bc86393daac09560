"""The block kernels of :mod:`twin.physics.kernels` (numba) against their fallback (pyamg's
Gauss-Seidel column by column, scipy's sparse product), against closed forms, and the block
V-cycle and the block adjoint solves built on them."""

import numpy as np
import pytest
import scipy.sparse as sp

from twin.physics import kernels

needs_numba = pytest.mark.skipif(not kernels.HAVE_NUMBA, reason="numba not installed: only the fallback runs")


def _spd(n: int = 300, seed: int = 0) -> sp.csr_matrix:
    """A sparse SPD matrix with an irregular pattern (a random graph Laplacian plus a diagonal)."""
    rng = np.random.default_rng(seed)
    i, j = rng.integers(0, n, (2, 6 * n))
    W = sp.coo_matrix((rng.uniform(0.1, 1.0, i.size), (i, j)), shape=(n, n)).tocsr()
    W = W + W.T
    W.setdiag(0.0)
    W.eliminate_zeros()
    L = sp.diags(np.asarray(W.sum(axis=1)).ravel()) - W
    A = (L + sp.diags(rng.uniform(0.5, 2.0, n))).tocsr()
    A.sort_indices()
    return A


@needs_numba
@pytest.mark.parametrize("m", [2, 3, 4, 5, 8, 11])
@pytest.mark.parametrize("sweep", ["forward", "backward", "symmetric"])
def test_block_gauss_seidel_equals_pyamg_column_by_column(m, sweep):
    """Each column of the compiled block sweep is pyamg's one-column sweep,
    x_i <- (b_i - sum_(j != i) a_ij x_j) / a_ii in the same order: equal to round-off (the sums are
    the same sums in the same order; measured bit for bit), for widths below, at and above four
    and eight (the four- and the eight-column pass)."""
    A = _spd()
    rng = np.random.default_rng(1)
    X0, B = rng.standard_normal((2, A.shape[0], m))
    fast, slow = X0.copy(), X0.copy()
    kernels.gauss_seidel(A, fast, B, sweep)
    kernels.gauss_seidel(A, slow, B, sweep, use_numba=False)
    assert kernels.compiled(m, None)
    np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-14 * np.abs(slow).max())


@pytest.mark.parametrize("use_numba", [None, False])
def test_gauss_seidel_solves_a_triangular_system_in_one_sweep(use_numba):
    """Closed form: for a lower-triangular A one forward sweep is forward substitution,
    x = A^-1 b exactly; for an upper-triangular A one backward sweep is back substitution."""
    if use_numba is None and not kernels.HAVE_NUMBA:
        pytest.skip("numba not installed")
    A = _spd(200)
    rng = np.random.default_rng(2)
    B = rng.standard_normal((200, 5))
    for part, sweep in ((sp.tril(A).tocsr(), "forward"), (sp.triu(A).tocsr(), "backward")):
        part.sort_indices()
        X = rng.standard_normal(B.shape)               # the start does not matter for a triangular A
        kernels.gauss_seidel(part, X, B, sweep, use_numba=use_numba)
        np.testing.assert_allclose(part @ X, B, rtol=0, atol=1e-12 * np.abs(B).max())


@needs_numba
@pytest.mark.parametrize("m", [2, 4, 5, 8, 13])
def test_block_product_equals_scipys(m):
    """A X by the compiled kernel equals scipy's product, for a rectangular A (the prolongations
    and restrictions are), to round-off."""
    rng = np.random.default_rng(3)
    A = sp.random(170, 90, density=0.05, random_state=4, format="csr")
    X = rng.standard_normal((90, m))
    np.testing.assert_allclose(kernels.product(A, X), A @ X, rtol=0, atol=1e-14 * np.abs(A @ X).max())
    np.testing.assert_array_equal(kernels.product(A, X[:, 0]), A @ X[:, 0])


@needs_numba
@pytest.mark.parametrize("width", [kernels.HALF, kernels.WIDTH])
def test_vectorised_pass_is_the_scalar_pass_bit_for_bit(width):
    """The pass compiled with LLVM's SLP vectoriser (:func:`twin.compiled.compile_kernel`,
    ``vectorise=True``) against the same function compiled as numba does by default (scalar, no
    disk cache): product, forward and backward sweep give identical bits, and the vectorised
    kernel is filed under its own name in numba's cache."""
    import numba

    from twin.compiled import compile_kernel

    A = _spd(500, seed=11)
    arrays = kernels._csr(A)
    rng = np.random.default_rng(12)
    X, B = rng.standard_normal((2, A.shape[0], width))
    empty = np.empty((0, width))
    vectorised = compile_kernel(kernels._block_pass, vectorise=True)
    scalar = numba.njit(kernels._block_pass)
    assert vectorised.dispatcher.py_func.__qualname__ == "_block_pass_vectorised"
    for mode in (kernels.FORWARD, kernels.BACKWARD):
        fast, slow = X.copy(), X.copy()
        vectorised(*arrays, fast, B, empty, mode)
        scalar(*arrays, slow, B, empty, mode)
        np.testing.assert_array_equal(fast, slow)
    fast, slow = np.empty_like(X), np.empty_like(X)
    vectorised(*arrays, X, empty, fast, kernels.PRODUCT)
    scalar(*arrays, X, empty, slow, kernels.PRODUCT)
    np.testing.assert_array_equal(fast, slow)


_SLP_PROBE = """
import numpy as np, numba
from twin.compiled import compile_kernel
from twin.physics import kernels
import scipy.sparse as sp
A = (sp.random(60, 60, density=0.1, random_state=1) + sp.identity(60)).tocsr()
X, B, E = np.zeros((60, 8)), np.ones((60, 8)), np.empty((0, 8))
vectorised = compile_kernel(kernels._block_pass, vectorise=True)
for kernel, dispatcher in ((vectorised, vectorised.dispatcher), (numba.njit(kernels._block_pass),) * 2):
    kernel(*kernels._csr(A), X, B, E, kernels.FORWARD)
    print(sum(ir.count(" x double>") for ir in dispatcher.inspect_llvm().values()))
"""


@needs_numba
def test_vectorise_switches_the_slp_vectoriser_on_for_that_kernel_alone(tmp_path):
    """With ``vectorise=True`` the pass's optimised LLVM code holds vector types (<k x double>),
    compiled as numba does by default it holds none: the switch acts, and only where asked. Run
    in a fresh process with an empty numba cache (code loaded from the cache cannot be
    inspected)."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", _SLP_PROBE], env=env, capture_output=True, text=True, check=True)
    vectorised, scalar = (int(line) for line in out.stdout.split())
    assert vectorised > 0 and scalar == 0


@needs_numba
@pytest.mark.parametrize("sweep", ["forward", "backward"])
def test_unsigned_index_view_changes_no_bit(sweep):
    """A matrix with 32-bit indices goes to the kernel through unsigned views of them (no
    wrap-around checks), one with 64-bit indices as it is: both give the same bits, sweep and
    product, so the view changes the speed and nothing else."""
    A = _spd(300, seed=9)
    wide = A.copy()
    wide.indptr, wide.indices = A.indptr.astype(np.int64), A.indices.astype(np.int64)
    assert A.indices.dtype == np.int32 and kernels._csr(A)[1].dtype == np.uint32
    assert kernels._csr(wide)[1].dtype == np.int64
    rng = np.random.default_rng(10)
    X, B = rng.standard_normal((2, A.shape[0], 5))
    X64 = X.copy()
    kernels.gauss_seidel(A, X, B, sweep)
    kernels.gauss_seidel(wide, X64, B, sweep)
    np.testing.assert_array_equal(X, X64)
    np.testing.assert_array_equal(kernels.product(A, B), kernels.product(wide, B))


@needs_numba
@pytest.mark.parametrize("sweep", ["forward", "symmetric"])
def test_four_column_pass_is_the_eight_column_pass_bit_for_bit(sweep):
    """The four-column pass does each column's arithmetic exactly as the eight-column one (the
    same products and sums in the same order): a block's first four columns swept, or multiplied,
    as a block of four equal those columns of the block of eight bit for bit. Splitting a V-cycle
    into two halves therefore cannot change a number."""
    A = _spd(400, seed=7)
    rng = np.random.default_rng(8)
    X8, B8 = rng.standard_normal((2, A.shape[0], 8))
    X4 = np.ascontiguousarray(X8[:, 4:])
    kernels.gauss_seidel(A, X8, B8, sweep)
    kernels.gauss_seidel(A, X4, np.ascontiguousarray(B8[:, 4:]), sweep)
    np.testing.assert_array_equal(X4, X8[:, 4:])
    np.testing.assert_array_equal(kernels.product(A, np.ascontiguousarray(B8[:, :4])), kernels.product(A, B8)[:, :4])


def test_gauss_seidel_refuses_an_unknown_sweep():
    with pytest.raises(ValueError, match="sweep"):
        kernels.gauss_seidel(_spd(20), np.zeros((20, 2)), np.ones((20, 2)), "sideways")


@pytest.mark.parametrize("smoothers", [{}, {"presmoother": ("gauss_seidel", {"sweep": "forward"}),
                                            "postsmoother": ("gauss_seidel", {"sweep": "backward"})}])
def test_block_v_cycle_equals_the_cycle_column_by_column(smoothers, monkeypatch):
    """amg_cycle on a block (n, m) takes every level as one block through the kernels; each of its
    columns is the one-vector cycle to round-off, with and without numba (then column by column)."""
    import pyamg

    from twin.physics.solvers import amg_cycle
    A = (pyamg.gallery.poisson((10, 10, 10), format="csr") + 1e-3 * sp.eye(1000)).tocsr()
    ml = pyamg.smoothed_aggregation_solver(A, symmetry="hermitian", max_coarse=50, coarse_solver="splu", **smoothers)
    R = np.random.default_rng(5).standard_normal((1000, 6))
    cycle = amg_cycle(ml)
    one = np.column_stack([cycle(R[:, j]) for j in range(6)])
    np.testing.assert_allclose(cycle(R), one, rtol=0, atol=1e-13 * np.abs(one).max())
    monkeypatch.setattr(kernels, "HAVE_NUMBA", False)
    np.testing.assert_array_equal(amg_cycle(ml)(R), one)


@needs_numba
def test_v_cycle_split_over_two_threads_gives_the_same_bits(monkeypatch):
    """A block of five to eight columns goes through two four-column cycles side by side when a
    helper thread is idle, else through one eight-column cycle: the result is the same bits
    either way (each column's arithmetic does not depend on the block's width), so a run's
    numbers do not depend on whether the second core happened to be free. The helper is replaced
    here by one that runs at once (so the split is taken on any machine, and counted)."""
    from concurrent.futures import Future

    import pyamg

    from twin.physics import parallel
    from twin.physics.solvers import amg_cycle

    A = (pyamg.gallery.poisson((10, 10, 10), format="csr") + 1e-3 * sp.eye(1000)).tocsr()
    ml = pyamg.smoothed_aggregation_solver(A, symmetry="hermitian", max_coarse=50, coarse_solver="splu")
    R = np.random.default_rng(9).standard_normal((1000, 7))
    monkeypatch.setattr(parallel, "SPLIT_FROM", 0)
    calls = []

    def at_once(fn, *args):
        calls.append(args[-1].shape)
        done = Future()
        done.set_result(fn(*args))
        return done

    monkeypatch.setattr(parallel, "on_idle_helper", lambda fn, *args: None)
    whole = amg_cycle(ml)(R)
    monkeypatch.setattr(parallel, "on_idle_helper", at_once)
    split = amg_cycle(ml)(R)
    assert calls == [(1000, 4)]
    np.testing.assert_array_equal(split, whole)
    monkeypatch.setattr(parallel, "SPLIT_FROM", A.nnz + 1)       # a small level is not split
    np.testing.assert_array_equal(amg_cycle(ml)(R), whole)
    assert len(calls) == 1


def test_block_adjoints_equal_the_direct_ones_within_their_tolerance():
    """The elastic adjoints of several outputs solved as one block by AMG-CG equal the direct
    solves to the relative residual asked (||K x - f|| <= rtol ||f|| per column, so
    ||x - x_direct|| <= cond(K) rtol ||x||; checked at rtol 1e-10 to 1e-6 relative), the columns
    of an all-zero load stay zero, and one block is one CG run."""
    from geometries import build_machine
    from twin.fem.mesh import mesh_machine
    from twin.physics.elastic import ElasticSolver

    mm = mesh_machine(build_machine("cframe-vmc"), "coarse")
    direct = ElasticSolver.build(mm, method="direct")
    amg = ElasticSolver.build(mm, method="amg", rtol=1e-10)
    rng = np.random.default_rng(6)
    F = rng.standard_normal((3 * mm.nnodes, 4))
    F[:, 2] = 0.0
    x_amg, x_lu = amg.solve(F), direct.solve(F)
    assert not x_amg[:, 2].any()
    live = [0, 1, 3]
    rel = np.linalg.norm(x_amg[:, live] - x_lu[:, live], axis=0) / np.linalg.norm(x_lu[:, live], axis=0)
    assert rel.max() < 1e-6
    assert len(amg._lu.iterations) == 1


@needs_numba
def test_fused_jacobi_pcg_is_the_numpy_iteration_up_to_the_order_of_its_sums(monkeypatch):
    """One-column Jacobi-PCG on the compiled passes (P . Q; X += alpha P, R -= alpha Q, Z = D^-1 R
    with sum w R^2 and R . Z; P = beta P + Z) against the numpy iteration: the same number of
    iterations and the same solution to round-off (only the order of the sums differs), the final
    residual equal to b - A x to round-off, and the same bits with one thread or two (the two row
    blocks' partial sums are added in a fixed order)."""
    from twin.physics import parallel
    from twin.physics.solvers import jacobi, pcg

    monkeypatch.setattr(kernels, "CG_FUSED_FROM", 0)
    A = _spd(2001, seed=4)
    rng = np.random.default_rng(5)
    b, x0 = rng.standard_normal((2, A.shape[0]))
    w = rng.uniform(0.5, 2.0, A.shape[0])
    dinv = 1.0 / A.diagonal()
    apply = lambda v: A @ v
    tol = 1e-10 * float(np.sqrt(w @ (b * b)))
    x, it, rho, R = pcg(apply, b, x0, jacobi(dinv), w, tol, residual=True)
    xs, its, rhos, Rs = pcg(apply, b, x0, lambda r: dinv[:, None] * r, w, tol, residual=True)   # numpy path
    assert it == its > 5 and rho <= tol and rhos <= tol
    assert np.allclose(x, xs, rtol=0, atol=1e-9 * np.abs(xs).max())
    assert np.allclose(R, b - A @ x, rtol=0, atol=1e-9 * np.abs(b).max())
    with parallel.limited(1):
        x1, it1, rho1, R1 = pcg(apply, b, x0, jacobi(dinv), w, tol, residual=True)
    assert it1 == it and rho1 == rho and np.array_equal(x1, x) and np.array_equal(R1, R)
    with pytest.raises(RuntimeError, match="did not converge in 2 iterations"):
        pcg(apply, b, x0, jacobi(dinv), w, tol, max_iterations=2)


@needs_numba
def test_block_pcg_on_compiled_passes_is_the_numpy_iteration_up_to_the_order_of_its_sums(monkeypatch):
    """A block PCG (five columns, an AMG V-cycle as preconditioner) with its vector work on the
    compiled passes (the columns' sums; X += alpha P, R -= alpha Q with sum w R^2; P = beta P + Z)
    against the array operations: the same iterations, the same solution and residual to
    round-off (only the order of the sums differs), a column that starts converged left as it is,
    and the same bits with one thread or two."""
    from twin.physics import parallel, solvers
    from twin.physics.solvers import amg_cycle, pcg, smoothed_aggregation

    A = _spd(3001, seed=13)
    rng = np.random.default_rng(14)
    B = rng.standard_normal((A.shape[0], 5))
    B[:, 4] = 0.0                                   # converged from the start: stays zero
    w = rng.uniform(0.5, 2.0, A.shape[0])
    cycle = amg_cycle(smoothed_aggregation(A, max_coarse=50))
    tol = 1e-9 * np.sqrt(w @ (B * B))
    apply = lambda U: A @ U
    monkeypatch.setattr(kernels, "CG_FUSED_FROM", 10 ** 9)
    xs, its, rhos, Rs = pcg(apply, B, np.zeros_like(B), cycle, w, tol, residual=True)
    monkeypatch.setattr(kernels, "CG_FUSED_FROM", 0)
    used, original = [], solvers._BlockWork.__init__
    monkeypatch.setattr(solvers._BlockWork, "__init__", lambda self, w: used.append(1) or original(self, w))
    x, it, rho, R = pcg(apply, B, np.zeros_like(B), cycle, w, tol, residual=True)
    assert used and it == its > 3 and (rho <= tol).all() and (rhos <= tol).all()
    np.testing.assert_allclose(x, xs, rtol=0, atol=1e-10 * np.abs(xs).max())
    np.testing.assert_allclose(R, B - A @ x, rtol=0, atol=1e-9 * np.abs(B).max())
    assert not x[:, 4].any() and rho[4] == 0.0
    with parallel.limited(1):
        x1, it1, rho1, R1 = pcg(apply, B, np.zeros_like(B), cycle, w, tol, residual=True)
    assert it1 == it and np.array_equal(rho1, rho) and np.array_equal(x1, x) and np.array_equal(R1, R)


def test_fused_cg_is_used_only_from_its_size_and_with_numba(monkeypatch):
    assert not kernels.fused_cg(kernels.CG_FUSED_FROM - 1)
    assert kernels.fused_cg(kernels.CG_FUSED_FROM) == kernels.HAVE_NUMBA
    assert not kernels.fused_cg(10 ** 6, use_numba=False)
    monkeypatch.setattr(kernels, "HAVE_NUMBA", False)
    assert not kernels.fused_cg(10 ** 6)


@pytest.mark.parametrize("m, width", [(1, 4), (3, 4), (4, 4), (5, 8), (7, 8), (8, 8), (9, 16), (16, 16)])
def test_as_block_pads_to_whole_passes_and_copies_only_when_it_must(m, width):
    """:func:`kernels.as_block`: X's columns then zeros up to four columns or whole passes of
    eight, C-ordered; a block already so is returned itself (no copy), a view of one is copied."""
    X = np.arange(6.0 * m).reshape(6, m)
    B = kernels.as_block(X)
    assert kernels.block_width(m) == width and B.shape == (6, width) and B.flags.c_contiguous
    np.testing.assert_array_equal(B[:, :m], X)
    assert not B[:, m:].any()
    assert kernels.as_block(B) is B
    assert (B is X) == (m == width)
    wide = np.zeros((6, width + 2))
    assert kernels.as_block(wide[:, :width]) is not wide


@pytest.mark.parametrize("have_numba", [True, False])
def test_vector_product_is_scipys_sum_bit_for_bit(have_numba, monkeypatch):
    """:func:`kernels.vector_product`: each row's sum in stored order, scipy's (the compiled pass on
    unsigned index views, or scipy's own product without numba), into the given array; on a
    rectangular block of rows, as :class:`twin.physics.parallel.RowBlocks` holds them."""
    if have_numba and not kernels.HAVE_NUMBA:
        pytest.skip("numba not installed")
    monkeypatch.setattr(kernels, "HAVE_NUMBA", have_numba)
    A = sp.random(300, 500, density=0.03, random_state=6, format="csr")
    x = np.random.default_rng(7).standard_normal(500)
    out = np.full(300, np.nan)
    assert kernels.vector_product(A, x, out) is out
    np.testing.assert_array_equal(out, A @ x)
