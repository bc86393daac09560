"""Mutation audit of the measurement comparison and what a diagnosis builds on it
(validate/compare.py, channels.py, channel_cost.py, candidates.py, search.py, inputs.py,
synthetic.py; the report and apply: tests/test_report_mutations.py): each test pins a behaviour
whose mutation the suite let survive, on small synthetic inputs with closed-form answers, no twin
run."""

from __future__ import annotations

from types import SimpleNamespace as NS

import numpy as np
import pytest
import xarray as xr

from validate.channels import Phase
from validate.compare import ChannelResult, CompareResult, Stats, compare, format_compare


# --- compare: ranking, per-phase statistics, the table ------------------------------------------

def _channel(name, rmse, spread, unit="K", max_abs=None, nse=0.0, phases=()):
    return ChannelResult(name, unit, Stats(rmse, rmse if max_abs is None else max_abs, nse, 4), spread, list(phases))


def test_ranking_is_worst_normalised_rmse_first_and_a_flat_channel_that_is_off_leads():
    """ranking(): largest RMSE / std(m) first. 0.5 K over a 1 K spread (0.5), 3 um over 10 um
    (0.3), 0.1 K over 2 K (0.05); a flat measured channel (std 0) that the model misses by 0.3 K
    scores RMSE / 0 = inf and leads (it is off and there is nothing to explain), a flat one
    matched exactly scores 0 and comes last."""
    chans = [_channel("temperature:a", 0.1, 2.0), _channel("temperature:b", 0.5, 1.0),
             _channel("probe:X1", 3.0, 10.0, "um"), _channel("temperature:flat_off", 0.3, 0.0),
             _channel("temperature:flat_ok", 0.0, 0.0)]
    assert chans[3].normalised_rmse == np.inf and chans[4].normalised_rmse == 0.0
    ranked = CompareResult(chans, [], None).ranking()
    assert [c.name for c in ranked] == ["temperature:flat_off", "temperature:b", "probe:X1", "temperature:a",
                                        "temperature:flat_ok"]


def test_a_flat_channel_that_is_off_leads_the_phase_cells_too():
    """phase_ranking(): each cell's RMSE over the channel's whole-run std, a flat channel's cells
    scored as its channel is (compare.normalised: inf when off, 0 when matched), never its raw RMSE
    in K beside the others' ratios: a flat sensor 0.3 K off beside a probe at 5 um over a 10 um
    spread leads the cells, as it leads the channel ranking (it came second, scored 0.3)."""
    phase = Phase("spindle", "spindle on 9000 rpm", 0.0, 600.0)
    chans = [_channel("probe:Z", 5.0, 10.0, "um", phases=[Stats(5.0, 5.0, 0.0, 10)]),
             _channel("temperature:flat_off", 0.3, 0.0, phases=[Stats(0.3, 0.3, 0.0, 10)]),
             _channel("temperature:flat_ok", 0.0, 0.0, phases=[Stats(0.0, 0.0, 1.0, 10)])]
    result = CompareResult(chans, [phase], None)
    cells = [(c.name, v) for c, _, _, v in result.phase_ranking()]
    assert cells == [("temperature:flat_off", np.inf), ("probe:Z", 0.5), ("temperature:flat_ok", 0.0)]
    assert [c.name for c in result.ranking()] == [name for name, _ in cells]


def _table():
    phases = [Phase("spindle", "spindle on 9000 rpm", 0.0, 1800.0),
              Phase("spindle", "spindle off", 1800.0, 5400.0, closed=True)]
    chans = [_channel("temperature:a", 0.25, 1.0, "K", max_abs=0.75, nse=0.5,
                      phases=[Stats(0.1, 0.1, 0.0, 2), Stats(0.35, 0.35, 0.0, 2)]),
             _channel("probe:X1", 2.0, 10.0, "um", max_abs=5.0, nse=-1.0,
                      phases=[Stats(4.0, 4.0, 0.0, 2), Stats(0.5, 0.5, 0.0, 2)]),
             _channel("probe:Z", 0.1, 10.0, "um", max_abs=0.2, nse=0.9,
                      phases=[Stats(0.1, 0.1, 0.0, 2), Stats(0.1, 0.1, 0.0, 2)])]
    return CompareResult(chans, phases, None)


