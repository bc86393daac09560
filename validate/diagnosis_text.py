"""A diagnosis in words and JSON: the reasoning per channel and phase, the printed ranking, and the
``--json`` document."""

from __future__ import annotations

import numpy as np

from validate.channels import GROUPS as CHANNEL_GROUPS, RUN_GROUPS, residual_unit
from validate.verdict import beyond_text, ratio_text, share_text


def reasoning(d, response: np.ndarray, top_channels: int = 4) -> dict:
    """Where a candidate's response g (flat) explains the residual r: per channel and per phase.

    With weighted squares e = (w r)^2 before and (w (r - g))^2 after (nuisance fitted to each), for
    a set S of samples (a channel's column, or a phase's rows over every channel of its record):

    * ``share``: sum_S e_before / SSE_0, the part of the baseline residual lying in S;
    * ``explained``: 1 - sum_S e_after / sum_S e_before, the fraction of it removed (negative:
      the candidate makes S worse).

    ``channels``: the ``top_channels`` channels carrying the largest explained share
    (share x explained), i.e. the evidence for the candidate; ``phases``: every phase.
    """
    ev = d.evidence
    before = ev.split((d.residual_after(np.zeros_like(response)) * d.weights_flat) ** 2)
    after = ev.split((d.residual_after(response) * d.weights_flat) ** 2)
    total = float(sum(b.sum() for b in before)) or 1.0

    def cell(b, a):
        sb = float(b.sum())
        return {"share": sb / total, "explained": (1 - float(a.sum()) / sb) if sb > 0 else 0.0}

    names = ev.channel_names()
    chans, phases, k = [], [], 0
    for rec, b, a in zip(ev.records, before, after):
        for j in range(b.shape[1]):
            chans.append({"channel": names[k], **cell(b[:, j], a[:, j])})
            k += 1
        for p in rec.phases:
            sel = p.mask(rec.times)
            if sel.any():
                label = f"{p.label} [{rec.label}]" if ev.multiple else p.label
                phases.append({"kind": p.kind, "phase": label, "start_h": (p.start + rec.t0) / 3600,
                               "end_h": (p.end + rec.t0) / 3600,
                               **cell(b[sel], a[sel])})
    chans.sort(key=lambda x: -x["share"] * x["explained"])
    return {"channels": chans[:top_channels], "phases": phases}


def _params_text(c: dict) -> str:
    """``effect.param=value unit``, each member fitted at a bound of its range flagged with the range."""
    bound = set(c.get("at_bound", ()))
    ranges = c.get("bounds", {})
    out = []
    for e, vals in c["parameters"].items():
        for p, v in vals.items():
            flag = ""
            if f"{e}.{p}" in bound:
                lo, hi = ranges.get(e, {}).get(p, ("?", "?"))
                flag = f" (AT ITS BOUND, range {lo} to {hi})"
            out.append(f"{e}.{p}={v}{flag}")
    return ", ".join(out)


def _unit(group: str) -> str:
    return residual_unit(group)


