"""The map of a diagnosis's localisation: the machine seen from the front (x-z) and the side (y-z),
its best regions coloured by the fitted generic heat input [W], its temperature sensors by the
residual RMSE the verdict's model leaves [K]."""

from __future__ import annotations

import numpy as np

from geometries.regions import AXES


def machine_outline(ax, machine, a: int, b: int) -> None:
    """Grey outlines of every box of the machine, projected on axes (a, b)."""
    import matplotlib.pyplot as plt

    for part in machine.parts:
        for box in part.boxes:
            ax.add_patch(plt.Rectangle((box.lo[a], box.lo[b]), box.hi[a] - box.lo[a], box.hi[b] - box.lo[b],
                                       fill=False, lw=0.5, color="grey"))


def _draw_region(ax, machine, name: str, colour, a: int, b: int) -> None:
    """A part filled (volume), or one of its faces: a thick edge when it is seen edge-on in this
    view, hatched when it faces the viewer or away."""
    import matplotlib.pyplot as plt

    part, _, direction = name.partition(".")
    for box in machine.part(part).boxes:
        lo, hi = np.asarray(box.lo), np.asarray(box.hi)
        rect = (lo[a], lo[b]), hi[a] - lo[a], hi[b] - lo[b]
        if not direction:
            ax.add_patch(plt.Rectangle(*rect, color=colour, alpha=0.85, lw=0))
            continue
        axis = AXES[direction[1]]
        at = hi[axis] if direction[0] == "+" else lo[axis]
        if axis == a:
            ax.plot([at, at], [lo[b], hi[b]], color=colour, lw=4, solid_capstyle="butt")
        elif axis == b:
            ax.plot([lo[a], hi[a]], [at, at], color=colour, lw=4, solid_capstyle="butt")
        else:
            ax.add_patch(plt.Rectangle(*rect, fill=False, hatch="///", edgecolor=colour, lw=1.5))


def _label_at(machine, name: str, a: int, b: int) -> tuple[float, float]:
    """Where to write a region's rank: its part's centre, moved onto the face for a face region."""
    part, _, direction = name.partition(".")
    box = machine.part(part).boxes[0]
    at = 0.5 * (np.asarray(box.lo) + np.asarray(box.hi))
    if direction:
        axis = AXES[direction[1]]
        at[axis] = box.hi[axis] if direction[0] == "+" else box.lo[axis]
    return float(at[a]), float(at[b])


def region_map(d, machine, top: int = 5):
    """A matplotlib figure (see the module docstring)."""
    import matplotlib.pyplot as plt
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize, TwoSlopeNorm

    from learners.metrics import rms

    regions = d.regions[:top]
    powers = [r["power_W"] for r in regions]
    span = max(max(abs(p) for p in powers), 1e-9)
    pnorm = TwoSlopeNorm(0.0, -span, span) if min(powers) < 0 else Normalize(0.0, span)
    pcmap = plt.get_cmap("RdBu_r" if min(powers) < 0 else "Reds")
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2), layout="constrained")
    rec = d.record
    kept = d.verdict in ("explained", "partly_explained") and d.fits
    left = d.evidence.split(d.residual_after(d.fits[0].response if kept else np.zeros_like(d.fitter.r)))[0]
    temps = [i for i, g in enumerate(rec.groups) if g == "temperature"]
    xyz = np.array([p.xyz for p in rec.sensor_points]) if temps else np.zeros((0, 3))
    values = rms(left[:, temps], axis=0) if temps else np.zeros(0)
    snorm = Normalize(0, max(float(values.max()) if len(values) else 0.0, 1e-9))
    for ax, (a, b, view) in zip(axes, ((0, 2, "front view (x-z)"), (1, 2, "side view (y-z, machine front on the left)"))):
        machine_outline(ax, machine, a, b)
        for i, r in list(enumerate(regions, 1))[::-1]:
            _draw_region(ax, machine, r["region"], pcmap(pnorm(r["power_W"])), a, b)
            ax.annotate(str(i), _label_at(machine, r["region"], a, b), fontsize=9, weight="bold", color="k",
                        ha="center", va="center", zorder=5)
        if len(values):
            sc = ax.scatter(xyz[:, a], xyz[:, b], c=values, cmap="Greys", norm=snorm, s=45, edgecolor="k", zorder=4)
        ax.set_xlabel(f"{'xy'[a]} [m]")
        ax.set_ylabel("z [m]")
        ax.set_title(view, fontsize=9)
        ax.set_aspect("equal")
        ax.autoscale()
    fig.colorbar(ScalarMappable(pnorm, pcmap), ax=axes, label="fitted heat input [W]", shrink=0.6)
    if len(values):
        fig.colorbar(sc, ax=axes, label="sensor residual RMSE [K]", shrink=0.6)
    key = "; ".join(f"{i}. {r['region']} {r['power_W']:.3g} W {r['schedule'].replace('_', ' ')} "
                    f"({r['explained']:.0%})" for i, r in enumerate(regions, 1))
    fig.suptitle("best regions: " + key, fontsize=8)
    return fig
