"""The C-frame's X, Y and Z ball-screw drives, one set of feed-drive effects per axis (issue 11,
item 2 on every axis): the energy each axis's drive delivers and the semi-closed loop's screw
error, each against its closed form."""

from __future__ import annotations

import numpy as np
import pytest

from geometries import build_machine
from geometries.axes import with_feed_drives
from geometries.base import material
from twin.effects.base import EFFECTS, HeatSource
from twin.effects.moving import REFERENCE_ACCELERATION, REFERENCE_FEED
from twin.fem.mesh import mesh_machine
from twin.motion import machine_for
from twin.scenario import scenario_from_dict

from tests.axis_cases import STROKES, axis_scenario, cframe_all_axes

FAMILIES = ("feed_nut", "feed_bearings", "feed_motor", "feed_guideways")


def drive_energy(p: dict, axis: str, duration: float, strokes: int = 6) -> float:
    """A feed effect's heat [J] over whole strokes of :func:`axis_scenario`, closed form:
    P_ref d / v_ref + P_hold T + P_a n 2 a v / a_ref^2 (d = n strokes x stroke, 2 a v each
    stroke's integral of a^2: two ramps of v / a at 10 mm/s2 to 20 mm/s)."""
    return (p["power"] * strokes * STROKES[axis][2] / REFERENCE_FEED + p.get("holding_power", 0.0) * duration
            + p.get("inertia_power", 0.0) * strokes * 2 * 0.01 * 0.02 / REFERENCE_ACCELERATION ** 2)


@pytest.fixture(scope="module")
def cframe_all():
    """The C-frame with the three drives, coarse mesh, and a scenario moving all three axes."""
    return cframe_all_axes()


def test_drives_are_added_only_for_the_axes_a_scenario_moves():
    """No drive part without a moving axis (the spindle tests' meshes stay as they were); a Y move
    adds the Y drive alone; a Z move brings z_axis_holding (its holding losses) beside the Z drive,
    whose motor adds no second holding term (feed_motor_z's holding_power is 0)."""
    base = build_machine("cframe-vmc")
    spindle = scenario_from_dict({"sample_interval": "10 s", "ambient": {"temperature": "20 degC"},
                                  "spindle": [{"speed": "1000 rpm", "duration": "1 min"}]}, "s.toml")
    assert machine_for(base, spindle) is base
    names = {p.name for p in machine_for(base, axis_scenario(("Y",))).parts} - {p.name for p in base.parts}
    assert names == {"y_screw", "y_front_bearing", "y_rear_bearing"}
    z = machine_for(base, axis_scenario(("Z",)))
    assert {"feed_nut_z", "feed_motor_z", "z_axis_holding"} <= set(z.default_effects)
    assert "feed_nut_y" not in z.default_effects
    assert EFFECTS["feed_motor_z"].defaults()["holding_power"] == 0.0
    assert all(EFFECTS[f"{f}_{a}"].applies_to(with_feed_drives(base)) for f in FAMILIES for a in "xyz")
    assert not EFFECTS["feed_nut_x"].applies_to(with_feed_drives(build_machine("belt-vmc")))


@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_each_drive_delivers_its_power_times_the_travelled_distance(cframe_all, axis):
    """Energy balance per axis over whole strokes: the drive's sources deliver
    E = (P_nut + P_bearings + P_motor + P_guideways) d / v_ref + P_hold T + P_a n 2 a v / a_ref^2,
    d the distance travelled (n strokes x stroke), T the scenario's duration, 2 a v each stroke's
    integral of a^2 (two ramps of v / a), on the C-frame's coarse mesh (exact: the path basis
    integrates |v| exactly, the inertia signal a^2 exactly, and the shares sum to one)."""
    machine, mm, sc = cframe_all
    t, dt = sc.times(), sc.sample_interval
    energy, expect = 0.0, 0.0
    for fam in FAMILIES:
        eff = EFFECTS[f"{fam}_{axis.lower()}"]
        p = eff.defaults()
        loads = eff.loads(mm, sc, p)
        assert loads and all(isinstance(s, HeatSource) and len(s.cells) for s in loads)
        energy += sum(np.sum(s.power(t[:-1] + 0.5 * dt)) * dt for s in loads)
        expect += drive_energy(p, axis, t[-1] - t[0])
    assert energy == pytest.approx(expect, rel=1e-12)


# each split family: its share parameter and the roles the share and the rest go into
SPLITS = {"feed_nut": ("screw_share", "screw", "nut_body"),
          "feed_bearings": ("front_share", "front_bearing", "rear_bearing"),
          "feed_guideways": ("rail_share", "guideways", "carriages")}


