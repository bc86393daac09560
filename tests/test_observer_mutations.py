"""Instrument models (:mod:`twin.observe`) against closed forms and exact identities the rest of
the suite did not hold: each test below fails for a plausible slip in the model that every
other test let pass (a mutation audit of ``twin/observe``). Small, fast inputs: raw readings
are built by hand wherever the observer's packaging (``data``) is what is checked.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from geometries import build_machine
from geometries.axes import LinearAxis
from geometries.base import Box, Machine, Part, Point, StrainGauge, Surface, material
from tests.stubs import OneAxisMachine
from twin.model import ModelSpec
from twin.observe import FiveProbeTestBar, HeatBalance, LaserTriangulation, RunContext, StrainGauges, ToolDrift
from twin.observe.temperature import TemperatureSensors

STEEL = material("steel")
KT = 8.64              # um/m/K, the FBG's cross-sensitivity (seed 000)
BAND = (7.5e-6, 13e-6)  # m, the S65's band


def _bar(gauges=(), points=None) -> Machine:
    """A steel bar 1 x 0.1 x 0.1 m with a glued sensor site ``s`` and, optionally, more points."""
    pts = [Point("s", (0.5, 0.05, 0.099), "bar")] + list(points or [])
    return Machine(name="bar", parts=[Part("bar", STEEL, (Box((0.0, 0.0, 0.0), (1.0, 0.1, 0.1)),))],
                   surfaces=[Surface("skin", ("bar",))], points=pts, probes=[], tool_point=pts[-1].name,
                   workpiece_point=pts[0].name, sensor_sites=["s"], resolutions={"test": 0.05},
                   strain_gauges=list(gauges))


def _ctx(machine, params, n_t, seed=0, dt=60.0):
    return RunContext(np.arange(n_t) * dt, types.SimpleNamespace(sample_interval=dt), ModelSpec((), params),
                      machine, None, np.random.default_rng(seed))


# ---------------------------------------------------------------- FBG strain gauges


def test_fbg_compensation_uses_the_temperature_the_run_recorded_at_the_nearest_sensor():
    """eps_comp = eps_raw - k_T (T_s - T_s,0) with T_s the *recorded* reading of the gauge's
    compensating sensor, the same values as the result's ``temperature`` (strain.py docstring;
    README: "the same reading as the result's temperature"). With the sensor model's lag, noise
    and 0.0625 K steps on, and a noise-free grating, strain - strain_raw = -k_T (T_rec - T_rec,0)
    exactly (round-off): a fresh draw of the sensor model, or a run that does not pass its
    readings on, differs by the sensor's noise times k_T (about 0.4 um/m)."""
    gauge = StrainGauge("g", (0.4, 0.05, 0.099), (1.0, 0.0, 0.0), 0.05, "bar")
    machine = _bar([gauge])
    n = 40
    ramp = 20.0 + np.linspace(0.0, 6.0, n)                       # [degC] at the sensor and the grating
    ctx = _ctx(machine, {"fbg": {"noise": 0.0, "quantisation": 0.0}}, n, seed=3)
    temp, _ = TemperatureSensors([machine.point("s")]).data(ramp[:, None], ctx)
    recorded = temp["temperature"][1][:, 0]
    assert np.any(recorded != np.round(ramp / 0.0625) * 0.0625)   # the sensor model's noise is on
    strain_true = np.linspace(0.0, 50e-6, n)                     # [m/m]
    grating = 20.0 + 1.2 * (ramp - 20.0)                          # warms more; the start is uniform
    raw = np.column_stack([strain_true, grating, ramp])
    data, coords = StrainGauges([gauge]).data(raw, ctx)
    assert list(coords["gauge_sensor"][1]) == ["s"]
    comp, meas = data["strain"][1][:, 0], data["strain_raw"][1][:, 0]
    np.testing.assert_allclose(meas, strain_true * 1e6 + KT * (grating - grating[0]), rtol=0, atol=1e-9)
    np.testing.assert_allclose(comp - meas, -KT * (recorded - recorded[0]), rtol=0, atol=1e-9)


