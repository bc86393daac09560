"""Diagnose: which missing effect, or which wrong parameter of the model's own effects, explains
the residual between measurement(s) and twin, and where on the machine the rest comes from.

Channels: every temperature sensor [K], ISO 230-3 probe [um], laser triangulation sensor [um] and
FBG strain gauge [um/m] a measurement has (any subset); residual r = measured - model (model through the sensor lag and bias, no noise), on
each measurement's time grid; several measurements are fitted together
(:mod:`validate.evidence`, which also gives the weights).

Model error: with ``error_resolution`` the baseline is run once more on another mesh; e_c, the
RMS over time of the difference on channel c, estimates the diagnosing model's discretisation
error and lowers the channel's weight (w_c = 1 / (sqrt(s_g^2 + e_c^2) sqrt(m_g))).

Nuisance: each material's thermal expansion coefficient is fitted with the baseline and with
every candidate, but only within the material's declared band (``Material.expansion_band``,
e.g. +-10 % for grey cast iron; :mod:`validate.fit`). A nuisance at its bound is reported: the
drift needs more than the plausible material spread, so something else is wrong.

Candidates (:mod:`validate.candidates`): every applicable effect the model lacks, every declared
uncertain parameter of the model's effects (``Effect.uncertain``) and the user's custom effects;
fitted within their bounds (:mod:`validate.search`). Scores of a candidate with k parameters and
weighted sum of squares SSE_k (nuisance fitted):

* explained = 1 - SSE_k / SSE_0 (SSE_0: the baseline);
* BIC_k = n_eff ln(SSE_k / N) + k ln(n_eff), n_eff the AR(1) effective sample count of the best
  candidate's residual (thermal residuals are strongly autocorrelated);
* confidence = Schwarz weight of the candidate among all candidates and "nothing missing"
  (printed as the BIC weight): relative among this set, so the best of a set of poor candidates
  holds about 1.00; it is not the probability that the candidate is the cause. Whether a candidate
  passes the significance test (below) is its own flag ``significant``;
* ``at_bound``: the members (``effect.parameter``) fitted at a bound of their range (within 1e-3
  of its width), flagged like the nuisance's: the fit wants more than the range allows, or, at the
  value where a missing effect adds nothing, the opposite sign;
* candidates within 6 BIC units, or with weighted signatures correlated |corr| > 0.95, are
  reported as not distinguishable.

Significance: the top candidate beats the baseline by >= ``bic_margin`` (10) BIC units and
explains >= ``min_explained`` (50 %) of the weighted residual *of the groups above noise and model
error* (factor > ``WITHIN`` before any candidate, :mod:`validate.verdict`; every group when none
is): explained = 1 - SSE_k(A) / SSE_0(A), A those groups' channels. ``Diagnosis.significant`` is
this test of the top candidate, whatever the verdict; the verdict names the candidate
(``Diagnosis.named``) only when it is also needed: some group above noise and model error, or the
candidate beyond the model error along its signature (:mod:`validate.verdict`). A group at its noise holds
nothing a candidate could explain, so counting it would cap the share by how many quiet channels
a machine has (the gantry's FBG gauges at 1.3x their noise held 43 % of the weighted residual and
kept a candidate that removed 99 % of the lasers' residual and 73 % of the temperatures' under
50 %). ``explained_all`` is the share over every channel. Pairs are tried among the ``pair_pool`` best singles when
none explains ``pair_threshold`` (80 %), or when the best single leaves a residual above noise and
model error (a factor > ``WITHIN`` in some group: a second cause may be what remains), and kept
only if the second member passes the same test against the residual its better member leaves. The verdict (:mod:`validate.verdict`) then holds
the residual against noise and model error; when it is not ``explained``, a generic heat input on
every region of the machine's partition is fitted to it (:mod:`validate.localise`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from learners.metrics import rms
from twin.model import ModelSpec, check_refusals, default_spec
from twin.physics.prepared import PreparedTwin, check_prepared
from twin.physics.prepared_args import check_beside_prepared, coarse_unless_given
from validate import verdict as V
from validate.verdict import Share
from validate.candidates import candidate_pool
from validate.channels import not_held
from validate.diagnose_args import SOURCE, check_arguments, check_model_error
from validate.diagnosis_text import diagnosis_json, format_diagnosis, reasoning  # noqa: F401  (re-exported)
from validate.evidence import Evidence, channel_weights, make_records, noise_levels
from validate.fit import BoundedFitter
from validate.fit_text import at_bound, bound_text, format_bounds, format_values, statement
from validate.model_error import error_with, mesh_error
from validate.search import Fit, Search
from validate.signatures import DISPLACEMENT_GROUPS, Engine


@dataclass
class Diagnosis:
    """Result of :func:`diagnose`. Flat vectors run over every channel of every record
    (:class:`validate.evidence.Evidence`); the single-record views (``times``, ``measured``,
    ``model`` ...) are those of the first record."""

    evidence: Evidence
    spec: ModelSpec
    base: np.ndarray
    weights_flat: np.ndarray
    fitter: BoundedFitter
    materials: list[str]
    candidates: list[dict] = field(default_factory=list)
    fits: list[Fit] = field(default_factory=list)
    verdict: str = "nothing_missing"
    significant: bool = False                      # the top candidate passes the significance test
    test: tuple = (10.0, 0.5)                      # (bic_margin, min_explained) of that test
    message: str = ""
    n_eff: float = 0.0
    residual_factor: dict = field(default_factory=dict)
    residual_factor_after: dict = field(default_factory=dict)
    levels: dict = field(default_factory=dict)     # group -> (noise, model error)
    share: "Share | None" = None                   # the significance share (the groups above noise)
    nuisance: dict = field(default_factory=dict)
    nuisance_baseline: dict = field(default_factory=dict)
    regions: list = field(default_factory=list)
    missing_channels: list = field(default_factory=list)
    not_used: list = field(default_factory=list)     # readings of the measurements no diagnosis holds (channels.NOT_HELD)
    model_error_flat: np.ndarray | None = None
    model_error_series_flat: np.ndarray | None = None   # signed estimate (flat), when from a mesh
    beyond_model_error: float | None = None
    levels_after: dict = field(default_factory=dict)   # levels of the model with the named candidate, when re-estimated
    error_resolution: str | None = None
    runs: int = 0
    twin: object = None

    @property
    def named(self) -> bool:
        """True when the verdict names the top candidate (``explained`` or ``partly_explained``)."""
        return self.verdict in ("explained", "partly_explained")

    # single-record views (the first record) for the report and the text
    @property
    def record(self):
        return self.evidence.records[0]

    @property
    def times(self):
        return self.record.times

    @property
    def channels(self):
        return self.evidence.channel_names()

    @property
    def groups(self):
        return [g for r in self.evidence.records for g in r.groups]

    @property
    def measured(self):
        return self.record.measured

    @property
    def model(self):
        return self.record.model

    @property
    def weights(self):
        return self.record.weights

    @property
    def phases(self):
        return self.record.phases

    @property
    def sensor_points(self):
        return self.record.sensor_points

    @property
    def scenario(self):
        return self.record.scenario

    @property
    def residual(self) -> np.ndarray:
        return self.measured - self.model

    @property
    def baseline_rmse(self) -> np.ndarray:
        """Per channel over all records (native units)."""
        return self.evidence.per_channel(self.fitter.r)

    @property
    def calibrated_rmse(self) -> np.ndarray:
        return self.evidence.per_channel(self.fitter.residual_after(np.zeros_like(self.fitter.r)))

    @property
    def model_error_rms(self):
        return None if self.model_error_flat is None else self.evidence.per_channel(self.model_error_flat, _first_row)

    @property
    def expansion(self) -> dict:
        return {m: v["change"] for m, v in self.nuisance_baseline.items()}

    def residual_after(self, g: np.ndarray) -> np.ndarray:
        """Flat r - g - nuisance fitted to r - g."""
        return self.fitter.residual_after(g)

    def expansion_fit(self, g: np.ndarray) -> dict:
        """material -> relative change of alpha fitted (within its band) to r - g."""
        return dict(zip(self.materials, (float(c) for c in self.fitter.nuisance(g))))


def _first_row(block: np.ndarray) -> np.ndarray:
    return block[0]


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


class Stages:
    """Counts the stages of a diagnosis and reports ``progress(done, total)`` after each."""

    def __init__(self, progress, total: int):
        self.progress, self.done, self.total = progress, 0, total

    def grow(self, n: int) -> None:
        self.total += n

    def __call__(self) -> None:
        self.done += 1
        if self.progress is not None:
            self.progress(self.done, self.total)


def expansion_bands(machine) -> dict[str, tuple[float, str]]:
    """material -> (band, source) of every material of the machine."""
    return {p.material.name: (p.material.expansion_band, p.material.expansion_band_source) for p in machine.parts}


def diagnose(ds, machine, scenario, spec: ModelSpec | None = None, **kw) -> Diagnosis:
    """:func:`diagnose_many` of one measurement ``ds`` driven by ``scenario``; its
    ``model_error``, when given, is this measurement's (one value per channel)."""
    label = str(getattr(ds, "attrs", {}).get("source", "measurement")).rsplit("/", 1)[-1]
    if kw.get("model_error") is not None:
        kw["model_error"] = [kw["model_error"]]
    return diagnose_many([(label, ds, scenario)], machine, spec, **kw)


