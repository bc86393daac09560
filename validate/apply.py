"""Apply a diagnosis: rerun the twin with the top candidate at its fitted strength, and the RMSE
per channel before and after (plain, and with the material expansion the diagnosis fitted)."""

from __future__ import annotations

import numpy as np

from learners.metrics import rms
from validate.channels import GROUPS, resampler
from validate.signatures import Engine, with_effect


def apply_top(d, machine, scenario, mm=None):
    """Rerun the twin with the top candidate(s) at the fitted strength.

    Returns (model after, model after with the material expansion fitted, the equivalent
    ``--effects``/``--set`` arguments); model arrays are (nt, nch) on the measurement's grid. The
    second is the same rerun with each material's expansion coefficient scaled by the nuisance
    the diagnosis fitted together with the candidate (None when it fitted none), from the same
    run's exact expansion sensitivities; the first is what the printed arguments reproduce."""
    top = d.candidates[0]
    spec = d.spec
    for eff, vals in top["values_si"].items():
        spec = with_effect(spec, eff, vals)
    fit = next((f for f in d.fits if set(f.effects) == set(top["values_si"])), None)
    coef = d.expansion_fit(fit.response) if d.expansion_fit is not None and fit is not None and d.expansion else {}
    same_mesh = d.twin is not None and (mm is None or mm is d.twin.mm)
    engine = Engine(machine, scenario, mm=mm, sensors=d.sensor_points, prepared=d.twin if same_mesh else None)
    observed, responses = engine.observe_with_expansion(spec, list(coef))
    interp = resampler(engine.times, d.times)
    after = interp(observed)
    # drift is linear in each alpha for the rerun's temperatures: the calibrated rerun is exact
    calibrated = after + sum(c * interp(r) for c, r in zip(coef.values(), responses)) if coef else None
    args = ["--effects", ",".join(f"+{e}" for e in top["values_si"])]
    for eff, vals in top["parameters"].items():
        args += [f"--set {eff}.{p}={v.replace(' ', '')}" for p, v in vals.items()]
    return after, calibrated, args


def format_before_after(d, after: np.ndarray, calibrated: np.ndarray | None = None) -> str:
    """Per-channel RMSE before and after applying the top candidate; with ``calibrated`` (the
    rerun with the fitted material expansion) two more columns: the baseline and the rerun, each
    with the expansion the diagnosis fitted."""
    rms_after = rms(d.measured - after, axis=0)
    head = f"{'channel':<32} {'unit':>4} {'before':>9} {'after':>9} {'change':>8}"
    extra = calibrated is not None and d.calibrated_rmse is not None
    if extra:
        head += f" {'before+a':>9} {'after+a':>9} {'change':>8}"
        rms_cal = rms(d.measured - calibrated, axis=0)
    lines = [head]
    for i, (c, g, b, a) in enumerate(zip(d.channels, d.groups, d.baseline_rmse, rms_after)):
        line = f"{c:<32} {GROUPS[g][1]:>4} {b:>9.4g} {a:>9.4g} {(a / b - 1) if b else 0:>+8.0%}"
        if extra:
            bc, ac = d.calibrated_rmse[i], rms_cal[i]
            line += f" {bc:>9.4g} {ac:>9.4g} {(ac / bc - 1) if bc else 0:>+8.0%}"
        lines.append(line)
    if extra:
        lines.append("+a: with the thermal expansion of each material fitted as the diagnosis did ("
                     + ", ".join(f"{m} {c:+.1%}" for m, c in d.expansion.items()) + " for the baseline)")
    return "\n".join(lines)