@pytest.mark.parametrize("family", sorted(SPLITS))
@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_each_split_drive_puts_its_share_where_it_belongs(cframe_all, family, axis):
    """A split source's heat divides as its share says: over whole strokes the cells of the first
    role (the screw, the fixed bearing, the rails) receive E_1 = s P_ref d / v_ref and those of
    the second (the nut housing, the floating bearing, the carriages) E_2 = (1 - s) P_ref d / v_ref,
    s the share; each exactly (the totals alone cannot tell a swapped share). The share is set
    to 0.8 here, away from every default and from 1/2."""
    from twin.fem.regions import role_cells
    from geometries.regions import feed_drive_role
    machine, mm, sc = cframe_all
    share, first, second = SPLITS[family]
    eff = EFFECTS[f"{family}_{axis.lower()}"]
    p = {**eff.defaults(), share: 0.8}
    t, dt = sc.times(), sc.sample_interval
    energy = {first: 0.0, second: 0.0}
    for s in eff.loads(mm, sc, p):
        e = float(np.sum(s.power(t[:-1] + 0.5 * dt)) * dt)
        into = [r for r in (first, second) if np.isin(s.cells, role_cells(mm, feed_drive_role(axis, r))).all()]
        assert len(into) == 1, (s.label, into)
        energy[into[0]] += e
    total = p["power"] * 6 * STROKES[axis][2] / REFERENCE_FEED
    assert energy[first] == pytest.approx(0.8 * total, rel=1e-12)
    assert energy[second] == pytest.approx(0.2 * total, rel=1e-12)


@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_the_screw_gap_couples_screw_and_structure_with_its_conductance(cframe_all, axis):
    """feed_screw_gap_<axis>: q = h_gap (T_screw - T_structure) on the role's facets, so the
    contact's signal is h_gap at every instant and its matrix the interface form on exactly those
    facets. With the screw's nodes at 1 K and the structure's at 0, the heat through the gap is
    h_gap u^T H u = h_gap int (jump)^2 dA: h_gap times the area of the facets whose nodes were all
    split, plus a part of those a support bearing's bond leaves partly joined, so it lies between
    h_gap A_split and h_gap A_gap."""
    from twin.effects.base import ContactConductance
    from twin.fem.assembly import assemble_interface
    from twin.fem.regions import role_facets, role_parts
    from twin.model import ModelSpec
    from twin.physics.loads import build_loads
    from geometries.regions import feed_drive_role
    machine, mm, sc = cframe_all
    name = f"feed_screw_gap_{axis.lower()}"
    ls = build_loads(mm, sc, ModelSpec((name,), {name: {"conductance": 7.5}}))
    (contact,) = ls.convections
    facets = role_facets(mm, feed_drive_role(axis, "screw_gap"))
    assert isinstance(contact, ContactConductance) and np.array_equal(contact.facets, facets)
    h, _, _ = ls.signals(sc.times())
    assert np.all(h[:, 0] == 7.5)
    H = ls.system.H[0]
    assert abs(H - assemble_interface(ls.mm, facets)).max() == 0.0
    screw = np.unique(ls.mm.heat_t[:, mm.cells_of(f"{axis.lower()}_screw")])
    u = np.zeros(ls.mm.nheat)
    u[screw] = 1.0                          # the screw keeps the mesh's nodes; the structure got copies
    structure = np.unique(ls.mm.heat_t[:, mm.cells_of(*role_parts(mm, feed_drive_role(axis, "structure_side")))])
    split = np.setdiff1d(np.unique(mm.mesh.facets[:, facets]), structure)   # the structure holds a copy instead
    assert ls.mm.nheat - mm.nheat == len(split) > 0
    full = facets[np.all(np.isin(mm.mesh.facets[:, facets], split), axis=0)]
    exchanged = 7.5 * float(u @ (H @ u))
    assert 7.5 * mm.facet_area(full) * (1 - 1e-12) <= exchanged <= 7.5 * mm.facet_area(facets) * (1 + 1e-12)
    assert mm.facet_area(full) > 0.5 * mm.facet_area(facets)


def test_the_heat_integrator_stores_all_three_drives_heat(cframe_all):
    """Through the Crank-Nicolson run with the three drives' feed effects alone (no convection):
    the heat in equals the sum of the closed forms above, and all of it is stored."""
    from twin.model import ModelSpec
    from twin.observe import HeatBalance
    from twin.simulate import run
    machine, mm, sc = cframe_all
    names = tuple(f"{f}_{a}" for f in FAMILIES for a in "xyz")
    r = run(machine, sc, ModelSpec(names), mm=mm, observers=[HeatBalance()])
    into, convected, stored = r.step_energy()
    expect = 0.0
    for a in "XYZ":
        for f in FAMILIES:
            expect += drive_energy(EFFECTS[f"{f}_{a.lower()}"].defaults(), a, 600.0)
    assert into == pytest.approx(expect, rel=1e-12)
    assert convected == 0.0 and stored == pytest.approx(into, rel=1e-9)


