"""The second half of ``twin demo``: hold the twin against a "measurement", find what it lacks.

The story, on generated data (nothing is downloaded):

1. **Measure.** The "real machine" is the default twin plus one effect the model does not know
   (:data:`HIDDEN`: losses of an electrical cabinet bolted to the column's left side,
   ``electrical_cabinet.power = 120 W``), made honestly different from the model by
   :func:`validate.synthetic.truth_measurement` (half the time step, cast iron and steel
   properties perturbed by 2-4 %, sensor noise, 0.0625 K quantisation, a 0.03 K sensor bias,
   probe noise). It runs the same spindle test (9000 rpm 120 min, stop 70 min) and is logged
   every :data:`LOG_INTERVAL` s into ``measurement/spindle-test.csv`` with its column mapping
   ``measurement/spindle-test.toml``: the format :func:`twin.io.measurement.read_measurement`
   reads, so the rest of the story runs exactly the path a user's own data takes.
2. **Compare** (:mod:`validate.compare`): the twin (default effects, on the demo's mesh) driven by
   the measured inputs; RMSE / max|r| / NSE per channel and per phase; worst channels first.
3. **Diagnose** (:mod:`validate.diagnose`) on the ``coarse`` mesh with ``twin diagnose``'s defaults
   (the model error estimated on the next finer mesh, every uncertain parameter tried; about 50
   twin runs): every library effect not in the model, ranked, with the fitted strength in W, K/m,
   W/K ..., the BIC weight and whether it passes the significance test, the expansion nuisance, and
   the verdict. The command it prints, ``twin diagnose CSV``, reproduces these numbers.
4. **Apply**: the top candidate at its fitted strength, RMSE before/after per channel, on the
   coarse mesh of the diagnosis and again on the demo's mesh (as ``twin compare --effects
   +NAME --set NAME.p=V`` would).
5. **Report**: ``report/index.html`` (figures embedded) and ``report/diagnosis.json``.

Units: temperatures [degC], temperature residuals [K], probe readings [um], tilts [urad],
time [s]. The library never prints; progress goes to the ``say`` callback.
"""

from __future__ import annotations

import json
import time
from dataclasses import replace
from pathlib import Path
from typing import Callable


from learners.metrics import rms
from twin.fem.mesh import mesh_machine
from twin.units import format_quantity
from validate.channels import GROUPS
from validate.verdict import share_text

MACHINE = "cframe-vmc"
SCENARIO = "spindle-heat-cool-9000"
HIDDEN = "electrical_cabinet"
HIDDEN_PARAMETER, HIDDEN_VALUE = "power", 120.0     # [W]
LOG_INTERVAL = 60.0                                 # [s] logging interval of the "measurement"
DIAGNOSE_MESH = "coarse"


def _short(value: float, dimension: str) -> str:
    """A parameter value with 3 significant digits and its unit ("136 W")."""
    return format_quantity(float(f"{value:.3g}"), dimension)


def _settings(cand: dict) -> list[str]:
    """``effect.param=value unit`` for each fitted parameter of a diagnosis candidate."""
    from twin.effects import EFFECTS

    return [f"{e}.{k}={_short(x, EFFECTS[e].parameter(k).dimension)}"
            for e, ps in cand["values_si"].items() for k, x in ps.items()]


def _candidate_args(cand: dict) -> str:
    return ", ".join(_settings(cand))


def _rmse_table(before, after=None, names: list[str] | None = None) -> list[str]:
    """Lines ``channel unit RMSE-before [RMSE-after change]`` from CompareResults."""
    rows = [c for c in before.channels if names is None or c.name in names]
    w = max([22] + [len(c.name) for c in rows])     # long sensor names keep the columns aligned
    head = f"    {'channel':<{w}} {'unit':>4} {'RMSE':>8}" + (f" {'after':>8} {'change':>7}" if after else "")
    out = [head]
    for c in rows:
        line = f"    {c.name:<{w}} {c.unit:>4} {c.stats.rmse:8.3g}"
        if after:
            a = after.channel(c.name).stats.rmse
            line += f" {a:8.3g} {a / c.stats.rmse - 1 if c.stats.rmse else 0:+7.0%}"
        out.append(line)
    return out


def _group_rmse(result, prefix: str) -> float:
    """Root-mean-square over a channel group's RMSEs (K, um or urad)."""
    v = [c.stats.rmse for c in result.channels if c.name.startswith(prefix + ":")]
    return float(rms(v)) if v else float("nan")


