"""Mutation audit of what a diagnosis reports and applies (validate/apply.py, report.py,
report_map.py; the comparison and the search: tests/test_compare_mutations.py): each test pins a
behaviour whose mutation the suite let survive, on small synthetic inputs, no twin run."""

from __future__ import annotations

from types import SimpleNamespace as NS

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from tests.stubs import TwoPartMachine  # noqa: E402


# --- apply: the rerun's arguments, its calibrated twin, the before/after table ------------------

def _evidence(residual: np.ndarray, groups, channels):
    """Real Evidence over one stand-in record (measured 10 everywhere), as tests/test_report_tables.py."""
    from validate.evidence import Evidence

    measured = np.full(residual.shape, 10.0)
    rec = NS(label="m", measured=measured, groups=list(groups), channels=list(channels), phases=[],
             times=np.arange(residual.shape[0]) * 60.0, noise={}, model_error=None)
    return Evidence([rec])


def _pair_fit():
    from validate.candidates import Candidate
    from validate.search import Fit

    cabinet = Candidate("electrical_cabinet", "effect", "electrical_cabinet", "power", 0.0, 2000.0, 0.0, 100.0,
                        True, False)
    front = Candidate("spindle_bearings.front_power", "parameter", "spindle_bearings", "front_power", 50.0, 450.0,
                      150.0, 300.0, True, True)
    return Fit((cabinet, front), (120.0, 195.0), np.zeros(8), 0.0)


def test_apply_top_sets_each_member_of_a_pair_to_its_own_fitted_value():
    """apply_top of a pair (a missing cabinet fitted at 120 W, the front bearing at 195 W for the
    model's 150 W): the rerun's model has each member at its own value, the printed arguments
    switch on only the effect the model lacks and set each parameter to its own value."""
    from geometries import build_machine
    from twin.model import model_spec
    from validate.apply import apply_top
    from validate.diagnose import Diagnosis
    from validate.fit import BoundedFitter

    ev = _evidence(np.zeros((4, 2)), ["temperature", "probe"], ["temperature:T0", "probe:X1"])
    seen = []
    ev.observe_with_expansion = lambda spec, materials: (seen.append(spec) or ev.measured.copy(), [])
    spec = model_spec(build_machine("cframe-vmc"))
    assert "electrical_cabinet" not in spec.effects and spec.params["spindle_bearings"]["front_power"] == 150.0
    d = Diagnosis(ev, spec, np.zeros(8), np.ones(8), BoundedFitter(np.zeros(8), np.ones(8)), [], fits=[_pair_fit()])
    after, calibrated, args = apply_top(d)
    assert calibrated is None
    assert seen[0].params["electrical_cabinet"]["power"] == 120.0
    assert seen[0].params["spindle_bearings"]["front_power"] == 195.0
    assert args == ["--effects", "+electrical_cabinet", "--set electrical_cabinet.power=120W",
                    "--set spindle_bearings.front_power=195W"]


def _calibrated_case():
    """Channels T0 [K] and X1 [um], 4 samples; baseline residual T0 2 K, X1 0.05 n (n = 1..4 um:
    the probe's response to a unit relative change of the cast iron's alpha, band +-10 %). The
    top candidate explains T0 (response 2 K on T0, 0 on X1); its rerun leaves X1's 0.05 n."""
    from twin.model import ModelSpec
    from validate.candidates import Candidate
    from validate.diagnose import Diagnosis
    from validate.fit import BoundedFitter
    from validate.search import Fit

    n = np.array([1.0, 2.0, 3.0, 4.0])
    r = np.column_stack([np.full(4, 2.0), 0.05 * n]).ravel()
    col = np.column_stack([np.zeros(4), n]).ravel()
    ev = _evidence(r.reshape(4, 2), ["temperature", "probe"], ["temperature:T0", "probe:X1"])
    after = ev.measured - np.column_stack([np.zeros(4), 0.05 * n]).ravel()
    ev.observe_with_expansion = lambda spec, materials: (after.copy(), [col.copy()])
    g = np.column_stack([np.full(4, 2.0), np.zeros(4)]).ravel()
    cabinet = Candidate("electrical_cabinet", "effect", "electrical_cabinet", "power", 0.0, 2000.0, 0.0, 100.0,
                        True, False)
    fitter = BoundedFitter(r, np.ones(8), col[None, :], [-0.1], [0.1])
    d = Diagnosis(ev, ModelSpec((), {}), np.zeros(8), np.ones(8), fitter, ["grey_cast_iron"],
                  fits=[Fit((cabinet,), (120.0,), g, 0.0)], nuisance_baseline={"grey_cast_iron": {"change": 0.05}})
    return d, after, n


