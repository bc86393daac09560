"""The thermal camera against closed forms: radiometry, noise statistics, determinism, the frame
schedule, and the count look-up round trip through a file (the pinhole geometry, footprint,
occlusion, ray casting and framing: ``tests/test_camera_geometry.py``).

Scenes are boxes on tiny meshes with 32 x 24 pixel cameras; a uniform field comes from a model
with no effects and the room at the start temperature (nothing heats or cools anything).
"""

import numpy as np
import pytest

from geometries.base import Box, CameraPose, Finish, Machine, Part, material
from geometries.finishes import Emissivity
from twin.fem.mesh import build_mesh
from twin.model import ModelSpec
from twin.observe.camera import CameraConfig, ThermalCamera
from twin.observe.camera_geometry import Intrinsics, pixel_directions
from twin.observe.microbolometer import Microbolometer
from twin.observe.radiometry import RadianceTable, band_radiance
from twin.scenario import Ambient, Scenario
from twin.simulate import run

SMALL = Intrinsics(width=32, height=24)
BAND = (7.5e-6, 13e-6)
POSE = CameraPose("front", (0.0, -1.5, 0.5), (0.0, 0.0, 0.5))


def _machine(parts, finishes, spacing=0.25):
    return Machine(name="scene", parts=parts, surfaces=[], points=[], probes=[], tool_point="", workpiece_point="",
                   sensor_sites=[], resolutions={"coarse": spacing}, finishes=finishes)


def _plate(emissivity=1.0):
    """A steel plate 2 m x 2 m, 2 cm thick, its front face at y = 0, centred on the camera axis."""
    plate = Part("plate", material("steel"), (Box((-1.0, 0.0, -0.5), (1.0, 0.02, 1.5)),))
    return _machine([plate], [Finish(Emissivity("test", emissivity, "test"), ("plate",))])


def _frames(machine, config, t0=35.0, nframes=3, seed=0):
    """Run a uniform scene at t0 [degC] and package the camera: (dataset, camera, result)."""
    from twin.io.results import to_dataset

    sc = Scenario("static", ((10.0 * (nframes - 1), 0.0),), Ambient("constant", mean=t0), sample_interval=10.0)
    cam = ThermalCamera(machine, config)
    mm = build_mesh(machine, machine.resolutions["coarse"])
    r = run(machine, sc, ModelSpec(()), mm=mm, observers=[cam])
    return to_dataset(r, seed), cam, r


def _config(**kw):
    base = dict(position=POSE.position, target=POSE.target, intrinsics=SMALL, air_path=False,
                sensor=Microbolometer().noiseless(), emissivity=1.0, distance=0.0)
    return CameraConfig(**{**base, **kw})


def test_band_radiance_series_matches_quadrature_and_stefan_boltzmann():
    """Widger-Woodall series = numerical integral of Planck's law; whole spectrum = sigma T^4 / pi."""
    from scipy.integrate import quad

    from twin.observe.radiometry import C_LIGHT, H_PLANCK, K_BOLTZMANN, SIGMA

    for t in (-20.0, 30.0, 300.0):
        T = t + 273.15
        planck = lambda lam: 2 * H_PLANCK * C_LIGHT ** 2 / lam ** 5 / np.expm1(H_PLANCK * C_LIGHT / (lam * K_BOLTZMANN * T))
        ref = quad(planck, *BAND, epsabs=0, epsrel=1e-12)[0]
        assert band_radiance(t, BAND) == pytest.approx(ref, rel=1e-10)
        assert band_radiance(t, (1e-9, np.inf)) == pytest.approx(SIGMA * T ** 4 / np.pi, rel=1e-12)
    table = RadianceTable(BAND)
    x = np.linspace(-30, 200, 777)
    assert np.abs(table.temperature(table.radiance(x)) - x).max() < 1e-6
    # the table against the series over the camera's range: linear interpolation's error bound
    # L'' h^2 / 8 (L'' by central differences; tight to 1 %), under 1e-5 K in temperature
    x = np.linspace(-40.0, 120.0, 16001)[:-1] + 0.0123
    exact = band_radiance(x, BAND)
    curvature = (band_radiance(x + 0.01, BAND) - 2 * exact + band_radiance(x - 0.01, BAND)) / 1e-4
    assert np.all(np.abs(table.radiance(x) - exact) <= 1.02 * table.step ** 2 / 8 * curvature)
    assert np.abs(table.temperature(exact) - x).max() < 1e-5