def test_fbg_noise_comes_from_the_runs_seeded_generator():
    """The readings are reproducible: the same seed gives bit-identical strain and strain_raw
    (instruments.py: "Noise comes from a seeded generator"), another seed other noise; the
    truth does not depend on it."""
    gauge = StrainGauge("g", (0.4, 0.05, 0.099), (1.0, 0.0, 0.0), 0.05, "bar")
    machine = _bar([gauge])
    n = 30
    raw = np.column_stack([np.linspace(0.0, 20e-6, n), np.full(n, 20.0), np.full(n, 20.0)])
    one, two, other = (StrainGauges([gauge]).data(raw, _ctx(machine, {}, n, seed=s))[0] for s in (11, 11, 12))
    for key in ("strain", "strain_raw", "strain_true"):
        assert np.array_equal(one[key][1], two[key][1]), key
    assert not np.array_equal(one["strain_raw"][1], other["strain_raw"][1])
    assert np.array_equal(one["strain_true"][1], other["strain_true"][1])


def test_fbg_gauge_coordinates_are_each_gauges_centre_direction_length_and_part():
    """``gauge_x/y/z`` [m] are the gauge's centre, ``gauge_dx/dy/dz`` its fibre direction,
    ``gauge_length`` [m] its length (README: the result file's coordinates), for gauges whose
    x, y and z all differ (a swapped axis would read another coordinate)."""
    gauges = [StrainGauge("a", (0.3, 0.02, 0.099), (1.0, 0.0, 0.0), 0.05, "bar"),
              StrainGauge("b", (0.7, 0.08, 0.06), (0.0, 0.6, 0.8), 0.04, "bar")]
    machine = _bar(gauges)
    raw = np.zeros((2, 3 * len(gauges)))
    raw[:, len(gauges):] = 20.0
    _, coords = StrainGauges(gauges).data(raw, _ctx(machine, {}, 2))
    for i, c in enumerate("xyz"):
        assert list(coords[f"gauge_{c}"][1]) == [g.xyz[i] for g in gauges]
        assert list(coords[f"gauge_d{c}"][1]) == [g.direction[i] for g in gauges]
        assert coords[f"gauge_{c}"][2]["units"] == "m"
    assert list(coords["gauge_length"][1]) == [0.05, 0.04]
    assert list(coords["gauge_part"][1]) == ["bar", "bar"]


# ---------------------------------------------------------------- displacement sensors


def test_laser_tilt_true_is_the_noise_free_pair_over_the_pairs_own_spacing():
    """A = (q_A1 - q_A2) / spacing, spacing = z_A2 - z_A1 (triangulation.py): on gantry-ram
    (0.1 m) ``laser_tilt_true`` is that of the true readings exactly, while ``laser_tilt`` carries
    the sensors' 0.2 um noise; on a machine whose pair stands 0.25 m apart the tilt divides by
    0.25 m, not by gantry-ram's 0.1 m."""
    m = build_machine("gantry-ram")
    names = [p.name for p in m.lasers]
    a1, a2 = names.index("A1"), names.index("A2")
    spacing = m.point("A2").xyz[2] - m.point("A1").xyz[2]
    n = 6
    raw = np.random.default_rng(1).normal(0.0, 5e-6, (n, len(names)))     # [m]
    ctx = _ctx(m, {}, n, seed=2)
    data, _ = LaserTriangulation().data(raw, ctx)
    true = (raw - raw[0]) * 1e6
    np.testing.assert_allclose(data["laser_tilt_true"][1], (true[:, a1] - true[:, a2]) / spacing, rtol=1e-13)
    assert np.abs(data["laser_tilt"][1] - data["laser_tilt_true"][1]).max() > 0.5   # urad: noise on the reading
    # another machine: the pair 0.25 m apart along z
    z = {"A1": 1.0, "A2": 1.25}
    stub = types.SimpleNamespace(point=lambda n: types.SimpleNamespace(xyz=(0.0, 0.0, z[n])))
    meas = np.array([[0.0, 0.0], [5.0, 2.5]])
    more, _ = LaserTriangulation().derived(meas, meas, ["A1", "A2"], stub)
    np.testing.assert_allclose(more["laser_tilt"][1], [0.0, 2.5 / 0.25], rtol=1e-14)


