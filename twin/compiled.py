"""Kernels compiled by numba where it is installed: loops that numpy cannot vectorise (a binary
search per matrix entry, a Gauss-Seidel sweep). numba is imported on the first kernel that is
asked for, not with the package, and each kernel module keeps a numpy (or pyamg/scipy) fallback
that gives the same numbers and is tested against the compiled kernel."""

from __future__ import annotations

import functools
import importlib.util

HAVE_NUMBA = importlib.util.find_spec("numba") is not None


@functools.cache
def compile_kernel(fn):
    """``fn`` compiled by numba in nopython mode (cached on disk where a cache can be written,
    else compiled in memory once per process), or None without numba."""
    if not HAVE_NUMBA:
        return None
    import numba

    try:
        return numba.njit(cache=True, nogil=True)(fn)
    except RuntimeError:                # no writable cache location
        return numba.njit(nogil=True)(fn)
