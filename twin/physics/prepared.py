"""A machine prepared once for many runs: simulations, diagnoses, sweeps.

Prepared once per machine, mesh and materials (no scenario, no effect set): the mesh, the
conduction and capacity matrices, and on first use the factorised elastic stiffness. Cached as
runs need them:

* per displacement observer, the adjoint solution lam = K^-1 G^T of its functionals G, and per
  temperature layout its rows (C^T lam)^T (C the thermal coupling on that layout; a layout is the
  mesh's temperature dofs, split where a contact conductance asks for it);
* per layout, the heat matrices and every observer's rows;
* per operator (layout, convection loads, dt, theta, film coefficients), the factorisation of
  M + theta dt A, so a later run with the same operators only back-substitutes.

A run with a scenario, a model spec and a list of observers then costs its load assembly and one
transient integration; the readings come back per observer (:mod:`twin.observe`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.fem.assembly import assemble_heat
from twin.fem.mesh import mesh_machine
from twin.physics.elastic import ElasticSolver
from twin.physics.heat import integrate, integrate_responses
from twin.physics.loads import LoadSet, build_loads, layout_key, source_pattern


class PreparedTwin:
    """``machine`` meshed (``mm``, or ``resolution``) and assembled with ``materials`` (a map from
    material name to a replacement Material) once; :meth:`run` any scenario and effect set."""

    def __init__(self, machine, mm=None, resolution: str = "default", materials: dict | None = None):
        self.machine = machine
        self.mm = mm if mm is not None else mesh_machine(machine, resolution)
        self.materials = {p.name: materials[p.material.name] for p in machine.parts
                          if materials and p.material.name in materials}
        self.heat = assemble_heat(self.mm, self.materials)
        self._elastic = None
        self._heat_cache = {layout_key(self.mm): self.heat}
        self._adjoints: dict[tuple, np.ndarray] = {}
        self._couplings: dict[tuple, sp.csr_matrix] = {}
        self._rows: dict[tuple, np.ndarray] = {}
        self.factorisations: dict[tuple, tuple] = {}

    @property
    def elastic(self) -> ElasticSolver:
        """The factorised stiffness of the supported machine (built on first use)."""
        if self._elastic is None:
            self._elastic = ElasticSolver.build(self.mm, self.materials)
        return self._elastic

    def coupling(self, layout, material: str | None = None) -> sp.csr_matrix:
        """Thermal coupling C [N/K] on the temperature dofs of ``layout``; with ``material``, the
        coupling of that material's cells alone (every other expansion coefficient set to 0)."""
        key = (layout_key(layout), material)
        if key not in self._couplings:
            if material is None and layout.nheat == self.mm.nheat:
                C = self.elastic.matrices.C
            else:
                parts = {p.name: self.materials.get(p.name, p.material) for p in self.machine.parts}
                if material is not None:
                    parts = {n: m if m.name == material else m.scaled(expansion=0.0) for n, m in parts.items()}
                C = ElasticSolver.coupling(layout, parts)
            self._couplings[key] = C
        return self._couplings[key]

    def adjoint(self, observer) -> np.ndarray:
        """lam = K^-1 G^T (3 n_nodes, k) of a displacement observer's functionals G, solved once."""
        key = observer.cache_key()
        if key not in self._adjoints:
            G = observer.functionals(self.mm)
            self._adjoints[key] = self.elastic.solve(np.asarray(G.todense()).T)
        return self._adjoints[key]

    def displacement_rows(self, observer, layout, material: str | None = None) -> np.ndarray:
        """(k, n_heat) rows (C^T lam)^T of a displacement observer on ``layout`` (see
        :mod:`twin.observe.displacement`), lam from :meth:`adjoint`."""
        return np.asarray(self.coupling(layout, material).T @ self.adjoint(observer)).T

    def loads(self, scenario, spec) -> LoadSet:
        """The load set of ``spec`` for ``scenario`` on this mesh (heat matrices from the cache)."""
        return build_loads(self.mm, scenario, spec, self.heat, self.materials, self._heat_cache)

    def _rows_of(self, observer, loads) -> np.ndarray:
        if not observer.layout_cached:
            rows = observer.rows(self, loads)
        else:
            key = (observer.cache_key(), layout_key(loads.mm))
            if key not in self._rows:
                self._rows[key] = observer.rows(self, loads)
            rows = self._rows[key]
        return np.zeros((0, loads.mm.nheat)) if rows is None else np.asarray(rows)

    def responses(self, scenario, spec, observers, sources, times: np.ndarray | None = None,
                  theta: float = 1.0) -> dict:
        """How every observer's raw readings respond to each of ``sources`` (heat sources or
        surface fluxes with their power signals [W]) added to the model ``spec``: {observer key:
        (n_t, k, J)} on ``times`` (a uniform grid from 0 [s]; default the scenario's), zero at
        t = 0 (:func:`twin.physics.heat.integrate_responses`: all J at once, on the operators of
        ``spec``). ``theta`` 1 (implicit Euler) by default: no ringing when the grid is coarse."""
        loads = self.loads(scenario, spec)
        blocks = [self._rows_of(o, loads) for o in observers]
        outputs = sp.csr_matrix(np.vstack(blocks)) if blocks else sp.csr_matrix((0, loads.mm.nheat))
        times = scenario.times() if times is None else np.asarray(times, float)
        dt = float(times[1] - times[0])
        mid = times[:-1] + theta * dt
        h, _, _ = loads.signals(mid)
        patterns = np.column_stack([source_pattern(loads.mm, s) for s in sources])
        signals = np.column_stack([s.power(mid) for s in sources])
        out = integrate_responses(loads.system, dt, len(times) - 1, h, patterns, signals, outputs, theta,
                                  self.factorisations, loads.operator_key)
        bounds = np.cumsum([0] + [len(b) for b in blocks])
        return {o.key: out[:, a:b, :] for o, a, b in zip(observers, bounds[:-1], bounds[1:])}

    def run(self, scenario, spec, observers, theta: float = 0.5, on_step=None) -> tuple[LoadSet, dict]:
        """Integrate ``scenario`` with the effects of ``spec``, observed by ``observers``.

        Returns (loads, readings): ``readings[observer.key]`` is that observer's raw output
        (n_t, k) at every output instant (see :class:`twin.observe.base.Observer`).
        ``on_step(n, T)`` is called after each step.
        """
        keys = [o.key for o in observers]
        if len(set(keys)) != len(keys):
            raise ValueError(f"observer keys must be unique in a run, got {keys}")
        loads = self.loads(scenario, spec)
        blocks = [self._rows_of(o, loads) for o in observers]
        outputs = sp.csr_matrix(np.vstack(blocks)) if blocks else sp.csr_matrix((0, loads.mm.nheat))
        times = scenario.times()
        dt = scenario.sample_interval
        h, air, s = loads.signals(times[:-1] + theta * dt)
        T0 = np.full(loads.mm.nheat, scenario.start_temperature)
        for o in observers:
            o.start(T0)

        def step(n, T):
            for o in observers:
                o.on_step(n, times[n], T)
            if on_step is not None:
                on_step(n, T)

        out = integrate(loads.system, T0, dt, len(times) - 1, h, air, s, outputs, theta, step,
                        self.factorisations, loads.operator_key)
        bounds = np.cumsum([0] + [len(b) for b in blocks])
        return loads, {o.key: out[:, a:b] for o, a, b in zip(observers, bounds[:-1], bounds[1:])}
