"""The verdict of a diagnosis, from numbers: is the residual above noise and model error, and does
a candidate explain it?

Per channel group g (temperatures in K, probes and lasers in um, strains in um/m), over every channel of every measurement:

    factor_g = RMS_g(residual) / sqrt(sigma_g^2 + e_g^2),

the residual with the bounded nuisance fitted, sigma_g the instruments' noise level
(:func:`validate.evidence.noise_levels`) and e_g the RMS over the group's channels of the
diagnosing model's estimated discretisation error (None, and left out of the sum, without an
estimate: the factor is then against noise alone, and every text says so). A factor of 1 is a
residual the size of noise and model error; ``WITHIN`` (3) is the largest factor still called
that. Then, with the top candidate (:mod:`validate.diagnose`'s significance test: >= 10 BIC units
better than "nothing missing" and >= 50 % of the weighted residual of the groups above ``WITHIN``
explained, of every group when none is above):

* ``nothing_missing``: every group's factor <= ``WITHIN``, unless the top candidate is significant
  *and beyond the model error along its own signature* (below): a candidate that would fit part of
  such a residual, by no more than the model error alone would make it move, is mentioned, not named.
  A top candidate that passes the significance test is still called significant (the test is about
  the candidate; the verdict about the residual): the message says it is significant, how much of a
  residual that is itself within noise and model error it explains, and why the verdict does not
  name it (its fitted change is < ``BEYOND`` times the model error's along its signature, or no
  model error was estimated, so that comparison could not be made);
* ``explained``: a significant candidate leaves every group's factor <= ``WITHIN``;
* ``partly_explained``: a significant candidate, but some group's factor stays above ``WITHIN``
  after it (how much remains, and where, is stated); with a model error from a mesh, the factors
  after it are held against the error of the model *with* the candidate, estimated again
  (:mod:`validate.model_error`; ``levels_after``), and only then is the verdict settled;
* ``unexplained``: some group's factor is above ``WITHIN`` and no library candidate explains it.

A residual above ``WITHIN`` is never called noise: the factor is stated.

Beyond the model error along a signature. The factor compares magnitudes only; the model error is
an estimate from another mesh (its RMS, e_g), and a candidate's change can stand far above it
along the candidate's own response even where the whole residual does not. With the fitted
candidate's local columns S (one per member, dg/dp) and the signed model-error estimate m (flat),

    x_r = argmin || w (r - S x - N c) ||,   x_m = argmin || w (m - S x - N c) ||,

(the nuisance N c fitted jointly, the same weights), ``beyond = min_i |x_r,i| / |x_m,i|``: how many
times larger the fitted change is than the change the model error alone would produce. A
significant candidate with ``beyond >= BEYOND`` (10) is named even when every factor is
<= ``WITHIN``: ``explained`` when it leaves every factor <= ``WITHIN``, ``partly_explained`` when
fitting it lifts some group above (it explains most of the weighted residual but not that group's);
the message states both numbers. The estimate's shape is not the true error's
shape (the truth differs from the model in more than its mesh: materials within their bands, the
time step), so ``beyond`` alone does not separate: in the hidden-effect study's nothing-hidden
cases the best candidate reached 2.4, 3.0 and 74 (a missing solar load on the day-night test,
which the mesh error cannot mimic at all), explaining only 9-15 %. What guards those cases is the
significance test's 50 % share; ``BEYOND`` is set well above ``WITHIN`` to be conservative, and the
wrong parameters that hide inside the size of the model error reached 13-51.
"""

from __future__ import annotations

import numpy as np

from learners.metrics import rms
from validate.channels import residual_unit

WITHIN = 3.0
BEYOND = 10.0
BEYOND_CAP = 1e6
VERDICTS = ("explained", "partly_explained", "unexplained", "nothing_missing")


