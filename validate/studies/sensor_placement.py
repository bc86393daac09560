"""Sensor-placement check: gm0n-fcm's 4 sensors against intuitive, random and truth-greedy sets.

``python -m validate.studies.sensor_placement [--quick] [-o DIR] [--camera [POSE]]`` uses the seed-001 runs of
:mod:`validate.studies.learner_data` (train ``spindle-heat-cool-9000``, test ``spindle-duty-cycle``, Z
drift [um], measured temperature rises [degC]) and scores, with ``mlr`` and ``anfis-fcm``, these
4-sensor sets:

- ``gm0n-fcm``: picked by GM(0,N) + FCM on the training run from the dense grid;
- ``intuitive``: one per major part, the machine's own sites ``motor`` (motor/carrier),
  ``spindle_boss``, ``column_front_top``, ``test_bar``;
- ``seed-move``: the gm0n-fcm set with its first sensor moved to ``spindle_boss`` (seed 001's
  "one sensor moved to an intuitive location");
- ``random``: 20 seeded draws of 4 grid sensors (mean, min, max over the draws);
- ``greedy-oracle``: forward selection over the grid, each step adding the sensor that most lowers
  the *test-set* RMSE of least squares (= ``mlr``) trained on the training run; it uses the known
  truth of the test run: a reference, not a method, and neither a bound nor an optimum (greedy, and
  judged by least squares, not by each learner; :mod:`validate.studies.placement_search`, whose
  exhaustive search, the least-squares optimum, the dataset study
  :mod:`validate.studies.dataset_learners` runs).

Writes ``placement.md``, ``placement.csv`` and ``placement.png``. With ``--camera`` the candidates
are seed 001's 525 spots on the thermal-camera frames (the intuitive sites stay the glued sensors).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from twin.plotting import save_figure
from validate.studies.common import data_main, fit_score, markdown_table, preset, score_units, select, write_csv
from validate.studies.placement_search import greedy_oracle

NAME = "sensor_placement"
INTUITIVE = ("motor", "spindle_boss", "column_front_top", "test_bar")
LEARNER_NAMES = ("mlr", "anfis-fcm")


def sensor_sets(data, seed: int = 0, n_random: int = 20, axis: str = "Z", k: int = 4) -> dict[str, list[list[int]]]:
    """Named lists of column sets (the random entry holds ``n_random`` sets)."""
    cand = data.candidate_columns
    picked = [cand[i] for i in select(data.X_train[:, cand], data.y_train[axis], k, data.candidates, seed=seed)]
    moved = [data.columns(["spindle_boss"])[0]] + picked[1:]
    rng = np.random.default_rng(seed)
    draws = [list(rng.choice(cand, size=k, replace=False)) for _ in range(n_random)]
    return {"gm0n-fcm": [picked], "intuitive": [data.columns(INTUITIVE)], "seed-move": [moved],
            "random": draws,
            "greedy-oracle": [greedy_oracle(data.X_train, data.y_train[axis], data.X_test, data.y_test[axis], cand, k)]}


def run_study(data, seed: int = 0, n_random: int = 20, axis: str = "Z", learner_names=LEARNER_NAMES):
    """Rows (one per set and learner; random as mean/min/max) and the raw per-draw rows."""
    sets = sensor_sets(data, seed, n_random, axis)
    rows, raw = [], []
    for label, col_sets in sets.items():
        for name in learner_names:
            scores = []
            for cols in col_sets:
                row, _ = fit_score(preset(name, seed), data.X_train[:, cols], data.y_train[axis],
                                   data.X_test[:, cols], data.y_test[axis])
                row = {"set": label, "learner": name, **row, "inputs": ";".join(data.names[c] for c in cols)}
                raw.append(row)
                scores.append(row)
            rmse = np.array([s["test_rmse"] for s in scores])
            res = np.array([s["test_max_abs_residual"] for s in scores])
            out = {"set": label, "learner": name, "axis": axis, "n_sets": len(scores),
                   "test_rmse": float(rmse.mean()), "test_nse": float(np.mean([s["test_nse"] for s in scores])),
                   "test_max_abs_residual": float(res.mean())}
            if len(scores) > 1:
                out.update(test_rmse_min=float(rmse.min()), test_rmse_max=float(rmse.max()),
                           test_max_abs_residual_min=float(res.min()), test_max_abs_residual_max=float(res.max()),
                           inputs="(random draws; see placement_draws.csv)")
            else:
                out["inputs"] = scores[0]["inputs"]
            rows.append(out)
    return rows, raw


def plot(path: Path, rows):
    """Bars of test RMSE per sensor set and learner; random draws with min-max whiskers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sets = list(dict.fromkeys(r["set"] for r in rows))
    names = list(dict.fromkeys(r["learner"] for r in rows))
    fig, ax = plt.subplots(figsize=(8, 4))
    w = 0.8 / len(names)
    for j, name in enumerate(names):
        rs = [next(r for r in rows if r["set"] == s and r["learner"] == name) for s in sets]
        x = np.arange(len(sets)) + j * w
        y = [r["test_rmse"] for r in rs]
        lo = [r["test_rmse"] - r.get("test_rmse_min", r["test_rmse"]) for r in rs]
        hi = [r.get("test_rmse_max", r["test_rmse"]) - r["test_rmse"] for r in rs]
        ax.bar(x, y, w, yerr=[lo, hi], capsize=3, label=name)
    ax.set_xticks(np.arange(len(sets)) + 0.4 - w / 2, sets)
    ax.set_ylabel("test RMSE, Z drift [um]")
    ax.set_yscale("log")
    ax.legend()
    ax.set_title("4-sensor sets on cframe-vmc (train heat/cool, test duty cycle)")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def reading(rows) -> str:
    """One sentence per learner comparing the sets' test RMSE [um]."""
    out = []
    for name in dict.fromkeys(r["learner"] for r in rows):
        r = {x["set"]: x for x in rows if x["learner"] == name}
        out.append(f"- `{name}`: gm0n-fcm {r['gm0n-fcm']['test_rmse']:.2f} um, intuitive "
                   f"{r['intuitive']['test_rmse']:.2f}, one sensor moved {r['seed-move']['test_rmse']:.2f}, random "
                   f"{r['random']['test_rmse']:.2f} (best draw {r['random'].get('test_rmse_min', np.nan):.2f}), "
                   f"truth-greedy {r['greedy-oracle']['test_rmse']:.2f} um.")
    return "\n".join(out)