def format_diagnosis(d, top: int = 8) -> str:
    """A readable summary: the residual against noise and model error, the nuisance, the ranking
    (the ``top`` candidates, every candidate of the user's ``--effects-file`` wherever it ranks,
    and how many more the JSON lists), the regions and the verdict."""
    names, groups = d.channels, d.groups
    base, err = d.baseline_rmse, d.model_error_rms
    lines = [f"Measurements: {', '.join(d.evidence.labels)}; {len(names)} channels, "
             f"effective samples {d.n_eff:.0f}, {d.runs} twin runs",
             "Baseline RMSE per channel (the model read through its instruments' lag and bias, before any fit; "
             "twin compare holds the model's true values):"]
    for g in list(CHANNEL_GROUPS) + list(RUN_GROUPS):
        idx = [i for i, k in enumerate(groups) if k == g]
        if idx:
            lines.append(f"  {g} [{_unit(g)}]: " + ", ".join(f"{names[i].split(':', 1)[1]} {base[i]:.3g}" for i in idx))
            if err is not None:
                what = (f"mesh error estimate ({d.error_resolution} vs the diagnosing mesh)" if d.error_resolution
                        else "model error (given)")
                lines.append(f"    {what}: "
                             + ", ".join(f"{names[i].split(':', 1)[1]} {err[i]:.3g}" for i in idx))
    if err is None:
        lines.append("  model error: not estimated (no --error-mesh run): the factors below compare with noise only")
    for g, f in d.residual_factor.items():
        noise, e = d.levels[g]
        after = d.residual_factor_after.get(g)
        envelope = (f"noise and model error (noise {noise:.2g} {_unit(g)}, model error {e:.2g} {_unit(g)})"
                    if e is not None else f"noise (noise {noise:.2g} {_unit(g)}, model error not estimated)")
        again = ""
        if after is not None and d.levels_after:
            again = (f" (against the model error of the model with it, {d.levels_after[g][1]:.2g} {_unit(g)}, "
                     "estimated again)")
        lines.append(f"  {g}: residual {ratio_text(f)} {envelope}"
                     + (f"; {ratio_text(after)} after the top candidate{again}" if after is not None else ""))
    if d.beyond_model_error is not None:
        lines.append(f"  top candidate's fitted change: {beyond_text(d.beyond_model_error)} what the model error alone "
                     f"produces along its signature")
    if d.nuisance_baseline:
        lines.append("Nuisance (thermal expansion within each material's band), baseline: " + nuisance_text(d.nuisance_baseline))
        if d.nuisance is not d.nuisance_baseline and d.verdict in ("explained", "partly_explained"):
            lines.append("  with the top candidate: " + nuisance_text(d.nuisance))
    for gap in d.missing_channels:
        lines.append("Channels: " + gap["note"])
    if d.not_used:
        lines.append("Not used (no diagnosis holds them against the model yet): " + "; ".join(d.not_used))
    lines.append("")
    w = max([44] + [len(c["effect"]) for i, c in enumerate(d.candidates) if i < top or c["kind"] == "custom"])
    # long names keep the columns aligned
    margin, share = getattr(d, "test", (10.0, 0.5))
    lines += [f"explained: share of the weighted residual {share_text(d.residual_factor)} the candidate removes "
              f"(negative: it makes those groups worse, its fit paid for by the others); "
              f"dBIC: BIC units better than 'nothing missing'",
              "BIC wt: Schwarz weight among these candidates and 'nothing missing' (relative: the best of a poor set "
              "still holds about 1.00; not the probability that it is the cause)",
              f"sig: passes the significance test (dBIC >= {margin:g} and explained >= {share:.0%}); AT ITS BOUND: "
              f"fitted at a bound of its range"]
    head = (f"{'rank':>4}  {'candidate':<{w}} {'kind':<9} {'explained':>9} {'dBIC':>8} {'BIC wt':>6} {'sig':>3}  "
            f"parameters")
    lines += [head, "-" * len(head)]
    # the top ones, and every candidate the user brought (--effects-file) wherever it ranks
    shown = [(i, c) for i, c in enumerate(d.candidates, 1) if i <= top or c["kind"] == "custom"]
    for i, c in shown:
        sig = "yes" if c.get("significant") else "no"
        lines.append(f"{i:>4}  {c['effect']:<{w}} {c['kind']:<9} {c['explained']:>8.1%} {c['delta_bic']:>8.1f} "
                     f"{c['confidence']:>6.2f} {sig:>3}  {_params_text(c)}")
        if i <= 3:
            lines += _reasoning_lines(c)
    if len(d.candidates) > len(shown):
        lines.append(f"  ({len(d.candidates) - len(shown)} more candidates ranked lower; --json lists them all)")
    if d.regions:
        lines += ["", "Where on the machine a generic heat input explains the residual best (share of the weighted "
                      "residual, all groups):"]
        rw = max([22] + [len(r["region"]) for r in d.regions])
        lines += [f"  {r['region']:<{rw}} {r['power_W']:>8.3g} W {r['schedule'].replace('_', ' '):<11} explains "
                  f"{r['explained']:.0%}" for r in d.regions]
    lines += ["", d.message]
    return "\n".join(lines)


def nuisance_text(nuisance: dict) -> str:
    return ", ".join(f"{m} {v['change']:+.1%} (band +-{v['band']:.0%}{', AT ITS BOUND' if v['at_bound'] else ''})"
                     for m, v in nuisance.items())


