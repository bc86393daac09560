"""Plausible limits of a scenario's ``[camera]`` values (twin.camera_config, and the camera's
position against the machine in twin.observe.camera): one clear error naming the scenario file and
the dotted field, before the run starts; plausible values still load."""

from __future__ import annotations

import pytest

from twin.cli import main
from twin.errors import InputError
from twin.observe.camera import ThermalCamera
from twin.scenario import scenario_from_dict

BASE = {"name": "s", "sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
        "spindle": [{"speed": "6000 rpm", "duration": "10 min"}]}
FRONT = {"position": ["0 m", "-2 m", "1.2 m"], "target": ["0 m", "0 m", "1.2 m"]}   # in front of the column


def _camera(**camera):
    return scenario_from_dict({**BASE, "camera": {"resolution": [32, 24], **camera}}, "s.toml").cameras[0]


def _refused(field, match, **camera):
    with pytest.raises(InputError) as err:
        _camera(**camera)
    assert (err.value.source, err.value.field) == ("s.toml", field), str(err.value)
    assert match in err.value.message, err.value.message


@pytest.mark.parametrize("camera,field,match", [
    ({**FRONT, "up": [0, 0, 0]}, "camera.up", "no direction"),
    ({"name": "a/b"}, "camera.name", "cannot name a file"),      # its export's folder would be a/b
    ({"name": ".."}, "camera.name", "cannot name a file"),
    ({"name": "tab\there"}, "camera.name", "cannot name a file"),
    ({**FRONT, "up": [0, 2, 0]}, "camera.up", "along the line of sight"),
    ({**FRONT, "up": [0, -1e-9, 0]}, "camera.up", "along the line of sight"),
    ({**FRONT, "up": [0, float("nan"), 1]}, "camera.up", "not a finite direction"),
    ({**FRONT, "up": [True, 0, 1]}, "camera.up", "three numbers"),
    ({"position": ["0 m", "0 m", "2 m"], "target": ["0 m", "0 m", "1 m"]}, "camera.up", "along the line of sight"),
    ({"position": ["0 m", "-2 m", "1.2 m"], "target": ["0 m", "-2000 mm", "1.2 m"]}, "camera.target", "must differ"),
    ({"settings": {"reflected_temperature": "-300 degC"}}, "camera.settings.reflected_temperature", "absolute zero"),
    ({"settings": {"reflected_temperature": "500 degC"}}, "camera.settings.reflected_temperature", "-40 to 200 degC"),
    ({"settings": {"air_temperature": "5000 degC"}}, "camera.settings.air_temperature", "-40 to 60 degC"),
    ({"settings": {"air_temperature": "-300 degC"}}, "camera.settings.air_temperature", "absolute zero"),
    ({"scene": {"room_temperature": "-300 degC"}}, "camera.scene.room_temperature", "absolute zero"),
    ({"scene": {"room_temperature": "900 degC"}}, "camera.scene.room_temperature", "-40 to 200 degC"),
    ({"sensor": {"range": ["-300 degC", "120 degC"]}}, "camera.sensor.range[0]", "absolute zero"),
    ({"sensor": {"range": ["-40 degC", "5000 degC"]}}, "camera.sensor.range[1]", "-100 to 1000 degC"),
    ({"sensor": {"range": ["120 degC", "120 degC"]}}, "camera.sensor.range", "lower temperature first"),
    ({"sensor": {"reference_temperature": "-280 degC"}}, "camera.sensor.reference_temperature", "absolute zero"),
])
def test_implausible_camera_values_are_refused(camera, field, match):
    _refused(field, match, **camera)


def test_a_camera_list_names_its_index():
    with pytest.raises(InputError) as err:
        scenario_from_dict({**BASE, "camera": [{"pose": "carrier-front"}, {**FRONT, "up": [0, 1, 0]}]}, "s.toml")
    assert err.value.field == "camera[1].up"


