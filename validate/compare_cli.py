"""``twin compare MEAS [--machine NAME] [--mapping TOML] [--scenario S] [--effects ..] [--set ..] [--mesh R]``:
the twin driven by a measurement's inputs, its residuals per channel and phase printed as a table
(:mod:`validate.compare`); registered with ``twin`` through the ``thermal_twin.commands`` entry point.
"""

from __future__ import annotations

from twin.cli.options import add_measurement_options, add_model_options


def add_compare_parser(subparsers) -> None:
    """Add ``twin compare`` to the ``twin`` command line."""
    p = subparsers.add_parser("compare", help="compare the twin with a measurement: residuals per channel and phase")
    add_measurement_options(p)
    add_model_options(p)
    p.set_defaults(func=run_compare)


def run_compare(args) -> int:
    """CLI body of ``twin compare``: prints the comparison table, returns 0."""
    from twin.cli.progress import progress_bar
    from twin.io.paths import Files
    from validate.compare import compare, format_compare, model_for
    from validate.inputs import declare_inputs, load_inputs

    declare_inputs(Files(), args)
    meas, machine, sc, _ = load_inputs(args)
    model, _ = model_for(meas, machine.name, sc, args.effects, args.set, args.mesh, args.seed,
                         progress=progress_bar(f"{machine.name} / measured inputs"), effects_file=args.effects_file)
    print(format_compare(compare(meas, model)))
    return 0