def group_levels(evidence, model_error_flat: np.ndarray | None,
                 estimated_flat: np.ndarray | None = None) -> dict[str, tuple[float, float | None]]:
    """group -> (noise sigma_g, model error e_g) over every record; e_g is None when no channel of
    the group has a model-error estimate (``model_error_flat`` None, or ``estimated_flat``, a flat
    boolean mask of the samples whose record has one, false on all of the group's samples)."""
    out = {}
    for g in evidence.groups():
        sig = [r.noise[g] for r in evidence.records if g in r.noise]
        noise = float(np.sqrt(np.mean(np.square(sig)))) if sig else 0.0
        err = None
        if model_error_flat is not None:
            mask = evidence.group_mask(g)
            if estimated_flat is not None:
                mask = mask & estimated_flat
            e = model_error_flat[mask]
            err = float(rms(e)) if e.size else None
        out[g] = (noise, err)
    return out


def envelope(level: tuple[float, float | None]) -> float:
    """sqrt(noise^2 + model error^2) of a group's (noise, model error); noise alone without an
    estimate of the model error."""
    noise, err = level
    return float(np.hypot(noise, err or 0.0))


def estimated(levels: dict) -> bool:
    """True when every group has a model-error estimate."""
    return all(e is not None for _, e in levels.values())


def against(levels: dict) -> str:
    """What the factors compare with: 'noise and model error', 'noise alone, the model error not
    estimated', or, when only some groups have an estimate, 'noise and model error, noise alone for
    probe whose model error was not estimated'."""
    missing = [g for g, (_, e) in levels.items() if e is None]
    if not missing:
        return "noise and model error"
    if len(missing) == len(levels):
        return "noise alone, the model error not estimated"
    return (f"noise and model error, noise alone for {', '.join(missing)} whose model error was not "
            f"estimated")


def residual_factors(evidence, residual_flat: np.ndarray, levels: dict) -> dict[str, float]:
    """group -> RMS of the residual over the group / sqrt(noise^2 + model error^2) (noise alone
    where the model error was not estimated)."""
    out = {}
    for g, level in levels.items():
        res = residual_flat[evidence.group_mask(g)]
        out[g] = float(rms(res) / max(envelope(level), 1e-300))
    return out


def beyond_model_error(fitter, fit, model_error_flat: np.ndarray) -> float:
    """min over the fit's members of |x_r| / |x_m| (module docstring): the fitted change over the
    change the signed model-error estimate alone produces along the member's column (unbounded
    fit, nuisance within its band), capped at ``BEYOND_CAP`` (1e6: the model error does not move it
    at all, e.g. a heat source the model lacks entirely)."""
    cols = np.column_stack(fit.slopes) if fit.slopes else fit.response[:, None]
    x_r = np.array([v - c.zero for c, v in zip(fit.candidates, fit.values)]) if fit.slopes else np.ones(1)
    free = np.full(cols.shape[1], np.inf)
    x_m = fitter.solve(cols, -free, free, model_error_flat)[0]
    ratio = np.abs(x_r) / np.maximum(np.abs(x_m), 1e-300)
    return float(min(ratio.min(), BEYOND_CAP))


def decide(factors: dict[str, float], significant: bool, after: dict[str, float] | None,
           beyond: float | None = None) -> str:
    """The verdict word (module docstring). A residual within noise and model error is
    ``nothing_missing`` even when a candidate would fit some of it, unless that candidate's fitted
    change is ``BEYOND`` times what the model error alone produces along its signature."""
    leaves_all_within = after is not None and all(f <= WITHIN for f in after.values())
    if not any(f > WITHIN for f in factors.values()):
        if significant and beyond is not None and beyond >= BEYOND:
            return "explained" if after is None or leaves_all_within else "partly_explained"
        return "nothing_missing"
    if significant:
        return "explained" if leaves_all_within else "partly_explained"
    return "unexplained"


def worst_channels(evidence, residual_flat: np.ndarray, levels: dict, top: int = 3) -> list[tuple[str, float]]:
    """The channels whose residual RMS most exceeds their group's noise and model error:
    [(channel, factor)], worst first."""
    names = evidence.channel_names()
    per = evidence.per_channel(residual_flat)
    groups = [g for r in evidence.records for g in r.groups]
    ratio = [v / max(envelope(levels[g]), 1e-300) for v, g in zip(per, groups)]
    order = np.argsort(ratio)[::-1][:top]
    return [(names[i], float(ratio[i])) for i in order]