def test_plausible_camera_values_load():
    c = _camera(**FRONT, up=[0, 0, 1], settings={"reflected_temperature": "-40 degC", "air_temperature": "60 degC"},
                scene={"room_temperature": "200 degC"}, sensor={"range": ["0 degC", "1000 degC"]})
    assert c.up == (0.0, 0.0, 1.0) and c.reflected_temperature == -40 and c.air_temperature == 60
    assert c.room_temperature == 200 and c.sensor.range == (0.0, 1000.0)
    looking_down = _camera(position=["0 m", "-2 m", "3 m"], target=["0 m", "-2 m", "1 m"], up=[0, 1, 0])
    assert looking_down.up == (0.0, 1.0, 0.0)


def test_a_camera_inside_a_part_is_refused_when_it_is_set_up(machine):
    inside = _camera(position=["0 m", "0.5 m", "1.2 m"], target=["0 m", "0 m", "1.2 m"])
    with pytest.raises(InputError) as err:
        ThermalCamera(machine, inside)
    assert (err.value.source, err.value.field) == ("s.toml", "camera.position")
    assert "inside part 'column' of machine cframe-vmc" in err.value.message
    assert ThermalCamera(machine, _camera(**FRONT)).pose.position == (0.0, -2.0, 1.2)


SCENARIO = ('name = "s"\nsample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
            '[[spindle]]\nspeed = "6000 rpm"\nduration = "10 min"\n[camera]\nresolution = [32, 24]\n')


@pytest.mark.parametrize("camera,field", [
    ('position = ["0 m", "0.5 m", "1.2 m"]\ntarget = ["0 m", "0 m", "1.2 m"]\n', "camera.position"),
    ('position = ["0 m", "-2 m", "1.2 m"]\ntarget = ["0 m", "0 m", "1.2 m"]\nup = [0, 0, 0]\n', "camera.up"),
    ('position = ["0 m", "-2 m", "1.2 m"]\ntarget = ["0 m", "-2 m", "1.2 m"]\n', "camera.target"),
    ('pose = "carrier-front"\n[camera.settings]\nair_temperature = "5000 degC"\n', "camera.settings.air_temperature"),
    ('pose = "carrier-front"\n[camera.sensor]\nrange = ["-300 degC", "120 degC"]\n', "camera.sensor.range[0]"),
    # the input audit's implausible cameras: each ran with exit 0 and wrote a thermogram of garbage
    # (-101 degC, a constant -46.9 degC with RuntimeWarnings) or failed after the run naming the output
    ('pose = "overview-front"\nband = ["0.4 um", "0.7 um"]\n', "camera.band[0]"),
    ('pose = "overview-front"\nifov = "3 rad"\n', "camera.ifov"),
    ('pose = "overview-front"\n[camera.scene]\nwall_distance = "1e300 m"\n', "camera.scene.wall_distance"),
    ('pose = "overview-front"\n[camera.settings]\ndistance = "1e300 m"\n', "camera.settings.distance"),
    ('position = ["0 m", "-3000 m", "1 m"]\ntarget = ["0 m", "0 m", "1 m"]\n', "camera.position"),
    ('pose = "overview-front"\n[camera.sensor]\nnetd = "1e6 K"\n', "camera.sensor.netd"),
    ('pose = "overview-front"\n[camera.sensor]\ndrift_time = "1e-300 s"\n', "camera.sensor.drift_time"),
])
def test_cli_refuses_with_exit_2_and_no_output(tmp_path, capsys, camera, field):
    (tmp_path / "s.toml").write_text(SCENARIO + camera)
    out = tmp_path / "out.nc"
    assert main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(out), "--mesh", "coarse"]) == 2
    err = capsys.readouterr().err
    assert f"s.toml: {field}: " in err and "Traceback" not in err and "Warning" not in err, err
    assert not out.exists()