def _reasoning_lines(c: dict, pad: str = " " * 6) -> list[str]:
    """The why of one candidate: channels and phases it explains (share of residual, explained)."""
    why = c.get("reasoning", {})
    out = []
    if why.get("channels"):
        out.append(pad + "channels (explained/share of residual): " + ", ".join(
            f"{x['channel']} {x['explained']:.0%}/{x['share']:.0%}" for x in why["channels"]))
    for kind in ("spindle", "c_axis", "ambient"):
        cells = [x for x in why.get("phases", []) if x["kind"] == kind]
        if cells:
            out.append(pad + f"{kind} phases: " + ", ".join(
                f"{x['phase']} ({x['start_h']:.3g}-{x['end_h']:.3g} h) {x['explained']:.0%}/{x['share']:.0%}"
                for x in cells))
    if c.get("indistinguishable_from"):
        out.append(pad + "cannot be told apart from: " + ", ".join(c["indistinguishable_from"]))
    return out


# what the JSON's unitless numbers are (the document's "dimensionless" entry)
DIMENSIONLESS = {
    "residual_factor": "ratio: RMS of the group's residual / sqrt(noise^2 + model error^2); noise alone where "
                       "levels.<group>.model_error is null (not estimated)",
    "residual_factor_after": "ratio, as residual_factor, of the residual the top candidate leaves; against "
                             "levels_after when that is not null (the model error of the model with the "
                             "candidate, estimated again), else against levels",
    "beyond_model_error": "ratio: the top candidate's fitted change / the change the model error alone produces "
                          "along its signature",
    "candidates[].explained": "fraction (0-1, 1 = 100 %) of the weighted residual of the groups above noise and "
                              "model error (of every group when none is)",
    "candidates[].explained_all": "fraction (0-1) of the weighted residual of every group",
    "candidates[].delta_bic": "BIC units better than 'nothing missing'",
    "candidates[].confidence": "Schwarz (BIC) weight (0-1) among the candidates and 'nothing missing', relative "
                               "to this set: not the probability that the candidate is the cause",
    "nuisance.<material>.change": "fraction of the material's expansion coefficient alpha (0.1 = +10 %); band too",
    "regions[].explained": "fraction (0-1) of the weighted residual of every group",
    "reasoning share, explained": "fractions (0-1) of the weighted residual",
}


def _levels_json(levels: dict) -> dict:
    return {g: {"noise": n, "model_error": e, "model_error_estimated": e is not None, "unit": _unit(g)}
            for g, (n, e) in levels.items()}


def diagnosis_json(d) -> dict:
    """The ``--json`` document (README, "twin diagnose")."""
    names = d.channels
    units = {c: _unit(g) for c, g in zip(names, d.groups)}
    err = d.model_error_rms
    return {
        "verdict": d.verdict,
        "significant": d.significant,
        "named": d.named,
        "message": d.message,
        "measurements": d.evidence.labels,
        "baseline": {"rmse": {c: float(v) for c, v in zip(names, d.baseline_rmse)}, "units": units},
        "residual_factor": d.residual_factor,
        "residual_factor_after": d.residual_factor_after,
        "beyond_model_error": d.beyond_model_error,
        "levels": _levels_json(d.levels),
        "levels_after": _levels_json(d.levels_after) if d.levels_after else None,
        "nuisance": d.nuisance,
        "nuisance_baseline": d.nuisance_baseline,
        "effective_samples": d.n_eff,
        "calibration": {"expansion": d.expansion, "expansion_unit": "fraction of alpha",
                        "rmse": {c: float(v) for c, v in zip(names, d.calibrated_rmse)}, "units": units},
        "model_error_rms": (None if err is None else
                            {"resolution": d.error_resolution, "rmse": {c: float(v) for c, v in zip(names, err)},
                             "units": units}),
        "missing_channels": d.missing_channels,
        "not_used": d.not_used,
        "phases": [{"measurement": r.label, "kind": p.kind, "phase": p.label, "start_s": p.start + r.t0,
                    "end_s": p.end + r.t0} for r in d.evidence.records for p in r.phases],
        "candidates": [_candidate_json(c, units) for c in d.candidates],
        "regions": d.regions,
        "twin_runs": d.runs,
        "dimensionless": DIMENSIONLESS,
    }


def _candidate_json(c: dict, units: dict) -> dict:
    """A candidate for the JSON: its SI values left out (``parameters`` carry them with units), the
    units of ``rmse_after`` beside it."""
    out = {k: v for k, v in c.items() if k != "values_si"}
    out["rmse_after_units"] = units
    return out