def diagnose_many(measurements, machine, spec: ModelSpec | None = None, resolution: str | None = None, mm=None,
                  candidates: list[str] | None = None, parameters: bool = True, min_explained: float = 0.5,
                  bic_margin: float = 10.0, pair_threshold: float = 0.8, pair_pool: int = 4,
                  error_resolution: str | None = None, model_error: list | None = None,
                  calibrate_expansion: bool = True, localise_regions: bool = True, localise_steps: int = 100,
                  twin: PreparedTwin | None = None, progress=None, custom: tuple[str, ...] = ()) -> Diagnosis:
    """Rank the effects and parameters that explain the residual of ``measurements``.

    ``measurements``: [(label, Dataset, Scenario)] (twin schema: any of ``temperature`` [degC],
    ``probe`` and ``laser`` [um], ``strain`` or ``strain_raw`` [um/m]); each scenario's grid must cover its measurement. ``machine``: a built
    machine; ``spec``: the diagnosing model (default: the machine's); ``mm``/``resolution``: its
    mesh (default the coarse one; both given, the resolution must be the mesh's), or ``twin`` a
    prepared twin (then ``mm`` and ``resolution`` are left out or its own). ``candidates``: the missing effects to try (default: every applicable library effect not
    in ``spec`` and the ``custom`` effects named, those of an effects file this diagnosis reads,
    :func:`twin.effects.custom.load_effects_file`); ``parameters``: also try the declared uncertain
    parameters of the model's effects. ``error_resolution``/``model_error`` (one per-channel RMS
    array per measurement): the model's discretisation error estimate. ``calibrate_expansion``: fit
    each material's expansion within its band. ``localise_regions``: when the verdict is not
    ``explained``, rank the machine's regions (``localise_steps``: time steps of that map).
    ``progress(done, total)`` is called after each stage (the baseline, each model-error
    estimate, each candidate, each pair, the region map); ``total`` grows when pairs are tried
    or the regions mapped.
    """
    measurements = check_arguments(measurements, machine, spec, candidates, custom,
                                   {"min_explained": min_explained, "pair_threshold": pair_threshold}, bic_margin,
                                   {"pair_pool": pair_pool, "localise_steps": localise_steps},
                                   {"resolution": resolution, "error_resolution": error_resolution}, model_error,
                                   {"parameters": parameters, "calibrate_expansion": calibrate_expansion,
                                    "localise_regions": localise_regions}, progress)
    if twin is not None:
        check_prepared(twin, machine, SOURCE, "twin")
        check_beside_prepared(twin, SOURCE, mm, resolution)
    spec = spec or default_spec(machine)
    check_refusals(spec, [sc for _, _, sc in measurements])   # each of the model's effects acts in a record
    pool = candidate_pool(machine, spec, candidates, parameters, custom, tuple(sc for _, _, sc in measurements))
    stage = Stages(progress, 1 + len(measurements) + len(pool))
    twin = twin or PreparedTwin(machine, mm, coarse_unless_given(mm, resolution))
    evidence = Evidence([rec for lab, ds, sc in measurements for rec in make_records(lab, ds, sc, machine, twin)])
    bands = expansion_bands(machine)
    with_drift = bool(set(DISPLACEMENT_GROUPS) & set(evidence.groups()))   # channels alpha moves
    materials = sorted(bands) if calibrate_expansion and with_drift else []
    base, responses = evidence.observe_with_expansion(spec, materials)
    keep = [k for k in range(len(materials)) if np.any(responses[k])]
    materials, responses = [materials[k] for k in keep], responses[keep]
    r = evidence.measured - base
    stage()
    errors, series, others = [], [], {}
    error_twin = None   # the other mesh, prepared once for every measurement's scenario
    k = -1
    for rec, block in zip(evidence.records, evidence.split(base)):
        k += rec.counts_as is None   # the measurement's index (its interferometer record follows it)
        rec.model = block
        rec.noise = noise_levels(rec.measured, rec.groups, spec)
        rec.model_error_series = None
        if model_error is not None:
            rec.model_error = check_model_error(model_error[k], rec.channels, rec.label) if rec.counts_as is None else None
        elif error_resolution:
            if id(rec.engine) not in others:   # one run on the other mesh serves the records of an engine
                error_twin = error_twin or PreparedTwin(machine, resolution=error_resolution)
                others[id(rec.engine)] = Engine(machine, rec.scenario, error_resolution, sensors=rec.sensor_points,
                                                prepared=error_twin)
            rec.error_engine = others[id(rec.engine)]
            rec.model_error_series = mesh_error(rec, machine, spec, error_resolution, rec.error_engine)
            rec.model_error = rms(rec.model_error_series, axis=0)
        if rec.counts_as is None:
            stage()
        rec.weights = channel_weights(rec.measured - rec.model, rec.groups, rec.noise, rec.model_error, rec.counts_as)
        errors.append(np.broadcast_to(rec.model_error if rec.model_error is not None else 0.0, rec.measured.shape))
        series.append(rec.model_error_series)
    w = evidence.flat([np.broadcast_to(rec.weights, rec.measured.shape) for rec in evidence.records])
    has_error = any(rec.model_error is not None for rec in evidence.records)
    estimated = evidence.flat([np.broadcast_to(float(rec.model_error is not None), rec.measured.shape)
                               for rec in evidence.records]) > 0
    fitter = BoundedFitter(r, w, responses, [-bands[m][0] for m in materials], [bands[m][0] for m in materials])
    d = Diagnosis(evidence, spec, base, w, fitter, materials, error_resolution=error_resolution, twin=twin,
                  model_error_flat=evidence.flat(errors) if has_error else None,
                  model_error_series_flat=(evidence.flat(series) if all(e is not None for e in series)
                                           else None))
    zero = np.zeros_like(r)
    d.nuisance_baseline = nuisance_report(fitter, materials, bands, zero)
    search = Search(evidence.observe, spec, base, fitter)
    fits = search.singles(pool, stage)
    d.test = (bic_margin, min_explained)
    d.levels = V.group_levels(evidence, d.model_error_flat, estimated)
    plain = fitter.residual_after(zero)
    d.residual_factor = V.residual_factors(evidence, plain, d.levels)
    d.share = Share(evidence, fitter, d.residual_factor, plain)
    if fits and _wants_pairs(d, fits[0], pair_threshold):
        fits += _pairs(search, fits[:pair_pool], d, min_explained, bic_margin, stage)
        fits.sort(key=lambda f: f.sse)
    d.fits = fits
    _score(d, fits, min_explained, bic_margin)
    _judge(d, machine, localise_regions, localise_steps, stage)
    d.runs = evidence.runs
    return d