def test_a_camera_built_in_python_meets_the_readers_limits():
    """API audit: a NaN emissivity or a 0-bit ADC wrote a thermogram of NaN, a 40-bit ADC asked for
    8 TiB, a camera at its own target divided by zero: each is one InputError naming the field as a
    scenario file would, checked before the run (CameraConfig.check)."""
    from dataclasses import replace

    from twin.errors import InputError
    from twin.observe.camera import CameraConfig
    from twin.observe.camera_geometry import Intrinsics
    from twin.observe.microbolometer import Microbolometer
    from twin.scenario import Ambient, Scenario

    sc = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0)
    base = CameraConfig(pose="carrier-front", where="camera.", source="s.toml")
    base.check(sc)
    cases = [({"emissivity": float("nan")}, "camera.settings.emissivity"), ({"emissivity": 2.0}, "camera.settings.emissivity"),
             ({"relative_humidity": -0.5}, "camera.settings.relative_humidity"),
             ({"reflected_temperature": -300.0}, "camera.settings.reflected_temperature"),
             ({"wall_distance": -5.0}, "camera.scene.wall_distance"), ({"distance": float("nan")}, "camera.settings.distance"),
             ({"room_temperature": float("nan")}, "camera.scene.room_temperature"),
             ({"intrinsics": Intrinsics(width=0)}, "camera.resolution"), ({"intrinsics": Intrinsics(fov_h=4.0)}, "camera.field_of_view"),
             ({"intrinsics": None}, "camera.resolution"), ({"band": (13e-6, 7.5e-6)}, "camera.band"),
             ({"edge_rays": 0}, "camera.edge_rays"), ({"backend": "foo"}, "camera.backend"),
             ({"frame_interval": float("nan")}, "camera.frame_interval"),
             ({"position": (0.0, -2.0, 1.0)}, "camera.target"),
             ({"position": (0.0, -2.0, 1.0), "target": (0.0, -2.0, 1.0)}, "camera.target"),
             ({"position": (0.0, -2.0, 1.0), "target": (0.0, 0.0, 1.0), "up": (0.0, 1.0, 0.0)}, "camera.up"),
             ({"sensor": Microbolometer(bits=0)}, "camera.sensor.bits"), ({"sensor": Microbolometer(bits=40)}, "camera.sensor.bits"),
             ({"sensor": Microbolometer(netd=float("nan"))}, "camera.sensor.netd"),
             ({"sensor": Microbolometer(drift_time=-1.0)}, "camera.sensor.drift_time"),
             ({"sensor": Microbolometer(range=(120.0, -40.0))}, "camera.sensor.range"),
             ({"sensor": Microbolometer(reference_temperature=-500.0)}, "camera.sensor.reference_temperature")]
    for change, field in cases:
        with pytest.raises(InputError) as err:
            replace(base, **change).check(sc)
        assert err.value.field == field, (change, str(err.value))


def test_every_documented_camera_key_reaches_the_config():
    """The module's example table, with values away from the defaults: each one arrives, in SI."""
    import math

    c = _camera(pose="carrier-front", name="carrier", field_of_view=["20 deg", "15 deg"], ifov="2 mrad",
                band=["8 um", "12 um"], frame_interval="120 s", edge_rays=2, store_counts=True,
                settings={"emissivity": 0.9, "distance": "1.4 m", "relative_humidity": "40 %"},
                scene={"relative_humidity": "50 %", "wall_distance": "4 m"},
                sensor={"netd": "0.1 K", "offset": "0.4 K", "accuracy": "1.5 K", "bits": 12})
    assert (c.pose, c.name, c.edge_rays, c.store_counts) == ("carrier-front", "carrier", 2, True)
    assert (c.intrinsics.width, c.intrinsics.height) == (32, 24)
    assert math.isclose(c.intrinsics.fov_h, math.radians(20), rel_tol=1e-12)
    assert math.isclose(c.intrinsics.fov_v, math.radians(15), rel_tol=1e-12)
    assert math.isclose(c.intrinsics.ifov, 2e-3, rel_tol=1e-12)
    assert c.band == pytest.approx((8e-6, 12e-6), rel=1e-12) and c.frame_interval == 120.0
    assert (c.emissivity, c.distance, c.relative_humidity) == (0.9, 1.4, pytest.approx(0.4))
    assert (c.room_humidity, c.wall_distance) == (pytest.approx(0.5), 4.0)
    assert (c.sensor.netd, c.sensor.offset, c.sensor.accuracy, c.sensor.bits) == (0.1, 0.4, 1.5, 12)
    # what a result's camera attributes record: the numbers as typed, not their SI round trip
    # (math.degrees(math.radians(24)) is 24.000000000000004; twin.units.clean)
    c = _camera(field_of_view=["24 deg", "18 deg"], ifov="1.3 mrad")
    assert c.intrinsics.as_dict() == {"width_px": 32, "height_px": 24, "fov_h_deg": 24.0, "fov_v_deg": 18.0,
                                      "ifov_mrad": 1.3}