COLUMNS = ["set", "learner", "n_sets", "test_rmse", "test_rmse_min", "test_rmse_max", "test_nse",
           "test_max_abs_residual", "test_max_abs_residual_max", "inputs"]
HEADERS = ["sensor set", "learner", "sets", "test RMSE um (mean)", "RMSE min um", "RMSE max um", "test NSE (mean)",
           "max |res| um (mean)", "max |res| um (max)", "inputs"]
# the CSV columns in um (Z drift): test_rmse_um, test_rmse_min_um, ..., as in the Markdown's headings
CSV_UNITS = {**score_units("um"), **dict.fromkeys(("test_rmse_min", "test_rmse_max", "test_max_abs_residual_min",
                                                   "test_max_abs_residual_max"), "um")}


def main(argv=None) -> int:
    return data_main(NAME, __doc__, argv, _run, ("placement.csv", "placement_draws.csv", "placement.md", "placement.png"))


def _run(args, out, data) -> int:
    print("scoring sensor sets (greedy oracle searches the whole grid) ...", flush=True)
    rows, raw = run_study(data, seed=args.seed)
    write_csv(out / "placement.csv", rows, CSV_UNITS)
    write_csv(out / "placement_draws.csv", raw, CSV_UNITS)
    table = markdown_table(rows, COLUMNS, HEADERS)
    i = data.info
    kind = (f"spots on the `{i['pose']}` camera's frames" if i.get("mode") == "camera" else "grid")
    text = (f"# Sensor placement on `{i['machine']}` (mesh `{i['mesh']}`), Z drift\n\n"
            f"Train `{i['train']}`, test `{i['test']}`; {i['n_grid']} {kind} candidates. The greedy oracle "
            "uses the test run's truth: a reference, not a method, and neither a bound nor an optimum (greedy, "
            "chosen for least squares).\n\n" + table + "\n\n" + reading(rows) + "\n")
    (out / "placement.md").write_text(text)
    plot(out / "placement.png", rows)
    print(table)
    print(f"wrote {out / 'placement.md'}, placement.csv, placement_draws.csv, placement.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