def _wants_pairs(d: Diagnosis, best: Fit, pair_threshold: float) -> bool:
    """Pairs are tried when the best single explains less than ``pair_threshold`` of the
    significance share, or explains more but leaves a residual above noise and model error
    (a second cause the first does not cover)."""
    return d.share.explained(best.response) < pair_threshold or _leaves_a_residual(d, best)


def _leaves_a_residual(d: Diagnosis, best: Fit) -> bool:
    """True when the residual after ``best`` stands above noise and model error in some group
    (a factor > ``WITHIN``, :mod:`validate.verdict`)."""
    after = V.residual_factors(d.evidence, d.fitter.residual_after(best.response), d.levels)
    return any(f > V.WITHIN for f in after.values())


def _pairs(search: Search, top: list[Fit], d: Diagnosis, min_explained, bic_margin, stage) -> list[Fit]:
    """Pairs of the ``top`` singles that pass the significance test of their second member; the
    best pair with a nonlinear member refined by Gauss-Newton."""
    couples = [(a, b) for i, a in enumerate(top) for b in top[i + 1:]]
    stage.grow(len(couples))
    pairs = []
    for a, b in couples:
        pairs.append(search.pair(a, b))
        stage()
    if not pairs:
        return []
    n_eff = d.evidence.effective_samples(search.fitter.residual_after(top[0].response))
    best = min(pairs, key=lambda p: p.sse)
    if any(not c.linear for c in best.candidates):
        refined = search.joint(best.candidates, best.values)
        if refined.sse < best.sse:
            pairs[pairs.index(best)] = refined
    return [p for p in pairs if _pair_significant(d, p, top, n_eff, min_explained, bic_margin)]


