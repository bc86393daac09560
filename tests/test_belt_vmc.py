"""``belt-vmc`` (seed 000, Machine B): its mesh, its 77 temperature points, the belt-drive law and
its calibration against the seed's heating/cooling tests (thesis Table 5-3, L5203-5257).

belt-vmc's default effect set is the C-frame's five plus ``belt_drive`` (``Machine.default_effects``).
Runtime (about 60 s on 2 idle cores with the solid castings; the hollow ones have 36 % more nodes on
``default``, 5 % on ``fine``; 6.7 min measured beside a running diagnosis study): the calibration
runs on the ``default`` mesh, one module-scoped run per scenario (belt-test-6, belt-test-1,
belt-test-4: the 8 h test is the longest, and Test IV is the seed's training test); the
mesh-convergence check needs one ``fine`` run (belt-test-6, the shortest test and the one with the
largest drift). The point checks
use the meshes only (no run). Test II, III and V are not run here: II and III repeat Test I's
speed for longer, V is Test VI without the room drift.

Two kinds of bands: the seed's range where the twin reaches it (peak X and Z at 8000 rpm, the
mesh convergence), and where it does not (peak Y: 19 um against 60-79 at 8000 rpm) the twin's own
calibrated value, held as a band, beside a strict ``xfail`` test that states the seed's band and
fails loudly (XPASS) once a change reaches it. Why Y falls short: ``geometries/belt_vmc.py``. The
hollow construction's bending is checked against thin-walled beam theory (last test).
"""

from __future__ import annotations

import numpy as np
import pytest

from geometries import build_machine
from geometries.belt_vmc import AIR_GAP_MAX, AIR_POINTS, TEMPERATURE_POINTS
from twin.api import simulate
from twin.effects import EFFECTS
from twin.errors import InputError
from twin.fem.mesh import mesh_machine
from twin.fem.points import locate
from twin.observe.sensor_grid import owner_of

AXES6 = np.vstack([np.eye(3), -np.eye(3)])
Y_SHORT = ("peak Y is 3-5x below the seed in this model: no heat path turns the twin's 330 W into the seed's Y "
           "without as much Z (geometries/belt_vmc.py)")


@pytest.fixture(scope="module")
def machine():
    return build_machine("belt-vmc")


@pytest.fixture(scope="module")
def meshes(machine):
    return {res: mesh_machine(machine, res) for res in machine.resolutions}


def _run(scenario, resolution="default"):
    ds, _ = simulate("belt-vmc", scenario, resolution=resolution)
    return ds


@pytest.fixture(scope="module")
def test6():
    return _run("belt-test-6")


@pytest.fixture(scope="module")
def test6_fine():
    return _run("belt-test-6", "fine")


@pytest.fixture(scope="module")
def test1():
    return _run("belt-test-1")


@pytest.fixture(scope="module")
def test4():
    return _run("belt-test-4")


def peak(ds, axis):
    return float(np.abs(ds.drift.sel(axis=axis).values).max())


# ---- the machine and its points ----------------------------------------------------------------

def test_meshes_at_every_resolution_with_every_part_and_surface(machine, meshes):
    """Every resolution meshes (coarse 100, default 60, fine 40 mm), each part has cells and each
    named surface faces (the mesher raises on an empty one); nodes grow as the cells shrink."""
    nodes = [meshes[r].nnodes for r in ("coarse", "default", "fine")]
    assert nodes == sorted(nodes) and nodes[0] > 1000
    for mm in meshes.values():
        assert all(len(mm.cells_of(p.name)) for p in machine.parts)
        assert set(mm.facets) == {s.name for s in machine.surfaces}
        assert all(len(f) for f in mm.facets.values())


def test_seventy_seven_points_in_the_seed_order(machine):
    """T1..T77 (Table 4-4) = the structural sensor sites + the air sites, disjoint, in that order;
    the air points are T66 T67 T70 T73 T75 T76 T77."""
    assert TEMPERATURE_POINTS == tuple(f"T{i}" for i in range(1, 78))
    assert set(machine.sensor_sites) | set(machine.air_sites) == set(TEMPERATURE_POINTS)
    assert not set(machine.sensor_sites) & set(machine.air_sites)
    assert sorted(machine.air_sites, key=TEMPERATURE_POINTS.index) == ["T66", "T67", "T70", "T73", "T75", "T76", "T77"]
    assert set(machine.air_sites) == set(AIR_POINTS)
    order = [TEMPERATURE_POINTS.index(n) for n in machine.sensor_sites]
    assert order == sorted(order) and len(machine.sensor_sites) == 70
    assert all(machine.point(n).part == "air" for n in machine.air_sites)