@pytest.mark.parametrize("camera,field,match", [
    ({"pose": "carrier-front", **FRONT}, "camera.pose", "not both"),
    ({"pose": "carrier-front", "up": [0, 0, 1]}, "camera.up", "goes with position and target"),
    ({"pose": ""}, "camera.pose", "expected a name"),
    ({"name": 3}, "camera.name", "expected a name"),
    ({"resolution": [32]}, "camera.resolution", "[width, height]"),
    ({"resolution": [32, 24.5]}, "camera.resolution", "whole number"),
    ({"resolution": [True, 24]}, "camera.resolution", "whole number"),
    ({"field_of_view": ["24 deg"]}, "camera.field_of_view", "two quantities"),
    ({"field_of_view": ["24 m", "18 deg"]}, "camera.field_of_view[0]", ""),
    ({"band": ["7.5 um", "13 um", "14 um"]}, "camera.band", "two quantities"),
    ({**FRONT, "target": ["0 m", "0 m"]}, "camera.target", "three lengths"),
    ({"edge_rays": 0}, "camera.edge_rays", "whole number"),
    ({"edge_rays": True}, "camera.edge_rays", "whole number"),
    ({"store_counts": "yes"}, "camera.store_counts", "true or false"),
])
def test_malformed_camera_keys_are_refused(camera, field, match):
    _refused(field, match, **{"resolution": [32, 24], **camera})


def test_an_empty_camera_list_and_an_empty_camera_name_are_refused():
    from twin.camera_config import cameras_from_option

    with pytest.raises(InputError) as err:
        scenario_from_dict({**BASE, "camera": []}, "s.toml")
    assert (err.value.source, err.value.field) == ("s.toml", "camera")
    with pytest.raises(InputError) as err:
        cameras_from_option("carrier-front,")
    assert (err.value.source, err.value.field) == ("command line", "--camera")
    assert [c.pose for c in cameras_from_option(" carrier-front , overview-front ")] == ["carrier-front", "overview-front"]


AT_THE_DOOR = {"position": ["0 m", "-100 m", "0 m"], "target": ["0 m", "-1 m", "0 m"]}   # 100 m from the origin
NOISE_3D = ("fixed_pattern", "row_fixed", "column_fixed", "row_temporal", "column_temporal", "frame_temporal")