def test_the_calibrated_rerun_adds_the_fitted_expansion_times_its_response():
    """apply_top's second model: after + sum_m c_m response_m, c the expansion fitted with the
    candidate (here c = +0.05 exactly: r - g = 0.05 n on X1). The rerun leaves 0.05 n on X1, so
    the calibrated model leaves nothing: measured - calibrated = 0."""
    from validate import apply as A

    d, after, n = _calibrated_case()
    got_after, calibrated, args = A.apply_top(d)
    assert d.expansion_fit(d.fits[0].response)["grey_cast_iron"] == pytest.approx(0.05, abs=1e-9)
    np.testing.assert_allclose(got_after, after, rtol=0, atol=1e-12)
    np.testing.assert_allclose(d.evidence.measured - calibrated, 0.0, atol=1e-9)
    assert args == ["--effects", "+electrical_cabinet", "--set electrical_cabinet.power=120W"]


def test_the_before_plus_a_column_is_the_baseline_with_its_fitted_expansion():
    """format_before_after's 'before+a' is the baseline residual after the expansion fitted to it
    (X1: 0.05 n minus 0.05 n = 0), not the plain baseline (X1: 0.05 sqrt(7.5) = 0.137 um);
    'after+a' of the calibrated rerun is 0 on both channels."""
    from validate.apply import format_before_after

    d, after, n = _calibrated_case()
    calibrated = d.evidence.measured.copy()
    rows = [ln.split() for ln in format_before_after(d, after, calibrated).splitlines()[1:3]]
    values = [[float(v) for v in (r[2], r[3], r[5], r[6])] for r in rows]
    plain = 0.05 * np.sqrt(np.mean(n ** 2))
    np.testing.assert_allclose(values[0], [2.0, 0.0, 2.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(values[1], [plain, plain, 0.0, 0.0], rtol=1e-3, atol=1e-9)


def test_group_rms_is_over_the_groups_own_samples():
    """group_rms(d, flat, group): the RMS of the group's entries only: temperature 3 K, probe
    4 um (not the RMS over both, sqrt(12.5))."""
    from validate.apply import group_rms
    from validate.diagnose import Diagnosis
    from validate.fit import BoundedFitter

    ev = _evidence(np.zeros((4, 2)), ["temperature", "probe"], ["temperature:T0", "probe:X1"])
    d = Diagnosis(ev, None, np.zeros(8), np.ones(8), BoundedFitter(np.zeros(8), np.ones(8)), [])
    flat = np.tile([3.0, -4.0], 4)
    assert group_rms(d, flat, "temperature") == pytest.approx(3.0, rel=1e-15)
    assert group_rms(d, flat, "probe") == pytest.approx(4.0, rel=1e-15)


# --- the report: titles, colours, captions, the sensor map ---------------------------------------

@pytest.fixture
def captured(monkeypatch):
    """The figures the report would embed, kept instead of encoded."""
    import validate.report as R

    figs = []
    monkeypatch.setattr(R, "_png", lambda fig: figs.append(fig) or "png")
    yield figs
    for f in figs:
        plt.close(f)


def test_the_worst_channels_titles_give_the_rmse_before_and_after(captured):
    """Each panel's title: the channel's RMSE before -> after adding the top candidate (constant
    offsets 1 K and 2 um before; after: 0.25 K and 0.5 um)."""
    import validate.report as R

    model = np.tile(np.linspace(20.0, 21.0, 5)[:, None], (1, 2))
    rec = NS(times=np.arange(5) * 600.0, t0=0.0, measured=model + [1.0, 2.0], model=model, weights=np.ones(2),
             phases=[], groups=["temperature", "probe"], channels=["temperature:a", "probe:X1"])
    R._worst_channels(NS(candidates=[]), rec, rec.measured - [0.25, 0.5])
    titles = [ax.get_title(loc="left") for ax in captured[0].axes]
    assert titles == ["probe:X1: RMSE 2 -> 0.5 um", "temperature:a: RMSE 1 -> 0.25 K"]


def _ranked(verdict):
    return NS(verdict=verdict, residual_factor={"temperature": 2.0},
              candidates=[{"effect": "electrical_cabinet", "explained": 0.6, "significant": True, "at_bound": [],
                           "confidence": 0.9, "values_si": {"electrical_cabinet": {"power": 120.0}}},
                          {"effect": "spindle_motor", "explained": 0.2, "significant": False, "at_bound": [],
                           "confidence": 0.1, "values_si": {"spindle_motor": {"power": 30.0}}}])


@pytest.mark.parametrize("verdict, top", [("explained", "C2"), ("partly_explained", "C2"), ("nothing_missing", "C1"),
                                          ("unexplained", "C1")])
def test_the_ranking_is_green_only_for_the_candidate_the_verdict_names(captured, verdict, top):
    """The candidate ranking's bars: green (C2) for the top candidate only when the verdict names
    it (explained, partly explained); a significant top candidate the verdict does not name is
    orange (C1); one that fails the test grey."""
    import matplotlib.colors as mc

    import validate.report as R

    R._ranking(_ranked(verdict))
    bars = captured[0].axes[0].patches
    colours = [mc.to_hex(b.get_facecolor()) for b in bars]     # drawn bottom-up: the top candidate last
    assert colours == [mc.to_hex("0.6"), mc.to_hex(top)]


def test_the_reports_ranking_caption_states_this_diagnosiss_test(monkeypatch, tmp_path):
    """write_report's caption of the candidate ranking gives the test the diagnosis applied:
    (bic_margin, min_explained) = (12, 0.6) reads '>= 12 BIC units, >= 60% explained'."""
    import validate.diagnose as D
    import validate.report as R
    from validate.fit import BoundedFitter

    monkeypatch.setattr(D, "format_diagnosis", lambda d: "ranking")
    monkeypatch.setattr(R, "figures", lambda d, machine, after=None: {"Candidate ranking": "png"})
    ev = _evidence(np.zeros((2, 1)), ["temperature"], ["temperature:T0"])
    d = D.Diagnosis(ev, None, np.zeros(2), np.ones(2), BoundedFitter(np.zeros(2), np.ones(2)), [],
                    test=(12.0, 0.6), levels={"temperature": (0.05, None)}, message="m")
    page = R.write_report(d, NS(name="cframe-vmc", parts=[]), tmp_path / "rep").read_text()
    assert "(&gt;= 12 BIC units, &gt;= 60% explained)" in page
    assert "within 3x noise alone, the model error not estimated" in page


def test_the_sensor_map_after_row_is_the_residual_after_the_candidate(captured):
    """The sensor map's second row colours each temperature sensor by RMS(measured - after):
    residuals 3 and 4 K before, 1 and 0.5 K after (the after model leaves them)."""
    import validate.report as R

    model = np.full((4, 3), 20.0)
    rec = NS(measured=model + [3.0, 4.0, 9.0], model=model, groups=["temperature", "temperature", "probe"],
             sensor_points=[NS(xyz=(1.0, 0.5, 0.4), name="a"), NS(xyz=(0.2, 0.5, 1.5), name="b")])
    R._sensor_map(NS(candidates=[]), rec, rec.measured - [1.0, 0.5, 0.0], TwoPartMachine())
    fig = captured[0]
    before, after = fig.axes[0].collections[-1], fig.axes[2].collections[-1]
    np.testing.assert_allclose(np.asarray(before.get_array()), [3.0, 4.0])
    np.testing.assert_allclose(np.asarray(after.get_array()), [1.0, 0.5])


# --- the region map --------------------------------------------------------------------------------

_R = np.tile([3.0, 4.0, 9.0], (4, 1))


def _localised(verdict="partly_explained", regions=None):
    return NS(regions=regions or [{"region": "column.+x", "power_W": 80.0, "schedule": "constant", "explained": 0.4}],
              record=NS(groups=["temperature", "temperature", "probe"],
                        sensor_points=[NS(xyz=(1.0, 0.5, 0.4)), NS(xyz=(0.2, 0.5, 1.5))]),
              verdict=verdict, fits=[NS(response=np.tile([2.0, 1.0, 9.0], (4, 1)))],
              evidence=NS(split=lambda x: (x,)), residual_after=lambda resp: _R - resp, fitter=NS(r=_R))


def test_a_face_region_is_drawn_on_its_own_side_of_the_part():
    """'column.+x' is the column's face at its largest x (0.5 m): in the front view (x-z) a thick
    vertical edge at x = 0.5 from z = 0.5 to 2 m; 'column.-x' at x = 0."""
    from validate.report_map import region_map

    for region, x in (("column.+x", 0.5), ("column.-x", 0.0)):
        fig = region_map(_localised(regions=[{"region": region, "power_W": 80.0, "schedule": "constant",
                                              "explained": 0.4}]), TwoPartMachine())
        try:
            edges = [ln for ln in fig.axes[0].lines if ln.get_linewidth() == 4]
            assert len(edges) == 1
            np.testing.assert_array_equal(edges[0].get_xdata(), [x, x])
            np.testing.assert_array_equal(edges[0].get_ydata(), [0.5, 2.0])
        finally:
            plt.close(fig)


def test_the_region_map_colours_sensors_by_the_residual_the_verdicts_model_leaves():
    """With an unexplained verdict no candidate is kept: the sensors show the baseline residual
    (residual_after(0): RMS 3 and 4 K), not what the unnamed top candidate would leave (1, 3)."""
    from validate.report_map import region_map

    fig = region_map(_localised("unexplained"), TwoPartMachine())
    try:
        np.testing.assert_allclose(np.asarray(fig.axes[0].collections[-1].get_array()), [3.0, 4.0])
    finally:
        plt.close(fig)


def test_the_region_map_keeps_the_five_best_regions():
    """region_map(top=5) of six ranked regions draws and keys the first five, best first."""
    from validate.report_map import region_map

    regions = [{"region": r, "power_W": 10.0 * (6 - k), "schedule": "constant", "explained": 0.1 * (6 - k)}
               for k, r in enumerate(["bed", "column", "bed.+z", "column.+x", "column.-y", "bed.-x"])]
    fig = region_map(_localised(regions=regions), TwoPartMachine())
    try:
        key = fig._suptitle.get_text()
        assert [k.split()[1] for k in key.removeprefix("best regions: ").split("; ")] == \
            ["bed", "column", "bed.+z", "column.+x", "column.-y"]
        assert sorted(t.get_text() for t in fig.axes[0].texts) == ["1", "2", "3", "4", "5"]
    finally:
        plt.close(fig)
