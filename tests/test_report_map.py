"""validate.report_map.region_map on stub inputs: a two-part machine of one box each, a diagnosis
with two regions of fitted powers 80 W and -120 W, two temperature sensors and one probe; and the
report's measured-vs-model figure (validate.report._worst_channels), which channels it plots."""

from __future__ import annotations

from types import SimpleNamespace as NS

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import TwoSlopeNorm  # noqa: E402

from tests.stubs import TwoPartMachine  # noqa: E402
from validate.report_map import region_map  # noqa: E402


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
    fig = region_map(_diagnosis(), TwoPartMachine())
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


def test_measured_vs_model_figure_plots_the_six_worst_weighted_channels_worst_first(monkeypatch):
    """The report's 'worst channels' figure: eight channels with constant residuals [1 .. 8] (RMSE
    = the offset) and weights that reorder them (RMSE x weight = [4, 0.8, 6, 1, 7.5, 2.4, 3.5,
    8]); the six panels, top to bottom, are the largest RMSE x weight first, channels 8, 5, 3, 1,
    7, 6 (not the plain-RMSE order 8, 7, 6, 5, 4, 3, not the best ones, not the first six), each
    titled with its own unweighted RMSE and unit."""
    import validate.report as R

    figs = []
    monkeypatch.setattr(R, "_png", lambda fig: figs.append(fig) or "png")
    n_t, offsets = 5, np.arange(1.0, 9.0)
    weights = np.array([4.0, 0.4, 2.0, 0.25, 1.5, 0.4, 0.5, 1.0])
    model = np.tile(np.linspace(20.0, 21.0, n_t)[:, None], (1, 8))
    rec = NS(times=np.arange(n_t) * 600.0, t0=0.0, measured=model + offsets, model=model, weights=weights,
             phases=[], groups=["temperature"] * 4 + ["probe"] * 4, channels=[f"c{k}" for k in range(1, 9)])
    assert R._worst_channels(NS(candidates=[]), rec, None) == "png"
    try:
        titles = [ax.get_title(loc="left") for ax in figs[0].axes]
        assert [t.split(":")[0] for t in titles] == ["c8", "c5", "c3", "c1", "c7", "c6"]
        assert titles[0] == "c8: RMSE 8 um" and titles[3] == "c1: RMSE 1 K"
    finally:
        plt.close(figs[0])