def _half_count(cam, t: float) -> float:
    """Half a count of the camera's ADC at t [degC] in kelvin, 0.5 / (G L'(t)), plus float32 storage."""
    from twin.observe.microbolometer import SensorChain

    table = RadianceTable(cam.config.band)
    gain = SensorChain(cam.config.sensor, table, (1, 1), np.zeros(1), np.random.default_rng(0)).gain
    return 0.5 / (gain * table.slope(t)) + 1e-5


def test_black_plate_without_air_reads_its_temperature():
    """e = 1, no air path, no noise: T_app = L^-1(L(T)) = T within half the 14-bit count (0.0052 K
    at 35 degC); the true-surface layer of a uniform field is T exactly (float32)."""
    ds, cam, _ = _frames(_plate(1.0), _config())
    on = ds.part_true.values == 0
    assert on.all()  # the plate fills the view
    assert np.abs(ds.thermogram.values - 35.0).max() <= _half_count(cam, 35.0)
    assert np.abs(ds.surface_temperature_true.values - 35.0).max() < 1e-5


def test_grey_plate_reads_the_inverse_of_the_mixed_radiance():
    """Scene e = 0.3 at T = 35 degC reflecting a room at T_r = 10 degC, camera set to e = 1:
    T_app = L^-1(e L(T) + (1 - e) L(T_r)); with e and T_r set right it reads T (within the count
    step divided by e)."""
    e, T, Tr = 0.3, 35.0, 10.0
    table = RadianceTable(BAND)
    expected = table.temperature(e * table.radiance(T) + (1 - e) * table.radiance(Tr))
    ds, _, _ = _frames(_plate(e), _config(room_temperature=Tr))
    assert expected < T - 10  # a shiny part looks much colder than it is
    assert np.abs(ds.thermogram.values - expected).max() < 0.01
    ds, _, _ = _frames(_plate(e), _config(room_temperature=Tr, emissivity=e, reflected_temperature=Tr))
    step = 1.0 / (e * 16383 / (table.radiance(120.0) - table.radiance(-40.0)) * table.slope(T))
    assert np.abs(ds.thermogram.values - T).max() < 0.5 * step + 1e-3


def test_air_path_compensated_by_matching_settings():
    """With an air path (FLIR model) and the camera told the true distance, air and humidity, a
    black plate reads T: W = tau L(T) + (1 - tau) L(T_air) inverted with the same tau, up to the
    path-length difference of off-axis pixels (d / cos) and the count step."""
    ds, cam, _ = _frames(_plate(1.0), _config(air_path=True, distance=1.5, air_temperature=20.0,
                                              room_temperature=20.0, room_humidity=0.3), t0=35.0)
    # the scenario's room air is 35 degC (uniform scene); the camera's air temperature 20 degC
    # is therefore wrong by 15 K and the reading off by (1 - tau)(L(35) - L(20)) / (tau L'(35))
    table = RadianceTable(BAND)
    from twin.observe.radiometry import air_transmission

    tau = float(air_transmission(1.5, 20.0, 0.3))
    L = table.radiance
    reading = table.temperature((L(35.0) - (1 - tau) * L(20.0)) / tau)       # the exact inverse
    bias = (1 - tau) * (L(35.0) - L(20.0)) / (tau * table.slope(35.0))       # its linearisation
    assert abs(reading - (35.0 + bias)) < 1e-4 and bias > 0.08
    centre = ds.thermogram.values[:, 11:13, 15:17]
    assert np.abs(centre - reading).max() <= _half_count(cam, reading)
    ds, _, _ = _frames(_plate(1.0), _config(air_path=True, distance=1.5, air_temperature=35.0), t0=35.0)
    assert np.abs(ds.thermogram.values[:, 11:13, 15:17] - 35.0).max() <= _half_count(cam, 35.0)


