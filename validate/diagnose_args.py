"""The arguments of a diagnosis (:func:`validate.diagnose.diagnose_many`) checked before any run.

A library user calls the diagnosis with Python values; each bad one is one
:class:`twin.errors.InputError` naming the argument, raised before the baseline runs: a threshold
that is NaN or out of its range would change the verdict silently, an unknown candidate would
fail deep in the fit, a measurement with NaN would fail in LAPACK. ``SOURCE`` is the source those
errors name.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from geometries.base import Machine
from twin.effects import EFFECTS
from twin.errors import InputError, describe
from twin.io.measured_inputs import sensors_of
from twin.io.measurement import check_measurement, check_named_machine
from twin.limits import check_flag, check_progress, is_finite_number, is_whole
from twin.model import ModelSpec, check_applicable
from twin.physics.prepared import check_resolution
from twin.scenario import Scenario

SOURCE = "diagnose"


def check_arguments(measurements, machine, spec, candidates, custom, shares: dict, bic_margin, counts: dict,
                    resolutions: dict, model_error, flags: dict | None = None, progress=None) -> list:
    """Raise :class:`InputError` for the first bad argument; return ``measurements`` as a list.

    ``measurements``: one or more ``(label, Dataset, Scenario)``, each Dataset a measurement of
    ``machine`` (:func:`twin.io.measurement.check_measurement`: finite values, increasing time,
    two samples or more; each temperature sensor a site of the machine or placed), each Scenario checked as the loader would; ``machine`` a built
    :class:`geometries.base.Machine`; ``spec`` None or a :class:`twin.model.ModelSpec` within its
    parameters' bounds; ``candidates`` None or effect names, ``custom`` registered custom effects;
    ``shares`` (name: value) from 0 (excluded) to 1 and ``bic_margin`` >= 0, each finite; ``counts``
    integers >= 1; ``resolutions`` (name: None or a mesh of the machine); ``model_error`` None or one
    array per measurement (its per-channel shape is checked once the channels are known,
    :func:`check_model_error`); ``flags`` (name: value) booleans; ``progress`` None or callable."""
    if not isinstance(machine, Machine):
        raise InputError(SOURCE, "machine", f"expected a built machine (twin.api.machine_by_name), got {describe(machine)}")
    if not isinstance(measurements, (list, tuple)) or not measurements:
        raise InputError(SOURCE, "measurements", f"expected a list of one or more (label, Dataset, Scenario), got "
                                                 f"{describe(measurements)}")
    for i, item in enumerate(measurements):
        if not isinstance(item, (list, tuple)) or len(item) != 3:
            raise InputError(SOURCE, f"measurements[{i}]", f"expected (label, Dataset, Scenario), got {describe(item)}")
        label, ds, scenario = item
        if not isinstance(label, str) or not label.strip():
            raise InputError(SOURCE, f"measurements[{i}]", f"a label is a non-empty text, got {describe(label)}")
        if any(label == other[0] for other in measurements[:i] if isinstance(other, (list, tuple)) and other):
            raise InputError(SOURCE, f"measurements[{i}]", f"the label {label!r} is given twice: its channels would "
                                                           "share names, and the same run given twice weighs twice")
        if any(ds is other[1] for other in measurements[:i] if isinstance(other, (list, tuple)) and len(other) > 1):
            raise InputError(SOURCE, f"measurements[{i}]", f"{label!r} is the same Dataset as an earlier measurement: "
                                                           "the same run given twice would weigh twice")
        if not isinstance(ds, xr.Dataset):
            raise InputError(label, "measurement", f"expected an xarray.Dataset (twin.io.measurement.read_measurement), "
                                                   f"got {describe(ds)}")
        check_named_machine(ds, machine.name, label, "the diagnosing model of")
        check_measurement(ds, machine, label)
        sensors_of(ds, machine, label)     # every temperature sensor a site or placed by x, y, z
        if not isinstance(scenario, Scenario):
            raise InputError(label, "scenario", f"expected a twin.scenario.Scenario (the measured inputs: "
                                                f"twin.io.measured_inputs.scenario_from_measurement), got {describe(scenario)}")
        scenario.check()
        t = np.asarray(ds["time"].values, dtype=float)
        if t[-1] - t[0] > scenario.duration + 1e-9:     # found by the records after the mesh, before
            raise InputError(label, "time", f"the measurement spans {(t[-1] - t[0]) / 60:g} min, beyond its scenario's "
                                            f"{scenario.duration / 60:g} min: give the scenario that drove the run")
    if spec is not None:
        if not isinstance(spec, ModelSpec):
            raise InputError(SOURCE, "spec", f"expected a twin.model.ModelSpec (twin.model.model_spec), got {describe(spec)}")
        spec.check_bounds(SOURCE)
        check_applicable(spec.effects, machine)     # before the mesh, not after it
    _check_names("candidates", candidates, lambda n: n in EFFECTS and EFFECTS[n].applies_to(machine),
                 f"a registered effect that applies to machine {machine.name}", allow_none=True)
    _check_names("custom", custom, lambda n: n in EFFECTS and getattr(EFFECTS[n], "custom", False),
                 "a custom effect registered from an effects file (twin.effects.custom.load_effects_file)")
    for name, value in shares.items():
        if not is_finite_number(value) or not 0.0 < value <= 1.0:
            raise InputError(SOURCE, name, f"expected a share above 0 and at most 1, got {describe(value)}")
    if not is_finite_number(bic_margin) or bic_margin < 0:
        raise InputError(SOURCE, "bic_margin", f"expected a finite number of BIC units >= 0, got {describe(bic_margin)}")
    for name, value in counts.items():
        if not is_whole(value) or value < 1:
            raise InputError(SOURCE, name, f"expected an integer >= 1, got {describe(value)}")
    for name, value in resolutions.items():
        if value is not None:
            check_resolution(machine, value, SOURCE, name)
    for name, value in (flags or {}).items():
        check_flag(value, SOURCE, name)
    check_progress(progress, SOURCE)
    if model_error is not None and (not isinstance(model_error, (list, tuple)) or len(model_error) != len(measurements)):
        raise InputError(SOURCE, "model_error", f"expected one per-channel array per measurement ({len(measurements)}), "
                                                f"got {describe(model_error)}")
    return list(measurements)


def check_model_error(value, channels: list[str], label: str) -> np.ndarray:
    """A measurement's model-error estimate: one finite value >= 0 per channel of the diagnosis
    (``channels``, in their order), in the channels' units."""
    try:
        e = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        e = None
    if e is None or e.shape != (len(channels),):
        got = describe(value) if e is None else f"{e.size} value{'s' * (e.size != 1)} (shape {e.shape})"
        raise InputError(label, "model_error", f"expected {len(channels)} values, one per channel "
                                               f"({', '.join(channels[:4])}{' ...' if len(channels) > 4 else ''}), "
                                               f"got {got}")
    bad = np.flatnonzero(~np.isfinite(e) | (e < 0))
    if bad.size:
        raise InputError(label, f"model_error[{bad[0]}]", f"{channels[bad[0]]}: expected a finite value >= 0, got "
                                                          f"{e[bad[0]]:g}")
    return e


def _check_names(argument: str, names, known, what: str, allow_none: bool = False) -> None:
    """``names``: a list or tuple of texts each ``known`` (None too when ``allow_none``)."""
    if names is None and allow_none:
        return
    if isinstance(names, str) or not isinstance(names, (list, tuple)):
        raise InputError(SOURCE, argument, f"expected a list of names, got {describe(names)}"
                                           + (f": write [{names!r}]" if isinstance(names, str) else ""))
    for i, name in enumerate(names):
        if not isinstance(name, str) or not known(name):
            raise InputError(SOURCE, f"{argument}[{i}]", f"{describe(name)} is not {what}")
        if name in names[:i]:        # tried twice, it split the BIC weights between its copies
            raise InputError(SOURCE, f"{argument}[{i}]", f"{name!r} is named twice; name each once")
