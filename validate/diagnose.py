"""Diagnose: which missing physical effect explains the residual between measurement and twin.

Channels: every temperature sensor [K] and every ISO 230-3 probe [um]. Residual r = measured -
model (model through the sensor lag and bias, no noise), on the measurement's time grid.

Weighting (so both kinds count): each channel group g (temperatures, probes) gets one weight

    w_g = 1 / (s_g sqrt(m_g)),   s_g = max(RMS of the baseline residual over the group, sigma_g),

m_g the number of channels in the group and sigma_g the group's noise level (median over its
channels of sqrt(mean(diff(y)^2) / 2), floored by half a quantisation step). Each group then
carries the same share of the weighted sum of squares SSE = sum (w r)^2, and a group already
at its noise level is not inflated.

Model error: with ``error_resolution`` the baseline is also run on a finer mesh; e_c, the RMS over
time of the difference on channel c, estimates the diagnosing model's discretisation error there,
and the channel's weight becomes w_c = 1 / (sqrt(s_g^2 + e_c^2) sqrt(m_g)) (generalised least
squares with a model-error variance): a channel the coarse model cannot reproduce anyway (a thin
test bar, a sensor beside a bearing) is weak evidence for any candidate.

Nuisance: material data are uncertain by a few %. With ``calibrate_expansion`` (default) the
thermal expansion coefficient of each material of the machine is a free parameter fitted with the
baseline and with every candidate (its response is linear: one extra run per material, profiled
out by projection, :class:`validate.signatures.SignatureFitter`). SSE_0, explained fractions,
RMSE after and the reasoning all refer to residuals with the nuisance fitted.

Scores of a candidate with k fitted parameters and weighted sum of squares SSE_k:

* explained = 1 - SSE_k / SSE_0 (SSE_0: the baseline model);
* BIC_k = n_eff ln(SSE_k / N) + k ln(n_eff), N samples; residuals of a thermal model are strongly
  autocorrelated, so n_eff = N (1 - rho) / (1 + rho) with rho the pooled lag-1 autocorrelation of
  the best candidate's residual (an AR(1) effective sample size). All candidates share n_eff;
* confidence = Schwarz weight exp(-BIC_k/2) / sum_j exp(-BIC_j/2) over the candidates *and* the
  baseline ("nothing missing"); candidates within 6 BIC units of each other, or with weighted
  signatures correlated |corr| > 0.95, are reported as not distinguishable.

Significance: the top candidate is reported as missing only if it beats the baseline by at least
``bic_margin`` (default 10, "very strong" evidence) *and* explains at least ``min_explained``
(default 50 %) of the weighted residual; otherwise the diagnosis says nothing significant is
missing. Pairs are tried among the best singles when none explains ``pair_threshold`` (80 %), and
kept only if the second member passes the same test against the residual the better member
leaves (BIC gain >= ``bic_margin``, >= ``min_explained`` of that residual explained).

Reasoning: for every candidate, the fraction of the weighted residual it removes per channel and
per phase of the inputs (:func:`validate.channels.detect_phases`: spindle on / off / speed change,
ambient rising / falling / steady), next to the share of the residual each cell holds
(:func:`reasoning`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from twin.effects import EFFECTS
from twin.model import ModelSpec, applicable_effects, default_spec
from twin.units import format_quantity
from learners.metrics import rms
from validate.channels import GROUPS as CHANNEL_GROUPS
from validate.channels import input_phases, resampler, stack
from validate.signatures import Engine, Fit, SignatureFitter

GROUPS = ("temperature", "probe")   # the channel groups the diagnosis fits (validate.channels)


@dataclass
class Diagnosis:
    """Result of :func:`diagnose`. Arrays are (nt, nch) on the measurement's time grid."""

    times: np.ndarray
    channels: list[str]          # "temperature:<sensor>" / "probe:<id>"
    groups: list[str]
    measured: np.ndarray
    model: np.ndarray
    weights: np.ndarray
    baseline_rmse: np.ndarray    # per channel, native units
    candidates: list[dict] = field(default_factory=list)
    fits: list[Fit] = field(default_factory=list)
    significant: bool = False
    message: str = ""
    n_eff: float = 0.0
    spec: ModelSpec | None = None
    runs: int = 0
    sensor_points: list = field(default_factory=list)
    scenario: object = None
    phases: list = field(default_factory=list)   # validate.channels.Phase, from the inputs
    model_error_rms: np.ndarray | None = None      # per channel, estimated discretisation error
    expansion: dict = field(default_factory=dict)   # material -> fitted relative change of alpha (baseline)
    calibrated_rmse: np.ndarray | None = None      # per channel, baseline with the nuisance fitted
    residual_after: object = None                  # g -> r - g - nuisance fitted to r - g
    expansion_fit: object = None                   # g -> {material: relative change of alpha} fitted to r - g
    error_resolution: str | None = None
    twin: object = None                            # the diagnosing PreparedTwin, reused by apply

    @property
    def residual(self) -> np.ndarray:
        return self.measured - self.model


