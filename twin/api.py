"""One-call entry points for library users (the CLI uses them too)."""

from __future__ import annotations

from os import PathLike

from geometries import MACHINES, build_machine
from geometries.base import Point  # noqa: F401 (re-exported: sensors are Points)
from twin import limits
from twin.errors import InputError, describe
from twin.fem.mesh import mesh_machine
from twin.io.results import to_dataset
from twin.model import ModelSpec, model_spec
from twin.motion import machine_for
from twin.observe import standard_observers
from twin.observe.camera import CameraConfig
from twin.observe.interferometer import LaserInterferometer, check_interferometer
from twin.observe.probing import DatumProbing, check_probing
from twin.observe.temperature import check_points
from twin.observe.camera import cameras as camera_observers
from twin.physics.part_materials import part_materials
from twin.physics.prepared import PreparedTwin, check_prepared  # noqa: F401 (PreparedTwin re-exported)
from twin.physics.prepared_args import check_beside_prepared, check_resolution
from twin.physics.options import as_options
from twin.scenario import Scenario, load_scenario
from twin.simulate import RunResult, run


CLI = "command line"   # the source named in errors about the arguments (the CLI's, and Python's alike)


def machine_by_name(name: str, field: str = "machine"):
    """Build a registered machine; unknown names raise InputError naming ``field`` (the argument
    or option that gave the name: ``machine``, ``--machine``)."""
    if not isinstance(name, str):
        hint = f" (pass its name, {name.name!r})" if isinstance(getattr(name, "name", None), str) else ""
        raise InputError("command line", field, f"expected a machine's name, got {describe(name)}{hint}")
    if name not in MACHINES:
        raise InputError("command line", field, f"unknown machine {name!r}; known: {', '.join(sorted(MACHINES))}")
    return build_machine(name)


def model_from_options(machine, effects: str | None = None, settings: list[str] | None = None,
                       effects_file: str | None = None) -> ModelSpec:
    """The model of the built ``machine`` from the command line's model options: ``--effects``,
    ``--set`` and the custom effects of ``--effects-file`` (registered, and always on:
    ``+name`` of one is accepted, ``-name`` refused with the reason)."""
    extra = ()
    if effects_file is not None:       # "" or 0 was no effects file, silently
        from twin.effects.custom import load_effects_file
        extra = tuple(load_effects_file(effects_file, machine))
    return model_spec(machine, effects, settings, extra)


