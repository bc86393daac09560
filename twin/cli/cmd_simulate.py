"""``twin simulate MACHINE SCENARIO -o OUT.nc [--field FILE] [model options]``."""

from __future__ import annotations

from pathlib import Path

from twin.cli.options import add_model_options, declare_effects_file, declare_scenario, solver_options
from twin.cli.progress import progress_bar
from twin.io.fields import declare_field
from twin.io.paths import NETCDF_SUFFIXES, Files


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="simulate a scenario on a machine and write a NetCDF result")
    p.add_argument("machine")
    p.add_argument("scenario", help="a bundled scenario name or a path to a TOML file")
    p.add_argument("-o", "--output", required=True, help="result file (.nc)")
    p.add_argument("--field", metavar="FILE", help="also write the temperature field at the hottest moment (.vtu, "
                   "or .xdmf with its arrays in a companion .h5 of the same name: hot.xdmf writes hot.h5 too)")
    p.add_argument("--camera", metavar="NAME[,NAME]", help="add thermal cameras at the machine's named poses "
                   "(e.g. carrier-front; overview-front for any machine), default settings: a frame at every sample "
                   "(the scenario's sample_interval) in the result; a scenario's [camera] section can set "
                   "frame_interval and the rest")
    add_model_options(p, solvers=True)
    p.set_defaults(func=run)


def simulate_with_progress(machine: str, scenario: str, args):
    """``twin.api.simulate`` with the CLI's model options and a progress bar; (Dataset, RunResult)."""
    from twin.api import simulate
    from twin.camera_config import cameras_from_option

    return simulate(machine, scenario, args.effects, args.set, args.mesh, args.seed,
                    progress=progress_bar(f"{machine} / {Path(scenario).stem}"), solver=solver_options(args),
                    cameras=cameras_from_option(getattr(args, "camera", None)),
                    effects_file=getattr(args, "effects_file", None))


def rom_error_line(ds, peak) -> str:
    """The reduced model's estimated drift error per axis [um] beside the peak |drift| ``peak``
    (xarray, um): the user of --solver rom sees what the order leaves, not only the attributes.
    The share is taken over the axes whose peak is at least a thousandth of the largest (an axis
    that does not drift, X of a symmetric machine, has a round-off peak)."""
    import json

    import numpy as np

    estimate = 1e6 * np.asarray(json.loads(ds.attrs["rom_error_estimate"])["drift"])     # m -> um
    peaks = np.array([float(peak.sel(axis=a)) for a in ds.axis.values])
    moving = peaks >= 1e-3 * peaks.max() if peaks.max() > 0 else np.zeros(len(peaks), bool)
    share = float(np.max(estimate[moving] / peaks[moving])) if moving.any() else 0.0
    return (f"  reduced model, order {int(ds.attrs['rom_order'])}: estimated drift error "
            + ", ".join(f"{a} {e:.2f} um" for a, e in zip(ds.axis.values, estimate))
            + f" (up to {100 * share:.2g} % of the peak; --rom-order raises the order)")


def run(args) -> int:
    from twin.api import machine_by_name
    from twin.io.results import write_netcdf

    machine_by_name(args.machine)
    files = Files()
    declare_scenario(files, args.scenario)
    if args.effects_file:
        declare_effects_file(files, args.effects_file)
    out = files.output(args.output, "-o", NETCDF_SUFFIXES)
    field_path = declare_field(files, args.field, "--field") if args.field else None
    ds, result = simulate_with_progress(args.machine, args.scenario, args)
    write_netcdf(ds, out, "-o")
    if field_path:
        from twin.io.fields import save_temperature_field

        written = save_temperature_field(result.mm, result.hottest_field, field_path, result.hottest_time, "--field")
        print(f"wrote {' and '.join(map(str, written))}: temperature field at the hottest moment, "
              f"t = {result.hottest_time / 60:.0f} min")
    peak = abs(ds.drift).max("time")
    print(f"wrote {out}: {len(ds.time)} samples, {result.mm.nnodes} nodes; peak |drift| "
          + ", ".join(f"{a} {float(peak.sel(axis=a)):.1f} um" for a in ds.axis.values))
    if "rom_error_estimate" in ds.attrs:
        print(rom_error_line(ds, peak))
    if "positioning_slope" in ds:
        k = ds.positioning_slope.values
        print(f"  interferometer: {len(k)} runs; thermal slope k - k0 at the last ({ds.run_time.values[-1] / 60:g} min) "
              f"{k[-1]:.4f} um/mm, error at {ds.target.values[-1]:g} mm {float(ds.positioning_error[-1, -1, 0]):.1f} um")
    if "probing_error" in ds:
        worst = abs(ds.probing_error).max(("probe_time", "datum"))
        print(f"  probing: {len(ds.probe_time)} routines of {len(ds.datum)} datums; largest error "
              + ", ".join(f"{a} {float(worst.sel(axis=a)):.1f} um" for a in ds.axis.values))
    for cam in (o for o in result.observers if o.key.startswith("camera")):
        thermo = ds[cam.name("thermogram")]
        print(f"  camera {cam.config.label}: {thermo.shape[0]} frames of {thermo.shape[2]} x {thermo.shape[1]} px "
              f"(variable {thermo.name}; export with `twin frames {out}`)")
    return 0
