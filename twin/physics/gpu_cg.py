"""One-column Jacobi-PCG on a CUDA GPU in five fused kernels an iteration (CuPy raw kernels).

:func:`twin.physics.solvers.pcg` on CuPy arrays runs each vector update, dot product and
``where`` of an iteration as its own kernel: about twenty launches, each with a few tens of
microseconds of Python and driver work, so that on an H100 an iteration cost 0.8-0.9 ms at 200 k
and at 890 k unknowns alike while its bytes need about 0.15 ms (validate/SCALE.md). Here the same
iteration (the same arithmetic as the CPU's compiled :func:`twin.physics.kernels.cg_kernels`) is

1. ``spmv_dot``: Q = A P (one warp a row of the CSR matrix) with the blocks' partial sums of P . Q;
2. ``finish``: the partial sums added in block order (one block), written to a scalar slot;
3. ``cg_update``: alpha = (r.z) / (p.q) read on the device; X += alpha P, R -= alpha Q,
   Z = D^-1 R over Q, with the partial sums of w R^2 and R . Z;
4. ``finish`` again (rho^2 and the new r.z), the only value read back: rho, for the test;
5. ``cg_direction``: beta = (r.z)_new / (r.z)_old on the device; P = beta P + Z.

Measured on an H200 at 200 k unknowns: 0.081 ms an iteration against 0.601 ms on CuPy's arrays
(validate/SCALE.md). :class:`DeviceMatrix` makes the step's other products with a heat matrix one
launch of the same warp-a-row product. Every sum is formed in a fixed order (each block's tree,
then the blocks in order), so a run gives the same numbers every time; they differ from CuPy's
array path in the order of the sums only (``tests/test_gpu_kernels.py`` holds them to it and to
the CPU's at 1e-8 K). CuPy is imported by the caller
(:func:`twin.physics.solvers.array_module`); nothing here runs without a GPU.
"""

from __future__ import annotations

import math

FUSED = True            # False: CuPy's array operations and cuSPARSE instead (to compare: benchmark --gpu-kernels)
BLOCK = 256             # threads a block (a power of two: the tree sums halve it)
MAX_BLOCKS = 1024       # blocks of a launch; loops stride over the rest (about 8 blocks per SM on an H100)

