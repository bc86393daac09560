"""What the channels a measurement lacks cost the diagnosis.

The machine's full instrument set is its temperature-sensor sites (glued ones), its probes, its
laser triangulation sensors and its FBG strain gauges (compensated readings). For each group a
measurement lacks wholly or partly (temperatures: wholly), the cost is stated for the top candidate as the
ratio of signal to instrument noise with the full set to that with the channels present:

    SNR = || g / sigma ||   over the samples,   cost = SNR_full / SNR_present,

g the top candidate's response at its fitted strength and sigma each instrument's noise
(``temperature_sensor.noise`` [K], ``probe.noise`` and ``laser_triangulation.noise`` [um],
``fbg.noise`` [um/m]; at least half its quantisation step).
For a linear candidate the standard error of the fitted strength scales as 1 / SNR, so the cost
is how many times less certain the strength is than with the full set. What the channels give
beyond that is telling candidates apart: the correlation of the runner-up's response with the
top one's, both weighted by the instrument noise, on the channels present and on the full set
(|corr| > 0.95: they cannot be told apart). Three extra runs on the first measurement's scenario.
"""

from __future__ import annotations

import numpy as np

from validate.evidence import POSITIONING_FLOOR
from validate.signatures import DISPLACEMENT_GROUPS, Engine


# group -> (instrument parameter group, its quantisation parameter), noise in SI
_INSTRUMENT = {"temperature": ("temperature_sensor", "quantisation", 1.0), "probe": ("probe", "resolution", 1e6),
               "laser": ("laser_triangulation", "resolution", 1e6), "strain": ("fbg", "quantisation", 1e6),
               "strain_raw": ("fbg", "quantisation", 1e6)}
_WHAT = {"temperature": "temperature sensors", "probe": "probes", "laser": "laser triangulation sensors",
         "strain": "FBG strain gauges"}


def _noise(spec) -> dict[str, float]:
    """group -> instrument noise in the channel's unit (at least half the quantisation step)."""
    out = {}
    for g, (group, quant, f) in _INSTRUMENT.items():
        p = spec.params[group]
        out[g] = max(p["noise"], 0.5 * p[quant], 1e-12) * f
    out["positioning"] = POSITIONING_FLOOR
    return out


def full_set(machine) -> dict[str, list[str]]:
    """group -> the machine's instruments of that group (glued temperature sites, probes, lasers,
    FBG gauges)."""
    return {"temperature": list(machine.sensor_sites), "probe": [p.name for p in machine.probes],
            "laser": [p.name for p in machine.lasers], "strain": [g.name for g in machine.strain_gauges]}


def missing_channels(d, machine) -> list[dict]:
    """[{group, missing, of, note, cost, runner_up, corr_present, corr_full}] for each channel group
    the measurements lack (wholly, or probes, lasers and gauges partly) against the machine's full
    set; ``cost`` as in the module doc and the correlation of the runner-up's response with the top
    one's on the channels present and on the full set (None without candidates)."""
    full = full_set(machine)
    have = {g: {c.split(":", 1)[1] for r in d.evidence.records for c, gg in zip(r.channels, r.groups)
                if gg == g or (g == "strain" and gg == "strain_raw")} for g in full}
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
    sizes = ", ".join(f"{len(v)} {_WHAT[g]}" for g, v in full.items() if v)
    for gap in gaps:
        g = gap["group"]
        what = _WHAT[g]
        if gap["missing"] == gap["of"]:
            note = {"temperature": f"no {what}: heat is seen only through the drift it causes",
                    "strain": f"no {what}: the structure's own deformation is not seen"}.get(
                g, f"no {what}: the drift they read is not seen")
        else:
            note = f"{gap['missing']} of the machine's {gap['of']} {what} missing"
        gap.update(numbers)
        if numbers["cost"] is not None:
            note += (f"; with the machine's full set ({sizes}) the top candidate's response would stand "
                     f"{numbers['cost']:.1f}x higher above the instrument noise")
        if numbers.get("runner_up"):
            note += (f"; the runner-up {numbers['runner_up']}'s response is {numbers['corr_present']:.2f} correlated "
                     f"with the top one's on these channels, {numbers['corr_full']:.2f} on the full set (above 0.95 "
                     "they cannot be told apart)")
        gap["note"] = note
    if not set(DISPLACEMENT_GROUPS) & set(d.evidence.groups()):
        for gap in gaps:
            if gap["group"] != "temperature":
                gap["note"] += ", and without any drift or strain channel the materials' expansion cannot be fitted"
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
    keep = np.array([g != "strain_raw" for g in engine.groups])   # each gauge once, compensated
    s = np.array([sigma[g] for g in engine.groups])[keep]
    base = rec.interp(engine.observe(d.spec))[:, keep]
    full = [(_response(d, engine, rec, d.fits[0])[:, keep] - base) / s] + present[1:]
    snr_p = float(np.sqrt(sum(np.sum(x ** 2) for x in present)))
    snr_f = float(np.sqrt(sum(np.sum(x ** 2) for x in full)))
    out = {"cost": (max(snr_f, snr_p) / snr_p) if snr_p > 0 else None,
           "runner_up": None, "corr_present": None, "corr_full": None}
    if len(d.fits) > 1:
        second = d.fits[1]
        p2 = [g / w for g, w in zip(ev.split(second.response), weights)]
        f2 = [(_response(d, engine, rec, second)[:, keep] - base) / s] + p2[1:]
        corr = lambda a, b: float(sum(np.sum(x * y) for x, y in zip(a, b)) / max(
            np.sqrt(sum(np.sum(x ** 2) for x in a) * sum(np.sum(y ** 2) for y in b)), 1e-300))
        out.update(runner_up=second.name, corr_present=corr(present, p2), corr_full=corr(full, f2))
    return out
