"""Command-line options shared by every command that builds a model or reads a measurement, and
the declaration of a command's files before its work starts (:class:`twin.io.paths.Files`)."""

from __future__ import annotations

import argparse

from twin import limits


def seed(text: str) -> int:
    """argparse type of ``--seed``: an integer from 0 to 2**32 - 1 (:func:`twin.limits.check_seed`)."""
    try:
        return limits.check_seed(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def positive_quantity_value(text: str, dimension: str, field: str) -> float:
    """``text``, a positive quantity with its unit (``"60 s"``, ``"20mm"``; :func:`twin.units.
    parse_quantity`), in SI units; else :class:`twin.errors.InputError` on the option ``field``."""
    from twin.errors import InputError
    from twin.units import UnitError, parse_quantity

    try:
        value = parse_quantity(text, dimension)
    except UnitError as err:
        raise InputError("command line", field, str(err)) from None
    if not value > 0:
        raise InputError("command line", field, f"must be positive, got {text!r}")
    return value


def positive_quantity(dimension: str):
    """argparse type of a positive quantity with its unit (:func:`positive_quantity_value`)."""
    from twin.errors import InputError

    def parse(text: str) -> float:
        try:
            return positive_quantity_value(text, dimension, "")
        except InputError as err:
            raise argparse.ArgumentTypeError(err.message) from None
    return parse


def whole_number(what: str, lower: int = 0, upper: int | None = None):
    """argparse type of an integer option counting ``what`` (workers, cases, segments), from
    ``lower`` to ``upper`` (no upper limit: None)."""
    def parse(text: str) -> int:
        try:
            n = limits.plain_int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number of {what}, got {text!r}") from None
        if upper is not None and not lower <= n <= upper:
            raise argparse.ArgumentTypeError(f"must be from {lower} to {upper}, got {n}")
        if n < lower:
            raise argparse.ArgumentTypeError(f"must not be negative, got {n}" if lower == 0 else
                                             f"must be at least {lower}, got {n}")
        return n
    return parse


def add_seed_option(p: argparse.ArgumentParser, help: str = "seed of the instrument noise") -> None:
    """--seed N (0 to 2**32 - 1, default 0)."""
    p.add_argument("--seed", type=seed, default=0, help=f"{help} (0 to 2**32-1, default 0)")


def add_model_options(p: argparse.ArgumentParser, mesh_default: str = "default", mesh_help: str = "mesh resolution",
                      effects_help: str = "+name,-name to change the default set (write --effects=-name when it "
                                          "starts with -), or a,b,c for an exact set", solvers: bool = False,
                      seed: bool = True) -> None:
    """--effects, --set, --mesh, --seed (unless ``seed`` is False: a command whose model runs
    carry no instrument noise, where a seed would change nothing); with ``solvers`` also
    --solver and --device (for the commands that pass them on: :func:`solver_options`)."""
    p.add_argument("--effects", help=effects_help)
    p.add_argument("--set", action="append", default=[], metavar="EFFECT.PARAM=VALUE",
                   help="set a parameter with its unit, e.g. spindle_motor.power=120W (repeatable, once per parameter)")
    p.add_argument("--mesh", default=mesh_default, choices=["coarse", "default", "fine"],
                   help=f"{mesh_help} (default {mesh_default})")
    if seed:
        add_seed_option(p)
    p.add_argument("--effects-file", metavar="FILE",
                   help="TOML file of effects the library lacks (twin.effects.custom): simulate and compare switch "
                        "them on, diagnose offers them as candidates")
    if solvers:
        p.add_argument("--solver", default="auto", choices=["auto", "direct", "iterative", "rom"],
                       help="linear solvers: auto (direct factorisation up to 30k nodes, iterative above), "
                            "direct, iterative (PCG heat steps, AMG-CG elastic adjoints) or rom (reduced model "
                            "with its error reported per output); default auto")
        p.add_argument("--device", default="cpu", choices=["cpu", "gpu"],
                       help="gpu: the iterative heat step on a CUDA GPU with CuPy (optional); default cpu")
        p.add_argument("--heat-start", default="auto", choices=["auto", "projection", "reduced"],
                       help="how each iterative heat step starts: from the projection on the last solutions, or "
                            "from the reduced model's basis (built once: pays back on long runs); default auto "
                            "(the reduced basis from 300 steps)")
        # bounds: twin.physics.options.MIN_ROM_ORDER / MAX_ROM_ORDER, checked by SolverOptions
        p.add_argument("--rom-order", type=whole_number("basis vectors", lower=1), default=None, metavar="R",
                       help="with --solver rom: the reduced model's basis size (default 48); the result reports "
                            "each output's estimated error, raise R where it is too large")
        # upper: twin.physics.options.MAX_ELASTIC_COARSENING (not imported here: the parser stays light)
        p.add_argument("--elastic-coarsening", type=whole_number("grid lines", lower=1, upper=8), default=1, metavar="N",
                       help="solve the elasticity on every N-th grid line of the temperature mesh, the thermal load "
                            "still integrated on the temperature mesh (for large meshes: the drift is smooth); "
                            "1 to 8, default 1, the same mesh")


def solver_options(args):
    """The :class:`twin.physics.options.SolverOptions` of parsed --solver/--device/--heat-start/
    --elastic-coarsening/--rom-order (auto on the CPU, one mesh, for a command that does not offer
    them). --rom-order is refused beside any solver but rom: only the reduced model reports the
    error its order leaves (an iterative run's start basis changes its iterations, not its result)."""
    from twin.errors import InputError
    from twin.physics.options import SolverOptions

    solver, order = getattr(args, "solver", "auto"), getattr(args, "rom_order", None)
    if order is not None and solver != "rom":
        raise InputError("command line", "--rom-order", f"sets the reduced model's order; --solver {solver} runs no "
                                                        "reduced model: add --solver rom, or leave --rom-order out")
    return SolverOptions(solver, getattr(args, "device", "cpu"), elastic_coarsening=getattr(args, "elastic_coarsening", 1),
                         heat_start=getattr(args, "heat_start", "auto"), rom_order=order)


def add_measurement_options(p: argparse.ArgumentParser) -> None:
    """MEASUREMENT, --mapping, --machine, --scenario."""
    p.add_argument("measurement", help="a twin NetCDF result, or a CSV file with a TOML column mapping")
    p.add_argument("--mapping", help="TOML column mapping of a CSV (default: the CSV's name with .toml)")
    p.add_argument("--machine", help="the measured machine (default: the one the measurement names: a result's "
                                     "'machine' attribute or the mapping's machine key)")
    p.add_argument("--scenario", help="drive the twin by this scenario instead of the measured inputs")


def declare_effects_file(files, path: str) -> None:
    """Declare an ``--effects-file`` and the schedule tables it names as inputs of the command: no
    output of the command may replace them."""
    from twin.effects.custom import table_files

    files.input(path, "--effects-file", "effects file")
    for table, field in table_files(path):
        files.input(table, field, "schedule table")


def declare_scenario(files, scenario: str) -> None:
    """Declare the scenario's file (a bundled name's file, or the path) as an input of the command,
    and the room record its ambient reads (``kind = "csv"``, field ``ambient.file``): no output of
    the command may replace either."""
    from twin.scenario import load_scenario, scenario_path

    files.input(scenario_path(scenario), "scenario", "scenario file")
    room = load_scenario(scenario).ambient.file
    if room:
        files.input(room, "ambient.file", "room record")
