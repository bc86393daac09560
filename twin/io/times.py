"""The time axis of a record, checked: :func:`check_times` (a measurement's, a model's, the one an
ISO 230-3 evaluation reads)."""

from __future__ import annotations

import numpy as np

from twin.errors import InputError


def sample_place(i: int, lines=None) -> str:
    """Where sample ``i`` (from 0) stands, for an error: 'line N' with ``lines`` (a CSV's line
    number of each sample, as an editor shows them: header line 1, blank lines counted), else
    'data row N' (from 1)."""
    return f"line {lines[i]}" if lines is not None else f"data row {i + 1}"


def check_times(t: np.ndarray, src: str, col: str, lines=None) -> None:
    """Times [s] of a measurement or a model: two or more, finite, increasing, without a gap of more
    than three median steps. ``lines``: the file's line number of each time (a CSV's, as an editor
    shows them: header line 1, blank lines counted), which an error names; else the data row."""
    if t.ndim != 1 or t.size < 2:
        raise InputError(src, col, f"needs two samples or more, got {t.size}")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise InputError(src, col, f"{sample_place(int(bad[0]), lines)}: not a finite number")
    dt = np.diff(t)
    if np.any(dt <= 0):
        i = int(np.flatnonzero(dt <= 0)[0])
        raise InputError(src, col, f"time is not increasing at {sample_place(i + 1, lines)} "
                                   f"({t[i]:g} -> {t[i + 1]:g} s)")
    med = float(np.median(dt))
    if np.any(dt > 3 * med):
        i = int(np.flatnonzero(dt > 3 * med)[0])
        where = f"{sample_place(i + 1, lines)}: " if lines is not None else ""
        raise InputError(src, col, f"{where}gap of {dt[i]:g} s after t = {t[i]:g} s (more than 3 x the median "
                                   f"interval {med:g} s)")