@pytest.mark.parametrize("past,at,field,match", [
    # band: the thermal infrared, 2-14 um (a visible band read -101 degC everywhere)
    ({"band": ["1.9 um", "13 um"]}, {"band": ["2 um", "13 um"]}, "camera.band[0]", "(2 to 14 um"),
    ({"band": ["7.5 um", "14.1 um"]}, {"band": ["7.5 um", "14 um"]}, "camera.band[1]", "(2 to 14 um"),
    ({"band": ["0.4 um", "0.7 um"]}, {"band": ["2 um", "14 um"]}, "camera.band[0]", "0.4 um is outside the thermal"),
    ({"band": ["7.5 mm", "13 mm"]}, {"band": ["3 um", "5 um"]}, "camera.band[0]", "7500 um is outside"),
    # field of view 2-120 deg, ifov 0.01-100 mrad: a thermographic camera's lenses and pixels
    ({"field_of_view": ["1.9 deg", "18 deg"]}, {"field_of_view": ["2 deg", "2 deg"]}, "camera.field_of_view",
     "from 2 to 120 deg"),
    ({"field_of_view": ["24 deg", "121 deg"]}, {"field_of_view": ["120 deg", "120 deg"]}, "camera.field_of_view",
     "from 2 to 120 deg"),
    ({"ifov": "0.009 mrad"}, {"ifov": "0.01 mrad"}, "camera.ifov", "from 0.01 to 100 mrad"),
    ({"ifov": "101 mrad"}, {"ifov": "100 mrad"}, "camera.ifov", "from 0.01 to 100 mrad"),
    ({"ifov": "3 rad"}, {"ifov": "0.1 rad"}, "camera.ifov", "got 3000 mrad"),
    # distances within a workshop: 100 m (FLIR's air path turns negative near 290 m)
    ({"settings": {"distance": "100.1 m"}}, {"settings": {"distance": "100 m"}}, "camera.settings.distance",
     "more than 100 m"),
    ({"settings": {"distance": "1e300 m"}}, {"settings": {"distance": "0 m"}}, "camera.settings.distance",
     "more than 100 m"),
    ({"scene": {"wall_distance": "100.1 m"}}, {"scene": {"wall_distance": "100 m"}}, "camera.scene.wall_distance",
     "more than 100 m"),
    ({"scene": {"wall_distance": "1e300 m"}}, {"scene": {"wall_distance": "0 m"}}, "camera.scene.wall_distance",
     "1e+300 m: more than 100 m"),
    ({**AT_THE_DOOR, "position": ["0 m", "-100.1 m", "0 m"]}, AT_THE_DOOR, "camera.position",
     "stands 100.1 m from the machine's origin: more than 100 m"),
    ({"position": ["0 m", "-3000 m", "1 m"], "target": ["0 m", "0 m", "1 m"]}, AT_THE_DOOR, "camera.position",
     "more than 100 m"),
    ({"position": ["0 m", "-2 m", "1 m"], "target": ["0 m", "98.1 m", "1 m"]},
     {"position": ["0 m", "-2 m", "1 m"], "target": ["0 m", "98 m", "1 m"]}, "camera.target",
     "lies 100.1 m from position"),
    # the microbolometer: noise at most 1 K, offsets and accuracy at most 10 K, drift over 1 s to 7 d
    ({"sensor": {"netd": "1.01 K"}}, {"sensor": {"netd": "1 K"}}, "camera.sensor.netd", "above 1 K"),
    ({"sensor": {"netd": "1e6 K"}}, {"sensor": {"netd": "1000 mK"}}, "camera.sensor.netd", "above 1 K"),
    *[({"sensor": {key: "1.01 K"}}, {"sensor": {key: "1 K"}}, f"camera.sensor.{key}", "above 1 K") for key in NOISE_3D],
    *[({"sensor": {key: "10.1 K"}}, {"sensor": {key: "10 K"}}, f"camera.sensor.{key}", "above 10 K")
      for key in ("offset", "drift", "accuracy")],
    ({"sensor": {"drift_time": "0.9 s"}}, {"sensor": {"drift_time": "1 s"}}, "camera.sensor.drift_time",
     "outside 1 s to 604800 s (7 d)"),
    ({"sensor": {"drift_time": "7.1 d"}}, {"sensor": {"drift_time": "7 d"}}, "camera.sensor.drift_time",
     "outside 1 s to 604800 s (7 d)"),
    ({"sensor": {"drift_time": "1e-300 s"}}, {"sensor": {"drift_time": "30 min"}}, "camera.sensor.drift_time",
     "outside 1 s to 604800 s"),
    # limits the reader held before: humidity 0-100 %, emissivity in (0, 1]
    ({"settings": {"relative_humidity": "100.1 %"}}, {"settings": {"relative_humidity": "100 %"}},
     "camera.settings.relative_humidity", "0-100 %"),
    ({"scene": {"relative_humidity": "-0.1 %"}}, {"scene": {"relative_humidity": "0 %"}},
     "camera.scene.relative_humidity", "0-100 %"),
    ({"settings": {"emissivity": 0}}, {"settings": {"emissivity": 1}}, "camera.settings.emissivity", "(0, 1]"),
])
def test_each_camera_limit_refuses_just_past_it_and_accepts_it(past, at, field, match):
    """Each plausible limit (twin.observe.camera_checks: BAND, FIELD_OF_VIEW, IFOV, MAX_DISTANCE,
    NOISE_LIMITS, DRIFT_TIME) refuses a value just past it, naming the field, the limit and its
    unit, and loads the value at it (or the plausible one beside an absurd value)."""
    _refused(field, match, **past)
    _camera(**at)


