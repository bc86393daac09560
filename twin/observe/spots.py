"""Virtual temperature spots on thermal-camera frames: averaged pixel groups along lines.

Seed 001 (L223) reduced each 320 x 240 frame of the spindle carrier to 525 "spots" by averaging
groups of pixels, laid out as "lines" of spots representing strips. :func:`spot_layout` does the
same on a camera's truth layer ``part_true``: it takes the bounding box of the pixels that see the
subject part, lays ``lines`` rows of ``per_line`` spot centres evenly across it (each centre at
least half a group from the box's edge), and keeps the spots whose whole ``size`` x ``size`` pixel
group sees the part (none straddles an edge). Spots are numbered line by line, left to right,
``spot-001`` ... as the seed numbers Spot-1 ... Spot-525. :func:`spot_series` averages each
group over the frames (the seed's noise reduction: the temporal noise of n pixels falls by
sqrt(n); fixed patterns, banding and the camera's offset do not average out).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Spot:
    """A pixel group: rows [v0, v0 + size), columns [u0, u0 + size)."""

    name: str
    v0: int
    u0: int
    size: int


def spot_layout(part_layer: np.ndarray, part: int, lines: int = 21, per_line: int = 25, size: int = 5) -> list[Spot]:
    """Spots on the pixels of ``part_layer`` (H, W) equal to ``part`` (module docstring);
    21 x 25 = 525 by default, as in seed 001."""
    on = np.asarray(part_layer) == part
    if not on.any():
        raise ValueError(f"no pixel sees part #{part}")
    rows, cols = np.flatnonzero(on.any(axis=1)), np.flatnonzero(on.any(axis=0))
    v_lines = _centres(rows.min(), rows.max(), lines, size)
    u_spots = _centres(cols.min(), cols.max(), per_line, size)
    spots = []
    for v in v_lines:
        for u in u_spots:
            v0, u0 = v - size // 2, u - size // 2
            if v0 >= 0 and u0 >= 0 and on[v0:v0 + size, u0:u0 + size].shape == (size, size) \
                    and on[v0:v0 + size, u0:u0 + size].all():
                spots.append(Spot(f"spot-{len(spots) + 1:03d}", int(v0), int(u0), size))
    return spots


def _centres(lo: int, hi: int, n: int, size: int) -> np.ndarray:
    """n integer centres evenly spread over [lo + size//2, hi - size//2] (unique)."""
    a, b = lo + size // 2, hi - size // 2
    return np.unique(np.rint(np.linspace(a, b, n)).astype(int)) if b >= a else np.array([], dtype=int)


def spot_series(frames: np.ndarray, spots: list[Spot]) -> np.ndarray:
    """(n_frames, n_spots): the mean of each spot's pixel group in every frame (n_frames, H, W)."""
    frames = np.asarray(frames, dtype=float)
    return np.stack([frames[:, s.v0:s.v0 + s.size, s.u0:s.u0 + s.size].mean(axis=(1, 2)) for s in spots], axis=1)
