"""Seed 001's protocol on the twin: train on the 9000 rpm heat/cool test, test on the duty cycle.

``python -m validate.studies.seed001 [--quick] [-o DIR] [--camera [POSE]]`` simulates
``cframe-vmc`` on ``spindle-heat-cool-9000`` (train) and ``spindle-duty-cycle`` (test) with a dense
grid of virtual surface sensors (50 mm pitch) on the carrier, column and test bar, lets
``gm0n-fcm`` pick 4 of them on the training run (per target axis), fits every registered learner
on the measured temperature rises [degC] against the true drift [um] and scores it on the test
run. Writes ``seed001.md``, ``seed001.csv`` and ``seed001.png`` (test Z drift, predictions and
residuals) to the output folder. With ``--camera`` the inputs are the seed's own: 525 virtual
spots averaged from the frames of a thermal camera at ``carrier-front`` (1.5 m from the carrier),
and ``frames.png`` shows the thermograms with the spots and the 4 picked ones.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import learners
from twin.plotting import save_figure
from validate.studies.common import data_main, fit_score, markdown_table, preset, score_units, select, write_csv

NAME = "seed001"
SEED_ROWS = [  # seed 001 Table 5 (FCM-ANFIS 4) and Table 6, Z axis, test set; um
    {"axis": "Z", "learner": "seed 001 FCM-ANFIS 4 (6 rules)", "train_rmse": 0.6069, "train_nse": 0.9939,
     "test_rmse": 1.4139, "test_nse": 0.9764, "test_r": 0.9912, "test_max_abs_residual": 2.9521},
    {"axis": "Z", "learner": "seed 001 ANN 4-10-1", "test_rmse": 2.6071, "test_nse": 0.9012, "test_r": 0.9807,
     "test_max_abs_residual": 7.0210},
]
COLUMNS = ["axis", "learner", "train_rmse", "train_nse", "test_rmse", "test_nse", "test_r", "test_max_abs_residual",
           "test_improvement_pct"]
HEADERS = ["axis", "learner", "train RMSE um", "train NSE", "test RMSE um", "test NSE", "test R", "test max|res| um",
           "improvement %"]


def run_study(data, seed: int = 0, learner_names=None, axes=("Z", "Y"), k: int = 4) -> tuple[list[dict], dict]:
    """Rows of scores (one per axis and learner) and, per axis, the selected names and test predictions."""
    learner_names = list(learner_names or learners.LEARNERS)
    cand = data.candidate_columns
    rows, extra = [], {}
    for axis in axes:
        picked = select(data.X_train[:, cand], data.y_train[axis], k, data.candidates, seed=seed)
        cols = [cand[i] for i in picked]
        names = [data.names[c] for c in cols]
        preds, models = {}, {}
        for name in learner_names:
            est = preset(name, seed)
            try:
                row, pred = fit_score(est, data.X_train[:, cols], data.y_train[axis],
                                      data.X_test[:, cols], data.y_test[axis])
                models[name] = est
            except ValueError as err:  # a learner refusing the data is reported, not fatal
                row, pred = {"error": str(err)}, np.full(len(data.y_test[axis]), np.nan)
            rows.append({"axis": axis, "learner": name, **row, "inputs": ";".join(names)})
            preds[name] = pred
        extra[axis] = {"inputs": names, "cols": cols, "pred": preds, "models": models}
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
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def _linear_slopes(X, y) -> np.ndarray:
    """Slopes [um/degC] of one least-squares linear model (the `mlr` baseline) on (X, y)."""
    A = np.column_stack([np.ones(len(y)), X])
    return np.linalg.lstsq(A, y, rcond=None)[0][1:]


def learner_note(name: str, row: dict, est, X_train, y_train, X_test) -> str | None:
    """Why a learner is unfit for this protocol, computed from the fitted model; ``None`` if it is fit
    (test NSE >= 0 and no error)."""
    if "error" in row:
        return f"`{name}` refused the data: {row['error']}"
    if row.get("test_nse", -1.0) >= 0.0 or est is None:
        return None
    with np.errstate(all="ignore"):
        blind = np.allclose(est.predict(X_test), est.predict(np.zeros_like(X_test)))
    if blind:
        coef = "".join(f", fitted {a[:-1]} = {getattr(est, a):.3g}" for a in ("a_", "b_")
                       if hasattr(est, a) and np.ndim(getattr(est, a)) == 0)
        return (f"`{name}` ignores the temperatures (its test prediction is unchanged with every input set to 0{coef}): "
                "it replays the time course fitted to the training drift from the start of the test run, and the "
                "duty cycle does not follow that course. A single-series forecaster is unfit for a cross-scenario "
                "test; this is the method, not a defect.")
    if hasattr(est, "rule_coefs_"):
        rule = float(np.max(np.abs(est.rule_coefs_)))
        lin = float(np.max(np.abs(_linear_slopes(X_train, y_train))))
        lo, hi = X_train.min(axis=0), X_train.max(axis=0)
        outside = float(np.mean(np.any((X_test < lo) | (X_test > hi), axis=1)))
        n_par = est.rule_coefs_.size + est.rule_intercepts_.size
        head = (f"`{name}`: {est.n_rules_} rules with {n_par} least-squares consequent parameters, fitted on one "
                "heating/cooling trajectory along which the inputs move almost together; the largest rule slope is "
                f"{rule:.3g} um/degC against {lin:.3g} um/degC for one linear model")
        box = f"{100 * outside:.0f}% of test samples lie outside the training range box"
        nse = f"train NSE {row['train_nse']:.3f}, test NSE {row['test_nse']:.2f}"
        if rule > 3 * lin:    # slopes that only cancel along the training trajectory
            return (f"{head}: the rules cancel each other on the training trajectory and amplify the duty cycle's "
                    f"other temperature combinations ({box}). Many rule consequents on few independent input "
                    f"directions: a limitation of the method on this protocol ({nse}).")
        return (f"{head}, of the same size: the rules do not amplify; the test leaves the training run's "
                f"temperatures ({box}), and the rules extrapolate it no better than they do ({nse}).")
    return (f"`{name}`: test NSE {row['test_nse']:.2f} (train NSE {row['train_nse']:.3f}); it does not transfer from "
            "the heating/cooling run to the duty cycle.")


def _anfis_train_text(z: dict, best: dict) -> str:
    """How twin ``anfis-fcm`` fits the training run against the best test learner, from the rows."""
    anfis = z.get("anfis-fcm", {})
    if "train_rmse" not in anfis or "train_rmse" not in best or best["learner"] == "anfis-fcm":
        return ""
    closer = anfis["train_rmse"] < best["train_rmse"]
    return (f"Twin `anfis-fcm` fits the training run {'more' if closer else 'less'} closely than `{best['learner']}` "
            f"(train RMSE {anfis['train_rmse']:.2f} against {best['train_rmse']:.2f} um) and tests "
            f"{'worse' if anfis['test_rmse'] > best['test_rmse'] else 'as well'} (test RMSE {anfis['test_rmse']:.2f} "
            f"against {best['test_rmse']:.2f} um): the duty cycle's 4000 rpm and re-heating phases show temperature "
            "patterns the training run never shows.")


def _grey_bounds(models: dict) -> str:
    """' `gm1n`'s development coefficient sits at ...': the grey learners whose response fit pinned
    the coefficient at an end of its search range (``at_bound_``), '' when none did."""
    pinned = [f"`{n}`'s development coefficient sits {m.at_bound_}" for n, m in models.items()
              if getattr(m, "at_bound_", "")]
    return (" In the response fit, " + "; ".join(pinned) + ": pinned there, not fitted.") if pinned else ""


def grey_equation_note(X, y) -> str:
    """The thesis's equation least squares of GM(1,N)/GMC(1,N) on the training run: coefficient and growth."""
    from learners.grey import ago, background, gm1n_retention
    from learners.grey_gmc import gmc_ls_fit, gmc_retention

    z1 = background(ago(y))
    a = float(np.linalg.lstsq(np.column_stack([-z1, ago(X)[1:]]), y[1:], rcond=None)[0][0])
    b1 = gmc_ls_fit(X, y)[0]
    parts = []
    for label, coef, r in (("GM(1,N) a", a, gm1n_retention(a, "difference")),
                           ("GMC(1,N) b_1", b1, gmc_retention(b1, "convolution"))):
        growth = (len(y) - 1) * np.log10(abs(r)) if abs(r) > 1 else 0.0
        parts.append(f"{label} = {coef:.3g} per sample" + (f" (response grows 1e{growth:.0f}-fold over {len(y)} samples)"
                                                          if growth > 3 else " (stable)"))
    return "; ".join(parts)


