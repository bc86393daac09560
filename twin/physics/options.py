"""Which linear solvers a prepared twin uses, as one checked value: :class:`SolverOptions`.

The solver (``auto``: direct factorisation up to :data:`DIRECT_LIMIT` temperature dofs,
iterative above; ``direct``, ``iterative`` or the reduced model ``rom``), the device of the
iterative heat step, how its steps start, the verified tolerance ``heat_tol`` [K] of the
iterative heat steps (:mod:`twin.physics.solvers`), the elastic solver's relative tolerance,
the reduced model's order and the coarsening of the elastic mesh. Every value is checked when the
options are made (:class:`twin.errors.InputError` naming the command-line option), and options
that would do nothing in the run asked for are refused.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from twin.errors import InputError, describe
from twin.limits import is_finite_number, is_number, is_whole
from twin.units import UnitError, parse_quantity

SOLVERS = ("auto", "direct", "iterative", "rom")
DEVICES = ("cpu", "gpu")
HEAT_STARTS = ("auto", "projection", "reduced")
REDUCED_START_STEPS = 300   # "auto" starts the iterative heat steps from the reduced basis from this many steps
MAX_ELASTIC_COARSENING = 8  # the widest spacing of the elastic mesh's grid lines, in temperature cells
DIRECT_LIMIT = 30_000       # temperature dofs up to which "auto" factorises (the default mesh: 15.6 k)
MIN_ROM_ORDER = 2           # the reduced model's smallest basis (a model may need more: three blocks of moments)
MAX_ROM_ORDER = 500         # its largest: the basis is nodes x order, the bound's Gram matrix (order x films)^2
ROM_ORDER = 48              # the default basis per reference operator: one operator when a run's films hold, two
                            # (their extremes) when they vary, each then given the depth of moments one alone gets
                            # (spindle-heat-cool-9000, coarse: 48 in all left Y 3.2 % off, 96 0.046 %)


@dataclass(frozen=True)
class SolverOptions:
    """What solves the linear systems of a prepared twin.

    ``solver``: auto (direct up to :data:`DIRECT_LIMIT` temperature dofs, iterative above), direct,
    iterative or rom (the reduced model, :mod:`twin.physics.rom`). ``device``: cpu or gpu (the
    iterative heat step on a GPU with CuPy). ``heat_tol`` [K]: bound on the capacity-weighted RMS
    temperature error the iterative heat solver may add over a run (module docstring): a number
    in K or a text with its unit (``"1e-4 K"``), finite and positive. ``elastic_rtol``: relative
    residual of the iterative elastic adjoint solves, between 0 and 1. ``max_iterations``: CG
    iterations a heat step may take (at least 1). ``rom_order``: the reduced model's basis size
    (:mod:`twin.physics.rom`), a whole number from :data:`MIN_ROM_ORDER` to :data:`MAX_ROM_ORDER`;
    None (the default): :data:`ROM_ORDER` per reference operator, 48 for a run whose films hold,
    96 for one whose films vary.
    Every value is checked here (:class:`twin.errors.InputError` naming it), before any work. ``elastic_coarsening``: solve the
    elasticity on every n-th grid line of the temperature mesh (:mod:`twin.fem.nesting`; 1: the
    same mesh), the thermal load still integrated on the temperature mesh's cells. ``heat_start``:
    how each iterative heat step starts: from the projection on the last solutions
    (:class:`Projection`), from the extrapolation 2 T^n - T^(n-1) corrected on the reduced basis
    (:class:`twin.physics.steppers.ReducedStart`, the basis built once per load set as for ``rom``,
    its solves to :data:`twin.physics.rom.START_BASIS_RTOL`), or auto (the reduced basis for runs
    of at least :data:`REDUCED_START_STEPS` steps, where its offline cost pays back).
    """

    solver: str = "auto"
    device: str = "cpu"
    heat_tol: float = 1e-6
    elastic_rtol: float = 1e-8
    rom_order: int | None = None
    max_iterations: int = 2000
    elastic_coarsening: int = 1
    heat_start: str = "auto"

    def __post_init__(self):
        if self.solver not in SOLVERS:
            raise InputError("command line", "--solver", f"unknown solver {self.solver!r}; known: {', '.join(SOLVERS)}")
        if self.device not in DEVICES:
            raise InputError("command line", "--device", f"unknown device {self.device!r}; known: {', '.join(DEVICES)}")
        if self.heat_start not in HEAT_STARTS:
            raise InputError("command line", "--heat-start",
                             f"unknown heat start {self.heat_start!r}; known: {', '.join(HEAT_STARTS)}")
        if self.heat_start != "auto" and self.solver in ("direct", "rom"):
            raise InputError("command line", "--heat-start", f"starts iterative heat steps; --solver {self.solver} has "
                                                             "none: leave --heat-start out, or use --solver iterative")
        if self.device == "gpu" and self.solver in ("direct", "rom"):
            raise InputError("command line", "--device", f"the GPU path is the full-order iterative heat step, not the "
                             f"{'direct solver' if self.solver == 'direct' else 'reduced model (it runs on the CPU)'}: "
                             f"use --solver iterative or auto with --device gpu")
        checked = {"heat_tol": _heat_tol(self.heat_tol), "elastic_rtol": _fraction(self.elastic_rtol, "elastic_rtol"),
                   "max_iterations": _whole(self.max_iterations, "max_iterations", 1, None, "iterations"),
                   "rom_order": None if self.rom_order is None else
                   _whole(self.rom_order, "--rom-order", MIN_ROM_ORDER, MAX_ROM_ORDER, "basis vectors")}
        for key, value in checked.items():     # frozen: the checked values replace the given ones once
            object.__setattr__(self, key, value)
        for key in UNUSED.get(self.solver, ()):   # a value the solver never reads would be ignored silently
            if getattr(self, key) != _DEFAULTS[key]:
                raise InputError("command line", OPTION[key], f"does nothing with --solver {self.solver}: leave it out "
                                                              "(or choose the solver that uses it)")
        if not is_whole(self.elastic_coarsening) or not 1 <= self.elastic_coarsening <= MAX_ELASTIC_COARSENING:
            raise InputError("command line", "--elastic-coarsening",
                             f"must be a whole number from 1 (the temperature mesh) to {MAX_ELASTIC_COARSENING} (beyond, "
                             f"the elastic mesh keeps little but the parts' faces), got {self.elastic_coarsening!r}")

    def reduced_start(self, nsteps: int) -> bool:
        """Whether a full-order iterative run of ``nsteps`` steps starts its steps from the reduced basis."""
        return self.heat_start == "reduced" or (self.heat_start == "auto" and nsteps >= REDUCED_START_STEPS)

    def resolve(self, nheat: int) -> str:
        """The full-order method for a layout of ``nheat`` temperature dofs: direct or iterative."""
        if self.solver in ("direct", "iterative"):
            return self.solver
        if self.device == "gpu":
            return "iterative"
        method = "direct" if nheat <= DIRECT_LIMIT else "iterative"
        if method == "direct" and self.heat_start != "auto" and self.solver == "auto":
            raise InputError("command line", "--heat-start", f"starts iterative heat steps; --solver auto factorises "
                                                             f"this mesh ({nheat} temperature nodes, up to "
                                                             f"{DIRECT_LIMIT} direct): add --solver iterative")
        return method


def _heat_tol(value) -> float:
    """``heat_tol`` [K]: a number (in K) or a quantity text (``"1e-4 K"``), finite and positive."""
    if isinstance(value, str):
        try:
            value = parse_quantity(value, "temperature_difference")
        except UnitError as err:
            raise InputError("command line", "--heat-tol", str(err)) from None
    if not is_finite_number(value) or not value > 0:
        raise InputError("command line", "--heat-tol", f"a temperature difference in K (a number, or a text like "
                                                       f"'1e-6 K'), finite and positive, got {value!r}")
    return float(value)


def _fraction(value, field: str) -> float:
    """A relative tolerance: a number strictly between 0 and 1."""
    if not is_number(value) or not 0 < value < 1:
        raise InputError("command line", field, f"a relative residual, a number greater than 0 and less than 1, "
                                                f"got {value!r}")
    return float(value)


def _whole(value, field: str, lower: int, upper: int | None, what: str) -> int:
    """A whole number of ``what`` from ``lower`` to ``upper`` (None: no upper limit)."""
    if not is_whole(value) or value < lower or (upper is not None and value > upper):
        span = f"from {lower} to {upper}" if upper is not None else f"at least {lower}"
        raise InputError("command line", field, f"a whole number of {what} {span}, got {value!r}")
    return int(value)


DEFAULT = {"solver": "auto"}   # what None means; the test suite's --solver option changes it
# what each solver never reads (the direct factorisation has no tolerance, iterations or basis; the
# reduced model no heat-step tolerance or iterations), and the options that set them
UNUSED = {"direct": ("heat_tol", "max_iterations", "rom_order"), "rom": ("heat_tol", "max_iterations")}
OPTION = {"heat_tol": "--heat-tol", "max_iterations": "max_iterations", "rom_order": "--rom-order"}
_DEFAULTS = {f.name: f.default for f in fields(SolverOptions)}


def as_options(solver) -> SolverOptions:
    """A :class:`SolverOptions` from itself, a solver name or None (``DEFAULT``: auto)."""
    if isinstance(solver, SolverOptions):
        return solver
    if solver is not None and not isinstance(solver, str):    # 0, False, [] read as "auto" before
        raise InputError("command line", "--solver", f"expected a solver name ({', '.join(SOLVERS)}) or "
                                                     f"twin.physics.options.SolverOptions, got {describe(solver)}")
    return SolverOptions(DEFAULT["solver"] if solver is None else solver)
