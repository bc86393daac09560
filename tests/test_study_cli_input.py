"""Bad input to the module command lines ``python -m validate.benchmark``, ``python -m
validate.camera_benchmark`` and ``python -m validate.studies.<name>``: as in the twin CLI (README
"Errors"), one line ``error: <source>: <field>: <message>`` on stderr, exit code 2, no traceback,
found before any output folder is made or any run starts. Every case here fails while the options
are checked: no study or benchmark runs."""

from __future__ import annotations

import numpy as np
import pytest

from validate import benchmark, camera_benchmark
from validate.studies import (axis_pose, dataset_learners, diagnosis_signals, etve_protocol, feed_signatures,
                              gantry_gnnmci, gantry_tests, gantry_z_variants, heat_step, hidden_effect,
                              machine_b_anfis, machine_b_gra, seed001, seed003)


def one_error(capsys, *needles) -> str:
    """The one ``error:`` line on stderr, holding every needle."""
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in lines[0], err
    return lines[0]


@pytest.fixture
def fast_scenario(tmp_path):
    """The seeds' heat-cool test at 30000 rpm, beyond cframe-vmc's 9000 rpm."""
    from twin.scenario import scenario_path

    text = scenario_path("spindle-heat-cool-9000").read_text().replace("9000 rpm", "30000 rpm")
    path = tmp_path / "fast.toml"
    path.write_text(text)
    return path


# 4 ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("study", [gantry_tests, gantry_z_variants, gantry_gnnmci, machine_b_gra, machine_b_anfis])
def test_studies_without_a_camera_do_not_offer_camera(study, tmp_path, capsys):
    out = tmp_path / "out"
    assert study.main(["--quick", "--camera", "bogus", "-o", str(out)]) == 2
    one_error(capsys, "unrecognized arguments: --camera")
    assert not out.exists()


def test_a_camera_study_checks_the_pose_before_anything_is_written(tmp_path, capsys):
    out = tmp_path / "out"
    assert seed001.main(["--quick", "--camera", "bogus", "-o", str(out)]) == 2
    one_error(capsys, "command line: --camera: ", "no camera pose 'bogus'")
    assert seed001.main(["--quick", "--camera", "overview-front", "-o", str(out)]) == 2   # aimed at no part: no spots
    one_error(capsys, "--camera: ", "aimed at no part")
    assert not out.exists()


# 5 ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("spacing", ["-100mm", "0mm"])
def test_benchmark_refuses_a_spacing_that_is_not_positive(spacing, capsys):
    assert benchmark.main([f"--spacing={spacing}"]) == 2
    one_error(capsys, "command line: --spacing: must be positive")


def test_benchmark_refuses_a_mesh_too_large_to_allocate(capsys):
    """--spacing 1mm: about 1.6e9 nodes, refused by twin.fem.mesh.build_mesh before any memory is
    taken (an InputError, not a MemoryError)."""
    assert benchmark.main(["--spacing", "1mm"]) == 2
    one_error(capsys, "spacing")


@pytest.mark.parametrize("spacing", ["-40mm", "0mm"])
def test_heat_step_refuses_a_spacing_that_is_not_positive(spacing, tmp_path, capsys):
    out = tmp_path / "out"
    assert heat_step.main([f"--spacing={spacing}", "--steps", "1", "-o", str(out)]) == 2
    one_error(capsys, "command line: --spacing: must be positive")
    assert not out.exists()


# 6 ---------------------------------------------------------------------------------------------------------------


def test_benchmark_checks_the_scenario_against_the_machine(fast_scenario, capsys):
    assert benchmark.main(["--scenario", str(fast_scenario), "--mesh", "coarse"]) == 2
    one_error(capsys, "spindle[0].speed", "beyond machine cframe-vmc's maximum of 9000 rpm")


def test_benchmark_checks_the_run_size(monkeypatch, capsys):
    from twin import limits

    monkeypatch.setattr(limits, "MAX_NODE_STEPS", 1.0)
    assert benchmark.main(["--scenario", "spindle-heat-cool-9000", "--mesh", "coarse"]) == 2
    one_error(capsys, "node-steps")


def test_camera_benchmark_checks_the_scenario_against_the_machine(fast_scenario, tmp_path, capsys):
    out = tmp_path / "out"
    assert camera_benchmark.main(["--scenario", str(fast_scenario), "-o", str(out)]) == 2
    one_error(capsys, "beyond machine cframe-vmc's maximum")
    assert not out.exists()