def _section(text, head):
    lines = text.splitlines()
    k = lines.index(head)
    out = []
    for line in lines[k + 1:]:
        if not line.strip():
            break
        out.append(line.split())
    return out


def test_the_compare_table_prints_rmse_max_and_nse_in_their_columns():
    """format_compare's channel rows read name, unit, RMSE, max|r|, NSE in the header's order:
    temperature:a 0.25 K RMSE, 0.75 K max, NSE 0.5 (RMSE and max differ, so a swap shows)."""
    rows = [ln.split() for ln in format_compare(_table()).splitlines()[:4]]
    assert rows[0] == ["channel", "unit", "RMSE", "max|r|", "NSE"]
    assert rows[1] == ["temperature:a", "K", "0.25", "0.75", "0.500"]
    assert rows[2] == ["probe:X1", "um", "2", "5", "-1.000"]


def test_the_compare_table_gives_each_phase_its_start_and_end_in_hours():
    """The phases section: each phase's start and end [s] / 3600 (0 .. 0.5 h, 0.5 .. 1.5 h)."""
    rows = _section(format_compare(_table()), "phases:")
    assert [r[-5:] for r in rows] == [["0.00", "h", "..", "0.50", "h"], ["0.50", "h", "..", "1.50", "h"]]


def test_the_compare_table_lists_top_worst_channels_and_phase_cells_with_the_phases_rmse():
    """top = 2: exactly the two worst channels (0.25 K / 1 K = 0.25, 2 um / 10 um = 0.2; probe:Z
    0.01 left out) and the two worst phase cells, each RMSE in the phase over the channel's spread:
    probe:X1 while on 4 um / 10 um = 0.4, temperature:a while off 0.35 K / 1 K = 0.35; each cell
    states the phase's own RMSE (4 um, 0.35 K), not the channel's over the run (2 um, 0.25 K)."""
    text = format_compare(_table(), top=2)
    worst = _section(text, "worst channels (RMSE / std of the measurement):")
    assert worst == [["1.", "temperature:a", "0.250"], ["2.", "probe:X1", "0.200"]]
    cells = _section(text, "worst phases (channel, phase, RMSE / std):")
    assert [" ".join(c) for c in cells] == ["1. probe:X1 spindle on 9000 rpm 0.400 (RMSE 4 um)",
                                            "2. temperature:a spindle off 0.350 (RMSE 0.35 K)"]


def test_per_phase_statistics_are_taken_over_the_phases_own_samples():
    """compare's per-phase Stats use only the samples in the phase: a model exact while the
    spindle turns (t < 600 s, 10 samples) and 0.4 K too warm after it (20 samples) has, in
    'spindle on', RMSE 0, max 0, NSE 1 on its 10 samples and, in 'spindle off', RMSE 0.4 K on its
    20; over the run RMSE = 0.4 sqrt(20 / 30)."""
    from tests.fuzz_files import result_dataset

    measured = result_dataset()
    model = measured.copy(deep=True)
    t = model.time.values
    model["temperature_true"] = model.temperature_true + xr.DataArray(np.where(t < 600.0, 0.0, 0.4), dims="time")
    result = compare(measured, model)
    ch = result.channel("temperature:motor")
    by_label = {p.label: s for p, s in zip(result.phases, ch.phases)}
    on, off = by_label["spindle on 6000 rpm"], by_label["spindle off"]
    assert (on.n, off.n) == (10, 20)
    assert on.rmse == 0.0 and on.max_abs == 0.0 and on.nse == 1.0
    assert off.rmse == pytest.approx(0.4, rel=1e-12) and off.max_abs == pytest.approx(0.4, rel=1e-12)
    assert ch.stats.rmse == pytest.approx(0.4 * np.sqrt(20 / 30), rel=1e-12)


# --- channels: units, noise-free variables, the C axis's phases -----------------------------------

