"""Seed 003's protocol on the twin: the slope of the thermal positioning error of the Y axis from
eleven temperatures (Li, Shi, Ji & Liang 2021, Micromachines 12:201).

``python -m validate.studies.seed003 [--quick] [-o DIR] [--seed N]`` simulates ``cframe-vmc`` on
``seed003-exp1`` (train: eight interferometer runs over 390 min at 20 mm/s) and ``seed003-exp2``
(test: runs at 40, 120, 160 and 220 min at 15 mm/s in the evening), takes the eleven sites'
measured temperatures at each run and the slope k of each run's least-squares line (k = k0 + the
twin's thermal slope change, k0 = -0.3903 um/mm the seed's cold slope: the twin has no pitch
error), selects sensors by the maximal-tree fuzzy clustering with R^2 / F (seed Sec. 3.3), fits MLR,
PCR (85 % cumulative variance) and an ANN 5-4-1 on Exp I, and scores the thermal error
(k^ - k) y over the targets y = 0 .. 280 mm (RMSE, MAXR, MINR [um]) on both experiments. Writes
``seed003.md`` (the seed's Tables 6-10 and 20-21 beside ours) and ``seed003.csv`` (columns
``RMSE_um``, ``MAXR_um``, ``MINR_um``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import scipy.stats

from learners import make_learner, make_selector
from validate.studies.common import markdown_table, study_main, write_csv

NAME = "seed003"
K0 = -0.3903   # um/mm, the seed's cold slope (note 003, sec. 5.5)
SITES = ["Y_motor", "Y_column", "Y_guideway_front", "Y_bed", "Y_guideway_back", "Y_air_machine",
         "Y_front_bearing", "Y_table", "Y_rear_bearing", "Y_nut", "Y_air_room"]   # seed T1 .. T11
LABELS = [f"T{i + 1}" for i in range(len(SITES))]
SEED_TABLE6 = {1: 0.963, 2: 0.963, 3: 0.971, 4: 0.989, 5: 0.997, 6: 0.999}
SEED_SELECTION = "T1, T2, T5, T7, T11"
SEED_MLR = {"R2": 0.997, "adj_R2": 0.988, "F": 120.014, "sig": 0.008, "se": 0.0044024}
CSV_UNITS = {"RMSE": "um", "MAXR": "um", "MINR": "um"}   # seed003.csv: RMSE_um, MAXR_um, MINR_um
SEED_SCORES = [  # Tables 20 and 21, um
    {"experiment": "I fit", "model": "PCR", "RMSE": 1.9978, "MAXR": 3.9, "MINR": -6.0},
    {"experiment": "I fit", "model": "MLR", "RMSE": 1.3134, "MAXR": 2.1, "MINR": -3.4},
    {"experiment": "I fit", "model": "ANN", "RMSE": 1.3357, "MAXR": 2.8, "MINR": -3.3},
    {"experiment": "II predict", "model": "PCR", "RMSE": 4.2093, "MAXR": 8.3, "MINR": -2.2},
    {"experiment": "II predict", "model": "MLR", "RMSE": 6.4909, "MAXR": 12.1, "MINR": -2.1},
    {"experiment": "II predict", "model": "ANN", "RMSE": 7.3053, "MAXR": 19.7, "MINR": -2.3},
]


def samples(ds, skip_cold: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(X (runs, 11) measured temperatures [degC] at the interferometer runs, k (runs,) [um/mm],
    targets [mm]) of a seed003 result; ``skip_cold`` drops the run at 0 s."""
    runs = ds.run_time.values
    idx = [int(np.argmin(np.abs(ds.time.values - t))) for t in runs]
    X = ds.temperature.sel(sensor=SITES).values[idx]
    k = K0 + ds.positioning_slope.values
    keep = slice(1, None) if skip_cold else slice(None)
    return X[keep], k[keep], ds.target.values


def ols_stats(X: np.ndarray, y: np.ndarray) -> dict:
    """OLS of y on X with intercept: R^2, adjusted R^2, F, its p-value, the standard error of the
    estimate and per coefficient B, SE, t, p (seed Eqs. 7-8; SPSS's tables)."""
    n, p = X.shape
    A = np.column_stack([np.ones(n), X])
    b = np.linalg.lstsq(A, y, rcond=None)[0]
    res = y - A @ b
    sse, sst = float(res @ res), float(((y - y.mean()) ** 2).sum())
    dof = n - p - 1
    r2 = 1 - sse / sst if sst > 0 else np.nan
    out = {"R2": r2, "adj_R2": 1 - (1 - r2) * (n - 1) / dof if dof > 0 else np.nan}
    if dof > 0 and sse > 0:
        s2 = sse / dof
        cov = s2 * np.linalg.pinv(A.T @ A)
        se = np.sqrt(np.clip(np.diag(cov), 0, None))
        t = b / np.where(se > 0, se, np.nan)
        out.update({"F": (sst - sse) / p / s2, "sig": float(scipy.stats.f.sf((sst - sse) / p / s2, p, dof)),
                    "se": float(np.sqrt(s2)), "B": b, "SE": se, "t": t,
                    "p": 2 * scipy.stats.t.sf(np.abs(t), dof)})
    else:
        out.update({"F": np.nan, "sig": np.nan, "se": np.nan, "B": b})
    return out


