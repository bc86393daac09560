"""Bad input to the Python API: :func:`twin.api.simulate`, :class:`twin.physics.prepared.PreparedTwin`,
:class:`twin.physics.options.SolverOptions`, a Scenario changed in Python and
:func:`twin.fem.mesh.build_mesh`. Each gets one :class:`twin.errors.InputError` naming the argument
or field, before any mesh is built or any step is run (the ``no_work`` fixture makes both fail the
test), never a bare TypeError, a silent wrong result or an error from deep in the solver."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from geometries import build_machine
from geometries.base import Point
from geometries.materials import MATERIALS
from twin import api, limits
from twin.errors import InputError
from twin.fem.mesh import build_mesh, check_spacing, estimated_nodes
from twin.observe.camera import CameraConfig
from twin.physics.prepared import PreparedTwin
from twin.physics.options import MAX_ROM_ORDER, SolverOptions
from twin.scenario import Ambient, Scenario, available, load_scenario

# 10 min at 8000 rpm, sampled every minute: ten steps
SHORT = Scenario("short", ((600.0, 8000.0),), Ambient("constant", mean=20.0), 60.0)
MOTOR = (0.0, -0.109, 1.7)      # a point inside the C-frame's motor


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if a mesh is built or a run starts: the check must come first."""
    def refuse(*args, **kwargs):
        raise AssertionError("expensive work started before the input was checked")
    monkeypatch.setattr(api, "run", refuse)
    monkeypatch.setattr(api, "mesh_machine", refuse)


@pytest.fixture(scope="module")
def cframe():
    return build_machine("cframe-vmc")


@pytest.fixture(scope="module")
def coarse(cframe):
    """A prepared C-frame on the coarse mesh with the direct solver."""
    return PreparedTwin(cframe, resolution="coarse", solver="direct")


def refused(field: str, call, *args, **kwargs) -> InputError:
    """``call(*args, **kwargs)`` raises one InputError whose field contains ``field``."""
    with pytest.raises(InputError) as info:
        call(*args, **kwargs)
    assert field in info.value.field, f"expected the field {field!r}, got {info.value}"
    return info.value


# ---------------------------------------------------------------------------- 1. SolverOptions
@pytest.mark.parametrize("options, field", [
    ({"heat_tol": float("inf")}, "--heat-tol"),
    ({"heat_tol": float("nan")}, "--heat-tol"),
    ({"heat_tol": 0.0}, "--heat-tol"),
    ({"heat_tol": "1e-6"}, "--heat-tol"),            # a text needs its unit
    ({"heat_tol": "1e-6 m"}, "--heat-tol"),
    ({"heat_tol": True}, "--heat-tol"),
    ({"elastic_rtol": 5.0}, "elastic_rtol"),
    ({"elastic_rtol": 1.0}, "elastic_rtol"),
    ({"elastic_rtol": -1e-8}, "elastic_rtol"),
    ({"elastic_rtol": float("nan")}, "elastic_rtol"),
    ({"max_iterations": 0}, "max_iterations"),
    ({"max_iterations": -5}, "max_iterations"),
    ({"max_iterations": 10.5}, "max_iterations"),
    ({"rom_order": 2.5}, "--rom-order"),
    ({"rom_order": "x"}, "--rom-order"),
    ({"rom_order": 1}, "--rom-order"),
    ({"rom_order": MAX_ROM_ORDER + 1}, "--rom-order"),
])
def test_solver_options_refuse_values_that_would_give_a_wrong_result_or_fail_mid_run(options, field):
    refused(field, SolverOptions, "rom", **options)


def test_solver_options_take_heat_tol_with_its_unit_and_a_too_small_rom_order_is_named(no_work):
    assert SolverOptions(heat_tol="1e-4 K").heat_tol == pytest.approx(1e-4)
    assert SolverOptions(heat_tol="5 mK").heat_tol == pytest.approx(5e-3)
    assert SolverOptions(heat_tol=1e-5, rom_order=np.int64(32)).rom_order == 32
    # a whole number in range, but smaller than three blocks of this model's moments: only the
    # loads know the block size, so the basis takes the three whole blocks its error estimate
    # needs, and the result says the order it ran
    twin = PreparedTwin(build_machine("cframe-vmc"), resolution="coarse", solver=SolverOptions("rom", rom_order=2))
    from twin.model import model_spec
    from twin.observe import HeatBalance
    twin.run(SHORT, model_spec(twin.machine), [HeatBalance()])
    info = twin.run_info
    assert info["rom_order"] > 2 and 0 < info["rom_estimate_order"] < info["rom_order"]