def sensor_points(ds, machine) -> list:
    """Sensor sites of the measurement: the machine's named points, or the Dataset's x, y, z."""
    from geometries.base import Point
    names = {p.name for p in machine.points}
    out = []
    for i, s in enumerate(ds["sensor"].values):
        s = str(s)
        if s in names and "x" not in ds.coords:
            out.append(machine.point(s))
        else:
            part = str(ds["part"].values[i]) if "part" in ds.coords else ""
            out.append(Point(s, (float(ds["x"].values[i]), float(ds["y"].values[i]), float(ds["z"].values[i])), part))
    return out


def noise_levels(y: np.ndarray, groups: list[str], spec: ModelSpec) -> dict[str, float]:
    """Group noise sigma_g: median over channels of sqrt(mean(diff(y)^2)/2), floored at half the
    instrument's quantisation step (K or um)."""
    floors = {"temperature": 0.5 * spec.params["temperature_sensor"]["quantisation"],
              "probe": 0.5 * spec.params["probe"]["resolution"] * 1e6}
    d = np.sqrt(np.mean(np.diff(y, axis=0) ** 2, axis=0) / 2)
    g = np.array(groups)
    return {k: max(float(np.median(d[g == k])), floors[k], 1e-12) for k in GROUPS if np.any(g == k)}


def channel_weights(residual: np.ndarray, groups: list[str], sigma: dict[str, float],
                    model_error: np.ndarray | None = None) -> np.ndarray:
    """w_c = 1 / (sqrt(s_g^2 + e_c^2) sqrt(m_g)), s_g = max(group residual RMS, sigma_g), e_c the
    RMS of the estimated model (discretisation) error of channel c (0 without an estimate); see
    the module doc."""
    g = np.array(groups)
    w = np.zeros(len(groups))
    e = np.zeros(len(groups)) if model_error is None else np.asarray(model_error, float)
    for k, s in sigma.items():
        m = g == k
        r = max(float(rms(residual[:, m])), s)
        w[m] = 1.0 / (np.sqrt(r ** 2 + e[m] ** 2) * np.sqrt(m.sum()))
    return w


def mesh_error(ds, machine, scenario, spec: ModelSpec, mm, resolution: str) -> np.ndarray:
    """Per-channel RMS of (model on ``resolution``) - (model on ``mm``) on the measurement's grid
    and channels: the estimate of the diagnosing model's discretisation error ``diagnose`` uses."""
    t = np.asarray(ds["time"].values, float)
    t = t - t[0]
    sensors = sensor_points(ds, machine) if "temperature" in ds else []
    coarse = Engine(machine, scenario, mm=mm, sensors=sensors)
    finer = Engine(machine, scenario, resolution, sensors=sensors)
    interp = resampler(coarse.times, t)
    return rms(interp(finer.observe(spec)) - interp(coarse.observe(spec)), axis=0)