def test_temporal_noise_of_a_static_scene_is_the_netd():
    """200 frames of a black plate at 30 degC: the temporal standard deviation per pixel is the
    NETD; with the temporal banding on, the variance grows by s_tv^2 + s_th^2 + s_t^2 (3-D noise:
    independent terms add in variance). The mean variance over 768 pixels x 200 frames has a
    relative standard error of about 0.4 % (0.2 % on the deviation, held to 0.8 %); the banding
    adds 6 % of the NETD's variance, so the excess is held to 25 % (a sensor without banding gives
    none of it)."""
    netd = Microbolometer(fixed_pattern=0.0, row_fixed=0.0, column_fixed=0.0, row_temporal=0.0,
                          column_temporal=0.0, frame_temporal=0.0, offset=0.0, drift=0.0)
    ds, _, _ = _frames(_plate(1.0), _config(sensor=netd), t0=30.0, nframes=200)
    std = ds.thermogram.values.astype(float).std(axis=0, ddof=1)
    plain = np.mean(std ** 2)
    assert np.sqrt(plain) == pytest.approx(0.08, rel=0.008)
    banded = Microbolometer(offset=0.0, drift=0.0, frame_temporal=0.01)
    ds, _, _ = _frames(_plate(1.0), _config(sensor=banded), t0=30.0, nframes=200)
    std = ds.thermogram.values.astype(float).std(axis=0, ddof=1)
    excess = np.mean(std ** 2) - 0.08 ** 2
    assert excess == pytest.approx(0.01 ** 2 + 0.01 ** 2 + 0.01 ** 2, rel=0.25)


def test_frames_are_bit_identical_for_the_same_seed(tmp_path):
    """Same seed, same frames (bit for bit); another seed, other noise. The counts come back
    exactly from the stored thermogram through the camera's look-up table."""
    import xarray as xr

    from twin.io.results import write_netcdf
    from twin.io.thermography import camera_counts

    cfg = _config(sensor=Microbolometer(), air_path=True, distance=None, emissivity=0.95)
    a, cam, r = _frames(_plate(0.9), cfg, nframes=4, seed=3)
    b, _, _ = _frames(_plate(0.9), cfg, nframes=4, seed=3)
    c, _, _ = _frames(_plate(0.9), cfg, nframes=4, seed=4)
    assert np.array_equal(a.thermogram.values, b.thermogram.values)
    assert not np.array_equal(a.thermogram.values, c.thermogram.values)
    counts = cam.frames(r.readings["camera"], r.context(3))[2]
    write_netcdf(a, tmp_path / "a.nc")
    with xr.open_dataset(tmp_path / "a.nc") as back:
        assert "counts" not in back
        assert np.array_equal(camera_counts(back), counts)
        assert np.abs(back.thermogram.values - a.thermogram.values).max() < 0.006
        # the true surface temperature is stored in centikelvin: back within half a step, 0.005 K
        true = a.surface_temperature_true.values
        assert back.surface_temperature_true.encoding["scale_factor"] == np.float32(0.01)
        assert np.nanmax(np.abs(back.surface_temperature_true.values - true)) <= 0.005 + 1e-6