# 7 ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("argv, needle", [
    (["--cases", "0"], "command line: --cases: must be at least 1"),
    (["--cases", "-5"], "command line: --cases: must be at least 1"),
    (["--mesh", "bogus"], "command line: --mesh: invalid choice: 'bogus'"),
    (["--cases", "3", "--seed", "-1", "--solver", "rom"], "command line: --seed: -1 is outside"),
    (["--machine", "belt-vmc", "--machine", "cframe-vmc"], "command line: --machine: given more than once"),
    (["--spacing", "100"], "command line: --spacing: '100' has no unit"),
    (["--spacing", "20mm", "--mesh", "coarse"], "--spacing or --mesh, not both"),
    (["--machine", "bogus"], "command line: --machine: unknown machine 'bogus'"),
    # options that would do nothing in the run asked for (a silent no-op reads as a measurement)
    (["--solver", "direct", "--rom-order", "10"], "command line: --rom-order: sets a reduced basis"),
    (["--mesh", "coarse", "--rom-order", "10"], "--rom-order: sets the reduced basis of the reduced model or of "
                                                "iterative steps; this run factorises"),
    (["--solver", "rom", "--no-bound"], "command line: --no-bound: skips the batched reduced model's bound"),
    (["--solver", "iterative", "--gpu-kernels", "arrays"], "command line: --gpu-kernels: chooses the GPU's kernels: "
                                                           "it needs --device gpu"),
    (["--solver", "direct", "--no-reference"], "command line: --no-reference: skips the full-order reference"),
    (["--solver", "direct", "--heat-start", "reduced"], "--heat-start: starts iterative heat steps; --solver direct"),
    (["--solver", "rom", "--heat-start", "projection"], "--heat-start: starts iterative heat steps; --solver rom"),
    (["--mesh", "coarse", "--heat-start", "reduced"], "--heat-start: starts iterative heat steps; --solver auto "
                                                      "factorises this mesh"),
    (["--mesh", "coarse", "--seed", "5"], "command line: --seed: seeds the factors of batched cases"),
    (["--solver", "direct", "--heat-tol", "1e-6 K"], "command line: --heat-tol: bounds the error of iterative heat "
                                                     "steps; --solver direct factorises them"),
    # the default's value too: given, it would be ignored
    (["--solver", "rom", "--heat-tol", "1e-6 K"], "command line: --heat-tol: bounds the error of iterative heat steps; "
                                                  "--solver rom takes none"),
    (["--mesh", "coarse", "--heat-tol", "1e-4 K"], "--heat-tol: bounds the error of iterative heat steps; this run "
                                                   "factorises"),
    (["--mesh", "coarse", "--elastic-coarsening", "2", "--heat-only"], "--elastic-coarsening: coarsens the elastic "
                                                                       "mesh; --heat-only solves no elasticity"),
    (["--mesh", "coarse", "--solver", "rom", "--cases", "3", "--prepare-only"], "command line: --cases: acts on the "
                                                                                "time steps; --prepare-only"),
    # a batch beyond the memory a batch may hold, before the mesh (it ran for minutes, then a MemoryError)
    (["--mesh", "coarse", "--solver", "rom", "--cases", "100000000"], "command line: --cases: 100000000 cases of "
                                                                       "1441 samples each"),
])
def test_benchmark_refuses_bad_options(argv, needle, capsys):
    assert benchmark.main(argv) == 2
    one_error(capsys, needle)


def test_benchmark_refuses_a_missing_gpu_before_its_preparation(capsys):
    """--device gpu without CuPy and a CUDA device: one error before the mesh, with --prepare-only
    too (it ran the CPU's preparation and printed JSON without a device)."""
    from twin.physics.solvers import array_module
    try:
        array_module("gpu")
    except Exception:   # noqa: BLE001 - the refusal this test is about
        pass
    else:
        pytest.skip("a GPU is present")
    for extra in ([], ["--prepare-only"]):
        assert benchmark.main(["--mesh", "coarse", "--device", "gpu", *extra]) == 2
        one_error(capsys, "command line: --device: gpu needs CuPy")


