"""The second core (:mod:`twin.physics.parallel`): products over row blocks equal the unsplit
ones bit for bit, the split reduction is the same with one thread or two, independent tasks run
beside each other and fail cleanly, and a whole run gives the same bits whatever the threads
(the property the dataset's identical case files rely on)."""

from __future__ import annotations

import threading

import numpy as np
import pytest
import scipy.sparse as sp

from twin.physics import parallel


def _matrix(n: int = 3000, seed: int = 0) -> sp.csr_matrix:
    """A random sparse matrix with rows of very different lengths (the split balances entries)."""
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=4.0 / n, format="csr", random_state=rng)
    A = A + sp.diags(rng.random(n) + 1.0) + sp.csr_matrix((rng.random(2000), (np.zeros(2000, int), rng.integers(0, n, 2000))), shape=(n, n))
    return sp.csr_matrix(A)


def test_row_blocks_cover_every_row_once_and_balance_the_entries():
    A = _matrix()
    blocks = parallel.row_blocks(A.indptr)
    assert len(blocks) == parallel.PARTS
    assert blocks[0].start == 0 and blocks[-1].stop == A.shape[0]
    assert all(a.stop == b.start for a, b in zip(blocks[:-1], blocks[1:]))
    counts = [A.indptr[b.stop] - A.indptr[b.start] for b in blocks]
    assert max(counts) - min(counts) <= 2 * np.diff(A.indptr).max()    # off by at most a row's entries


@pytest.mark.parametrize("shape", [(), (1,), (5,)])
def test_split_product_is_the_unsplit_one_bit_for_bit(shape):
    """Each row of [A_1 X; A_2 X] is the same sum as in A X: exact, with one thread or two."""
    A = _matrix()
    X = np.random.default_rng(1).random((A.shape[0],) + shape)
    split = parallel.RowBlocks(A)
    assert np.array_equal(split @ X, A @ X)
    with parallel.limited(1):
        assert np.array_equal(split @ X, A @ X)


def test_dense_passes_are_the_same_with_one_thread_or_two(monkeypatch):
    """V c by rows equals the unsplit product row for row; V^T r adds the blocks' partial sums
    in a fixed order: identical with one thread or two, and equal to V^T r to round-off."""
    monkeypatch.setattr(parallel, "SPLIT_FROM", 0)
    rng = np.random.default_rng(2)
    V = np.asfortranarray(rng.standard_normal((20001, 7)).astype(np.float32))
    r = rng.standard_normal(20001).astype(np.float32)
    c = rng.standard_normal(7).astype(np.float32)
    two = parallel.transposed_product(V, r), parallel.rows_product(V, c)
    with parallel.limited(1):
        one = parallel.transposed_product(V, r), parallel.rows_product(V, c)
    assert np.array_equal(one[0], two[0]) and np.array_equal(one[1], two[1])
    ref = V.astype(float).T @ r.astype(float)
    scale = np.abs(V).T.astype(float) @ np.abs(r).astype(float)
    assert np.all(np.abs(two[0] - ref) <= 1e-5 * scale)          # float32 sums of 20 k terms
    assert np.allclose(two[1], V @ c, rtol=1e-5, atol=1e-5)


def test_tasks_run_beside_each_other_and_return_in_order():
    """With two threads the second task runs on the helper while the first runs here (both wait
    for each other: only concurrent execution lets them finish); results in the tasks' order."""
    if parallel.threads() < 2:
        pytest.skip("one core: the tasks run one after the other")
    barrier = threading.Barrier(2, timeout=30)
    idents = []

    def task(value):
        def run():
            idents.append(threading.get_ident())
            barrier.wait()
            return value
        return run

    assert parallel.concurrently(task("a"), task("b")) == ["a", "b"]
    assert len(set(idents)) == 2


