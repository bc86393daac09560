"""The GPU's own kernels (:mod:`twin.physics.gpu_cg`) against CuPy's array path and the CPU.
Every test skips without CuPy and a CUDA device (CI has none); they run where a GPU is lent
(README "Scale": the measurements name the machine)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from tests.test_heat_steps import _cooled_slab
from twin.physics import gpu_cg
from twin.physics.heat import integrate
from twin.physics.solvers import jacobi, pcg
from twin.physics.steppers import IterativeStepper


def _cuda():
    """(cupy, cupyx.scipy.sparse), or skip the calling test without CuPy and a CUDA device."""
    cupy = pytest.importorskip("cupy")
    try:
        cupy.cuda.runtime.getDeviceCount()
    except Exception:  # noqa: BLE001
        pytest.skip("no CUDA device")
    import cupyx.scipy.sparse as csp
    return cupy, csp


def _spd(n: int, seed: int) -> sp.csr_matrix:
    """A random sparse SPD matrix: symmetric, strictly diagonally dominant with a positive diagonal."""
    A = sp.random(n, n, density=5e-4, random_state=seed)
    A = A + A.T
    return (A + sp.diags(np.asarray(abs(A).sum(axis=1)).ravel() + 0.05)).tocsr()


def test_gpu_fused_cg_is_the_array_path_to_round_off():
    """twin.physics.gpu_cg's five kernels an iteration do CG's arithmetic (alpha = r.z / p.Ap,
    beta = r.z_new / r.z_old) with the sums in another order: on an SPD system the same iterations
    as CuPy's array path and as the CPU, the same solution and final residual to round-off, and
    the same numbers on every run (sums in a fixed order). Skipped without CuPy and a CUDA device."""
    cupy, csp = _cuda()
    n = 20_000                      # several blocks and the strided loops of a launch
    A = _spd(n, 3)
    b, w, dinv = np.random.default_rng(4).standard_normal(n), np.full(n, 2.0), 1.0 / A.diagonal()
    cpu = pcg(lambda v: A @ v, b, np.zeros(n), jacobi(dinv), w, 1e-9, residual=True)
    Ag, bg, wg, dg = csp.csr_matrix(A), cupy.asarray(b), cupy.asarray(w), cupy.asarray(dinv)
    arrays = pcg(lambda v: Ag @ v, bg, cupy.zeros(n), jacobi(dg), wg, 1e-9, cupy, residual=True)
    fused = [gpu_cg.jacobi_pcg(Ag, bg, cupy.zeros(n), dg, wg, 1e-9, 2000, True) for _ in range(2)]
    assert fused[0][1] == arrays[1] == cpu[1] > 10
    x, r = cupy.asnumpy(fused[0][0]), cupy.asnumpy(fused[0][3])
    np.testing.assert_allclose(x, cpu[0], rtol=0, atol=1e-10 * np.abs(cpu[0]).max())
    np.testing.assert_allclose(x, cupy.asnumpy(arrays[0]), rtol=0, atol=1e-10 * np.abs(cpu[0]).max())
    np.testing.assert_allclose(r, b - A @ x, rtol=0, atol=1e-9 * np.abs(b).max())     # the recurrence's residual
    assert fused[0][2] <= 1e-9 and np.array_equal(x, cupy.asnumpy(fused[1][0]))      # deterministic
    with pytest.raises(RuntimeError, match="did not converge in 3"):
        gpu_cg.jacobi_pcg(Ag, bg, cupy.zeros(n), dg, wg, 1e-9, 3, False)


def test_gpu_heat_steps_equal_cpu_ones(monkeypatch):
    """The heat steps on the GPU's fused CG kernels and on CuPy's array path (the same PCG code
    on CuPy arrays) equal the CPU's (skipped without CuPy and a CUDA device)."""
    _cuda()
    _, system, n, args = _cooled_slab(50)
    cpu = integrate(system, *args, stepper=IterativeStepper(heat_tol=1e-6))
    gpu = integrate(system, *args, stepper=IterativeStepper(heat_tol=1e-6, device="gpu"))
    np.testing.assert_allclose(gpu, cpu, atol=1e-8)
    monkeypatch.setattr(gpu_cg, "FUSED", False)
    arrays = integrate(system, *args, stepper=IterativeStepper(heat_tol=1e-6, device="gpu"))
    np.testing.assert_allclose(arrays, cpu, atol=1e-8)


