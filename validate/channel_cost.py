"""What the channels a measurement lacks cost the diagnosis.

The machine's full instrument set is its temperature-sensor sites (glued ones) and its probes. For
each group a measurement lacks wholly or partly, the cost is stated for the top candidate as the
ratio of signal to instrument noise with the full set to that with the channels present:

    SNR = || g / sigma ||   over the samples,   cost = SNR_full / SNR_present,

g the top candidate's response at its fitted strength and sigma each instrument's noise
(``temperature_sensor.noise`` [K], ``probe.noise`` [um]; at least half its quantisation step).
For a linear candidate the standard error of the fitted strength scales as 1 / SNR, so the cost
is how many times less certain the strength is than with the full set (two extra runs on the first
measurement's scenario).
"""

from __future__ import annotations

import numpy as np

from validate.signatures import Engine


def _noise(spec) -> dict[str, float]:
    t, p = spec.params["temperature_sensor"], spec.params["probe"]
    return {"temperature": max(t["noise"], 0.5 * t["quantisation"], 1e-6),
            "probe": max(p["noise"], 0.5 * p["resolution"], 1e-12) * 1e6}


def missing_channels(d, machine) -> list[dict]:
    """[{group, missing, of, note, cost}] for each channel group the measurements lack (wholly or
    partly) against the machine's full set; ``cost`` as in the module doc (None without a
    candidate)."""
    sites = [machine.point(n).name for n in machine.sensor_sites]
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
    cost = _cost(d, machine) if d.fits else None
    for gap in gaps:
        g = gap["group"]
        what = "temperature sensors" if g == "temperature" else "probes"
        if gap["missing"] == gap["of"]:
            note = (f"no {what}: heat is seen only through the drift it causes" if g == "temperature" else
                    f"no {what}: the drift is not seen, and the materials' expansion cannot be fitted")
        else:
            note = f"{gap['missing']} of the machine's {gap['of']} {what} missing"
        gap["cost"] = cost
        if cost is not None:
            note += (f"; with the machine's full set ({len(sites)} sensor sites, {len(probes)} probes) the top "
                     f"candidate's response would stand {cost:.1f}x higher above the instrument noise, so its "
                     f"strength would be about {cost:.1f}x more certain")
        gap["note"] = note
    return gaps


def _cost(d, machine) -> float | None:
    """SNR_full / SNR_present of the top fit (module doc)."""
    f = d.fits[0]
    spec = d.spec
    for c, v in zip(f.candidates, f.values):
        spec = c.spec(spec, v)
    sigma = _noise(d.spec)
    present = 0.0
    for rec, g in zip(d.evidence.records, d.evidence.split(f.response)):
        s = np.array([sigma[k] for k in rec.groups])
        present += float(np.sum((g / s) ** 2))
    rec = d.evidence.records[0]
    engine = Engine(machine, rec.scenario, mm=d.twin.mm, prepared=d.twin,
                    sensors=[machine.point(n) for n in machine.sensor_sites])
    g_full = rec.interp(engine.observe(spec) - engine.observe(d.spec))
    s = np.array([sigma["temperature"]] * engine.nsensor + [sigma["probe"]] * len(engine.probe_names))
    full = float(np.sum((g_full / s) ** 2))
    for other in d.evidence.records[1:]:   # the other records as they are (their share, unchanged)
        gg = d.evidence.split(f.response)[d.evidence.records.index(other)]
        full += float(np.sum((gg / np.array([sigma[k] for k in other.groups])) ** 2))
    if present <= 0:
        return None
    return float(np.sqrt(max(full, present) / present))