def finer_resolution(machine, resolution: str) -> str | None:
    """The machine's next finer mesh resolution than ``resolution`` (None if it is the finest)."""
    sizes = machine.resolutions
    finer = [r for r in sizes if sizes[r] < sizes[resolution]]
    return max(finer, key=lambda r: sizes[r]) if finer else None


def coarser_resolution(machine, resolution: str) -> str | None:
    """The machine's next coarser mesh resolution than ``resolution`` (None if it is the coarsest)."""
    sizes = machine.resolutions
    coarser = [r for r in sizes if sizes[r] > sizes[resolution]]
    return min(coarser, key=lambda r: sizes[r]) if coarser else None


def effective_samples(res: np.ndarray) -> float:
    """AR(1) effective sample size N (1 - rho) / (1 + rho), rho pooled lag-1 autocorrelation."""
    x = res - res.mean(axis=0)
    num = float(np.sum(x[1:] * x[:-1]))
    den = float(np.sum(x * x)) or 1.0
    rho = min(max(num / den, 0.0), 0.999)
    return max(res.size * (1 - rho) / (1 + rho), 2.0)


def format_values(values: dict[str, dict[str, float]]) -> dict[str, dict[str, str]]:
    """SI values -> strings with units ("120 W")."""
    return {e: {p: format_quantity(v, EFFECTS[e].parameter(p).dimension) for p, v in vals.items()}
            for e, vals in values.items()}


def diagnose(ds, machine, scenario, spec: ModelSpec | None = None, resolution: str = "coarse", mm=None,
             candidates: list[str] | None = None, min_explained: float = 0.5, bic_margin: float = 10.0,
             pair_threshold: float = 0.8, pair_pool: int = 4, error_resolution: str | None = None,
             model_error: np.ndarray | None = None, calibrate_expansion: bool = True, progress=None) -> Diagnosis:
    """Rank the effects missing from ``spec`` by how much of the residual of ``ds`` they explain.

    ``ds``: a measurement Dataset (twin schema: ``temperature`` [degC], ``probe`` [um]);
    ``machine``: a built machine; ``scenario``: the Scenario that drove it (its grid must cover
    ``ds.time``); ``mm``: a prebuilt mesh of ``machine`` (else ``mesh_machine(machine, resolution)``).
    ``candidates`` defaults to every registered effect that applies to the machine (its roles
    exist) and is not in ``spec``. ``error_resolution``: a
    finer mesh on which the baseline is run once more; the difference per channel estimates the
    diagnosing model's discretisation error, and channels where it is large weigh less;
    ``model_error`` gives that per-channel RMS directly (e.g. from :func:`mesh_error`, reused
    for several measurements of one scenario and model). ``calibrate_expansion``: fit the thermal
    expansion coefficient of every material of the machine as a free nuisance parameter with the
    baseline and with every candidate (material data are uncertain by a few %, and a missing
    effect must explain what they cannot). ``progress(done, total)`` is called after each stage
    (the baseline, the error estimate, each candidate, each pair); ``total`` grows when pairs are
    tried.
    """
    spec = spec or default_spec(machine)
    pool = candidates if candidates is not None else [e for e in applicable_effects(machine) if e not in spec.effects]
    stages = {"done": 0, "total": 2 + len(pool)}

    def stage():
        stages["done"] += 1
        if progress is not None:
            progress(stages["done"], stages["total"])

    stacked = stack(ds, GROUPS)
    meas, names, groups = stacked.values, stacked.names, stacked.groups
    t_meas = np.asarray(ds["time"].values, float)
    t_meas = t_meas - t_meas[0]
    sensors = sensor_points(ds, machine) if "temperature" in ds else []
    engine = Engine(machine, scenario, resolution, mm=mm, sensors=sensors)
    interp = resampler(engine.times, t_meas)
    # the baseline and, from the same run, the exact expansion sensitivities (the nuisance)
    materials = sorted({p.material.name for p in machine.parts}) if calibrate_expansion else []
    observed, responses = engine.observe_with_expansion(spec, materials)
    base = interp(observed)
    nuisance = [interp(n) for n in responses]
    r = meas - base
    stage()
    sigma = noise_levels(meas, groups, spec)
    err = model_error
    if err is None and error_resolution:
        finer = Engine(machine, scenario, error_resolution, sensors=sensors)
        err = rms(interp(finer.observe(spec)) - base, axis=0)
    stage()
    w = channel_weights(r, groups, sigma, err)
    d = Diagnosis(t_meas, names, groups, meas, base, w, rms(r, axis=0), spec=spec)
    d.model_error_rms, d.error_resolution = err, error_resolution
    d.sensor_points, d.scenario, d.twin = engine.sensors, scenario, engine.twin
    d.phases = input_phases(ds, t_meas, scenario)
    fitter = SignatureFitter(_Resampled(engine, interp), spec, base, r, w,
                             nuisance=np.array(nuisance) if nuisance else None)
    d.residual_after = fitter.residual_after
    calibrated = fitter.residual_after(np.zeros_like(r))
    d.calibrated_rmse = rms(calibrated, axis=0)
    d.expansion_fit = lambda g: {m: float(c)
                                 for m, c in zip(materials, fitter.nuisance_coefficients(g))}
    d.expansion = d.expansion_fit(np.zeros_like(r))
    fits = []
    for e in pool:
        fits.append(fitter.fit_single(e))
        stage()
    fits = [f for f in fits if f is not None]
    fits.sort(key=lambda f: f.sse)
    sse0 = fitter.sse(np.zeros_like(r))
    if fits and 1 - fits[0].sse / sse0 < pair_threshold:
        top = fits[:pair_pool]
        couples = [(a, b) for i, a in enumerate(top) for b in top[i + 1:]]
        stages["total"] += len(couples)
        pairs = []
        for a, b in couples:
            pairs.append(fitter.fit_pair(a, b))
            stage()
        n_eff = effective_samples(fitter.residual_after(fits[0].response))
        fits += [p for p in pairs if _pair_significant(p, top, n_eff, min_explained, bic_margin)]
        fits.sort(key=lambda f: f.sse)
    d.fits, d.runs = fits, engine.runs
    _score(d, fits, r, sse0, min_explained, bic_margin)
    return d


