"""The diagnosis's parts, each against a closed form: bounded least squares with a bounded
nuisance, Gauss-Newton, the verdict rule and its messages, the region partition and map, the
response of the observables to added heat inputs (superposition), and the declared uncertain
parameters (linear or not). The candidate search: tests/test_diagnosis_search.py."""

from __future__ import annotations

import numpy as np
import pytest

from geometries.regions import DIRECTIONS, Facing, Parts, partition, region_by_name
from twin.effects import EFFECTS
from twin.model import ModelSpec, model_spec
from twin.scenario import AirEvent, Ambient, Scenario
from validate.fit import BoundedFitter, gauss_newton
from validate.search import Fit
from validate.candidates import Candidate
from validate.verdict import BEYOND, WITHIN, beyond_model_error, decide


def _problem(seed=0, n=400):
    rng = np.random.default_rng(seed)
    u, v = rng.standard_normal(n), rng.standard_normal(n)
    return u, v, rng


def test_bounded_nuisance_recovers_or_sits_at_its_bound():
    """r = 2 u + 0.05 v: with the nuisance band +-0.1 the fit is the ordinary least-squares
    solution (x, c) = (2, 0.05) exactly; with the band +-0.02 the nuisance sits at +0.02, is
    flagged at its bound, and x is the least-squares solution with c pinned there,
    x = u.(r - 0.02 v) / u.u."""
    u, v, _ = _problem()
    r = 2 * u + 0.05 * v
    wide = BoundedFitter(r, np.ones_like(r), v[None, :], [-0.1], [0.1])
    x, c, sse = wide.solve(u[:, None], [-10], [10])
    assert x[0] == pytest.approx(2.0, abs=1e-9) and c[0] == pytest.approx(0.05, abs=1e-9) and sse < 1e-15
    assert not wide.at_bound(c)[0]
    tight = BoundedFitter(r, np.ones_like(r), v[None, :], [-0.02], [0.02])
    x, c, _ = tight.solve(u[:, None], [-10], [10])
    assert c[0] == pytest.approx(0.02, abs=1e-9) and tight.at_bound(c)[0]
    assert x[0] == pytest.approx(u @ (r - 0.02 * v) / (u @ u), rel=1e-9)
    # the residual after a response g is r - g - c v with c refitted within the band
    np.testing.assert_allclose(tight.residual_after(2 * u), r - 2 * u - 0.02 * v, atol=1e-9)


def test_gauss_newton_finds_a_bounded_nonlinear_parameter():
    """y(p) = exp(-p t) - 1 sampled on t in [0, 1], truth p = 1.7: bounded Gauss-Newton from
    p = 0.5 reaches it (noise-free), from p = 5, its upper bound, too (the forward difference
    turned backwards there, dy/dp = (y(p - dp) - y(p)) / (-dp)), and with the upper bound at 1.2
    stops at the bound."""
    t = np.linspace(0, 1, 200)
    seen = []

    def ev(p):
        seen.append(float(p[0]))
        return np.exp(-p[0] * t) - 1

    r = ev([1.7])
    f = BoundedFitter(r, np.ones_like(r))
    for start in (0.5, 5.0):
        seen.clear()
        p, g, sse, _ = gauss_newton(f, ev, np.array([start]), np.array([0.0]), np.array([5.0]), np.array([False]),
                                    {}, 8)
        assert p[0] == pytest.approx(1.7, rel=1e-4) and sse < 1e-10, start
        assert 0.0 <= min(seen) and max(seen) <= 5.0, start    # never evaluated outside its bounds
    p, *_ = gauss_newton(f, ev, np.array([0.5]), np.array([0.0]), np.array([1.2]), np.array([False]), {}, 8)
    assert p[0] == pytest.approx(1.2)


def test_a_pinned_variable_is_held_at_its_value_and_the_rest_fit_what_it_leaves():
    """r = 2 u + 3 v with x_u pinned by a zero-width bound [2, 2]: x = (2, 3) and the SSE vanishes
    (the free variable fits r - 2 u); pinned at 1 instead, x_v is the least-squares fit to
    r - u, v.(r - u) / v.v."""
    u, v, _ = _problem()
    r = 2 * u + 3 * v
    f = BoundedFitter(r, np.ones_like(r))
    x, _, sse = f.solve(np.column_stack([u, v]), [2.0, -10.0], [2.0, 10.0])
    assert x == pytest.approx([2.0, 3.0], abs=1e-12) and sse < 1e-15
    x, _, _ = f.solve(np.column_stack([u, v]), [1.0, -10.0], [1.0, 10.0])
    assert x[0] == 1.0 and x[1] == pytest.approx(v @ (r - u) / (v @ v), rel=1e-12)


