"""Observers read what their instrument would: closed forms for the temperature sensors."""

from __future__ import annotations

import numpy as np
import pytest

from geometries import build_machine
from twin.fem.mesh import mesh_machine
from twin.model import model_spec
from twin.observe import TemperatureSensors, sensor_points
from twin.scenario import Ambient, Scenario
from twin.simulate import run

SHORT = Scenario("short", ((600.0, 4000.0), (300.0, 0.0)),
                 Ambient("table", times=(0.0, 900.0), temperatures=(20.0, 21.5)), 60.0)


def test_sensor_order_is_the_machine_numbering():
    """belt-vmc's 77 points come out as T1 .. T77 (glued and air sites interleaved as numbered)."""
    m = build_machine("belt-vmc")
    assert [p.name for p in sensor_points(m)] == [f"T{i}" for i in range(1, 78)]


def test_air_sensors_read_the_model_air():
    """An air sensor reads the air the model assumes: the room air T_air(t), and with
    ``ambient_stratification`` T_air(t) + g (z - z_ref) (exact; its rows on the field are zero)."""
    m = build_machine("belt-vmc")
    mm = mesh_machine(m, "coarse")
    air = [m.point(n) for n in m.air_sites]
    room = SHORT.ambient_temperature(SHORT.times())[:, None]
    plain = run(m, SHORT, model_spec(m), mm=mm, observers=[TemperatureSensors(air)])
    assert np.array_equal(plain.sensor_true, np.repeat(room, len(air), axis=1))
    spec = model_spec(m, "+ambient_stratification", ["ambient_stratification.gradient=0.8 K/m",
                                                     "ambient_stratification.reference_height=1 m"])
    strat = run(m, SHORT, spec, mm=mm, observers=[TemperatureSensors(air)])
    z = np.array([p.xyz[2] for p in air])
    np.testing.assert_allclose(strat.sensor_true, room + 0.8 * (z - 1.0), rtol=0, atol=1e-12)
    # and with stratified_swing in a room that swings: T_air(t) + s (z - z_ref) (T_air(t) - T_air(0))
    daily = Scenario("daily", ((7200.0, 0.0),), Ambient("daily", mean=20.0, amplitude=3.0), 600.0)
    room = daily.ambient_temperature(daily.times())[:, None]
    spec = model_spec(m, "+stratified_swing", ["stratified_swing.growth=1.5 /m",
                                               "stratified_swing.reference_height=0.5 m"])
    swing = run(m, daily, spec, mm=mm, observers=[TemperatureSensors(air)])
    np.testing.assert_allclose(swing.sensor_true, room + 1.5 * (z - 0.5) * (room - room[0]), rtol=0, atol=1e-12)
    assert np.ptp(room) > 0.5


def test_five_probe_evaluation_of_a_rigid_motion_of_the_spindle_side():
    """ISO 230-3's five-probe evaluation on a rigid motion u = t + theta x (x - r0) of the test bar,
    spindle and carrier (the table still): the tilts A = (Y1 - Y2)/d and B = (X2 - X1)/d read
    theta_x and theta_y, and the drift extrapolated to the tool point (X, Y linearly from the two
    probe heights, Z the end probe) is the rigid motion of the tool point, t + theta x (x_tool - r0),
    as the tool-point functional reads it: exact for a rigid motion, to round-off."""
    from twin.observe import FiveProbeTestBar
    from twin.observe.displacement import derived_from_probes, relative_displacement
    m = build_machine("cframe-vmc")
    mm = mesh_machine(m, "coarse")
    nodes = np.unique(mm.mesh.t[:, mm.cells_of("test_bar", "spindle", "carrier")])
    theta, t, r0 = np.array([7e-6, -4e-6, 0.0]), np.array([2e-6, -3e-6, 5e-6]), np.array([0.1, -0.2, 1.3])
    u = np.zeros((mm.nnodes, 3))
    u[nodes] = t + np.cross(theta, mm.mesh.p[:, nodes].T - r0)
    readings = (FiveProbeTestBar().functionals(mm) @ u.ravel())[None, :] * 1e6
    drift, tilt = derived_from_probes(readings, [p.name for p in m.probes], m)
    exact = (t + np.cross(theta, np.asarray(m.point(m.tool_point).xyz) - r0)) * 1e6
    np.testing.assert_allclose(tilt[0], theta[:2] * 1e6, rtol=1e-12)
    np.testing.assert_allclose(drift[0], exact, rtol=1e-12)
    tool = relative_displacement(mm, m.tool_point, m.workpiece_point, np.eye(3)) @ u.ravel() * 1e6
    np.testing.assert_allclose(tool, exact, rtol=1e-12)


def test_sensor_lag_of_a_ramp_is_the_closed_form_first_order_response():
    """First-order lag tau dy/dt = x - y from rest (y(0) = x(0)) of a ramp x = T_0 + a t:

        y(t) = T_0 + a (t - tau (1 - exp(-t / tau))),  lagging a tau behind x in steady state.

    The sensor model's lag (:func:`twin.signals.lag_series`) is an exponential integrator, exact
    for input linear between samples, so an air sensor in a room ramping at a = 1.5 K/h, sampled
    every 10 s with the default tau = 5 s (explicit Euler, 1 - dt / tau = -1, would oscillate),
    reads the formula to round-off (1e-12 K); with a bias b and quantisation q the reading is
    q round((y + b) / q), within q / 2 of y + b (the instruments' docstring)."""
    import types

    from geometries.base import Point
    from twin.model import ModelSpec
    from twin.observe.base import RunContext
    from twin.observe.instruments import temperature_reading

    a, T0, tau, dt = 1.5 / 3600.0, 20.0, 5.0, 10.0
    sc = Scenario("ramp", ((3600.0, 0.0),), Ambient("table", times=(0.0, 3600.0), temperatures=(T0, T0 + 1.5)), dt)
    t = sc.times()
    spec = ModelSpec((), {"temperature_sensor": {"noise": 0.0, "quantisation": 0.0, "bias": 0.0}})
    assert spec.params["temperature_sensor"]["lag"] == tau
    ctx = RunContext(t, sc, spec, types.SimpleNamespace(), None, np.random.default_rng(0))
    obs = TemperatureSensors([Point("air1", (0.0, 0.0, 1.0), "air")])
    data, _ = obs.data(np.zeros((len(t), 1)), ctx)
    y = data["temperature"][1][:, 0]
    exact = T0 + a * (t - tau * -np.expm1(-t / tau))
    np.testing.assert_allclose(data["temperature_true"][1][:, 0], T0 + a * t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(y, exact, rtol=0, atol=1e-12)
    assert (T0 + a * t - y)[-1] == pytest.approx(a * tau, rel=1e-12)   # exp(-360) = 0: steady lag a tau
    # bias and quantisation on the same lag (no noise): within half a step of y + b
    q, b = 0.0625, 0.3
    p = {"lag": tau, "bias": b, "noise": 0.0, "quantisation": q}
    read = temperature_reading((T0 + a * t)[:, None], dt, p, np.random.default_rng(0))[:, 0]
    assert np.all(np.abs(read - (exact + b)) <= q / 2 + 1e-12)
    assert np.allclose(read / q, np.round(read / q), rtol=0, atol=1e-9) and len(np.unique(read)) > 20