def worst_time(evidence, residual_flat: np.ndarray, weights_flat: np.ndarray) -> str:
    """When the weighted residual is largest: 'record: a-b h' of the phase holding most of it."""
    best, where = -1.0, ""
    for rec, res, w in zip(evidence.records, evidence.split(residual_flat), evidence.split(weights_flat)):
        e = ((res * w) ** 2).sum(axis=1)
        for p in (p for p in rec.phases if p.kind in ("spindle", "c_axis")) or ():
            sel = p.mask(rec.times)
            share = float(e[sel].sum())
            if share > best:
                best = share
                where = (f"{rec.label + ': ' if evidence.multiple else ''}{p.label} "
                         f"({(p.start + rec.t0) / 3600:.1f}-{(p.end + rec.t0) / 3600:.1f} h)")
    return where


def loud_blocks(evidence, residual_flat: np.ndarray, groups: list[str]) -> list[np.ndarray]:
    """Flat boolean masks of each record's block of each of ``groups`` whose residual stands above
    ``WITHIN`` times that record's noise and model error there (:func:`envelope`; the model error
    where the record has an estimate)."""
    out = []
    for k, (rec, res) in enumerate(zip(evidence.records, evidence.split(residual_flat))):
        for g in groups:
            cols = np.array(rec.groups) == g
            if not cols.any():
                continue
            err = None if rec.model_error is None else float(rms(np.asarray(rec.model_error)[cols]))
            if rms(res[:, cols]) / max(envelope((rec.noise.get(g, 0.0), err)), 1e-300) > WITHIN:
                mask = np.zeros(residual_flat.shape, bool)
                mask[evidence.offsets[k]:evidence.offsets[k + 1]] = np.broadcast_to(cols, res.shape).ravel()
                out.append(mask)
    return out


def above_noise(factors: dict[str, float]) -> list[str]:
    """The groups whose residual factor is above ``WITHIN`` (the groups the significance share
    counts, :class:`validate.verdict.Share`)."""
    return [g for g, f in factors.items() if f > WITHIN]


def share_text(factors: dict[str, float]) -> str:
    """Which groups the explained share counts: '(of the groups above noise: laser, temperature)',
    '(all groups)', or '(all groups, none above noise)'."""
    above = above_noise(factors)
    if not above or len(above) == len(factors):
        return "(all groups)" if above else "(all groups, none above noise)"
    return f"(of the groups above noise: {', '.join(above)})"


def ratio_text(f: float, limit: float = WITHIN, strict: bool = True) -> str:
    """``f`` as '4.9x': two decimals within 0.05 of ``limit`` (3.04x is not printed as the limit's
    3.0x), and more (up to four) where needed to keep the printed number on the side of ``limit``
    that ``f`` is on under the verdict's rule (``f > limit`` when ``strict``, else ``f >= limit``):
    3.004 is '3.004x', 9.996 (below ``BEYOND``) '9.996x', not '10.00x'."""
    above = (lambda v: v > limit) if strict else (lambda v: v >= limit)
    for digits in range(2 if abs(f - limit) < 0.05 else 1, 5):
        text = f"{f:.{digits}f}"
        if above(float(text)) == above(f):
            break
    return text + "x"


def beyond_text(beyond: float) -> str:
    """The fitted change over the model error's along the signature, as :func:`ratio_text` prints
    it on its side of ``BEYOND`` (the rule is ``beyond >= BEYOND``)."""
    return ratio_text(beyond, BEYOND, strict=False)


def _factor_text(g: str, f: float, level: tuple) -> str:
    """'probe 4.9x (noise 0.098 um, model error 0.12 um)', or '..., model error not estimated)'."""
    unit = residual_unit(g)
    noise, err = level
    e = f"model error {err:.2g} {unit}" if err is not None else "model error not estimated"
    return f"{g} {ratio_text(f)} (noise {noise:.2g} {unit}, {e})"


def _factors_text(factors: dict[str, float], levels: dict) -> str:
    return ", ".join(_factor_text(g, f, levels[g]) for g, f in factors.items())


