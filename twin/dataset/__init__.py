"""Benchmark datasets: a TOML spec (:mod:`~twin.dataset.spec`) expanded into cases named by the
hash of their content (:mod:`~twin.dataset.plan`), built one NetCDF file per case on a process
pool or a Dask cluster, resumable (:mod:`~twin.dataset.runner`), with an index and a dataset
card (:mod:`~twin.dataset.card`) and a calibrated time estimate (:mod:`~twin.dataset.estimate`).
"""

from twin.dataset.card import INDEX_FILES, write_index
from twin.dataset.estimate import estimate
from twin.dataset.plan import Case, case_hash, plan
from twin.dataset.runner import CASES, build, build_case, executor, is_whole
from twin.dataset.spec import DatasetSpec, load_spec

__all__ = ["INDEX_FILES", "write_index", "estimate", "Case", "case_hash", "plan", "CASES", "build", "build_case",
           "executor", "is_whole", "DatasetSpec", "load_spec"]