def _pair_significant(d: Diagnosis, pair: Fit, singles: list[Fit], n_eff: float, min_explained: float,
                      bic_margin: float) -> bool:
    """The second member of a pair must pass the same test as a single against the baseline, taken
    against the residual its better member leaves: BIC gain >= ``bic_margin`` for the extra
    parameter and at least ``min_explained`` of that residual explained (over the groups above
    noise, :class:`Share`)."""
    names = {c.name for c in pair.candidates}
    better = min((f for f in singles if f.candidates[0].name in names), key=lambda f: f.sse)
    if better.sse <= 0:
        return False
    gain = n_eff * np.log(better.sse / max(pair.sse, 1e-300)) - (pair.nparams - better.nparams) * np.log(n_eff)
    return bool(gain >= bic_margin and d.share.explained(pair.response, better.response) >= min_explained)


NUISANCE_UNIT = "fraction of alpha"   # change and band: relative to the material's expansion coefficient


def nuisance_report(fitter: BoundedFitter, materials: list[str], bands: dict, g: np.ndarray) -> dict:
    """material -> {change, band, unit, at_bound, source} of the expansion fitted to r - g; change
    and band are fractions of the material's expansion coefficient alpha (0.1 = +10 %)."""
    c = fitter.nuisance(g)
    at = fitter.at_bound(c) if len(c) else []
    return {m: {"change": float(v), "band": float(bands[m][0]), "unit": NUISANCE_UNIT, "at_bound": bool(a),
                "source": bands[m][1]}
            for m, v, a in zip(materials, c, at)}