def run_story(out_dir: Path, mesh: str = "default", seed: int = 0, say: Callable[[str], None] = lambda s: None,
              hidden_value: float = HIDDEN_VALUE) -> dict:
    """Run the story (see module docstring) into ``out_dir``; returns a summary dict.

    ``mesh``: the demo's mesh, used for the "real machine" (truth) and for the twin that is
    compared with it; the diagnosis always runs on ``coarse``. ``seed``: the twin's noise seed
    (the measurement uses ``seed + 1``). ``hidden_value``: the cabinet's true power [W].
    Keys of the result: ``measurement``, ``mapping``, ``report``, ``json`` (paths), ``hidden``,
    ``true_value`` [W], ``top``, ``significant``, ``fitted`` ({effect: {param: "value unit"}}),
    ``explained``, ``confidence``, ``rmse_before`` / ``rmse_after`` ({channel: RMSE in K, um or
    urad}, on ``mesh``), ``seconds`` (wall time per stage).
    """
    from geometries import build_machine
    from twin.model import model_spec
    from twin.physics.prepared import PreparedTwin
    from twin.effects import EFFECTS
    from twin.scenario import load_scenario
    from validate.compare import compare, model_for
    from validate.diagnose import diagnose, diagnosis_json
    from twin.io.atomic import atomic_write_text
    from validate.apply import apply_top, format_before_after
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement
    from twin.io.measurement_writer import write_measurement
    from validate.report import write_report
    from validate.synthetic import truth_measurement

    out_dir = Path(out_dir)
    clock, seconds = time.perf_counter(), {}

    def lap(stage: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        seconds[stage] = round(now - clock, 1)
        clock = now

    par = EFFECTS[HIDDEN].parameter(HIDDEN_PARAMETER)
    true_text = _short(hidden_value, par.dimension)
    say("")
    say(f"story: the 'real' machine ran the same spindle test; it has an electrical cabinet on the column's "
        f"left side that the model does not know ({HIDDEN}.{HIDDEN_PARAMETER} = {true_text}, hidden).")
    say(f"  measuring: truth on the {mesh} mesh, half time step, materials perturbed 2-4 %, sensor noise, "
        f"quantisation and bias; logged every {LOG_INTERVAL:g} s")
    sc = replace(load_scenario(SCENARIO), sample_interval=LOG_INTERVAL)
    truth = truth_measurement(MACHINE, sc, f"+{HIDDEN}", [f"{HIDDEN}.{HIDDEN_PARAMETER}={true_text.replace(' ', '')}"],
                              resolution=mesh, seed=seed + 1)
    csv_path, toml_path = write_measurement(truth, out_dir / "measurement", "spindle-test", MACHINE)
    say(f"  wrote {csv_path} and its column mapping {toml_path.name} "
        f"({len(truth.time)} rows: time, spindle speed, room air, {truth.sizes['sensor']} temperatures, 5 probes)")
    lap("measure")

    meas = read_measurement(csv_path)
    model_twin = PreparedTwin(build_machine(MACHINE), resolution=mesh)   # the model before and after the fix
    cmp0 = compare(meas, model_for(meas, MACHINE, resolution=mesh, seed=seed, prepared=model_twin)[0])
    say(f"compare (twin compare {csv_path} --mesh {mesh}): the default twin driven by the measured inputs")
    say("  phases: " + "; ".join(f"{p.label} {p.start / 3600:.1f}-{p.end / 3600:.1f} h" for p in cmp0.phases))
    say("  worst channels (RMSE / std of the measurement; NSE 1 = perfect, < 0 = worse than a constant):")
    worst = cmp0.ranking()[:5]
    w = max([22] + [len(c.name) for c in worst])
    for c in worst:
        say(f"    {c.name:<{w}} RMSE {c.stats.rmse:6.3g} {c.unit:<4} max|r| {c.stats.max_abs:6.3g} {c.unit:<4} "
            f"NSE {c.stats.nse:6.2f}  ratio {c.normalised_rmse:5.2f}")
    c, p, s, v = cmp0.phase_ranking()[0]
    say(f"  worst phase: {c.name} during '{p.label}' (RMSE {s.rmse:.3g} {c.unit})")
    lap("compare")

    machine = build_machine(MACHINE)
    mm = mesh_machine(machine, DIAGNOSE_MESH)
    sc_meas = scenario_from_measurement(meas)
    error_mesh = diagnose_error_mesh(machine)
    d = diagnose(meas, machine, sc_meas, model_spec(machine), mm=mm, error_resolution=error_mesh)
    say(f"diagnose (twin diagnose {csv_path}; its defaults --mesh {DIAGNOSE_MESH} --error-mesh auto = {error_mesh}, "
        f"which reproduce these numbers): every library effect not in the model and every uncertain parameter of "
        f"its own, fitted on the {DIAGNOSE_MESH} mesh, the model error estimated on the {error_mesh} mesh "
        f"({d.runs} twin runs)")
    say(f"  explained: share of the weighted residual {share_text(d.residual_factor)}; BIC weight: relative among "
        f"the candidates, not the probability of being the cause; significant: >= {d.test[0]:g} BIC units and "
        f">= {d.test[1]:.0%} explained")
    for i, cand in enumerate(d.candidates[:3], 1):
        vals = _candidate_args(cand)
        flags = "significant" if cand["significant"] else "not significant"
        if cand["at_bound"]:
            flags += ", AT ITS BOUND: " + ", ".join(cand["at_bound"])
        say(f"  {i}. {cand['effect']:<24} explains {cand['explained']:5.1%}  BIC weight {cand['confidence']:.2f}  "
            f"{vals}  ({flags})")
    for line in _nuisance_lines(d):
        say(line)
    say(f"  verdict: {d.message}")
    lap("diagnose")

    after_coarse = calibrated = cmp1 = None
    top = d.candidates[0] if d.candidates else None
    if d.named and top:
        after_coarse, calibrated, _ = apply_top(d)
        effects = ",".join(f"+{e}" for e in top["values_si"])
        settings = [x.replace(" ", "") for x in _settings(top)]
        cmp1 = compare(meas, model_for(meas, MACHINE, effects=effects, settings=settings, resolution=mesh, seed=seed,
                                       prepared=model_twin)[0])
        say(f"apply: twin compare {csv_path} --mesh {mesh} --effects {effects} "
            + " ".join(f"--set {x}" for x in settings))
        worst = [c.name for c in cmp0.ranking()[:6]]
        say("\n".join(_rmse_table(cmp0, cmp1, worst)))
        say("  all channels: " + ", ".join(
            f"{g} RMSE {_group_rmse(cmp0, g):.3g} -> {_group_rmse(cmp1, g):.3g} {u}" for g, (_, u) in GROUPS.items()
            if any(c.name.startswith(g + ":") for c in cmp0.channels)))
        if top["effect"] == HIDDEN:
            fit = top["values_si"][HIDDEN][HIDDEN_PARAMETER]
            say(f"  the hidden truth was {HIDDEN}.{HIDDEN_PARAMETER} = {true_text}; fitted {_short(fit, par.dimension)} "
                f"({fit / hidden_value - 1:+.0%}; the model differs from the 'real' machine in materials, time step "
                f"and mesh, which the fitted value may absorb in part)")
    else:
        say(f"apply: nothing to add (the verdict is {d.verdict})")
    lap("apply")

    rep = out_dir / "report"
    rep.mkdir(parents=True, exist_ok=True)
    about = (f"This page was written by `twin demo` on generated data. The 'measurement' {csv_path.name} is the\n"
             f"default twin plus {HIDDEN} ({HIDDEN}.{HIDDEN_PARAMETER} = {true_text}), which the model does not\n"
             f"have, simulated on the {mesh} mesh with half the time step, perturbed materials, sensor noise,\n"
             f"quantisation and bias. The diagnosis should find {HIDDEN} and a strength near {true_text}.")
    sections = [("About this measurement", about),
                (f"Compare: the default twin ({mesh} mesh) vs the measurement {csv_path.name}", _compare_text(cmp0))]
    closing = []
    if cmp1 is not None:
        closing.append((f"After adding {_candidate_args(top)}: RMSE per channel, twin on the {mesh} mesh",
                        "\n".join(_rmse_table(cmp0, cmp1))))
    report = write_report(d, machine, rep, after_coarse, sections=sections, closing=closing, calibrated=calibrated)
    doc = diagnosis_json(d)
    json_path = atomic_write_text(rep / "diagnosis.json", json.dumps(doc, indent=2))
    lap("report")
    say(f"wrote {report} and {json_path.name}")
    return {
        "measurement": csv_path, "mapping": toml_path, "report": report, "json": json_path,
        "hidden": HIDDEN, "true_value": hidden_value, "top": top["effect"] if top else None,
        "significant": d.significant, "named": d.named, "verdict": d.verdict, "runs": d.runs,
        "command": f"twin diagnose {csv_path}", "fitted": top["parameters"] if top else {},
        "explained": top["explained"] if top else 0.0, "confidence": top["confidence"] if top else 0.0,
        "rmse_before": {c.name: c.stats.rmse for c in cmp0.channels},
        "rmse_after": {c.name: c.stats.rmse for c in cmp1.channels} if cmp1 else {},
        "before_after_coarse": format_before_after(d, after_coarse, calibrated) if after_coarse is not None else "",
        "seconds": seconds,
    }


def diagnose_error_mesh(machine) -> str | None:
    """The mesh ``twin diagnose --error-mesh auto`` (its default) estimates the model error on for a
    model on :data:`DIAGNOSE_MESH`: the next finer, else the next coarser."""
    from validate.diagnose import coarser_resolution, finer_resolution

    return finer_resolution(machine, DIAGNOSE_MESH) or coarser_resolution(machine, DIAGNOSE_MESH)


def _nuisance_lines(d) -> list[str]:
    """The thermal-expansion nuisance the diagnosis fitted (each material within its band), for the
    baseline and with the named candidate; a material at its bound flagged, with what it means."""
    from validate.diagnosis_text import nuisance_text

    if not d.nuisance_baseline:
        return []
    out = ["  expansion nuisance (alpha within each material's band), baseline: " + nuisance_text(d.nuisance_baseline)]
    if d.named:
        out.append("    with the top candidate: " + nuisance_text(d.nuisance))
    if any(v["at_bound"] for v in d.nuisance_baseline.values()):
        out.append("    at its bound: the baseline's drift needs more than the materials' plausible spread"
                   + (", which the top candidate removes" if d.named and not any(v["at_bound"] for v in d.nuisance.values())
                      else ", so something else is wrong"))
    return out


def _compare_text(result) -> str:
    from validate.compare import format_compare

    return format_compare(result)
