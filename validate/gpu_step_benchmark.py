"""The GPU heat step's operations one by one: where a step's time goes on a CUDA GPU.

    python -m validate.gpu_step_benchmark [--machine cframe-vmc] [--scenario etve-day-night] [--spacing 23mm]
                               [--repeats 200] [--json]

On the machine's heat system at ``--spacing`` (the scenario's first film coefficients, its 60 s
theta step), each operation of an iterative heat step is timed over ``--repeats`` repeats between
two synchronisations of the device, on the fused kernels of :mod:`twin.physics.gpu_cg` and on
CuPy's array operations and cuSPARSE where both exist: the product with the heat matrix, the
product with the output rows (temperature sensors and heat balance) with and without the copy
back, the reduced start's correction V (G (V^T r)) on a basis of order 49, the load vector, one
vector operation, and a CG iteration (20 iterations less the start, over 50 repeats). Prints one
JSON object (``--json``) or one line per operation, in ms. It needs CuPy and a CUDA device
(refused otherwise, exit code 2). Not a test: the numbers depend on the card and its load; the
products' largest relative difference from cuSPARSE is printed beside them.
"""

from __future__ import annotations

import json
import time

import numpy as np

ORDER = 49          # the reduced basis's order (the twin's default start)
CG_ITERATIONS = 20


def _parser():
    from twin.cli.options import positive_quantity, whole_number
    from validate.studies.common import cli_parser

    ap = cli_parser("python -m validate.gpu_step_benchmark", __doc__)
    ap.add_argument("--machine", default="cframe-vmc")
    ap.add_argument("--scenario", default="etve-day-night")
    ap.add_argument("--spacing", type=positive_quantity("length"), default="23mm",
                    help="cell size with its unit (default 23mm: about 200 k nodes on cframe-vmc)")
    ap.add_argument("--repeats", type=whole_number("repeats", 1, 100_000), default=200,
                    help="repeats of each operation between two synchronisations (default 200)")
    ap.add_argument("--json", action="store_true", help="print only the JSON object")
    return ap


def main(argv=None) -> int:
    from validate.studies.common import run_cli

    return run_cli(_parser().parse_args, argv, _run)


def _timer(repeats: int):
    import cupy as cp

    sync = cp.cuda.Device().synchronize

    def ms(f, n: int = repeats) -> float:
        f()
        sync()
        t0 = time.perf_counter()
        for _ in range(n):
            f()
        sync()
        return 1e3 * (time.perf_counter() - t0) / n
    return ms


def _run(args) -> int:
    from twin import limits
    from twin.api import machine_by_name
    from twin.fem.mesh import build_mesh
    from twin.model import model_spec
    from twin.observe import HeatBalance, TemperatureSensors, sensor_points
    from twin.physics.prepared import PreparedTwin
    from twin.physics.solvers import array_module
    from twin.scenario import load_scenario

    from twin.errors import InputError

    try:
        cp = array_module("gpu")        # refused here, before the mesh, without CuPy and a device
    except InputError:
        raise InputError("command line", "python -m validate.gpu_step_benchmark",
                         "needs CuPy (pip install cupy-cuda12x) and a CUDA GPU") from None
    machine, scenario = machine_by_name(args.machine, "--machine"), load_scenario(args.scenario)
    limits.check_scenario(scenario, machine)
    mm = build_mesh(machine, args.spacing)
    limits.check_run_size(scenario, mm.nheat)
    twin = PreparedTwin(machine, mm, solver="iterative")
    loads = twin.loads(scenario, model_spec(machine))
    W, _ = twin.output_rows([TemperatureSensors(sensor_points(machine)), HeatBalance()], loads)
    result = {"machine": args.machine, "spacing_m": mm.spacing, "nodes": int(mm.nheat),
              "device": cp.cuda.runtime.getDeviceProperties(0)["name"].decode(), "repeats": args.repeats,
              **_times(cp, loads, W, scenario, _timer(args.repeats))}
    print(json.dumps(result, sort_keys=True) if args.json else
          "\n".join(f"{k}: {v}" for k, v in result.items()))
    return 0


def _times(cp, loads, W, scenario, ms) -> dict:
    """Each operation's ms (module docstring) and the products' largest relative difference."""
    import cupyx.scipy.sparse as csp

    from twin.physics import gpu_cg
    from twin.physics.solvers import jacobi, mass_weights, pcg
    from twin.physics.steppers import theta_operators

    dt = scenario.sample_interval
    h = loads.signals(scenario.times()[:1] + 0.5 * dt)[0][0]
    lhs, rhs = theta_operators(loads.system, dt, 0.5, h)
    n = lhs.shape[0]
    rng = np.random.default_rng(0)
    x = cp.asarray(rng.random(n))
    out = {}
    for name, A in (("heat_product", rhs), ("output_rows", W)):
        sparse, ours = csp.csr_matrix(A), gpu_cg.DeviceMatrix(A)
        ref = sparse @ x
        out[f"{name}_cusparse_ms"] = ms(lambda: sparse @ x)
        out[f"{name}_kernel_ms"] = ms(lambda: ours @ x)
        out[f"{name}_kernel_rel_difference"] = float(cp.abs(ours @ x - ref).max() / cp.abs(ref).max())
    out["output_rows_cusparse_copied_back_ms"] = ms(lambda: cp.asnumpy(csp.csr_matrix(W) @ x))
    V = cp.asarray(np.asfortranarray(rng.random((n, ORDER)), dtype=np.float32))
    G, f32 = cp.asarray(np.eye(ORDER)), cp.float32
    out["reduced_start_correction_ms"] = ms(lambda: V @ (G @ (V.T @ x.astype(f32)).astype(float)).astype(f32))
    F, s = cp.asarray(loads.system.F), np.ones(loads.system.F.shape[1])
    out["load_vector_ms"] = ms(lambda: F @ cp.asarray(s))
    out["vector_operation_ms"] = ms(lambda: 2.0 * x - x)
    w, dinv, b = cp.asarray(mass_weights(loads.system.M)), cp.asarray(1.0 / lhs.diagonal()), cp.asarray(rng.random(n))
    sparse, ours = csp.csr_matrix(lhs), gpu_cg.DeviceMatrix(lhs)

    def cg(k: int, fused: bool):
        def run():          # tolerance 0: CG runs k iterations and says it did not converge
            try:
                if fused:
                    gpu_cg.jacobi_pcg(ours, b, cp.zeros(n), dinv, w, 0.0, k, False)
                else:
                    pcg(lambda v: sparse @ v, b, cp.zeros(n), jacobi(dinv), w, 0.0, cp, k)
            except RuntimeError:
                pass
        return run

    for label, fused in (("fused", True), ("arrays", False)):
        start, many = ms(cg(0, fused), 50), ms(cg(CG_ITERATIONS, fused), 50)
        out[f"cg_{label}_start_ms"] = start
        out[f"cg_{label}_iteration_ms"] = (many - start) / CG_ITERATIONS
    return {k: round(v, 4) if k.endswith("_ms") else v for k, v in out.items()}


if __name__ == "__main__":
    raise SystemExit(main())