@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_semi_closed_screw_at_a_uniform_rise_reads_alpha_dT_times_the_nut_distance(cframe_all, axis):
    """Semi-closed loop on each C-frame axis, its screw at a uniform rise dT: the screw's share of
    the positioning error is e(p) = alpha dT (s(p) - s_fixed), s(p) the nut's machine coordinate
    and s_fixed the fixed bearing's (negative where the nut lies below/left of it), exactly."""
    from twin.observe.interferometer import screw_line_rows
    machine, mm, _ = cframe_all
    ax = machine.axis(axis)
    lo, hi = ax.travel
    targets = np.arange(lo, hi + 1e-9, 0.01)
    alpha, dT = material("steel").expansion, 3.0
    rows = screw_line_rows(mm, ax, targets, alpha)
    e = rows @ np.full(mm.nheat, dT)
    assert e == pytest.approx(alpha * dT * (ax.nut_coordinate(targets) - ax.drive.fixed_end), rel=1e-12, abs=1e-18)


AXIS_SPEC = """\
name = "axes"
machines = ["cframe-vmc"]
mesh = "coarse"
seed = 5

[[scenarios]]
family = "axis-duty"
cases = 2
duration = "20 min"
sample_interval = "60 s"
[scenarios.spindle]
step = ["4 min", "8 min"]
speed = ["2000 rpm", "9000 rpm"]
idle_probability = 0.3
[scenarios.ambient]
kind = "constant"
temperature = "20 degC"
[[scenarios.axis]]
name = "Y"
range = ["0 mm", "280 mm"]
feed = ["5 mm/s", "30 mm/s"]
[[scenarios.axis]]
name = "X"
range = ["50 mm", "450 mm"]
feed = "20 mm/s"
acceleration = "50 mm/s2"
"""


def test_dataset_generator_draws_axis_duty_cycles(tmp_path):
    """An axis duty cycle in a dataset generator: deterministic draws, every drawn scenario
    parses and stays in its range, the axes reciprocate only while the spindle runs, and a case
    runs on the C-frame with the commanded axes' drives (their feed effects in its model)."""
    from twin.dataset import load_spec, plan
    from twin.dataset.runner import simulate_case
    from twin.scenario import scenario_from_dict
    (tmp_path / "s.toml").write_text(AXIS_SPEC)
    cases = plan(load_spec(tmp_path / "s.toml"))
    assert [c.hash for c in cases] == [c.hash for c in plan(load_spec(tmp_path / "s.toml"))]
    for c in cases:
        sc = scenario_from_dict(c.record["scenario"], "drawn")
        assert [m.axis for m in sc.axes] == ["Y", "X"]
        t = sc.times()
        for m, (lo, hi) in zip(sc.axes, ((0.0, 0.28), (0.05, 0.45))):
            x = m.position(t)
            assert x.min() >= lo - 1e-12 and x.max() <= hi + 1e-12
            still = np.array([sc.spindle_speed(tt) == 0 for tt in t[1:]])
            assert np.all(m.velocity(t[1:] - 1e-3)[still] == 0.0)
    moving = [c for c in cases if any(m["kind"] == "reciprocate" for a in c.record["scenario"]["axis"]
                                      for m in a["move"])]
    ds, result = simulate_case(moving[0].record, moving[0].hash, max_steps=3)
    assert {"y_screw", "x_screw"} <= {p.name for p in result.machine.parts}
    assert {"feed_nut_x", "feed_nut_y", "feed_motor_x"} <= set(ds.attrs["effects"].split(","))
    assert "feed_nut_z" not in ds.attrs["effects"]