def test_sampled_observer_records_the_dense_rows_at_its_steps():
    """An observer that samples every 3rd output instant gets exactly those rows of R @ T."""
    from geometries import build_machine
    from twin.fem.mesh import mesh_machine
    from twin.observe import TemperatureSensors, sensor_points

    class Every3(TemperatureSensors):
        key = "every3"

        def sample_steps(self, times):
            return np.arange(0, len(times), 3)

    m = build_machine("cframe-vmc")
    sc = Scenario("short", ((70.0, 9000.0),), Ambient("constant", mean=20.0), sample_interval=10.0)
    dense, every = TemperatureSensors(sensor_points(m)), Every3(sensor_points(m))
    r = run(m, sc, mm=mesh_machine(m, "coarse"), observers=[dense, every])
    assert r.readings["every3"].shape == (3, len(dense.points))
    assert np.array_equal(r.readings["every3"], r.readings["temperature"][::3])


def test_scenario_camera_section_and_cli_errors(tmp_path, capsys):
    """A [camera] section is read with units; an unknown key, a missing unit, an emissivity out
    of (0, 1], a frame interval that is not a multiple of the sample interval or is longer than
    the run (one cold frame at t = 0, nothing recorded) and an unknown pose each give one error
    naming file and field, exit code 2 and no output file."""
    from twin.cli import main
    from twin.scenario import load_scenario

    base = ('sample_interval = "60 s"\n[ambient]\nkind = "constant"\ntemperature = "20 degC"\n'
            '[[spindle]]\nspeed = "9000 rpm"\nduration = "2 min"\n')
    good = tmp_path / "good.toml"
    good.write_text(base + '[camera]\npose = "spindle-front"\nresolution = [32, 24]\nifov = "1.5 mrad"\n'
                           'frame_interval = "2 min"\n[camera.settings]\nemissivity = 0.9\nrelative_humidity = "40 %"\n')
    cam = load_scenario(str(good)).cameras[0]
    assert (cam.intrinsics.width, cam.emissivity, cam.relative_humidity, cam.frame_interval) == (32, 0.9, 0.4, 120.0)
    cases = {"unknown": ('[camera]\nzoom = 2\n', "camera.zoom"),
             "unit": ('[camera]\nifov = 1.5\n', "camera.ifov"),
             "emissivity": ('[[camera]]\n[camera.settings]\nemissivity = 1.2\n', "camera[0].settings.emissivity"),
             "interval": ('[camera]\nframe_interval = "90 s"\n', "camera.frame_interval"),
             "longer": ('[camera]\nframe_interval = "3 min"\n', "camera.frame_interval: 180 s is longer than the run")}
    for name, (text, field) in cases.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(base + text)
        out = tmp_path / f"{name}.nc"
        assert main(["simulate", "cframe-vmc", str(path), "-o", str(out), "--mesh", "coarse"]) == 2
        assert f"{path.name}: {field}" in capsys.readouterr().err
        assert not out.exists()
    out = tmp_path / "pose.nc"
    assert main(["simulate", "cframe-vmc", str(good), "-o", str(out), "--mesh", "coarse", "--camera", "nope"]) == 2
    assert not out.exists()


def test_error_messages_name_the_field(tmp_path, capsys):
    from twin.cli import main

    path = tmp_path / "bad.toml"
    path.write_text('[ambient]\nkind = "constant"\ntemperature = "20 degC"\n[[spindle]]\nspeed = "0 rpm"\n'
                    'duration = "1 min"\n[camera]\n[camera.sensor]\nnetd = "-1 K"\n')
    assert main(["simulate", "cframe-vmc", str(path), "-o", str(tmp_path / "x.nc")]) == 2
    assert f"error: {path}: camera.sensor.netd: must not be negative" in capsys.readouterr().err
    assert main(["simulate", "cframe-vmc", "spindle-duty-cycle", "-o", str(tmp_path / "y.nc"), "--camera", "nope"]) == 2
    assert "error: command line: --camera: machine cframe-vmc has no camera pose 'nope'" in capsys.readouterr().err


