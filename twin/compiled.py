"""Kernels compiled by numba where it is installed: loops that numpy cannot vectorise (a binary
search per matrix entry, a Gauss-Seidel sweep). numba is imported on the first kernel that is
asked for, not with the package, and each kernel module keeps a numpy (or pyamg/scipy) fallback
that gives the same numbers and is tested against the compiled kernel.

**Vectorised kernels.** numba switched LLVM's SLP (straight-line) vectoriser off by default in
version 0.57 (numba pull request #8852), after miscompilations it caused in other code (numba
issues #8681 and #8705, the latter with SVML's vectorised exp and log). A kernel that carries
several independent sums per matrix entry, as :func:`twin.physics.kernels._block_pass` carries
eight columns, needs exactly that vectoriser to use SIMD registers: on the development machine
(AVX-512) it halves an eight-column Gauss-Seidel sweep of the 200 k-node heat matrix, 13.7 to
6.8 ms, and the product, 11.1 to 6.0 ms. :func:`compile_kernel` with ``vectorise=True`` switches
it on for that kernel alone, while holding numba's compiler lock, so that nothing else compiled in
the process is affected. Vectorising independent sums changes no operation and no order (no
fused multiply-add: numba does not contract without ``fastmath``), so the vectorised kernel gives
the scalar kernel's numbers bit for bit; ``tests/test_kernels.py`` checks that, and the kernel
against pyamg and scipy, on every machine the tests run on."""

from __future__ import annotations

import contextlib
import functools
import importlib.util
import types

HAVE_NUMBA = importlib.util.find_spec("numba") is not None


@functools.cache
def compile_kernel(fn, vectorise: bool = False):
    """``fn`` compiled by numba in nopython mode (cached on disk where a cache can be written,
    else compiled in memory once per process), or None without numba. ``vectorise``: compiled
    with the SLP vectoriser on (module docstring); a callable with the dispatcher's signature."""
    if not HAVE_NUMBA:
        return None
    import numba

    if vectorise:
        fn = _renamed(fn, "vectorised")
    try:
        dispatcher = numba.njit(cache=True, nogil=True)(fn)
    except RuntimeError:                # no writable cache location
        dispatcher = numba.njit(nogil=True)(fn)
    return _Vectorised(dispatcher) if vectorise else dispatcher


def _renamed(fn, suffix: str):
    """The same function under another qualified name: numba's disk cache files a kernel by its
    module, qualified name and line, not by the options it was compiled with, so the vectorised
    kernel keeps its own entries (a scalar compilation of the same function, a test's say, can
    neither be loaded in its place nor overwrite it)."""
    twin = types.FunctionType(fn.__code__, fn.__globals__, fn.__name__, fn.__defaults__, fn.__closure__)
    twin.__qualname__ = f"{fn.__qualname__}_{suffix}"
    twin.__doc__ = fn.__doc__
    return twin


@contextlib.contextmanager
def _slp_vectoriser():
    """numba's SLP vectoriser switched on for what is compiled inside, under numba's compiler
    lock (no other thread compiles meanwhile). numba reads ``config.SLP_VECTORIZE`` each time it
    builds an optimisation pipeline, that is, per compilation; where a numba version keeps the
    lock elsewhere, the kernel is compiled as numba would by default (slower, the same numbers)."""
    from numba.core import config

    try:
        from numba.core.compiler_lock import global_compiler_lock
    except ImportError:                 # pragma: no cover - a numba without the lock here
        yield
        return
    with global_compiler_lock:
        before = config.SLP_VECTORIZE
        config.SLP_VECTORIZE = 1
        try:
            yield
        finally:
            config.SLP_VECTORIZE = before


class _Vectorised:
    """A numba dispatcher whose every new signature is compiled (or loaded from numba's disk
    cache, which holds what an earlier process compiled this way) with the SLP vectoriser on, then
    called like the dispatcher itself."""

    def __init__(self, dispatcher):
        self.dispatcher = dispatcher
        self._seen: set = set()

    def __call__(self, *args):
        key = tuple((a.dtype.str, a.ndim, a.flags.c_contiguous, a.flags.f_contiguous)
                    if hasattr(a, "dtype") and hasattr(a, "flags") else type(a) for a in args)
        if key not in self._seen:
            with _slp_vectoriser():
                self.dispatcher.compile(tuple(self.dispatcher.typeof_pyval(a) for a in args))
            self._seen.add(key)
        return self.dispatcher(*args)