def _inside(levels: dict) -> str:
    """'noise and model error', or 'noise' when no group has a model-error estimate."""
    return "noise" if all(e is None for _, e in levels.values()) else "noise and model error"


def _above_text(factors: dict[str, float], levels: dict, what: str) -> str:
    """'above noise and model error: probe 4.9x (...); temperature 2.4x (...) is within the limit
    of 3x': only the groups above ``WITHIN`` are called above (``what``: 'above', 'still
    above')."""
    above = {g: f for g, f in factors.items() if f > WITHIN}
    within = {g: f for g, f in factors.items() if f <= WITHIN}
    text = f"{what} {against(levels)}: {_factors_text(above, levels)}"
    if within:
        text += (f"; {_factors_text(within, levels)} {'is' if len(within) == 1 else 'are'} within the limit "
                 f"of {WITHIN:g}x")
    return text


def significance_reasons(top: dict, test: tuple[float, float]) -> str:
    """Why ``top`` fails the significance test (``test``: (BIC margin, share)): 'explains < 50 %',
    'dBIC < 10', or both."""
    margin, share = test
    out = []
    if top["delta_bic"] < margin:
        out.append(f"dBIC {top['delta_bic']:.1f} < {margin:g}")
    if top["explained"] < share:
        out.append(f"explains < {share:.0%}")
    return " and ".join(out) or "it fails the pair test"


def _all_groups_text(top: dict, factors: dict) -> str:
    """', 17% of all groups' when the share counts only the groups above noise (a second base,
    so the number compares with the region map's, which counts every group)."""
    above = above_noise(factors)
    if not above or len(above) == len(factors) or top.get("explained_all") is None:
        return ""
    return f", {top['explained_all']:.0%} of all groups"


def message(verdict: str, top: dict | None, factors: dict, after: dict | None, levels: dict,
            where: list[tuple[str, float]], when: str, regions: list[dict], beyond: float | None = None,
            test: tuple[float, float] = (10.0, 0.5), levels_after: dict | None = None) -> str:
    """One paragraph saying the verdict with its numbers. ``test``: the significance test's BIC
    margin and share (:func:`validate.diagnose.diagnose_many`'s ``bic_margin``, ``min_explained``);
    ``top['significant']`` says whether the top candidate passes it. Every percentage states its
    base (the groups above noise, or all groups); only the groups whose factor exceeds ``WITHIN``
    are called above noise and model error; without a model-error estimate the text says the
    comparison is with noise alone. ``levels_after``: the levels the factors after the candidate
    were taken against, when the model error was estimated again with the candidate in the model
    (:func:`validate.model_error.error_with`); ``levels`` otherwise."""
    fac = _factors_text(factors, levels)
    after_levels = levels_after or levels
    again = "the model error estimated again with the candidate in the model" if levels_after else ""
    env = against(levels)
    along = (f"; along its signature the fitted change is {beyond_text(beyond)} what the model error alone produces"
             if beyond is not None else "")
    share = share_text(factors)
    if verdict == "nothing_missing":
        head = f"nothing_missing: the residual is within {WITHIN:g}x {env} ({fac})"
        if not top:
            return head
        if top.get("significant"):
            why = (f"along its signature its fitted change is only {beyond_text(beyond)} what the model error alone "
                   f"produces (the verdict names a candidate within the envelope from {BEYOND:g}x)"
                   if beyond is not None else
                   "no model error was estimated, so whether it stands beyond the model's own discretisation "
                   "error could not be tested (--error-mesh auto, the default, estimates that error)")
            return (head + f"; the best candidate {top['effect']} is significant (dBIC {top['delta_bic']:.1f} >= "
                    f"{test[0]:g}, explains {top['explained']:.0%} >= {test[1]:.0%} of the weighted residual {share}), "
                    f"but that residual is itself within {_inside(levels)}, so the verdict does not name it: {why}")
        return (head + f"; the best candidate {top['effect']} would explain {top['explained']:.0%} of the weighted "
                f"residual {share}, dBIC {top['delta_bic']:.1f}: not significant "
                f"({significance_reasons(top, test)}){along}")
    if verdict in ("explained", "partly_explained"):
        head = (f"{verdict}: {top['statement']}; this explains {top['explained']:.0%} of the weighted residual "
                f"{share}, BIC weight {top['confidence']:.2f} among the candidates")
        if verdict == "explained" and not any(f > WITHIN for f in factors.values()):
            return (head + f"; the residual before it was within {env} ({fac}), but{along[1:]}; "
                    f"after it: {_factors_text(after, levels)}")
        if verdict == "explained":
            return (head + f"; residual after it within {against(after_levels)}{', ' + again if again else ''} "
                    f"({_factors_text(after, after_levels)}){along}")
        left = ", ".join(f"{c} {ratio_text(f)}" for c, f in where)
        return (head + f"; what remains{', against ' + again + ',' if again else ''} is "
                f"{_above_text(after, after_levels, 'still above')}; worst at {left}"
                + (f"; a heat input on {regions[0]['region']} would explain {regions[0]['explained']:.0%} of "
                   f"what remains (weighted, all groups)" if regions else ""))
    left = ", ".join(f"{c} {ratio_text(f)}" for c, f in where)
    best = ("there are no library candidates" if not top else
            f"the best library candidate {top['effect']} explains {'only ' * (top['explained'] < test[1])}"
            f"{top['explained']:.0%} of the weighted "
            f"residual {share}{_all_groups_text(top, factors)}, dBIC {top['delta_bic']:.1f}: not significant "
            f"({significance_reasons(top, test)})" if top["explained"] >= 0 else
            f"the best library candidate {top['effect']} explains none of it: fitted, it leaves the groups "
            f"above noise {-top['explained']:.0%} worse (dBIC {top['delta_bic']:.1f})")
    reg = (f"; a generic heat input fits best on {regions[0]['region']} ({regions[0]['power_W']:.3g} W "
           f"{regions[0]['schedule'].replace('_', ' ')}, explains {regions[0]['explained']:.0%} of the weighted "
           f"residual of all groups)" if regions else "")
    return (f"unexplained: the residual is {_above_text(factors, levels, 'above')}; {best}; no library candidate, "
            f"as fitted, explains it: the cause may lie outside the library (or a candidate's fit failed: see "
            f"its bounds); worst at {left}, mostly during {when}{reg}")


