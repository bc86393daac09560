"""``twin dataset``'s spec checks and plan: counts, hashes and draws deterministic, a changed
spec changing only the cases it touches, grids and splits, and every bad spec one clear error with
nothing written (issue 14)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.dataset_files import REF, SPEC, write_spec

DAILY = 'kind = "daily"\nmean = ["18 degC", "22 degC"]\namplitude = ["0 K", "3 K"]\ncoldest_at = ["0 h", "24 h"]'

from twin.cli import main
from twin.dataset import load_spec, plan
from twin.dataset.spec import spec_from_dict


# --- the plan -----------------------------------------------------------------------------------

def test_plan_counts_hashes_and_draws_are_deterministic(tmp_path):
    spec_path = write_spec(tmp_path)
    a, b = plan(load_spec(spec_path)), plan(load_spec(spec_path))
    assert len(a) == 3 and [c.hash for c in a] == [c.hash for c in b]
    assert len({c.hash for c in a}) == 3
    assert [c.info["family"] for c in a] == ["duty", "duty", "reference"]
    assert sorted(c.split for c in a if c.info["family"] == "duty") == ["test", "train"]
    duty = a[0].record["scenario"]
    total = sum(float(s["duration"].split()[0]) for s in duty["spindle"])
    assert total == 600.0 and all(float(s["speed"].split()[0]) % 500 == 0 for s in duty["spindle"])
    assert 40 <= a[0].info["spindle_motor.power [W]"] <= 80 and a[0].info["ambient_convection.h [W/m2K]"] == 7


def test_a_changed_spec_changes_only_the_cases_it_touches(tmp_path):
    base = {c.info["family"] + str(c.info["draw"]): c.hash for c in plan(load_spec(write_spec(tmp_path)))}
    more = plan(load_spec(write_spec(tmp_path, SPEC.replace("cases = 2", "cases = 3"))))
    assert {c.info["family"] + str(c.info["draw"]): c.hash for c in more if c.info["draw"] < 2} == base
    assert len(more) == 4
    # a new range for the duty family's room changes the duty cases only
    other = plan(load_spec(write_spec(tmp_path, SPEC.replace('mean = ["18 degC", "22 degC"]', 'mean = "21 degC"'))))
    changed = {c.info["family"] for c in other if c.hash != base[c.info["family"] + str(c.info["draw"])]}
    assert changed == {"duty"}
    # splits are metadata: never part of a hash
    split = plan(load_spec(write_spec(tmp_path, SPEC.replace("train = 0.5\ntest = 0.5", "train = 1.0"))))
    assert {c.hash for c in split} == set(base.values()) and {c.split for c in split} == {"train"}


def test_a_grid_crosses_every_draw_with_the_same_scenarios(tmp_path):
    text = SPEC.replace('"7 W/m2K"', '{ grid = ["6 W/m2K", "10 W/m2K"] }')
    cases = plan(load_spec(write_spec(tmp_path, text)))
    assert len(cases) == 6
    duty = [c for c in cases if c.info["family"] == "duty"]
    assert duty[0].record["scenario"] == duty[2].record["scenario"]
    assert {c.info["ambient_convection.h [W/m2K]"] for c in duty} == {6.0, 10.0}


def test_splits_by_family(tmp_path):
    text = SPEC.replace('by = "case"\ntrain = 0.5\ntest = 0.5', 'by = "family"\ntrain = ["duty"]\ntest = ["reference"]')
    cases = plan(load_spec(write_spec(tmp_path, text)))
    assert {(c.info["family"], c.split) for c in cases} == {("duty", "train"), ("reference", "test")}


BAD = [
    ('mesh = "coarse"', 'mesh = "coarse"\ncolour = "red"', "colour", "unknown key"),
    # a family reading the spec itself as its scenario: said so (it was "machines: unknown key")
    ('file = "ref.toml"', 'file = "tiny.toml"', "scenarios[1].file", "is this spec itself"),
    ('machines = ["cframe-vmc"]', 'machines = ["lathe"]', "machines[0]", "unknown machine"),
    ('mesh = "coarse"', 'mesh = "huge"', "mesh", "unknown resolution"),
    ('{ uniform = ["40 W", "80 W"] }', '{ uniform = ["40 W", "80 K"] }', "parameters.spindle_motor.power.uniform[1]",
     "wrong unit"),
    ('{ uniform = ["40 W", "80 W"] }', '{ uniform = ["80 W", "40 W"] }', "parameters.spindle_motor.power.uniform",
     "reversed range"),
    ('{ uniform = ["40 W", "80 W"] }', '{ uniform = ["40 W", "8000 W"] }', "parameters.spindle_motor.power.uniform",
     "outside the bounds"),
    ('{ uniform = ["40 W", "80 W"] }', '{ normal = ["60 W", "-1 W"] }', "parameters.spindle_motor.power.normal",
     "standard deviation"),
    ('{ uniform = ["40 W", "80 W"] }', '{ gauss = ["60 W", "1 W"] }', "parameters.spindle_motor.power", "expected one of"),
    # each kind's own form in the message (it said "([lo, hi] or [mean, sd])" for a fixed too)
    ('{ uniform = ["40 W", "80 W"] }', '{ fixed = ["40 W", "80 W"] }', "parameters.spindle_motor.power.fixed",
     'a fixed takes one value, e.g. { fixed = "40 W" }, got 2 values'),
    ('{ uniform = ["40 W", "80 W"] }', '{ normal = ["60 W"] }', "parameters.spindle_motor.power.normal",
     "a normal takes [mean, sd], got 1 value"),
    # a normal with (almost) none of its probability within the parameter's bounds [0 .. 5000 W]
    ('{ uniform = ["40 W", "80 W"] }', '{ normal = ["60 W", "1e300 W"] }', "parameters.spindle_motor.power.normal",
     "only 2e-297 of the normal's probability lies within the bounds"),
    ('mean = ["18 degC", "22 degC"]', 'mean = { normal = ["20 degC", "1e12 K"] }', "scenarios[0].ambient.mean.normal",
     "of the normal's probability lies within the bounds"),
    ('"spindle_motor.power"', '"spindle_motor.volume"', "parameters.spindle_motor.volume", "unknown parameter"),
    ('speed = ["2000 rpm", "9000 rpm"]', 'speed = ["2000 rpm", "12000 rpm"]', "scenarios[0].spindle.speed", "maximum"),
    ('duration = "10 min"', 'duration = "10 kg"', "scenarios[0].duration", "wrong unit"),
    ('duration = "10 min"', 'duration = "90 s"', "scenarios[0].duration", "multiple of the sample interval"),
    ('amplitude = ["0 K", "3 K"]', 'amplitude = ["0 K", "-3 K"]', "scenarios[0].ambient.amplitude", "reversed"),
    ('idle_probability = 0.3', 'idle_probability = 1.3', "scenarios[0].spindle.idle_probability", "from 0 to 1"),
    ('coldest_at = ["0 h", "24 h"]', 'coldest_at = ["-30 h", "24 h"]', "scenarios[0].ambient.coldest_at",
     "outside the bounds [0 h .. 24 h]"),
    ('[parameters]', 'effects = "+warp"\n[parameters]', "effects", "warp: unknown effect"),
    ('speed_step = "500 rpm"', 'speed_step = "50000 rpm"', "scenarios[0].spindle.speed_step", "no multiple"),
    ('file = "ref.toml"', 'file = "missing.toml"', "scenarios[1].file", "no scenario"),
    ('file = "ref.toml"', 'file = "no-such-scenario"', "scenarios[1].file", "no scenario"),
    ('cases = 2', 'cases = 0', "scenarios[0].cases", "from 1"),
    ('seed = 3', 'seed = 3\n[observers]\ncameras = ["nowhere"]', "observers.cameras[0]", "no camera pose"),
    ('seed = 3', 'seed = 3\n[observers]\nsurface_grid = { parts = ["roof"], spacing = "100 mm" }',
     "observers.surface_grid.parts[0]", "no part"),
    ('seed = 3', 'seed = 3\n[observers]\nsurface_grid = { parts = ["carrier"], spacing = "1 mm" }',
     "observers.surface_grid.spacing", "from 5 mm"),
    ('family = "duty"', 'family = "reference"', "scenarios[1].family", "named twice"),
    ("test = 0.5", "test = 0.4", "splits", "add up to"),
    ("seed = 3", "seed = -3", "seed", "outside"),
    # a misspelled key is named, not its correct sibling reported missing
    ('seed = 3', 'seed = 3\n[observers]\nsurface_grid = { parts = ["carrier"], spacng = "100 mm" }',
     "observers.surface_grid.spacng", "unknown key (known: parts, spacing)"),
    ('step = ["2 min", "5 min"]', 'stp = ["2 min", "5 min"]', "scenarios[0].spindle.stp", "unknown key (known: "),
    ('family = "duty"', 'famly = "duty"', "scenarios[0].famly", "unknown key (known: "),
    ('machines = ["cframe-vmc"]', 'machine = ["cframe-vmc"]', "machine", "unknown key (known: "),
    # values in the user's terms: a table where an array of tables belongs
    ('[scenarios.ambient]', '[scenarios.axis]\nname = "Y"\n[scenarios.ambient]', "scenarios[0].axis",
     "expected a list of tables ([[scenarios.axis]]), got a table ([scenarios.axis])"),
    ('mesh = "coarse"', 'mesh = true', "mesh", "expected a string, got the boolean true"),
    # a parameter of an effect that is off: the fix is the spec's effects key, not --effects
    ('"ambient_convection.h" = "7 W/m2K"', '"door_draft.h" = "7 W/m2K"', "parameters.door_draft.h",
     'is not switched on for machine cframe-vmc; switch it on with the spec\'s effects key: effects = "+door_draft"'),
    ('"ambient_convection.h" = "7 W/m2K"', '"belt_drive.power" = "50 W"', "parameters.belt_drive.power",
     "effect 'belt_drive' does not apply to machine cframe-vmc"),
    # a fixed room and drawn events in a generator family
    (DAILY, 'kind = "table"\ntimes = ["0 min", "5 min"]\ntemperatures = ["20 degC", "21 degC"]',
     "scenarios[0].ambient.times", "must cover the scenario's 0 to 0.166667 h"),
    (DAILY, 'kind = "table"\ntimes = ["0 min", "10 min"]\ntemperatures = ["20 degC", "21 degC"]\nfile = "r.csv"',
     "scenarios[0].ambient.file", "is not read by kind 'table'"),
    (DAILY, 'kind = "table"\ntimes = ["0 min", "10 min"]\ntemperatures = ["20 degC", "-300 degC"]',
     "scenarios[0].ambient.temperatures", "absolute zero"),
    (DAILY, 'kind = "sunny"', "scenarios[0].ambient.kind", "known for a generator: constant, daily, table, csv"),
    (DAILY, DAILY + '\n[[scenarios.ambient.events]]\nstart = ["1 min", "10 min"]\nchange = "-5 K"\nfall = "1 min"',
     "scenarios[0].ambient.events[0].start", "may fall at or after the end"),
    (DAILY, DAILY + '\n[[scenarios.ambient.events]]\nstart = "1 min"\nchange = "-5 kg"\nfall = "1 min"',
     "scenarios[0].ambient.events[0].change", "wrong unit"),
    (DAILY, DAILY + '\n[[scenarios.ambient.events]]\nstart = "1 min"\nchange = "-5 K"\nfal = "1 min"',
     "scenarios[0].ambient.events[0].fal", "unknown key"),
    (DAILY, DAILY + '\n[[scenarios.ambient.events]]\nstart = "1 min"\nchange = "-5 K"\nfall = "1 min"\ndoor = "yes"',
     "scenarios[0].ambient.events[0].door", "expected"),
    (DAILY, DAILY + ''.join('\n[[scenarios.ambient.events]]\nstart = "1 min"\nchange = "-30 K"\nfall = "1 min"'
                            for _ in range(2)), "scenarios[0].ambient.events", "outside the plausible room air"),
]


@pytest.mark.parametrize("old,new,field,message", BAD, ids=[b[2] + ":" + b[3] for b in BAD])
def test_a_bad_spec_is_one_clear_error_and_nothing_is_written(tmp_path, capsys, old, new, field, message):
    assert old in SPEC
    spec = write_spec(tmp_path, SPEC.replace(old, new, 1))
    out = tmp_path / "out"
    assert main(["dataset", str(spec), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {spec}: {field}: ") and message in err, err
    assert not out.exists()


def test_a_generator_room_from_a_csv_with_drawn_door_events(tmp_path, capsys):
    """``kind = "csv"`` in a generator: the record (relative to the spec) is the room of every case,
    held in the case as a table (the dataset does not depend on the file beside the spec); each
    event's start is drawn per case within its range; the draws repeat; a missing or short record
    is one error naming it and the field."""
    from twin.scenario import scenario_from_dict
    (tmp_path / "room.csv").write_text("time [min],air [degC]\n0,18\n5,21\n10,19\n", encoding="utf-8")
    room = ('kind = "csv"\nfile = "room.csv"\n[[scenarios.ambient.events]]\nstart = ["2 min", "8 min"]\n'
            'change = "-5 K"\nfall = "1 min"\nrecovery = "2 min"\ndoor = true')
    path = write_spec(tmp_path, SPEC.replace(DAILY, room))
    cases = [c for c in plan(load_spec(path)) if c.info["family"] == "duty"]
    assert [c.hash for c in cases] == [c.hash for c in plan(load_spec(path)) if c.info["family"] == "duty"]
    starts = []
    for c in cases:
        ambient = c.record["scenario"]["ambient"]
        assert ambient["kind"] == "table" and "file" not in ambient
        sc = scenario_from_dict(c.record["scenario"], "case")
        (event,) = sc.ambient.events
        assert event.door and event.change == -5.0 and 120.0 <= event.start <= 480.0
        assert sc.ambient.base([0.0, 300.0, 450.0]).tolist() == [18.0, 21.0, 20.0]
        starts.append(event.start)
    assert starts[0] != starts[1]
    for text, field, message in (("room.csv", "scenarios[0].ambient.file", "ends at 0.15 h, before"),
                                 ("none.csv", "scenarios[0].ambient.file", "no such")):
        (tmp_path / "room.csv").write_text("time [min],air [degC]\n0,18\n9,19\n", encoding="utf-8")
        spec = write_spec(tmp_path, SPEC.replace(DAILY, room.replace("room.csv", text)))
        assert main(["dataset", str(spec), "-o", str(tmp_path / "out")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f": {field}: " in err and message in err, err
        assert not (tmp_path / "out").exists()


def test_a_scenario_files_room_record_is_read_beside_it_and_held_by_the_case(tmp_path, monkeypatch):
    """A file family whose scenario reads ``ambient.file``: the record is found beside the scenario
    (not in the folder the command runs from, where a file of the same name must not be used)
    and the case holds its values as a table, so a changed record is a changed case (its hash)."""
    sub = tmp_path / "scenarios"
    sub.mkdir()
    (sub / "room.csv").write_text("time [h],air [degC]\n0,20\n1,21\n", encoding="utf-8")
    (sub / "ref.toml").write_text(REF.replace('kind = "constant"\ntemperature = "20 degC"',
                                              'kind = "csv"\nfile = "room.csv"'), encoding="utf-8")
    path = write_spec(tmp_path, SPEC.replace('file = "ref.toml"', 'file = "scenarios/ref.toml"'))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "room.csv").write_text("time [h],air [degC]\n0,30\n1,30\n", encoding="utf-8")
    monkeypatch.chdir(elsewhere)

    def reference():
        (case,) = [c for c in plan(load_spec(path)) if c.info["family"] == "reference"]
        return case
    first = reference()
    ambient = first.record["scenario"]["ambient"]
    assert ambient["kind"] == "table" and "file" not in ambient
    assert [float(v.split()[0]) for v in ambient["temperatures"]] == [20.0, 21.0]
    (sub / "room.csv").write_text("time [h],air [degC]\n0,20\n1,22\n", encoding="utf-8")
    assert reference().hash != first.hash


def test_an_effect_that_cannot_act_in_a_case_is_refused_by_the_plan(tmp_path, capsys):
    """A door draft whose first opening (1 h, its default) lies after a 10-min case would do
    nothing: the plan refuses it naming the spec file, the effect and the family, before any case
    is built or timed (it failed in the dry run's calibration as a 'command line' error)."""
    spec = write_spec(tmp_path, SPEC.replace('seed = 3', 'seed = 3\neffects = "+door_draft"'))
    out = tmp_path / "out"
    assert main(["dataset", str(spec), "-o", str(out), "--dry-run"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {spec}: effects: door_draft.start in scenarios[0] (family duty, draw 0): the "
                          "first opening at 1 h lies at or after the end of the run"), err
    assert err.count("\n") == 1 and not out.exists()


def test_a_calibration_of_a_few_steps_is_not_refused_what_the_whole_case_does(tmp_path):
    """The dry run's estimate times a few steps of a case (calibration_steps): a door draft opening
    at 8 min of a 20-min case acts in the case, not in 6 calibration steps, and is not refused
    there (it was: the truncated run was checked as a whole one)."""
    from twin.dataset import estimate
    text = SPEC.replace('seed = 3', 'seed = 3\neffects = "+door_draft"').replace('duration = "10 min"',
                                                                             'duration = "20 min"')
    text = text.replace('"ambient_convection.h" = "7 W/m2K"', '"ambient_convection.h" = "7 W/m2K"\n'
                        '"door_draft.start" = "8 min"')
    cases = [c for c in plan(load_spec(write_spec(tmp_path, text))) if c.info["family"] == "duty"]
    e = estimate(cases[:1], calibration_steps=6, length_steps=8)
    assert e["cases"] == 1 and e["steps"] == 20


def test_spec_errors_name_the_file_in_library_use():
    with pytest.raises(Exception, match=r"^x\.toml: machines: missing$"):
        spec_from_dict({"scenarios": []}, "x.toml")


def test_the_python_api_names_a_wrong_argument_before_any_work(tmp_path):
    """API audit: plan, estimate, write_index, executor, load_spec and spec_path given the wrong
    kind of thing raise one InputError naming it (they raised AttributeError or TypeError), and
    write_index refuses the cases of another spec and writes nothing when one of its four files
    cannot be written (index.csv was left alone before)."""
    from twin.dataset import estimate, executor, write_index
    from twin.dataset.runner import build_case
    from twin.dataset.spec import spec_path
    from twin.errors import InputError

    spec = load_spec(write_spec(tmp_path))
    other = load_spec(write_spec(tmp_path, SPEC.replace("seed = 3", "seed = 4")))
    out = tmp_path / "out"
    out.mkdir()
    (out / "index.parquet").mkdir()
    for call, field in ((lambda: plan(None), "spec"), (lambda: plan(str(tmp_path / "tiny.toml")), "spec"),
                        (lambda: estimate(None), "cases"), (lambda: estimate(spec), "cases"),
                        (lambda: write_index(None, [], out), "spec"),
                        (lambda: write_index(spec, plan(other), out), "cases"),
                        (lambda: write_index(spec, plan(spec), out), "index"),
                        (lambda: executor(5), "--scheduler"), (lambda: load_spec(None), "spec"),
                        (lambda: spec_path(5), "spec"),
                        (lambda: build_case(plan(spec)[0].record, plan(spec)[0].hash, 5), "folder"),
                        (lambda: build_case(plan(spec)[0].record, plan(spec)[0].hash, tmp_path / "none"), "folder")):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == field, str(err.value)
    assert sorted(p.name for p in out.iterdir()) == ["index.parquet"]


def test_a_changed_case_record_is_named_not_a_key_error(tmp_path):
    """API audit: a record whose machine is unknown raised KeyError from the machine registry, and
    ``max_steps=0`` blamed the scenario's spindle steps."""
    from twin.dataset.runner import simulate_case
    from twin.errors import InputError

    record = plan(load_spec(write_spec(tmp_path)))[0].record
    for bad, field in (({**record, "machine": "nope"}, "machine"), ({k: v for k, v in record.items() if k != "mesh"},
                                                                     "mesh"), ("x", "record")):
        with pytest.raises(InputError) as err:
            simulate_case(bad)
        assert err.value.field == field, str(err.value)
    for steps in (0, -1, 2.5):
        with pytest.raises(InputError) as err:
            simulate_case(record, max_steps=steps)
        assert err.value.field == "max_steps"
    with pytest.raises(InputError) as err:
        spec_from_dict({"machines": [["cframe-vmc"]], "scenarios": []}, "x.toml")
    assert err.value.field == "machines[0]"


def test_each_distribution_draws_what_its_name_says():
    """A spec's draws, 20 000 each from one seeded generator (so the test is deterministic): uniform
    (5, 12) fills the range with mean (lo + hi) / 2; log-uniform (5, 12) has log-values uniform on
    [ln 5, ln 12], so its median is the geometric mean sqrt(5 x 12) = 7.746, not 8.5; a normal
    (20, 2) truncated to [17, 21] stays inside with the truncated mean
    mu + sigma (phi(a) - phi(b)) / (Phi(b) - Phi(a)), a = -1.5, b = 0.5 (= 19.246); fixed is its
    value. Tolerances: 4 standard errors of each statistic."""
    from scipy.stats import norm, truncnorm

    from twin.dataset.fields import Dist
    rng = np.random.default_rng(5)
    n = 20_000
    u = np.array([Dist("uniform", (5.0, 12.0), "heat_transfer_coefficient").sample(rng) for _ in range(n)])
    assert 5.0 <= u.min() and u.max() <= 12.0
    assert abs(u.mean() - 8.5) < 4 * 7.0 / np.sqrt(12 * n)
    g = np.array([Dist("log_uniform", (5.0, 12.0), "heat_transfer_coefficient").sample(rng) for _ in range(n)])
    width = np.log(12.0 / 5.0)
    assert 5.0 <= g.min() and g.max() <= 12.0
    assert abs(np.log(np.median(g)) - 0.5 * np.log(60.0)) < 4 * width / (2 * np.sqrt(n))
    assert abs(np.log(g).std() - width / np.sqrt(12)) < 4 * width / np.sqrt(12) / np.sqrt(2 * n)
    t = np.array([Dist("normal", (20.0, 2.0), "temperature", 17.0, 21.0).sample(rng) for _ in range(n)])
    a, b = -1.5, 0.5
    mean = 20.0 + 2.0 * (norm.pdf(a) - norm.pdf(b)) / (norm.cdf(b) - norm.cdf(a))
    assert mean == pytest.approx(truncnorm(a, b, loc=20.0, scale=2.0).mean(), rel=1e-12)
    assert 17.0 <= t.min() and t.max() <= 21.0
    assert abs(t.mean() - mean) < 4 * truncnorm(a, b, loc=20.0, scale=2.0).std() / np.sqrt(n)
    assert Dist("fixed", (7.0,), "power").sample(rng) == 7.0


def test_a_normal_is_drawn_exactly_from_its_truncation(tmp_path):
    """A normal is truncated to its bounds by the inverse CDF at one uniform a draw (no redrawing):
    x = mu + sigma Phi^-1(Phi(a) + u (Phi(b) - Phi(a))), here against scipy's truncnorm.ppf (to
    1e-12 sigma; far in either tail too, through the mirrored bounds), and a normal whose sd dwarfs
    the bounds (1e7 W on spindle_motor.power's [0 .. 5000 W]: 2e-4 of it inside, where redrawing
    ran out of tries now and then) plans every time, each draw inside, the same on every plan."""
    from scipy.stats import norm, truncnorm

    from twin.dataset.fields import Dist, normal_mass, truncated_normal
    for mean, sd, lo, hi in [(20.0, 2.0, 17.0, 21.0), (60.0, 1e7, 0.0, 5000.0), (0.0, 1.0, 8.0, 9.0),
                             (0.0, 1.0, -9.0, -8.0), (0.0, 1.0, -40.0, 40.0), (5.0, 1.0, 5.0, 5.001),
                             (1.0, 3.0, -np.inf, 2.0), (1.0, 3.0, 0.5, np.inf)]:
        a, b = (lo - mean) / sd, (hi - mean) / sd
        mass = norm.sf(a) - norm.sf(b) if a >= 0 else norm.cdf(b) - norm.cdf(a)   # each in its accurate tail
        assert normal_mass(mean, sd, lo, hi) == pytest.approx(mass, rel=1e-9)
        for u in (0.0, 2.0**-40, 0.25, 0.5, 0.875, 1.0 - 2.0**-40, 1.0 - 2.0**-53):   # 1 - u exact
            x = truncated_normal(mean, sd, lo, hi, u)
            assert lo <= x <= hi and np.isfinite(x)    # u = 0 on an open lower end: finite, far down the tail
            # the upper half through the mirrored normal (scipy's ppf loses 1 - u there)
            assert -truncated_normal(-mean, sd, -hi, -lo, 1.0 - u) == pytest.approx(x, abs=1e-12 * sd, rel=1e-12)
            if u <= 0.875:
                want = truncnorm.ppf(u, a, b, loc=mean, scale=sd)
                assert x == pytest.approx(want, abs=1e-12 * sd, rel=1e-12) or (u == 0.0 and want == -np.inf)
    # one uniform a draw, whatever the bounds: the next draw of the generator is where it would be
    wide = Dist("normal", (60.0, 1e7), "power", 0.0, 5000.0)
    r, s = np.random.default_rng(9), np.random.default_rng(9)
    for _ in range(1000):
        assert 0.0 <= wide.sample(r) <= 5000.0
        s.uniform()
    assert r.uniform() == s.uniform()
    text = SPEC.replace('{ uniform = ["40 W", "80 W"] }', '{ normal = ["60 W", "1e7 W"] }').replace("cases = 2",
                                                                                                 "cases = 50")
    a, b = plan(load_spec(write_spec(tmp_path, text))), plan(load_spec(write_spec(tmp_path, text)))
    drawn = [c.info["spindle_motor.power [W]"] for c in a]
    assert drawn == [c.info["spindle_motor.power [W]"] for c in b] and [c.hash for c in a] == [c.hash for c in b]
    assert len(drawn) == 51 and all(0.0 <= x <= 5000.0 for x in drawn) and len(set(drawn)) == 51


def test_split_counts_are_rounded_fractions_of_each_family(tmp_path):
    """assign_splits: the first round(fraction n) ranked cases of a family go to the first split.
    Splits 0.6 / 0.4 over 3 draws: round(0.6 x 3) = round(1.8) = 2 train, 3 - 2 = 1 test
    (floor would give 1 train, 2 test); the 1-case reference family: round(0.6) = 1 train."""
    text = SPEC.replace("cases = 2", "cases = 3").replace("train = 0.5\ntest = 0.5", "train = 0.6\ntest = 0.4")
    cases = plan(load_spec(write_spec(tmp_path, text)))
    duty = [c.split for c in cases if c.info["family"] == "duty"]
    assert len(duty) == 3
    n_train = int(np.floor(0.6 * 3 + 0.5))
    assert n_train == 2
    assert duty.count("train") == n_train and duty.count("test") == 3 - n_train
    assert [c.split for c in cases if c.info["family"] == "reference"] == ["train"]


def test_each_draw_of_a_family_has_its_own_noise_seed(tmp_path):
    """Module docstring: the instrument-noise seed is drawn with key (f, i, "noise"), so draws 0
    and 1 of one family get different seeds, and the record's seed is the index's seed."""
    cases = plan(load_spec(write_spec(tmp_path)))
    duty = [c for c in cases if c.info["family"] == "duty"]
    assert [c.info["draw"] for c in duty] == [0, 1]
    assert duty[0].info["seed"] != duty[1].info["seed"]
    assert all(c.record["seed"] == c.info["seed"] for c in duty)


def test_the_split_key_includes_the_machine(tmp_path):
    """Split rank key (f, i, machine, grid point, "split"): with two machines and 20 draws, the
    split vectors of the two machines over the draws differ (with the machine left out of the key
    both machines would get identical vectors); each machine's vector is a fixed function of its key."""
    text = (SPEC.replace('machines = ["cframe-vmc"]', 'machines = ["cframe-vmc", "belt-vmc"]')
            .replace("cases = 2", "cases = 20").replace('"9000 rpm"]', '"8000 rpm"]'))
    cases = plan(load_spec(write_spec(tmp_path, text)))
    vec = {m: [c.split for c in sorted((c for c in cases if c.info["family"] == "duty" and c.info["machine"] == m),
                                       key=lambda c: c.info["draw"])]
           for m in ("cframe-vmc", "belt-vmc")}
    assert len(vec["cframe-vmc"]) == len(vec["belt-vmc"]) == 20
    assert vec["cframe-vmc"] != vec["belt-vmc"]
    duty = [c.split for c in cases if c.info["family"] == "duty"]
    assert duty.count("train") == duty.count("test") == 20   # round(0.5 x 40) per family


def test_scenario_summary_is_weighted_by_duration(tmp_path):
    """A case's index row: mean_speed = sum_k d_k v_k / sum_k d_k and running_fraction =
    sum_{v_k > 0} d_k / sum_k d_k. Steps 600 s at 1000 rpm then 1800 s at 0 rpm:
    mean = 600 x 1000 / 2400 = 250 rpm (not the step mean 500), running = 600 / 2400 = 0.25
    (not 1 of 2 steps = 0.5)."""
    path = write_spec(tmp_path)
    (tmp_path / "ref.toml").write_text(REF.replace(
        '[[spindle]]\nspeed = "6000 rpm"\nduration = "10 min"',
        '[[spindle]]\nspeed = "1000 rpm"\nduration = "600 s"\n[[spindle]]\nspeed = "0 rpm"\nduration = "1800 s"'))
    (case,) = [c for c in plan(load_spec(path)) if c.info["family"] == "reference"]
    d, v = np.array([600.0, 1800.0]), np.array([1000.0, 0.0])
    assert case.info["steps"] == 2 and case.info["duration [s]"] == pytest.approx(2400.0)
    assert case.info["mean_speed [rpm]"] == pytest.approx(np.sum(d * v) / np.sum(d), rel=1e-12)
    assert case.info["mean_speed [rpm]"] == pytest.approx(250.0, rel=1e-12)
    assert case.info["running_fraction"] == pytest.approx(0.25, rel=1e-12)
    assert case.info["max_speed [rpm]"] == pytest.approx(1000.0, rel=1e-12)


def test_a_full_disk_while_the_index_is_written_leaves_the_old_set(tmp_path, monkeypatch):
    """write_index's four files (index.csv, index.parquet, card.json, README.md) belong together:
    a disk that fills after the third leaves the set written before, byte for byte, with no new
    file beside it (each went to its temporary file; all four are renamed only when all are whole).
    Before, index.csv and index.parquet were replaced and the card kept describing the old ones."""
    from twin.dataset import write_index
    from twin.errors import InputError
    from twin.io import atomic

    spec = load_spec(write_spec(tmp_path))
    out = tmp_path / "out"
    out.mkdir()
    write_index(spec, plan(spec)[:1], out)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    free = iter([10 ** 12, 10 ** 12, 10])              # index.csv and .parquet fit, card.json fills the disk
    monkeypatch.setattr(atomic, "free_space", lambda folder: next(free))
    with pytest.raises(InputError, match="the disk is full") as err:
        write_index(spec, plan(spec), out)
    assert err.value.source.endswith("card.json")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
