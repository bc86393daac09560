"""A machine prepared once for many runs: simulations, diagnoses, sweeps.

Prepared once per machine, mesh and materials (no scenario, no effect set): the mesh, the
conduction and capacity matrices, and on first use the factorised elastic stiffness. Cached as
runs need them:

* per displacement observer, the adjoint solution lam = K^-1 G^T of its functionals G, and per
  temperature layout its rows (C^T lam)^T (C the thermal coupling on that layout; a layout is the
  mesh's temperature dofs, split where a contact conductance asks for it);
* per layout, the heat matrices and every observer's rows;
* per operator (layout, convection loads, dt, theta, film coefficients), the factorisation of
  M + theta dt A (direct) or the operator and its diagonal (iterative), so a later run with the
  same operators only back-substitutes or iterates;
* per load set, the reduced model (``solver="rom"``, :mod:`twin.physics.rom`).

The solvers are chosen by size or by ``solver`` (:class:`twin.physics.options.SolverOptions`):
direct factorisations for small meshes, warm-started PCG for the heat steps and AMG-CG for the
elastic adjoints on large ones, or the reduced model. :attr:`PreparedTwin.run_info` holds what
solved the last run, its tolerances and the bound (iterative) or estimate (reduced) of every
output's error, for the result attributes.

A run with a scenario, a model spec and a list of observers then costs its load assembly and one
transient integration; the readings come back per observer (:mod:`twin.observe`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin import limits
from twin.errors import InputError
from twin.fem.assembly import assemble_heat, assemble_nested_coupling
from twin.fem.mesh import MachineMesh, mesh_machine
from twin.fem.nesting import coarsen
from twin.observe.base import Observer, error_units
from twin.physics.elastic import ElasticSolver
from twin.physics.heat import integrate, integrate_responses
from twin.physics.loads import LoadSet, build_loads, layout_key, source_pattern
from twin.physics.options import as_options
from twin.physics.part_materials import part_materials
from twin.physics.solvers import mass_weights, output_bounds

from twin.physics.prepared_args import SOURCE, check_resolution, mesh_label
from twin.physics.steppers import DirectStepper, IterativeStepper, ReducedStart
from twin.signals import load_instants


def check_prepared(prepared, machine, source: str, field: str = "prepared") -> None:
    """``prepared`` is a :class:`PreparedTwin` of ``machine`` (its name), or
    :class:`InputError` naming ``field``."""
    if not isinstance(prepared, PreparedTwin):
        raise InputError(source, field, f"expected a twin.physics.prepared.PreparedTwin, got {prepared!r}")
    if prepared.machine.name != machine.name:
        raise InputError(source, field, f"the prepared twin is of machine {prepared.machine.name}, not {machine.name}")


class PreparedTwin:
    """``machine`` meshed (``mm``, or ``resolution``) and assembled with ``materials`` (a map from
    material name to a replacement Material) once; :meth:`run` any scenario and effect set.
    ``solver``: a :class:`twin.physics.options.SolverOptions` or a solver name (default auto).
    The arguments are checked before the mesh is built (:class:`twin.errors.InputError`): a
    Machine (not its name), a resolution it has, materials it is made of (:func:`part_materials`).
    ``resolution`` (default ``"default"``) names the mesh to build; given with ``mm`` it must be
    the one ``mm`` was built at (never silently ignored). ``self.resolution`` records the mesh's
    name (:func:`mesh_label`)."""

    def __init__(self, machine, mm=None, resolution: str | None = None, materials: dict | None = None,
                 solver=None):
        limits.check_machine(machine, SOURCE)
        if mm is None:
            resolution = check_resolution(machine, "default" if resolution is None else resolution)
        elif not isinstance(mm, MachineMesh):
            raise InputError(SOURCE, "mm", f"expected a twin.fem.mesh.MachineMesh of the machine, got {mm!r}")
        elif mm.machine.name != machine.name or [p.name for p in mm.machine.parts] != [p.name for p in machine.parts]:
            raise InputError(SOURCE, "mm", f"is a mesh of {mm.machine.name} with the parts "
                                           f"{', '.join(p.name for p in mm.machine.parts)}, not of {machine.name} with "
                                           f"{', '.join(p.name for p in machine.parts)} (mesh the machine the twin is "
                                           "of: twin.fem.mesh.mesh_machine(machine, resolution))")
        elif resolution is not None and check_resolution(machine, resolution) != mesh_label(machine, mm):
            raise InputError(SOURCE, "resolution", f"is {resolution!r} but the mesh mm given with it is at "
                                                   f"{mesh_label(machine, mm)!r}: give the mesh or the resolution")
        materials = part_materials(machine, materials)
        self.machine = machine
        self.options = as_options(solver)
        self.mm = mm if mm is not None else mesh_machine(machine, resolution)
        self.resolution = mesh_label(machine, self.mm)
        self.materials = materials
        self.heat = assemble_heat(self.mm, self.materials)
        self._elastic = None
        self._nested = None
        self._heat_cache = {layout_key(self.mm): self.heat}
        self._adjoints: dict[tuple, np.ndarray] = {}
        self._couplings: dict[tuple, sp.csr_matrix] = {}
        self._rows: dict[tuple, sp.csr_matrix] = {}
        self.factorisations: dict[tuple, tuple] = {}
        self.reduced: dict[tuple, object] = {}
        self.method = self.options.resolve(self.mm.nheat)   # the full-order method: direct | iterative
        self.run_info: dict = {}
        self.prepare_s: dict = {}       # [s] the parts of the last run's preparation (:meth:`_prepare`)

    @property
    def elastic_mm(self):
        """The mesh the displacements live on: the temperature mesh, or every
        ``elastic_coarsening``-th line of it (:mod:`twin.fem.nesting`)."""
        if self._nested is None and self.options.elastic_coarsening > 1:
            self._nested = coarsen(self.mm, self.options.elastic_coarsening)
        return self.mm if self._nested is None else self._nested.coarse

    @property
    def elastic(self) -> ElasticSolver:
        """The factorised stiffness of the supported machine (built on first use)."""
        if self._elastic is None:
            method = "direct" if self.method == "direct" else "amg"
            self._elastic = ElasticSolver.build(self.elastic_mm, self.materials, method, self.options.elastic_rtol)
        return self._elastic

    def coupling(self, layout, material: str | None = None) -> sp.csr_matrix:
        """Thermal coupling C [N/K] from the temperature dofs of ``layout`` to the displacements;
        with ``material``, the coupling of that material's cells alone (every other expansion
        coefficient set to 0)."""
        key = (layout_key(layout), material)
        if key not in self._couplings:
            nested = self.elastic_mm is not self.mm
            if material is None and layout.nheat == self.mm.nheat and not nested:
                C = self.elastic.matrices.C
            else:
                parts = {p.name: self.materials.get(p.name, p.material) for p in self.machine.parts}
                if material is not None:
                    parts = {n: m if m.name == material else m.scaled(expansion=0.0) for n, m in parts.items()}
                C = assemble_nested_coupling(self._nested, layout, parts) if nested else ElasticSolver.coupling(layout, parts)
            self._couplings[key] = C
        return self._couplings[key]

    def adjoint(self, observer) -> np.ndarray:
        """lam = K^-1 G^T (3 n_nodes, k) of a displacement observer's functionals G on the elastic
        mesh, solved once (:meth:`adjoints`)."""
        self.adjoints([observer])
        return self._adjoints[observer.cache_key()]

    def adjoints(self, observers) -> None:
        """Solve the adjoints of every displacement observer among ``observers`` (those with
        ``functionals``) not solved yet, all of their rows as one block: an iterative elastic
        solver then advances them together (:class:`twin.physics.solvers.AmgElastic`), a
        factorised one back-substitutes each column as it would alone."""
        todo = {}
        for o in observers:
            key = o.cache_key() if hasattr(o, "functionals") else None
            if key is not None and key not in self._adjoints and key not in todo:
                todo[key] = o.all_functionals(self.elastic_mm)
        if not todo:
            return
        lam = self.elastic.solve(np.asarray(sp.vstack(list(todo.values())).todense()).T)
        ends = np.cumsum([G.shape[0] for G in todo.values()])
        for key, a, b in zip(todo, np.r_[0, ends[:-1]], ends):
            self._adjoints[key] = lam[:, a:b]

    def elastic_info(self) -> dict:
        """What solved the elasticity and on which mesh, for the result attributes."""
        if self._elastic is None:
            return {}
        return {**self._elastic.info(), "elastic_nodes": int(self.elastic_mm.nnodes),
                "elastic_coarsening": int(self.options.elastic_coarsening)}

    def displacement_rows(self, observer, layout, material: str | None = None) -> np.ndarray:
        """(k, n_heat) rows (C^T lam)^T of a displacement observer on ``layout`` (see
        :mod:`twin.observe.displacement`), lam from :meth:`adjoint`."""
        return np.asarray(self.coupling(layout, material).T @ self.adjoint(observer)).T

    def loads(self, scenario, spec) -> LoadSet:
        """The load set of ``spec`` for ``scenario`` on this mesh (heat matrices from the cache)."""
        return build_loads(self.mm, scenario, spec, self.heat, self.materials, self._heat_cache)

    def _rows_of(self, observer, loads) -> sp.csr_matrix:
        """The observer's rows on the layout of ``loads`` as a sparse matrix (cached per layout)."""
        key = (observer.cache_key(), layout_key(loads.mm))
        if observer.layout_cached and key in self._rows:
            return self._rows[key]
        rows = observer.rows(self, loads)
        rows = sp.csr_matrix((0, loads.mm.nheat)) if rows is None else sp.csr_matrix(rows)
        if observer.layout_cached:
            self._rows[key] = rows
        return rows

    def prepare(self, scenario, spec, observers, theta: float = 0.5) -> dict:
        """Build what :meth:`run` of these arguments needs before its first step (the elastic
        solver, the adjoints, the observers' rows, and the reduced basis of ``rom`` or of the
        reduced start), as :meth:`run` itself does (:meth:`_prepare`); the seconds each part took.
        The arguments are checked as :meth:`run` checks them."""
        self.check_run(scenario, theta)
        self.check_spec(spec, scenario)
        check_observers(observers, [scenario], self.machine)
        loads = self.loads(scenario, spec)
        times = scenario.times()
        h, _, _ = loads.signals(load_instants(times, theta))
        self._prepare(loads, observers, {o.key: o.sample_steps(times) for o in observers}, h, len(times) - 1)
        return dict(self.prepare_s)

    def _basis_task(self, loads, h, nsteps: int, bound: bool = True):
        """The reduced basis a run of ``nsteps`` steps needs, as a task (None when it needs none):
        the reduced model's (``rom``; with the verified bound's Gram matrix when ``bound``) or the
        reduced start's (:meth:`stepper`)."""
        from twin.physics import rom

        if self.options.solver == "rom":
            return lambda: rom.run_basis(self, loads, h, bound)
        if self.method == "iterative" and self.options.reduced_start(nsteps):
            return lambda: rom.start_basis(self, loads, h)
        return None

    def _prepare(self, loads, observers, steps: dict, h, nsteps: int, bound: bool = True):
        """((outputs, bounds) of the observers read every step, [(observer, rows)] of those read
        at ``steps``) and the run's reduced basis, cached. On a large layout
        (:data:`twin.physics.parallel.CONCURRENT_FROM`) the two are built concurrently: the
        elastic chain (assembly, multigrid, adjoints, rows) beside the heat basis, which need
        nothing of each other (:func:`twin.physics.parallel.concurrently`; the same numbers as
        one after the other), the basis in this thread and the shorter elastic chain on the
        helper, so that once the chain is done the basis's multigrid cycles take both cores
        (:func:`twin.physics.solvers.amg_cycle`). ``prepare_s`` records the seconds of each part; ``bound``: the
        reduced model's verified bound will be computed (its Gram matrix is part of the basis)."""
        import time

        from twin.physics import parallel

        times = {}

        def rows():
            t0 = time.perf_counter()
            if any(hasattr(o, "functionals") for o in observers):
                self.elastic
                times["elastic_assembly"] = time.perf_counter() - t0
                self.adjoints(observers)
                times["adjoints"] = time.perf_counter() - t0 - times["elastic_assembly"]
            t1 = time.perf_counter()
            dense = self.output_rows([o for o in observers if steps[o.key] is None], loads)
            sampled = [(o, self._rows_of(o, loads)) for o in observers if steps[o.key] is not None]
            times["rows"] = time.perf_counter() - t1
            return dense, sampled

        def basis():
            t0 = time.perf_counter()
            task()
            times["basis"] = time.perf_counter() - t0

        task = self._basis_task(loads, h, nsteps, bound)
        t0 = time.perf_counter()
        together = task is not None and loads.mm.nheat >= parallel.CONCURRENT_FROM
        if together:
            result = parallel.concurrently(basis, rows)[1]      # the basis here: its cycles split once rows are done
        else:
            result = rows()
            if task is not None:
                basis()
        self.prepare_s = {**times, "wall": time.perf_counter() - t0, "concurrent": together and parallel.threads() > 1}
        return result

    def stepper(self, loads=None, h: np.ndarray | None = None, nsteps: int = 0):
        """The full-order heat stepper of this twin (its caches persist across runs). For a run of
        ``nsteps`` steps of ``loads`` with film coefficients ``h``, an iterative stepper starts
        its steps from the reduced basis when the options say so (``heat_start``;
        :class:`twin.physics.steppers.ReducedStart`; the basis is the reduced model's, cached)."""
        if self.method == "direct":
            return DirectStepper(self.factorisations)
        o = self.options
        stepper = IterativeStepper(o.heat_tol, o.device, o.max_iterations, self.factorisations)
        if loads is not None and o.reduced_start(nsteps):
            from twin.physics.rom import start_basis
            basis = start_basis(self, loads, h)
            stepper.start = ReducedStart(basis.V, stepper.xp, basis.offline_s)
        return stepper

    def output_rows(self, observers, loads) -> tuple[sp.csr_matrix, np.ndarray]:
        """The stacked rows of ``observers`` on the layout of ``loads`` (CSR) and the block bounds."""
        keys = [o.key for o in observers]
        if len(set(keys)) != len(keys):
            raise ValueError(f"observer keys must be unique in a run, got {keys}")
        blocks = [sp.csr_matrix(self._rows_of(o, loads)) for o in observers]
        outputs = sp.vstack(blocks).tocsr() if blocks else sp.csr_matrix((0, loads.mm.nheat))
        return outputs, np.cumsum([0] + [b.shape[0] for b in blocks])

    def responses(self, scenario, spec, observers, sources, times: np.ndarray | None = None,
                  theta: float = 1.0) -> dict:
        """How every observer's raw readings respond to each of ``sources`` (heat sources or
        surface fluxes with their power signals [W]) added to the model ``spec``: {observer key:
        (n_t, k, J)} on ``times`` (a uniform grid from 0 [s]; default the scenario's), zero at
        t = 0 (:func:`twin.physics.heat.integrate_responses`: all J at once, on the operators of
        ``spec``, on the CPU with this twin's heat solver). ``theta`` 1 (implicit Euler) by
        default: no ringing when the grid is coarse."""
        loads = self.loads(scenario, spec)
        outputs, bounds = self.output_rows(observers, loads)
        times = scenario.times() if times is None else np.asarray(times, float)
        dt = float(times[1] - times[0])
        mid = load_instants(times, theta)
        h, _, _ = loads.signals(mid)
        patterns = np.column_stack([source_pattern(loads.mm, s) for s in sources])
        signals = np.column_stack([s.power(mid) for s in sources])
        stepper = (self.stepper(loads, h, len(times) - 1) if self.options.device == "cpu"
                   else IterativeStepper(self.options.heat_tol))
        out = integrate_responses(loads.system, dt, len(times) - 1, h, patterns, signals, outputs, theta,
                                  stepper, loads.operator_key)
        return {o.key: out[:, a:b, :] for o, a, b in zip(observers, bounds[:-1], bounds[1:])}

    def run(self, scenario, spec, observers, theta: float = 0.5, on_step=None, progress=None,
            plausible: bool = True, idle_effects: bool = False) -> tuple[LoadSet, dict]:
        """Integrate ``scenario`` with the effects of ``spec``, observed by ``observers``.

        Returns (loads, readings): ``readings[observer.key]`` is that observer's raw output
        (n_t, k) at every output instant (see :class:`twin.observe.base.Observer`).
        ``on_step(n, T)`` is called after each step with the field, ``progress(n, total)``
        without it (the reduced model then never forms the field unless an observer needs it).
        :attr:`run_info` then describes the solvers and the error of every output. Readings are
        in each observer's raw SI unit (``raw_unit``: m, m/m, K ...), not the Dataset's um.
        The scenario is checked against this twin's machine and theta against the stable range
        first (:func:`twin.limits.check_scenario`, :func:`twin.limits.theta_value`), as
        :func:`twin.api.simulate` does: a Python caller meets the same rules; so is ``spec``: its
        effects must apply to the machine and, with ``plausible`` (the default), every parameter lie
        within its declared bounds (``plausible=False`` for a study of the model beyond them, such
        as an effect at zero strength); ``idle_effects``: an effect that cannot act in this run (a
        door draft opening after its end, :meth:`twin.effects.base.Effect.refusal`) runs, doing
        nothing, instead of being refused (a diagnosis fits one model to several records, an effect
        acting in one of them; a dataset's calibration times a few steps of a whole case).
        """
        plausible, idle_effects = (limits.check_flag(plausible, "command line", "plausible"),
                                   limits.check_flag(idle_effects, "command line", "idle_effects"))
        limits.check_progress(on_step, "command line", "on_step")
        limits.check_progress(progress, "command line", "progress")
        self.check_run(scenario, theta)
        self.check_spec(spec, scenario, plausible, idle_effects)
        check_observers(observers, [scenario], self.machine)
        loads = self.loads(scenario, spec)
        times = scenario.times()
        nsteps = len(times) - 1
        steps = {o.key: o.sample_steps(times) for o in observers}
        dense = [o for o in observers if steps[o.key] is None]
        dt = scenario.sample_interval
        h, air, s = loads.signals(load_instants(times, theta))
        (outputs, bounds), sampled_rows = self._prepare(loads, observers, steps, h, nsteps)
        sampled = [_Sampled(o, rows, steps[o.key]) for o, rows in sampled_rows]
        T0 = np.full(loads.mm.nheat, scenario.start_temperature)
        for o in observers:
            o.start(T0)
        for s_ in sampled:
            s_.record(0, T0)
        hooks = [o for o in observers if type(o).on_step is not Observer.on_step]

        def step(n, T):
            for s_ in sampled:
                s_.record(n, T)
            for o in hooks:
                o.on_step(n, times[n], T)
            if on_step is not None:
                on_step(n, T)
            if progress is not None:
                progress(n, nsteps)

        needs_field = bool(hooks) or bool(sampled) or on_step is not None
        per_output = lambda values: {o.key: values[a:b].tolist() for o, a, b in zip(dense, bounds[:-1], bounds[1:])}
        if self.options.solver == "rom":
            from twin.physics.rom import reduced_model
            rom = reduced_model(self, loads, outputs, h)
            out, info = rom.integrate(scenario.start_temperature, dt, nsteps, h, air, s, theta,
                                      step if needs_field else None, progress)
            for name, key in (("_estimate", "rom_error_estimate"), ("_bound", "rom_error_bound")):
                info[key] = per_output(info.pop(name))
            info["solver_error_units"] = error_units(dense)
        else:
            stepper = self.stepper(loads, h, nsteps)
            hook = step if needs_field else ((lambda n, T: progress(n, nsteps)) if progress is not None else None)
            out = integrate(loads.system, T0, dt, nsteps, h, air, s, outputs, theta, hook,
                            self.factorisations, loads.operator_key, stepper)
            info = stepper.info()
            if stepper.method == "iterative":
                info["solver_error_bound"] = per_output(
                    output_bounds(outputs, mass_weights(loads.system.M), float(stepper.rho_sum)))
                info["solver_error_units"] = error_units(dense)
        self.run_info = {"solver": self.options.solver, "solver_method": self.method, "device": self.options.device,
                         **info, **self.elastic_info()}
        readings = {o.key: out[:, a:b] for o, a, b in zip(dense, bounds[:-1], bounds[1:])}
        readings.update({s_.observer.key: s_.raw for s_ in sampled})
        readings = {o.key: readings[o.key] for o in observers}
        check_finite(readings, times, scenario.source or scenario.name)
        return loads, readings

    def run_batch(self, cases, observers, theta: float = 0.5, progress=None, bound: bool = True,
                  plausible: bool = True) -> tuple[LoadSet, dict, dict]:
        """Many (scenario, spec) cases at once, vectorised in the reduced model and as multiple
        right-hand sides in the full one (:func:`twin.physics.batch.run_batch`): (loads, readings
        {key: (n_t, k, cases)}, info), in the observers' raw SI units. Observers must be linear
        (rows only); every case's scenario is checked as :meth:`run` checks one."""
        from twin.physics.batch import run_batch
        plausible, bound = (limits.check_flag(plausible, "command line", "plausible"),
                            limits.check_flag(bound, "command line", "bound"))
        limits.check_progress(progress, "command line", "progress")
        if isinstance(cases, (str, bytes)) or not isinstance(cases, (list, tuple)) or not cases:
            raise InputError("command line", "cases", f"expected a list of one or more (scenario, spec), got {cases!r}")
        for i, case in enumerate(cases):
            if not isinstance(case, (list, tuple)) or len(case) != 2:
                raise InputError("command line", f"cases[{i}]", f"expected (scenario, spec), got {case!r}")
            self.check_run(case[0], theta)
            self.check_spec(case[1], case[0], plausible)
        check_observers(observers, [sc for sc, _ in cases], self.machine)
        for o in observers:   # a step hook or a sampled observer would come back empty, silently
            if type(o).on_step is not Observer.on_step or o.sample_steps(cases[0][0].times()) is not None:
                raise InputError("command line", "observers", f"{type(o).__name__} ({o.key}) is read at a step or "
                                                              "sampled: a batch takes linear observers read every "
                                                              "step (rows only); run it with run()")
        return run_batch(self, cases, observers, theta, progress, bound)

    def check_spec(self, spec, scenario, plausible: bool = True, idle_effects: bool = False) -> None:
        """:class:`InputError` unless ``spec`` is a :class:`twin.model.ModelSpec` whose effects
        apply to this twin's machine, with its parameters within their bounds and (unless
        ``idle_effects``) every effect able to act in ``scenario`` (:func:`twin.model.check_refusals`:
        a switched-on effect that would do nothing) when ``plausible``."""
        from twin.model import ModelSpec, check_applicable, check_refusals

        if not isinstance(spec, ModelSpec):
            raise InputError("command line", "spec", f"expected a twin.model.ModelSpec (twin.model.model_spec), "
                                                     f"got {spec!r}")
        check_applicable(spec.effects, self.machine)
        if plausible:
            spec.check_bounds(scenario.source or scenario.name)
            if not idle_effects:
                check_refusals(spec, scenario)

    def check_run(self, scenario, theta: float) -> None:
        """:class:`InputError` unless ``scenario`` may run on this twin's machine (its values, the
        machine's speeds, its axis moves with their feed drives built) and ``theta`` lies in
        [1/2, 1]; its interferometer and probing are checked by the observers that read them
        (:func:`check_observers`)."""
        from geometries.axes import with_feed_drives
        from twin.motion_checks import check_motions
        from twin.scenario import Scenario

        if not isinstance(scenario, Scenario):
            raise InputError("command line", "scenario", f"expected a twin.scenario.Scenario, got "
                                                         f"{type(scenario).__name__}")
        limits.theta_value(theta, scenario.source or scenario.name)
        limits.check_scenario(scenario, self.machine)
        if scenario.axes:
            check_motions(scenario, self.machine)
            needed = with_feed_drives(self.machine, {m.axis for m in scenario.axes})
            if [q.name for q in needed.parts] != [q.name for q in self.machine.parts]:
                raise InputError(scenario.source or scenario.name, "axis", "the scenario moves axes whose feed drives "
                                 "this twin's machine lacks: prepare it on twin.motion.machine_for(machine, scenario)")