def test_every_channel_group_has_its_documented_residual_unit():
    """README 'twin compare': temperature K, probe um, tilt urad, laser um, strain and strain_raw
    um/m, the interferometer's positioning um; a laser stacked from a Dataset is in um."""
    from validate.channels import residual_unit, stack

    assert {g: residual_unit(g) for g in ("temperature", "probe", "tilt", "laser", "strain", "strain_raw",
                                          "positioning")} == {
        "temperature": "K", "probe": "um", "tilt": "urad", "laser": "um", "strain": "um/m", "strain_raw": "um/m",
        "positioning": "um"}
    ds = xr.Dataset({"laser": (("time", "laser_id"), np.zeros((3, 2)))}, coords={"time": [0.0, 60.0, 120.0],
                                                                               "laser_id": ["Y", "Z"]})
    assert stack(ds, ("laser",)).units == ["um", "um"]


def test_the_noise_free_variable_is_read_except_for_the_strain_gauges():
    """stack(prefer_true=True) reads temperature_true for the temperatures, but the gauges'
    ``strain`` (the reading with its compensation), never ``strain_true`` (the strain without
    the grating's cross-sensitivity): NO_TRUE = (strain, strain_raw)."""
    from validate.channels import stack

    ds = xr.Dataset({"temperature": (("time", "sensor"), [[20.0], [20.5], [21.0]]),
                     "temperature_true": (("time", "sensor"), [[20.0], [20.4], [20.8]]),
                     "strain": (("time", "gauge"), [[0.0], [1.0], [2.0]]),
                     "strain_true": (("time", "gauge"), [[0.0], [5.0], [9.0]]),
                     "strain_raw": (("time", "gauge"), [[0.0], [3.0], [6.0]]),
                     "strain_raw_true": (("time", "gauge"), [[0.0], [7.0], [8.0]])},
                    coords={"time": [0.0, 60.0, 120.0], "sensor": ["T1"], "gauge": ["FBG-1"]})
    ch = stack(ds, ("temperature", "strain", "strain_raw"), prefer_true=True)
    assert ch.names == ["temperature:T1", "strain:FBG-1", "strain_raw:FBG-1"]
    np.testing.assert_array_equal(ch.values, [[20.0, 0.0, 0.0], [20.4, 1.0, 3.0], [20.8, 2.0, 6.0]])


def test_a_c_axis_logged_at_duty_zero_is_off():
    """input_phases: the C axis turns where its logged speed is > 0 and its duty is not 0; a
    speed of 2500 rpm logged with duty 0.5 for 10 min, then duty 0 for 10 min, is 'C axis on
    2500 rpm' for [0, 600) s and 'C axis off' for [600, 1140] s (the spindle at rest: no spindle
    phases)."""
    from validate.channels import input_phases

    t = np.arange(20) * 60.0
    ds = xr.Dataset({"c_axis_speed": ("time", np.full(20, 2500.0)),
                     "c_axis_duty": ("time", np.where(t < 600.0, 0.5, 0.0)),
                     "spindle_speed": ("time", np.zeros(20))}, coords={"time": t})
    phases = [(p.kind, p.label, p.start, p.end) for p in input_phases(ds, t)]
    assert phases == [("c_axis", "C axis on 2500 rpm", 0.0, 600.0), ("c_axis", "C axis off", 600.0, 1140.0)]


# --- what the missing channels cost ----------------------------------------------------------------

def _machine_set():
    return NS(sensor_sites=["motor", "column_side", "bed_front"],
              probes=[NS(name=p) for p in ("X1", "X2", "Y1", "Y2", "Z")],
              lasers=[], strain_gauges=[NS(name="FBG-1"), NS(name="FBG-2")])


def _having(channels):
    groups = [c.split(":")[0] for c in channels]
    return NS(evidence=NS(records=[NS(channels=channels, groups=groups)], groups=lambda: list(dict.fromkeys(groups))),
              fits=[])


def test_partly_logged_temperatures_and_raw_only_gauges_are_not_missing():
    """missing_channels: temperatures count only when wholly absent (any sensor, site or not,
    sees the heat); a gauge logged raw (strain_raw) is that gauge present; probes count one by
    one: one sensor of three, all five probes and both gauges raw is no gap; four probes of five
    is '1 of the machine's 5 probes missing'."""
    from validate.channel_cost import missing_channels

    probes = [f"probe:{p}" for p in ("X1", "X2", "Y1", "Y2", "Z")]
    full = ["temperature:motor"] + probes + ["strain_raw:FBG-1", "strain_raw:FBG-2"]
    assert missing_channels(_having(full), _machine_set()) == []
    gaps = missing_channels(_having(full[:-3] + full[-2:]), _machine_set())
    assert [(g["group"], g["missing"], g["of"]) for g in gaps] == [("probe", 1, 5)]
    assert gaps[0]["note"] == "1 of the machine's 5 probes missing"


