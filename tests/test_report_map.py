"""validate.report_map.region_map on stub inputs: a two-part machine of one box each, a diagnosis
with two regions of fitted powers 80 W and -120 W, two temperature sensors and one probe."""

from __future__ import annotations

from types import SimpleNamespace as NS

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import TwoSlopeNorm  # noqa: E402

from validate.report_map import region_map  # noqa: E402


class _Machine:
    """Parts 'bed' (0..2 x 0..1 x 0..0.5 m) and 'column' (0..0.5 x 0..1 x 0.5..2 m), one box each."""

    def __init__(self):
        self.parts = [NS(name="bed", boxes=[NS(lo=(0.0, 0.0, 0.0), hi=(2.0, 1.0, 0.5))]),
                      NS(name="column", boxes=[NS(lo=(0.0, 0.0, 0.5), hi=(0.5, 1.0, 2.0))])]

    def part(self, name):
        return next(p for p in self.parts if p.name == name)


# channels: temperature, temperature, probe; residual r before the fit, the top fit's response
_R = np.tile([3.0, 4.0, 9.0], (4, 1))
_RESPONSE = np.tile([2.0, 1.0, 9.0], (4, 1))


def _diagnosis():
    """A partly_explained stub: residual_after(response) = r - response, evidence.split keeps all
    channels (returns a 1-tuple), two temperature sensors at known points."""
    return NS(regions=[{"region": "bed", "power_W": 80.0, "schedule": "constant", "explained": 0.4},
                       {"region": "column.+x", "power_W": -120.0, "schedule": "constant", "explained": 0.3}],
              record=NS(groups=["temperature", "temperature", "probe"],
                        sensor_points=[NS(xyz=(1.0, 0.5, 0.4)), NS(xyz=(0.2, 0.5, 1.5))]),
              verdict="partly_explained", fits=[NS(response=_RESPONSE)],
              evidence=NS(split=lambda x: (x,)), residual_after=lambda resp: _R - resp,
              fitter=NS(r=_R))


def test_region_map_power_scale_is_symmetric_and_sensors_show_the_residual_after_the_fit():
    """Powers [80, -120] W: span = max |P| = 120, so the colour scale is TwoSlopeNorm(0, -120, 120)
    (not +-80 from max P); the bed (80 W) is filled with RdBu_r(0.5 + 0.5 * 80/120 = 0.8333).
    Sensors: residual after the top fit r - response = [1, 3] K on every row, so their colours are the
    RMS per sensor [1, 3] (not the pre-fit [3, 4]) on a 0..3 K scale."""
    fig = region_map(_diagnosis(), _Machine())
    try:
        norms = [a._colorbar.norm for a in fig.axes if getattr(a, "_colorbar", None) is not None]
        power = [n for n in norms if isinstance(n, TwoSlopeNorm)]
        assert len(power) == 1
        assert (power[0].vmin, power[0].vcenter, power[0].vmax) == (-120.0, 0.0, 120.0)
        front = fig.axes[0]
        bed_fill = plt.get_cmap("RdBu_r")(0.5 + 0.5 * 80.0 / 120.0)
        fills = [p.get_facecolor() for p in front.patches if p.get_fill() and p.get_alpha() == 0.85]
        assert len(fills) == 1
        np.testing.assert_allclose(fills[0][:3], bed_fill[:3], atol=1e-12)
        sc = front.collections[-1]
        np.testing.assert_allclose(np.asarray(sc.get_array()), [1.0, 3.0], rtol=1e-12)
        assert sc.norm.vmin == 0 and sc.norm.vmax == 3.0
    finally:
        plt.close(fig)