def test_gpu_reduced_start_equals_cpu_one():
    """The start from a fixed basis on CuPy arrays: the same steps as on the CPU (skipped without
    CuPy and a CUDA device)."""
    _cuda()
    from twin.physics.steppers import ReducedStart
    _, system, n, args = _cooled_slab(50)
    V = np.random.default_rng(2).standard_normal((n, 6))
    out = []
    for device in ("cpu", "gpu"):
        stepper = IterativeStepper(heat_tol=1e-6, device=device)
        stepper.start = ReducedStart(V, stepper.xp)
        out.append(integrate(system, *args, stepper=stepper))
    np.testing.assert_allclose(out[1], out[0], atol=1e-8)


def test_device_matrix_products_equal_scipys():
    """y = A x by the warp-a-row kernel (blocks of vectors through cupyx): scipy's product within
    the dot product's rounding bound k eps |a| . |x| for a row a of k entries (each row's sum in
    another order); a matrix with a row longer than LONG_ROW (an output row over the whole
    machine) stays with cuSPARSE."""
    cupy, csp = _cuda()
    n = 30_000
    rng = np.random.default_rng(5)
    short = sp.random(7, n, density=0.002, random_state=7).tocsr()
    x, X = rng.standard_normal(n), rng.standard_normal((n, 3))
    eps = np.finfo(float).eps
    for M in (_spd(n, 6), short, sp.csr_matrix((4, n))):
        D = gpu_cg.device_matrix(M)
        assert isinstance(D, gpu_cg.DeviceMatrix)
        length = np.diff(M.indptr)[:, None]
        for v in (x, X):
            got = cupy.asnumpy(D @ cupy.asarray(v))
            assert got.shape == (M @ v).shape
            bound = length * eps * (abs(M) @ np.abs(v)).reshape(len(length), -1)
            assert np.all(np.abs(got - M @ v).reshape(len(length), -1) <= bound)
    whole = sp.vstack([short, sp.csr_matrix(rng.random((1, n)))]).tocsr()
    assert isinstance(gpu_cg.device_matrix(whole), csp.csr_matrix)


def _gpu_present() -> bool:
    try:
        import cupy
        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:  # noqa: BLE001
        return False


@pytest.mark.skipif(_gpu_present(), reason="a CUDA device is present: the commands would run")
def test_gpu_commands_without_a_gpu_are_one_clear_error(tmp_path, capsys):
    """Without CuPy or a device, `--device gpu` and `python -m validate.gpu_step_benchmark` are refused with
    one line and exit code 2 before any mesh is built or output written (CI's case)."""
    from twin.cli import main as twin_main
    from validate import gpu_step_benchmark

    assert gpu_step_benchmark.main(["--spacing", "60mm"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["error: command line: python -m validate.gpu_step_benchmark: needs CuPy (pip install cupy-cuda12x) "
                   "and a CUDA GPU"]
    out = tmp_path / "x.nc"
    assert twin_main(["simulate", "cframe-vmc", "spindle-duty-cycle", "--mesh", "coarse", "--device", "gpu",
                      "-o", str(out)]) == 2
    assert "--device: gpu needs CuPy" in capsys.readouterr().err and not out.exists()


@pytest.mark.parametrize("argv, needle", [
    (["--spacing", "3"], "command line: --spacing: '3' has no unit"),
    (["--repeats", "0"], "command line: --repeats: must be from 1 to 100000"),
    (["--repeats", "5", "--repeats", "6"], "command line: --repeats: given more than once"),
    (["--bogus"], "unrecognized arguments"),
])
def test_gpu_step_benchmark_refuses_bad_options_on_any_machine(argv, needle, capsys):
    """Its options are checked before the device is asked for: one line, exit code 2."""
    from validate import gpu_step_benchmark

    assert gpu_step_benchmark.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and needle in err[0], err