# 8 ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("argv, needle", [
    (["--machine", "bogus"], "command line: --machine: unknown machine 'bogus'"),
    (["--scenario", "bogus"], "unknown scenario 'bogus'"),
    (["--camera", "bogus"], "command line: --camera: machine cframe-vmc has no camera pose 'bogus'"),
    (["--mesh", "bogus"], "command line: --mesh: invalid choice"),
    (["--repeat", "0"], "command line: --repeat: must be at least 1"),
    (["--repeat", "1", "--repeat", "2"], "command line: --repeat: given more than once"),
])
def test_camera_benchmark_checks_everything_before_its_folder(argv, needle, tmp_path, capsys):
    out = tmp_path / "out"
    assert camera_benchmark.main([*argv, "-o", str(out)]) == 2
    one_error(capsys, needle)
    assert not out.exists()


def test_camera_benchmark_refuses_a_file_as_its_folder(tmp_path, capsys):
    path = tmp_path / "file"
    path.write_text("keep")
    assert camera_benchmark.main(["-o", str(path)]) == 2
    one_error(capsys, f"{path}: -o: exists and is not a folder")
    assert path.read_text() == "keep"


# 9 ---------------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("study", [seed001, seed003, heat_step, etve_protocol])
def test_a_study_refuses_a_file_as_its_folder(study, tmp_path, capsys):
    path = tmp_path / "file"
    path.write_text("keep")
    assert study.main(["--quick", "-o", str(path)]) == 2
    one_error(capsys, f"{path}: -o: exists and is not a folder")
    assert path.read_text() == "keep"


@pytest.mark.parametrize("study", [seed001, seed003, etve_protocol, gantry_gnnmci, machine_b_gra])
@pytest.mark.parametrize("seed, needle", [("-1", "-1 is outside"), ("1.5", "not an integer")])
def test_a_study_checks_its_seed_before_anything_is_made(study, seed, needle, tmp_path, capsys):
    out = tmp_path / "out"
    assert study.main(["--quick", f"--seed={seed}", "-o", str(out)]) == 2
    one_error(capsys, "command line: --seed: ", needle)
    assert study.main(["--quick", "--seed", "1", "--seed", "2", "-o", str(out)]) == 2
    one_error(capsys, "--seed: given more than once")
    assert not out.exists()


@pytest.mark.parametrize("main, argv, needle", [
    (feed_signatures.main, ["--mesh", "bogus"], "command line: --mesh: invalid choice: 'bogus'"),
    (diagnosis_signals.main, ["--resolution", "bogus"], "command line: --resolution: invalid choice: 'bogus'"),
    (diagnosis_signals.main, ["--error-mesh", "bogus"], "command line: --error-mesh: invalid choice: 'bogus'"),
    (diagnosis_signals.main, ["--error-mesh", "default"], "command line: --error-mesh: default is the model's own"),
    (axis_pose.main, ["--readout", "--poses", "abc"], "command line: --poses: expected comma-separated"),
    (axis_pose.main, ["--readout", "--poses=-500 mm"], "command line: --poses: -500 mm is outside the Y axis's travel"),
    (axis_pose.main, ["--readout", "--poses", "60 mm,0.06 m"], "command line: --poses: 60 mm given more than once"),
    (axis_pose.main, ["--readout", "--poses", "60,340"], "command line: --poses: expected comma-separated"),
    (heat_step.main, ["--coarsening", "2,2"], "command line: --coarsening: 2 given more than once"),
    # an empty item is a value left out by mistake: refused, never dropped
    (heat_step.main, ["--coarsening", "2,,3"], "command line: --coarsening: expected comma-separated whole numbers"),
    (heat_step.main, ["--coarsening", ",2"], "command line: --coarsening: expected comma-separated whole numbers"),
    (axis_pose.main, ["--readout", "--poses", "60 mm,,340 mm"], "command line: --poses: an empty position"),
])
def test_study_options_are_checked_names_and_numbers(main, argv, needle, capsys):
    assert main(argv) == 2
    one_error(capsys, needle)


