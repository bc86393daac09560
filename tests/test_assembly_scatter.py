"""The pattern assembly (:mod:`twin.fem.scatter`) against the plain one: every cell's element
matrix copied into COO triplets and summed by the COO -> CSR conversion (the assembly before
the scale work). Same matrices to round-off: sum_e P_e^T A_e Q_e in another order of addition."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from twin.api import machine_by_name
from twin.fem import elements
from twin.fem.assembly import _groups, assemble_coupling, assemble_elastic, assemble_heat, cell_materials
from twin.fem.mesh import build_mesh
from twin.fem.scatter import Pattern


def _coo(rows, cols, blocks, shape):
    r = np.broadcast_to(rows[:, :, None], blocks.shape).ravel()
    c = np.broadcast_to(cols[:, None, :], blocks.shape).ravel()
    return sp.coo_matrix((blocks.ravel(), (r, c)), shape=shape).tocsr()


@pytest.fixture(scope="module")
def split_mesh():
    """The C-frame at 120 mm with the test bar's temperatures split from the spindle's (a contact
    layout: corners of one node carry different temperature dofs)."""
    machine = machine_by_name("cframe-vmc")
    mm = build_mesh(machine, 0.12)
    return mm.split_heat(("test_bar",), mm.facets["test_bar_seat"])


def _close(a, b):
    return abs(a - b).max() <= 1e-13 * abs(b).max()


def test_heat_and_elastic_matrices_equal_the_per_cell_coo_assembly(split_mesh):
    """K, M (heat), K (elastic, 3 x 3 node blocks) and C (3 x 1 blocks on the split layout) equal
    sum_e P_e^T A_e Q_e assembled from per-cell COO triplets, to round-off."""
    mm = split_mesh
    assert mm.nheat > mm.nnodes
    mats = cell_materials(mm)
    uniq, inverse = _groups(mm)
    part = uniq[:, 3].astype(int)
    k_ref, m_ref = elements.heat_matrices(uniq[:, :3])
    k = np.array([mats[p].conductivity for p in part])[:, None, None]
    c = np.array([mats[p].volumetric_heat_capacity for p in part])[:, None, None]
    lame = np.array([mats[p].lame for p in part])
    k_e, c_e = elements.elastic_matrices(uniq[:, :3], lame[:, 0], lame[:, 1],
                                         np.array([mats[p].expansion for p in part]))
    t, th = mm.mesh.t.T, mm.heat_t.T
    dofs = (3 * t[:, :, None] + np.arange(3)).reshape(len(t), 24)
    heat = assemble_heat(mm)
    elastic = assemble_elastic(mm)
    assert _close(heat.K, _coo(th, th, (k_ref * k)[inverse], (mm.nheat, mm.nheat)))
    assert _close(heat.M, _coo(th, th, (m_ref * c)[inverse], (mm.nheat, mm.nheat)))
    assert _close(elastic.K, _coo(dofs, dofs, k_e[inverse], (3 * mm.nnodes, 3 * mm.nnodes)))
    C = _coo(dofs, th, c_e[inverse], (3 * mm.nnodes, mm.nheat))
    assert _close(elastic.C, C)
    assert _close(assemble_coupling(mm), C)


def test_repeated_nodes_fall_back_to_accumulation():
    """Cells that share a corner node in the same local position (not a grid: the unbuffered
    pass would drop one) still sum: two 'cells' on nodes (0, 1) give [[2, 2], [2, 2]] for a block
    of ones."""
    rows = np.array([[0, 0], [1, 1]])
    A = Pattern(rows, rows, (2, 2)).assemble(np.ones((1, 2, 2)), np.zeros(2, dtype=int))
    assert np.array_equal(A.toarray(), np.full((2, 2), 2.0))


@pytest.mark.parametrize("layout", ["heat", "elastic_on_split_heat", "nested"])
def test_compiled_positions_equal_the_searchsorted_ones(split_mesh, layout):
    """Every (corner a, corner b, cell)'s position in the pattern found by the compiled binary
    search in its row equals the one np.searchsorted finds among all node pairs (integers:
    exactly), for a square heat pattern, the rectangular coupling pattern of a split layout, and
    a nested (coarse elastic x fine heat) pattern; and a compiled pattern assembles the same
    matrix bit for bit, for scalar and 3 x 1 node blocks."""
    from twin.fem import scatter
    from twin.fem.nesting import coarsen

    if scatter.compile_kernel(scatter._positions) is None:
        pytest.skip("numba not installed: only the searchsorted path runs")
    mm = split_mesh
    if layout == "heat":
        rows, cols, shape = mm.heat_t, mm.heat_t, (mm.nheat, mm.nheat)
    elif layout == "elastic_on_split_heat":
        rows, cols, shape = mm.mesh.t, mm.heat_t, (mm.nnodes, mm.nheat)
    else:
        nested = coarsen(mm, 2)
        rows, cols, shape = nested.coarse.mesh.t[:, nested.parent], mm.heat_t, (nested.coarse.nnodes, mm.nheat)
    fast, slow = Pattern(rows, cols, shape, use_numba=True), Pattern(rows, cols, shape, use_numba=False)
    assert np.array_equal(fast.positions, slow.positions)
    assert np.array_equal(fast.indices, slow.indices) and np.array_equal(fast.indptr, slow.indptr)
    # the compiled accumulation: the same sums in the same order as the numpy passes, bit for bit
    rng = np.random.default_rng(7)
    for ref_shape in ((3, rows.shape[0], cols.shape[0]), (3, rows.shape[0], cols.shape[0], 3, 1)):
        ref, group = rng.standard_normal(ref_shape), rng.integers(0, 3, rows.shape[1])
        assert (fast.assemble(ref, group) != slow.assemble(ref, group)).nnz == 0


def test_volume_vector_integrates_constants_and_linear_fields_over_cells_of_many_sizes(split_mesh):
    """b_i = int N_i dV: sum_i b_i = V and sum_i b_i x_i = int x dV = sum_c V_c xbar_c (a trilinear
    interpolation reproduces linear fields, and the corners' mean is each brick's centroid), over
    the C-frame's cells of many sizes, to round-off; the first moments see which corner got which
    brick's volume, the total alone does not."""
    from twin.fem.assembly import volume_vector
    mm = split_mesh
    cells = np.arange(mm.ncells)
    b = volume_vector(mm, cells)
    vol = np.prod(mm.cell_size[cells], axis=1)
    assert len(np.unique(np.round(vol, 12))) > 3
    assert b.sum() == pytest.approx(vol.sum(), rel=1e-12)
    x = mm.mesh.p[:, mm.heat_node]                               # each temperature dof's position
    centroids = mm.mesh.p[:, mm.mesh.t[:, cells]].mean(axis=1)   # (3, cells)
    for d in range(3):
        assert b @ x[d] == pytest.approx(vol @ centroids[d], rel=1e-12)