def test_a_new_camera_on_a_prepared_twin_reuses_the_cached_rows():
    """Rows are cached per pose and layout; a second camera object on the same prepared twin
    still packages its frames (it builds its view for the data), identical to the first."""
    from twin.io.results import to_dataset
    from twin.physics.prepared import PreparedTwin

    m = _plate(1.0)
    twin = PreparedTwin(m, build_mesh(m, 0.25))
    sc = Scenario("static", ((20.0, 0.0),), Ambient("constant", mean=30.0), sample_interval=10.0)
    first = [to_dataset(run(m, sc, ModelSpec(()), prepared=twin, observers=[ThermalCamera(m, _config())]), 1)
             for _ in range(2)]
    assert len(twin._rows) == 1
    assert np.array_equal(first[0].thermogram.values, first[1].thermogram.values)


def test_a_camera_run_is_written_and_read_back_with_the_room_in_view(tmp_path):
    """Pixels that see the room hold NaN in the geometry layers (declared by ``nan_means``); the
    result file is written, read back by the checked reader, and ``twin frames`` exports it. NaN
    in a variable without that declaration is still refused."""
    import xarray as xr

    from twin.cli import main
    from twin.errors import InputError
    from twin.io.results import check_finite, read_result, write_netcdf

    ds, _, _ = _frames(_machine([Part("block", material("steel"), (Box((-0.2, 0.0, 0.3), (0.2, 0.2, 0.7)),))],
                                [Finish(Emissivity("test", 0.9, "test"), ("block",))]), _config())
    assert np.isnan(ds.emissivity_true.values).any() and np.isfinite(ds.emissivity_true.values).any()
    path = write_netcdf(ds, tmp_path / "cam.nc")
    back = read_result(path, "result")
    assert np.array_equal(np.isnan(back.depth_true.values), np.isnan(ds.depth_true.values))
    assert main(["frames", str(path), "-o", str(tmp_path / "frames")]) == 0
    bad = xr.Dataset({"x": ("i", np.array([1.0, np.nan]))})
    with pytest.raises(InputError, match="x: holds NaN"):
        check_finite(bad, "bad.nc")
    bad.x.attrs["nan_means"] = "nothing"
    check_finite(bad, "ok.nc")
    bad["x"] = ("i", np.array([1.0, np.inf]), {"nan_means": "nothing"})
    with pytest.raises(InputError, match="x: holds NaN or infinite"):
        check_finite(bad, "inf.nc")


def test_every_numeric_camera_variable_and_coordinate_states_its_unit():
    """Units at every boundary: the camera's numeric layers and index coordinates (pixel row and
    column, detector count, part and facet indices) carry a ``units`` attribute ("1" for a
    dimensionless index)."""
    ds, _, _ = _frames(_machine([Part("block", material("steel"), (Box((-0.2, 0.0, 0.3), (0.2, 0.2, 0.7)),))],
                                [Finish(Emissivity("test", 0.9, "test"), ("block",))]), _config())
    names = [k for k in list(ds.data_vars) + list(ds.coords) if ds[k].dtype.kind in "iufc"]
    assert {"part_true", "facet_true"} <= set(names)
    missing = [k for k in names if "units" not in ds[k].attrs]
    assert missing == []