def test_five_probe_tilt_true_is_from_the_true_readings():
    """ISO 230-3: A = (Y1 - Y2) / d, B = (X2 - X1) / d. ``tilt_true`` is that of the noise-free
    ``probe_true`` (README: "tilt, tilt_true ... as measured and the truth"), exactly, while
    ``tilt`` is that of the noisy readings."""
    m = build_machine("cframe-vmc")
    names = [p.name for p in m.probes]
    n = 8
    raw = np.random.default_rng(4).normal(0.0, 3e-6, (n, len(names)))
    data, _ = FiveProbeTestBar().data(raw, _ctx(m, {}, n, seed=5))
    true = data["probe_true"][1]
    col = {k: true[:, i] for i, k in enumerate(names)}
    d = m.point("X2").xyz[2] - m.point("X1").xyz[2]
    expected = np.column_stack([(col["Y1"] - col["Y2"]) / d, (col["X2"] - col["X1"]) / d])
    np.testing.assert_allclose(data["tilt_true"][1], expected, rtol=1e-13, atol=1e-12)
    assert np.abs(data["tilt"][1] - data["tilt_true"][1]).max() > 0.05


def test_tool_drift_of_an_affine_displacement_is_tool_minus_workpiece():
    """For u(x) = G (x - x0) (a general affine field, reproduced exactly by trilinear
    interpolation) the drift is the tool point's displacement minus the workpiece point's,
    G (x_tool - x_wp), to round-off (README: "tool relative to the table"; so the spindle growing
    towards the table is negative Z). Swapped ends give the opposite sign."""
    from twin.fem.mesh import build_mesh

    machine = _bar(points=[Point("tool", (0.85, 0.07, 0.08), "bar")])   # workpiece point: s
    mm = build_mesh(machine, 0.05)
    G = np.array([[12.0, -3.0, 1.5], [2.0, 7.0, -4.0], [-5.0, 0.5, 9.0]]) * 1e-6
    x0 = np.array([0.2, 0.01, 0.03])
    u = ((mm.mesh.p.T - x0) @ G.T).ravel()
    drift = ToolDrift().functionals(mm) @ u
    expected = G @ (np.subtract(machine.point("tool").xyz, machine.point("s").xyz))
    np.testing.assert_allclose(drift, expected, rtol=1e-11, atol=1e-20)


def test_temperature_sensor_coordinates_are_the_sensor_points():
    """``x, y, z`` [m] and ``part`` of the result's sensors are their points' (README), for
    sensors whose three coordinates differ."""
    pts = [Point("a", (0.1, 0.02, 0.03), "bar"), Point("b", (0.6, 0.07, 0.09), "bar")]
    data, coords = TemperatureSensors(pts).data(np.full((3, 2), 20.0), _ctx(_bar(), {}, 3))
    for i, c in enumerate("xyz"):
        assert list(coords[c][1]) == [p.xyz[i] for p in pts]
        assert coords[c][2]["units"] == "m"
    assert list(coords["part"][1]) == ["bar", "bar"] and list(coords["sensor"][1]) == ["a", "b"]


def test_probe_and_temperature_noise_come_from_the_seeded_generator():
    """probe_reading and temperature_reading draw from the generator they are given: the same
    seed gives bit-identical readings (the run's seed fixes every instrument's noise)."""
    from twin.observe.instruments import INSTRUMENTS, probe_reading, temperature_reading

    x = np.linspace(0.0, 30.0, 200)[:, None]
    for name in ("probe", "laser_triangulation"):
        p = {q.name: q.default for q in INSTRUMENTS[name]}
        a, b = (probe_reading(x, p, np.random.default_rng(5)) for _ in range(2))
        assert np.array_equal(a, b)
    p = {q.name: q.default for q in INSTRUMENTS["temperature_sensor"]}
    a, b = (temperature_reading(20.0 + x / 10, 60.0, p, np.random.default_rng(6)) for _ in range(2))
    assert np.array_equal(a, b)


# ---------------------------------------------------------------- interferometer and probing


def test_interferometer_runs_read_at_the_nearest_output_step():
    """A run at t reads output step round(t / dt): at 0.1 s samples, 0.3 s / 0.1 s is
    2.9999999999999996 and 0.7 s / 0.1 s 6.999999999999999 in floating point; truncating would
    read the step before (as the probing routine's test holds for DatumProbing)."""
    from twin.observe.interferometer import InterferometerConfig, LaserInterferometer

    obs = LaserInterferometer(InterferometerConfig("Y", (0.0, 0.3, 0.7)),
                              OneAxisMachine(LinearAxis("Y", "y", (0.0, 0.4), "closed")))
    assert list(obs.sample_steps(np.arange(10) * 0.1)) == [0, 3, 7]


