"""One-call entry points for library users (the CLI uses them too)."""

from __future__ import annotations

from geometries import MACHINES, build_machine
from twin.errors import InputError
from twin.model import ModelSpec, parse_effects, parse_settings
from twin.io.results import to_dataset
from twin.scenario import Scenario, load_scenario
from twin.simulate import RunResult, run


def machine_by_name(name: str):
    """Build a registered machine; unknown names raise InputError."""
    if name not in MACHINES:
        raise InputError("command line", "machine", f"unknown machine {name!r}; known: {', '.join(sorted(MACHINES))}")
    return build_machine(name)


def model_spec(effects: str | None = None, settings: list[str] | None = None) -> ModelSpec:
    """ModelSpec from CLI-style strings: ``effects="+a,-b"``, ``settings=["a.p=3 W"]``."""
    chosen = parse_effects(effects)
    return ModelSpec(chosen, parse_settings(settings, chosen))


def simulate(machine: str, scenario: str | Scenario, effects: str | None = None, settings: list[str] | None = None,
             resolution: str = "default", seed: int = 0, theta: float = 0.5, progress=None,
             sensors: list | None = None, materials: dict | None = None) -> tuple:
    """Simulate by names; returns (Dataset, RunResult)."""
    m = machine_by_name(machine)
    if resolution not in m.resolutions:
        raise InputError("command line", "--mesh", f"unknown resolution {resolution!r}; known: {', '.join(m.resolutions)}")
    sc = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
    spec = model_spec(effects, settings)
    result: RunResult = run(m, sc, spec, resolution, theta, materials=materials, progress=progress, sensors=sensors)
    return to_dataset(result, seed, resolution), result