def _pair_significant(pair: Fit, singles: list[Fit], n_eff: float, min_explained: float, bic_margin: float) -> bool:
    """The second member of a pair must pass the same test as a single against the baseline, taken
    against the residual its better member leaves: BIC gain >= ``bic_margin`` for the extra
    parameter and at least ``min_explained`` of that residual explained. (A fixed gain in the
    fraction of the *baseline* residual lets a second effect in on weaker evidence than the first:
    with structured model error left over, some candidate always soaks up 10 % of it.)"""
    better = min((f for f in singles if f.effects[0] in pair.effects), key=lambda f: f.sse)
    if better.sse <= 0:
        return False
    gain = n_eff * np.log(better.sse / max(pair.sse, 1e-300)) - (pair.nparams - better.nparams) * np.log(n_eff)
    return bool(gain >= bic_margin and 1 - pair.sse / better.sse >= min_explained)


def reasoning(d: Diagnosis, response: np.ndarray, top_channels: int = 4) -> dict:
    """Where a candidate's response g explains the residual r: per channel and per input phase.

    With weighted squares e = (w r)^2 before and (w (r - g))^2 after, for a set S of samples
    (a channel's column, or a phase's rows over every channel):

    * ``share``: sum_S e_before / SSE_0, the part of the baseline residual lying in S;
    * ``explained``: 1 - sum_S e_after / sum_S e_before, the fraction of it removed (negative:
      the candidate makes S worse).

    ``channels``: the ``top_channels`` channels carrying the largest explained share
    (share x explained), i.e. the evidence for the candidate; ``phases``: every phase.
    """
    after_of = d.residual_after or (lambda g: d.residual - g)
    before = (after_of(np.zeros_like(response)) * d.weights) ** 2
    after = (after_of(response) * d.weights) ** 2
    total = float(before.sum()) or 1.0

    def cell(b, a):
        sb = float(b.sum())
        return {"share": sb / total, "explained": (1 - float(a.sum()) / sb) if sb > 0 else 0.0}

    chans = [{"channel": c, **cell(before[:, k], after[:, k])} for k, c in enumerate(d.channels)]
    chans.sort(key=lambda x: -x["share"] * x["explained"])
    phases = []
    for p in d.phases:
        sel = (d.times >= p.start) & (d.times < p.end)
        if sel.any():
            phases.append({"kind": p.kind, "phase": p.label, "start_h": p.start / 3600, "end_h": p.end / 3600,
                           **cell(before[sel], after[sel])})
    return {"channels": chans[:top_channels], "phases": phases}


