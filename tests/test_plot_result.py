"""``twin plot``'s title names the shading only where something is shaded."""

from __future__ import annotations

import numpy as np
import pytest

from tests.fuzz_files import result_dataset


@pytest.mark.parametrize("speed, note", [(6000.0, " (shaded: spindle running)"), (0.0, "")])
def test_the_title_mentions_the_shading_only_when_the_spindle_ran(monkeypatch, tmp_path, speed, note):
    """A room-only run (an ETVE test) has nothing shaded, so its title says nothing about shading."""
    import twin.plotting as plotting

    titles = []
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path, dpi: titles.append(fig.axes[0].get_title()))
    ds = result_dataset()
    ds["spindle_speed"].values[:] = np.where(ds.time.values < 600, speed, 0.0)
    ds.attrs.update(machine="cframe-vmc", scenario="s")
    plotting.plot_result(ds, tmp_path / "p.png")
    assert titles == [f"cframe-vmc / s{note}"]