_SOURCE = r"""
#define BLOCK 256

__device__ __forceinline__ void block_tree(double& s1, double& s2) {
    // the block's sums of s1 and s2 by a tree in shared memory, in a fixed order; every thread gets them
    __shared__ double a1[BLOCK];
    __shared__ double a2[BLOCK];
    int t = threadIdx.x;
    a1[t] = s1;
    a2[t] = s2;
    __syncthreads();
    for (int k = BLOCK / 2; k > 0; k >>= 1) {
        if (t < k) { a1[t] += a1[t + k]; a2[t] += a2[t + k]; }
        __syncthreads();
    }
    s1 = a1[0];
    s2 = a2[0];
}

__device__ __forceinline__ void block_sums(double s1, double s2, double* parts) {
    // the block's two partial sums to parts[b] and parts[gridDim.x + b]
    block_tree(s1, s2);
    if (threadIdx.x == 0) { parts[blockIdx.x] = s1; parts[gridDim.x + blockIdx.x] = s2; }
}

__device__ __forceinline__ double warp_row(const int* indptr, const int* indices, const double* data,
                                           const double* x, long row, int lane) {
    // (A x)_row by the 32 lanes of a warp, the lanes' products added by shuffles (every lane returns it)
    double s = 0.0;
    for (int k = indptr[row] + lane; k < indptr[row + 1]; k += 32) s += data[k] * x[indices[k]];
    for (int o = 16; o > 0; o >>= 1) s += __shfl_down_sync(0xffffffff, s, o);
    return __shfl_sync(0xffffffff, s, 0);
}

extern "C" __global__ void residual(const int* indptr, const int* indices, const double* data,
                                    const double* x, const double* b, double* r, long n) {
    // r = b - A x
    long warps = (long)gridDim.x * (BLOCK / 32);
    int lane = threadIdx.x & 31;
    for (long row = (long)blockIdx.x * (BLOCK / 32) + threadIdx.x / 32; row < n; row += warps) {
        double ax = warp_row(indptr, indices, data, x, row, lane);
        if (lane == 0) r[row] = b[row] - ax;
    }
}

extern "C" __global__ void product(const int* indptr, const int* indices, const double* data,
                                   const double* x, double* y, long n) {
    // y = A x
    long warps = (long)gridDim.x * (BLOCK / 32);
    int lane = threadIdx.x & 31;
    for (long row = (long)blockIdx.x * (BLOCK / 32) + threadIdx.x / 32; row < n; row += warps) {
        double ax = warp_row(indptr, indices, data, x, row, lane);
        if (lane == 0) y[row] = ax;
    }
}

extern "C" __global__ void spmv_dot(const int* indptr, const int* indices, const double* data,
                                    const double* p, double* q, long n, double* parts) {
    // q = A p; the block's partial sum of p . q
    long warps = (long)gridDim.x * (BLOCK / 32);
    int lane = threadIdx.x & 31;
    double s = 0.0;
    for (long row = (long)blockIdx.x * (BLOCK / 32) + threadIdx.x / 32; row < n; row += warps) {
        double ap = warp_row(indptr, indices, data, p, row, lane);
        if (lane == 0) { q[row] = ap; s += p[row] * ap; }
    }
    block_sums(s, 0.0, parts);
}

extern "C" __global__ void jacobi_start(const double* r, const double* w, const double* dinv, double* z,
                                        long n, double* parts) {
    // z = D^-1 r; the block's partial sums of w r^2 and r . z
    double s1 = 0.0, s2 = 0.0;
    for (long i = (long)blockIdx.x * BLOCK + threadIdx.x; i < n; i += (long)gridDim.x * BLOCK) {
        double ri = r[i], zi = dinv[i] * ri;
        z[i] = zi;
        s1 += w[i] * ri * ri;
        s2 += ri * zi;
    }
    block_sums(s1, s2, parts);
}

extern "C" __global__ void cg_update(double* x, double* r, const double* p, double* q, const double* w,
                                     const double* dinv, const double* scal, int pq_slot, int rz_slot,
                                     long n, double* parts) {
    // alpha = rz / pq; x += alpha p, r -= alpha q, then z = D^-1 r over q; partial sums of w r^2, r . z
    double pq = scal[pq_slot];
    double alpha = scal[rz_slot] / (pq > 0.0 ? pq : 1.0);
    double s1 = 0.0, s2 = 0.0;
    for (long i = (long)blockIdx.x * BLOCK + threadIdx.x; i < n; i += (long)gridDim.x * BLOCK) {
        x[i] += alpha * p[i];
        double ri = r[i] - alpha * q[i];
        r[i] = ri;
        double zi = dinv[i] * ri;
        q[i] = zi;
        s1 += w[i] * ri * ri;
        s2 += ri * zi;
    }
    block_sums(s1, s2, parts);
}

extern "C" __global__ void cg_direction(double* p, const double* z, const double* scal, int new_slot,
                                        int old_slot, long n) {
    // beta = rz_new / rz_old; p = beta p + z
    double old = scal[old_slot];
    double beta = scal[new_slot] / (old > 0.0 ? old : 1.0);
    for (long i = (long)blockIdx.x * BLOCK + threadIdx.x; i < n; i += (long)gridDim.x * BLOCK)
        p[i] = beta * p[i] + z[i];
}

extern "C" __global__ void finish(const double* parts, int nparts, double* scal, int slot0, int slot1) {
    // one block: the two sums of the partials of a launch of nparts blocks, in block order, to
    // scal[slot0] and scal[slot1] (slot1 < 0: the second is not kept)
    double s1 = 0.0, s2 = 0.0;
    for (int i = threadIdx.x; i < nparts; i += BLOCK) { s1 += parts[i]; s2 += parts[nparts + i]; }
    block_tree(s1, s2);
    if (threadIdx.x == 0) { scal[slot0] = s1; if (slot1 >= 0) scal[slot1] = s2; }
}
"""

RHO2, PQ = 0, 1         # slots of the device scalars; r.z alternates between slots 2 and 3
_KERNELS = ("residual", "product", "spmv_dot", "jacobi_start", "cg_update", "cg_direction", "finish")
_module = None
_functions: dict = {}


def _kernels() -> dict:
    """The kernels by name, compiled once a process (NVRTC)."""
    global _module
    if _module is None:
        import cupy
        _module = cupy.RawModule(code=_SOURCE)
        _functions.clear()
    if not _functions:
        _functions.update({name: _module.get_function(name) for name in _KERNELS})
    return _functions


def _blocks(rows: int, rows_a_block: int) -> int:
    return max(1, min(MAX_BLOCKS, math.ceil(rows / rows_a_block)))