# ---------------------------------------------------------------------------- 2. a prepared twin
def test_a_prepared_twin_must_match_what_simulate_is_asked(coarse, no_work):
    belt = PreparedTwin(build_machine("belt-vmc"), resolution="coarse")
    refused("prepared", api.simulate, "cframe-vmc", SHORT, prepared=belt)
    refused("prepared", api.simulate, "cframe-vmc", SHORT, prepared="coarse")
    refused("--mesh", api.simulate, "cframe-vmc", SHORT, resolution="default", prepared=coarse)
    refused("--mesh", api.simulate, "cframe-vmc", SHORT, resolution="ultra", prepared=coarse)
    refused("--solver", api.simulate, "cframe-vmc", SHORT, solver="rom", prepared=coarse)
    steel = {"steel": MATERIALS["steel"].scaled(conductivity=1.1)}
    refused("materials", api.simulate, "cframe-vmc", SHORT, materials=steel, prepared=coarse)
    # a scenario that moves an axis runs on the machine with its feed drives
    axis = load_scenario("seed003-exp1")
    refused("prepared", api.simulate, "cframe-vmc", axis, prepared=coarse)


def test_a_run_on_a_prepared_twin_is_labelled_with_what_ran(coarse):
    ds, _ = api.simulate("cframe-vmc", SHORT, prepared=coarse, seed=3)
    assert ds.attrs["mesh"] == "coarse" and ds.attrs["mesh_nodes"] == coarse.mm.nnodes
    assert ds.attrs["solver"] == "direct"
    same, _ = api.simulate("cframe-vmc", SHORT, resolution="coarse", solver="direct", prepared=coarse, seed=3)
    assert same.attrs["mesh"] == "coarse"
    np.testing.assert_array_equal(ds.drift.values, same.drift.values)



def test_an_empty_sensor_list_is_a_run_without_temperature_sensors_and_its_file_reads_back(coarse, tmp_path):
    """``sensors=[]`` asks for the drift alone (a measurement of probes only is diagnosed that way):
    the result has a sensor axis of length 0, the same drift as with the machine's sites (the
    sensors observe, they do not load), and its file reads back as a result."""
    from twin.io.measurement import read_checked_result

    none, _ = api.simulate("cframe-vmc", SHORT, prepared=coarse, sensors=[])
    sites, _ = api.simulate("cframe-vmc", SHORT, prepared=coarse)
    assert none.sizes["sensor"] == 0 and sites.sizes["sensor"] > 0
    np.testing.assert_array_equal(none.drift.values, sites.drift.values)
    none.to_netcdf(tmp_path / "r.nc", engine="h5netcdf")
    assert read_checked_result(tmp_path / "r.nc").sizes["sensor"] == 0

# ---------------------------------------------------------------------------- 3. the seed
@pytest.mark.parametrize("seed", [None, -1, 1.5, "3", 2**40, 2**32, True])
def test_the_seed_is_an_integer_from_0_to_2_32_checked_first(seed, no_work):
    refused("seed", api.simulate, "cframe-vmc", SHORT, resolution="coarse", seed=seed)


def test_a_seed_within_range_is_kept():
    assert limits.seed_value(np.uint32(2**32 - 1), "s") == 2**32 - 1
    assert limits.seed_value(0, "s") == 0


