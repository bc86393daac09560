"""Apply a diagnosis: rerun the twin with the top candidate at its fitted value, and the RMSE per
channel before and after (plain, and with the material expansion the diagnosis fitted)."""

from __future__ import annotations

import numpy as np

from learners.metrics import rms
from twin.errors import InputError, describe
from validate.channels import residual_unit


def check_diagnosis(d, source: str, fitted: bool = False) -> None:
    """``d`` is a :class:`validate.diagnose.Diagnosis` (with a fitted candidate when ``fitted``)."""
    from validate.diagnose import Diagnosis

    if not isinstance(d, Diagnosis):
        raise InputError(source, "d", f"expected a diagnosis (validate.diagnose.diagnose), got {describe(d)}")
    if fitted and not d.fits:
        raise InputError(source, "d", "the diagnosis fitted no candidate: there is nothing to apply")


def check_flat(d, values, source: str, field: str) -> np.ndarray:
    """``values``: a flat model vector of the diagnosis (every channel of every record, as
    :func:`apply_top` returns), finite."""
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        v = None
    n = d.evidence.measured.shape
    if v is None or v.shape != n:
        raise InputError(source, field, f"expected the flat model of the diagnosis ({n[0]} values, apply_top's), got "
                                        + (describe(values) if v is None else f"shape {v.shape}"))
    if not np.all(np.isfinite(v)):
        raise InputError(source, field, "is not finite (NaN or inf)")
    return v


def apply_top(d):
    """Rerun the twin with the top candidate(s) at the fitted values, on the diagnosing mesh.

    Returns (model after, model after with the material expansion fitted, the equivalent
    ``--effects``/``--set`` arguments); the model arrays are flat over every record (split them
    with ``d.evidence.split``). The second is the same rerun with each material's expansion
    coefficient scaled by the nuisance the diagnosis fitted together with the candidate (None
    when it fitted none), from the same run's exact expansion sensitivities; the first is what
    the printed arguments reproduce; the diagnosis's own records and prepared twin are used."""
    check_diagnosis(d, "apply_top", fitted=True)
    f = d.fits[0]
    spec = f.in_model(d.spec)
    coef = d.expansion_fit(f.response) if d.materials else {}
    after, responses = d.evidence.observe_with_expansion(spec, list(coef))
    # drift is linear in each alpha for the rerun's temperatures: the calibrated rerun is exact
    calibrated = after + sum(c * r for c, r in zip(coef.values(), responses)) if coef else None
    added = [c.effect for c in f.candidates if not c.in_model]
    args = ["--effects", ",".join(f"+{e}" for e in added)] if added else []
    if any(c.kind == "custom" for c in f.candidates):
        args = ["--effects-file", "FILE"] + args
    for c, v in zip(f.candidates, f.values):
        from twin.units import format_quantity
        args.append(f"--set {c.effect}.{c.parameter}={format_quantity(float(f'{v:.4g}'), c.dimension).replace(' ', '')}")
    return after, calibrated, args


def format_before_after(d, after: np.ndarray, calibrated: np.ndarray | None = None) -> str:
    """Per-channel RMSE before and after applying the top candidate (``after`` flat); with
    ``calibrated`` (the rerun with the fitted material expansion) two more columns: the baseline
    and the rerun, each with the expansion the diagnosis fitted."""
    check_diagnosis(d, "format_before_after")
    after = check_flat(d, after, "format_before_after", "after")
    if calibrated is not None:
        calibrated = check_flat(d, calibrated, "format_before_after", "calibrated")
    ev = d.evidence
    meas = ev.measured
    rms_after = ev.per_channel(meas - after)
    w = max([32] + [len(c) for c in d.channels])    # long sensor names keep the columns aligned
    head = f"{'channel':<{w}} {'unit':>4} {'before':>9} {'after':>9} {'change':>8}"
    extra = calibrated is not None
    if extra:
        head += f" {'before+a':>9} {'after+a':>9} {'change':>8}"
        rms_cal = ev.per_channel(meas - calibrated)
        before_cal = d.calibrated_rmse
    lines = [head]
    for i, (c, g, b, a) in enumerate(zip(d.channels, d.groups, d.baseline_rmse, rms_after)):
        line = f"{c:<{w}} {residual_unit(g):>4} {b:>9.4g} {a:>9.4g} {(a / b - 1) if b else 0:>+8.0%}"
        if extra:
            bc, ac = before_cal[i], rms_cal[i]
            line += f" {bc:>9.4g} {ac:>9.4g} {(ac / bc - 1) if bc else 0:>+8.0%}"
        lines.append(line)
    if extra:
        lines.append("+a: with the thermal expansion of each material fitted within its band as the diagnosis did ("
                     + ", ".join(f"{m} {c:+.1%}" for m, c in d.expansion.items()) + " for the baseline)")
    return "\n".join(lines)


def group_rms(d, flat: np.ndarray, group: str) -> float:
    """RMS over every sample of one channel group of a flat vector."""
    if group not in d.groups:
        raise InputError("group_rms", "group", f"no group {group!r} in the diagnosis; known: "
                                               f"{', '.join(dict.fromkeys(d.groups))}")
    flat = check_flat(d, flat, "group_rms", "flat")
    return float(rms(flat[d.evidence.group_mask(group)]))