# --- candidates --------------------------------------------------------------------------------------

def test_a_reference_strength_is_a_tenth_of_the_widest_bound_or_the_default():
    """reference_value: the default when it is not zero, else 10 % of the bound of larger
    magnitude, with its sign: (-500, 100) gives -50 (a sink), (0, 300) gives 30."""
    from validate.candidates import reference_value

    assert reference_value(NS(default=80.0, lower=0.0, upper=300.0)) == 80.0
    assert reference_value(NS(default=0.0, lower=0.0, upper=300.0)) == pytest.approx(30.0)
    assert reference_value(NS(default=0.0, lower=-500.0, upper=100.0)) == pytest.approx(-50.0)


def test_a_nonlinear_parameter_with_a_zero_lower_bound_vanishes_at_zero():
    """_zero_of: a film or jacket conductance whose range starts at 0 adds nothing at 0 (zero 0,
    not reciprocal); one whose range starts above 0 (a contact, perfect at infinity) vanishes at
    its upper bound."""
    from validate.candidates import _zero_of

    assert _zero_of(NS(lower=0.0, upper=50.0)) == 0.0
    assert _zero_of(NS(lower=0.1, upper=1000.0)) == 1000.0


def test_the_pool_offers_as_missing_only_effects_the_model_lacks():
    """candidate_pool: a missing-effect candidate (kind 'effect', zero strength = nothing) for
    every applicable library effect *not* in the model; an effect the model has is offered only
    through its uncertain parameters (its response vanishes at the model's value, not at 0)."""
    from geometries import build_machine
    from twin.model import model_spec
    from validate.candidates import candidate_pool

    machine = build_machine("cframe-vmc")
    spec = model_spec(machine)
    pool = candidate_pool(machine, spec)
    missing = {c.effect for c in pool if not c.in_model}
    assert "spindle_motor" in spec.effects and "electrical_cabinet" in missing
    assert not missing & set(spec.effects)
    assert {c.kind for c in pool if c.effect in spec.effects} == {"parameter"}


# --- the search: singles refined and ranked, a linear parameter, a pair's linearisation ----------

def _film(effect, parameter):
    from validate.candidates import Candidate

    return Candidate(f"{effect}.{parameter}", "parameter", effect, parameter, 50.0, 450.0, 150.0, 300.0, False, True)


def test_singles_refine_the_best_nonlinear_fits_and_rank_best_first():
    """Two film-like parameters a (spindle_forced_convection.h_reference) and b
    (spindle_coolant.conductance), each g(h) = 40 s_i (1/(h + 10) - 1/160) on its own samples
    (h_0 = 150); truth a at 90, b unchanged. singles(refine=2) refines both nonlinear fits by
    Gauss-Newton (the second best too) and returns them by SSE: a (at 90, SSE ~ 0) first, then b."""
    from twin.model import ModelSpec
    from validate.fit import BoundedFitter
    from validate.search import Search

    s = np.linspace(0.0, 1.0, 200) ** 0.5
    a, b = _film("spindle_forced_convection", "h_reference"), _film("spindle_coolant", "conductance")
    shapes = {a: np.concatenate([s, 0 * s]), b: np.concatenate([0 * s, s])}
    resp = lambda h, shape: 40.0 * shape * (1 / (h + 10.0) - 1 / 160.0)       # noqa: E731
    observe = lambda spec: sum(resp(spec.params[c.effect][c.parameter], shapes[c]) for c in shapes)   # noqa: E731
    spec = ModelSpec((a.effect, b.effect), {a.effect: {a.parameter: 150.0}, b.effect: {b.parameter: 150.0}})
    r = resp(90.0, shapes[a])
    refined = []

    class Counting(Search):
        def joint(self, cands, start):
            refined.append(cands[0].name)
            return super().joint(cands, start)

    search = Counting(observe, spec, observe(spec), BoundedFitter(r, np.ones_like(r)), gn_iterations=8, refine=2)
    fits = search.singles([b, a])
    assert sorted(refined) == sorted([a.name, b.name])
    assert [f.name for f in fits] == [a.name, b.name] and fits[0].sse < fits[1].sse
    assert fits[0].values[0] == pytest.approx(90.0, rel=1e-3)


