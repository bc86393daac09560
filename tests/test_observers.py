"""Observers read what their instrument would: closed forms for the temperature sensors."""

from __future__ import annotations

import numpy as np

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
