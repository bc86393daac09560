"""HTML report of a diagnosis: measured vs model per channel (phases shaded), the machine with
sensors coloured by residual RMSE, the candidate ranking, and before/after overlays."""

from __future__ import annotations

import base64
import html
import io
import os
import tempfile
from pathlib import Path

import numpy as np


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


def _shade_phases(ax, d):
    """Shade spans where the model's spindle ran (from the scenario the diagnosis used)."""
    sc = getattr(d, "scenario", None)
    if sc is None:
        return
    for (t0, t1), (_, n) in zip(zip(sc.step_starts[:-1], sc.step_starts[1:]), sc.steps):
        if n > 0:
            ax.axvspan(t0 / 3600, t1 / 3600, color="orange", alpha=0.12, lw=0)


def figures(d, machine, after: np.ndarray | None = None) -> dict[str, str]:
    """Base64 PNGs keyed by title."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from validate.diagnose import UNITS

    out = {}
    th = d.times / 3600
    order = np.argsort(-d.baseline_rmse * d.weights)[:6]
    fig, axes = plt.subplots(len(order), 1, figsize=(8, 2.0 * len(order)), sharex=True, squeeze=False)
    for ax, k in zip(axes[:, 0], order):
        _shade_phases(ax, d)
        ax.plot(th, d.measured[:, k], "k.", ms=2, label="measured")
        ax.plot(th, d.model[:, k], "C0-", label="model")
        if after is not None:
            ax.plot(th, after[:, k], "C3--", label="model + top candidate")
        ax.set_ylabel(f"{d.channels[k]}\n[{'degC' if d.groups[k] == 'temperature' else 'um'}]", fontsize=7)
    axes[0, 0].legend(fontsize=7)
    axes[-1, 0].set_xlabel("time [h] (shaded: spindle on)")
    out["Measured vs model, worst channels (before/after overlay dashed)"] = _png(fig)

    temps = [i for i, g in enumerate(d.groups) if g == "temperature"]
    if temps and d.sensor_points:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        xyz = np.array([p.xyz for p in d.sensor_points])
        for ax, (a, b, la) in zip(axes, ((0, 2, "x-z"), (1, 2, "y-z"))):
            for part in machine.parts:
                for box in part.boxes:
                    ax.add_patch(plt.Rectangle((box.lo[a], box.lo[b]), box.hi[a] - box.lo[a], box.hi[b] - box.lo[b],
                                               fill=False, lw=0.5, color="grey"))
            sc = ax.scatter(xyz[:, a], xyz[:, b], c=d.baseline_rmse[temps], cmap="inferno_r", s=40, edgecolor="k")
            ax.set_xlabel(f"{'xy'[a]} [m]")
            ax.set_ylabel("z [m]")
            ax.set_title(la)
            ax.set_aspect("equal")
            ax.autoscale()
        fig.colorbar(sc, ax=axes, label=f"baseline residual RMSE [{UNITS['temperature']}]")
        out["Machine with sensors coloured by residual"] = _png(fig)

    if d.candidates:
        c = d.candidates[:10][::-1]
        fig, ax = plt.subplots(figsize=(8, 0.4 * len(c) + 1))
        ax.barh([x["effect"] for x in c], [100 * x["explained"] for x in c], color="C2")
        ax.set_xlabel("explained weighted residual [%]")
        out["Candidate ranking"] = _png(fig)
    return out


def write_report(d, machine, folder: str | os.PathLike, after: np.ndarray | None = None,
                 sections: list[tuple[str, str]] | None = None) -> Path:
    """Write ``folder/index.html`` atomically (figures embedded); returns its path.

    ``sections``: extra (title, preformatted text) blocks shown after the verdict, e.g. the
    comparison table of :func:`validate.compare.format_compare`."""
    from validate.diagnose import format_diagnosis
    from validate.diagnose_cli import format_before_after

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    parts = ["<html><head><meta charset='utf-8'><title>twin diagnose</title></head><body>",
             "<h1>Diagnosis: missing physical effects</h1>",
             f"<p><b>{html.escape(d.message)}</b></p><pre>{html.escape(format_diagnosis(d))}</pre>"]
    for title, text in sections or []:
        parts.append(f"<h2>{html.escape(title)}</h2><pre>{html.escape(text)}</pre>")
    if after is not None:
        parts.append(f"<h2>RMSE before and after adding the top candidate</h2><pre>"
                     f"{html.escape(format_before_after(d, after))}</pre>")
    for title, png in figures(d, machine, after).items():
        parts.append(f"<h2>{html.escape(title)}</h2><img src='data:image/png;base64,{png}'/>")
    parts.append("</body></html>")
    path = folder / "index.html"
    fd, tmp = tempfile.mkstemp(prefix=".twin-", suffix=".html", dir=folder)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write("\n".join(parts))
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
