"""The diagnosis's numbers against their documented formulas, on small stand-in evidence (records
with channels, groups and samples only; no twin run): the noise levels and group levels
(validate.evidence, validate.verdict), the BIC scores, weights and twins of the candidates
(validate.diagnose's module docstring), the pair test, the 'at_bound' flag and the model-error
ratio along a signature."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from twin.model import ModelSpec
from validate.candidates import Candidate
from validate.evidence import Evidence, noise_levels
from validate.fit import BOUND_TOL, BoundedFitter, at_bounds
from validate.search import Fit
from validate.verdict import BEYOND_CAP, WITHIN, Share, above_noise, beyond_model_error, group_levels

REL = 1e-12
FRONT = Candidate("spindle_bearings.front_power", "parameter", "spindle_bearings", "front_power", 50.0, 450.0,
                  150.0, 300.0, True, True)
CABINET = Candidate("electrical_cabinet", "effect", "electrical_cabinet", "power", 0.0, 1000.0, 0.0, 40.0, True, False)
MOTOR = Candidate("spindle_motor.power", "parameter", "spindle_motor", "power", 0.0, 5000.0, 500.0, 800.0, True, True)
FLOOR = Candidate("floor.conductance", "parameter", "floor", "conductance", 2.0, 200.0, 20.0, 110.0, False, True)


def _record(label, measured, groups, channels=None, noise=None):
    measured = np.asarray(measured, float)
    return SimpleNamespace(label=label, measured=measured, groups=list(groups), phases=[],
                           channels=list(channels or [f"{g}:{k}" for k, g in enumerate(groups)]),
                           times=np.arange(len(measured)) * 60.0, noise=noise or {}, model_error=None)


# --- noise and group levels -----------------------------------------------------------------------

def test_noise_level_is_the_median_of_sqrt_half_mean_squared_difference_floored_at_half_a_step():
    """sigma_g = median over the group's channels of sqrt(mean(diff(y)^2) / 2), at least half the
    instrument's step. Three temperature ramps of 0.1, 0.2 and 0.9 K per sample: levels
    0.1/sqrt 2, 0.2/sqrt 2, 0.9/sqrt 2, median 0.2/sqrt 2 = 0.14142 K (the mean would be
    0.4/sqrt 2; without the 1/2, 0.2). A constant probe reads 0: its floor, half the default
    0.1 um resolution = 0.05 um; a temperature group ramping 0.01 K a sample (0.0071 K) is floored
    at half the 0.0625 K step, 0.03125 K."""
    spec = ModelSpec(())
    k = np.arange(20.0)[:, None]
    y = np.hstack([k * 0.1, k * 0.9, k * 0.2, np.full((20, 1), 3.0)])
    levels = noise_levels(y, ["temperature"] * 3 + ["probe"], spec)
    assert levels["temperature"] == pytest.approx(0.2 / math.sqrt(2.0), rel=REL, abs=0)
    probe_step = spec.params["probe"]["resolution"] * 1e6
    assert probe_step == pytest.approx(0.1, rel=REL)
    assert levels["probe"] == pytest.approx(0.5 * probe_step, rel=REL, abs=0)
    quiet = noise_levels(k * 0.01, ["temperature"], spec)["temperature"]
    step = spec.params["temperature_sensor"]["quantisation"]
    assert step == 0.0625 and quiet == 0.5 * step


def test_group_noise_over_two_records_is_their_quadratic_mean():
    """group_levels: sigma_g over every record is the root mean square of the records' levels (the
    same quadratic combination as the factor's RMS numerator): records at 0.03 and 0.04 K give
    sqrt((0.03^2 + 0.04^2) / 2) = 0.035355 K, not their mean 0.035 K; a group in one record only
    keeps that record's level."""
    a = _record("a", np.zeros((4, 2)), ["temperature", "probe"], noise={"temperature": 0.03, "probe": 0.2})
    b = _record("b", np.zeros((4, 1)), ["temperature"], noise={"temperature": 0.04})
    levels = group_levels(Evidence([a, b]), None)
    assert levels["temperature"][0] == pytest.approx(math.sqrt((0.03 ** 2 + 0.04 ** 2) / 2), rel=REL, abs=0)
    assert levels["probe"] == (0.2, None)


def test_a_factor_of_exactly_within_is_not_above_noise():
    """WITHIN is the largest factor still called noise: a group at exactly 3.0 is not above it
    (nor counted by the significance share), one a hair above is."""
    assert WITHIN == 3.0
    assert above_noise({"temperature": 3.0, "probe": 3.0 + 1e-9, "laser": 0.5}) == ["probe"]


