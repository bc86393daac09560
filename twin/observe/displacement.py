"""Displacement observers: tool-point drift, the ISO 230-3 five-probe test bar, and the
sensitivity of any displacement observer to one material's expansion coefficient.

Each is a set of linear functionals q = G u of the displacement u [m] (``functionals``: G, rows
over the interleaved nodal displacements). The prepared twin solves K lam = G^T once and gives
rows (C^T lam)^T on a temperature layout, so q(t) - q(0) = rows (T(t) - T_0) [m]: the change
from the uniform start temperature, which is also the zero-strain reference.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin.errors import InputError
from twin.fem.points import displacement_functional, interpolation_matrix
from twin.observe.base import Observer, variable
from twin.observe.instruments import probe_reading

AXES = ("X", "Y", "Z")
_UNIT = np.eye(3)


def relative_displacement(mm, a: str, b: str, directions) -> sp.csr_matrix:
    """Rows: displacement of machine point ``a`` minus that of point ``b`` along each direction."""
    machine = mm.machine
    P = {n: interpolation_matrix(mm, [machine.point(n).xyz], [n], field="mesh") for n in {a, b}}
    return sp.vstack([displacement_functional(P[a], d) - displacement_functional(P[b], d)
                      for d in directions]).tocsr()


class DisplacementObserver(Observer):
    """Base of linear displacement observers: subclasses give :meth:`functionals`, and those whose
    points may ride on a moving body (:mod:`twin.observe.pose`) their :meth:`posed_points`."""

    raw_unit = "m"

    def functionals(self, mm) -> sp.csr_matrix:
        raise NotImplementedError

    def posed_points(self, machine):
        """None, or (point names, readings): each reading (a, b, direction) of :meth:`functionals`'
        rows, in order, is (u_a - u_b) . direction with a, b indices into the point names; such an
        observer is read at the pose of the measurement (:class:`twin.observe.pose.PoseCarry`)."""
        return None

    def _carry(self, machine):
        posed = self.posed_points(machine)
        if posed is None:
            return None, None
        from twin.observe.pose import PoseCarry
        carry = PoseCarry(machine, posed[0])
        return (carry, posed[1]) if carry.nrows else (None, None)

    def all_functionals(self, mm) -> sp.csr_matrix:
        """What the twin solves adjoints for: :meth:`functionals`, then the pose carry's rows."""
        G = self.functionals(mm)
        carry, _ = self._carry(mm.machine)
        return G if carry is None else sp.vstack([G, carry.functionals(mm)]).tocsr()

    def readings(self, raw: np.ndarray, ctx) -> np.ndarray:
        """(n_t, readings) [m] at the pose of each instant from the raw block of :meth:`all_functionals`."""
        carry, pairs = self._carry(ctx.machine)
        if carry is None:
            return raw
        n = len(pairs)
        return raw[:, :n] + carry.correction(raw[:, n:], carry.positions(ctx.times, ctx.scenario), pairs)

    def rows(self, twin, loads):
        return twin.displacement_rows(self, loads.mm)

    def material_rows(self, twin, loads, material: str):
        """The rows of one material's expansion alone (:class:`ExpansionSensitivity`): by default
        those of :meth:`functionals` through that material's cells; an observer whose reading has
        another term in alpha (the interferometer's screw) adds it."""
        return twin.displacement_rows(self, loads.mm, material=material)

    @staticmethod
    def change_um(raw: np.ndarray) -> np.ndarray:
        """Readings [m] as changes from the first instant, in um."""
        return (raw - raw[0]) * 1e6


class ToolDrift(DisplacementObserver):
    """The true tool-point drift X, Y, Z: the machine's tool point relative to its workpiece point,
    variable ``drift(time, axis)`` [um]."""

    key = "drift"

    def functionals(self, mm):
        return relative_displacement(mm, mm.machine.tool_point, mm.machine.workpiece_point, _UNIT)

    def posed_points(self, machine):
        return [machine.tool_point, machine.workpiece_point], [(0, 1, d) for d in _UNIT]

    def data(self, raw, ctx):
        return ({"drift": variable(("time", "axis"), self.change_um(self.readings(raw, ctx)), "um",
                                   "true tool-point drift, tool relative to table")},
                {"axis": ("axis", list(AXES), {"long_name": "machine axis"})})


def probe_geometry(machine) -> tuple[float, float, float]:
    """(z of the X1/Y1 probes, z of X2/Y2, z of the tool point) [m]."""
    return machine.point("X1").xyz[2], machine.point("X2").xyz[2], machine.point(machine.tool_point).xyz[2]


def derived_from_probes(probe_um: np.ndarray, names: list[str], machine) -> tuple[np.ndarray, np.ndarray]:
    """ISO 230-3 five-probe evaluation: drift at the tool point [um] and tilts A, B [urad].

    A (about X) = (Y1 - Y2) / d, B (about Y) = (X2 - X1) / d, d the probe spacing [m]; X and Y are
    extrapolated linearly from the two heights to the tool point, Z is the end probe.
    """
    col = {n: probe_um[:, i] for i, n in enumerate(names)}
    z1, z2, zt = probe_geometry(machine)
    d = z2 - z1
    ext = (z1 - zt) / d
    x = col["X1"] + (col["X1"] - col["X2"]) * ext
    y = col["Y1"] + (col["Y1"] - col["Y2"]) * ext
    tilt = np.column_stack([(col["Y1"] - col["Y2"]) / d, (col["X2"] - col["X1"]) / d])
    return np.column_stack([x, y, col["Z"]]), tilt


