"""Benchmark one run or a batch of cases and print one JSON object.

    python -m validate.benchmark --machine cframe-vmc --scenario etve-day-night --spacing 20mm \
        --solver full|rom|direct|iterative [--device gpu [--gpu-kernels fused|arrays]] [--cases N] [--heat-tol "1e-4 K"] [--json]

(``--mesh coarse|default|fine`` instead of ``--spacing``). Every option is checked first, as the
twin CLI checks them: the scenario's speeds against the machine, the mesh's size and the run's
(:mod:`twin.limits`); bad input is one line ``error: <source>: <field>: <message>``, exit code 2.

``nodes``, ``preparation_s`` (mesh, heat and elastic assembly, elastic adjoints, the observers'
rows on the run's layout; for the reduced model also its offline phase, and the same basis when
the full model's iterative heat steps start from it, ``--heat-start``) and ``prepare_s`` (those
stages one by one; ``prepare_concurrent`` says whether the elastic stages ran beside the basis,
:meth:`twin.physics.prepared.PreparedTwin.prepare`), ``step_ms`` (time stepping / steps), ``total_s`` (end to end),
``cpu_s`` (CPU time of the process over the same span: on a shared machine it varies less than
the wall time), ``peak_mib`` (max RSS of the process), the solver information of the run and, for the reduced
model, ``rom_order``, ``offline_s`` and ``max_rel_error``: the largest error of each drift output
(tool-point drift X, Y, Z and the five probes) against a full-order run of the same prepared
twin, relative to that output's peak |value| (the reference run is not counted in the times;
``--no-reference`` skips it). With ``--cases N`` it runs N cases at once (:mod:`twin.physics.
batch`): every linear effect strength and the room air's amplitude scaled by factors drawn
uniformly in [0.5, 1.5] (seeded), and ``max_rel_error`` compares a few of them with full runs.
Not a test: the numbers depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import json
import resource
import time
from dataclasses import replace

import numpy as np

SOLVER_NAMES = {"full": "auto", "rom": "rom", "direct": "direct", "iterative": "iterative"}


def _parser() -> argparse.ArgumentParser:
    from twin.cli.options import add_seed_option, whole_number
    from twin.cli.options import positive_quantity
    from validate.studies.common import cli_parser

    ap = cli_parser("python -m validate.benchmark", __doc__)
    ap.add_argument("--machine", default="cframe-vmc")
    ap.add_argument("--scenario", default="etve-day-night")
    ap.add_argument("--spacing", type=positive_quantity("length"), default=None,
                    help="cell size with its unit, e.g. 20mm (default: the --mesh resolution's)")
    ap.add_argument("--mesh", default=None, choices=["coarse", "default", "fine"],
                    help="a named resolution, not with --spacing (default: default)")
    ap.add_argument("--solver", default="full", choices=sorted(SOLVER_NAMES))
    ap.add_argument("--device", default="cpu", choices=["cpu", "gpu"])
    ap.add_argument("--gpu-kernels", default=None, choices=["fused", "arrays"],
                    help="--device gpu: the heat step's CG and products on the kernels of twin.physics.gpu_cg "
                         "(default) or on CuPy's array operations and cuSPARSE (the path they replace, to compare)")
    ap.add_argument("--cases", type=whole_number("cases", 1), default=1,
                    help="number of batched cases (default 1: one plain run)")
    ap.add_argument("--rom-order", type=whole_number("basis vectors", 2), default=None,
                    help="the reduced model's order, also of the basis iterative steps start from (default 48)")
    # upper: twin.physics.options.MAX_ELASTIC_COARSENING, as twin.cli.options (the parser stays light)
    ap.add_argument("--elastic-coarsening", type=whole_number("grid lines", 1, 8), default=1,
                    help="solve the elasticity on every N-th grid line of the temperature mesh, 1 to 8 (default 1: "
                         "the same)")
    ap.add_argument("--heat-tol", type=positive_quantity("temperature_difference"), default=None,
                    help="iterative heat solver: bound on the run's capacity-weighted RMS temperature error, "
                         "with its unit (default 1e-6 K)")
    ap.add_argument("--heat-start", default="auto", choices=["auto", "projection", "reduced"],
                    help="iterative heat steps: start each from the projection on the last solutions, or from the "
                         "extrapolation corrected on the reduced basis (built once, counted in the preparation); "
                         "auto: the reduced basis from 300 steps (default)")
    ap.add_argument("--no-reference", action="store_true", help="skip the full-order reference of the ROM")
    ap.add_argument("--heat-only", action="store_true",
                    help="observe temperatures and the heat balance only (no elastic adjoints): times the heat step")
    ap.add_argument("--no-bound", action="store_true", help="batched ROM: skip the verified error bound")
    ap.add_argument("--prepare-only", action="store_true",
                    help="stop after the preparation (mesh, assembly, elastic adjoints, rows, the basis): its stages and memory")
    add_seed_option(ap, "seed of the cases' factors (--cases)")
    ap.add_argument("--json", action="store_true", help="print only the JSON object")
    return ap


def vary_cases(scenario, spec, n: int, seed: int) -> list:
    """``n`` (scenario, spec) cases: every linear strength and the ambient amplitude scaled by
    factors uniform in [0.5, 1.5] (case 0 is the unscaled model). Every case starts from case 0's
    machine temperature (batched cases share it): a room whose cycle is away from its mean at
    t = 0 (``etve-training`` starts at 08:00) would otherwise start each case elsewhere."""
    from twin.effects import EFFECTS
    from twin.model import ModelSpec

    rng = np.random.default_rng(seed)
    linear = [e for e in spec.effects if EFFECTS[e].linear and EFFECTS[e].strength]
    cases = []
    for i in range(n):
        f = np.ones(len(linear) + 1) if i == 0 else rng.uniform(0.5, 1.5, len(linear) + 1)
        params = {g: dict(v) for g, v in spec.params.items()}
        for k, e in enumerate(linear):
            params[e][EFFECTS[e].strength] *= f[k]
        amb = replace(scenario.ambient, amplitude=scenario.ambient.amplitude * f[-1])
        cases.append((replace(scenario, ambient=amb, initial_temperature=scenario.start_temperature),
                       ModelSpec(spec.effects, params)))
    return cases


def main(argv=None) -> int:
    """The benchmark; bad input is one line ``error: <source>: <field>: <message>`` and exit code 2,
    found before any preparation (the mesh, whose size is checked, included)."""
    from validate.studies.common import run_cli

    return run_cli(_parser().parse_args, argv, _run)


def _run(args) -> int:
    from twin import limits
    from twin.api import machine_by_name
    from twin.errors import InputError
    from twin.fem.mesh import build_mesh, check_spacing, mesh_machine
    from twin.model import model_spec
    from twin.observe import FiveProbeTestBar, HeatBalance, TemperatureSensors, ToolDrift, sensor_points
    from twin.physics import gpu_cg
    from twin.physics.solvers import array_module
    from twin.physics.prepared import PreparedTwin
    from twin.physics.options import SolverOptions
    from twin.scenario import load_scenario

    if args.spacing is not None and args.mesh is not None:
        raise InputError("command line", "--spacing", "give --spacing or --mesh, not both")
    _check_combination(args)
    machine = machine_by_name(args.machine, "--machine")
    if args.spacing is not None:
        check_spacing(machine, args.spacing, "command line", "--spacing")
    scenario = load_scenario(args.scenario)
    limits.check_scenario(scenario, machine)
    limits.check_batch_size(args.cases, len(scenario.times()), "command line", "--cases")   # before the mesh
    tol = {"heat_tol": args.heat_tol} if args.heat_tol is not None else {}
    options = SolverOptions(SOLVER_NAMES[args.solver], args.device, rom_order=args.rom_order,
                            elastic_coarsening=args.elastic_coarsening, heat_start=args.heat_start, **tol)
    gpu_cg.FUSED = args.gpu_kernels != "arrays"
    if args.device == "gpu":         # refused before the mesh, --prepare-only too (its preparation is the CPU's)
        array_module("gpu")
    t0, c0 = time.perf_counter(), time.process_time()
    mm = build_mesh(machine, args.spacing) if args.spacing is not None else mesh_machine(machine, args.mesh or "default")
    limits.check_run_size(scenario, mm.nheat)
    stages = {"mesh": time.perf_counter() - t0}
    twin = PreparedTwin(machine, mm, solver=options)
    if args.rom_order is not None and args.solver != "rom" and twin.method == "direct":
        raise InputError("command line", "--rom-order", f"sets the reduced basis of the reduced model or of iterative "
                                                        f"steps; this run factorises its {mm.nheat} temperature nodes: "
                                                        "use --solver rom or iterative")
    if args.heat_tol is not None and twin.method == "direct":
        raise InputError("command line", "--heat-tol", f"bounds the error of iterative heat steps; this run factorises "
                                                       f"its {mm.nheat} temperature nodes: use --solver iterative")
    stages["heat_assembly"] = time.perf_counter() - t0 - sum(stages.values())
    observers = [TemperatureSensors(sensor_points(machine))] + ([] if args.heat_only else [ToolDrift()])
    if machine.probes and not args.heat_only:
        observers.append(FiveProbeTestBar())
    observers.append(HeatBalance())
    spec = model_spec(machine)
    if args.prepare_only:
        twin.prepare(scenario, spec, observers)
        result = {"machine": args.machine, "spacing_m": mm.spacing, "nodes": int(mm.nnodes), "nheat": int(mm.nheat),
                  **_stages(stages, twin), "preparation_s": round(time.perf_counter() - t0, 3),
                  **_process_use(c0), **twin.elastic_info()}
        return _print(result, args)
    cases = vary_cases(scenario, spec, args.cases, args.seed) if args.cases > 1 else [(scenario, spec)]
    t1 = time.perf_counter()
    if args.cases > 1:
        loads, readings, info = twin.run_batch(cases, observers, bound=not args.no_bound)
    else:
        snapshots = _Snapshots(len(scenario.times()) - 1) if _elastic_reference(args) else None
        loads, readings = twin.run(scenario, spec, observers, on_step=snapshots)
        info = twin.run_info
        readings = {k: v[:, :, None] for k, v in readings.items()}
    t2 = time.perf_counter()
    steps = len(scenario.times()) - 1
    prepared = float(twin.prepare_s.get("wall", 0.0))
    offline = float(info.get("rom_offline_s", info.get("heat_start_basis_s", 0.0)))
    result = {"machine": args.machine, "scenario": args.scenario, "spacing_m": mm.spacing, "nodes": int(mm.nnodes),
              **_stages(stages, twin),
              "solver": args.solver, "device": args.device, "cases": len(cases),
              "preparation_s": round(t1 - t0 + prepared, 3), "step_ms": round(1e3 * (t2 - t1 - prepared) / steps, 4),
              "total_s": round(t2 - t0, 3), **_process_use(c0)}
    result.update({k: v for k, v in info.items() if isinstance(v, (int, float, str)) and k not in result})
    if args.solver == "rom":
        result.update(rom_order=info["rom_order"], offline_s=round(offline, 3))
        if not args.no_reference:
            result["max_rel_error"], result["max_rel_error_of"] = _reference_error(twin, cases, observers, readings)
    if args.cases == 1 and _elastic_reference(args):
        result["elastic_rel_error"] = _elastic_error(twin, loads, scenario, observers, readings, snapshots)
    return _print(result, args)


def _stages(stages: dict, twin) -> dict:
    """``prepare_s``: the stages timed here (mesh, heat assembly) and those of the twin's run
    preparation (elastic assembly, adjoints, rows, the basis; :meth:`PreparedTwin.prepare`), each
    to the millisecond; ``prepare_concurrent``: whether the elastic chain ran beside the basis
    (then the stages overlap and their sum exceeds ``preparation_s``)."""
    parts = {**stages, **{k: v for k, v in twin.prepare_s.items() if k not in ("wall", "concurrent")}}
    return {"prepare_s": {k: round(v, 3) for k, v in parts.items()},
            "prepare_concurrent": bool(twin.prepare_s.get("concurrent", False))}


def _process_use(c0: float) -> dict:
    """``cpu_s`` (the process's CPU time since ``c0``) and ``peak_mib`` (its largest resident size)."""
    return {"cpu_s": round(time.process_time() - c0, 3),
            "peak_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)}


def _print(result: dict, args) -> int:
    """Print ``result`` as one JSON object (on one line with --json) and return the exit code 0."""
    print(json.dumps(result, sort_keys=True) if args.json else json.dumps(result, indent=2, sort_keys=True))
    return 0


def _check_combination(args) -> None:
    """Refuse options that would do nothing in this run (a silent no-op reads as a measurement)."""
    from twin.errors import InputError

    if args.no_bound and not (args.solver == "rom" and args.cases > 1):
        raise InputError("command line", "--no-bound", "skips the batched reduced model's bound: it needs --solver rom "
                                                       "and --cases N > 1")
    if args.no_reference and not (args.solver == "rom" or (args.elastic_coarsening > 1 and not args.heat_only)):
        raise InputError("command line", "--no-reference", "skips the full-order reference of --solver rom or the "
                                                           "one-mesh elastic reference of --elastic-coarsening N > 1; "
                                                           "this run has neither")
    if args.gpu_kernels is not None and args.device != "gpu":
        raise InputError("command line", "--gpu-kernels", "chooses the GPU's kernels: it needs --device gpu")
    if args.rom_order is not None and args.solver == "direct":
        raise InputError("command line", "--rom-order", "sets a reduced basis; --solver direct has none")
    if args.heat_tol is not None and args.solver in ("direct", "rom"):
        raise InputError("command line", "--heat-tol", f"bounds the error of iterative heat steps; --solver "
                                                       f"{args.solver} takes none (the reduced model reports its own "
                                                       "error)" if args.solver == "rom" else
                                                       "bounds the error of iterative heat steps; --solver direct "
                                                       "factorises them")
    given = getattr(args, "_options_given", set())       # the options typed (twin.cli.Parser)
    if "seed" in given and args.cases == 1:
        raise InputError("command line", "--seed", "seeds the factors of batched cases: it needs --cases N > 1")
    if args.elastic_coarsening > 1 and args.heat_only:
        raise InputError("command line", "--elastic-coarsening", "coarsens the elastic mesh; --heat-only solves no "
                                                                 "elasticity")
    if args.prepare_only:
        stepped = [o for o, on in (("--cases", args.cases > 1), ("--no-bound", args.no_bound),
                                   ("--no-reference", args.no_reference), ("--seed", "seed" in given)) if on]
        if stepped:
            raise InputError("command line", stepped[0], "acts on the time steps; --prepare-only stops before them")


def _elastic_reference(args) -> bool:
    """Whether to compare a full-order run on a coarser elastic mesh with the one-mesh elasticity."""
    return args.elastic_coarsening > 1 and args.solver != "rom" and not args.heat_only and not args.no_reference


class _Snapshots:
    """``on_step`` hook keeping the temperature field at about ``count`` evenly spaced steps."""

    def __init__(self, nsteps: int, count: int = 24):
        self.steps = set(np.unique(np.linspace(1, nsteps, count).round().astype(int)).tolist())
        self.fields: dict[int, np.ndarray] = {}

    def __call__(self, n, T):
        if n in self.steps:
            self.fields[n] = np.array(T)


def _elastic_error(twin, loads, scenario, observers, readings, snapshots) -> float:
    """max over the drift outputs of |coarse - one mesh| / max |one mesh| at the snapshot steps,
    both as changes from the start: the elasticity of ``twin`` (on every n-th line) against the
    same temperatures through the temperature mesh's own elasticity (built here, not timed)."""
    from twin.physics.prepared import PreparedTwin

    one = PreparedTwin(twin.machine, twin.mm, solver=replace(twin.options, elastic_coarsening=1))
    steps = sorted(snapshots.fields)
    fields = np.column_stack([snapshots.fields[n] for n in steps])
    T0 = np.full(fields.shape[0], scenario.start_temperature)
    worst = 0.0
    for o in observers:
        if o.key not in ("drift", "probes"):
            continue
        rows = one.displacement_rows(o, loads.mm)
        ref = (rows @ fields).T - rows @ T0
        worst = max(worst, _worst_relative(readings[o.key][steps, :, 0] - readings[o.key][0, :, 0], ref))
    return worst


def _worst_relative(got: np.ndarray, ref: np.ndarray) -> float:
    """max over the outputs (columns) of max_t |got - ref| / max_t |ref|; an output whose peak is
    below 1e-3 of the largest does not move and has no relative error."""
    peak = np.abs(ref).max(axis=0)
    ok = peak > 1e-3 * peak.max()
    return float(np.max(np.abs(got - ref).max(axis=0)[ok] / peak[ok]))


def _reference_error(twin, cases, observers, readings, most: int = 3) -> tuple[float, list[str]]:
    """(max over the drift outputs (and up to ``most`` cases) of max_t |rom - full| / max_t |full|,
    both as changes from the start; the outputs compared). Without drift outputs (``--heat-only``)
    the temperature sensors are compared instead, and the second item says so."""
    reduced_options = twin.options
    twin.options = replace(reduced_options, solver="auto")
    keys = [k for k in ("drift", "probes") if k in readings] or ["temperature"]
    worst = 0.0
    try:
        for j, (sc, spec) in enumerate(cases[:most]):
            _, full = twin.run(sc, spec, observers)
            for key in keys:
                ref = full[key] - full[key][0]
                worst = max(worst, _worst_relative(readings[key][:, :, j] - readings[key][0, :, j], ref))
    finally:
        twin.options = reduced_options
    return worst, keys


if __name__ == "__main__":
    raise SystemExit(main())
