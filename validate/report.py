"""HTML report of a diagnosis: measured vs model per channel (phases shaded), the machine with
sensors coloured by residual RMSE, the candidate ranking, and before/after overlays."""

from __future__ import annotations

import base64
import html
import io
import os
from pathlib import Path

import numpy as np

from learners.metrics import rms
from twin.errors import InputError, describe
from twin.io.atomic import atomic_write_text, output_folder
from twin.io.paths import output_folder as checked_folder
from validate.channels import residual_unit
from validate.verdict import WITHIN, against
from validate.report_map import machine_outline as _machine_outline

def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


_SPINDLE_COLOURS = {"spindle on": "orange", "speed change": "gold", "spindle off": None, "C axis on": "C4",
                    "C axis speed change": "C6", "C axis off": None}
_AMBIENT_COLOURS = {"ambient rising": "C3", "ambient falling": "C0", "ambient steady": None}


def _shade_phases(ax, phases, label: bool = False, offset: float = 0.0) -> list:
    """Shade spindle phases (on: orange, speed change: gold, off: clear) over the whole height and
    ambient rising (red) / falling (blue) as a strip along the bottom; with ``label``, write each
    spindle phase's name at the top. Returns legend handles."""
    from matplotlib.patches import Patch

    seen = {}
    for p in phases:
        th = ((p.start + offset) / 3600, (p.end + offset) / 3600)
        if p.kind in ("spindle", "c_axis"):
            key = next(k for k in _SPINDLE_COLOURS if p.label.startswith(k))
            colour = _SPINDLE_COLOURS[key]
            if colour:
                ax.axvspan(*th, color=colour, alpha=0.15, lw=0)
                seen.setdefault(key, Patch(color=colour, alpha=0.3, label=key))
            if label:
                ax.text(0.5 * sum(th), 1.2, p.label, transform=ax.get_xaxis_transform(), ha="center",
                        va="bottom", fontsize=7, color="0.3")
        else:
            colour = _AMBIENT_COLOURS.get(p.label)
            if colour:
                ax.axvspan(*th, ymin=0, ymax=0.04, color=colour, alpha=0.5, lw=0)
                seen.setdefault(p.label, Patch(color=colour, alpha=0.5, label=p.label + " (bottom strip)"))
    return list(seen.values())


def _candidate_text(c: dict, names: bool = True) -> str:
    """``effect param = value unit`` (3 significant digits; values below 1e-9 of the parameter's
    range shown as 0) from the candidate's SI values; ``names=False`` drops the effect name."""
    from twin.effects import EFFECTS
    from twin.units import format_quantity

    out = []
    for e, vals in c["values_si"].items():
        for k, v in vals.items():
            par = EFFECTS[e].parameter(k)
            v = 0.0 if abs(v) < 1e-9 * (par.upper - par.lower) else float(f"{v:.3g}")
            out.append(f"{e + ' ' if names or len(c['values_si']) > 1 else ''}{k} = {format_quantity(v, par.dimension)}")
    return "; ".join(out)


def figures(d, machine, after: np.ndarray | None = None) -> dict[str, str]:
    """Base64 PNGs keyed by title: per measurement the worst channels measured vs model (phases
    shaded) and the machine with its sensors coloured by residual RMSE [K] (before and, with
    ``after`` (flat, every record), after adding the top candidate); the candidate ranking; and,
    when the diagnosis localised the missing heat, the map of the machine's regions."""
    import matplotlib
    matplotlib.use("Agg")

    out = {}
    afters = d.evidence.split(after) if after is not None else [None] * len(d.evidence.records)
    many = d.evidence.multiple
    for rec, aft in zip(d.evidence.records, afters):
        tag = f" ({rec.label})" if many else ""
        out[f"Measured vs model, the worst channels{tag} (diagnosis mesh; dashed: after adding the top candidate)"] = \
            _worst_channels(d, rec, aft)
        if "temperature" in rec.groups and rec.sensor_points:
            out[f"The machine with its temperature sensors coloured by residual RMSE{tag}"] = _sensor_map(d, rec, aft, machine)
    if d.candidates:
        out["Candidate ranking"] = _ranking(d)
    if d.regions:
        from validate.report_map import region_map
        out["Where on the machine: regions coloured by the fitted heat input"] = _png(region_map(d, machine))
    return out