def test_the_share_is_one_minus_the_ratio_of_weighted_sums_of_squares():
    """Share.of_residual = 1 - SSE(res) / SSE_0 over A (weighted, nuisance fitted): r = (1, 2),
    weights (1, 1), a residual (0.5, 1) after: SSE = 1.25 of SSE_0 = 5, explained 0.75 (not the
    RMS ratio's 0.5)."""
    ev = Evidence([_record("a", [[1.0, 2.0]], ["temperature", "temperature"])])
    r = np.array([1.0, 2.0])
    share = Share(ev, BoundedFitter(r, np.ones(2)), {"temperature": 1.0}, r)
    assert share.of_residual(np.array([0.5, 1.0])) == pytest.approx(0.75, rel=REL)


# --- the model error along a signature ------------------------------------------------------------

def test_beyond_is_the_smallest_member_ratio_and_is_capped():
    """beyond = min_i |x_r,i| / |x_m,i| with x_m the least-squares fit of the signed model error m
    on the members' columns: m = 2 u + 5 v on independent columns u, v gives x_m = (2, 5) exactly;
    members fitted 60 W and 40 W from their zeros give ratios 30 and 8: beyond = 8 (not 30). A model
    error with no component along the columns (m = 0) moves nothing: the ratio is capped at
    BEYOND_CAP = 1e6."""
    rng = np.random.default_rng(11)
    u, v = rng.standard_normal((2, 300))
    fitter = BoundedFitter(rng.standard_normal(300), np.ones(300))
    fit = Fit((FRONT, CABINET), (210.0, 40.0), 60.0 * u + 40.0 * v, 0.0, (u, v))
    assert beyond_model_error(fitter, fit, 2.0 * u + 5.0 * v) == pytest.approx(8.0, rel=1e-9)
    assert BEYOND_CAP == 1e6
    assert beyond_model_error(fitter, fit, np.zeros(300)) == BEYOND_CAP


# --- at a bound -----------------------------------------------------------------------------------

def test_at_bound_is_within_a_thousandth_of_the_ranges_width():
    """A member is at a bound when within BOUND_TOL (1e-3) of its range's width of either end:
    the cabinet in [0, 1000] W at 0.3 W (0.3 <= 1 W) and the front bearing in [50, 450] W at
    449.7 W (0.3 <= 0.4 W) are; at 5 W and 449.5 W they are not (a 1 % tolerance would flag 5 W,
    an absolute 1e-3 would miss 0.3 W)."""
    from validate.fit_text import at_bound
    assert BOUND_TOL == 1e-3
    g = np.zeros(3)
    assert at_bound(Fit((CABINET, FRONT), (0.3, 449.7), g, 0.0)) == ["electrical_cabinet.power",
                                                                     "spindle_bearings.front_power"]
    assert at_bound(Fit((CABINET, FRONT), (5.0, 449.5), g, 0.0)) == []
    np.testing.assert_array_equal(at_bounds([0.3, 5.0, 999.2, 998.9], [0.0] * 4, [1000.0] * 4),
                                  [True, False, True, False])


# --- the candidates' scores -----------------------------------------------------------------------

def _effective(res: np.ndarray) -> float:
    """AR(1) effective samples of a (n_t, n_ch) block: N (1 - rho) / (1 + rho), rho the pooled
    lag-1 autocorrelation of the channel-centred residual, within [0, 0.999], at least 2."""
    x = res - res.mean(axis=0)
    rho = min(max(float(np.sum(x[1:] * x[:-1]) / np.sum(x * x)), 0.0), 0.999)
    return max(res.size * (1 - rho) / (1 + rho), 2.0)