def test_a_linear_parameters_response_is_its_change_from_the_model_value_times_the_unit():
    """A wrong linear parameter (a source of power P, response P s, model value p_0 = 150 W,
    truth 195 W): g(p) = (p - p_0) u, so the single fit is 195 W with response 45 s and SSE 0
    (p u = 195 s would be the whole source, not the change)."""
    from twin.model import ModelSpec
    from validate.candidates import Candidate
    from validate.fit import BoundedFitter
    from validate.search import Search

    s = np.linspace(0.0, 1.0, 100) ** 2
    observe = lambda spec: spec.params["spindle_motor"]["power"] * s      # noqa: E731
    spec = ModelSpec(("spindle_motor",), {"spindle_motor": {"power": 150.0}})
    c = Candidate("spindle_motor.power", "parameter", "spindle_motor", "power", 50.0, 450.0, 150.0, 300.0, True, True)
    r = 45.0 * s
    fit = Search(observe, spec, observe(spec), BoundedFitter(r, np.ones_like(r))).single(c)
    assert fit.values[0] == pytest.approx(195.0, rel=1e-12)
    np.testing.assert_allclose(fit.response, r, rtol=0, atol=1e-12)
    assert fit.sse < 1e-20


def test_a_pair_steps_a_nonlinear_member_from_its_single_fit_along_its_slope():
    """Pairs linearise each member about its single fit: g_a(q) ~ g_a(p) + s (q - p_0) - s (p -
    p_0). Member a, nonlinear: g_a(k) = k^2 s_1 (p_0 = 0, reference 5: secant slope s = 5 s_1;
    floor.conductance carries k); member b a linear source g_b(P) = P s_2 (spindle_motor.power;
    s_1, s_2 on disjoint samples). Truth k = 2, P = 3: r = 4 s_1 +
    3 s_2. Alone, a fits at k = 4/5 = 0.8 (g = 0.64 s_1; the second secant's 5 is worse), b at 3.
    The pair fits r minus the offset g_a(0.8) - 0.8 s: k = 0.8 + (4 - 0.64) / 5 = 1.472, P = 3."""
    from twin.model import ModelSpec
    from validate.candidates import Candidate
    from validate.fit import BoundedFitter
    from validate.search import Search

    s = np.linspace(0.1, 1.0, 50)
    s1, s2 = np.concatenate([s, 0 * s]), np.concatenate([0 * s, s])
    observe = lambda spec: (spec.params["floor"]["conductance"] ** 2 * s1        # noqa: E731
                            + spec.params["spindle_motor"]["power"] * s2)
    spec = ModelSpec(("floor", "spindle_motor"), {"floor": {"conductance": 0.0}, "spindle_motor": {"power": 0.0}})
    a = Candidate("floor.conductance", "parameter", "floor", "conductance", 0.0, 10.0, 0.0, 5.0, False, True)
    b = Candidate("spindle_motor.power", "parameter", "spindle_motor", "power", 0.0, 10.0, 0.0, 5.0, True, True)
    r = 4.0 * s1 + 3.0 * s2
    search = Search(observe, spec, observe(spec), BoundedFitter(r, np.ones_like(r)))
    fa, fb = search.single(a), search.single(b)
    assert fa.values[0] == pytest.approx(0.8, rel=1e-12) and fb.values[0] == pytest.approx(3.0, rel=1e-12)
    pair = search.pair(fa, fb)
    assert pair.values == pytest.approx((0.8 + (4.0 - 0.64) / 5.0, 3.0), rel=1e-9)
    np.testing.assert_allclose(pair.response, observe(a.spec(b.spec(spec, 3.0), pair.values[0])), rtol=1e-12)


# --- the synthetic truth ---------------------------------------------------------------------------

def _scenario(duration=600.0, dt=60.0):
    from twin.ambient import Ambient
    from twin.scenario import Scenario

    return Scenario("s", ((duration / 2, 9000.0), (duration / 2, 0.0)), Ambient("constant", mean=20.0), dt)