def test_interferometer_targets_run_every_spacing_and_end_on_the_last_target():
    """ISO 230-2 targets: first, first + spacing, ... and the last target itself, also when
    last - first is not a multiple of the spacing (0 .. 285 mm every 10 mm: 0, 10, ..., 280, 285)."""
    from twin.observe.interferometer import InterferometerConfig

    axis = LinearAxis("Y", "y", (0.0, 0.4), "closed")
    t = InterferometerConfig("Y", (0.0,), 0.0, 0.285, 0.010).targets(axis)
    np.testing.assert_allclose(t, np.r_[np.arange(29) * 0.010, 0.285], rtol=0, atol=1e-15)
    t = InterferometerConfig("Y", (0.0,)).targets(axis)                   # the travel, every 10 mm
    np.testing.assert_allclose(t, np.arange(41) * 0.010, rtol=0, atol=1e-15)
    # far from the origin (a gantry's X at 2.5 m) a last target 20 um past a multiple is kept
    far = LinearAxis("X", "x", (0.0, 2.6), "closed")
    t = InterferometerConfig("X", (0.0,), 2.4, 2.50002, 0.010).targets(far)
    assert len(t) == 12 and t[-1] == 2.50002 and abs(t[-2] - 2.5) < 1e-12


def test_probing_screw_rows_reach_each_axis_nut_and_read_in_micrometres():
    """DatumProbing's own rows: each semi-closed screw's line integral runs from its fixed bearing
    to the nut at the datum's coordinate *on that axis*, so with the structure still and every
    screw at a uniform rise dT datum j reads s_a alpha dT (nut_a(p_aj) - fixed_a) along axis a
    (s = -1 for X and Y, +1 for Z: exact, trapezoids of a constant). ``probing_error`` is that in
    um and ``datum_position`` the datums in mm."""
    from twin.fem.mesh import mesh_machine
    from twin.motion import machine_for
    from twin.observe.probing import DatumProbing, ProbingConfig
    from twin.scenario import load_scenario

    machine = machine_for(build_machine("cframe-vmc"), load_scenario("thesis-duty-test1"))
    mm = mesh_machine(machine, "coarse")
    datums = ((0.10, 0.05, 0.02), (0.45, 0.35, 0.30))
    obs = DatumProbing(ProbingConfig((0.0, 60.0), datums), machine)
    carry, _ = obs._carry(machine)
    still = np.zeros((3 + carry.nrows, mm.nheat))        # the structure does not move
    twin = types.SimpleNamespace(machine=machine, materials={}, displacement_rows=lambda o, layout: still)
    rows = obs.rows(twin, types.SimpleNamespace(mm=mm))
    alpha, dT = STEEL.expansion, 2.5
    raw = np.vstack([rows @ np.full(mm.nheat, 20.0), rows @ np.full(mm.nheat, 20.0 + dT)])
    data, _ = obs.data(raw, types.SimpleNamespace(machine=machine))
    err = data["probing_error"][1]
    assert data["probing_error"][2]["units"] == "um" and [a.name for a in obs.screws] == ["X", "Y", "Z"]
    for k, a in enumerate(obs.screws):
        nut = a.nut_coordinate(np.array(datums)[:, k])
        expect = (1.0 if a.name == "Z" else -1.0) * alpha * dT * (nut - a.drive.fixed_end) * 1e6
        np.testing.assert_allclose(err[1, :, k], expect, rtol=1e-10)
    assert np.all(err[0] == 0.0)
    np.testing.assert_allclose(data["datum_position"][1], np.array(datums) * 1e3, rtol=1e-15)


# ---------------------------------------------------------------- microbolometer


def _chain(sensor, table, shape=(1, 1), times=(0.0,), seed=0):
    from twin.observe.microbolometer import SensorChain

    return SensorChain(sensor, table, shape, np.asarray(times, float), np.random.default_rng(seed))


@pytest.fixture(scope="module")
def table():
    from twin.observe.radiometry import RadianceTable

    return RadianceTable(BAND)


QUIET = dict(netd=0.0, fixed_pattern=0.0, row_fixed=0.0, column_fixed=0.0, row_temporal=0.0, column_temporal=0.0,
             frame_temporal=0.0, offset=0.0, drift=0.0)


