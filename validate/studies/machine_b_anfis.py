"""Seed 000 Machine B: ANFIS-FCM with five inputs trained on Test IV and tested on Tests I-III, V,
VI (thesis Tables 5-5, 5-7, 5-8), on ``belt-vmc``.

``python -m validate.studies.machine_b_anfis [--quick] [-o DIR] [--seed N]`` writes
``anfis.md``, ``anfis.csv`` and ``anfis.png`` into ``validate-out/machine_b_anfis/``.

Protocol (thesis §5.3, L5203-5566): inputs five temperature points, target the Y displacement
[um]; train on Test IV (4000 rpm 2 h / 1 h / 2 h / 3 h), test on the other five tests. Table 5-5:
the FCM cluster count (= rules) swept 2-6 (best testing RMSE 1.7 um at nc = 4; the thesis's text
calls it the model with 3 rules, inconsistent with its own table: L5385-5416). Tables 5-7/5-8:
R, RMSE, NSE and max |residual| per test for ANFIS-FCM at the best cluster count and for
ANFIS-Grid with 3 MFs per input (243 rules). Two input sets: the thesis's five (T5, T11, T40,
T65, T75) and the five the twin's own grey relational grouping keeps
(:mod:`validate.studies.machine_b_gra`). ANFIS uses the studies' preset (checking data: every
5th block of 5 min of the training run; the epoch of least checking error is kept).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from twin.io.atomic import atomic_write_text
from twin.plotting import save_figure
from validate.studies.common import fit_score, markdown_table, preset, score_units, study_main, write_csv
from validate.studies.machine_b_data import column, load_tests
from validate.studies.machine_b_gra import SEED_SELECTED
from validate.studies.machine_b_gra import run_study as gra_study

NAME = "machine_b_anfis"
THESIS_NC = {2: 2.3, 3: 1.8, 4: 1.7, 5: 2.1, 6: 5.6}               # Table 5-5, testing RMSE [um]
THESIS_PER_TEST = {  # Tables 5-7 / 5-8: (learner, test) -> (R, RMSE, NSE, residual +-um)
    ("anfis-grid", "I"): (0.96, 1.53, 0.92, 3), ("anfis-fcm", "I"): (0.99, 1.23, 0.94, 2),
    ("anfis-grid", "II"): (0.99, 2.72, 0.96, 4), ("anfis-fcm", "II"): (0.99, 0.57, 0.99, 2),
    ("anfis-grid", "III"): (0.98, 2.78, 0.95, 5), ("anfis-fcm", "III"): (0.99, 1.06, 0.98, 2),
    ("anfis-grid", "V"): (0.97, 3.98, 0.95, 8), ("anfis-fcm", "V"): (0.99, 2.78, 0.97, 4),
    ("anfis-grid", "VI"): (0.98, 3.88, 0.95, 7)}
TEST_RUNS = ("I", "II", "III", "V", "VI")
# anfis.csv: the Y drift's scores in um (train_rmse_um, test_rmse_um, thesis_rmse_um, ...)
CSV_UNITS = {**score_units("um"), **dict.fromkeys(("thesis_test_rmse", "thesis_rmse", "thesis_residual"), "um")}


def _matrices(runs, points):
    cols = [column(p) for p in points]
    return {k: (r.X[:, cols], r.y) for k, r in runs.items()}


def sweep(data, seed: int = 0, clusters=range(2, 7)) -> list[dict]:
    """Table 5-5: ANFIS-FCM trained on IV, pooled testing RMSE over the other tests, per cluster count."""
    Xtr, ytr = data["IV"]
    Xte = np.vstack([data[k][0] for k in TEST_RUNS])
    yte = np.concatenate([data[k][1] for k in TEST_RUNS])
    rows = []
    for nc in clusters:
        row, _ = fit_score(preset("anfis-fcm", seed, n_rules=nc), Xtr, ytr, Xte, yte)
        rows.append({"clusters": nc, **row, "thesis_test_rmse": THESIS_NC.get(nc)})
    return rows


def per_test(data, n_rules: int, seed: int = 0) -> tuple[list[dict], dict]:
    """Tables 5-7/5-8: each learner fitted once on IV, scored on every other test."""
    Xtr, ytr = data["IV"]
    rows, preds = [], {}
    for name, est in (("anfis-fcm", preset("anfis-fcm", seed, n_rules=n_rules)),
                      ("anfis-grid", preset("anfis-grid", seed, n_mfs=3))):
        for k in TEST_RUNS:
            row, pred = fit_score(est, Xtr, ytr, *data[k]) if k == TEST_RUNS[0] else _score(est, *data[k])
            th = THESIS_PER_TEST.get((name, k), (None,) * 4)
            rows.append({"learner": name, "test": k, **row, "thesis_r": th[0], "thesis_rmse": th[1],
                         "thesis_nse": th[2], "thesis_residual": th[3]})
            preds[(name, k)] = pred
    return rows, preds


def _score(est, X, y):
    from learners.metrics import score_all

    pred = np.asarray(est.predict(X), float)
    return {f"test_{k}": float(v) for k, v in score_all(y, pred).items()}, pred


def outside_training(data) -> dict[str, float]:
    """Share of each test's samples with at least one input outside the training run's range."""
    Xtr = data["IV"][0]
    lo, hi = Xtr.min(axis=0), Xtr.max(axis=0)
    return {k: float(np.mean(np.any((data[k][0] < lo) | (data[k][0] > hi), axis=1))) for k in TEST_RUNS}


def plot(path: Path, runs, preds, label: str):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(TEST_RUNS), figsize=(15, 3.2), sharey=True)
    for ax, k in zip(axes, TEST_RUNS):
        t = runs[k].time / 3600
        ax.plot(t, runs[k].y, "k", lw=1.5, label="twin Y (truth)")
        ax.plot(t, preds[("anfis-fcm", k)], label="ANFIS-FCM")
        ax.plot(t, preds[("anfis-grid", k)], ls=":", label="ANFIS-Grid")
        ax.set_title(f"Test {k}"), ax.set_xlabel("time [h]")
    axes[0].set_ylabel("Y [um]"), axes[0].legend(fontsize=7)
    fig.suptitle(f"Machine B on belt-vmc, trained on Test IV, inputs {label}")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


SEED_PEAK_Y = {"I": 25.0, "II": 35.0, "III": 40.0, "IV": 39.0, "V": 64.0, "VI": 79.0}   # thesis Figs 5-x [um]


def _y_against_seed(runs) -> str:
    """'; the twin's Y is 0.2-0.4 of the seed's (README)' from the runs' peaks, for the tests both have."""
    ratios = [float(np.abs(r.y).max()) / SEED_PEAK_Y[k] for k, r in runs.items() if k in SEED_PEAK_Y]
    if not ratios:
        return ""
    return f"; the twin's Y is {min(ratios):.2g}-{max(ratios):.2g} of the seed's (README)"


