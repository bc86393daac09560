"""Virtual temperature spots (:mod:`twin.observe.spots`) against their definition: the layout on a
part's pixels and the group means, whose temporal noise falls as 1 / sqrt(n) for n pixels."""

from __future__ import annotations

import numpy as np
import pytest

from twin.observe.spots import spot_layout, spot_series


def test_spots_lie_wholly_on_the_part_evenly_line_by_line():
    """On a 60 x 80 truth layer whose part fills rows 10-49 and columns 5-74 less a hole, every
    5 x 5 group sees the part only; centres lie on 21 lines and 25 columns spread evenly over the
    part's box at least half a group from its edges (np.linspace, rounded); the groups that would
    touch the hole are left out, and the spots are numbered line by line, left to right."""
    layer = np.full((60, 80), -1)
    layer[10:50, 5:75] = 2
    layer[25:31, 30:41] = -1                  # a hole: no group may touch it
    spots = spot_layout(layer, 2)
    for s in spots:
        assert np.all(layer[s.v0:s.v0 + 5, s.u0:s.u0 + 5] == 2)
    rows = np.unique(np.rint(np.linspace(12, 47, 21)).astype(int))
    cols = np.unique(np.rint(np.linspace(7, 72, 25)).astype(int))
    whole = [(v - 2, u - 2) for v in rows for u in cols
             if not (v + 2 >= 25 and v - 2 <= 30 and u + 2 >= 30 and u - 2 <= 40)]
    assert [(s.v0, s.u0) for s in spots] == whole
    assert [s.name for s in spots] == [f"spot-{k:03d}" for k in range(1, len(whole) + 1)]
    assert len(whole) < len(rows) * len(cols)
    with pytest.raises(ValueError, match="no pixel sees part #7"):
        spot_layout(layer, 7)


def test_a_spot_is_its_groups_mean_and_averages_temporal_noise_by_sqrt_n():
    """spot_series is the mean of each 5 x 5 group in every frame (exact), so white temporal noise
    of deviation sigma per pixel has deviation sigma / 5 in a spot: over 4000 frames x 12 spots
    (N = 48000) the sample variance is held to 4 relative standard errors, 4 sqrt(2 / N)."""
    rng = np.random.default_rng(3)
    layer = np.zeros((30, 40), dtype=int)
    spots = spot_layout(layer, 0, lines=3, per_line=4)
    assert len(spots) == 12
    base = rng.uniform(20.0, 40.0, (30, 40))
    frames = base[None] + 0.08 * rng.standard_normal((4000, 30, 40))
    series = spot_series(frames, spots)
    for k, s in enumerate(spots[:3]):
        assert np.array_equal(series[:, k], frames[:, s.v0:s.v0 + 5, s.u0:s.u0 + 5].mean(axis=(1, 2)))
    noise = series - np.array([base[s.v0:s.v0 + 5, s.u0:s.u0 + 5].mean() for s in spots])[None]
    assert noise.var() == pytest.approx((0.08 / 5) ** 2, rel=4 * np.sqrt(2 / noise.size))