def test_effective_samples_of_an_ar1_residual():
    """N_eff = N (1 - rho) / (1 + rho), rho the pooled lag-1 autocorrelation of the centred
    residual: four blocks of ten +1 / -1 (mean 0) have sum x_t x_(t-1) = 39 - 6 = 33 over
    sum x^2 = 40, rho = 33/40, N_eff = 40 (7/40) / (73/40) = 280/73; white-ish alternation
    (rho < 0, clipped to 0) counts every sample, as does a constant one (nothing to correlate)."""
    from validate.evidence import effective_samples
    blocks = np.repeat([1.0, -1.0, 1.0, -1.0], 10)[:, None]
    assert effective_samples(blocks) == pytest.approx(280 / 73, rel=1e-12)
    assert effective_samples(np.resize([1.0, -1.0], 40)[:, None]) == pytest.approx(40.0, rel=1e-12)
    assert effective_samples(np.ones((40, 1))) == 40.0          # nothing varies: no correlation to discount
    assert effective_samples(np.linspace(0.0, 1.0, 40)[:, None]) == 2.0   # a ramp: 40 (1 - rho) / (1 + rho) < 2, floored


def test_instrument_noise_levels_of_the_missing_channels_cost():
    """The noise each group's instruments would add (validate.channel_cost), in the channel's unit,
    at least half the reading step: the defaults (twin list instruments) give temperature
    max(0.05, 0.0625 / 2) = 0.05 K, probe max(0.05, 0.1 / 2) = 0.05 um, laser max(0.2, 0.05) =
    0.2 um, FBG max(0.5, 0.8 / 2) = 0.5 um/m; a coarser temperature step of 0.25 K gives 0.125 K."""
    from geometries import build_machine
    from validate.channel_cost import _noise
    machine = build_machine("cframe-vmc")
    noise = _noise(model_spec(machine))
    for group, value in (("temperature", 0.05), ("probe", 0.05), ("laser", 0.2), ("strain", 0.5)):
        assert noise[group] == pytest.approx(value, rel=1e-12), group
    coarse = _noise(model_spec(machine, settings=["temperature_sensor.quantisation=0.25 K"]))
    assert coarse["temperature"] == pytest.approx(0.125, rel=1e-12)


@pytest.mark.parametrize("factors,significant,after,expected", [
    ({"temperature": 1.2, "probe": 2.9}, False, None, "nothing_missing"),
    ({"temperature": 1.2, "probe": 2.9}, True, {"temperature": 1.0, "probe": 1.0}, "nothing_missing"),
    ({"temperature": 20.0, "probe": 2.0}, True, {"temperature": 1.3, "probe": 0.7}, "explained"),
    ({"temperature": 20.0, "probe": 2.0}, True, {"temperature": 5.0, "probe": 0.7}, "partly_explained"),
    ({"temperature": 3.5}, False, {"temperature": 3.4}, "unexplained"),
    ({"temperature": 3.0, "probe": 1.0}, False, None, "nothing_missing"),        # 3 is still within
    ({"temperature": 20.0}, True, {"temperature": 3.0}, "explained"),
])
def test_verdict_rule(factors, significant, after, expected):
    """The four verdicts from the residual factors (residual / sqrt(noise^2 + model error^2)) and
    the significance of the top candidate, WITHIN = 3."""
    assert WITHIN == 3.0
    assert decide(factors, significant, after) == expected


@pytest.mark.parametrize("beyond,significant,expected", [
    (None, True, "nothing_missing"), (9.9, True, "nothing_missing"), (10.0, True, "explained"),
    (50.0, False, "nothing_missing"),
])
def test_verdict_within_the_envelope_but_beyond_the_model_error_along_the_signature(beyond, significant, expected):
    """Every factor <= WITHIN: ``explained`` only for a significant candidate whose fitted change
    is >= BEYOND (10) times what the model error alone produces along its signature."""
    assert BEYOND == 10.0
    factors = {"temperature": 2.0, "probe": 1.5}
    assert decide(factors, significant, {"temperature": 1.0, "probe": 1.0}, beyond) == expected