@pytest.mark.parametrize("old,new,field", [
    ('name = "Y"', 'name = "W"', "scenarios[0].axis[0].name"),
    ('range = ["0 mm", "280 mm"]', 'range = ["0 mm", "600 mm"]', "scenarios[0].axis[0].range"),
    ('feed = ["5 mm/s", "30 mm/s"]', 'feed = ["0 mm/s", "30 mm/s"]', "scenarios[0].axis[0].feed"),
    ('acceleration = "50 mm/s2"', 'acceleration = "0 mm/s2"', "scenarios[0].axis[1].acceleration"),
    ('acceleration = "50 mm/s2"', 'acceleration = "50 mm/s2"\nstroke = "1 mm"', "scenarios[0].axis[1].stroke"),
    # beyond twin.limits.MAX_ACCELERATION: refused in the spec, not later in the plan's drawn moves
    ('acceleration = "50 mm/s2"', 'acceleration = "100 m/s2"', "scenarios[0].axis[1].acceleration"),
    ('range = ["0 mm", "280 mm"]', 'range = { normal = ["100 mm", "10 mm"] }', "scenarios[0].axis[0].range"),
])
def test_a_bad_axis_duty_cycle_names_its_field(tmp_path, old, new, field):
    """Bad axis generator values are InputErrors naming the spec file and the field."""
    from twin.dataset import load_spec
    from twin.errors import InputError
    assert old in AXIS_SPEC
    (tmp_path / "s.toml").write_text(AXIS_SPEC.replace(old, new, 1))
    with pytest.raises(InputError) as err:
        load_spec(tmp_path / "s.toml")
    assert err.value.source == str(tmp_path / "s.toml") and err.value.field == field
    if "normal" in new:
        assert "not a distribution" in str(err.value)


def test_cframe_axes_have_the_seeds_travels_and_the_readmes_nut_positions():
    """README "Axis motion" (seed 000, Machine A: X 500, Y 400, Z 330 mm, ball screws with rotary
    encoders): X 0-500, Y 0-400, Z 0-330 mm, all semi-closed, meshed at X = 250, Y = 200, Z = 0 mm.
    Where the nut is (nut_at_zero + p), from the README's thesis-duty-test1 paragraph: at X = 150 mm
    the X nut is 0.40 m from its fixed bearing and at X = 350 mm half that; at Z = 100 mm the Z nut
    is 0.45 m below its top (fixed) bearing; and (geometries/cframe_vmc.py) at the mesh's pose the
    Y nut is under the saddle's centre and the X nut under the table's. Every nut stays on its
    screw, between its two bearings, over the whole travel."""
    m = build_machine("cframe-vmc")
    assert [(a.name, a.direction, a.travel, a.feedback, a.p_ref) for a in m.axes] == [
        ("X", "x", (0.0, 0.50), "semi-closed", 0.25), ("Y", "y", (0.0, 0.40), "semi-closed", 0.20),
        ("Z", "z", (0.0, 0.33), "semi-closed", 0.0)]
    x, y, z = m.axis("X"), m.axis("Y"), m.axis("Z")
    assert x.drive.fixed_end - x.nut_coordinate(0.15) == pytest.approx(0.40, abs=1e-12)
    assert x.drive.fixed_end - x.nut_coordinate(0.35) == pytest.approx(0.20, abs=1e-12)
    assert z.drive.fixed_end - z.nut_coordinate(0.10) == pytest.approx(0.45, abs=1e-12)

    def centre(part, k):
        box = m.part(part).boxes[0]
        return 0.5 * (box.lo[k] + box.hi[k])

    assert y.nut_coordinate(y.p_ref) == pytest.approx(centre("saddle", 1), abs=1e-12)
    assert x.nut_coordinate(x.p_ref) == pytest.approx(centre("table", 0), abs=1e-12)
    for ax in m.axes:
        k = "xyz".index(ax.direction)
        screw = next(p for p in ax.drive.parts if p.name.endswith("_screw")).boxes[0]
        for p in ax.travel:
            assert screw.lo[k] <= ax.nut_coordinate(p) <= screw.hi[k], (ax.name, p)


def test_guideway_heat_sits_at_the_carriages_ahead_of_and_behind_the_nut():
    """The rails' share of the guideway friction enters where the two carriages are, at the nut's
    coordinate +- carriage_offset (250 mm on Y), half each, and none under the nut: over a
    reciprocation of n strokes of d, each carriage's band receives P_ref (n d / v_ref) / 2 [J]
    exactly (the path basis's step averages of |v|); the offsets (0, 0) passed every test before."""
    sc = scenario_from_dict({"sample_interval": "10 s", "ambient": {"temperature": "20 degC"},
                             "spindle": [{"speed": "0 rpm", "duration": "10 min"}],
                             "axis": [{"name": "Y", "move": [{"kind": "reciprocate", "between": ["190 mm", "210 mm"],
                                                              "feed": "20 mm/s", "acceleration": "10 mm/s2",
                                                              "count": 10}]}]}, "t.toml")
    from twin.fem.regions import cell_centres

    machine = machine_for(build_machine("cframe-vmc"), sc)
    mm = mesh_machine(machine, "coarse")
    effect = EFFECTS["feed_guideways_y"]
    p = {**effect.defaults(), "rail_share": 1.0}
    nut = float(machine.axis("Y").nut_coordinate(np.array([0.2]))[0])
    t, dt = sc.times(), sc.sample_interval
    energy = {"ahead": 0.0, "behind": 0.0, "under the nut": 0.0}
    for source in effect.loads(mm, sc, p):
        y = cell_centres(mm, source.cells)[:, 1].mean()
        joules = float(np.sum(source.power(t[:-1] + 0.5 * dt)) * dt)
        for where, at in (("ahead", nut + p["carriage_offset"]), ("behind", nut - p["carriage_offset"]),
                          ("under the nut", nut)):
            if abs(y - at) < 0.1:
                energy[where] += joules
    assert p["carriage_offset"] == 0.25
    total = p["power"] * 10 * 0.02 / REFERENCE_FEED
    assert energy["ahead"] == pytest.approx(total / 2, rel=1e-12)
    assert energy["behind"] == pytest.approx(total / 2, rel=1e-12)
    assert energy["under the nut"] == 0.0


