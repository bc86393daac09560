"""What ``twin compare`` and ``twin diagnose`` start from: the measurement(s), their machine, the
scenario that drives the twin, and the model, all checked before any simulation runs."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from twin.errors import InputError


def measured_machine(meas, args, source: str | None = None):
    """The machine of a measurement: ``--machine``, else the one the measurement names (a result's
    ``machine`` attribute, a mapping's ``machine`` key); both given and different is an error."""
    from geometries import MACHINES
    from twin.api import machine_by_name

    source = source or args.measurement
    named = meas.attrs.get("machine")
    if args.machine and named and args.machine != named:
        raise InputError(source, "machine", f"the measurement is of {named!r}, --machine says {args.machine!r}")
    if args.machine:
        return machine_by_name(args.machine, "--machine")
    if not named:
        raise InputError(source, "machine", "the measurement does not name its machine; give --machine "
                                            f"(known: {', '.join(sorted(MACHINES))})")
    try:
        return machine_by_name(named)
    except InputError as err:    # a result's attribute naming a machine this version does not have
        raise InputError(source, "machine", err.message) from None


def measurement_paths(args) -> list[str]:
    """The measurement file(s) of the command: ``args.measurements`` (diagnose) or ``args.measurement``."""
    paths = getattr(args, "measurements", None)
    return list(paths) if paths is not None else [args.measurement]


def declare_inputs(files, args) -> None:
    """Declare the measurement(s), their column mappings, a ``--scenario`` file and an
    ``--effects-file`` as inputs of the command (:class:`twin.io.paths.Files`: existing regular
    readable files, never an output)."""
    from twin.cli.options import declare_effects_file, declare_scenario
    from twin.io.measurement import mapping_path

    given = getattr(args, "mapping", None)
    for path in measurement_paths(args):
        files.input(path, "measurement", "measurement file", once=True)
        mapping = mapping_path(path, given)
        if given or (mapping is not None and os.path.lexists(mapping)):   # a missing default: the reader says so
            files.input(mapping, "--mapping", "column mapping")
    if args.scenario:
        declare_scenario(files, args.scenario)
    if getattr(args, "effects_file", None):
        declare_effects_file(files, args.effects_file)


def custom_effects(args, machine) -> tuple[str, ...]:
    """Register the custom effects of ``--effects-file`` (if given) for ``machine``; their names."""
    path = getattr(args, "effects_file", None)
    if not path:
        return ()
    from twin.effects.custom import load_effects_file
    return tuple(load_effects_file(path, machine))


def measured_scenario(meas, args, machine):
    """The scenario that drives the twin for ``meas``: ``--scenario`` (it must last at least as
    long as the measurement) or the one built from the logged inputs; within the machine's limits."""
    from twin import limits
    from twin.io.measured_inputs import scenario_from_measurement
    from twin.scenario import load_scenario

    if args.scenario:
        sc = load_scenario(args.scenario)
        t = np.asarray(meas.time.values, float)
        if sc.duration < t[-1] - t[0]:
            raise InputError(sc.source, "duration", f"the scenario lasts {sc.duration:g} s, the measurement "
                                                    f"{t[-1] - t[0]:g} s: it must cover the whole measurement")
    else:
        sc = scenario_from_measurement(meas)
    limits.check_scenario(sc, machine)
    return sc


def load_inputs(args):
    """(measurement Dataset, machine, Scenario, ModelSpec) from the parsed arguments of a command
    with the measurement and model options (:mod:`twin.cli.options`); the custom effects of
    ``--effects-file`` are registered and switched on, as the twin the command runs has them
    (:func:`twin.api.simulate`): ``--effects=-NAME`` of one is refused, not taken for an effect
    that is not in the model."""
    from twin.io.measurement import read_measurement
    from twin.model import model_spec
    from twin.motion import machine_for

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    machine = measured_machine(meas, args)
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    sc = measured_scenario(meas, args, machine)
    machine = machine_for(machine, sc)   # with its feed drives' parts when an axis moves
    spec = model_spec(machine, args.effects, args.set, custom_effects(args, machine))
    return meas, machine, sc, spec


def measurement_labels(paths) -> list[str]:
    """A label per measurement path, unique among them: its file name, or where two share a file
    name the shortest tail of its path that tells it from the others (``a/m.csv``, ``b/m.csv``);
    a diagnosis suffixes every channel with ``@label``, so equal labels would merge channels. The
    paths are distinct files (:func:`declare_inputs` refuses one given twice), so the longest tail,
    the whole absolute path, always tells them apart."""
    parts = [Path(os.path.abspath(p)).parts for p in paths]
    labels = []
    for i, mine in enumerate(parts):
        k = next(k for k in range(1, len(mine) + 1)
                 if all(other[-k:] != mine[-k:] for j, other in enumerate(parts) if j != i))
        labels.append(str(Path(*mine[-k:])))
    return labels


def refuse_copies(paths) -> None:
    """Two measurement files with the same bytes are one run given twice under two names (a copy):
    a joint fit would weigh it twice. :class:`InputError` naming the later one and the earlier."""
    import hashlib

    seen = {}
    for path in paths:
        digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
        if digest in seen:
            raise InputError(str(path), "measurement", f"holds the same bytes as {seen[digest]}: a copy would weigh "
                                                       "one run twice in the joint fit; give each run once")
        seen[digest] = str(path)


def load_measurements(args):
    """([(label, Dataset, Scenario)], machine, ModelSpec, custom effect names) for ``twin
    diagnose MEAS [MEAS ...]``, declared first (:func:`declare_inputs`: each file once): every
    measurement must be of the same machine; ``--mapping`` and ``--scenario`` need a single
    measurement."""
    from twin.io.measurement import read_measurement
    from twin.model import model_spec
    from twin.motion import machine_for

    paths = measurement_paths(args)
    if len(paths) > 1 and args.mapping:
        raise InputError("command line", "--mapping", "applies to a single measurement; give each CSV its own "
                                                      "mapping next to it")
    if len(paths) > 1 and args.scenario:
        raise InputError("command line", "--scenario", "applies to a single measurement; leave it out (each "
                                                       "measurement drives the twin by its own logged inputs) or "
                                                       "diagnose one measurement at a time")
    refuse_copies(paths)
    runs, machine = [], None
    for path, label in zip(paths, measurement_labels(paths)):
        meas = read_measurement(path, args.mapping, args.machine)
        m = measured_machine(meas, args, path)
        if machine is not None and m.name != machine.name:
            raise InputError(path, "machine", f"is of {m.name!r}, the first measurement of {machine.name!r}")
        machine = m
        runs.append((label, meas, measured_scenario(meas, args, machine)))
    if args.mesh not in machine.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {args.mesh!r}")
    for _, _, sc in runs:   # with its feed drives' parts when a measurement moves an axis
        machine = machine_for(machine, sc)
    custom = custom_effects(args, machine)
    spec = model_spec(machine, args.effects, args.set)
    return runs, machine, spec, custom