class _TwoGroups:
    """Evidence stand-in: the first n samples are group "laser", the rest "strain" (one measurement)."""

    multiple = False

    def __init__(self, n, m):
        self.mask = {"laser": np.r_[np.ones(n, bool), np.zeros(m, bool)],
                     "strain": np.r_[np.zeros(n, bool), np.ones(m, bool)]}

    def group_mask(self, g):
        return self.mask[g]


def test_explained_share_counts_only_the_groups_above_noise():
    """explained = 1 - SSE_k(A) / SSE_0(A), A the channels of the groups whose factor
    RMS(r) / sqrt(sigma^2 + e^2) exceeds WITHIN before any candidate. Lasers at 10x their noise
    and strain gauges at their noise (1x) carrying half the weighted residual: a candidate that
    removes the lasers' residual exactly explains 100 % of A (to round-off) though only about
    half of everything; with both groups at noise A is every channel and the share is the
    all-channel 1 - SSE_k / SSE_0."""
    from validate.verdict import Share
    from validate.verdict import residual_factors
    rng = np.random.default_rng(3)
    n = 500
    laser = 10 * 0.2 * np.sin(np.linspace(0, 6, n)) * np.sqrt(2)   # RMS 2.0 um = 10x a 0.2 um noise
    strain = rng.standard_normal(n)                                  # RMS about 1 um/m = its noise
    r = np.r_[laser, strain]
    w = np.r_[np.full(n, 1 / 2.0), np.full(n, 1.0)]                  # each group's weighted SSE alike
    fitter = BoundedFitter(r, w)
    ev = _TwoGroups(n, n)
    levels = {"laser": (0.2, 0.0), "strain": (float(np.sqrt(np.mean(strain ** 2))), 0.0)}
    share = Share(ev, fitter, residual_factors(ev, r, levels), r)
    np.testing.assert_array_equal(share.mask, ev.mask["laser"])
    g = np.r_[laser, np.zeros(n)]
    assert share.explained(g) == pytest.approx(1.0, abs=1e-12)
    everything = 1 - fitter.sse(g) / fitter.sse(np.zeros_like(r))
    assert 0.4 < everything < 0.6
    quiet = {"laser": (2.0, 0.0), "strain": levels["strain"]}
    share = Share(ev, fitter, residual_factors(ev, r, quiet), r)
    assert share.mask.all()
    assert share.explained(g) == pytest.approx(everything, rel=1e-12)
    # against a reference response (the pair test: the residual the better member leaves)
    half = np.r_[laser / 2, np.zeros(n)]
    share = Share(ev, fitter, residual_factors(ev, r, levels), r)
    assert share.explained(g, half) == pytest.approx(1.0, abs=1e-12)


def test_beyond_model_error_is_the_ratio_of_the_projections():
    """Weighted least squares along one column u: with m = a u + v, v w-orthogonal to u (and to
    the nuisance column n), x_m = a exactly; the candidate's fitted change x_r = p - p_0, so
    beyond = |p - p_0| / |a| to round-off. The nuisance is fitted jointly, within its band."""
    rng = np.random.default_rng(3)
    N = 400
    w = rng.uniform(0.5, 2.0, N)
    u, n, v = rng.normal(size=(3, N))
    basis = np.column_stack([u, n]) * w[:, None]
    vw = v * w
    vw -= basis @ np.linalg.lstsq(basis, vw, rcond=None)[0]   # v w-orthogonal to u and n
    v = vw / w
    a = 0.37
    fitter = BoundedFitter(rng.normal(size=N), w, n[None, :], [-0.1], [0.1])
    cand = Candidate("e.p", "parameter", "e", "p", 0.0, 400.0, 150.0, 200.0, True, True)
    fit = Fit((cand,), (212.0,), (212.0 - 150.0) * u, 0.0, (u,))
    assert beyond_model_error(fitter, fit, a * u + v) == pytest.approx(62.0 / a, rel=1e-9)