# ---------------------------------------------------------------------------- 4. the other arguments
BAD_ARGUMENTS = [
    ("effects-list", {"effects": ["floor"]}, "--effects"),
    ("settings-a-text", {"settings": "spindle_bearings.front_power=200W"}, "--set"),
    ("settings-not-texts", {"settings": [200]}, "--set"),
    ("materials-unknown", {"materials": {"unobtainium": 1}}, "materials"),
    ("materials-unused", {"materials": {"granite": MATERIALS["granite"]}}, "materials"),
    ("materials-a-number", {"materials": {"steel": 1}}, "materials"),
    ("materials-not-a-dict", {"materials": [MATERIALS["steel"]]}, "materials"),
    ("materials-negative", {"materials": {"steel": MATERIALS["steel"].scaled(density=-1.0)}}, "materials"),
    # possible but no machine structure (an expansion of 1 /K drifted 584 m)
    ("materials-expansion", {"materials": {"steel": replace(MATERIALS["steel"], expansion=1.0)}},
     "materials['steel'].expansion"),
    ("materials-stiffness", {"materials": {"steel": replace(MATERIALS["steel"], youngs_modulus=1.0)}},
     "materials['steel'].youngs_modulus"),
    ("materials-band", {"materials": {"steel": replace(MATERIALS["steel"], expansion_band=-1.0)}},
     "materials['steel'].expansion_band"),
    ("sensor-on-another-part", {"sensors": [Point("s1", MOTOR, "table")]}, "sensors[0] s1"),
    ("sensor-unknown-part", {"sensors": [Point("s1", MOTOR, "nopart")]}, "sensors[0] s1"),
    ("sensor-outside", {"sensors": [Point("s1", (10.0, 10.0, 10.0), "carrier")]}, "sensors[0] s1"),
    ("sensor-outside-any-part", {"sensors": [Point("s1", (10.0, 10.0, 10.0), "")]}, "sensors[0] s1"),
    ("sensor-nan", {"sensors": [Point("s1", (np.nan, 0.0, 1.0), "carrier")]}, "sensors[0] s1"),
    ("sensor-two-coordinates", {"sensors": [Point("s1", (0.0, 1.0), "motor")]}, "sensors[0] s1"),
    ("sensor-twice", {"sensors": [Point("s1", MOTOR, "motor"), Point("s1", MOTOR, "motor")]}, "sensors[1] s1"),
    ("sensor-a-text", {"sensors": ["x"]}, "sensors[0]"),
    # names a measurement file cannot hold: write_measurement's file would not read back
    ("sensor-name-comma", {"sensors": [Point("a,b", MOTOR, "motor")]}, "sensors[0]"),
    ("sensor-name-at", {"sensors": [Point("a@b", MOTOR, "motor")]}, "sensors[0]"),
    ("sensor-name-newline", {"sensors": [Point("a\nb", MOTOR, "motor")]}, "sensors[0]"),
    ("sensor-name-padded", {"sensors": [Point(" a", MOTOR, "motor")]}, "sensors[0]"),
    ("sensor-name-number", {"sensors": [Point(1, MOTOR, "motor")]}, "sensors[0]"),
    ("sensors-a-text", {"sensors": "motor"}, "sensors"),
    ("sensor-air-far-above", {"sensors": [Point("s1", (0.0, 0.0, 12.5), "air")]}, "sensors[0] s1"),   # 10 m above the top
    ("cameras-a-text", {"cameras": "carrier-front"}, "cameras"),     # read letter by letter before
    ("camera-unknown-pose", {"cameras": ["nosuch"]}, "camera.pose"),   # found after the mesh before
    ("camera-inside-a-part", {"cameras": [CameraConfig(position=MOTOR, target=(0.0, -2.0, 1.0))]}, "camera.position"),
    ("theta-0", {"theta": 0.0}, "theta"),
    ("theta-0.25", {"theta": 0.25}, "theta"),     # below 1/2 the scheme is not stable (the ROM gave 1e19 um)
    ("theta-0.49", {"theta": 0.49}, "theta"),
    ("theta-2", {"theta": 2.0}, "theta"),
    ("theta-nan", {"theta": float("nan")}, "theta"),
    ("theta-text", {"theta": "0.5"}, "theta"),
    ("progress-a-number", {"progress": 5}, "progress"),       # failed with a TypeError after the mesh
    ("scenario-a-dict", {"scenario": {"name": "x"}}, "scenario"),
    ("resolution-a-list", {"resolution": ["coarse"]}, "--mesh"),
]


@pytest.mark.parametrize("case, kwargs, field", BAD_ARGUMENTS, ids=[c for c, _, _ in BAD_ARGUMENTS])
def test_bad_arguments_are_named_before_any_work(case, kwargs, field, no_work):
    args = {"machine": "cframe-vmc", "scenario": SHORT, "resolution": "coarse", **kwargs}
    refused(field, api.simulate, **args)


def test_a_sensor_on_its_part_in_the_air_or_on_any_part_is_taken(cframe):
    api._check_sensors([Point("a", MOTOR, "motor"), Point("b", MOTOR, ""), Point("c", (0.0, 0.0, 5.0), "air")], cframe)