@pytest.mark.parametrize("machine, axis, mass, lead, inertia, torque_constant, resistance", [
    ("cframe-vmc", "Y", 600.0, 0.010, 0.0044, 1.2, 1.2),       # the registry's default (every axis)
    ("gantry-ram", "Z", 1190.0, 0.020, 0.013, 2.0, 1.05),      # geometries.gantry_ram.Z_DRIVE_DEFAULTS
])
def test_the_motors_inertia_losses_are_the_copper_losses_of_the_inertia_torque(machine, axis, mass, lead, inertia,
                                                                                torque_constant, resistance):
    """feed_motor's inertia_power at a_ref = 1 m/s2: R (M / k_t)^2 with the torque that accelerates
    the moving mass and the rotor and screw, M = (m l / (2 pi eta) + J 2 pi / l) a, eta 0.9, from
    the inputs its text states (C-frame 12.2 W, 3.83 N m; gantry Z 18.1 W, 8.30 N m); the defaults
    are rounded to whole watts. The Z ram's moving mass is what the machine's parts that move with
    Z weigh (rho V of their cells), 1.19 t."""
    from geometries.axes import with_feed_drives

    torque = mass * lead / (2 * np.pi * 0.9) + inertia * 2 * np.pi / lead
    expect = resistance * (torque / torque_constant) ** 2
    built = with_feed_drives(build_machine(machine))
    effect = EFFECTS[f"feed_motor_{axis.lower()}"]
    default = {**effect.defaults(), **built.effect_defaults.get(effect.name, {})}["inertia_power"]
    assert default == pytest.approx(expect, abs=0.5)
    if machine == "gantry-ram":
        mm = mesh_machine(built, "coarse")                 # each cell of one part: no box counted twice
        weight = sum(p.material.density * mm.volume_of(mm.cells_of(p.name))
                     for p in built.parts if p.name in built.axis(axis).moving)
        assert weight == pytest.approx(mass, rel=0.01)


def test_a_standing_axis_puts_no_feed_heat_and_its_motor_holds():
    """A [[axis]] that only holds (kind = "hold"): mean |v| = 0 on every step, so every
    feed-proportional load is exactly 0 (not NaN) and feed_motor_x delivers its holding 5 W."""
    from twin.fem.mesh import mesh_machine
    from twin.motion import machine_for
    sc = scenario_from_dict({"sample_interval": "60 s", "ambient": {"temperature": "20 degC"},
                             "spindle": [{"speed": "0 rpm", "duration": "5 min"}],
                             "axis": [{"name": "X", "move": [{"kind": "hold", "position": "100 mm",
                                                              "duration": "5 min"}]}]}, "hold.toml")
    machine = machine_for(build_machine("cframe-vmc"), sc)
    mm = mesh_machine(machine, "coarse")
    t = sc.times()[:-1] + 30.0
    for name in ("feed_nut_x", "feed_bearings_x", "feed_motor_x", "feed_guideways_x"):
        for load in EFFECTS[name].loads(mm, sc, EFFECTS[name].defaults()):
            expect = 5.0 if load.label == "feed_motor_x.hold" else 0.0
            assert load.power(t).tolist() == [expect] * len(t), load.label


def test_guideway_carriage_offsets_are_the_readmes():
    """The carriages sit ahead of and behind the nut by 50 mm on X, 250 mm on Y and 120 mm on Z (README
    feed-drive table; twin.effects.feed.AXIS_DEFAULTS)."""
    offs = [EFFECTS[f"feed_guideways_{a}"].defaults()["carriage_offset"] for a in "xyz"]
    assert offs == [0.05, 0.25, 0.12]
