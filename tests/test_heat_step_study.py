"""The heat-step study's full path (``--spacing``/``--steps``, not ``--quick``) on a model whose
heat operators are :class:`twin.physics.parallel.RowBlocks`, as the stepper holds them from
:data:`twin.physics.parallel.SPLIT_FROM` stored entries (the default 40 mm mesh): the two-grid
cycle's Galerkin product once failed on them (``csr_matrix @ RowBlocks``) while ``--quick``, below
the threshold, passed. The threshold is lowered here so a small mesh takes that path."""

from __future__ import annotations

import csv

import numpy as np
import scipy.sparse as sp

from twin.physics import parallel


def test_as_csr_stacks_row_blocks_back_into_the_matrix():
    from validate.studies.heat_step import as_csr

    A = sp.random(40, 40, density=0.2, format="csr", random_state=np.random.default_rng(1)) + sp.eye(40)
    for M in (A, parallel.RowBlocks(A)):
        B = as_csr(M)
        assert sp.isspmatrix_csr(B) and B.shape == A.shape and (B != A).nnz == 0


def test_heat_step_study_runs_its_full_path_on_row_block_operators(tmp_path, monkeypatch):
    from validate.studies import heat_step

    monkeypatch.setattr(parallel, "SPLIT_FROM", 1)      # every operator split, as on the 40 mm mesh
    seen = []
    cycle = heat_step.TwoGridStepper._cycle

    def spy(self, lhs, dinv):
        seen.append(type(lhs))
        return cycle(self, lhs, dinv)

    monkeypatch.setattr(heat_step.TwoGridStepper, "_cycle", spy)
    assert heat_step.main(["--spacing", "100mm", "--steps", "2", "--coarsening", "2", "-o", str(tmp_path)]) == 0
    assert seen and all(t is parallel.RowBlocks for t in seen)
    rows = list(csv.DictReader(open(tmp_path / "heat_step.csv")))
    assert [r["variant"].split(",")[0] for r in rows] == ["jacobi"] * 5 + ["two-grid"]
    assert {r["steps"] for r in rows} == {"2"}
    for r in rows:
        assert float(r["difference_K"]) <= float(r["bound_K"])
