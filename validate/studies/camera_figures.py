"""Figures of the camera-mode learner studies: thermograms with seed 001's spots on them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from twin.plotting import save_figure


def plot_frames(path: Path, data, picked: list[str] | None = None, hours=(0.0, 1.0, 2.0, None)) -> Path:
    """Thermograms of the training run at ``hours`` (None: the last frame) on one colour scale,
    the spots as small squares and the ``picked`` spots (names) outlined and labelled; a fifth
    panel shows the camera's error (thermogram - true surface temperature) at the hottest frame."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    spots = data.info["spots"]
    picked = set(picked or ())
    with xr.open_dataset(data.paths[0]) as ds:
        t = ds["frame_time"].values
        idx = [int(np.argmin(np.abs(t - h * 3600))) if h is not None else len(t) - 1 for h in hours]
        frames = ds["thermogram"].values[idx]
        hot = int(np.argmax(ds["thermogram"].values.reshape(len(t), -1).mean(axis=1)))
        error = ds["thermogram"].values[hot] - ds["surface_temperature_true"].values[hot]
        info = f"{ds.attrs['machine']} / {ds.attrs['scenario']}, camera {data.info['pose']}"
    lo, hi = np.percentile(frames, [1, 99.7])
    fig, axes = plt.subplots(1, len(idx) + 1, figsize=(3.6 * (len(idx) + 1), 3.4), layout="constrained")
    for ax, i, frame in zip(axes, idx, frames):
        im = ax.imshow(frame, cmap="inferno", vmin=lo, vmax=hi)
        for s in spots:
            chosen = s.name in picked
            ax.add_patch(Rectangle((s.u0 - 0.5, s.v0 - 0.5), s.size, s.size, fill=False, lw=1.6 if chosen else 0.3,
                                   ec="cyan" if chosen else "white", alpha=1.0 if chosen else 0.35))
            if chosen:
                ax.text(s.u0 + s.size + 2, s.v0, s.name, color="cyan", fontsize=7)
        ax.set_title(f"t = {t[i] / 60:.0f} min", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(im, ax=axes[:-1], shrink=0.8, label="apparent temperature [degC]")
    lim = float(np.nanpercentile(np.abs(error), 99))
    em = axes[-1].imshow(error, cmap="RdBu_r", vmin=-lim, vmax=lim)
    axes[-1].set_title(f"camera - truth at t = {t[hot] / 60:.0f} min", fontsize=9)
    axes[-1].set_xticks([])
    axes[-1].set_yticks([])
    fig.colorbar(em, ax=axes[-1], shrink=0.8, label="K")
    fig.suptitle(f"{info}: {len(spots)} spots, picked ones outlined", fontsize=10)
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return path


if __name__ == "__main__":
    from validate.studies.not_a_study import not_a_command

    not_a_command("validate.studies.camera_figures")