class Share:
    """The significance share 1 - SSE(g) / SSE_0 over A, the channels of the groups whose residual
    factor before any candidate (``factors``) is above ``WITHIN`` (every channel when none is;
    with several measurements, of each measurement's groups above ``WITHIN`` in it); SSE
    weighted, nuisance fitted. ``plain``: the baseline residual r - nuisance (flat), whose SSE over
    A is kept as SSE_0."""

    def __init__(self, evidence, fitter, factors: dict, plain: np.ndarray):
        above = above_noise(factors)
        self.fitter = fitter
        self.mask = (np.logical_or.reduce([evidence.group_mask(g) for g in above]) if above
                     else np.ones(fitter.r.shape, bool))
        if above and evidence.multiple:
            # several measurements: only each one's groups that stand above noise there (a quiet
            # ambient run's channels, noise-weighted, would otherwise hold most of SSE_0 and hide
            # what a candidate explains in the spindle run beside it)
            loud = loud_blocks(evidence, plain, above)
            if loud:
                self.mask = np.logical_or.reduce(loud)
        self.sse0 = self.sse(plain)

    def sse(self, residual: np.ndarray) -> float:
        """Weighted sum of squares of a flat residual over A."""
        e = (self.fitter.w * residual)[self.mask]
        return float(e @ e)

    def of_residual(self, residual: np.ndarray, reference_sse: float | None = None) -> float:
        """1 - SSE(residual) / SSE_ref over A (reference: the baseline's SSE_0)."""
        ref = self.sse0 if reference_sse is None else reference_sse
        return float(1 - self.sse(residual) / ref) if ref > 0 else 0.0

    def explained(self, g: np.ndarray, reference: np.ndarray | None = None) -> float:
        """The share a response g explains, of the baseline or of what ``reference`` leaves."""
        ref = None if reference is None else self.sse(self.fitter.residual_after(reference))
        return self.of_residual(self.fitter.residual_after(g), ref)