def _scored():
    """One record of 200 samples: temperature channels T0, T1 (weight 1) and a probe P
    (weight 0.05). The baseline residual r is smooth; four fits leave e_k = r - g_k:
    e_1 = 0.6 q1 (q1 an AR(1) series, rho 0.5: the best fit); e_2 = beta q2 (beta = 0.6 e^(2/n),
    4 BIC units behind); e_3 = e_1 + 0.2 q3; e_4 = e_1 + D, D a cubic on the probe alone
    (large unweighted, small at weight 0.05); q_k weighted-orthonormal to r and to each other. The responses' SSEs are
    their own (no nuisance)."""
    from validate.diagnose import Diagnosis
    rng = np.random.default_rng(7)
    n_t, groups = 200, ["temperature", "temperature", "probe"]
    w_ch = np.array([1.0, 1.0, 0.05])
    w = np.broadcast_to(w_ch, (n_t, 3)).ravel()
    t = np.linspace(0.0, 1.0, n_t)[:, None]
    r = np.hstack([np.sin(2 * np.pi * t), 0.5 * np.cos(3 * np.pi * t), 40 * t ** 2]).ravel()

    def ar1():
        e = rng.standard_normal((n_t, 3))
        for k in range(1, n_t):
            e[k] += 0.5 * e[k - 1]
        return e

    basis = [r / np.linalg.norm(w * r)]
    qs = []
    for make in (ar1, ar1, ar1):
        q = make().ravel()
        for b in basis:
            q = q - (w * q) @ (w * b) * b
        q /= np.linalg.norm(w * q)
        basis.append(q)
        qs.append(q)
    r = basis[0]                                   # |w r| = 1: SSE_0 = 1
    q1, q2, q3 = qs
    e1 = 0.6 * q1
    n = _effective(e1.reshape(n_t, 3))
    beta = 0.6 * math.exp(2.0 / n)
    D = np.zeros((n_t, 3))
    D[:, 2] = 1.1 * np.linspace(-1.0, 1.0, n_t) ** 3
    residuals = [e1, beta * q2, e1 + 0.2 * q3, e1 + D.ravel()]
    fitter = BoundedFitter(r, w)
    rec = _record("m", r.reshape(n_t, 3), groups, ["temperature:T0", "temperature:T1", "probe:P"])
    ev = Evidence([rec])
    d = Diagnosis(ev, None, np.zeros_like(r), w, fitter, [])
    d.share = Share(ev, fitter, {"temperature": 10.0, "probe": 1.0}, r)
    cands = (FRONT, CABINET, MOTOR, FLOOR)
    fits = [Fit((c,), (c.reference,), r - e, fitter.sse(r - e)) for c, e in zip(cands, residuals)]
    fits.sort(key=lambda f: f.sse)
    return d, fits, r, w, n_t


def test_candidate_scores_are_the_documented_bic_weights_shares_and_twins(monkeypatch):
    """validate.diagnose, per candidate k (k parameters, weighted SSE_k; N samples; n the AR(1)
    effective samples of the best candidate's residual):

        BIC_0 = n ln(SSE_0 / N),  BIC_k = n ln(SSE_k / N) + k ln n,  delta_bic = BIC_0 - BIC_k,
        confidence = exp(-BIC_k / 2) / sum over {0, candidates} exp(-BIC / 2),
        explained_all = 1 - SSE_k / SSE_0,  explained = 1 - SSE_k(A) / SSE_0(A) (A: the groups
        above noise, here the temperatures),
        twins: |BIC_k - BIC_j| < 6 or |corr(w g_k, w g_j)| > 0.95,
        explains_most: channels by 1 - (RMS_after / RMS_before)^2, largest first.

    The set-up hits each threshold from its side: fit 2 is 4 BIC units behind fit 1 with its
    signature correlated < 0.95 (twins by BIC only), fit 3 is >= 6 units behind with corr in
    (0.95, 0.99] (twins by correlation only), fit 4 differs from fit 1 on the low-weight probe
    only: weighted corr > 0.95, unweighted < 0.95."""
    import validate.diagnose as D
    monkeypatch.setattr(D, "reasoning", lambda d, g: {})
    d, fits, r, w, n_t = _scored()
    D._score(d, fits, 0.5, 10.0)
    N = r.size
    sse0 = float((w * r) @ (w * r))
    n = _effective((r - fits[0].response).reshape(n_t, 3))
    assert n != pytest.approx(N, rel=0.05) and n != pytest.approx(_effective(r.reshape(n_t, 3)), rel=0.05)
    assert d.n_eff == pytest.approx(n, rel=REL)
    bic0 = n * math.log(sse0 / N)
    bic = [n * math.log(f.sse / N) + math.log(n) for f in fits]
    every = np.array([bic0] + bic)
    weights = np.exp(-(every - every.min()) / 2)
    weights /= weights.sum()
    temp = np.broadcast_to(np.array([True, True, False]), (n_t, 3)).ravel()
    sse0_a = float(((w * r)[temp]) @ ((w * r)[temp]))
    sig = [w * f.response for f in fits]
    corr = lambda a, b: float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)))
    by_name = {c["effect"]: c for c in d.candidates}
    assert [c["effect"] for c in d.candidates] == [f.name for f in fits]
    for i, f in enumerate(fits):
        c = d.candidates[i]
        e = (w * (r - f.response))[temp]
        assert c["delta_bic"] == pytest.approx(bic0 - bic[i], rel=REL)
        assert c["confidence"] == pytest.approx(weights[i + 1], rel=1e-9, abs=1e-300)
        assert c["explained_all"] == pytest.approx(1 - f.sse / sse0, rel=REL)
        assert c["explained"] == pytest.approx(1 - float(e @ e) / sse0_a, rel=REL)
        assert c["significant"] == (bic0 - bic[i] >= 10 and c["explained"] >= 0.5)
        want = [o.name for j, o in enumerate(fits) if j != i
                and (abs(bic[i] - bic[j]) < 6 or abs(corr(sig[i], sig[j])) > 0.95)]
        assert c["indistinguishable_from"] == want[:5], f.name
        before = np.sqrt(np.mean(r.reshape(n_t, 3) ** 2, axis=0))
        after = np.sqrt(np.mean((r - f.response).reshape(n_t, 3) ** 2, axis=0))
        per = 1 - (after / before) ** 2
        assert c["explains_most"] == [["temperature:T0", "temperature:T1", "probe:P"][k] for k in np.argsort(-per)]
    assert sum(c["confidence"] for c in d.candidates) + weights[0] == pytest.approx(1.0, rel=1e-12)
    assert d.significant == d.candidates[0]["significant"]
    # the set-up reaches each threshold from the side the docstring names
    best, second = by_name[FRONT.name], by_name[CABINET.name]
    g = {f.name: f for f in fits}
    b = {f.name: bic[i] for i, f in enumerate(fits)}
    s = {f.name: sig[i] for i, f in enumerate(fits)}
    assert b[CABINET.name] - b[FRONT.name] == pytest.approx(4.0, rel=1e-9)
    assert abs(corr(s[FRONT.name], s[CABINET.name])) < 0.95 and CABINET.name in best["indistinguishable_from"]
    assert b[MOTOR.name] - b[FRONT.name] >= 6 and 0.95 < corr(s[FRONT.name], s[MOTOR.name]) <= 0.99
    assert MOTOR.name in best["indistinguishable_from"]
    assert b[FLOOR.name] - b[FRONT.name] >= 6 and corr(s[FRONT.name], s[FLOOR.name]) > 0.95
    assert corr(g[FRONT.name].response, g[FLOOR.name].response) < 0.95
    assert FLOOR.name in best["indistinguishable_from"]
    assert second["confidence"] < best["confidence"]


