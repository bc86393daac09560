"""Synthetic "measurements" from a truth model made honestly different from the diagnosing model.

Truth = a model spec (e.g. the default effects plus one hidden effect) simulated

* on a finer mesh than the diagnosing model (``resolution``),
* with half the sample interval (a scenario copy with dt / 2, then every second sample kept),
* with cast-iron and steel properties perturbed by up to 5 % (conductivity, heat capacity,
  expansion; fixed factors so that runs are reproducible),
* through the instrument models with noise, quantisation and a small sensor bias
  (``temperature_sensor.bias``), seeded; the laser interferometer's positioning error (the twin's
  is noise-free) gets Gaussian noise of :data:`INTERFEROMETER_NOISE` per reading, seeded.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from twin.api import simulate
from geometries.materials import MATERIALS
from twin.errors import InputError, describe
from twin.limits import is_finite_number
from twin.scenario import Scenario

PERTURBED = {
    "grey_cast_iron": MATERIALS["grey_cast_iron"].scaled(conductivity=1.03, specific_heat=0.97, expansion=1.02),
    "steel": MATERIALS["steel"].scaled(conductivity=0.96, specific_heat=1.02, expansion=0.98),
}
INTERFEROMETER_NOISE = 0.1   # [um] per reading: plausible repeatability of an environment-compensated run
INSTRUMENT_SETTINGS = ["temperature_sensor.bias=0.03 K", "temperature_sensor.noise=0.05 K", "probe.noise=0.05 um"]


def short_scenario(sc: Scenario, factor: float) -> Scenario:
    """A copy of ``sc`` with every step ``factor`` times as long (rounded to the sample interval),
    the C axis's steps too; ``factor`` is a finite number > 0."""
    if not isinstance(sc, Scenario):
        raise InputError("short_scenario", "sc", f"expected a twin.scenario.Scenario, got {describe(sc)}")
    if not is_finite_number(factor) or factor <= 0:
        raise InputError("short_scenario", "factor", f"expected a finite number > 0, got {describe(factor)}")
    scale = lambda d: max(round(d * factor / sc.sample_interval), 1) * sc.sample_interval
    steps = tuple((scale(d), s) for d, s in sc.steps)
    c_axis = sc.c_axis
    if c_axis is not None:
        from twin.rotary import RotarySchedule
        c_axis = RotarySchedule(tuple((scale(d), n, duty) for d, n, duty in c_axis.steps))
    return replace(sc, steps=steps, c_axis=c_axis, name=f"{sc.name}-x{factor:g}")


def truth_twin(machine, resolution: str = "default", perturb: bool = True):
    """A prepared twin of the truth (``machine`` built, on ``resolution``, perturbed materials) to
    reuse for several truths of one machine."""
    from twin.physics.prepared import PreparedTwin
    return PreparedTwin(machine, resolution=resolution, materials=PERTURBED if perturb else None)


def truth_measurement(machine: str, scenario: Scenario, effects: str | None = None, settings: list[str] | None = None,
                      resolution: str = "default", seed: int = 1, perturb: bool = True, prepared=None):
    """Simulate the truth and return the measurement Dataset on ``scenario``'s time grid
    (``prepared``: a :func:`truth_twin` to reuse). ``settings`` (a list of ``--set`` texts) may
    set the instruments' bias and noise, which the truth otherwise takes from
    :data:`INSTRUMENT_SETTINGS`."""
    if isinstance(settings, str):
        raise InputError("command line", "--set", f"expected a list of 'effect.param=VALUE UNIT' texts, got the text "
                                                  f"{settings!r}: write [{settings!r}]")
    given = {str(t).split("=", 1)[0].strip() for t in settings or []}
    instruments = [t for t in INSTRUMENT_SETTINGS if t.split("=", 1)[0] not in given]   # the user's value wins
    fine = replace(scenario, sample_interval=scenario.sample_interval / 2)
    ds, _ = simulate(machine, fine, effects=effects, settings=list(settings or []) + instruments,
                     resolution=resolution, seed=seed, materials=PERTURBED if perturb else None, prepared=prepared)
    ds = ds.isel(time=slice(None, None, 2))
    if "positioning_error" in ds:
        pe = ds["positioning_error"]
        noise = INTERFEROMETER_NOISE * np.random.default_rng([seed, 230]).standard_normal(pe.shape)
        noise[0] = 0.0   # the cold run is the reference the others are taken from
        ds["positioning_error"] = pe.copy(data=pe.values + noise)
    return ds