def test_partition_names_every_part_and_its_faces(machine, mm):
    """Each part's cells and its outer faces by direction; the region names resolve to the same
    regions a user writes; volume parts tile the machine (every cell in exactly one part)."""
    from twin.fem.regions import region_cells, region_facets
    p = partition(machine)
    assert len(p) == 7 * len(machine.parts)
    assert p["column"] == ("volume", Parts(("column",))) and p["column.+x"] == ("surface", Facing(Parts(("column",)), "+x"))
    assert region_by_name(machine, "column.+x", surface=True) == p["column.+x"][1]
    cells = np.concatenate([region_cells(mm, r) for k, r in p.values() if k == "volume"])
    assert len(cells) == len(np.unique(cells)) == mm.mesh.t.shape[1]
    faces = region_facets(mm, p["column.+x"][1])
    normals = mm.mesh.p[0, mm.mesh.facets[:, faces]]
    assert len(faces) and np.allclose(normals, 0.25)          # the column's right side, x = +0.25 m
    for bad, surface in (("columnn", True), ("column.+w", True), ("column.+x", False)):
        with pytest.raises(ValueError):
            region_by_name(machine, bad, surface)
    assert set(DIRECTIONS) == {"+x", "-x", "+y", "-y", "+z", "-z"}


def test_added_heat_responses_are_exact_superposition(machine, mm):
    """The theta-scheme is linear in its sources, so the response of every observable to an added
    source b s(t), computed alone from a zero start (PreparedTwin.responses), equals the run with
    the source minus the run without it, to round-off, for every column at once."""
    from twin.effects import HeatSource, SurfaceHeatFlux
    from twin.effects.custom import effects_from_dict, register_custom, unregister_custom
    from twin.fem.regions import region_cells, region_facets
    from twin.observe import FiveProbeTestBar, TemperatureSensors, sensor_points
    from twin.physics.prepared import PreparedTwin
    sc = Scenario("sup", ((1800.0, 9000.0), (1200.0, 0.0)), Ambient("constant", mean=20.0), 300.0)
    twin = PreparedTwin(machine, mm)
    spec = model_spec(machine)
    on = lambda t: 40.0 * (sc.spindle_speed(t) > 0)
    sources = [HeatSource("s", region_cells(mm, Parts(("saddle",))), lambda t: 25.0 * np.ones(np.shape(t))),
               SurfaceHeatFlux("c", region_facets(mm, Facing(Parts(("column",)), "+x")), on)]
    obs = [TemperatureSensors(sensor_points(machine)), FiveProbeTestBar()]
    resp = twin.responses(sc, spec, obs, sources, theta=1.0)
    data = {"effects": {"sup_a": {"kind": "heat_source", "region": "saddle", "power": "25 W"},
                        "sup_b": {"kind": "heat_flux", "region": "column.+x", "power": "40 W", "schedule": "spindle_on"}}}
    names = register_custom(effects_from_dict(data, "test", machine))
    try:
        _, base = twin.run(sc, spec, obs, theta=1.0)
        for j, name in enumerate(names):
            _, with_ = twin.run(sc, ModelSpec(spec.effects + (name,), spec.params), obs, theta=1.0)
            for key in ("temperature", "probes"):
                diff = (with_[key] - with_[key][0]) - (base[key] - base[key][0])
                scale = np.abs(diff).max()
                assert scale > 0
                np.testing.assert_allclose(resp[key][:, :, j], diff, atol=1e-9 * scale)
    finally:
        unregister_custom(names)



def test_added_heat_responses_on_the_iterative_solver(machine, mm):
    """The same responses from the Jacobi-PCG stepper (``--solver iterative``, heat_tol 1e-9 K:
    the capacity-weighted RMS error it may add over the run) agree with the direct solver's far
    inside 1e-6 of their peak."""
    from twin.effects import HeatSource
    from twin.fem.regions import region_cells
    from twin.observe import TemperatureSensors, sensor_points
    from twin.physics.prepared import PreparedTwin
    from twin.physics.options import SolverOptions

    sc = Scenario("sup", ((1200.0, 9000.0), (900.0, 0.0)), Ambient("constant", mean=20.0), 300.0)
    sources = [HeatSource("s", region_cells(mm, Parts(("saddle",))), lambda t: 25.0 * np.ones(np.shape(t)))]
    obs = [TemperatureSensors(sensor_points(machine))]
    direct = PreparedTwin(machine, mm, solver=SolverOptions("direct")).responses(sc, model_spec(machine), obs, sources)
    iterative = PreparedTwin(machine, mm, solver=SolverOptions("iterative", heat_tol=1e-9))
    got = iterative.responses(sc, model_spec(machine), obs, sources)
    scale = np.abs(direct["temperature"]).max()
    assert scale > 0.01
    np.testing.assert_allclose(got["temperature"], direct["temperature"], atol=1e-6 * scale)

