"""Shared fixtures: small single-box bodies for physics checks against closed-form answers."""

from __future__ import annotations

import numpy as np
import pytest

from geometries.base import Box, Machine, Part, Surface
from geometries.materials import MATERIALS
from twin.fem.mesh import mesh_machine


def pytest_addoption(parser):
    parser.addoption("--solver", default=None, choices=["auto", "direct", "iterative", "rom"],
                     help="force the solver of every twin built without an explicit one (e.g. run the "
                          "hidden-effect tests with --solver iterative)")


def pytest_configure(config):
    forced = config.getoption("--solver")
    if forced:
        from twin.physics import options
        options.DEFAULT["solver"] = forced


def box_body(size, spacing, material="steel", surfaces=(), refine=1.0):
    """A one-part machine: a box [0, size] [m] meshed with cubes no wider than ``spacing`` [m]
    (times the part's ``refine``).

    ``surfaces``: (name, Box-within) pairs of exterior faces to name.
    """
    size = np.asarray(size, dtype=float)
    part = Part("body", MATERIALS[material], (Box((0.0, 0.0, 0.0), tuple(size)),), refine=refine)
    named = [Surface(name, ("body",), within=within) for name, within in surfaces]
    m = Machine("box", [part], named, [], [], "", "", [], {"test": spacing})
    return mesh_machine(m, "test")


def face(axis: int, value: float) -> Box:
    """A thin box selecting the exterior faces at coordinate ``value`` along ``axis``."""
    lo, hi = [-10.0] * 3, [10.0] * 3
    lo[axis], hi[axis] = value - 1e-6, value + 1e-6
    return Box(tuple(lo), tuple(hi))


@pytest.fixture(autouse=True)
def _custom_effects_stay_in_their_test():
    """A custom effect a test registers (an effects file read in-process) is removed after that
    test: the registry (twin.effects.EFFECTS) is global, and a later test looping over every effect
    met it (test_effect_registry failed on 'pump' when it ran after test_prepared_run_args)."""
    from twin.effects.custom import CUSTOM, unregister_custom

    before = set(CUSTOM)
    yield
    unregister_custom([name for name in list(CUSTOM) if name not in before])


@pytest.fixture
def make_box():
    return box_body


@pytest.fixture(scope="session")
def machine_coarse_run():
    """The C-frame VMC, default effects, duty-cycle scenario, coarse mesh (shared by tests)."""
    from geometries import build_machine
    from twin.scenario import load_scenario
    from twin.simulate import run

    return run(build_machine("cframe-vmc"), load_scenario("spindle-duty-cycle"), resolution="coarse")


@pytest.fixture(scope="session")
def machine():
    """The C-frame VMC (built once for the session)."""
    from geometries import build_machine

    return build_machine("cframe-vmc")


@pytest.fixture(scope="session")
def mm(machine):
    """The C-frame VMC's coarse mesh (tests may override ``mm`` with their own)."""
    return mesh_machine(machine, "coarse")


@pytest.fixture(scope="session")
def heat(mm):
    """The heat matrices of :func:`mm` (assembled once for the session)."""
    from twin.fem.assembly import assemble_heat

    return assemble_heat(mm)