@pytest.mark.parametrize("n,share", [(2, 0.5), (3, 2.0 / 3.0)])
def test_a_pixel_straddling_two_surfaces_reads_the_mean_radiance_not_the_mean_temperature(n, share):
    """Mixed pixels: a pixel averages the radiance of its n x n footprint rays (module
    docstring, step 2), so with black surfaces, no air path and no noise a pixel whose rays hit
    part A at T_A on a share f and part B at T_B on the rest reads

        T_app = L^-1(f L(T_A) + (1 - f) L(T_B)),

    above the temperature mean f T_A + (1 - f) T_B (L is convex: 20 and 80 degC half and half read
    53.7 degC, 3.7 K above their mean), while its true-surface layer holds that temperature mean.
    The rays' temperatures are set part by part (the pixel's mixing is under test, not the field's
    interpolation), and the frames come from the camera's own :meth:`ThermalCamera.frames`. Edges are placed
    0.1 mm right of pixel centres: a 2 x 2 footprint (rays +-0.56 mm apart) splits 1/2 : 1/2, a
    3 x 3 one (the middle column on the centre) 2/3 : 1/3, exactly. The same at B's outer edge
    against the room wall at T_r, (1 - f) of the pixel being room: L^-1(f L(T_B) + (1 - f) L(T_r)).
    Tolerance: the reading is within half a count of the radiance, 0.5 / (G L'(T_app)) [K], plus
    float32 storage (1e-5 K)."""
    import types

    from twin.observe.base import RunContext

    T_A, T_B, T_r = 20.0, 80.0, 0.0
    u_ab, u_br = 20, 26   # pixel columns whose centres the edges A|B and B|room sit beside
    ray = pixel_directions(POSE, SMALL, np.array([u_ab, u_br]), np.array([12, 12]))
    x_ab, x_br = 1.5 * ray[:, 0] / ray[:, 1] + 1e-4   # where the centre rays cross the plane y = 0, + 0.1 mm
    a = Part("a", material("steel"), (Box((-1.0, 0.0, -0.5), (x_ab, 0.02, 1.5)),))
    b = Part("b", material("steel"), (Box((x_ab, 0.0, -0.5), (x_br, 0.02, 1.5)),))
    m = _machine([a, b], [Finish(Emissivity("test", 1.0, "test"), ("a", "b"))])
    cam = ThermalCamera(m, _config(edge_rays=n, room_temperature=T_r))
    mm = build_mesh(m, 0.25)
    view = cam.geometry(mm)
    hit = view.hit
    ray_part = mm.cell_part[view.surface.owner[view.ray_facet[hit]]]
    assert set(ray_part) == {mm.part_names.index("a"), mm.part_names.index("b")}
    raw = np.where(ray_part == mm.part_names.index("a"), T_A, T_B)[None, :].repeat(2, axis=0)
    sc = Scenario("static", ((10.0, 0.0),), Ambient("constant", mean=T_A), sample_interval=10.0)
    ctx = RunContext(sc.times(), sc, ModelSpec(()), m, types.SimpleNamespace(mm=mm), np.random.default_rng(0))
    _, thermo, _, true, _, _ = cam.frames(raw, ctx)
    table = RadianceTable(BAND)
    from twin.observe.microbolometer import SensorChain
    gain = SensorChain(cam.config.sensor, table, (1, 1), np.zeros(1), np.random.default_rng(0)).gain

    def reads(w):
        t_app = float(table.temperature(w))
        return t_app, 0.5 / (gain * table.slope(t_app)) + 1e-5

    rows = slice(2, 22)
    L = table.radiance
    t_mix, tol = reads(share * L(T_A) + (1 - share) * L(T_B))
    assert t_mix - (share * T_A + (1 - share) * T_B) > 2.0   # the radiance mean, not the temperature mean
    assert np.abs(thermo[:, rows, u_ab] - t_mix).max() <= tol
    assert np.abs(true[:, rows, u_ab] - (share * T_A + (1 - share) * T_B)).max() < 1e-5
    assert np.allclose(view.coverage[rows, u_ab], 1.0, rtol=0, atol=1e-15)
    t_room, tol = reads(share * L(T_B) + (1 - share) * L(T_r))
    assert np.abs(thermo[:, rows, u_br] - t_room).max() <= tol
    assert np.allclose(view.coverage[rows, u_br], share, rtol=0, atol=1e-15)
    assert np.abs(true[:, rows, u_br] - T_B).max() < 1e-5   # the truth layer averages the hits only
    # the neighbours see one surface whole
    for u, T in ((u_ab - 1, T_A), (u_ab + 1, T_B), (u_br - 1, T_B)):
        t_one, tol = reads(L(T))
        assert np.abs(thermo[:, rows, u] - t_one).max() <= tol and abs(t_one - T) < 1e-5