UNCERTAIN = [(e, u.name) for e in sorted(EFFECTS) for u in EFFECTS[e].uncertain]


def test_candidates_whose_effect_cannot_act_are_left_out(machine):
    """The door stream acts only while a scenario's door is open (Effect.acts): on records
    without one its parameters are no candidates (their responses would be zero), with one they
    are; the room swing's growth with height acts only where the room air moves, door events
    aside (a daily room, a holiday); a door draft only if it opens within the record; a missing
    effect named by the user is kept regardless."""
    from twin.model import model_spec
    from validate.candidates import candidate_pool
    spec = model_spec(machine)
    calm = Scenario("calm", ((3600.0, 0.0),), Ambient("constant", mean=20.0), 60.0)
    door = Scenario("door", ((3600.0, 0.0),), Ambient("constant", mean=20.0, events=(
        AirEvent(start=600.0, change=-9.0, fall=600.0, recovery=1200.0, door=True),)), 60.0)
    daily = Scenario("daily", ((3600.0, 0.0),), Ambient("daily", mean=20.0, amplitude=2.0), 60.0)
    holiday = Scenario("holiday", ((3600.0, 0.0),), Ambient("constant", mean=20.0, events=(
        AirEvent(start=0.0, change=-4.0, fall=0.0, hold=1800.0),)), 60.0)
    names = lambda *scs, **kw: {c.name for c in candidate_pool(machine, spec, scenarios=scs, **kw)}  # noqa: E731
    stream = {"door_stream.h", "door_stream.temperature_difference"}
    assert "door_stream" in spec.effects and "stratified_swing" in spec.effects
    assert not stream & names(calm) and stream <= names(door) and stream <= names(calm, door)
    growth = "stratified_swing.growth"
    assert growth not in names(calm) | names(door) and growth in names(daily) and growth in names(holiday)
    # a door draft whose first opening (1 h by default) is not within the record
    longer = Scenario("longer", ((7200.0, 0.0),), Ambient("constant", mean=20.0), 60.0)
    assert "door_draft" not in names(calm) and "door_draft" in names(longer)
    less = model_spec(machine, "-door_stream")
    assert "door_stream" not in {c.name for c in candidate_pool(machine, less, scenarios=(calm,))}
    assert "door_stream" in {c.name for c in candidate_pool(machine, less, ["door_stream"], scenarios=(calm,))}


@pytest.mark.parametrize("effect,name", UNCERTAIN)
def test_uncertain_parameters_are_declared_linear_or_not_truthfully(machine, mm, effect, name):
    """Every declared uncertain parameter lies in its parameter's bounds with the default inside,
    and its linearity declaration holds both ways on heat loads: a linear one makes every heat
    source's power affine in it, P(2 p) - 2 P(p) + P(0) = 0 (a linear heat equation then gives
    affine observables), a nonlinear one changes a film coefficient, a conductance or a signal's
    shape."""
    from twin.effects import ContactConductance, Convection
    eff = EFFECTS[effect]
    u, par = eff.uncertainty(name), eff.parameter(name)
    assert par.lower <= u.lower <= par.default <= u.upper <= par.upper and u.why
    if not eff.applies_to(machine):
        return
    door = (AirEvent(start=900.0, change=-9.0, fall=600.0, recovery=1200.0, door=True),)   # door_stream's trigger
    sc = Scenario("u", ((1800.0, 6000.0), (1800.0, 0.0)), Ambient("daily", mean=20.0, amplitude=2.0,
                                                                   start_time_of_day=11 * 3600.0, events=door), 300.0)
    t = sc.times()
    p = {**eff.defaults(), "start": 600.0} if effect == "door_draft" else eff.defaults()
    zero, a, b = (eff.loads(mm, sc, {**p, name: k * u.upper / 2}) for k in (0, 1, 2))
    operator = any(isinstance(x, (Convection, ContactConductance)) for x in a)
    affine = all(np.allclose(y.power(t) - 2 * x.power(t) + z.power(t), 0, atol=1e-9 * (1 + np.abs(y.power(t)).max()))
                 for z, x, y in zip(zero, a, b) if hasattr(x, "power"))
    assert u.linear == (not operator and affine)