def test_a_camera_built_in_python_meets_the_new_limits():
    """The same limits hold for a CameraConfig, Intrinsics and Microbolometer built in Python
    (CameraConfig.check): just past each one is an InputError naming the field as a scenario file
    would, at it the camera is accepted."""
    import math
    from dataclasses import replace

    from twin.observe.camera import CameraConfig
    from twin.observe.camera_geometry import Intrinsics
    from twin.observe.microbolometer import Microbolometer
    from twin.scenario import Ambient, Scenario

    sc = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0)
    base = CameraConfig(pose="carrier-front", where="camera.", source="s.toml")
    deg = math.radians
    cases = [  # (past, at, field)
        ({"band": (1.9e-6, 13e-6)}, {"band": (2e-6, 13e-6)}, "camera.band[0]"),
        ({"band": (7.5e-6, 14.1e-6)}, {"band": (7.5e-6, 14e-6)}, "camera.band[1]"),
        ({"band": (0.4e-6, 0.7e-6)}, {"band": (3e-6, 5e-6)}, "camera.band[0]"),
        ({"intrinsics": Intrinsics(fov_h=deg(1.9))}, {"intrinsics": Intrinsics(fov_h=deg(2))}, "camera.field_of_view"),
        ({"intrinsics": Intrinsics(fov_v=deg(121))}, {"intrinsics": Intrinsics(fov_v=deg(120))},
         "camera.field_of_view"),
        ({"intrinsics": Intrinsics(ifov=0.9e-5)}, {"intrinsics": Intrinsics(ifov=1e-5)}, "camera.ifov"),
        ({"intrinsics": Intrinsics(ifov=3.0)}, {"intrinsics": Intrinsics(ifov=0.1)}, "camera.ifov"),
        ({"distance": 100.1}, {"distance": 100.0}, "camera.settings.distance"),
        ({"wall_distance": 1e300}, {"wall_distance": 100.0}, "camera.scene.wall_distance"),
        ({"position": (0.0, -100.1, 0.0), "target": (0.0, -1.0, 0.0)},
         {"position": (0.0, -100.0, 0.0), "target": (0.0, -1.0, 0.0)}, "camera.position"),
        ({"position": (0.0, -2.0, 1.0), "target": (0.0, 98.1, 1.0)},
         {"position": (0.0, -2.0, 1.0), "target": (0.0, 98.0, 1.0)}, "camera.target"),
        ({"sensor": Microbolometer(netd=1.01)}, {"sensor": Microbolometer(netd=1.0)}, "camera.sensor.netd"),
        *[({"sensor": Microbolometer(**{key: 1.01})}, {"sensor": Microbolometer(**{key: 1.0})}, f"camera.sensor.{key}")
          for key in NOISE_3D],
        *[({"sensor": Microbolometer(**{key: 10.1})}, {"sensor": Microbolometer(**{key: 10.0})}, f"camera.sensor.{key}")
          for key in ("offset", "drift", "accuracy")],
        ({"sensor": Microbolometer(drift_time=0.9)}, {"sensor": Microbolometer(drift_time=1.0)},
         "camera.sensor.drift_time"),
        ({"sensor": Microbolometer(drift_time=7.1 * 86400)}, {"sensor": Microbolometer(drift_time=7 * 86400.0)},
         "camera.sensor.drift_time"),
        ({"relative_humidity": 1.001}, {"relative_humidity": 1.0}, "camera.settings.relative_humidity"),
        ({"room_humidity": -0.001}, {"room_humidity": 0.0}, "camera.scene.relative_humidity"),
        ({"emissivity": 0.0}, {"emissivity": 1.0}, "camera.settings.emissivity"),
    ]
    for past, at, field in cases:
        with pytest.raises(InputError) as err:
            replace(base, **past).check(sc)
        assert (err.value.source, err.value.field) == ("s.toml", field), (past, str(err.value))
        replace(base, **at).check(sc)


