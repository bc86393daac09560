"""What ``twin compare`` and ``twin diagnose`` start from: the measurement, its machine, the
scenario that drives the twin, and the model, all checked before any simulation runs."""

from __future__ import annotations

from twin.errors import InputError


def measured_machine(meas, args):
    """The machine of a measurement: ``--machine``, else the one the measurement names (a result's
    ``machine`` attribute, a mapping's ``machine`` key); both given and different is an error."""
    from geometries import MACHINES
    from twin.api import machine_by_name

    named = meas.attrs.get("machine")
    if args.machine and named and args.machine != named:
        raise InputError(args.measurement, "machine", f"the measurement is of {named!r}, --machine says {args.machine!r}")
    name = args.machine or named
    if not name:
        raise InputError(args.measurement, "machine", "the measurement does not name its machine; give --machine "
                                                      f"(known: {', '.join(sorted(MACHINES))})")
    return machine_by_name(name)


def load_inputs(args):
    """(measurement Dataset, machine, Scenario, ModelSpec) from the parsed arguments of a command
    with the measurement and model options (:mod:`twin.cli.options`)."""
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement
    from twin.model import model_spec
    from twin.scenario import load_scenario

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    machine = measured_machine(meas, args)
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    spec = model_spec(machine, args.effects, args.set)
    sc = load_scenario(args.scenario) if args.scenario else scenario_from_measurement(meas)
    return meas, machine, sc, spec