def check_observers(observers, scenarios: list, machine) -> None:
    """``observers``: a list of :class:`twin.observe.base.Observer` with distinct keys, each able
    to read each of ``scenarios`` on ``machine`` (:meth:`twin.observe.base.Observer.check`)."""
    if isinstance(observers, (str, bytes)) or not isinstance(observers, (list, tuple)):
        raise InputError("command line", "observers", f"expected a list of observers (twin.observe), got {observers!r}")
    for i, o in enumerate(observers):
        if not isinstance(o, Observer):
            raise InputError("command line", f"observers[{i}]", f"expected an observer (twin.observe), got {o!r}")
    keys = [o.key for o in observers]
    twice = sorted({k for k in keys if keys.count(k) > 1})
    if twice:
        raise InputError("command line", "observers", f"two observers read {twice[0]!r}: give each observer once")
    for scenario in scenarios:
        for o in observers:
            o.check(scenario, machine)


def check_finite(readings: dict, times: np.ndarray, source: str) -> None:
    """Raise :class:`twin.errors.InputError` naming the first observer whose readings hold NaN or
    inf, and when they begin: a result never passes them off as numbers."""
    for key, values in readings.items():
        bad = ~np.isfinite(values)
        if bad.any():
            n = int(np.flatnonzero(bad.any(axis=1))[0])
            raise InputError(source, key, f"the run produced NaN or infinite values from t = {times[n]:g} s on; "
                                          "no result is written (an input beyond what the model can represent?)")


class _Sampled:
    """The raw block of an observer that records only at ``steps`` (indices of output instants):
    R @ T at those steps, one row per sample, in the observer's ``raw_dtype``."""

    def __init__(self, observer, rows: sp.csr_matrix, steps: np.ndarray):
        self.observer, self.rows = observer, rows
        self.slot = {int(n): i for i, n in enumerate(np.asarray(steps, dtype=int))}
        self.raw = np.empty((len(self.slot), rows.shape[0]), dtype=observer.raw_dtype)

    def record(self, n: int, T: np.ndarray) -> None:
        i = self.slot.get(n)
        if i is not None:
            self.raw[i] = self.rows @ T