# --- the pair test --------------------------------------------------------------------------------

def _pair_setup(sse_temp_a: float, sse_temp_b: float, n_ln_ratio: float, n: float = 100.0):
    """Residual r over a loud temperature block (T) and a quiet probe block (P, the same S after
    every fit): single a leaves sse_temp_a + S, single b sse_temp_b + S, the pair 0.001 + S, S
    solved so that n ln(SSE_a / SSE_pair) = ``n_ln_ratio``."""
    k = math.exp(n_ln_ratio / n)
    S = (sse_temp_a - k * 0.001) / (k - 1)
    m = 50
    rng = np.random.default_rng(2)
    base_t, base_p = rng.standard_normal(m), rng.standard_normal(m)
    unit_t, unit_p = base_t / np.linalg.norm(base_t), base_p / np.linalg.norm(base_p)
    r = np.r_[3.0 * unit_t, 2.0 * math.sqrt(S) * unit_p]
    w = np.ones(2 * m)
    left = lambda sse_t: np.r_[math.sqrt(sse_t) * unit_t, math.sqrt(S) * unit_p]
    ev = Evidence([_record("m", r.reshape(2, m).T, ["temperature", "probe"])])
    # the evidence's flat order is row-major (n_t, n_ch): lay the blocks out in that order
    order = np.arange(2 * m).reshape(2, m).T.ravel()
    r, w = r[order], w[order]
    fitter = BoundedFitter(r, w)
    share = Share(ev, fitter, {"temperature": 10.0, "probe": 1.0}, r)
    mk = lambda cands, sse_t: Fit(cands, tuple(c.reference for c in cands), r - left(sse_t)[order],
                                  float(sse_t + S))
    a, b = mk((FRONT,), sse_temp_a), mk((CABINET,), sse_temp_b)
    pair = mk((FRONT, CABINET), 0.001)
    d = SimpleNamespace(share=share)
    return d, pair, [a, b], n


def test_a_pairs_second_member_must_gain_the_bic_margin_against_its_better_member():
    """_pair_significant: gain = n ln(SSE_better / SSE_pair) - (k_pair - k_better) ln n >= 10 and
    the pair explains >= 50 % of what the better member leaves over the loud groups. With
    n = 100: n ln(SSE_a / SSE_pair) = 17 gives gain 17 - ln 100 = 12.4 (passes; charging both
    parameters, 17 - 2 ln 100 = 7.8, would not); = 12 gives 7.4 (fails), though against the worse
    single b (its temperature SSE twice a's) the gain would pass."""
    from validate.diagnose import _pair_significant
    d, pair, singles, n = _pair_setup(0.1, 0.1, 17.0)
    assert d.share.explained(pair.response, singles[0].response) == pytest.approx(0.99, rel=1e-9)
    assert n * math.log(singles[0].sse / pair.sse) == pytest.approx(17.0, rel=1e-9)
    assert _pair_significant(d, pair, singles, n, 0.5, 10.0)
    d, pair, singles, n = _pair_setup(0.1, 0.2, 12.0)
    assert n * math.log(singles[1].sse / pair.sse) - math.log(n) >= 10
    assert not _pair_significant(d, pair, singles, n, 0.5, 10.0)