def simulate(machine: str, scenario: str | Scenario, effects: str | None = None, settings: list[str] | None = None,
             resolution: str | None = None, seed: int = 0, theta: float = 0.5, progress=None,
             sensors: list | None = None, materials: dict | None = None, solver=None,
             cameras: list | None = None, effects_file: str | None = None, prepared=None) -> tuple:
    """Simulate by names; returns (Dataset, RunResult). ``effects`` edits the machine's default
    set (``"+a,-b"``) or replaces it (``"a,b"``), one text; ``settings`` a list of
    ``"effect.param=VALUE UNIT"`` texts; the effects of ``effects_file`` (a TOML file
    of custom effects, :mod:`twin.effects.custom`) are registered and switched on as well;
    ``resolution`` a mesh name of the machine (default ``"default"``); ``seed`` an integer from 0
    to 2**32 - 1; ``theta`` the time scheme's, from 0.5 (Crank-Nicolson) to 1 (implicit Euler);
    ``sensors`` :class:`geometries.base.Point` s with distinct names, each on its part (or in the
    air); ``materials`` material name -> :class:`geometries.materials.Material` for materials the
    machine is made of; ``solver``: a :class:`twin.physics.options.SolverOptions` or a solver name
    (default: chosen by size); ``cameras`` (pose names or :class:`twin.observe.camera.CameraConfig`)
    add thermal cameras to those of the scenario; ``prepared``: a
    :class:`twin.physics.prepared.PreparedTwin` of this machine to reuse: its mesh, materials and
    solver are the run's, so ``resolution``, ``materials`` and ``solver`` are left out or equal
    to its own (anything else is refused, never ignored), and the result's attributes name them.
    Everything is checked before the run starts (:class:`twin.errors.InputError` naming the
    argument): names, types, units, the scenario's values and speeds against the machine's
    maximum, the sensors' positions and the run's size (:mod:`twin.limits`)."""
    seed = limits.seed_value(seed, CLI, "seed")
    theta = limits.theta_value(theta, CLI)
    limits.check_progress(progress, CLI)
    m = machine_by_name(machine)
    if prepared is not None:
        check_prepared(prepared, m, CLI)
        check_beside_prepared(prepared, CLI, resolution=resolution, fields={"resolution": "--mesh"})
        resolution = prepared.resolution
    else:
        resolution = check_resolution(m, "default" if resolution is None else resolution, CLI, "--mesh")
    if not isinstance(scenario, (Scenario, str, PathLike)):
        raise InputError(CLI, "scenario", f"expected a scenario name, a path to a .toml file or a twin.scenario.Scenario, "
                                          f"got {scenario!r}")
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    sc.check()          # one built or changed in Python meets the loader's checks (again in check_scenario)
    m = machine_for(m, sc)
    if prepared is not None and [p.name for p in prepared.machine.parts] != [p.name for p in m.parts]:
        raise InputError(CLI, "prepared", f"the prepared twin's machine has the parts "
                                          f"{', '.join(p.name for p in prepared.machine.parts)}; scenario {sc.name} "
                                          f"runs on {', '.join(p.name for p in m.parts)} (the feed drives of its axes): "
                                          "prepare the twin with twin.motion.machine_for(machine, scenario)")
    spec = model_from_options(m, effects, settings, effects_file)
    limits.check_scenario(sc, m)
    part_materials(m, materials, CLI, "materials")      # checked before the mesh is built
    options = as_options(solver)
    if prepared is not None:
        check_beside_prepared(prepared, CLI, materials=materials, solver=solver, fields={"solver": "--solver"})
    _check_sensors(sensors, m)
    if cameras is not None and (isinstance(cameras, str) or not isinstance(cameras, (list, tuple))):
        raise InputError(CLI, "cameras", f"expected a list of pose names or CameraConfig, got {cameras!r}"
                                         + (f": write [{cameras!r}]" if isinstance(cameras, str) else ""))
    configs = list(sc.cameras) + [c if isinstance(c, CameraConfig) else CameraConfig(pose=c) for c in cameras or ()]
    for c in configs:
        c.check(sc)
    if sc.interferometer is not None:
        check_interferometer(sc.interferometer, sc, m)
    if sc.probing is not None:
        check_probing(sc.probing, sc, m)
    # the observers (a camera's pose in the air, the instruments' places) before the mesh is built
    observers = standard_observers(m, sensors) + camera_observers(m, configs) if configs else None
    if sc.interferometer is not None:
        observers = (observers or standard_observers(m, sensors)) + [LaserInterferometer(sc.interferometer, m)]
    if sc.probing is not None:
        observers = (observers or standard_observers(m, sensors)) + [DatumProbing(sc.probing, m)]
    mm = prepared.mm if prepared is not None else mesh_machine(m, resolution)
    limits.check_run_size(sc, mm.nheat)
    beside = {"prepared": prepared} if prepared is not None else {"mm": mm, "materials": materials, "solver": options}
    result: RunResult = run(m, sc, spec, theta=theta, progress=progress, sensors=sensors, observers=observers,
                            **beside)
    return to_dataset(result, seed, resolution), result


def _check_sensors(sensors, machine) -> None:
    """``sensors``: None (the machine's sites) or points :func:`twin.observe.temperature.check_points`
    takes (the arguments' source: the command line)."""
    if sensors is not None:
        check_points(sensors, machine, CLI, "sensors")