def _worst_channels(d, rec, after) -> str:
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    th = (rec.times + rec.t0) / 3600      # on the log's own clock
    top = _candidate_text(d.candidates[0]) if d.candidates else ""
    base_rmse = rms(rec.measured - rec.model, axis=0)
    order = np.argsort(-base_rmse * rec.weights)[:6]
    fig, axes = plt.subplots(len(order), 1, figsize=(8, 1.9 * len(order) + 0.6), sharex=True, squeeze=False)
    handles = []
    for i, (ax, k) in enumerate(zip(axes[:, 0], order)):
        handles = _shade_phases(ax, rec.phases, label=i == 0, offset=rec.t0) or handles
        ax.plot(th, rec.measured[:, k], "k.", ms=2)
        ax.plot(th, rec.model[:, k], "C0-")
        if after is not None:
            ax.plot(th, after[:, k], "C3--")
        unit = "degC" if rec.groups[k] == "temperature" else residual_unit(rec.groups[k])
        ax.set_ylabel(f"[{unit}]", fontsize=8)
        ax.set_title(f"{rec.channels[k]}: RMSE {base_rmse[k]:.3g}"
                     + (f" -> {rms(rec.measured[:, k] - after[:, k]):.3g}" if after is not None else "")
                     + f" {'K' if unit == 'degC' else unit}", fontsize=8, loc="left")
    lines = [Line2D([], [], color="k", marker=".", ls="", label="measured"),
             Line2D([], [], color="C0", label="model")]
    if after is not None:
        lines.append(Line2D([], [], color="C3", ls="--", label=f"model + {top}"))
    axes[-1, 0].set_xlabel("time since start [h]")
    entries = lines + handles
    fig.tight_layout(rect=(0, 0.015 + 0.014 * -(-len(entries) // 3), 1, 1))
    fig.legend(handles=entries, loc="lower center", ncol=3, fontsize=7, bbox_to_anchor=(0.5, 0.0))
    return _png(fig)


def _sensor_map(d, rec, after, machine) -> str:
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    top = _candidate_text(d.candidates[0]) if d.candidates else ""
    temps = [i for i, g in enumerate(rec.groups) if g == "temperature"]
    rows = [("before", rms(rec.measured - rec.model, axis=0)[temps])]
    if after is not None:
        rows.append(("after", rms(rec.measured - after, axis=0)[temps]))
    norm = Normalize(0, max(float(rows[0][1].max()), 1e-9))
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 4.6 * len(rows)), squeeze=False, layout="constrained")
    points = rec.sensor_points
    xyz = np.array([p.xyz for p in points])
    for (what, values), axrow in zip(rows, axes):
        for ax, (a, b, view) in zip(axrow, ((0, 2, "front view (x-z)"), (1, 2, "side view (y-z, machine front on the left)"))):
            _machine_outline(ax, machine, a, b)
            sc = ax.scatter(xyz[:, a], xyz[:, b], c=values, cmap="inferno_r", norm=norm, s=60, edgecolor="k", zorder=3)
            for n, (x, z) in enumerate(zip(xyz[:, a], xyz[:, b]), 1):
                ax.annotate(str(n), (x, z), xytext=(5, 2), textcoords="offset points", fontsize=7, color="0.2")
            ax.set_xlabel(f"{'xy'[a]} [m]")
            ax.set_ylabel("z [m]")
            ax.set_title(f"{what}: {view}", fontsize=9)
            ax.set_aspect("equal")
            ax.autoscale()
    fig.colorbar(sc, ax=axes, label="residual RMSE of each temperature sensor [K]", shrink=0.7)
    key = ", ".join(f"{n} {p.name}" for n, p in enumerate(points, 1))
    fig.text(0.0, -0.01, "sensors: " + key + (f"\nafter: with {top}" if after is not None else ""), fontsize=7,
             va="top", wrap=True)
    return _png(fig)


def _ranking(d) -> str:
    import matplotlib.pyplot as plt

    from validate.verdict import share_text

    c = d.candidates[:10][::-1]
    fig, ax = plt.subplots(figsize=(8, 0.45 * len(c) + 1.2))
    named = d.verdict in ("explained", "partly_explained")
    colours = ["C2" if (x is d.candidates[0] and named) else "C1" if x.get("significant") else "0.6" for x in c]
    ax.barh([x["effect"] for x in c], [100 * x["explained"] for x in c], color=colours)
    for y, x in enumerate(c):
        bound = ", AT A BOUND" if x.get("at_bound") else ""
        ax.text(max(100 * x["explained"], 0) + 1, y,
                f"{_candidate_text(x, names=False)}{bound}, BIC weight {x['confidence']:.2f}", va="center", fontsize=7)
    ax.set_xlim(0, 160)
    ax.set_xticks(range(0, 101, 20))
    ax.set_xlabel(f"share of the weighted residual {share_text(d.residual_factor)} the candidate explains at its "
                  f"fitted value [%]")
    ax.set_title(f"verdict {d.verdict}; green: the candidate the verdict names; orange: passes the significance "
                 f"test, not named; grey: fails it", fontsize=8)
    return _png(fig)


_CSS = ("body{font-family:sans-serif;max-width:1100px;margin:1em auto;padding:0 1em}"
        "pre{white-space:pre-wrap;font-size:12px;background:#f6f6f6;padding:.5em}"
        "img{max-width:100%}p.caption{color:#444;font-size:13px}")
_CAPTIONS = {
    "Measured": "Black dots: the measurement; blue: the model as it is; red dashed: the model with the top "
                "candidate at its fitted strength. Shading: the phases found from the inputs (spindle on, "
                "speed changes, the C axis turning; a red/blue strip at the bottom: room air rising/falling). Each panel's title "
                "gives the channel's RMSE before -> after (temperatures in K, probes and lasers in um, strains in "
                "um/m).",
    "The machine": "Each dot is a temperature sensor at its place on the machine (grey: the part outlines), "
                   "coloured by the RMSE of measured minus model; the numbers are keyed below the picture.",
    "Candidate": "Each effect the model lacks and each uncertain parameter of its own effects, fitted to the "
                 "residual; the bar is the share of the weighted residual it explains (over the channel groups "
                 "above noise and model error, every group when none is), the label its fitted value (AT A BOUND "
                 "when a member sits at a bound of its range) and its BIC weight (the Schwarz weight of the "
                 "candidate among these candidates and 'nothing missing': relative, so the best of a poor set "
                 "holds about 1.00; not the probability that it is the cause). Green: the candidate the verdict "
                 "names; orange: it passes the significance test (>= {margin:g} BIC units, >= {share:.0%} explained) "
                 "but the verdict does not name it (it is not the top candidate, or the residual is within "
                 "{within:g}x {envelope}); grey: it fails the test.",
    "Where": "A generic heat input (constant, or while the spindle turns) fitted alone on each region of the "
             "machine's partition (each part, each part's outer faces by direction); the best regions are "
             "coloured by their fitted power [W] (volumes filled, faces as thick edges or hatched when they face "
             "the viewer), the temperature sensors by the residual RMSE left after the verdict's model [K].",
}


def write_report(d, machine, folder: str | os.PathLike, after: np.ndarray | None = None,
                 sections: list[tuple[str, str]] | None = None,
                 closing: list[tuple[str, str]] | None = None, calibrated: np.ndarray | None = None) -> Path:
    """Write ``folder/index.html`` atomically (figures embedded); returns its path.

    Order: the verdict; ``sections`` (title, preformatted text), e.g. the comparison table of
    :func:`validate.compare.format_compare`; the candidate ranking; RMSE before/after on the
    diagnosing model (with ``after``; with ``calibrated``, the rerun with the fitted material
    expansion, too); ``closing`` sections; the figures with captions. ``machine`` is the
    diagnosis's; ``folder`` an existing folder or one that can be made in an existing one. The
    page is made before the folder: a bad argument leaves nothing behind."""
    from validate.diagnose import format_diagnosis
    from validate.apply import check_diagnosis, format_before_after

    def block(title: str, text: str) -> str:
        return f"<h2>{html.escape(title)}</h2><pre>{html.escape(text)}</pre>"

    check_diagnosis(d, "write_report")
    own = d.twin.machine.name if d.twin is not None else None
    if getattr(machine, "name", None) is None or not hasattr(machine, "parts") or (own and machine.name != own):
        raise InputError("write_report", "machine", f"expected the diagnosis's machine{f' ({own})' if own else ''}, "
                                                    f"got {describe(getattr(machine, 'name', machine))}")
    for name, items in (("sections", sections), ("closing", closing)):
        if items is not None and (not isinstance(items, (list, tuple)) or not all(
                isinstance(i, (list, tuple)) and len(i) == 2 and all(isinstance(x, str) for x in i) for i in items)):
            raise InputError("write_report", name, f"expected a list of (title, text) pairs, got {describe(items)}")
    folder = checked_folder(folder, "folder")
    parts = [f"<html><head><meta charset='utf-8'><title>twin diagnose</title><style>{_CSS}</style></head><body>",
             "<h1>Diagnosis: what the model lacks</h1>", f"<p><b>{html.escape(d.message)}</b></p>"]
    parts += [block(t, x) for t, x in sections or []]
    parts.append(block("Ranking of the candidate effects", format_diagnosis(d)))
    if after is not None:
        parts.append(block("RMSE before and after adding the top candidate (diagnosing model)",
                           format_before_after(d, after, calibrated)))
    parts += [block(t, x) for t, x in closing or []]
    for title, png in figures(d, machine, after).items():
        caption = next((c for k, c in _CAPTIONS.items() if title.startswith(k)), "").format(
            margin=d.test[0], share=d.test[1], within=WITHIN, envelope=against(d.levels))   # this diagnosis's test
        parts.append(f"<h2>{html.escape(title)}</h2><p class='caption'>{html.escape(caption)}</p>"
                     f"<img src='data:image/png;base64,{png}'/>")
    parts.append("</body></html>")
    with output_folder(folder):      # made for the page, removed again if writing it fails
        return atomic_write_text(folder / "index.html", "\n".join(parts))