FIVE_PROBES = ("X1", "X2", "Y1", "Y2", "Z")


class FiveProbeTestBar(DisplacementObserver):
    """The ISO 230-3 five-probe nest: each probe (fixed to the workpiece side) reads the test bar's
    displacement along its direction. Variables ``probe``/``probe_true(time, probe_id)`` [um] and,
    from the readings, ``probe_drift(time, axis)`` [um] and ``tilt``/``tilt_true(time, rotation)``
    [urad] (:func:`derived_from_probes`).

    Subclasses (other displacement sensors on the test bar) change ``key``, the machine's list of
    sensors (:meth:`sensors`), the ``instrument`` parameter group, the ``name`` of the variables and
    of their dimension, and :meth:`derived`."""

    key = "probes"
    instrument = "probe"
    name, dim, long_name = "probe", "probe_id", "ISO 230-3 probe"

    def sensors(self, machine) -> list:
        return machine.probes

    def functionals(self, mm):
        sensors = self.sensors(mm.machine)
        if not sensors:     # an empty stack of rows is no reading
            raise InputError("command line", "observers", f"machine {mm.machine.name} has no {self.long_name} "
                                                          f"({type(self).__name__} reads the machine's own)")
        rows = [relative_displacement(mm, p.target, p.fixture, [p.direction]) for p in sensors]
        return sp.vstack(rows).tocsr()

    def posed_points(self, machine):
        probes = self.sensors(machine)
        return ([n for p in probes for n in (p.target, p.fixture)],
                [(2 * i, 2 * i + 1, p.direction) for i, p in enumerate(probes)])

    def data(self, raw, ctx):
        names = [p.name for p in self.sensors(ctx.machine)]
        true = self.change_um(self.readings(raw, ctx))
        meas = probe_reading(true, ctx.spec.params[self.instrument], ctx.rng)
        data = {self.name: variable(("time", self.dim), meas, "um", f"{self.long_name} reading as measured"),
                f"{self.name}_true": variable(("time", self.dim), true, "um", f"true {self.long_name} reading")}
        coords = {self.dim: (self.dim, names, {"long_name": self.long_name})}
        more, more_coords = self.derived(meas, true, names, ctx.machine)
        return {**data, **more}, {**coords, **more_coords}

    def derived(self, meas: np.ndarray, true: np.ndarray, names: list[str], machine) -> tuple[dict, dict]:
        """Variables derived from the readings [um] (as measured and true): the five-probe drift and tilts."""
        if not set(FIVE_PROBES) <= set(names):
            return {}, {}
        pdrift, tilt = derived_from_probes(meas, names, machine)
        _, tilt_true = derived_from_probes(true, names, machine)
        data = {"probe_drift": variable(("time", "axis"), pdrift, "um", "tool-point drift derived from the probe readings"),
                "tilt": variable(("time", "rotation"), tilt, "urad",
                                 "test-bar tilt from the probe readings (A about X, B about Y)"),
                "tilt_true": variable(("time", "rotation"), tilt_true, "urad", "true test-bar tilt")}
        coords = {"axis": ("axis", list(AXES), {"long_name": "machine axis"}),
                  "rotation": ("rotation", ["A", "B"], {"long_name": "rotation about X (A) and Y (B)"})}
        return data, coords


class ExpansionSensitivity(Observer):
    """d q / d s of a displacement observer's readings q for a relative change s of one material's
    expansion coefficient, alpha_m (1 + s) [m per unit]: rows (C_m^T lam)^T with C_m the thermal
    coupling of that material's cells alone. Drift is linear in each alpha and K does not depend
    on alpha, so q(alpha_m (1 + s)) - q(alpha_m) = s (C_m^T lam)^T (T - T_0) exactly. Raw only
    (no Dataset variables): the diagnosis fits it as a nuisance."""

    def __init__(self, material: str, of: DisplacementObserver):
        if not isinstance(of, DisplacementObserver):
            raise InputError("command line", "of", f"expected a displacement observer (twin.observe), got {of!r}")
        if not isinstance(material, str):
            raise InputError("command line", "material", f"expected a material name, got {material!r}")
        self.material, self.of = material, of
        self.key = f"expansion:{material}:{of.key}"
        self.raw_unit = of.raw_unit   # per unit change of alpha

    def cache_key(self) -> tuple:
        return (type(self).__name__, self.material) + self.of.cache_key()

    def rows(self, twin, loads):
        made_of = sorted({p.material.name for p in twin.machine.parts})
        if self.material not in made_of:     # its rows would be zeros: a sensitivity of nothing
            raise InputError("command line", "material", f"no part of machine {twin.machine.name} is made of "
                                                         f"{self.material!r}; its materials: {', '.join(made_of)}")
        return self.of.material_rows(twin, loads, self.material)