def _score(d: Diagnosis, fits: list[Fit], r, sse0, min_explained, bic_margin):
    N = r.size
    after_of = d.residual_after or (lambda g: r - g)
    d.n_eff = n = effective_samples(after_of(fits[0].response)) if fits else float(N)
    bic0 = n * np.log(max(sse0, 1e-300) / N)
    bics = np.array([n * np.log(max(f.sse, 1e-300) / N) + f.nparams * np.log(n) for f in fits])
    all_b = np.concatenate([[bic0], bics])
    weights = np.exp(-(all_b - all_b.min()) / 2)
    weights /= weights.sum()
    sig = {f.effects: (f.response * d.weights).ravel() for f in fits}
    for i, f in enumerate(fits):
        after = after_of(f.response)
        twins = []
        for j, o in enumerate(fits):
            if j == i:
                continue
            a, b = sig[f.effects], sig[o.effects]
            corr = float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b) or 1.0))
            if abs(bics[i] - bics[j]) < 6 or abs(corr) > 0.95:
                twins.append("+".join(o.effects))
        rms_before = rms(after_of(np.zeros_like(r)), axis=0)
        rms_after = rms(after, axis=0)
        per_ch = 1 - (rms_after / np.where(rms_before > 0, rms_before, 1)) ** 2
        best_ch = [d.channels[k] for k in np.argsort(-per_ch)[:3]]
        d.candidates.append({
            "effect": "+".join(f.effects),
            "parameters": format_values(f.values),
            "values_si": f.values,
            "explained": float(1 - f.sse / sse0),
            "rmse_after": {c: float(v) for c, v in zip(d.channels, rms_after)},
            "delta_bic": float(bic0 - bics[i]),
            "confidence": float(weights[i + 1]),
            "indistinguishable_from": twins[:5],
            "explains_most": best_ch,
            "fitted_parameters": f.nparams,
            "reasoning": reasoning(d, f.response),
        })
    top = d.candidates[0] if d.candidates else None
    d.significant = bool(top and top["delta_bic"] >= bic_margin and top["explained"] >= min_explained)
    if d.significant:
        d.message = (f"missing effect: {top['effect']} ({_params_text(top)}), explains {top['explained']:.0%} "
                     f"of the weighted residual, confidence {top['confidence']:.2f}")
    else:
        why = (f"best candidate {top['effect']} explains {top['explained']:.0%} (dBIC {top['delta_bic']:.1f})"
               if top else "no candidate effects")
        d.message = f"nothing significant is missing: {why}; the residual is model error and noise"


def _params_text(c: dict) -> str:
    return ", ".join(f"{e}.{p}={v}" for e, vals in c["parameters"].items() for p, v in vals.items())


class _Resampled:
    """Engine wrapper returning observables on the measurement's time grid."""

    def __init__(self, engine, interp):
        self._e, self._i = engine, interp
        self.mm, self.scenario = engine.mm, engine.scenario

    def observe(self, spec):
        return self._i(self._e.observe(spec))


