"""``twin dataset``: one file per case, index and card, resume after an interrupt, the pool and
Dask giving identical files, learners on the dataset's runs (issue 14).

Everything runs on the coarse C-frame mesh with 10-minute scenarios sampled once a minute (a
case takes well under a second; the spec is :mod:`tests.dataset_files`'s; its checks and the plan
are in ``tests/test_dataset_plan.py``)."""

from __future__ import annotations

import json
import shutil

import pandas as pd
import pytest
import xarray as xr

from tests.dataset_files import REF, SPEC, assert_same_cases, fake_estimate_clock, write_spec
from twin.cli import main
from twin.dataset import build, executor, is_whole, load_spec, plan, write_index


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The tiny dataset built in this process: (spec path, dataset folder, cases)."""
    root = tmp_path_factory.mktemp("ds")
    spec_path = write_spec(root)
    spec = load_spec(spec_path)
    cases = plan(spec)
    out = root / "out"
    out.mkdir()
    build(cases, out)
    write_index(spec, cases, out)
    return spec_path, out, cases


# --- building ------------------------------------------------------------------------------------

def test_one_whole_file_per_case_index_and_card_agree(built):
    spec_path, out, cases = built
    files = sorted(p.name for p in (out / "cases").iterdir())
    assert files == sorted(c.file for c in cases)
    index = pd.read_csv(out / "index.csv")
    parquet = pd.read_parquet(out / "index.parquet")
    pd.testing.assert_frame_equal(index, parquet, check_dtype=False)
    assert list(index["hash"]) == [c.hash for c in cases] and index["built"].all()
    for row in index.itertuples():
        with xr.open_dataset(out / row.file, engine="h5netcdf") as ds:
            assert ds.attrs["case_hash"] == row.hash and str(ds["case"].values) == row.hash
            assert ds.attrs["seed"] == row.seed and ds.attrs["dataset_family"] == row.family
    card = json.loads((out / "card.json").read_text())
    assert card["counts"]["planned"] == card["counts"]["built"] == 3
    assert card["spec"] == spec_path.read_text() and card["package_version"]
    roles = {s["name"]: s["role"] for s in card["schema"]}
    assert roles["drift"] == "truth" and roles["temperature"] == "measured" and roles["spindle_speed"] == "input"
    units = {s["name"]: s["units"] for s in card["schema"]}
    assert units["drift"] == "um" and units["temperature"] == "degC"
    readme = (out / "README.md").read_text()
    assert "# Dataset tiny" in readme and "| drift |" in readme and "```toml" in readme
    assert card["solver_error"] == {} and "None reported" in readme      # the direct solver: exact


def test_open_mfdataset_reads_every_case(built):
    _, out, cases = built
    with xr.open_mfdataset(str(out / "cases" / "*.nc"), combine="nested", concat_dim="case",
                           engine="h5netcdf") as ds:
        assert ds.sizes["case"] == len(cases) and set(ds["case"].values) == {c.hash for c in cases}
        assert ds["drift"].dims == ("case", "time", "axis")


def test_a_rerun_skips_finished_cases(built):
    _, out, cases = built
    before = {p: p.stat().st_mtime_ns for p in (out / "cases").iterdir()}
    assert build(cases, out) == {}
    assert {p: p.stat().st_mtime_ns for p in (out / "cases").iterdir()} == before


def test_a_killed_and_resumed_run_equals_an_uninterrupted_one(built, tmp_path):
    _, reference, cases = built
    out = tmp_path / "out"
    out.mkdir()

    def stop_after_first(done, total):
        if done == 1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        build(cases, out, progress=stop_after_first)
    left = list((out / "cases").iterdir())
    assert len(left) == 1 and is_whole(left[0], left[0].stem)      # whole files only, no temporary
    (out / "cases" / ".twin-k3x9_q2a.nc").write_bytes(b"half")     # what a SIGKILL could leave
    (out / "cases" / ".twin-notes.toml").write_text("a user's file")  # not ours: kept (an input, perhaps)
    (out / "cases" / cases[1].file).write_bytes(b"not a netcdf")   # a corrupt file is rebuilt
    assert len(build(cases, out)) == 2
    assert not (out / "cases" / ".twin-k3x9_q2a.nc").exists()
    assert (out / "cases" / ".twin-notes.toml").read_text() == "a user's file"
    (out / "cases" / ".twin-notes.toml").unlink()
    assert_same_cases(out, reference)


def test_the_pool_and_dask_write_identical_files(built, tmp_path):
    _, reference, cases = built
    for name, scheduler, jobs in (("pool", None, 2), ("dask", "local-threads", 1)):
        out = tmp_path / name
        out.mkdir()
        with executor(scheduler, jobs) as pool:
            assert len(build(cases, out, pool)) == len(cases)
        assert_same_cases(out, reference, name)


# --- the command ---------------------------------------------------------------------------------

def test_dry_run_prints_the_plan_and_writes_nothing(built, tmp_path, capsys):
    spec_path, _, _ = built
    out = tmp_path / "new"
    assert main(["dataset", str(spec_path), "-o", str(out), "--dry-run", "--jobs", "1"]) == 0
    text = capsys.readouterr().out
    assert "3 case(s) planned" in text and "estimated time:" in text and "per step" in text
    assert not out.exists()


def test_a_scheduler_that_is_no_address_or_cannot_be_reached_is_refused(built, tmp_path, capsys, monkeypatch):
    """`--scheduler` is 'local', 'local-threads' or [protocol://]host:port, checked before anything
    runs (a dry run too); an address nobody answers is one error on --scheduler, not a traceback."""
    import twin.dataset.runner as runner

    spec_path, _, _ = built
    out = tmp_path / "new"
    for bad in ("bogus", "tcp://host", "http://host:8786"):
        assert main(["dataset", str(spec_path), "-o", str(out), "--dry-run", "--scheduler", bad]) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: command line: --scheduler:") and "Traceback" not in err
    runner.check_scheduler("tcp://10.0.0.5:8786")
    runner.check_scheduler("scheduler-host:8786")
    monkeypatch.setattr(runner, "CONNECT_TIMEOUT", "1s")
    assert main(["dataset", str(spec_path), "-o", str(out), "--jobs", "1", "--scheduler", "tcp://127.0.0.1:9"]) == 2
    assert "cannot reach the Dask scheduler" in capsys.readouterr().err
    assert not out.exists()


def test_max_cases_then_the_rest_and_a_changed_spec(built, tmp_path, capsys):
    spec_path, reference, cases = built
    root = tmp_path
    spec = write_spec(root)
    out = root / "out"
    assert main(["dataset", str(spec), "-o", str(out), "--max-cases", "1", "--jobs", "1"]) == 0
    index = pd.read_csv(out / "index.csv")
    assert list(index["built"]) == [True, False, False]
    assert main(["dataset", str(spec), "-o", str(out), "--jobs", "1"]) == 0
    assert "built 2 case(s)" in capsys.readouterr().out
    assert_same_cases(out, reference)
    # the reference family's scenario changes: one case is new, its old file is stale
    (root / "ref.toml").write_text(REF.replace("6000 rpm", "7000 rpm"))
    spec.write_text(SPEC)
    assert main(["dataset", str(spec), "-o", str(out), "--jobs", "1"]) == 0
    text = capsys.readouterr().out
    assert "built 1 case(s)" in text and "2 already there" in text and "1 case file(s) from an earlier spec kept" in text
    mine = out / "cases" / "mine.nc"             # a user's file among the cases: never pruned
    shutil.copy(next((out / "cases").glob("*.nc")), mine)
    assert main(["dataset", str(spec), "-o", str(out), "--jobs", "1", "--prune"]) == 0
    text = capsys.readouterr().out
    assert "1 case file(s) from an earlier spec removed" in text and "1 other file(s)" in text and "mine.nc" in text
    assert len(list((out / "cases").glob("*.nc"))) == 4 and mine.is_file()


def test_the_output_folder_never_replaces_the_spec(tmp_path, capsys):
    spec = write_spec(tmp_path)
    shutil.copy(spec, tmp_path / "index.csv")
    assert main(["dataset", str(tmp_path / "index.csv"), "-o", str(tmp_path), "--dry-run"]) == 2
    # nor a scenario file a family reads, named by its family's place in the spec
    (tmp_path / "out").mkdir()
    shutil.copy(tmp_path / "ref.toml", tmp_path / "out" / "index.csv")
    text = SPEC.replace('file = "ref.toml"', 'file = "out/index.csv"')
    capsys.readouterr()
    assert main(["dataset", str(write_spec(tmp_path, text)), "-o", str(tmp_path / "out")]) == 2
    assert "scenarios[1].file" in capsys.readouterr().err


def test_a_folder_with_a_users_own_readme_is_refused_and_a_dataset_folder_is_not(built, tmp_path, capsys):
    """``twin dataset SPEC -o .`` replaced a user's own README.md (not an input, so no clash):
    an index or card file in the folder must be a dataset's, with its card.json beside it."""
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "README.md").write_text("my notes\n", encoding="utf-8")
    assert main(["dataset", str(write_spec(tmp_path)), "-o", str(folder), "--max-cases", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "README.md: -o: exists and is not a twin dataset's" in err
    assert (folder / "README.md").read_text(encoding="utf-8") == "my notes\n" and not (folder / "cases").exists()
    (folder / "card.json").write_text("[1, 2]", encoding="utf-8")          # a JSON file, not a card
    assert main(["dataset", str(write_spec(tmp_path)), "-o", str(folder), "--dry-run"]) == 2
    capsys.readouterr()
    spec_path, dataset, _ = built            # an earlier build of the dataset: its files are ours to rewrite
    assert main(["dataset", str(spec_path), "-o", str(dataset), "--dry-run"]) == 0


def test_reduced_model_cases_are_identical_and_carry_no_wall_times(tmp_path):
    spec = load_spec(write_spec(tmp_path, SPEC.replace('seed = 3', 'seed = 3\nsolver = "rom"')))
    case = plan(spec)[:1]
    for name in ("a", "b"):
        out = tmp_path / name
        out.mkdir()
        build(case, out)
    assert_same_cases(tmp_path / "b", tmp_path / "a")
    with xr.open_dataset(tmp_path / "a" / "cases" / case[0].file, engine="h5netcdf") as ds:
        assert ds.attrs["solver"] == "rom" and "rom_offline_s" not in ds.attrs
        estimate = json.loads(ds.attrs["rom_error_estimate"])
    # the card reports the reduced model's error: the largest per group, drift in um, temperature in K
    write_index(spec, case, tmp_path / "a")
    reported = json.loads((tmp_path / "a" / "card.json").read_text())["solver_error"]
    assert reported["rom_error_estimate"]["drift"] == {"max": pytest.approx(1e6 * max(estimate["drift"]), rel=1e-12),
                                                       "units": "um"}
    assert reported["rom_error_estimate"]["temperature"]["max"] == pytest.approx(max(estimate["temperature"]))
    assert reported["rom_error_bound"]["temperature"]["max"] >= reported["rom_error_estimate"]["temperature"]["max"]
    assert "rom_error_bound" in (tmp_path / "a" / "README.md").read_text()


def test_reduced_model_cases_do_not_depend_on_the_case_a_worker_ran_before(tmp_path):
    """A worker keeps its prepared twin, and the reduced basis is built from the film coefficients
    of the run that first needs it: each case builds its own, so a case's bytes do not depend on
    the order its worker met the cases in (--jobs 1 and --jobs 2 gave different files before)."""
    from twin.dataset import runner
    spec = load_spec(write_spec(tmp_path, SPEC.replace('seed = 3', 'seed = 3\nsolver = "rom"')))
    cases = plan(spec)[:2]
    for name, order in (("a", cases), ("b", cases[::-1])):
        runner._local.__dict__.pop("twins", None)      # a fresh worker
        out = tmp_path / name
        out.mkdir()
        build(order, out)
    assert_same_cases(tmp_path / "b", tmp_path / "a")


def test_the_bundled_example_plans_100_cases():
    from twin.scenario import SCENARIO_DIR

    spec = load_spec(SCENARIO_DIR / "datasets" / "spindle-ambient-100.toml")
    cases = plan(spec)
    assert len(cases) == 100 and {c.split for c in cases} == {"train", "validation", "test"}


def test_the_estimate_spreads_a_cases_own_set_up_over_a_cases_length(monkeypatch):
    """The dry run times the first case cut to 600 steps (20 x 30, or the whole case when
    shorter) after a 30-step warm-up: on a clock where preparing takes 2 s and a run of n steps
    0.3 s + n 2 ms (the reduced model's own basis per case, then the steps), the rate is
    t(n) / n = (0.3 + 0.002 n) / n, the plan costs prepare + rate sum_c n_c / workers, and the
    preparation is the time before the timed run less the warm-up's 30 steps at that rate. (Timed
    over 30 steps alone, the rate was 12 ms here: the 100-case example was estimated 3-5 times
    too slow.)"""
    from twin.scenario import SCENARIO_DIR

    E, _ = fake_estimate_clock(monkeypatch)
    cases = plan(load_spec(SCENARIO_DIR / "datasets" / "spindle-ambient-100.toml"))[:7]
    steps = [E._steps(c) for c in cases]
    n = min(600, steps[0])
    rate = (0.3 + 0.002 * n) / n
    e = E.estimate(cases, jobs=2)
    (key,) = e["per_step_s"]
    assert e["per_step_s"][key] == pytest.approx(rate, rel=1e-12)
    prepare = 2.0 + 0.3 + 0.002 * 30 - 30 * rate
    assert e["prepare_s"] == pytest.approx(prepare, rel=1e-12)
    assert e["steps"] == sum(steps)
    assert e["seconds"] == pytest.approx(prepare + rate * sum(steps) / 2, rel=1e-12)
    # two workers on one core take as long as one: the steps share min(jobs, cores) lanes
    one_core = E.estimate(cases, jobs=2, cores=1)
    assert one_core["seconds"] == pytest.approx(one_core["prepare_s"] + rate * sum(steps), rel=1e-12)
    assert E.estimate(cases, jobs=2, cores=8)["seconds"] == pytest.approx(e["seconds"], rel=1e-12)


# --- learners on many runs -----------------------------------------------------------------------

def test_learn_trains_on_several_runs_and_on_a_dataset_split(built, capsys):
    _, out, cases = built
    files = [str(out / "cases" / c.file) for c in cases]
    common = ["--target", "drift:Z", "--select", "correlation:2", "--learner", "mlr,gm1n,ar-temp"]
    assert main(["learn", "--train", files[0], "--train", files[1], "--test", files[2], *common]) == 0
    text = capsys.readouterr().out
    assert all(name in text for name in ("mlr", "gm1n", "ar-temp"))
    scores = out.parent / "scores.csv"
    assert main(["learn", "--dataset", str(out), "--split", "test", "--segments", "2", "-o", str(scores), *common]) == 0
    n_test = sum(c.split == "test" for c in cases)
    assert f"[test: {n_test} runs]" in capsys.readouterr().out
    board = pd.read_csv(scores)
    assert len(board) == 3 * 3 and board["test"].str.endswith("[segment 2/2]").sum() == 3
    assert (board["p95_abs_residual"] <= board["max_abs_residual"] + 1e-12).all() and (board["unit"] == "um").all()
    assert "fit_time_s" not in board      # wall clock is shown, not written: the same inputs give the same file
    # every time-ordered learner now trains on several runs, each its own sequence
    assert main(["learn", "--train", files[0], "--train", files[1], "--test", files[2], "--target", "drift:Z",
                 "--select", "correlation:2", "--learner", "gm11,gmc1n,combination"]) == 0
    text = capsys.readouterr().out
    assert all(name in text for name in ("gm11", "gmc1n", "combination")), text
    assert main(["learn", "--dataset", str(out), "--split", "nope", *common]) == 2
    assert "no split 'nope'" in capsys.readouterr().err
    index = out / "index.csv"       # a file given as the dataset is named as one, not as a missing index
    assert main(["learn", "--dataset", str(index), "--split", "test", *common]) == 2
    assert capsys.readouterr().err.startswith(f"error: {index}: --dataset: is a file, not a dataset folder")


def test_learn_writes_the_leaderboard_as_markdown(built, capsys):
    _, out, _ = built
    board = out.parent / "board.md"
    assert main(["learn", "--dataset", str(out), "--split", "test", "--target", "drift:Z", "--learner", "mlr,gm1n",
                 "--inputs", "motor,spindle_boss,test_bar", "--interval", "2 min", "--segments", "2",
                 "-o", str(board)]) == 0
    text = board.read_text()
    assert text.startswith("# twin learn: drift:Z") and "thinned to 2 min" in text and "[segment 2/2]" in text
    assert "| gm1n |" in text and "| mlr |" in text


def test_learn_never_writes_over_the_dataset_index_and_refuses_repeated_inputs(built, capsys):
    """The dataset's index.csv is an input of `twin learn --dataset`: `-o DIR/index.csv` (as any
    path in the dataset's folder) is refused (exit 2) and the index is unchanged; `--inputs T1,T1`
    names one input twice and is refused."""
    _, out, _ = built
    index = out / "index.csv"
    before = index.read_bytes()
    common = ["--dataset", str(out), "--split", "test", "--target", "drift:Z", "--learner", "mlr"]
    assert main(["learn", *common, "-o", str(index)]) == 2
    assert "lies in the input dataset" in capsys.readouterr().err and index.read_bytes() == before
    assert main(["learn", *common, "--inputs", "motor,motor"]) == 2
    assert "motor given more than once" in capsys.readouterr().err


def test_the_dataset_study_writes_a_leaderboard_and_a_placement_benchmark(built, tmp_path):
    """The exhaustive set is the least-squares optimum over all sets, so mlr (least squares with
    an intercept) scores no set better than it (to round-off)."""
    from validate.studies import dataset_learners

    _, out, _ = built
    res = tmp_path / "study"
    assert dataset_learners.main([str(out), "-o", str(res), "--learners", "mlr,gm1n", "--select", "correlation:2",
                                  "--n-random", "3", "--segments", "2"]) == 0
    board = pd.read_csv(res / "leaderboard.csv")
    assert set(board["learner"]) == {"mlr", "gm1n"} and board["test"].str.contains("segment 2/2").any()
    placement = pd.read_csv(res / "placement.csv")
    mlr = placement[placement["learner"] == "mlr"].set_index("set")
    assert {"selected: gm0n-fcm", "intuitive", "random", "truth-greedy", "truth-exhaustive"} <= set(mlr.index)
    assert (mlr.loc["truth-exhaustive", "rmse"] <= mlr["rmse_min"] + 1e-9).all()
    # results carry units: both tables name the target's unit in their rows (drift: um)
    assert set(placement["unit"]) == set(board["unit"]) == {"um"}
    assert "| test RMSE um |" in (res / "placement.md").read_text()
    assert "truth-exhaustive" in (res / "placement.md").read_text()
    assert dataset_learners.main([str(out), "-o", str(res), "--split", "nope"]) == 2


def test_gm1n_on_two_runs_sees_each_runs_own_sequence():
    """Two runs generated by GM(1,N)'s own difference equation (closed form: the model reproduces
    its own data exactly, learners.grey): fitted as runs, a and b come back; stacked as one
    sequence they do not (the jump between the runs is no step in time)."""
    import numpy as np

    from learners.grey import GM1N, ago, gm1n_simulate

    rng = np.random.default_rng(0)
    runs = []
    for _ in range(2):
        X = np.cumsum(rng.uniform(0.0, 0.2, (60, 2)), axis=0)
        runs.append((X, gm1n_simulate(0.08, np.array([0.3, -0.1]), ago(X), 0.0)))
    fitted = GM1N().fit_runs(runs)
    assert fitted.a_ == pytest.approx(0.08, rel=1e-4) and np.allclose(fitted.b_, [0.3, -0.1], rtol=1e-4)
    stacked = GM1N().fit(np.vstack([r[0] for r in runs]), np.concatenate([r[1] for r in runs]))
    assert abs(stacked.a_ - 0.08) > 1e-3


def test_ar_temp_runs_take_no_lag_pair_across_a_run_boundary():
    import numpy as np

    from learners.ar_temp import ARTemp

    rng = np.random.default_rng(1)
    X = rng.normal(size=(40, 2))
    y = X @ [1.0, -2.0] + rng.normal(size=40)
    one, same = ARTemp().fit(X, y), ARTemp().fit_runs([(X, y)])
    assert one.phi_ == same.phi_ and np.array_equal(one.coef_, same.coef_)
    two = ARTemp().fit_runs([(X[:20], y[:20]), (X[20:], y[20:])])
    r = y - two.intercept_ - X @ two.coef_
    rc = r - r.mean()
    within = (rc[1:20] @ rc[:19] + rc[21:] @ rc[20:39]) / (rc @ rc)
    assert two.phi_ == pytest.approx(within) and np.allclose(two.coef_, one.coef_)


def test_a_surface_grid_adds_dense_virtual_sensors(tmp_path):
    text = SPEC.replace("seed = 3", 'seed = 3\n[observers]\nsurface_grid = { parts = ["carrier"], spacing = "200 mm" }')
    spec = load_spec(write_spec(tmp_path, text))
    case = plan(spec)[:1]
    build(case, tmp_path)
    with xr.open_dataset(tmp_path / "cases" / case[0].file, engine="h5netcdf") as ds:
        names = [str(n) for n in ds["sensor"].values]
    assert len(names) > 16 and any(n.startswith("carrier:") for n in names)
