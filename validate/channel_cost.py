"""What the channels a measurement lacks cost the diagnosis.

The machine's full instrument set is its temperature-sensor sites (glued ones) and its probes. For
each group a measurement lacks wholly or partly, the cost is stated for the top candidate as the
ratio of signal to instrument noise with the full set to that with the channels present:

    SNR = || g / sigma ||   over the samples,   cost = SNR_full / SNR_present,

g the top candidate's response at its fitted strength and sigma each instrument's noise
(``temperature_sensor.noise`` [K], ``probe.noise`` [um]; at least half its quantisation step).
For a linear candidate the standard error of the fitted strength scales as 1 / SNR, so the cost
is how many times less certain the strength is than with the full set. What the channels give
beyond that is telling candidates apart: the correlation of the runner-up's response with the
top one's, both weighted by the instrument noise, on the channels present and on the full set
(|corr| > 0.95: they cannot be told apart). Three extra runs on the first measurement's scenario.
"""

from __future__ import annotations

import numpy as np

from validate.signatures import Engine


def _noise(spec) -> dict[str, float]:
    t, p = spec.params["temperature_sensor"], spec.params["probe"]
    return {"temperature": max(t["noise"], 0.5 * t["quantisation"], 1e-6),
            "probe": max(p["noise"], 0.5 * p["resolution"], 1e-12) * 1e6}


def missing_channels(d, machine) -> list[dict]:
    """[{group, missing, of, note, cost, runner_up, corr_present, corr_full}] for each channel group
    the measurements lack (wholly, or probes partly) against the machine's full set; ``cost`` as in
    the module doc and the correlation of the runner-up's response with the top one's on the
    channels present and on the full set (None without candidates)."""
    sites = list(machine.sensor_sites)
    probes = [p.name for p in machine.probes]
    full = {"temperature": sites, "probe": probes}
    have = {g: {c.split(":", 1)[1] for r in d.evidence.records for c, gg in zip(r.channels, r.groups) if gg == g}
            for g in full}
    gaps = []
    for g, names in full.items():
        if not names:
            continue
        present = len(have[g]) if g == "temperature" else len(have[g] & set(names))
        if present < len(names) and (g != "temperature" or present == 0):
            gaps.append({"group": g, "missing": len(names) - present, "of": len(names)})
    if not gaps:
        return []
    numbers = _cost(d, machine) if d.fits else {"cost": None}
    for gap in gaps:
        g = gap["group"]
        what = "temperature sensors" if g == "temperature" else "probes"
        if gap["missing"] == gap["of"]:
            note = (f"no {what}: heat is seen only through the drift it causes" if g == "temperature" else
                    f"no {what}: the drift is not seen, and the materials' expansion cannot be fitted")
        else:
            note = f"{gap['missing']} of the machine's {gap['of']} {what} missing"
        gap.update(numbers)
        if numbers["cost"] is not None:
            note += (f"; with the machine's full set ({len(sites)} sensor sites, {len(probes)} probes) the top "
                     f"candidate's response would stand {numbers['cost']:.1f}x higher above the instrument noise")
        if numbers.get("runner_up"):
            note += (f"; the runner-up {numbers['runner_up']}'s response is {numbers['corr_present']:.2f} correlated "
                     f"with the top one's on these channels, {numbers['corr_full']:.2f} on the full set (above 0.95 "
                     "they cannot be told apart)")
        gap["note"] = note
    return gaps


def _response(d, engine, rec, fit) -> np.ndarray:
    spec = d.spec
    for c, v in zip(fit.candidates, fit.values):
        spec = c.spec(spec, v)
    return rec.interp(engine.observe(spec))


def _cost(d, machine) -> dict:
    """SNR_full / SNR_present of the top fit, and the top and runner-up responses' correlation (on
    the instrument-noise-weighted channels) present and full (first measurement's scenario)."""
    sigma = _noise(d.spec)
    ev = d.evidence
    weights = [np.array([sigma[k] for k in rec.groups]) for rec in ev.records]
    present = [g / s for g, s in zip(ev.split(d.fits[0].response), weights)]
    rec = ev.records[0]
    engine = Engine(machine, rec.scenario, mm=d.twin.mm, prepared=d.twin,
                    sensors=[machine.point(n) for n in machine.sensor_sites])
    s = np.array([sigma["temperature"]] * engine.nsensor + [sigma["probe"]] * len(engine.probe_names))
    base = rec.interp(engine.observe(d.spec))
    full = [(_response(d, engine, rec, d.fits[0]) - base) / s] + present[1:]
    snr_p = float(np.sqrt(sum(np.sum(x ** 2) for x in present)))
    snr_f = float(np.sqrt(sum(np.sum(x ** 2) for x in full)))
    out = {"cost": (max(snr_f, snr_p) / snr_p) if snr_p > 0 else None,
           "runner_up": None, "corr_present": None, "corr_full": None}
    if len(d.fits) > 1:
        second = d.fits[1]
        p2 = [g / w for g, w in zip(ev.split(second.response), weights)]
        f2 = [(_response(d, engine, rec, second) - base) / s] + p2[1:]
        corr = lambda a, b: float(sum(np.sum(x * y) for x, y in zip(a, b)) / max(
            np.sqrt(sum(np.sum(x ** 2) for x in a) * sum(np.sum(y ** 2) for y in b)), 1e-300))
        out.update(runner_up=second.name, corr_present=corr(present, p2), corr_full=corr(full, f2))
    return out
