"""One-call entry points for library users (the CLI uses them too)."""

from __future__ import annotations

from geometries import MACHINES, build_machine
from twin import limits
from twin.errors import InputError
from twin.fem.mesh import mesh_machine
from twin.io.results import to_dataset
from twin.model import ModelSpec, model_spec
from twin.motion import machine_for
from twin.observe import standard_observers
from twin.observe.camera import CameraConfig
from twin.observe.interferometer import LaserInterferometer, check_interferometer
from twin.observe.probing import DatumProbing, check_probing
from twin.observe.camera import cameras as camera_observers
from twin.scenario import Scenario, load_scenario
from twin.simulate import RunResult, run


def machine_by_name(name: str):
    """Build a registered machine; unknown names raise InputError."""
    if name not in MACHINES:
        raise InputError("command line", "machine", f"unknown machine {name!r}; known: {', '.join(sorted(MACHINES))}")
    return build_machine(name)


def simulate(machine: str, scenario: str | Scenario, effects: str | None = None, settings: list[str] | None = None,
             resolution: str = "default", seed: int = 0, theta: float = 0.5, progress=None,
             sensors: list | None = None, materials: dict | None = None, solver=None,
             cameras: list | None = None, effects_file: str | None = None, prepared=None) -> tuple:
    """Simulate by names; returns (Dataset, RunResult). ``effects`` edits the machine's default
    set (``"+a,-b"``) or replaces it (``"a,b"``); the effects of ``effects_file`` (a TOML file
    of custom effects, :mod:`twin.effects.custom`) are registered and switched on as well;
    ``solver``: a :class:`twin.physics.solvers.SolverOptions` or a solver name (default: chosen
    by size); ``cameras`` (pose names or :class:`twin.observe.camera.CameraConfig`) add thermal
    cameras to those of the scenario; ``prepared``: a :class:`twin.physics.prepared.PreparedTwin`
    of the machine on ``resolution`` (with ``materials``) to reuse. Everything is checked before
    the run starts: names, units, the scenario's speeds against the machine's maximum and the
    run's size (:mod:`twin.limits`)."""
    m = machine_by_name(machine)
    if resolution not in m.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {resolution!r}; known: {', '.join(m.resolutions)}")
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    m = machine_for(m, sc)
    extra = ()
    if effects_file:
        from twin.effects.custom import load_effects_file
        extra = tuple(load_effects_file(effects_file, m))
    spec: ModelSpec = model_spec(m, effects, settings, extra)
    limits.check_scenario(sc, m)
    configs = list(sc.cameras) + [c if isinstance(c, CameraConfig) else CameraConfig(pose=c) for c in cameras or ()]
    for c in configs:
        c.check(sc)
    mm = prepared.mm if prepared is not None else mesh_machine(m, resolution)
    limits.check_run_size(sc, mm.nheat)
    observers = standard_observers(m, sensors) + camera_observers(m, configs) if configs else None
    if sc.interferometer is not None:
        check_interferometer(sc.interferometer, sc, m)
        observers = (observers or standard_observers(m, sensors)) + [LaserInterferometer(sc.interferometer, m)]
    if sc.probing is not None:
        check_probing(sc.probing, sc, m)
        observers = (observers or standard_observers(m, sensors)) + [DatumProbing(sc.probing, m)]
    result: RunResult = run(m, sc, spec, theta=theta, materials=materials, progress=progress, sensors=sensors,
                            mm=None if prepared is not None else mm, prepared=prepared, solver=solver,
                            observers=observers)
    return to_dataset(result, seed, resolution), result