def scores(k_hat: np.ndarray, k: np.ndarray, targets: np.ndarray) -> dict:
    """RMSE, MAXR, MINR [um] of the thermal positioning error (k^ - k) y over runs and targets."""
    r = np.outer(k_hat - k, targets).ravel()
    return {"RMSE": float(np.sqrt(np.mean(r ** 2))), "MAXR": float(r.max()), "MINR": float(r.min())}


def run_study(exp1, exp2, seed: int = 0) -> dict:
    """Selection, fits and scores (see module docstring) on two seed003 results."""
    X1, k1, targets = samples(exp1)
    X2, k2, _ = samples(exp2, skip_cold=True)
    sel = make_selector("fuzzy-r2").fit(X1, k1)
    cols = [int(i) for i in sel.selected_]
    levels = []
    for n, combo in enumerate(sel.combinations_[:6], start=1):
        st = ols_stats(X1[:, combo], k1)
        levels.append({"n_vars": n, "variables": ", ".join(LABELS[i] for i in combo), "R2": st["R2"],
                       "F": st["F"], "sig": st["sig"], "seed_R2": SEED_TABLE6.get(n)})
    models = {"MLR": make_learner("mlr"), "PCR": make_learner("pcr", n_components=0.85),
              "ANN": make_learner("ann", hidden_layer_sizes=(4,), random_state=seed, max_iter=5000)}
    rows = []
    for name, est in models.items():
        est.fit(X1[:, cols], k1)
        for label, X, k in (("I fit", X1, k1), ("II predict", X2, k2)):
            rows.append({"experiment": label, "model": name, **scores(est.predict(X[:, cols]), k, targets)})
    pcr = models["PCR"]
    return {"k1": k1, "k2": k2, "cols": cols, "levels": levels, "mlr": ols_stats(X1[:, cols], k1), "rows": rows,
            "pcr_kept": int(pcr.n_components_), "pcr_ratio": pcr.explained_variance_ratio_,
            "sd": X1.std(axis=0, ddof=1)}


def report(res: dict) -> str:
    """The Markdown report: ours beside the seed's tables."""
    chosen = ", ".join(LABELS[i] for i in res["cols"])
    m = res["mlr"]
    lines = ["# Seed 003 on the twin (cframe-vmc, seed003-exp1 -> seed003-exp2)", "",
             "Sites T1..T11 = " + ", ".join(f"{a} {b}" for a, b in zip(LABELS, SITES)) + ".", "",
             f"Slopes k [um/mm], Exp I: {', '.join(f'{v:.4f}' for v in res['k1'])} (seed: k0 = -0.3903, mean of the "
             f"eight -0.3243; ours {res['k1'].mean():.4f}); Exp II: {', '.join(f'{v:.4f}' for v in res['k2'])}.", "",
             "Temperature sd over the eight Exp I samples [K]: " + ", ".join(
                 f"{a} {s:.2f}" for a, s in zip(LABELS, res["sd"])) + " (seed: T1 1.28, T2 0.43, T5 0.85, T7 0.31, "
             "T11 0.17).", "",
             "## Tables 5-8: the maximal-tree selection, R^2 and F per level", "",
             markdown_table(res["levels"], ["n_vars", "variables", "R2", "seed_R2", "F", "sig"],
                            ["variables", "combination (ours)", "R^2", "seed R^2", "F", "Sig."]), "",
             f"Chosen: **{chosen}** (seed: {SEED_SELECTION}, 5 variables; F 120.014, Sig. 0.008).", "",
             "## Tables 9-10: MLR on the chosen variables", "",
             markdown_table([{"what": "ours", **{k: m.get(k) for k in ("R2", "adj_R2", "F", "sig", "se")}},
                             {"what": "seed", **SEED_MLR}], ["what", "R2", "adj_R2", "F", "sig", "se"],
                            ["", "R^2", "adj. R^2", "F", "Sig.", "std. error"]), ""]
    if "SE" in m:
        coef = [{"term": t, "B": b, "SE": s, "t": tt, "p": p} for t, b, s, tt, p in
                zip(["(constant)"] + [LABELS[i] for i in res["cols"]], m["B"], m["SE"], m["t"], m["p"])]
        lines += [markdown_table(coef, ["term", "B", "SE", "t", "p"], ["term", "B", "std. error", "t", "Sig."]), ""]
    ratio = np.cumsum(res["pcr_ratio"]) * 100
    lines += [f"PCR: {res['pcr_kept']} component(s) kept, cumulative variance "
              + ", ".join(f"{v:.1f} %" for v in ratio) + " (seed: PC1 92.9 %, only PC1 kept).", "",
              "## Tables 20-21: thermal positioning error (k^ - k) y over 0..280 mm [um]", "",
              markdown_table([{**o, "seed_RMSE": s["RMSE"], "seed_MAXR": s["MAXR"], "seed_MINR": s["MINR"]}
                              for o, s in zip(res["rows"], _seed_rows(res["rows"]))],
                             ["experiment", "model", "RMSE", "MAXR", "MINR", "seed_RMSE", "seed_MAXR", "seed_MINR"],
                             ["experiment", "model", "RMSE", "MAXR", "MINR", "seed RMSE", "seed MAXR", "seed MINR"]),
              "", verdict(res["rows"]), "", "## What differs and why", "", why(res)]
    return "\n".join(lines) + "\n"