def _score(d: Diagnosis, fits: list[Fit], min_explained: float, bic_margin: float) -> None:
    N = d.fitter.r.size
    ev = d.evidence
    sse0 = d.fitter.sse(np.zeros_like(d.fitter.r))
    d.n_eff = n = ev.effective_samples(d.residual_after(fits[0].response)) if fits else float(N)
    bic0 = n * np.log(max(sse0, 1e-300) / N)
    bics = np.array([n * np.log(max(f.sse, 1e-300) / N) + f.nparams * np.log(n) for f in fits])
    all_b = np.concatenate([[bic0], bics])
    weights = np.exp(-(all_b - all_b.min()) / 2)
    weights /= weights.sum()
    sig = {f.name: f.response * d.weights_flat for f in fits}
    before = ev.per_channel(d.residual_after(np.zeros_like(d.fitter.r)))
    names = ev.channel_names()
    for i, f in enumerate(fits):
        twins = []
        for j, o in enumerate(fits):
            if j == i:
                continue
            a, b = sig[f.name], sig[o.name]
            corr = float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b) or 1.0))
            if abs(bics[i] - bics[j]) < 6 or abs(corr) > 0.95:
                twins.append(o.name)
        res = d.residual_after(f.response)
        rms_after = ev.per_channel(res)
        per_ch = 1 - (rms_after / np.where(before > 0, before, 1)) ** 2
        explained = d.share.of_residual(res)
        d.candidates.append({
            "effect": f.name,
            "kind": f.kind,
            "parameters": format_values(f),
            "values_si": {c.effect: {c.parameter: v} for c, v in zip(f.candidates, f.values)},
            "model_values": {c.effect: {c.parameter: c.zero} for c in f.candidates if c.in_model},
            "model_parameters": format_values(f, model=True),
            "statement": statement(f),
            "explained": explained,
            "explained_all": float(1 - f.sse / sse0) if sse0 > 0 else 0.0,
            "rmse_after": {c: float(v) for c, v in zip(names, rms_after)},
            "delta_bic": float(bic0 - bics[i]),
            "confidence": float(weights[i + 1]),
            "indistinguishable_from": twins[:5],
            "explains_most": [names[k] for k in np.argsort(-per_ch)[:3]],
            "significant": bool(bic0 - bics[i] >= bic_margin and explained >= min_explained),
            "at_bound": at_bound(f),
            "bounds": format_bounds(f),
            "fitted_parameters": f.nparams,
            "reasoning": reasoning(d, f.response),
        })
    top = d.candidates[0] if d.candidates else None
    d.significant = bool(top and top["significant"])