@pytest.mark.parametrize("camera,field,message", [
    # the audit's: 'got True', 'got False' and numpy's reprs, not what the scenario says
    ('pose = "carrier-front"\nresolution = [true, 240]\n', "camera.resolution",
     "expected a whole number from 1 to 8192, got the boolean true"),
    ('pose = "carrier-front"\nedge_rays = true\n', "camera.edge_rays",
     "expected a whole number from 1 to 8, got the boolean true"),
    ('pose = "carrier-front"\n[camera.sensor]\nbits = false\n', "camera.sensor.bits",
     "expected a whole number from 8 to 16, got the boolean false"),
    ('position = ["0 m", "-2 m", "1.2 m"]\ntarget = ["0 m", "0 m", "1.2 m"]\nup = [0, 0, inf]\n', "camera.up",
     "[0, 0, inf] is not a finite direction"),
    ('position = ["0 m", "-2 m", "1.2 m"]\ntarget = ["0 m", "0 m", "1.2 m"]\nup = [0, 2, 0]\n', "camera.up",
     "[0, 2, 0] is along the line of sight"),
    ('pose = "carrier-front"\nresolution = [320.5, 240]\n', "camera.resolution",
     "expected a whole number from 1 to 8192, got 320.5"),
])
def test_camera_errors_show_the_value_as_the_scenario_writes_it(tmp_path, capsys, camera, field, message):
    """A camera setting's error shows the value in the scenario's terms (twin.errors.describe: 'the
    boolean true'; a direction as [0, 0, inf]), never a Python repr (True, np.float64(0.0))."""
    (tmp_path / "s.toml").write_text(SCENARIO.replace("resolution = [32, 24]\n", "") + camera)
    out = tmp_path / "out.nc"
    assert main(["simulate", "cframe-vmc", str(tmp_path / "s.toml"), "-o", str(out), "--mesh", "coarse"]) == 2
    err = capsys.readouterr().err
    assert f"s.toml: {field}: {message}" in err, err
    assert "True" not in err and "False" not in err and "np." not in err and not out.exists()


def test_a_camera_built_in_python_shows_its_values_in_words():
    """The same checks for a CameraConfig built in Python: numpy numbers and booleans in words."""
    from dataclasses import replace

    import numpy as np

    from twin.observe.camera import CameraConfig
    from twin.observe.camera_geometry import Intrinsics
    from twin.observe.microbolometer import Microbolometer
    from twin.scenario import Ambient, Scenario

    sc = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0)
    base = CameraConfig(pose="carrier-front", where="camera.", source="s.toml")
    cases = [({"position": (0.0, -2.0, 1.0), "target": (0.0, 0.0, 1.0), "up": (np.float64(0), 0.0, np.inf)},
              "camera.up: [0, 0, inf] is not a finite direction"),
             ({"edge_rays": True}, "camera.edge_rays: expected a whole number from 1 to 8, got the boolean true"),
             ({"intrinsics": Intrinsics(width=np.bool_(True))}, "got the boolean true"),
             ({"sensor": Microbolometer(bits=np.float64(12.5))}, "camera.sensor.bits: expected a whole number from "
                                                                 "8 to 16, got 12.5"),
             ({"emissivity": np.float64(np.nan)}, "camera.settings.emissivity: expected a fraction above 0 and at "
                                                  "most 1, got nan"),
             ({"store_counts": None}, "camera.store_counts: expected true or false, got nothing")]
    for change, message in cases:
        with pytest.raises(InputError) as err:
            replace(base, **change).check(sc)
        assert message in str(err.value) and "np." not in str(err.value), (change, str(err.value))