def test_unexplained_message_says_a_candidate_that_makes_the_loud_groups_worse_explains_none():
    """The share over the groups above noise is negative when the best fit over every channel leaves
    those groups worse: the message says so with the number, never 'explains only -31 %'."""
    from validate.verdict import message
    top = {"effect": "z_axis_holding", "explained": -0.31, "delta_bic": 12.0, "statement": "x"}
    levels = {"temperature": (0.05, 0.01), "probe": (0.05, 0.1)}
    text = message("unexplained", top, {"temperature": 2.6, "probe": 3.5}, None, levels, [("probe:Z", 4.0)],
                   "spindle on", [])
    assert "explains none of it" in text and "31% worse" in text and "-31" not in text
    top["explained"] = 0.2
    text = message("unexplained", top, {"temperature": 2.6, "probe": 3.5}, None, levels, [("probe:Z", 4.0)],
                   "spindle on", [])
    assert "explains only 20%" in text


def test_the_region_map_fits_a_missing_cooler_as_a_negative_power(monkeypatch):
    """A generic heat input of either sign: with one region whose 1 W response is u, another's w
    (nearly orthogonal) and the residual r = -3 u + 0.5 w, each region's power is its least-squares
    one alone, x = u.r / u.u (about -3 W: a cooler, within the +-POWER_LIMIT bounds), explaining
    1 - |r - x u|^2 / |r|^2, and the second's about 0.5 W."""
    import validate.localise as L
    u, w, _ = _problem()
    r = -3 * u + 0.5 * w
    monkeypatch.setattr(L, "region_columns", lambda *a, **k: (np.stack([u, w]), [("cooled", "part", "constant"),
                                                                               ("warmed", "part", "constant")]))
    regions = L.localise(None, BoundedFitter(r, np.ones_like(r)), None, None, twin=object())
    by = {x["region"]: x for x in regions}
    assert by["cooled"]["power_W"] == pytest.approx(u @ r / (u @ u), rel=1e-9)
    assert by["warmed"]["power_W"] == pytest.approx(w @ r / (w @ w), rel=1e-9)
    res = r - by["cooled"]["power_W"] * u
    assert by["cooled"]["explained"] == pytest.approx(1 - res @ res / (r @ r), rel=1e-9)
    assert by["cooled"]["power_W"] < -2.0


def test_the_region_maps_explained_share_is_of_the_nuisance_fitted_residual(monkeypatch):
    """The baseline of the explained share is the residual with the material-expansion nuisance
    already fitted, SSE_0 = min_c |r - c v|^2, not |r|^2: with r = 2 u + w + 3 v, the nuisance v
    (band +-10, wide enough to be free) and one region of response u, the region explains
    1 - SSE(u, v) / SSE_0 (about 0.8, its 2 u of the 2 u + w left after the nuisance), where a
    baseline without the nuisance would credit it with the expansion's 3 v too (about 0.93)."""
    import validate.localise as L
    u, w, rng = _problem(1)
    v = rng.standard_normal(len(u))
    r = 2 * u + w + 3 * v
    monkeypatch.setattr(L, "region_columns", lambda *a, **k: (u[None, :], [("heated", "part", "constant")]))
    (region,) = L.localise(None, BoundedFitter(r, np.ones_like(r), v[None, :], [-10.0], [10.0]), None, None,
                           twin=object())

    def sse(cols):
        res = r - cols @ np.linalg.lstsq(cols, r, rcond=None)[0]
        return res @ res

    sse0, sse1 = sse(v[:, None]), sse(np.column_stack([u, v]))
    assert region["explained"] == pytest.approx(1 - sse1 / sse0, rel=1e-9)
    assert 0.7 < region["explained"] < 0.85 < 0.9 < 1 - sse1 / (r @ r)
    assert region["power_W"] == pytest.approx(np.linalg.lstsq(np.column_stack([u, v]), r, rcond=None)[0][0], rel=1e-9)