def jacobi_pcg(A, b, x0, dinv, weights, tol: float, max_iterations: int, residual: bool):
    """:func:`twin.physics.solvers.pcg` for one column with the Jacobi preconditioner D^-1
    (``dinv``, (n,)) on the GPU: ``A`` a :class:`DeviceMatrix` or a ``cupyx.scipy.sparse.csr_matrix``
    (its ``indptr``, ``indices``, ``data`` are read), the vectors CuPy arrays. Returns (x, iterations, rho) and with ``residual`` the final residual as well;
    RuntimeError after ``max_iterations`` (never a silent unconverged answer)."""
    import cupy as cp
    import numpy as np

    k = _kernels()
    n = int(b.shape[0])
    f64 = cp.float64
    indptr, indices = A.indptr.astype(cp.int32, copy=False), A.indices.astype(cp.int32, copy=False)
    data = A.data.astype(f64, copy=False)
    w, dinv = cp.ascontiguousarray(weights, dtype=f64), cp.ascontiguousarray(dinv, dtype=f64)
    X, B = cp.array(x0, dtype=f64, order="C"), cp.ascontiguousarray(b, dtype=f64)
    R, Z, Q = cp.empty_like(B), cp.empty_like(B), cp.empty_like(B)
    parts, scal = cp.zeros(2 * MAX_BLOCKS, dtype=f64), cp.zeros(4, dtype=f64)
    rows, warps = _blocks(n, BLOCK), _blocks(n, BLOCK // 32)
    nn, one = np.int64(n), (1,)
    k["residual"]((warps,), (BLOCK,), (indptr, indices, data, X, B, R, nn))
    k["jacobi_start"]((rows,), (BLOCK,), (R, w, dinv, Z, nn, parts))
    finish, spmv_dot, update, direction = k["finish"], k["spmv_dot"], k["cg_update"], k["cg_direction"]
    finish(one, (BLOCK,), (parts, np.int32(rows), scal, np.int32(RHO2), np.int32(2)))
    rho, it, old = math.sqrt(max(float(scal[RHO2]), 0.0)), 0, 2
    if rho > tol:
        P = Z
        while True:
            if it >= max_iterations:
                raise RuntimeError(f"PCG did not converge in {max_iterations} iterations (residual {rho:.3g})")
            new = 5 - old
            spmv_dot((warps,), (BLOCK,), (indptr, indices, data, P, Q, nn, parts))
            finish(one, (BLOCK,), (parts, np.int32(warps), scal, np.int32(PQ), np.int32(-1)))
            update((rows,), (BLOCK,), (X, R, P, Q, w, dinv, scal, np.int32(PQ), np.int32(old), nn, parts))
            finish(one, (BLOCK,), (parts, np.int32(rows), scal, np.int32(RHO2), np.int32(new)))
            rho, it = math.sqrt(max(float(scal[RHO2]), 0.0)), it + 1      # Q now holds Z
            if not rho > tol:
                break
            direction((rows,), (BLOCK,), (P, Q, scal, np.int32(new), np.int32(old), nn))
            old = new
    return (X, it, rho, R) if residual else (X, it, rho)


LONG_ROW = 2048             # entries from which a row is left to cuSPARSE (one warp would walk it alone)


class DeviceMatrix:
    """A CSR matrix on the GPU whose product with one vector is one launch of ``product`` (a warp
    a row) instead of cuSPARSE through ``cupyx``, which builds descriptors, queries a buffer and
    allocates it in Python on every call (measured on an H200 for the 200 k-node heat matrix:
    0.037 ms against 0.088 ms). Products with a block of vectors, and every other use, go to the
    ``cupyx`` matrix ``csr``; ``indptr``, ``indices`` and ``data`` are its arrays (the fused CG
    reads them). For matrices whose rows are all short: :func:`device_matrix` chooses."""

    def __init__(self, A):
        import cupy as cp
        import cupyx.scipy.sparse as csp
        import scipy.sparse as sp

        self.csr = csp.csr_matrix(sp.csr_matrix(A, dtype=float))
        self.shape = self.csr.shape
        self.indptr = self.csr.indptr.astype(cp.int32, copy=False)        # no second copy on the card
        self.indices = self.csr.indices.astype(cp.int32, copy=False)
        self.data = self.csr.data

    def __matmul__(self, x):
        import cupy as cp
        import numpy as np

        if x.ndim != 1:
            return self.csr @ x
        rows = self.shape[0]
        y = cp.empty(rows)
        if rows:
            _kernels()["product"]((_blocks(rows, BLOCK // 32),), (BLOCK,),
                                  (self.indptr, self.indices, self.data, cp.ascontiguousarray(x, dtype=cp.float64),
                                   y, np.int64(rows)))
        return y


def device_matrix(A):
    """A scipy sparse matrix on the GPU: a :class:`DeviceMatrix` when :data:`FUSED` and every row
    has at most :data:`LONG_ROW` entries (the heat step's operators), else a ``cupyx`` CSR matrix
    (the output rows, some of which, such as the heat balance's stored heat, span the whole
    machine: cuSPARSE took 0.052 ms for the 200 k model's rows, the warp kernel with those rows
    as a dense block 0.091 ms)."""
    import cupyx.scipy.sparse as csp
    import numpy as np
    import scipy.sparse as sp

    A = sp.csr_matrix(A)
    if FUSED and (A.shape[0] == 0 or int(np.diff(A.indptr).max()) <= LONG_ROW):
        return DeviceMatrix(A)
    return csp.csr_matrix(A)
