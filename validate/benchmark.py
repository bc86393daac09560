"""Benchmark one run: ``python -m validate.benchmark [--machine M] [--scenario S] [--mesh R]``.

Prints node count, heat assembly, elastic factorisation (+ adjoint drift operator), time per
step, total wall time and peak memory. Not a test: numbers depend on the machine.
"""

from __future__ import annotations

import argparse
import resource
import time


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m validate.benchmark")
    ap.add_argument("--machine", default="cframe-vmc")
    ap.add_argument("--scenario", default="spindle-heat-cool-9000")
    ap.add_argument("--mesh", default="default")
    args = ap.parse_args(argv)
    from twin.api import simulate

    t0 = time.perf_counter()
    ds, r = simulate(args.machine, args.scenario, resolution=args.mesh)
    wall = time.perf_counter() - t0
    t = r.timings
    peak_mib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"machine {args.machine}, scenario {args.scenario}, mesh {args.mesh}")
    print(f"  nodes                      {r.mm.nnodes} ({r.mm.ncells} cells, {3 * r.mm.nnodes} elastic dofs)")
    print(f"  preparation                {t['preparation']:.2f} s (heat assembly, elastic assembly and "
          f"factorisation, adjoint drift solves, sensor operators)")
    print(f"  time stepping              {t['time_stepping']:.2f} s for {t['steps']} steps "
          f"({1e3 * t['time_stepping'] / t['steps']:.2f} ms per step, incl. factorisations of the heat operators)")
    print(f"  total wall time            {wall:.2f} s")
    print(f"  peak memory (max RSS)      {peak_mib:.0f} MiB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
