"""The thesis's ambient modelling protocol on the twin (seed 000 Ch. 6), the seed's findings beside ours.

    python -m validate.studies.etve_protocol [--quick] [-o DIR] [--seed N]

Runs ``etve-training``, ``etve-winter`` and ``etve-summer`` on ``cframe-vmc`` (default mesh; ``--quick``:
coarse) and scores, on the probes' Z and Y drift [um] (ISO 230-3 five-probe evaluation):

A. GNNMCI(1,N) trained on the first readings (< 1 min) of the 80-min training test, applied to the
   160-h winter test (seed L6344-6363: correlation 97 % Z, 98 % Y; residual within +-10 um Z and
   +-6 um Y, door events included); and, for reference, MLR on the whole training test. The seed used
   5 readings with 4 inputs; GNNMCI(1,N) has N + 1 weights (``learners.gnnmci``: it needs p + 3 rows
   for p inputs), so here 6 readings (50 s) with 3 inputs, the fewest it accepts.
B. A model trained on the winter test applied to the summer test (seed L6478-6503: it needed
   re-optimisation, no numbers), and recalibrated on the summer test's first day, scored on the
   other two.

Inputs as the seed's selected four (L6283-6287): T1 carrier (``carrier_front``), T2 column
(``column_side``), T5 and T9, the air near the spindle and the column (the room air the model assumes,
``ambient_temperature``: one input, the twin's air is one temperature per height band), each as its rise
from the test's first reading. Writes ``DIR/etve-protocol.md`` and prints the table.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from learners import make_learner
from learners.metrics import score_all
from twin.io.atomic import atomic_write_text
from validate.studies.common import study_main

SENSORS = ("carrier_front", "column_side")
FIRST = 6   # readings of the training test GNNMCI learns from (the seed: 5; see the module docstring)
SEED_A = {"Z": "r 0.97, max residual < 10 um", "Y": "r 0.98, max residual < 6 um"}
SEED_B = "needed re-optimisation on summer data (Figs. 6-8, 6-9: no numbers)"


def inputs(ds) -> np.ndarray:
    """(n, 3) rises [K] from the first reading: carrier, column, room air."""
    cols = [ds.temperature.sel(sensor=s).values for s in SENSORS] + [ds.ambient_temperature.values]
    X = np.column_stack(cols).astype(float)
    return X - X[0]


def target(ds, axis: str) -> np.ndarray:
    """The five-probe drift on ``axis`` [um] from its first reading."""
    y = np.asarray(ds.probe_drift.sel(axis=axis).values, float)
    return y - y[0]


def protocol_a(train, test, axis: str, seed: int) -> dict[str, dict]:
    """GNNMCI on the first :data:`FIRST` training readings, and MLR on the whole training test, scored on ``test``."""
    X, y = inputs(train), target(train, axis)
    g = make_learner("gnnmci", y0=0.0, random_state=seed).fit(X[:FIRST], y[:FIRST])
    m = make_learner("mlr").fit(X, y)
    Xt, yt = inputs(test), target(test, axis)
    return {f"gnnmci, first {FIRST} readings": score_all(yt, g.predict(Xt)), "mlr, whole 80 min": score_all(yt, m.predict(Xt))}


def protocol_b(winter, summer, axis: str) -> dict[str, dict]:
    """MLR trained on winter, scored on summer days 2-3; and recalibrated on summer day 1."""
    day = summer.time.values < 86400.0
    Xs, ys = inputs(summer), target(summer, axis)
    w = make_learner("mlr").fit(inputs(winter), target(winter, axis))
    r = make_learner("mlr").fit(Xs[day], ys[day])
    return {"mlr winter -> summer days 2-3": score_all(ys[~day], w.predict(Xs[~day])),
            "mlr recalibrated on summer day 1 -> days 2-3": score_all(ys[~day], r.predict(Xs[~day]))}


def table(results: dict[str, dict[str, dict]]) -> str:
    """Markdown table: protocol, model, axis, r, RMSE, max |residual|, the seed's finding."""
    rows = ["| protocol | model | axis | r | RMSE um | max abs residual um | seed |", "|---|---|---|---|---|---|---|"]
    for (proto, axis), models in results.items():
        for name, s in models.items():
            seed = SEED_A[axis] if proto == "A" and name.startswith("gnnmci") else SEED_B if "winter ->" in name else ""
            rows.append(f"| {proto} | {name} | {axis} | {s['r']:.3f} | {s['rmse']:.2f} | {s['max_abs_residual']:.2f} | "
                        f"{seed} |")
    return "\n".join(rows)


def run(resolution: str = "default", seed: int = 0, progress=print) -> dict:
    """Simulate the three tests and score both protocols on Z and Y."""
    from geometries import build_machine
    from twin.api import simulate
    from twin.physics.prepared import PreparedTwin

    twin = PreparedTwin(build_machine("cframe-vmc"), resolution=resolution)   # one mesh and elasticity for the three
    runs = {}
    for name in ("training", "winter", "summer"):
        progress(f"simulating etve-{name} ({resolution}) ...")
        runs[name] = simulate("cframe-vmc", f"etve-{name}", seed=seed, prepared=twin)[0]
    out = {}
    for axis in ("Z", "Y"):
        out[("A", axis)] = protocol_a(runs["training"], runs["winter"], axis, seed)
        out[("B", axis)] = protocol_b(runs["winter"], runs["summer"], axis)
    return out


def main(argv=None) -> int:
    return study_main("etve_protocol", __doc__, argv, _run, ("etve-protocol.md",), folder="etve-protocol")


def _run(args, out: Path) -> int:
    text = table(run("coarse" if args.quick else "default", args.seed))
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / "etve-protocol.md", "# The thesis's ETVE protocol on the twin\n\n" + text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