def test_hidden_effect_analyse_needs_its_table(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        hidden_effect.main(["--analyse", "-o", str(tmp_path / "none")])
    assert e.value.code == 2
    one_error(capsys, "hidden_effect.csv: --output: no such study table")


@pytest.mark.parametrize("argv, needle", [
    (["--classes", "hidden,,none"], "command line: --classes: an empty class in 'hidden,,none'"),
    (["--classes", "hidden", "--effects", "floor_lag,"], "command line: --effects: an empty effect in 'floor_lag,'"),
    (["--classes", "none", "--cases", ",(none)"], "command line: --cases: an empty text in ',(none)'"),
])
def test_hidden_effect_refuses_an_empty_item(argv, needle, tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        hidden_effect.main(["--out", str(tmp_path / "out"), *argv])
    assert e.value.code == 2
    one_error(capsys, needle)
    assert not (tmp_path / "out").exists()


def test_hidden_effect_checks_its_folder_before_any_case(tmp_path, capsys):
    path = tmp_path / "file"
    path.write_text("keep")
    with pytest.raises(SystemExit) as e:
        hidden_effect.main(["--out", str(path), "--classes", "none"])
    assert e.value.code == 2
    one_error(capsys, f"{path}: --output: exists and is not a folder")


# 10 --------------------------------------------------------------------------------------------------------------


@pytest.fixture
def csv_dataset(tmp_path):
    """A dataset folder of two CSV runs (train, test) with two sensors, ten rows at 60 s."""
    folder = tmp_path / "ds"
    folder.mkdir()
    t = np.arange(10) * 60.0
    for name in ("a", "b"):
        rows = ["time,T1,T2,drift:Z"] + [f"{x},{np.sin(x / 100) + 0.01 * i},{np.cos(x / 90)},{x / 60 + np.sin(x)}"
                                         for i, x in enumerate(t)]
        (folder / f"{name}.csv").write_text("\n".join(rows) + "\n")
    (folder / "index.csv").write_text("file,split,built,family\na.csv,train,True,f\nb.csv,test,True,f\n")
    return folder


@pytest.mark.parametrize("argv, needle", [
    (["--select", "gm0n-fcm:5"], "command line: --select: asks for 5 inputs, the dataset's runs have 2 sensors"),
    (["--select", "all:2"], "command line: --select: all keeps every sensor and takes no count"),
    (["--select", "all"], "the placement benchmark compares sets of 4 sensors"),
    (["--select", "gm0n-fcm:"], "K must be a whole number >= 1, got ''"),
    (["--learners", "mlr,mlr"], "command line: --learners: mlr given more than once"),
    (["--learners", "mlr,,ann"], "command line: --learners: an empty name in 'mlr,,ann'"),
    (["--seed", "1", "--seed", "2"], "command line: --seed: given more than once"),
    (["--n-random", "0"], "--n-random"),      # it failed after the leaderboard was written
    # the placement's own options beside --no-placement would do nothing
    (["--no-placement", "--no-exhaustive"], "command line: --no-exhaustive: sets the placement benchmark, which "
                                            "--no-placement leaves out"),
    (["--no-placement", "--n-random", "20"], "command line: --n-random: sets the placement benchmark"),
    (["--interval", "0 s"], "command line: --interval: must be positive"),
    (["--interval", "-60 s"], "command line: --interval: must be positive"),
    (["--split", "bogus"], "no split 'bogus'"),
    (["--target", "bogus"], "a.csv: bogus: missing target column"),
    (["--split", "train"], "a.csv: --split: is also a training run"),     # scored on its own training data
    (["--select", "gm0n-fcm:1", "--learners", "mlr", "--no-placement"],
     "--segments: 4 segments leave 2 row(s) in a segment of test: all 1 runs; a scored segment needs at least 3: "
     "give --segments 3 or fewer"),
])
def test_dataset_study_checks_everything_before_its_folder(csv_dataset, argv, needle, tmp_path, capsys):
    out = tmp_path / "out"
    assert dataset_learners.main([str(csv_dataset), "-o", str(out), *argv]) == 2
    one_error(capsys, needle)
    assert not out.exists()


def test_dataset_study_refusal_by_a_selector_names_the_split_and_leaves_no_folder(csv_dataset, tmp_path, capsys):
    """A constant target makes the selector refuse the training runs after the checks: the error
    names the dataset's split and the target (it named the selector), and no empty folder stays."""
    for name in ("a", "b"):
        path = csv_dataset / f"{name}.csv"
        rows = path.read_text().splitlines()
        path.write_text("\n".join([rows[0]] + [",".join(r.split(",")[:3] + ["1.0"]) for r in rows[1:]]) + "\n")
    out = tmp_path / "out"
    assert dataset_learners.main([str(csv_dataset), "-o", str(out), "--select", "gm0n-fcm:1", "--learners", "mlr",
                                  "--no-placement", "--segments", "1"]) == 2
    one_error(capsys, f"{csv_dataset} (split train): drift:Z: the target is constant")
    assert not out.exists()


def test_an_empty_option_value_is_refused_not_read_as_not_given(csv_dataset, capsys, tmp_path, monkeypatch):
    """``-o ""`` wrote the study into the current folder (argparse's empty string read as "not
    given"): refused, and nothing is written where the command runs."""
    monkeypatch.chdir(tmp_path)
    assert dataset_learners.main([str(csv_dataset), "-o", ""]) == 2
    one_error(capsys, "command line: -o/--output: is empty: give a value, or leave the option out")
    assert list(tmp_path.iterdir()) == [csv_dataset]


def test_dataset_study_leaderboard_on_every_sensor(csv_dataset, tmp_path):
    """``--select all`` (the registry's selector without a count) puts every sensor into the
    leaderboard's inputs."""
    import pandas as pd
    out = tmp_path / "out"
    assert dataset_learners.main([str(csv_dataset), "-o", str(out), "--select", "all", "--no-placement",
                                  "--learners", "mlr", "--segments", "1"]) == 0
    board = pd.read_csv(out / "leaderboard.csv")
    assert set(board["inputs"]) == {"T1;T2"}


def test_dataset_study_and_learn_write_nothing_into_their_input_dataset(csv_dataset, capsys):
    """-o inside the input dataset (its README, index, a subfolder) is refused: the dataset is an
    input, and an output never replaces one; the folder is unchanged."""
    from twin.cli import main
    before = sorted(p.name for p in csv_dataset.rglob("*"))
    alias = csv_dataset.parent / "alias"
    alias.symlink_to(csv_dataset)           # a second name for the dataset (as a bind mount would be)
    for out in (csv_dataset, csv_dataset / "board", alias / "board"):
        assert dataset_learners.main([str(csv_dataset), "-o", str(out)]) == 2
        one_error(capsys, f"{out}: -o: lies in the input dataset")
    assert main(["learn", "--dataset", str(csv_dataset), "--target", "drift:Z", "--learner", "mlr",
                 "-o", str(csv_dataset / "README.md")]) == 2
    one_error(capsys, "README.md: -o: lies in the input dataset")
    assert main(["learn", "--dataset", str(csv_dataset), "--target", "drift:Z", "--learner", "mlr",
                 "-o", str(alias / "scores.csv")]) == 2
    one_error(capsys, "scores.csv: -o: lies in the input dataset")
    assert sorted(p.name for p in csv_dataset.rglob("*")) == before


def test_learn_refuses_split_options_without_a_dataset(csv_dataset, capsys):
    """--split and --train-split name a dataset's splits: without --dataset they would do nothing."""
    from twin.cli import main
    a, b = str(csv_dataset / "a.csv"), str(csv_dataset / "b.csv")
    for option in ("--split", "--train-split"):
        assert main(["learn", "--train", a, "--test", b, "--target", "drift:Z", "--learner", "mlr", option, "x"]) == 2
        one_error(capsys, f"command line: {option}: names a split of a --dataset")


def test_a_text_that_is_no_dataset_index_is_named_so(csv_dataset, capsys):
    """An index.csv without the columns of a dataset index, or without a case: not 'no split'."""
    from twin.cli import main
    for text, needle in (("hello\n", "index.csv: file: missing column: not the index.csv of a twin dataset"),
                         ("file,split,built\n", "index.csv: file: lists no case")):
        (csv_dataset / "index.csv").write_text(text)
        assert main(["learn", "--dataset", str(csv_dataset), "--target", "drift:Z", "--learner", "mlr"]) == 2
        one_error(capsys, needle)


@pytest.mark.parametrize("module", ["common", "camera_figures", "diagnosis_cases", "learner_data", "machine_b_data",
                                    "placement_search", "not_a_study"])
def test_a_module_the_studies_share_is_not_run_as_a_study(module):
    """``python -m validate.studies.<module>`` of a shared module exits 2 with one line saying so
    (it exited 0 silently, even with --help)."""
    import subprocess
    import sys
    run = subprocess.run([sys.executable, "-m", f"validate.studies.{module}", "--help"], capture_output=True, text=True)
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.strip().splitlines() == [f"error: python -m validate.studies.{module}: a module the studies use, "
                                               "not a study; the studies are listed in the README (\"Learner studies "
                                               "on the twin\" and the sections that name them)"]
