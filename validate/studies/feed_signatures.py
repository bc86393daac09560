"""How alike the feed drive's signatures are on ``seed003-exp1``: each feed-drive effect's response
(the default model minus the model without it, default strengths) per channel group, its RMS and
the correlation between effects, sum(a b) / sqrt(sum(a^2) sum(b^2)) over time and channels.

``python -m validate.studies.feed_signatures [--mesh coarse] [--full]`` (default: the diagnosis
study's quick scenario, halved to 195 min with interferometer runs at 0, 20, 60, 120 and 195 min;
``--full``: the whole 390 min). The interferometer's group is read at its runs, the temperature
sensors and probes at every sample. A correlation near 1 means the group cannot tell the two
effects apart (the diagnosis reports them as indistinguishable above 0.95).
"""

from __future__ import annotations

import numpy as np

from validate.studies.common import cli_parser, run_cli

FEED = ("feed_nut_y", "feed_motor_y", "feed_guideways_y", "feed_bearings_y")
GROUPS = ("temperature", "probe", "positioning")


def responses(resolution: str, quick: bool) -> tuple[dict, np.ndarray, np.ndarray]:
    """({effect: (n_t, n_columns) response}, the columns' groups, the interferometer runs' steps)."""
    from geometries import build_machine
    from twin.model import model_spec
    from twin.motion import machine_for
    from validate.signatures import Engine
    from validate.studies.diagnosis_cases import AXIS, load_case_scenario

    sc = load_case_scenario(AXIS, quick)
    machine = machine_for(build_machine("cframe-vmc"), sc)
    engine = Engine(machine, sc, resolution)
    base = engine.observe(model_spec(machine))
    out = {e: base - engine.observe(model_spec(machine, f"-{e}")) for e in FEED}
    steps = np.round(np.asarray(sc.interferometer.runs) / sc.sample_interval).astype(int)
    return out, np.array(engine.groups), steps


def correlation(a: np.ndarray, b: np.ndarray) -> float:
    """sum(a b) / sqrt(sum(a^2) sum(b^2)) (0 when either is zero)."""
    den = float(np.sqrt(np.sum(a * a) * np.sum(b * b)))
    return float(np.sum(a * b) / den) if den > 0 else 0.0


def main(argv=None) -> int:
    p = cli_parser("python -m validate.studies.feed_signatures", __doc__)
    p.add_argument("--mesh", default="coarse", choices=["coarse", "default", "fine"],
                   help="mesh resolution (default: %(default)s)")
    p.add_argument("--full", action="store_true", help="the whole 390 min scenario (default: the study's quick one)")
    return run_cli(p.parse_args, argv, _run)


def _run(a) -> int:
    sig, groups, steps = responses(a.mesh, not a.full)
    for g in GROUPS:
        rows = steps if g == "positioning" else slice(None)
        block = {e: s[rows][:, groups == g] for e, s in sig.items()}
        unit = "K" if g == "temperature" else "um"
        print(f"{g}: RMS response " + ", ".join(f"{e} {np.sqrt(np.mean(v ** 2)):.3g} {unit}" for e, v in block.items()))
        for e in FEED:
            print(f"  {e:<18}" + " ".join(f"{correlation(block[e], block[o]):+.3f}" for o in FEED))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
