"""The thermal camera's air path against closed forms: FLIR's two-band transmission at its
reference values, and each ray transmitted over its own depth through air colder than the scene
(:mod:`twin.observe.radiometry`, :meth:`twin.observe.camera.ThermalCamera.frames`)."""

from __future__ import annotations

import types

import numpy as np

from geometries.base import Box, CameraPose, Finish, Part, material
from geometries.finishes import Emissivity
from tests.test_camera import BAND, SMALL, _config, _machine
from twin.fem.mesh import build_mesh
from twin.model import ModelSpec
from twin.observe.base import RunContext
from twin.observe.camera import ThermalCamera
from twin.observe.camera_geometry import pixel_directions
from twin.observe.microbolometer import SensorChain
from twin.observe.radiometry import ObjectSettings, RadianceTable, air_transmission, scene_radiance
from twin.scenario import Ambient, Scenario


def flir_two_band(d: float, t: float, rh: float) -> float:
    """tau(d) = X e^(-sqrt(d)(a1 + b1 sqrt(H))) + (1 - X) e^(-sqrt(d)(a2 + b2 sqrt(H))), H = RH
    e^(1.5587 + 0.06939 t - 0.00027816 t^2 + 0.00000068455 t^3), with the constants of FLIR's
    radiometric files (Minkina & Dudzik 2009; Thermimage ``raw2temp``), written out here."""
    x, a1, a2, b1, b2 = 1.9, 0.006569, 0.01262, -0.002276, -0.00667
    h = rh * np.exp(1.5587 + 0.06939 * t - 0.00027816 * t ** 2 + 0.00000068455 * t ** 3)
    return x * np.exp(-np.sqrt(d) * (a1 + b1 * np.sqrt(h))) + (1 - x) * np.exp(-np.sqrt(d) * (a2 + b2 * np.sqrt(h)))


def test_air_transmission_is_flirs_two_band_model_at_its_reference_values():
    """The module's tau(d) is the two-band formula with FLIR's constants (to round-off), 0.9935 at
    1.5 m, 23 degC, 30 % (the docstring's value) and 0.9940 at 20 degC, where Thermimage's
    two half paths, tau(d/2)^2, give 0.9915 (both to the 4 digits quoted)."""
    for d, t, rh in ((1.5, 23.0, 0.3), (0.2, 5.0, 0.9), (10.0, 35.0, 0.5), (0.0, 20.0, 0.3)):
        assert abs(float(air_transmission(d, t, rh)) - flir_two_band(d, t, rh)) < 1e-15
    assert abs(float(air_transmission(1.5, 23.0, 0.3)) - 0.9935) < 5e-5
    assert abs(float(air_transmission(1.5, 20.0, 0.3)) - 0.9940) < 5e-5
    assert abs(float(air_transmission(0.75, 20.0, 0.3)) ** 2 - 0.9915) < 5e-5
    assert float(air_transmission(0.0, 20.0, 0.3)) == 1.0


def test_each_ray_is_transmitted_over_its_own_depth_through_colder_air():
    """A black plate at 35 degC seen through air at 20 degC (30 %) from 6 m, the camera set to
    1.5 m, 20 degC and 30 %: the pixel looking along the unit ray r receives
    W = tau(d) L(35) + (1 - tau(d)) L(20) over its own depth d = 6 m / r_y to the plate's face, and
    reads T_app = L^-1((W - (1 - tau_s) L(20)) / tau_s), tau_s = tau(1.5 m): about 0.09 K below
    35 degC (the camera under-corrects the longer path), where the scene's path at the distance
    setting would read 35 degC and no air path 35.08 degC. Every pixel within half a count,
    0.5 / (G L'(T_app)) [K], plus float32 storage."""
    far = CameraPose("far", (0.0, -6.0, 0.5), (0.0, 0.0, 0.5))
    plate = Part("plate", material("steel"), (Box((-3.0, 0.0, -2.0), (3.0, 0.02, 3.0)),))
    m = _machine([plate], [Finish(Emissivity("test", 1.0, "test"), ("plate",))], spacing=0.5)
    cam = ThermalCamera(m, _config(position=far.position, target=far.target, air_path=True, distance=1.5,
                                   air_temperature=20.0, relative_humidity=0.3, room_humidity=0.3, edge_rays=1))
    mm = build_mesh(m, 0.5)
    view = cam.geometry(mm)
    assert (view.part == 0).all()                  # the plate fills the view
    raw = np.full((2, len(view.hit)), 35.0)
    sc = Scenario("static", ((10.0, 0.0),), Ambient("constant", mean=20.0), sample_interval=10.0)
    ctx = RunContext(sc.times(), sc, ModelSpec(()), m, types.SimpleNamespace(mm=mm), np.random.default_rng(0))
    _, thermo, _, _, _, _ = cam.frames(raw, ctx)
    table = RadianceTable(BAND)
    L = table.radiance
    v, u = np.mgrid[0:SMALL.height, 0:SMALL.width]
    ray = pixel_directions(far, SMALL, u.ravel(), v.ravel())
    depth = 6.0 / ray[:, 1]
    tau, tau_s = flir_two_band(depth, 20.0, 0.3), flir_two_band(1.5, 20.0, 0.3)
    w = tau * L(35.0) + (1 - tau) * L(20.0)
    expected = table.temperature((w - (1 - tau_s) * L(20.0)) / tau_s).reshape(SMALL.height, SMALL.width)
    gain = SensorChain(cam.config.sensor, table, (1, 1), np.zeros(1), np.random.default_rng(0)).gain
    tol = 0.5 / (gain * table.slope(float(expected.min()))) + 1e-5     # L' grows with T: the widest step
    assert np.abs(thermo - expected[None]).max() <= tol
    assert (35.0 - expected).min() > 10 * tol       # far from both readings a wrong path would give


def test_grey_surface_through_air_round_trips_with_matching_settings():
    """Emissivity and air path together, e = 0.3, reflected surroundings at 60 degC, air at 18 degC and
    40 % over 1.5 m (tau < 1): the scene radiance is W = tau (e L(T) + (1 - e) L(T_refl)) + (1 - tau)
    L(T_atm), written out here with tau the two-band formula above and L the module's table (tested
    against the band series, and the series against Planck's law, in tests/test_camera.py), and the
    camera set to the truth inverts it, L^-1((W - tau (1 - e) L(T_refl) - (1 - tau) L(T_atm)) / (tau e))
    = T, to round-off (the table's inverse undoes its linear interpolation)."""
    table = RadianceTable(BAND)
    L = table.radiance
    e, t_refl, t_air, rh, d = 0.3, 60.0, 18.0, 0.4, 1.5
    tau = flir_two_band(d, t_air, rh)
    assert tau < 0.995
    t = np.array([-12.34, 21.7, 47.123, 95.55])
    w = scene_radiance(table, t, e, t_refl, tau, t_air)
    np.testing.assert_allclose(w, tau * (e * L(t) + (1 - e) * L(t_refl)) + (1 - tau) * L(t_air), rtol=1e-14)
    settings = ObjectSettings(emissivity=e, reflected_temperature=t_refl, distance=d, air_temperature=t_air,
                              relative_humidity=rh)
    # atol: np.arange places the table's nodes up to 6e-11 K off lo + i step (the forward look-up's grid)
    np.testing.assert_allclose(settings.object_temperature(table, w), t, rtol=0, atol=1e-10)
