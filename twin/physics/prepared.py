"""A machine and a scenario prepared once for many runs (simulation, diagnosis, sweeps).

Prepared once: the mesh, the conduction and capacity matrices, the factorised stiffness and the
adjoint solutions lam_i = K^-1 g_i of every drift output g_i (tool-point drift X, Y, Z and each
probe), and the sensor interpolation. A run with a given set of effects then costs its load
assembly and one transient integration: drift outputs are q_i = (C^T lam_i)^T (T - T_0), where
the coupling C depends on the temperature layout (split at contact interfaces or not), so the
influence vectors C^T lam_i are cached per layout.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.fem.assembly import assemble_heat
from twin.physics.elastic import ElasticSolver
from twin.model import LoadSet, ModelSpec, build_loads
from twin.fem.points import displacement_functional, interpolation_matrix
from twin.physics.heat import integrate
from twin.fem.mesh import mesh_machine

_UNIT = np.eye(3)


def drift_functionals(mm) -> sp.csr_matrix:
    """Rows: tool-minus-workpiece displacement X, Y, Z, then each probe's reading [m per m]."""
    machine = mm.machine
    names = {machine.tool_point, machine.workpiece_point} | {p.target for p in machine.probes} | {
        p.fixture for p in machine.probes}
    pts = {n: interpolation_matrix(mm, [machine.point(n).xyz], [n], field="mesh") for n in names}
    rows = [displacement_functional(pts[machine.tool_point], _UNIT[d])
            - displacement_functional(pts[machine.workpiece_point], _UNIT[d]) for d in range(3)]
    rows += [displacement_functional(pts[p.target], p.direction) - displacement_functional(pts[p.fixture], p.direction)
             for p in machine.probes]
    return sp.vstack(rows).tocsr()


class PreparedTwin:
    """Machine + mesh + scenario + sensors, with everything that does not depend on the effects
    assembled and factorised once. ``materials`` maps material names to replacements."""

    def __init__(self, machine, scenario, mm=None, resolution: str = "default", materials: dict | None = None,
                 sensors: list | None = None):
        self.machine, self.scenario = machine, scenario
        self.mm = mm if mm is not None else mesh_machine(machine, resolution)
        self.materials = {p.name: materials[p.material.name] for p in machine.parts
                          if materials and p.material.name in materials}
        self.heat = assemble_heat(self.mm, self.materials)
        self.elastic = ElasticSolver.build(self.mm, self.materials)
        self.adjoint = self.elastic.solve(np.asarray(drift_functionals(self.mm).todense()).T)  # (3 nnodes, nout)
        self.sensors = sensors if sensors is not None else [machine.point(n) for n in machine.sensor_sites]
        self._layouts: dict[int, tuple] = {}
        self._expansion: dict[tuple, np.ndarray] = {}

    def _layout(self, mm_heat):
        """(sensor interpolation S, influence W) on the temperature dofs of ``mm_heat``."""
        if mm_heat.nheat not in self._layouts:
            if mm_heat.nheat == self.mm.nheat:
                C = self.elastic.matrices.C
            else:
                C = ElasticSolver.coupling(mm_heat, self.materials)
            S = interpolation_matrix(mm_heat, [p.xyz for p in self.sensors], [p.name for p in self.sensors])
            self._layouts[mm_heat.nheat] = (S.toarray(), np.asarray(C.T @ self.adjoint))
        return self._layouts[mm_heat.nheat]

    def expansion_influence(self, mm_heat, material: str) -> np.ndarray:
        """Influence vectors (nheat, nout) of the drift outputs per unit relative change of the
        expansion coefficient of ``material`` (a material name): C_m^T lam_i with C_m the coupling
        of that material's cells alone. The drift is linear in each alpha and K does not depend
        on alpha, so q_i(alpha_m (1 + s)) - q_i(alpha_m) = s (C_m^T lam_i)^T (T - T_0) exactly."""
        key = (mm_heat.nheat, material)
        if key not in self._expansion:
            parts = {p.name: self.materials.get(p.name, p.material) for p in self.machine.parts}
            alone = {name: m if m.name == material else m.scaled(expansion=0.0) for name, m in parts.items()}
            self._expansion[key] = np.asarray(ElasticSolver.coupling(mm_heat, alone).T @ self.adjoint)
        return self._expansion[key]

    def loads(self, spec: ModelSpec) -> LoadSet:
        return build_loads(self.mm, self.scenario, spec, self.heat, self.materials)

    def run(self, spec: ModelSpec, theta: float = 0.5, on_step=None, expansion: tuple[str, ...] = ()):
        """Integrate the scenario with the effects of ``spec``.

        Returns (loads, out) with out (nt, nsensor + 1 + nconv + nout [+ nout per material]):
        sensor temperatures [degC], stored heat 1^T M T [J], int T dA per convection load
        [K m2], and the drift outputs q_i = W_i^T T [m] (subtract the first row for the change
        from the start); then, for each material named in ``expansion``, the drift outputs'
        sensitivity to a relative change of its expansion coefficient [m per unit]
        (:meth:`expansion_influence`), from the same temperature history.
        """
        loads = self.loads(spec)
        S, W = self._layout(loads.mm)
        ones_M = np.asarray(loads.heat.M.sum(axis=0)).ravel()
        rows = [S, ones_M[None, :], loads.system.r.T, W.T] + [self.expansion_influence(loads.mm, m).T
                                                               for m in expansion]
        outputs = sp.csr_matrix(np.vstack(rows))
        times = self.scenario.times()
        dt = self.scenario.sample_interval
        h, air, s = loads.signals(times[:-1] + theta * dt)
        T0 = np.full(loads.mm.nheat, self.scenario.start_temperature)
        out = integrate(loads.system, T0, dt, len(times) - 1, h, air, s, outputs, theta, on_step)
        return loads, out
