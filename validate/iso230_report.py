"""The ISO 230-3 report of an :class:`validate.iso230.Evaluation`: ``report.md`` (the tables) and
``index.html`` (the same tables and the figures, embedded), both written atomically."""

from __future__ import annotations

import html
from pathlib import Path

from twin.io.atomic import atomic_write_text
from twin.io.markdown import fixed, table
from validate.iso230 import WARNING, Evaluation
from validate.report import _CSS, _png

TITLES = {"etve": "Environmental temperature variation error (ETVE)",
          "spindle": "Thermal distortion caused by a rotating spindle",
          "axis": "Thermal distortion caused by moving linear axes"}


def sections(ev: Evaluation) -> list[tuple[str, list[str]]]:
    """(title, Markdown lines) of the report, in order."""
    out = [("Test conditions", table(["item", "value"], [[k, v] for k, v in ev.conditions]))]
    if ev.departures:
        out.append(("Departures from the test's conditions", [f"- {d}" for d in ev.departures]))
    rows = [[c.name, fixed(c.range), fixed(c.values.min()), fixed(c.values.max()), c.unit] for c in ev.channels]
    lines = table(["channel", "maximum range", "min", "max", "unit"], rows)
    if ev.air is not None:
        where = "at the interferometer's runs" if ev.test == "axis" else "over the test"   # the axis test reads runs
        lines += ["", f"Room air range {where}: {ev.air_range:.3f} K "
                      f"({ev.air.min():.2f} to {ev.air.max():.2f} degC)."]
    out.append(("Maximum range over the test", lines))
    if ev.test == "etve":
        out.append(("Caution", [WARNING]))
    if ev.steps:
        ranges = ev.step_ranges()
        names = [c.name for c in ev.channels]
        rows = [[f"{a / 3600:.3g}-{b / 3600:.3g} h", f"{n:g} rpm"] + [fixed(r[k]) for k in names]
                for (a, b, n), r in zip(ev.steps, ranges)]
        heads = [f"{c.name} [{c.unit}]" for c in ev.channels]
        out.append(("Range within each speed step", table(["step", "speed"] + heads, rows)))
    if ev.runs:
        rows = [[f"{t / 3600:.3f} h"] + [fixed(c.values[i]) for c in ev.channels] + ([f"{ev.air[i]:.2f}"] if
                                                                                      ev.air is not None else [])
                for i, t in enumerate(ev.time)]
        head = ["run"] + [c.name for c in ev.channels] + (["room air [degC]"] if ev.air is not None else [])
        units = ", ".join(sorted({c.unit for c in ev.channels}))
        out.append(("Positioning-error change at the targets, run by run",
                    table(head, rows) + ["", f"Each target's positioning error minus the first run's [{units}], "
                                              "the mean of both approach directions."]))
    stats = []
    for c in ev.channels:
        rows = [[f"{s['start'] / 3600:.3g}-{s['end'] / 3600:.3g} h", fixed(s['min']), fixed(s['max']),
                 fixed(s['mean']), f"{fixed(s['low'])} .. {fixed(s['high'])}", fixed(s['p95_abs'])]
                for s in ev.segment_stats()[c.name]]
        stats += [f"**{c.name}** [{c.unit}]", ""] + table(
            ["segment", "min", "max", "mean", "mean -/+ 2 std", "95th percentile of abs. value"], rows) + [""]
    out.append(("Segment statistics", stats))
    return out


def markdown(ev: Evaluation) -> str:
    lines = [f"# ISO 230-3: {TITLES[ev.test]}", ""]
    for title, body in sections(ev):
        lines += [f"## {title}", ""] + body + [""]
    return "\n".join(lines)


def figures(ev: Evaluation) -> dict[str, str]:
    """Base64 PNGs keyed by title: channels over time (air or speed on a second axis); for ETVE each
    channel against the room air."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = {}
    units = sorted({c.unit for c in ev.channels}, key=lambda u: u != "um")
    fig, axes = plt.subplots(len(units), 1, figsize=(9, 3.2 * len(units)), sharex=True, squeeze=False)
    h = ev.time / 3600
    for ax, unit in zip(axes[:, 0], units):
        for c in ev.channels:
            if c.unit == unit:
                ax.plot(h, c.values, label=c.name, lw=1)
        ax.set_ylabel(unit)
        ax.legend(loc="upper left", fontsize=8)
        ax.grid(alpha=0.3)
    top = axes[0, 0].twinx()
    if ev.air is not None and ev.test == "etve":
        top.plot(h, ev.air, color="0.5", ls="--", lw=1)
        top.set_ylabel("room air [degC]", color="0.4")
    elif ev.steps:
        top.step([a / 3600 for a, _, _ in ev.steps] + [h[-1]], [n for _, _, n in ev.steps] + [ev.steps[-1][2]],
                 where="post", color="0.5", ls="--", lw=1)
        top.set_ylabel("spindle speed [rpm]", color="0.4")
    else:
        top.set_axis_off()
    axes[-1, 0].set_xlabel("time [h]")
    out["Drift and tilts over the test"] = _png(fig)
    if ev.test == "etve":
        n = len(ev.channels)
        fig, axes = plt.subplots(1, n, figsize=(3.0 * n, 3.0), squeeze=False)
        for ax, c in zip(axes[0], ev.channels):
            ax.plot(ev.air, c.values, lw=0.8)
            ax.set_xlabel("room air [degC]")
            ax.set_title(f"{c.name} [{c.unit}]", fontsize=9)
            ax.grid(alpha=0.3)
        fig.tight_layout()
        out["Drift and tilts against the room air"] = _png(fig)
    return out


def write_iso230_report(ev: Evaluation, folder: str | Path) -> tuple[Path, Path]:
    """Write ``folder/report.md`` and ``folder/index.html`` (figures embedded), each atomically."""
    folder = Path(folder)
    md = atomic_write_text(folder / "report.md", markdown(ev))
    parts = [f"<html><head><meta charset='utf-8'><title>ISO 230-3 {ev.test}</title><style>{_CSS}</style></head><body>",
             f"<h1>ISO 230-3: {html.escape(TITLES[ev.test])}</h1>"]
    for title, body in sections(ev):
        parts.append(f"<h2>{html.escape(title)}</h2>" + _html_body(body))
    for title, png in figures(ev).items():
        parts.append(f"<h2>{html.escape(title)}</h2><img src='data:image/png;base64,{png}'/>")
    parts.append("</body></html>")
    return md, atomic_write_text(folder / "index.html", "\n".join(parts))


def _html_body(lines: list[str]) -> str:
    """Markdown tables and paragraphs of :func:`sections` as HTML."""
    out, rows = [], []

    def flush():
        if rows:
            head, body = rows[0], rows[2:]
            out.append("<table><tr>" + _cells(head, "th") + "</tr>" + "".join(f"<tr>{_cells(r, 'td')}</tr>" for r in body)
                       + "</table>")
            rows.clear()

    for line in lines:
        if line.startswith("|"):
            rows.append(line)
            continue
        flush()
        if line.strip():
            text = html.escape(line)
            if line.startswith("- "):    # an item of a list: a paragraph with a bullet
                text = "&bull; " + html.escape(line[2:])
            if line.startswith("**") and "**" in line[2:]:
                name, rest = line[2:].split("**", 1)
                text = f"<b>{html.escape(name)}</b>{html.escape(rest)}"
            out.append(f"<p>{text}</p>")
    flush()
    return "\n".join(out)



def _cells(row: str, tag: str) -> str:
    return "".join(f"<{tag}>{html.escape(c.strip())}</{tag}>" for c in row.strip().strip("|").split("|"))