# ---------------------------------------------------------------------------- 5. a changed scenario
CHANGED = [
    ("initial-below-absolute-zero", {"initial_temperature": -300.0}, "initial_temperature"),
    ("initial-implausible", {"initial_temperature": 500.0}, "initial_temperature"),
    ("initial-text", {"initial_temperature": "20 degC"}, "initial_temperature"),
    ("interval-negative", {"sample_interval": -60.0}, "sample_interval"),
    ("interval-zero", {"sample_interval": 0.0}, "sample_interval"),
    ("interval-nan", {"sample_interval": float("nan")}, "sample_interval"),
    ("interval-text", {"sample_interval": "60 s"}, "sample_interval"),
    ("interval-too-fine", {"sample_interval": 1e-4}, "sample_interval"),
    ("steps-none", {"steps": ()}, "spindle"),
    ("step-negative", {"steps": ((-600.0, 8000.0),)}, "spindle[0].duration"),
    ("step-speed-nan", {"steps": ((600.0, float("nan")),)}, "spindle[0].speed"),
    ("step-speed-negative", {"steps": ((600.0, -10.0),)}, "spindle[0].speed"),
    ("step-one-number", {"steps": ((600.0,),)}, "spindle[0]"),
    ("ambient-nan", {"ambient": Ambient("constant", mean=float("nan"))}, "ambient.temperature"),
    ("ambient-kelvin", {"ambient": Ambient("constant", mean=293.15)}, "ambient.temperature"),
    ("ambient-negative-amplitude", {"ambient": Ambient("daily", mean=20.0, amplitude=-3.0)}, "ambient.amplitude"),
    ("ambient-table-short", {"ambient": Ambient("table", times=(0.0, 60.0), temperatures=(20.0, 21.0))},
     "ambient.times"),
    ("ambient-table-backwards", {"ambient": Ambient("table", times=(600.0, 0.0), temperatures=(20.0, 21.0))},
     "ambient.times"),
    ("ambient-kind", {"ambient": Ambient("weekly")}, "ambient.kind"),
    # a step that is no whole number of samples: the run's grid would end early or hold it past the end
    ("step-off-grid", {"steps": ((900.0, 8000.0),), "sample_interval": 420.0}, "spindle[0].duration"),
    # fields of the wrong type: named, not an AttributeError deep in the run
    ("name-a-number", {"name": 5}, "name"),
    ("name-empty", {"name": " "}, "name"),
    ("description-a-number", {"description": 3}, "description"),
    ("extra-none", {"extra": None}, "extra"),
    ("cameras-a-text", {"cameras": "carrier-front"}, "cameras"),
    ("cameras-of-texts", {"cameras": ("carrier-front",)}, "cameras[0]"),
    ("axes-a-text", {"axes": "Y"}, "axes"),
    ("axes-of-numbers", {"axes": (1,)}, "axes[0]"),
    ("c-axis-a-number", {"c_axis": 3}, "c_axis"),
    ("interferometer-a-text", {"interferometer": "X"}, "interferometer"),
    ("probing-a-number", {"probing": 1}, "probing"),
]


@pytest.mark.parametrize("case, change, field", CHANGED, ids=[c for c, _, _ in CHANGED])
def test_a_scenario_changed_in_python_meets_the_loaders_checks_before_the_run(case, change, field, no_work):
    refused(field, api.simulate, "cframe-vmc", replace(SHORT, **change), resolution="coarse")


def test_every_bundled_scenario_and_a_log_snapped_to_its_grid_pass_the_check():
    for name in available():
        load_scenario(name).check()
    # a log's last step snapped to the sample grid may end up to half an interval after its record
    logged = replace(SHORT, ambient=Ambient("table", times=(0.0, 580.0), temperatures=(20.0, 21.0)),
                     extra={"logged": True})
    limits.check_scenario(logged, build_machine("cframe-vmc"))


# ---------------------------------------------------------------------------- 6. PreparedTwin's arguments
def test_prepared_twin_arguments_are_named_before_the_mesh(cframe, monkeypatch):
    from twin.physics import prepared
    monkeypatch.setattr(prepared, "mesh_machine", lambda *a, **k: pytest.fail("meshed before the check"))
    refused("machine", PreparedTwin, "cframe-vmc")
    refused("machine", PreparedTwin, 3)
    refused("resolution", PreparedTwin, cframe, resolution="bogus")
    refused("mm", PreparedTwin, cframe, "coarse")
    refused("materials", PreparedTwin, cframe, materials={"unobtainium": MATERIALS["steel"]})
    refused("materials", PreparedTwin, cframe, materials={"steel": None})
    refused("--solver", PreparedTwin, cframe, solver="bogus")


