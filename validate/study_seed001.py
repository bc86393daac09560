"""Seed 001's protocol on the twin: train on the 9000 rpm heat/cool test, test on the duty cycle.

``python -m validate.study_seed001 [--quick] [-o DIR]`` simulates ``cframe-vmc`` on
``spindle-heat-cool-9000`` (train) and ``spindle-duty-cycle`` (test) with a dense grid of virtual
surface sensors (50 mm pitch) on the carrier, column and test bar, lets ``gm0n-fcm`` pick 4 of them
on the training run (per target axis), fits every registered learner on the measured temperature
rises [degC] against the true drift [um] and scores it on the test run. Writes ``seed001.md``,
``seed001.csv`` and ``seed001.png`` (test Z drift, predictions and residuals) to the output folder.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import learners
from validate.learner_data import build_data
from validate.study_common import fit_score, markdown_table, parse_args, preset, select, write_csv

NAME = "study_seed001"
SEED_ROWS = [  # seed 001 Table 5 (FCM-ANFIS 4) and Table 6, Z axis, test set; um
    {"axis": "Z", "learner": "seed 001 FCM-ANFIS 4 (6 rules)", "train_rmse": 0.6069, "train_nse": 0.9939,
     "test_rmse": 1.4139, "test_nse": 0.9764, "test_r": 0.9912, "test_max_abs_residual": 2.9521},
    {"axis": "Z", "learner": "seed 001 ANN 4-10-1", "test_rmse": 2.6071, "test_nse": 0.9012, "test_r": 0.9807,
     "test_max_abs_residual": 7.0210},
]
COLUMNS = ["axis", "learner", "train_rmse", "train_nse", "test_rmse", "test_nse", "test_r", "test_max_abs_residual",
           "test_improvement_pct", "fit_time_s"]
HEADERS = ["axis", "learner", "train RMSE um", "train NSE", "test RMSE um", "test NSE", "test R", "test max|res| um",
           "improvement %", "fit s"]


def run_study(data, seed: int = 0, learner_names=None, axes=("Z", "Y"), k: int = 4) -> tuple[list[dict], dict]:
    """Rows of scores (one per axis and learner) and, per axis, the selected names and test predictions."""
    learner_names = list(learner_names or learners.LEARNERS)
    cand = data.candidate_columns
    rows, extra = [], {}
    for axis in axes:
        picked = select(data.X_train[:, cand], data.y_train[axis], k, data.candidates, seed=seed)
        cols = [cand[i] for i in picked]
        names = [data.names[c] for c in cols]
        preds = {}
        for name in learner_names:
            try:
                row, pred = fit_score(preset(name, seed), data.X_train[:, cols], data.y_train[axis],
                                      data.X_test[:, cols], data.y_test[axis])
            except ValueError as err:  # a learner refusing the data is reported, not fatal
                row, pred = {"error": str(err)}, np.full(len(data.y_test[axis]), np.nan)
            rows.append({"axis": axis, "learner": name, **row, "inputs": ";".join(names)})
            preds[name] = pred
        extra[axis] = {"inputs": names, "pred": preds}
    return rows, extra


def plot(path: Path, data, extra, axis: str = "Z", show=("anfis-fcm", "ann", "mlr", "lssvm")):
    """Test-run drift (truth) with predictions, and residuals, against time in hours."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = data.t_test / 3600.0
    y = data.y_test[axis]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    a1.plot(t, y, "k", lw=2, label=f"true {axis} drift")
    for name in show:
        if name in extra[axis]["pred"]:
            a1.plot(t, extra[axis]["pred"][name], lw=1, label=name)
            a2.plot(t, extra[axis]["pred"][name] - y, lw=1, label=name)
    a1.set_ylabel(f"{axis} drift [um]")
    a1.legend(fontsize=8)
    a2.set_ylabel("prediction - truth [um]")
    a2.set_xlabel("time [h] (spindle-duty-cycle)")
    a2.axhline(0, color="k", lw=0.5)
    fig.suptitle("Seed 001 protocol on cframe-vmc: 4 gm0n-fcm inputs from dense surface sensors")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def markdown(rows, extra, data) -> str:
    """The report: our table, the seed's rows, the inputs, and what differs and why."""
    z = {r["learner"]: r for r in rows if r["axis"] == "Z"}
    best = min((r for r in rows if r["axis"] == "Z" and "test_rmse" in r), key=lambda r: r["test_rmse"])
    anfis = z.get("anfis-fcm", {}).get("test_rmse", np.inf)
    better = [n for n, r in z.items() if r.get("test_rmse", np.inf) < anfis]
    bad = [n for n, r in z.items() if not r.get("test_nse", -1.0) >= 0.0]
    i = data.info
    lines = [
        "# Seed 001 protocol on the twin",
        "",
        f"Machine `{i['machine']}`, mesh `{i['mesh']}` ({i['mesh_nodes']} nodes); train `{i['train']}`, test "
        f"`{i['test']}`; {i['n_grid']} virtual surface sensors every {i['spacing_m'] * 1000:.0f} mm on "
        "carrier, column and test bar; inputs = measured temperature rises (noisy, quantised), target = true "
        "drift; `gm0n-fcm` picks 4 inputs on the training run for each axis.",
        "",
        "Inputs picked: " + "; ".join(f"{a}: `{', '.join(e['inputs'])}`" for a, e in extra.items()),
        "",
        markdown_table(SEED_ROWS + rows, COLUMNS, HEADERS),
        "",
        "## What differs from the seed, and why",
        "",
        f"- Best twin learner on Z: `{best['learner']}`, test RMSE {best['test_rmse']:.2f} um, NSE "
        f"{best['test_nse']:.3f} (seed: FCM-ANFIS 4 inputs 1.41 um / 0.976, ANN 2.61 um / 0.901). "
        + (f"Twin `anfis-fcm`: {z['anfis-fcm']['test_rmse']:.2f} um; twin `ann`: {z['ann']['test_rmse']:.2f} um."
           if "test_rmse" in z.get("anfis-fcm", {}) and "test_rmse" in z.get("ann", {}) else ""),
        f"- Learners beating twin `anfis-fcm` on Z: {', '.join(f'`{n}`' for n in better) or 'none'}. The twin is "
        "linear, one-way coupled thermoelasticity with constant heat-transfer coefficients, so the drift is a "
        "linear functional of the temperature field: a linear model on a few well-placed temperatures has no "
        "model error to make up, whereas the real machine's nonlinearities (speed-dependent bearing preload and "
        "heat, convection changing with speed, joints) are what ANFIS's rules buy in the seed. With 6 rules "
        "ANFIS fits the training run more closely (lower train RMSE) and, presumably, extrapolates worse to "
        "the duty cycle's 4000 rpm and re-heating phases, whose temperature patterns the training run never shows.",
        "- Sensor noise and quantisation are the twin's instrument model, not the seed's camera (about "
        "0.1 degC NETD averaged over pixels); the seed's spots are on the carrier only and come from a camera "
        "1.5 m away, ours are 1 mm inside carrier, column and test-bar faces.",
        "- The twin's geometry is solid boxes with assumed proportions (the seed gives no drawings), so "
        "time constants and the split between fast (spindle, bar) and slow (column) growth differ; the "
        "seed's test set also had different ambient history, which the twin holds at 20 degC.",
        "- Training here uses all training samples for one fit (no checking set or early stopping), a fixed "
        "100 epochs for ANFIS (seed: 9 iterations, chosen by convergence), and seeded random states.",
        f"- Learners with test NSE < 0 on Z (worse than predicting the mean): {', '.join(f'`{n}`' for n in bad) or 'none'}. "
        "The grey models simulate the accumulated series forward from the first sample (GM(1,1) ignores the "
        "temperatures; GM(1,N)/GMC(1,N) fitted by least squares can have an unstable exponential that "
        "diverges over a run of 1000+ samples, here already on the training run), and grid ANFIS with 16 rules extrapolates outside the "
        "training range; they are run with the registry's defaults, not tuned.",
        "- Y: reported for completeness; the seed reports only Z for its models.",
    ]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    args = parse_args(NAME, __doc__, argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    print(f"simulating (or reading cached runs) in {out} ...", flush=True)
    data = build_data(out, resolution="coarse" if args.quick else "default", seed=args.seed)
    print(f"{len(data.candidates)} candidate sensors; fitting {len(learners.LEARNERS)} learners per axis ...",
          flush=True)
    rows, extra = run_study(data, seed=args.seed)
    write_csv(out / "seed001.csv", SEED_ROWS + rows)
    (out / "seed001.md").write_text(markdown(rows, extra, data))
    plot(out / "seed001.png", data, extra)
    print(markdown_table(SEED_ROWS + rows, COLUMNS, HEADERS))
    print(f"wrote {out / 'seed001.md'}, seed001.csv, seed001.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