def test_adc_count_is_the_rounded_linear_map_from_the_range_ends(table):
    """c = round((2^14 - 1) (W - L(T_lo)) / (L(T_hi) - L(T_lo))) (microbolometer.py: the range's
    ends give 0 and 2^14 - 1): radiances a quarter count above counts k = 0, 5000, 10000, 16000,
    16382 read k exactly; a gain of 2^14 / (L_hi - L_lo) would read k + 1 above k = 4096."""
    from twin.observe.microbolometer import Microbolometer

    chain = _chain(Microbolometer().noiseless(), table, (1, 5))
    lo, hi = table.radiance(np.array([-40.0, 120.0]))
    k = np.array([0, 5000, 10000, 16000, 16382])
    w = lo + (k + 0.25) / 16383 * (hi - lo)
    assert np.array_equal(chain.counts(w.reshape(1, 1, -1))[0, 0], k)


def test_offset_drift_starts_from_its_stationary_distribution(table):
    """The Ornstein-Uhlenbeck drift is started from N(0, sigma_d^2) (microbolometer.py; as the
    OU test's docstring states: stationary variance at every frame), so its first value has the
    variance sigma_d^2 too, not 0. 3000 independent chains (seeds), sigma_d = 0.3 K: the sample
    variance has relative standard error sqrt(2 / 3000) = 2.6 %, held to 4 of them."""
    from twin.observe.microbolometer import Microbolometer

    sensor = Microbolometer(**{**QUIET, "drift": 0.3, "accuracy": 100.0})
    first = np.array([_chain(sensor, table, seed=s).offset[0] for s in range(3000)])
    assert np.mean(first ** 2) == pytest.approx(0.3 ** 2, rel=4 * np.sqrt(2 / first.size))


def test_frame_flicker_is_one_offset_per_frame_with_its_declared_deviation(table):
    """3-D noise sigma_t (``frame_temporal``): one offset per frame shared by every pixel, drawn
    anew each frame; at T_ref the counts' variance over frames is (G L'(T_ref) sigma_t)^2 + 1/12
    (Sheppard). 20000 frames: relative standard error sqrt(2 / 20000) = 1 %, held to 4 %."""
    from twin.observe.microbolometer import Microbolometer

    L30 = table.radiance(30.0)
    n = 20000
    chain = _chain(Microbolometer(**{**QUIET, "frame_temporal": 0.05}), table, (2, 3), np.arange(n) * 10.0, seed=8)
    c = chain.counts(np.full((n, 2, 3), L30)).astype(float)
    assert np.all(c == c[:, :1, :1])
    sigma_c = chain.gain * chain.kelvin * 0.05
    assert c[:, 0, 0].var(ddof=1) == pytest.approx(sigma_c ** 2 + 1 / 12, rel=4 * np.sqrt(2 / n))


# ---------------------------------------------------------------- energy balance


def test_energy_closure_attribute_is_the_relative_first_law_residual():
    """energy_closure = |sources + convection - stored| / max(|sources|, |convection|, |stored|)
    (README, energy.py). Two steps of 10 s: sources 0.5 W -> 10 J; convection h (T_air A - I)
    with h = 1 W/(m2 K), A = 1 m2, T_air = 0 and I = 2 K m2 -> -40 J; stored E_N - E_0 = 80 - 100
    = -20 J; closure |10 - 40 + 20| / 40 = 0.25 (the largest term is the convection)."""
    def signals(t):
        t = np.asarray(t, float)
        return np.ones((len(t), 1)), np.zeros((len(t), 1)), np.full((len(t), 1), 0.5)

    loads = types.SimpleNamespace(signals=signals, areas=np.array([1.0]))
    ctx = types.SimpleNamespace(times=np.array([0.0, 10.0, 20.0]), theta=0.5, loads=loads)
    raw = np.array([[100.0, 2.0], [90.0, 2.0], [80.0, 2.0]])
    attrs = HeatBalance().attrs(raw, ctx)
    assert attrs["energy_sources_J"] == pytest.approx(10.0, rel=1e-15)
    assert attrs["energy_convection_J"] == pytest.approx(-40.0, rel=1e-15)
    assert attrs["energy_stored_J"] == pytest.approx(-20.0, rel=1e-15)
    assert attrs["energy_closure"] == pytest.approx(0.25, rel=1e-15)