# ---------------------------------------------------------------------------- 7. mesh spacing
@pytest.mark.parametrize("spacing", [0.0, -0.1, float("nan"), float("inf"), "0.1", None, 1e-3, 1e-300])
def test_a_mesh_spacing_is_positive_finite_and_affordable_checked_before_allocating(spacing, cframe):
    err = refused("spacing", build_mesh, cframe, spacing)
    if spacing in (1e-3, 1e-300):
        assert "nodes" in err.message


def test_a_mesh_spacing_wider_than_the_machine_is_refused(cframe):
    """A spacing beyond the machine's largest extent (1.9 m for the C-frame) leaves only the parts'
    boundary lines: refused, as the benchmark's --spacing (8000 m meshed 1432 nodes)."""
    from validate import benchmark
    err = refused("spacing", build_mesh, cframe, 8000.0)
    assert "wider than cframe-vmc (1.9 m at its largest)" in err.message
    assert check_spacing(cframe, 1.8) == 1.8
    assert benchmark.main(["--spacing", "8000 m", "--json"]) == 2


def test_the_node_estimate_bounds_the_mesh_and_allows_the_million_node_mesh(cframe):
    coarse = build_mesh(cframe, cframe.resolutions["coarse"])
    assert coarse.nnodes <= estimated_nodes(cframe, cframe.resolutions["coarse"]) <= 1.2 * coarse.nnodes
    # 12 mm: 1 045 574 nodes (README's 1 M-node runs), not built here
    assert check_spacing(cframe, 0.012) == 0.012
    assert 1.0e6 < estimated_nodes(cframe, 0.012) < limits.MAX_NODES


def test_a_prepared_twin_checks_its_runs_as_simulate_does(cframe):
    """PreparedTwin.run and run_batch, a Python user's way past twin.api.simulate, meet the same
    rules: theta in [1/2, 1] (the reduced model integrated theta 0 to a drift of 1e25 m), the
    scenario's values (a step off the sample grid) and the machine's speeds (1e6 rpm ran)."""
    from twin.model import model_spec
    from twin.observe import ToolDrift

    rom = PreparedTwin(cframe, resolution="coarse", solver="rom")
    spec = model_spec(cframe)
    refused("theta", rom.run, SHORT, spec, [ToolDrift()], theta=0.0)
    refused("theta", rom.run_batch, [(SHORT, spec)], [ToolDrift()], theta=1.5)
    refused("spindle[0].speed", rom.run, replace(SHORT, steps=((600.0, 1e6),)), spec, [ToolDrift()])
    refused("spindle[0].duration", rom.run_batch, [(replace(SHORT, steps=((630.0, 8000.0),)), spec)], [ToolDrift()])
    refused("scenario", rom.run, "spindle-duty-cycle", spec, [ToolDrift()])
    # a mesh of another machine (it failed later, "outside the machine") or without the feed drives
    from geometries.axes import with_feed_drives
    refused("mm", PreparedTwin, build_machine("belt-vmc"), rom.mm)
    refused("mm", PreparedTwin, with_feed_drives(cframe), rom.mm)
    refused("sample_interval", rom.run, replace(SHORT, sample_interval=0.0), spec, [ToolDrift()])
    from twin.observe.snapshot import HottestField
    refused("observers", rom.run_batch, [(SHORT, spec)], [ToolDrift(), HottestField()])


def test_solver_options_are_frozen_and_refuse_what_their_solver_never_reads():
    """API audit: ``SolverOptions("direct", rom_order=100)`` was accepted (no basis is built) and
    ``options.heat_tol = -1`` after construction ran as if checked."""
    import dataclasses

    refused("--rom-order", SolverOptions, "direct", rom_order=100)
    refused("--heat-tol", SolverOptions, "direct", heat_tol=1e-3)
    refused("--heat-tol", SolverOptions, "rom", heat_tol="1e-4 K")
    refused("max_iterations", SolverOptions, "rom", max_iterations=10)
    with pytest.raises(dataclasses.FrozenInstanceError):
        SolverOptions().heat_tol = -1.0
    assert SolverOptions("rom", rom_order=32).rom_order == 32