def test_structural_sites_lie_in_their_part_one_mm_under_a_face(machine, meshes):
    """Each structural site is in a cell of its own part on every mesh (``twin.fem.points.locate``);
    a glued sensor has air 2 mm away along one axis (it is 1 mm inside an exterior face; T71-T72
    "inside the column" are glued to the walls of the hollow column's cavity)."""
    pts = [machine.point(n) for n in machine.sensor_sites]
    xyz = np.array([p.xyz for p in pts])
    for mm in meshes.values():
        cells, _ = locate(mm, xyz, [p.name for p in pts])
        assert [mm.part_names[mm.cell_part[c]] for c in cells] == [p.part for p in pts]
    index = {p.name: i for i, p in enumerate(machine.parts)}
    assert list(owner_of(machine, xyz)) == [index[p.part] for p in pts]
    for p in pts:
        assert np.any(owner_of(machine, np.asarray(p.xyz) + 0.002 * AXES6) == -1), p.name
    # T71 on the front wall's inner face, T72 on the rear wall's: the cavity 2 mm away
    for name, inwards in (("T71", (0.0, 1.0, 0.0)), ("T72", (0.0, -1.0, 0.0))):
        assert owner_of(machine, np.add(machine.point(name).xyz, np.multiply(0.002, inwards)))[0] == -1, name


def test_sensor_groups_where_table_4_4_puts_them(machine):
    """Column T1-T7 on the column; strip 1 T8-T33 up the carrier's front face and strip 2 T34-T62
    down its right side, each spread evenly over the carrier's height (spacing h/n, first and last
    h/(2n) from the ends); boss T63-T65 below the carrier; Y bed T68-T69 on the bed; table T74."""
    body = machine.part("carrier").boxes[:-1]  # the hollow carrier's boxes; the last is the boss under it
    lo, hi = np.min([b.lo for b in body], axis=0), np.max([b.hi for b in body], axis=0)
    z0, z1 = lo[2], hi[2]
    assert all(machine.point(f"T{i}").part == "column" for i in (*range(1, 8), 71, 72))
    for first, n, rising, axis, face in ((8, 26, True, 1, lo[1]), (34, 29, False, 0, hi[0])):
        xyz = np.array([machine.point(f"T{first + i}").xyz for i in range(n)])
        z = xyz[:, 2] if rising else xyz[::-1, 2]
        assert np.allclose(np.diff(z), (z1 - z0) / n) and z[0] == pytest.approx(z0 + (z1 - z0) / (2 * n))
        assert np.allclose(np.abs(xyz[:, axis] - face), 1e-3)
    assert all(machine.point(f"T{i}").part == "carrier" and machine.point(f"T{i}").xyz[2] < z0 for i in (63, 64, 65))
    assert [machine.point(n).part for n in ("T68", "T69", "T74")] == ["bed", "bed", "table"]


def test_air_sites_in_the_air_beside_their_place(machine, meshes):
    """Each air point is outside every part (no mesh cell holds it: ``locate`` raises) and
    between 20 mm and ``AIR_GAP_MAX`` = 0.1 m from the part it is named after (AIR_POINTS)."""
    for name in machine.air_sites:
        p = np.asarray(machine.point(name).xyz)
        assert owner_of(machine, p)[0] == -1, name
        for mm in meshes.values():
            with pytest.raises(ValueError, match="outside the machine"):
                locate(mm, p, [name])
        gap = min(np.linalg.norm(np.maximum(np.maximum(np.subtract(b.lo, p), np.subtract(p, b.hi)), 0.0))
                  for b in machine.part(AIR_POINTS[name]).boxes)
        assert 0.02 <= gap <= AIR_GAP_MAX, (name, gap)


def test_belt_drive_needs_a_belt_and_is_a_belt_vmc_default():
    """belt_drive acts on the role ``spindle.belt_contact``: belt-vmc declares it (and has the
    effect by default), cframe-vmc does not, so the C-frame refuses the effect with an InputError
    naming the role and the diagnosis never tries it there."""
    belt = EFFECTS["belt_drive"]
    assert "belt_drive" in build_machine("belt-vmc").default_effects
    assert "belt_drive" not in build_machine("cframe-vmc").default_effects
    assert belt.applies_to(build_machine("belt-vmc")) and not belt.applies_to(build_machine("cframe-vmc"))
    with pytest.raises(InputError, match="spindle.belt_contact"):
        simulate("cframe-vmc", "belt-test-1", effects="+belt_drive", resolution="coarse")


# ---- the belt-drive law -------------------------------------------------------------------------