def test_the_diagnosis_names_the_channels_furthest_above_their_groups_noise_worst_first():
    """verdict.worst_channels (the channels the diagnosis message names): the residual RMS of each
    channel over its group's envelope sqrt(noise^2 + model error^2); temperatures [0.3, 0.1] K over
    sqrt(0.03^2 + 0.04^2) = 0.05 K give 6 and 2, probes [4, 1] um over 0.5 um (noise alone, no
    estimate) 8 and 2: the top two are probe:Z (8) then temperature:a (6), not the largest raw
    RMS alone nor the order of the channels."""
    from types import SimpleNamespace as NS

    from validate.verdict import worst_channels
    names = ["temperature:a", "temperature:b", "probe:Y", "probe:Z"]
    per = np.array([0.3, 0.1, 1.0, 4.0])
    ev = NS(channel_names=lambda: names, per_channel=lambda r: per,
            records=[NS(groups=["temperature", "temperature", "probe", "probe"])])
    top = worst_channels(ev, np.zeros(4), {"temperature": (0.03, 0.04), "probe": (0.5, None)}, top=2)
    assert [n for n, _ in top] == ["probe:Z", "temperature:a"]
    assert [f for _, f in top] == pytest.approx([8.0, 6.0], rel=1e-12)


class _Record:
    """A record stand-in for validate.verdict.worst_time: times, phases, its clock's start t0."""

    def __init__(self, times, phases, t0, label="m"):
        self.times, self.phases, self.t0, self.label = times, phases, t0, label


class _OneRecord:
    """Evidence stand-in: one record whose flat vector is (time, channel) row by row."""

    multiple = False

    def __init__(self, rec, channels):
        self.records, self.channels = [rec], channels

    def split(self, flat):
        return [np.asarray(flat).reshape(-1, self.channels)]


def test_the_worst_time_is_the_phase_with_most_weighted_residual_on_the_logs_clock():
    """worst_time (the 'mostly during' of an unexplained verdict): sum over a phase's samples of
    (w r)^2, the weights making kelvin and micrometres comparable. 0.5 K on a temperature (w 10)
    over the six samples of the first hour: 6 x 5^2 = 150; 2 um on a probe (w 1) over the seven of
    the second: 7 x 2^2 = 28; so the first hour, printed on the log's clock (t0 = 2 h): 2.0-3.0 h
    (unweighted, the second hour would hold 28 against 1.5)."""
    from validate.channels import Phase
    from validate.verdict import worst_time

    t = np.arange(0.0, 7201.0, 600.0)
    phases = [Phase("spindle", "spindle on 9000 rpm", 0.0, 3600.0),
              Phase("spindle", "spindle off", 3600.0, 7200.0, closed=True)]
    residual = np.column_stack([np.where(t < 3600, 0.5, 0.0), np.where(t >= 3600, 2.0, 0.0)])
    weights = np.broadcast_to([10.0, 1.0], residual.shape)
    ev = _OneRecord(_Record(t, phases, 7200.0), 2)
    assert worst_time(ev, residual.ravel(), weights.ravel()) == "spindle on 9000 rpm (2.0-3.0 h)"


def test_the_region_map_keeps_each_regions_best_schedule(monkeypatch):
    """validate.localise.localise fits a generic heat input per region and schedule and keeps, per
    region, the schedule that explains most: with r = 2 u_spindle_on exactly, the saddle's
    'spindle_on' column explains all of it at 2 W (least squares, exact), whatever schedule was
    tried first ('constant', independent noise, explains nearly nothing)."""
    import validate.localise as L

    rng = np.random.default_rng(0)
    constant, spindle_on = rng.standard_normal(50), rng.standard_normal(50)
    labels = [("saddle", "volume", "constant"), ("saddle", "volume", "spindle_on")]
    monkeypatch.setattr(L, "region_columns", lambda evidence, spec, twin, steps: ([constant, spindle_on], labels))
    r = 2.0 * spindle_on
    (entry,) = L.localise(None, BoundedFitter(r, np.ones_like(r)), None, None, twin=object())
    assert (entry["region"], entry["schedule"]) == ("saddle", "spindle_on")
    assert entry["power_W"] == pytest.approx(2.0, rel=1e-12) and entry["explained"] == pytest.approx(1.0, abs=1e-12)