def markdown(rows, extra, data) -> str:
    """The report: our table, the seed's rows, the inputs, and what differs and why."""
    z = {r["learner"]: r for r in rows if r["axis"] == "Z"}
    best = min((r for r in rows if r["axis"] == "Z" and "test_rmse" in r), key=lambda r: r["test_rmse"])
    anfis = z.get("anfis-fcm", {}).get("test_rmse", np.inf)
    better = [n for n, r in z.items() if r.get("test_rmse", np.inf) < anfis]
    bad = [n for n, r in z.items() if not r.get("test_nse", -1.0) >= 0.0]
    ez = extra.get("Z", {})
    cols = ez.get("cols")
    notes = []
    if cols is not None:
        Xtr, ytr, Xte = data.X_train[:, cols], data.y_train["Z"], data.X_test[:, cols]
        for name in bad:
            note = learner_note(name, z[name], ez.get("models", {}).get(name), Xtr, ytr, Xte)
            if note:
                notes.append(note)
        grey_note = grey_equation_note(Xtr, ytr)
    else:
        grey_note = "(not computed)"
    i = data.info
    camera = i.get("mode") == "camera"
    if camera:
        inputs = (f"{i['n_grid']} virtual spots ({i['spot_size_px']} x {i['spot_size_px']}-pixel groups on "
                  f"{i['lines']} lines across the `{i['subject']}`) from a 320 x 240 thermal camera at "
                  f"`{i['pose']}` (FLIR S65 model: NETD 0.08 K, 3-D noise, offset drift, 14-bit counts, the "
                  "camera's own emissivity and reflection settings); inputs = apparent temperature rises of the "
                  "spots")
    else:
        inputs = (f"{i['n_grid']} virtual surface sensors every {i['spacing_m'] * 1000:.0f} mm on carrier, column "
                  "and test bar; inputs = measured temperature rises (noisy, quantised)")
    lines = [
        "# Seed 001 protocol on the twin" + (" (inputs from the thermal camera)" if camera else ""),
        "",
        f"Machine `{i['machine']}`, mesh `{i['mesh']}` ({i['mesh_nodes']} nodes); train `{i['train']}`, test "
        f"`{i['test']}`; {inputs}, target = true drift; `gm0n-fcm` picks 4 inputs on the training run for each axis.",
        "",
        "Inputs picked: " + "; ".join(f"{a}: `{', '.join(e['inputs'])}`" for a, e in extra.items()),
        "",
        "Seed 001 Table 6 (ANFIS and ANN, Z, test run) is in the first rows, ours below:",
        "",
        markdown_table(SEED_ROWS + rows, COLUMNS, HEADERS),
        "",
        *(["![thermograms of the training run with the 525 spots; the 4 picked for Z outlined](frames.png)", ""]
          if camera else []),
        "## What differs from the seed, and why",
        "",
        f"- Best twin learner on Z: `{best['learner']}`, test RMSE {best['test_rmse']:.2f} um, NSE "
        f"{best['test_nse']:.3f} (seed: FCM-ANFIS 4 inputs 1.41 um / 0.976, ANN 2.61 um / 0.901). "
        + (f"Twin `anfis-fcm`: {z['anfis-fcm']['test_rmse']:.2f} um; twin `ann`: {z['ann']['test_rmse']:.2f} um."
           if "test_rmse" in z.get("anfis-fcm", {}) and "test_rmse" in z.get("ann", {}) else ""),
        f"- Learners beating twin `anfis-fcm` on Z: {', '.join(f'`{n}`' for n in better) or 'none'}. The twin's "
        "drift is a linear functional of its temperature field (linear, one-way coupled thermoelasticity); its heat "
        "inputs and films depend on the spindle speed but not on temperature, and it has no preload change and no "
        "joints, so a linear model on a few well-placed temperatures has little model error to make up (four "
        "sensors do not hold the whole field), whereas the real machine's preload, joints and other "
        "nonlinearities are what ANFIS's rules may buy in the seed. " + _anfis_train_text(z, best),
        ("- The inputs come, as in the seed, from a camera 1.5 m from the carrier: the spots average 25 pixels, "
         "which cuts the temporal noise from 0.08 K to about 0.016 K but not the fixed pattern, the banding or the "
         "camera's slowly drifting offset, which moves every spot together; and the carrier's spots see only its "
         "front face, not the test bar, whose spots the seed found most influential for Z (its Fig. 11)."
         if camera else
         "- Sensor noise and quantisation are the twin's instrument model, not the seed's camera (about "
         "0.1 degC NETD averaged over pixels); the seed's spots are on the carrier only and come from a camera "
         "1.5 m away, ours are 1 mm inside carrier, column and test-bar faces (`--camera` takes them from frames)."),
        "- The twin's geometry is solid boxes with assumed proportions (the seed gives no drawings), so "
        "time constants and the split between fast (spindle, bar) and slow (column) growth differ; the "
        "seed's test set also had different ambient history, which the twin holds at 20 degC.",
        "- ANFIS is trained as MATLAB's `anfis` with checking data: every 5th 5-min block of the training run is "
        "held out and the epoch of least checking error is kept"
        + (f" (`anfis-fcm` on Z: epoch {extra['Z']['models']['anfis-fcm'].best_epoch_} of at most 100; seed: 9 "
           "iterations)" if "anfis-fcm" in extra.get("Z", {}).get("models", {}) else "")
        + ". The checking blocks come from the same heating/cooling run, so the checking error cannot see the gap "
        "to the duty cycle. Seeded random states throughout.",
        f"- Learners with test NSE < 0 on Z (worse than predicting the mean): {', '.join(f'`{n}`' for n in bad) or 'none'}. "
        "Per-learner notes (computed from the fitted models):",
        *[f"  - {note}" for note in notes],
        "- Grey models `gm1n`/`gmc1n` are fitted by least squares of their simulated response (the fitness the "
        "thesis's PSO minimises: the linear coefficients exactly, the development coefficient by a log grid refined "
        "by Brent's method, a minimum to the grid's resolution), with a stable development coefficient. The thesis's least "
        "squares of the grey *equation* on accumulated series (`fit_method='equation'`, Table 6-3) is refused on "
        f"this 1141-sample record: on Z it gives {grey_note}.{_grey_bounds(ez.get('models', {}))} Its regressors are "
        "accumulated sums that grow with the "
        "record, so the fit pushes the development coefficient to about 0 with a noise-set sign; the seeds fit "
        "grey models on a handful of readings, where this does not arise.",
        "- Y: reported for completeness; the seed reports only Z for its models.",
    ]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    return data_main(NAME, __doc__, argv, _run, ("seed001.csv", "seed001.md", "seed001.png", "frames.png"))


def _run(args, out, data) -> int:
    print(f"{len(data.candidates)} candidate sensors; fitting {len(learners.LEARNERS)} learners per axis ...",
          flush=True)
    rows, extra = run_study(data, seed=args.seed)
    write_csv(out / "seed001.csv", SEED_ROWS + rows, score_units("um"))   # train_rmse_um, test_rmse_um, ...
    (out / "seed001.md").write_text(markdown(rows, extra, data))
    plot(out / "seed001.png", data, extra)
    written = "seed001.csv, seed001.png"
    if data.info.get("mode") == "camera":
        from validate.studies.camera_figures import plot_frames

        plot_frames(out / "frames.png", data, extra["Z"]["inputs"])
        written += ", frames.png"
    print(markdown_table(SEED_ROWS + rows, COLUMNS, HEADERS))
    print(f"wrote {out / 'seed001.md'}, {written}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
