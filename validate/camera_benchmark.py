"""What a thermal camera costs: ``python -m validate.camera_benchmark [--camera POSE] [--mesh R]
[--scenario S] [--repeat N] [-o DIR]``.

Simulates the scenario (default the seeds' 190-min spindle test, sampled every 10 s) on one
prepared twin without and with a camera (default ``carrier-front``, 320 x 240, a frame every
sample), each packaged and written to NetCDF, ``--repeat`` times in alternation (default 2), and
prints the best wall time of each, the camera's overhead (run, packaging with the radiometry and
sensor chain, writing) and the bytes it adds to the file. The first plain run also factorises the
elastic stiffness and the heat operators and is not counted. Not a test: the numbers depend on
the machine and its load.
"""

from __future__ import annotations

import os
import resource
import time
from pathlib import Path


def timed_run(machine, scenario, twin, observers, path: Path) -> dict:
    """Wall times [s] of the run, the packaging and the writing, and the file size [B]."""
    from twin.io.results import to_dataset, write_netcdf
    from twin.simulate import run

    t0 = time.perf_counter()
    r = run(machine, scenario, prepared=twin, observers=observers)
    t1 = time.perf_counter()
    ds = to_dataset(r, 0, "")
    t2 = time.perf_counter()
    write_netcdf(ds, path)
    t3 = time.perf_counter()
    return {"run": t1 - t0, "package": t2 - t1, "write": t3 - t2, "total": t3 - t0, "bytes": os.path.getsize(path)}


DEFAULT_OUTPUT = "validate-out/camera_benchmark"
FILES = ("plain.nc", "camera.nc")


def _parser():
    from twin.cli.options import whole_number
    from validate.studies.common import cli_parser

    ap = cli_parser("python -m validate.camera_benchmark", __doc__)
    ap.add_argument("--machine", default="cframe-vmc", help="machine (default: %(default)s)")
    ap.add_argument("--scenario", default="spindle-heat-cool-9000", help="scenario name or file (default: %(default)s)")
    ap.add_argument("--mesh", default="default", choices=["coarse", "default", "fine"],
                    help="mesh resolution (default: %(default)s)")
    ap.add_argument("--camera", default="carrier-front", metavar="POSE",
                    help="the machine's camera pose (default: %(default)s)")
    ap.add_argument("--repeat", type=whole_number("repetitions", 1), default=2,
                    help="timed runs of each kind, at least 1 (default: %(default)s)")
    ap.add_argument("-o", "--output", default=DEFAULT_OUTPUT,
                    help=f"folder for {' and '.join(FILES)} (default: %(default)s)")
    return ap


def main(argv=None) -> int:
    """The benchmark; bad input is one line ``error: <source>: <field>: <message>`` and exit code 2,
    found before the output folder is made or any run starts."""
    from validate.studies.common import run_cli

    return run_cli(_parser().parse_args, argv, _run)


def _run(args) -> int:
    from twin import limits
    from twin.api import machine_by_name
    from twin.cli.options import declare_scenario
    from twin.fem.mesh import mesh_machine
    from twin.io.paths import Files
    from twin.observe import standard_observers
    from twin.observe.camera import CameraConfig, ThermalCamera
    from twin.physics.prepared import PreparedTwin
    from twin.scenario import load_scenario
    from validate.studies.common import check_output_folder

    m = machine_by_name(args.machine, "--machine")
    files = Files()
    declare_scenario(files, args.scenario)
    sc = load_scenario(args.scenario)
    limits.check_scenario(sc, m)
    config = CameraConfig(pose=args.camera, source="command line", where="--camera")
    config.resolve_pose(m)
    config.check(sc)
    out = check_output_folder(args.output, FILES, default=DEFAULT_OUTPUT, files=files)
    mm = mesh_machine(m, args.mesh)
    limits.check_run_size(sc, mm.nheat)
    twin = PreparedTwin(m, mm)
    out.mkdir(parents=True, exist_ok=True)
    timed_run(m, sc, twin, standard_observers(m), out / "plain.nc")  # warm-up: factorisations
    plain, camera = [], []
    for _ in range(args.repeat):
        plain.append(timed_run(m, sc, twin, standard_observers(m), out / "plain.nc"))
        cam = ThermalCamera(m, config)
        camera.append(timed_run(m, sc, twin, standard_observers(m) + [cam], out / "camera.nc"))
    best = {k: min(r["total"] for r in runs) for k, runs in (("plain", plain), ("camera", camera))}
    c = min(camera, key=lambda r: r["total"])
    frames = len(sc.times())
    print(f"{args.machine} / {args.scenario} / mesh {args.mesh}: {frames} samples; camera {args.camera}, "
          f"320 x 240, a frame every sample")
    print(f"  plain run + package + write   {best['plain']:.1f} s (best of {len(plain)}: "
          + ", ".join(f"{r['total']:.1f}" for r in plain) + ")")
    print(f"  with camera                   {best['camera']:.1f} s (best of {len(camera)}: "
          + ", ".join(f"{r['total']:.1f}" for r in camera) + f"); run {c['run']:.1f} s, package {c['package']:.1f} s, "
          f"write {c['write']:.1f} s")
    print(f"  camera overhead               {best['camera'] - best['plain']:.1f} s")
    print(f"  file size                     {plain[0]['bytes'] / 1e6:.1f} MB -> {camera[0]['bytes'] / 1e6:.1f} MB "
          f"(+{(camera[0]['bytes'] - plain[0]['bytes']) / 1e6:.1f} MB)")
    print(f"  peak memory (max RSS)         {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