def _error_after(d: Diagnosis, machine, after: np.ndarray, stage) -> None:
    """The residual a named candidate leaves, held against the discretisation error of the model
    *with* that candidate (:func:`validate.model_error.error_with`, one more run on each mesh):
    ``levels_after`` and the factors after are re-estimated, and the verdict becomes ``explained``
    when every group is then within ``WITHIN``."""
    stage.grow(1)
    flat = error_with(d.evidence, machine, d.fits[0].in_model(d.spec), d.error_resolution)
    stage()
    d.levels_after = V.group_levels(d.evidence, flat)
    d.residual_factor_after = V.residual_factors(d.evidence, after, d.levels_after)
    d.verdict = V.decide(d.residual_factor, d.significant, d.residual_factor_after, d.beyond_model_error)


def _judge(d: Diagnosis, machine, localise_regions: bool, localise_steps: int, stage) -> None:
    """Verdict, nuisance report, the region map when needed, the missing channels' cost, message."""
    from validate.channel_cost import missing_channels
    ev, fitter = d.evidence, d.fitter
    zero = np.zeros_like(fitter.r)
    top_fit = d.fits[0] if d.fits else None
    after = fitter.residual_after(top_fit.response) if top_fit is not None else fitter.residual_after(zero)
    d.residual_factor_after = V.residual_factors(ev, after, d.levels) if top_fit is not None else {}
    if top_fit is not None and d.model_error_series_flat is not None:
        d.beyond_model_error = V.beyond_model_error(fitter, top_fit, d.model_error_series_flat)
    d.verdict = V.decide(d.residual_factor, d.significant, d.residual_factor_after, d.beyond_model_error)
    if d.verdict == "partly_explained" and d.error_resolution:
        _error_after(d, machine, after, stage)
    bands = expansion_bands(machine)
    kept = d.named
    d.nuisance = nuisance_report(fitter, d.materials, bands, top_fit.response if kept else zero)
    left = after if kept else fitter.residual_after(zero)
    if d.verdict != "explained" and d.verdict != "nothing_missing" and localise_regions:
        from validate.localise import localise
        stage.grow(1)
        target = BoundedFitter(fitter.r - (top_fit.response if kept else zero), fitter.w, fitter.N, fitter.lo, fitter.hi)
        d.regions = localise(ev, target, d.spec, machine, max_steps=localise_steps)
        stage()
    d.missing_channels = missing_channels(d, machine)
    d.not_used = [f"{r.label}: {reading}" for r in ev.records for reading in not_held(r.ds)]
    top = d.candidates[0] if d.candidates else None
    d.message = V.message(d.verdict, top, d.residual_factor, d.residual_factor_after, d.levels,
                          V.worst_channels(ev, left, d.levels_after or d.levels),   # set only with a named candidate
                          V.worst_time(ev, left, d.weights_flat), d.regions, d.beyond_model_error, d.test,
                          d.levels_after)
    bound = bound_text(top_fit) if top_fit is not None else ""
    if bound:   # a member within 0.1 % of its range's end: reported, not read as an interior optimum
        d.message += (f"; the {'named' if kept else 'best'} candidate's {bound}: it sits at the end of its "
                      "plausible range (the range may be too narrow, or something else is wrong)")
    at_bound = [m for m, v in d.nuisance.items() if v["at_bound"]]
    if at_bound:
        d.message += ("; " + ", ".join(f"{m} expansion at its bound {d.nuisance[m]['change']:+.0%}" for m in at_bound)
                      + ": the drift needs more than the materials' plausible spread, so something else is wrong")