def test_frames_every_frame_interval_that_is_a_whole_multiple_in_floating_point():
    """A frame interval of 3.3 s at a 1.1 s sample interval is N = 3.3 / 1.1 = 3 samples, although
    the float quotient is 2.9999999999999996 (N = round of the quotient, not its floor): over
    9.9 s (samples 0..9 at 1.1 k s) the frames are the steps 0, 3, 6, 9, at times 3.3 k s (to
    rounding, rel 1e-15)."""
    assert 3.3 / 1.1 < 3                                     # the float quotient sits just below 3
    sc = Scenario("static", ((9.9, 0.0),), Ambient("constant", mean=20.0), sample_interval=1.1)
    cam = ThermalCamera(_plate(), _config(frame_interval=3.3))
    cam.check(sc, cam.machine)                               # accepted as a whole multiple
    times = sc.times()
    assert len(times) == 10
    steps = cam.sample_steps(times)
    assert steps.tolist() == [0, 3, 6, 9]
    np.testing.assert_allclose(times[steps], 3.3 * np.arange(4), rtol=1e-15)


def test_centikelvin_is_a_hundredth_of_a_kelvin_clipped_to_sixteen_bits():
    """TIFF frames: value = round(100 (T + 273.15)), clipped to 0 .. 65535: 20 degC -> 29315,
    absolute zero -> 0, 400 degC (67315) -> 65535, 35.004 degC -> 30815."""
    from twin.io.thermography import centikelvin
    assert centikelvin(np.array([20.0, -273.15, 400.0, 35.004])).tolist() == [29315, 0, 65535, 30815]


def test_thermogram_encoding_holds_cold_scenes_and_recovers_every_count():
    """The thermogram's uint16 encoding (``thermogram_encoding``): offset floor(min lut) - 1, so a
    look-up table reaching -40.3 degC stores at offset -42 and no value falls below integer 0;
    step 0.9 x the smallest look-up difference over the counts that occur (here counts 100-200 of
    lut_k = -40.3 + 0.01 k + 1e-6 k^2: 0.9 (0.01 + 201e-6) = 0.0091809 degC to the float32 table's
    rounding, coarser than the span / 65534), so decoding ints x step + offset lands within half a step and the nearest look-up value
    gives back each count. A table whose finest step is far below span / 65534 (lut_k = 1e-4 k^2
    - 40.3 over all 16384 counts) cannot be exact, and says so (its counts are then stored)."""
    from twin.observe.camera_output import UINT16_TOP, thermogram_encoding

    k = np.arange(16384, dtype=float)
    lut = (-40.3 + 0.01 * k + 1e-6 * k ** 2).astype(np.float32)
    counts = np.arange(100, 201).repeat(3).reshape(3, -1)
    enc, exact = thermogram_encoding(lut, counts, (1, 3, 101))
    assert exact and enc["dtype"] == "uint16" and enc["_FillValue"] == 65535
    assert enc["add_offset"] == np.float32(-42.0)
    # the float32 table's values near -39 degC are rounded to 3.8e-6 (half an ulp), so its
    # differences to 7.6e-6: the step is 0.9 x the hand value within 0.9 x 7.6e-6
    assert float(enc["scale_factor"]) == pytest.approx(0.9 * (0.01 + 201e-6), abs=0.9 * 7.6e-6)
    q, off = float(enc["scale_factor"]), float(enc["add_offset"])
    ints = np.rint((lut.astype(np.float64) - off) / q)
    assert ints.min() >= 0 and ints.max() <= UINT16_TOP
    decoded = off + q * ints[counts]
    assert np.abs(decoded - lut[counts]).max() <= q / 2 + 1e-6
    nearest = np.abs(decoded[..., None] - lut[None, None, 90:211]).argmin(axis=-1) + 90
    assert np.array_equal(nearest, counts)
    fine = (1e-4 * k ** 2 - 40.3).astype(np.float32)
    enc, exact = thermogram_encoding(fine, np.arange(16384).reshape(1, 128, 128), (1, 128, 128))
    span = np.ceil(fine.max()) + 1.0 - (np.floor(fine.min()) - 1.0)
    assert not exact and enc["scale_factor"] == np.float32(span / UINT16_TOP)