def test_limited_to_one_thread_runs_every_task_here():
    idents = []
    with parallel.limited(1):
        out = parallel.concurrently(lambda: idents.append(threading.get_ident()) or 1,
                                    lambda: idents.append(threading.get_ident()) or 2)
    assert out == [1, 2] and set(idents) == {threading.get_ident()}


def test_a_failing_task_is_raised_after_the_others_finish():
    done = []

    def slow():
        threading.Event().wait(0.2)
        done.append(True)
        return 1

    def fail():
        raise ValueError("broken task")

    with pytest.raises(ValueError, match="broken task"):
        parallel.concurrently(fail, slow)
    assert done == [True]


def test_a_task_on_the_helper_splits_its_products_without_waiting_on_itself():
    """Nested use: a task running on the helper that splits a product finds no idle helper and
    computes both blocks itself (a queue behind a busy helper would deadlock)."""
    M = _matrix()
    A = parallel.RowBlocks(M)
    x = np.ones(A.shape[0])
    out = parallel.concurrently(lambda: A @ x, lambda: A @ x)
    assert np.array_equal(out[0], M @ x) and np.array_equal(out[1], M @ x)


def test_limited_refuses_zero_threads():
    with pytest.raises(ValueError, match="at least one thread"):
        with parallel.limited(0):
            pass


def test_a_large_run_gives_the_same_bits_whatever_the_threads(monkeypatch):
    """The coarse C-frame, iterative heat steps started from the reduced basis, treated as large
    (every product split, the rows and the basis built concurrently): the readings with the
    helper thread equal those without it bit for bit, and both equal the unsplit run to its
    verified solver bound (the split reduction V^T r and BLAS on one thread change round-off)."""
    from geometries import build_machine
    from twin.fem.mesh import mesh_machine
    from twin.model import model_spec
    from twin.observe import HeatBalance, TemperatureSensors, ToolDrift, sensor_points
    from twin.physics.prepared import PreparedTwin
    from twin.physics.options import SolverOptions
    from twin.scenario import Ambient, Scenario

    machine = build_machine("cframe-vmc")
    mm = mesh_machine(machine, "coarse")
    scenario = Scenario("short", ((1200.0, 9000.0), (900.0, 0.0)), Ambient("daily", 20.0, 2.0), 60.0)
    observers = [TemperatureSensors(sensor_points(machine)), ToolDrift(), HeatBalance()]
    spec = model_spec(machine)

    def run():
        twin = PreparedTwin(machine, mm, solver=SolverOptions("iterative", heat_start="reduced", heat_tol=1e-5))
        _, readings = twin.run(scenario, spec, observers)
        return twin, readings

    _, plain = run()
    monkeypatch.setattr(parallel, "SPLIT_FROM", 0)
    monkeypatch.setattr(parallel, "CONCURRENT_FROM", 0)
    twin, two = run()
    assert twin.prepare_s["concurrent"] == (parallel.threads() > 1)
    assert {"elastic_assembly", "adjoints", "rows", "basis", "wall"} <= set(twin.prepare_s)
    with parallel.limited(1):
        twin1, one = run()
    assert twin1.prepare_s["concurrent"] is False
    for key in plain:
        assert np.array_equal(one[key], two[key]), key
    bounds = twin.run_info["solver_error_bound"]
    for key in ("temperature", "drift"):
        err = np.abs(np.asarray(two[key]) - np.asarray(plain[key])).max(axis=0)
        assert np.all(err <= 2 * np.asarray(bounds[key])), key



def test_an_interrupt_is_raised_at_once_without_waiting_for_the_helper():
    """Ctrl-C in this thread's task answers at once; the helper's task finishes alone."""
    if parallel.threads() < 2:
        pytest.skip("one core: no helper to wait for")
    release = threading.Event()
    finished = threading.Event()

    def helper_task():
        release.wait(30)
        finished.set()

    def interrupted():
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        parallel.concurrently(interrupted, helper_task)
    assert not finished.is_set()        # raised while the helper still worked
    release.set()
    assert finished.wait(30)