def test_belt_heat_power_is_the_power_law(test1, test6):
    """heat_power[belt_drive] = P_ref (n / n_ref)^x with P_ref = 50 W, n_ref = 8000 rpm, x = 1.5
    at the tests' speeds (4000 rpm: 50 / 2^1.5 = 17.678 W; 8000 rpm: 50 W) to 1e-9 relative,
    and exactly 0 while the spindle stands."""
    defaults = EFFECTS["belt_drive"].defaults()
    p_ref, n_ref, x = defaults["power"], defaults["reference_speed"], defaults["exponent"]
    assert (p_ref, n_ref, x) == (50.0, 8000.0, 1.5)
    for ds, n in ((test1, 4000.0), (test6, 8000.0)):
        power = ds.heat_power.sel(effect="belt_drive").values
        running = ds.spindle_speed.values == n
        assert running.sum() > 100
        np.testing.assert_allclose(power[running], p_ref * (n / n_ref) ** x, rtol=1e-9)
        assert np.all(power[ds.spindle_speed.values == 0] == 0.0)


# ---- calibration ---------------------------------------------------------------------------------

def test_8000_rpm_x_and_z_in_the_seed_range(test6):
    """Test VI (8000 rpm 1 h, 1 h stopped; seed X 3, Z 22-24 um): peak |X| < 5 um (symmetry) and
    peak |Z| in 15-30 um."""
    assert peak(test6, "X") < 5.0
    assert 15.0 <= peak(test6, "Z") <= 30.0


def test_twin_calibration_of_peak_y(test6, test1, test4):
    """The twin's own peak |Y| (not the seed's): Test VI 15-23 um (18.9), Test I 3.5-7 um (5.2),
    Test IV 10-17 um (13.7); as in the seed, Y grows with heating time and speed (IV > I, VI > I)."""
    y6, y1, y4 = peak(test6, "Y"), peak(test1, "Y"), peak(test4, "Y")
    assert 15.0 <= y6 <= 23.0 and 3.5 <= y1 <= 7.0 and 10.0 <= y4 <= 17.0
    assert y4 > y1 and y6 > y1


@pytest.mark.xfail(strict=True, reason=Y_SHORT)
def test_seed_band_8000_rpm_y(test6):
    """Seed band, not reached: Test VI peak |Y| in 55-85 um (seed 60-79) and above peak |Z|."""
    assert 55.0 <= peak(test6, "Y") <= 85.0 and peak(test6, "Y") > peak(test6, "Z")


@pytest.mark.xfail(strict=True, reason=Y_SHORT)
def test_seed_band_4000_rpm_y(test1, test4):
    """Seed band, not reached: Test I peak |Y| in 18-32 um (seed 25), Test IV in 30-50 um (seed 39)."""
    assert 18.0 <= peak(test1, "Y") <= 32.0 and 30.0 <= peak(test4, "Y") <= 50.0


def test_mesh_convergence_of_peak_y(test6, test6_fine):
    """Peak |Y| (and |Z|) of Test VI differ by less than 3 % between the default and fine meshes."""
    for axis in "YZ":
        d, f = peak(test6, axis), peak(test6_fine, axis)
        assert abs(d - f) < 0.03 * f, axis


def test_diagnose_finds_a_cabinet_on_a_belt_vmc_measurement(tmp_path, capsys):
    """``twin diagnose`` on a belt-vmc result (the machine taken from the file): a hidden 150 W
    electrical cabinet is ranked first and fitted within 10 % (coarse meshes, 40 min at 60 s)."""
    import json

    from twin.cli import main

    sc = tmp_path / "short.toml"
    sc.write_text('sample_interval = "60 s"\n[ambient]\ntemperature = "20 degC"\n'
                  '[[spindle]]\nspeed = "8000 rpm"\nduration = "30 min"\n[[spindle]]\nspeed = "0 rpm"\nduration = "10 min"\n')
    meas, report = tmp_path / "meas.nc", tmp_path / "d.json"
    assert main(["simulate", "belt-vmc", str(sc), "-o", str(meas), "--mesh", "coarse", "--seed", "1",
                 "--effects", "+electrical_cabinet", "--set", "electrical_cabinet.power=150W"]) == 0
    assert main(["diagnose", str(meas), "--mesh", "coarse", "--error-mesh", "none", "--json", str(report)]) == 0
    top = json.loads(report.read_text())["candidates"][0]
    assert top["effect"] == "electrical_cabinet"
    assert float(top["parameters"]["electrical_cabinet"]["power"].split()[0]) == pytest.approx(150, rel=0.1)


