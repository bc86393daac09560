"""What ``twin compare`` and ``twin diagnose`` start from: the measurement, its machine, the
scenario that drives the twin, and the model, all checked before any simulation runs."""

from __future__ import annotations

import os

import numpy as np

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


def declare_inputs(files, args) -> None:
    """Declare the measurement, its column mapping and a ``--scenario`` file as inputs of the
    command (:class:`twin.io.paths.Files`: existing regular readable files, never an output)."""
    from twin.cli.options import declare_scenario
    from twin.io.measurement import mapping_path

    files.input(args.measurement, "measurement", "measurement file")
    given = getattr(args, "mapping", None)
    mapping = mapping_path(args.measurement, given)
    if given or (mapping is not None and os.path.lexists(mapping)):   # a missing default: the reader says so
        files.input(mapping, "--mapping", "column mapping")
    if args.scenario:
        declare_scenario(files, args.scenario)


def load_inputs(args):
    """(measurement Dataset, machine, Scenario, ModelSpec) from the parsed arguments of a command
    with the measurement and model options (:mod:`twin.cli.options`). A ``--scenario`` must
    respect the machine's speed limit and last at least as long as the measurement."""
    from twin import limits
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.io.measurement import read_measurement
    from twin.model import model_spec
    from twin.scenario import load_scenario

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    machine = measured_machine(meas, args)
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    spec = model_spec(machine, args.effects, args.set)
    if args.scenario:
        sc = load_scenario(args.scenario)
        t = np.asarray(meas.time.values, float)
        if sc.duration < t[-1] - t[0]:
            raise InputError(sc.source, "duration", f"the scenario lasts {sc.duration:g} s, the measurement "
                                                    f"{t[-1] - t[0]:g} s: it must cover the whole measurement")
    else:
        sc = scenario_from_measurement(meas)
    limits.check_scenario(sc, machine)
    return meas, machine, sc, spec