def test_ground_steel_is_the_flir_tables_freshly_emeried_steel():
    """geometries/finishes.py cites FLIR's camera user's manual emissivity table for bare ground
    steel: "Iron and steel, freshly worked with emery, 20 degC, T, 0.24" (and "polished, 0.07"
    for polished steel); the README's Surfaces paragraph states 0.24 for the ground spindle nose
    and test mandrel. The value, the figure its own source quotes and the README's agree."""
    from geometries.finishes import FINISHES, GROUND_STEEL, POLISHED_STEEL

    assert GROUND_STEEL.value == 0.24 and FINISHES["ground_steel"] is GROUND_STEEL
    assert "FLIR" in GROUND_STEEL.source and "emery" in GROUND_STEEL.source
    assert "0.24" in GROUND_STEEL.source
    assert POLISHED_STEEL.value == 0.07 and "0.07" in POLISHED_STEEL.source


def test_cframe_surfaces_are_the_readmes_paint_bare_steel_and_tape_band():
    """README "Surfaces": on cframe-vmc painted castings and motor 0.90, the bare ground spindle
    nose and test mandrel 0.24, masking tape 0.95 on the carrier's front face and on a band of the
    mandrel 20-100 mm below the nose (seed 000 L4140: tape on the rotating test bar). Read at
    points on the mandrel's front face half a millimetre inside and outside the band's edges, on
    the carrier's front and side faces and on the spindle nose."""
    from geometries import build_machine
    from twin.observe.camera_geometry import surface_emissivity

    m = build_machine("cframe-vmc")
    names = [p.name for p in m.parts]
    bar = m.part("test_bar").boxes[0]
    nose, front = bar.hi[2], bar.lo[1]
    below = [0.0195, 0.0205, 0.0995, 0.1005]                # m below the nose
    points = [(0.0, front, nose - d) for d in below]
    parts = ["test_bar"] * 4
    carrier = m.part("carrier").boxes[0]
    points += [(0.0, carrier.lo[1], 1.30), (carrier.lo[0], 0.0, 1.30)]   # front face (taped), side face
    parts += ["carrier", "carrier"]
    spindle = m.part("spindle").boxes[0]
    points += [(0.06, 0.0, spindle.lo[2])]                   # the nose's annulus round the bar
    parts += ["spindle"]
    eps = surface_emissivity(m, names, np.array([names.index(p) for p in parts]), np.array(points))
    assert eps.tolist() == [0.24, 0.95, 0.95, 0.24, 0.95, 0.90, 0.24]


def test_a_hit_reads_a_linear_field_at_its_hit_point():
    """A hit reads the field of its cell at the hit point (trilinear shape functions): a linear
    field T = a + g . x lies in the trilinear space, so each hitting ray's row gives a + g . x_hit
    to round-off wherever in its cell the ray lands (the cell's mean, 0.125 at each corner, passed
    every camera test before this one)."""
    from twin.observe.camera_geometry import temperature_rows, view_machine

    m = _plate()
    mm = build_mesh(m, 0.25)
    view = view_machine(mm, m, POSE, SMALL, edge_rays=3)
    a, g = 20.0, np.array([3.0, -2.0, 5.0])
    expect = a + view.ray_point[view.hit] @ g
    assert len(expect) > 100
    got = temperature_rows(view, mm) @ (a + g @ mm.mesh.p)
    assert np.max(np.abs(got - expect)) <= 1e-12 * np.max(np.abs(expect))