def format_diagnosis(d: Diagnosis, top: int = 8) -> str:
    """A readable ranking table plus the verdict."""
    lines = [f"Baseline RMSE per channel ({len(d.channels)} channels, effective samples {d.n_eff:.0f}):"]
    for g in GROUPS:
        idx = [i for i, k in enumerate(d.groups) if k == g]
        if idx:
            vals = ", ".join(f"{d.channels[i].split(':', 1)[1]} {d.baseline_rmse[i]:.3g}" for i in idx)
            lines.append(f"  {g} [{CHANNEL_GROUPS[g][1]}]: {vals}")
            if d.model_error_rms is not None:
                vals = ", ".join(f"{d.channels[i].split(':', 1)[1]} {d.model_error_rms[i]:.3g}" for i in idx)
                lines.append(f"    mesh error estimate ({d.error_resolution} vs the diagnosing mesh): {vals}")
    if d.expansion:
        exp = ", ".join(f"{m} {v:+.1%}" for m, v in d.expansion.items())
        probes = [i for i, g in enumerate(d.groups) if g == "probe"]
        lines.append(f"Nuisance fitted with the baseline and every candidate: thermal expansion {exp}"
                     + (f"; probe RMSE {rms(d.baseline_rmse[probes]):.3g} -> "
                        f"{rms(d.calibrated_rmse[probes]):.3g} um" if probes else ""))
    lines.append("")
    head = f"{'rank':>4}  {'effect':<44} {'explained':>9} {'dBIC':>8} {'conf':>5}  parameters"
    lines += [head, "-" * len(head)]
    for i, c in enumerate(d.candidates[:top], 1):
        lines.append(f"{i:>4}  {c['effect']:<44} {c['explained']:>8.1%} {c['delta_bic']:>8.1f} "
                     f"{c['confidence']:>5.2f}  {_params_text(c)}")
        if i <= 3:
            lines += _reasoning_lines(c)
    lines += ["", d.message]
    return "\n".join(lines)


def _reasoning_lines(c: dict, pad: str = " " * 6) -> list[str]:
    """The why of one candidate: channels and phases it explains (share of residual, explained)."""
    why = c.get("reasoning", {})
    out = []
    if why.get("channels"):
        out.append(pad + "channels (explained/share of residual): " + ", ".join(
            f"{x['channel']} {x['explained']:.0%}/{x['share']:.0%}" for x in why["channels"]))
    for kind in ("spindle", "ambient"):
        cells = [x for x in why.get("phases", []) if x["kind"] == kind]
        if cells:
            out.append(pad + f"{kind} phases: " + ", ".join(
                f"{x['phase']} ({x['start_h']:.1f}-{x['end_h']:.1f} h) {x['explained']:.0%}/{x['share']:.0%}"
                for x in cells))
    if c.get("indistinguishable_from"):
        out.append(pad + "cannot be told apart from: " + ", ".join(c["indistinguishable_from"]))
    return out


def diagnosis_json(d: Diagnosis) -> dict:
    """The ``--json`` document: baseline per-channel RMSE and the ordered candidates."""
    return {
        "baseline": {"rmse": {c: float(v) for c, v in zip(d.channels, d.baseline_rmse)},
                     "units": {c: CHANNEL_GROUPS[g][1] for c, g in zip(d.channels, d.groups)}},
        "significant": d.significant,
        "message": d.message,
        "effective_samples": d.n_eff,
        "calibration": {"expansion": d.expansion,
                        "rmse": (None if d.calibrated_rmse is None else
                                 {c: float(v) for c, v in zip(d.channels, d.calibrated_rmse)})},
        "model_error_rms": (None if d.model_error_rms is None else
                            {"resolution": d.error_resolution,
                             "rmse": {c: float(v) for c, v in zip(d.channels, d.model_error_rms)}}),
        "phases": [{"kind": p.kind, "phase": p.label, "start_s": p.start, "end_s": p.end} for p in d.phases],
        "candidates": [{k: v for k, v in c.items() if k != "values_si"} for c in d.candidates],
    }