def test_the_truth_is_sampled_on_the_scenarios_grid_and_its_cold_run_is_noise_free(monkeypatch):
    """truth_measurement simulates at dt / 2 and keeps every second sample from the first: the
    measurement's instants are the scenario's own 0, 60, ... 600 s (not 30, 90, ...); the
    interferometer's noise (0.1 um) spares the cold run, the reference the others are taken from."""
    from validate import synthetic

    def fake(machine, sc, effects=None, settings=None, resolution="default", seed=0, materials=None, prepared=None):
        t = sc.times()
        ds = xr.Dataset({"temperature": (("time",), 20.0 + t / 3600.0),
                         "positioning_error": (("run_time", "target", "direction"), np.zeros((4, 3, 2)))},
                        coords={"time": t})
        return ds, None

    monkeypatch.setattr(synthetic, "simulate", fake)
    sc = _scenario()
    ds = synthetic.truth_measurement("cframe-vmc", sc)
    np.testing.assert_array_equal(ds.time.values, sc.times())
    pe = ds.positioning_error.values
    assert np.all(pe[0] == 0.0) and np.all(pe[1:] != 0.0)


def test_a_shortened_scenario_keeps_every_step_at_least_one_sample():
    """short_scenario: each step's duration times the factor, rounded to the sample interval and
    at least one interval (a step rounded to nothing would vanish): factor 0.001 on 300 s steps
    at 60 s leaves 60 s steps."""
    from validate.synthetic import short_scenario

    short = short_scenario(_scenario(), 0.001)
    assert [d for d, _ in short.steps] == [60.0, 60.0] and [n for _, n in short.steps] == [9000.0, 0.0]


# --- the inputs of compare and diagnose ------------------------------------------------------------

def test_a_scenario_need_only_last_as_long_as_a_log_on_its_own_clock():
    """measured_scenario: --scenario must cover the measurement's span t[-1] - t[0]; a 29-min log
    whose clock starts a day in (t = 86400 s ..) is covered by a 3.2 h scenario, though t[-1]
    is more than the scenario's duration."""
    from geometries import build_machine
    from tests.fuzz_files import result_dataset
    from validate.inputs import measured_scenario

    ds = result_dataset()
    ds = ds.assign_coords(time=("time", ds.time.values + 86400.0, ds.time.attrs))
    sc = measured_scenario(ds, NS(scenario="spindle-heat-cool-9000"), build_machine("cframe-vmc"))
    assert sc.duration == 11400.0 < float(ds.time[-1])


def test_a_machine_option_contradicting_the_measurement_is_refused():
    """measured_machine: a measurement of cframe-vmc with --machine gantry-ram is an error naming
    both, never a twin of the other machine."""
    from twin.errors import InputError
    from validate.inputs import measured_machine

    meas = xr.Dataset(attrs={"machine": "cframe-vmc"})
    with pytest.raises(InputError) as err:
        measured_machine(meas, NS(machine="gantry-ram", measurement="m.csv"))
    assert err.value.field == "machine"
    assert err.value.message == "the measurement is of 'cframe-vmc', --machine says 'gantry-ram'"
    assert measured_machine(meas, NS(machine=None, measurement="m.csv")).name == "cframe-vmc"


def test_measurements_of_two_machines_are_refused(tmp_path, monkeypatch):
    """load_measurements: one set of strengths is fitted to one machine; a second measurement of
    another machine (gantry-ram after cframe-vmc) is an error naming it and both machines."""
    import twin.io.measurement as M
    from tests.fuzz_files import result_dataset
    from twin.errors import InputError
    from validate.inputs import load_measurements

    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    a.write_bytes(b"a")
    b.write_bytes(b"b")
    logs = {str(a): result_dataset(), str(b): xr.Dataset(attrs={"machine": "gantry-ram"})}
    monkeypatch.setattr(M, "read_measurement", lambda path, mapping=None, machine=None: logs[str(path)])
    args = NS(measurements=[str(a), str(b)], mapping=None, scenario=None, machine=None, mesh="coarse",
              effects=None, set=None, effects_file=None)
    with pytest.raises(InputError) as err:
        load_measurements(args)
    assert err.value.source == str(b) and err.value.field == "machine"
    assert err.value.message == "is of 'gantry-ram', the first measurement of 'cframe-vmc'"
