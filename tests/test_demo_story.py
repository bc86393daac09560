"""The demo's story on the coarse mesh: measurement CSV + mapping written and readable, compare,
diagnosis finding the hidden electrical cabinet, error falling after adding it, HTML report."""

from __future__ import annotations

import json

from validate.demo_story import HIDDEN, run_story
from twin.io.measurement import read_measurement


def test_story_finds_the_hidden_cabinet(tmp_path):
    lines: list[str] = []
    r = run_story(tmp_path, "coarse", 0, lines.append)   # about 30-40 s on 2 cores
    for key in ("measurement", "mapping", "report", "json"):
        assert r[key].is_file() and r[key].stat().st_size > 0, key
    assert r["measurement"] == tmp_path / "measurement" / "spindle-test.csv"
    assert r["report"] == tmp_path / "report" / "index.html"
    ds = read_measurement(r["measurement"])   # the mapping is found next to the CSV
    assert ds.sizes["sensor"] == 16 and ds.sizes["probe_id"] == 5
    assert r["top"] == HIDDEN and r["significant"]
    doc = json.loads(r["json"].read_text())
    assert doc["candidates"][0]["effect"] == HIDDEN
    assert doc["candidates"][0]["parameters"][HIDDEN]["power"].endswith(" W")
    fitted = float(doc["candidates"][0]["parameters"][HIDDEN]["power"].split()[0])
    assert abs(fitted / r["true_value"] - 1) < 0.25, fitted
    before = sum(v ** 2 for k, v in r["rmse_before"].items() if k.startswith("probe:"))
    after = sum(v ** 2 for k, v in r["rmse_after"].items() if k.startswith("probe:"))
    assert after < 0.3 * before, (before, after)
    html = r["report"].read_text()
    assert "data:image/png;base64," in html and HIDDEN in html
    text = "\n".join(lines)
    assert "compare" in text and "diagnose" in text and "apply" in text