TIE_RTOL = 1e-9   # two RMSEs this close are one model twice (PCR on one variable is MLR), not a ranking


def verdict(rows: list[dict]) -> str:
    """Which model predicts Exp II best, ours beside the seed's (PCR). Models whose RMSEs agree to
    ``TIE_RTOL`` share the lead: round-off must not pick a winner."""
    test = [r for r in rows if r["experiment"] == "II predict"]
    best = min(r["RMSE"] for r in test)
    leaders = [r["model"] for r in test if r["RMSE"] <= best * (1 + TIE_RTOL)]
    head = (f"**Verdict**: on the twin {' and '.join(leaders)} "
            + (f"tie for the best Exp II prediction (RMSE {best:.2f} um, equal to round-off)" if len(leaders) > 1
               else f"predicts Exp II best (RMSE {best:.2f} um)"))
    if leaders == ["PCR"]:
        return head + "; the seed's PCR (4.21 um) also leads here."
    tail = "; the seed's PCR (4.21 um) led alone: the seed's finding that PCR generalises best under the changed "
    if "PCR" in leaders:
        return head + tail + "room and feed is not reproduced by this twin, whose PCR is no better than " \
            + " and ".join(m for m in leaders if m != "PCR") + "."
    return head + tail + "room and feed is not reproduced by this twin."


def _seed_rows(rows):
    table = {(r["experiment"], r["model"]): r for r in SEED_SCORES}
    return [table[(r["experiment"], r["model"])] for r in rows]


def why(res: dict) -> str:
    """What differs from the seed and why, from this run's numbers (the selection's size, the
    network's weights, each model's Exp I and Exp II RMSE)."""
    rmse = {(r["experiment"], r["model"]): r["RMSE"] for r in res["rows"]}
    p = len(res["cols"])
    weights = (p + 1) * 4 + 5          # an ANN p-4-1: (p inputs + bias) x 4 hidden, (4 + bias) x 1 output
    ii = ", ".join(f"{m} {rmse[('II predict', m)]:.2f}" for m in ("MLR", "PCR", "ANN"))
    return (f"""- The twin's k comes from the screw's temperature alone (semi-closed loop), without the
  interferometer's and the curve fit's scatter and without a measurement run that heats the axis
  itself; with eight samples an ANN {p}-4-1 ({weights} weights) fits Exp I to RMSE
  {rmse[('I fit', 'ANN')]:.3f} um (seed: 5 inputs, 29 weights).
- The structure sites of the twin warm less than the seed's (column, back guideway): the castings
  are solid blocks and the feed-drive powers are plausible values tuned to the slope change only,
  so the correlations among the sites, and with them the selection ({p} variable{'s' * (p != 1)} here,
  5 in the seed), differ.
- Exp II differs from Exp I by the feed (15 against 20 mm/s) and a cooler, falling evening room, as
  in the seed; how much the room moves the chosen sites decides how each model extrapolates
  (Exp II RMSE [um]: {ii}). Plausible, not a measured machine.""")


RUNS = ("seed003-exp1", "seed003-exp2")


def main(argv=None) -> int:
    return study_main(NAME, __doc__, argv, _run, tuple(f"{n}.nc" for n in RUNS) + (f"{NAME}.md", f"{NAME}.csv"))


def _run(args, out: Path) -> int:
    from geometries import build_machine
    from twin.api import simulate
    from twin.io.results import write_netcdf
    from twin.motion import machine_for
    from twin.physics.prepared import PreparedTwin
    from twin.scenario import load_scenario

    resolution = "coarse" if args.quick else "default"
    # both experiments move Y: one machine with its feed drive, one mesh and elasticity for both
    twin = PreparedTwin(machine_for(build_machine("cframe-vmc"), load_scenario(RUNS[0])), resolution=resolution)
    runs = []
    for name in RUNS:
        print(f"simulating {name} on the {resolution} mesh ...", flush=True)
        ds, _ = simulate("cframe-vmc", name, seed=args.seed, prepared=twin)
        out.mkdir(parents=True, exist_ok=True)
        write_netcdf(ds, out / f"{name}.nc")
        runs.append(ds)
    res = run_study(*runs, seed=args.seed)
    (out / f"{NAME}.md").write_text(report(res))
    write_csv(out / f"{NAME}.csv", res["rows"], CSV_UNITS)
    print(report(res))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