def main(argv=None) -> int:
    return study_main(NAME, __doc__, argv, _run, ("anfis.csv", "anfis.md", "anfis.png"))


def _run(args, out: Path) -> int:
    out.mkdir(parents=True, exist_ok=True)
    res = "coarse" if args.quick else "default"
    runs = load_tests(out, res, args.seed)
    _, sel = gra_study(runs, args.seed)
    sets = {"thesis": [f"T{i}" for i in SEED_SELECTED], "twin GRA": [f"T{i}" for i in sel["best_per_group"]]}
    md = ["# Machine B: ANFIS-FCM trained on Test IV (thesis Tables 5-5, 5-7, 5-8)", "",
          f"Command: `python -m validate.studies.machine_b_anfis{' --quick' if args.quick else ''}`. belt-vmc, "
          f"`{res}` mesh; inputs measured temperature rises [K], target the true Y drift [um]. Peak |Y| of the "
          "twin's tests: " + ", ".join(f"{k} {np.abs(r.y).max():.1f}" for k, r in runs.items())
          + " um (the seed's: I 25, II 35, III 40, IV 39, V 64, VI 79 um" + _y_against_seed(runs) + ")."]
    csv_rows = []
    for label, points in sets.items():
        data = _matrices(runs, points)
        nc_rows = sweep(data, args.seed)
        best = min(nc_rows, key=lambda r: r["test_rmse"])
        test_rows, preds = per_test(data, best["clusters"], args.seed)
        csv_rows += [{"inputs": label, "table": "5-5", **r} for r in nc_rows]
        csv_rows += [{"inputs": label, "table": "5-7/5-8", **r} for r in test_rows]
        md += ["", f"## Inputs: {label} ({', '.join(points)})", "", "### Cluster count (Table 5-5), pooled testing RMSE [um]", "",
               markdown_table(nc_rows, ["clusters", "test_rmse", "thesis_test_rmse", "test_nse"],
                              ["clusters (rules)", "twin RMSE", "thesis RMSE", "twin NSE"]),
               "", f"Best: {best['clusters']} clusters, {best['test_rmse']:.2f} um (thesis: 1.7 um, the best of its 2-6 sweep; both chosen by test RMSE, so optimistic).", "",
               "### Per test (Tables 5-7, 5-8)", "",
               markdown_table(test_rows, ["learner", "test", "test_r", "thesis_r", "test_rmse", "thesis_rmse",
                                          "test_nse", "thesis_nse", "test_max_abs_residual", "thesis_residual"],
                              ["learner", "test", "R", "thesis R", "RMSE [um]", "thesis RMSE [um]", "NSE", "thesis NSE",
                               "max abs residual [um]", "thesis +- [um]"])]
        share = outside_training(data)
        grid = {r["test"]: r for r in test_rows if r["learner"] == "anfis-grid"}
        md += ["", "Inputs outside Test IV's range (share of samples): "
               + ", ".join(f"{k} {v:.0%}" for k, v in share.items())
               + f". ANFIS-Grid's {3 ** len(points)} rules are fitted on Test IV only; where a test leaves that range "
               "its rules extrapolate (largest residual "
               + ", ".join(f"{k} {grid[k]['test_max_abs_residual']:.3g} um" for k in TEST_RUNS) + ")."]
        if label == "thesis":
            plot(out / "anfis.png", runs, preds, ", ".join(points))
    write_csv(out / "anfis.csv", csv_rows, CSV_UNITS)
    atomic_write_text(out / "anfis.md", "\n".join(md) + "\n")
    print(f"wrote {out}/anfis.md, anfis.csv, anfis.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