def test_hollow_column_bends_as_a_thin_walled_beam():
    """The hollow column construction (``column_boxes``: 25 mm walls, one cell through each) with
    its front wall heated: Euler-Bernoulli for a free beam of any section, plane sections,
    kappa = alpha * integral T (y - y_c) dA / I (here T is the mesh's own nodal field, dT on the
    front wall, falling linearly to 0 across the side walls' first cell), so the middle of a
    length c of the column's rear wall bows kappa c^2 / 8 against its ends (within 2 %, away from
    the open foot and the top plate; 0.9 % on this mesh: shear lag and the one-cell walls)."""
    from geometries.base import Machine, Part, material
    from geometries.belt_vmc import column_boxes
    from twin.physics.elastic import ElasticSolver

    b, depth, t, height, dT = 0.4, 0.4, 0.025, 2.4, 10.0
    iron = material("grey_cast_iron")
    part = Part("column", iron, column_boxes((0.0, 0.0, 0.0), (b, depth, height), t))
    mm = mesh_machine(Machine("hollow", [part], [], [], [], "", "", [], {"test": 0.05}), "test")
    y = mm.mesh.p[1]
    grid = np.unique(y)
    ramp_end = grid[grid > t + 1e-9][0]
    T = dT * np.clip((ramp_end - y) / (ramp_end - t), 0.0, 1.0)
    u = ElasticSolver.build(mm).displacement(T)
    # the section: front and rear walls b x t, side walls t x (depth - 2t); centroid at depth / 2
    ys = np.linspace(0.0, depth, 400001)
    width = np.where((ys <= t) | (ys >= depth - t), b, 2 * t)
    temp = dT * np.clip((ramp_end - ys) / (ramp_end - t), 0.0, 1.0)
    yc = depth / 2
    inertia = np.trapezoid(width * (ys - yc) ** 2, ys)
    kappa = iron.expansion * np.trapezoid(width * temp * (ys - yc), ys) / inertia  # < 0: the hot front is longer
    node = lambda z: int(np.argmin(np.sum((mm.mesh.p.T - np.array([b / 2, depth, z])) ** 2, axis=1)))
    z0, z1 = 0.6, 1.8
    ends, mid = (node(z0), node(z1)), node((z0 + z1) / 2)
    bow = u[mid, 1] - 0.5 * (u[ends[0], 1] + u[ends[1], 1])
    assert bow == pytest.approx(kappa * (z1 - z0) ** 2 / 8, rel=0.02)  # bows towards the hot front (-y)


def test_speed_range_travels_and_motor_place_are_the_documented_ones(machine):
    """Seed 000, Machine B (../shared/notes/000_thesis.md section 1.2, thesis L4052): spindle
    speed 60 to 8000 rpm, so 8000 rpm is the limit scenarios and logs are held to; linear scales
    on every axis (closed loop). The seed gives no travels: README's machine list states the
    chosen X 400, Y 300, Z 300 mm, and the DC motor on the carrier top 0.29 m behind the
    spindle (the belt's centre distance, ``motor_offset``; y points to the column, the rear)."""
    from twin import limits

    assert machine.max_speed == 8000.0 and limits.max_speed(machine) == 8000.0
    assert machine.parameters["min_speed"] == 60.0
    limits.check_speeds([0.0, 8000.0], machine, "s", "f")
    with pytest.raises(InputError, match="8000 rpm"):
        limits.check_speeds(8001.0, machine, "s", "f")
    assert [(a.name, a.travel, a.feedback) for a in machine.axes] == [
        ("X", (0.0, 0.40), "closed"), ("Y", (0.0, 0.30), "closed"), ("Z", (0.0, 0.30), "closed")]
    assert [machine.parameters[f"travel_{a}"] for a in "xyz"] == [0.40, 0.30, 0.30]
    assert machine.parameters["motor_offset"] == 0.29
    motor = machine.part("motor").boxes[0]
    assert 0.5 * (motor.lo[0] + motor.hi[0]) == pytest.approx(0.0, abs=1e-12)
    assert 0.5 * (motor.lo[1] + motor.hi[1]) == pytest.approx(0.29, abs=1e-12)
    assert motor.lo[2] == pytest.approx(max(b.hi[2] for b in machine.part("carrier").boxes), abs=1e-12)  # on its top


@pytest.mark.parametrize("speed, refused", [(30.0, True), (59.9, True), (0.0, False), (60.0, False), (8000.0, False)])
def test_a_step_below_the_slowest_steady_speed_is_refused(speed, refused):
    """Machine B turns 60-8000 rpm (seed 000 L4052): a scenario step between stopped and 60 rpm is
    impossible and refused; a measured log ramping through it is not (logged)."""
    from twin import limits
    machine = build_machine("belt-vmc")
    limits.check_speeds([speed], machine, "s.toml", "spindle[0].speed", logged=True)
    if not refused:
        limits.check_speeds([speed], machine, "s.toml", "spindle[0].speed")
        return
    with pytest.raises(InputError) as err:
        limits.check_speeds([speed], machine, "s.toml", "spindle[0].speed")
    assert err.value.message == f"{speed:g} rpm is below machine belt-vmc's slowest steady speed of 60 rpm (0 rpm: stopped)"
