"""Probing datum points on the table with a spindle-mounted probe (seed 000, the duty-cycle test:
a Renishaw OMP40-2 touching the corners of a granite square before the first part and after the
third and sixth).

A scenario asks for it with::

    [probing]
    times = ["0 min", "330 min", "600 min"]           # on the time grid; the first (0 s) is the datum baseline
    datums = [["100 mm", "100 mm", "150 mm"], ...]     # commanded X, Y, Z of each datum point

At each probing the probe (the tool point) touches every datum with the temperature field frozen
at that instant (the seconds a routine takes are neglected). Each datum's error is the apparent
shift of the tool relative to the workpiece at the datum's pose, along X, Y and Z:

    e(t, datum) = d(t; pose) + sum_axes s_a e_a(p_a) u_a  -  the same at the baseline,

with d the tool-point drift (tool minus workpiece point) read at the datum's pose
(:mod:`twin.observe.pose`: the moving bodies carried by the structure under their carriages
there), e_a = alpha_s integral_{fixed}^{nut(p_a)} (T_screw - T_0) ds the semi-closed positioning
error of each axis whose screw is in the model (:func:`twin.observe.interferometer.screw_line_rows`)
along its direction u_a, and s_a = +1 when the axis carries the tool (Z), -1 when it carries the
workpiece (X, Y). Output: ``probing_error(probe_time, datum, axis)`` [um] and the datums' commanded
positions ``datum_position(datum, axis)`` [mm].

Not modelled: the bonded mesh's body follows the structure under its nut along its own axis
(the interferometer's structure share c, :mod:`twin.observe.interferometer`, is not added), the
probe's own repeatability (1 um) and the datum square's expansion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from geometries.axes import carried_sign
from geometries.regions import feed_drive_role
from twin.errors import InputError
from twin.io.table_reader import TableReader
from twin.observe.base import variable
from twin.observe.displacement import AXES, DisplacementObserver, relative_displacement
from twin.observe.instants import baseline_instants, check_on_grid
from twin.units import UnitError, parse_quantity

_UNIT = np.eye(3)


@dataclass(frozen=True)
class ProbingConfig:
    """Probing instants [s] (the first 0 s) and datum points (n, 3) commanded X, Y, Z [m]."""

    times: tuple[float, ...]
    datums: tuple[tuple[float, float, float], ...]
    source: str = ""


def probing_from_toml(raw, source: str) -> ProbingConfig | None:
    """The scenario's ``[probing]`` table (None when absent)."""
    if raw is None:
        return None
    r = TableReader(raw, source, "probing.", known=("times", "datums"))
    times = r.get("times", required=True)
    datums = r.get("datums", required=True)
    r.finish()
    t = baseline_instants(times, source, "probing.times", "the datum baseline")
    if not isinstance(datums, list) or not datums or not all(isinstance(d, list) and len(d) == 3 for d in datums):
        raise InputError(source, "probing.datums", 'expected a list of [X, Y, Z] positions such as ["100 mm", "50 mm", "0 mm"]')
    try:
        xyz = tuple(tuple(parse_quantity(v, "length") for v in d) for d in datums)
    except UnitError as err:
        raise InputError(source, "probing.datums", str(err)) from None
    return ProbingConfig(t, xyz, source)


def check_probing(config: ProbingConfig, scenario, machine) -> None:
    """The machine has axes X, Y, Z, every datum lies in their travel, and the probings fall on
    the scenario's time grid within its duration."""
    src = config.source or scenario.name
    names = [a.name for a in machine.axes]
    if names[:3] != list(AXES):
        raise InputError(src, "probing", f"machine {machine.name} has no X, Y, Z axes to probe with (its axes: "
                                         f"{', '.join(names) or 'none'})")
    if not isinstance(config, ProbingConfig):
        raise InputError(src, "probing", f"expected a twin.observe.probing.ProbingConfig, got {config!r}")
    datums = config.datums
    if isinstance(datums, (str, bytes)) or not hasattr(datums, "__len__") or not len(datums):
        raise InputError(src, "probing.datums", f"expected one or more (X, Y, Z) positions [m], got {datums!r}")
    for i, d in enumerate(datums):
        try:
            xyz = np.asarray(d, dtype=float)
        except (TypeError, ValueError):
            xyz = None
        if xyz is None or xyz.shape != (3,) or not np.all(np.isfinite(xyz)):
            raise InputError(src, f"probing.datums[{i}]", f"expected three finite positions (X, Y, Z) [m], got {d!r}")
        for a, v in zip(machine.axes, xyz):
            if v < a.travel[0] - 1e-9 or v > a.travel[1] + 1e-9:
                raise InputError(src, f"probing.datums[{i}]", f"{a.name} {v * 1e3:g} mm is outside the travel "
                                                             f"{a.travel[0] * 1e3:g} .. {a.travel[1] * 1e3:g} mm")
        same = next((j for j in range(i) if np.allclose(np.asarray(datums[j], float), xyz, rtol=0, atol=1e-9)), None)
        if same is not None:
            raise InputError(src, f"probing.datums[{i}]", f"repeats datums[{same}] "
                                                         f"({', '.join(f'{v * 1e3:g} mm' for v in xyz)}): give each once")
    check_on_grid(config.times, scenario, src, "probing.times", "the datum baseline")


class DatumProbing(DisplacementObserver):
    """The probing routine of ``config`` (see module)."""

    key = "probing"
    layout_cached = True

    def __init__(self, config: ProbingConfig, machine):
        if not isinstance(config, ProbingConfig):
            raise InputError("command line", "probing", f"expected a ProbingConfig, got {config!r}")
        self.config = config
        self.datums = np.array(config.datums, float).reshape(-1, 3)
        self.screws = [a for a in machine.axes[:3] if a.feedback == "semi-closed" and a.drive is not None
                       and feed_drive_role(a.name, "screw") in machine.roles]

    def cache_key(self) -> tuple:
        return (type(self).__name__, self.config)

    def check(self, scenario, machine) -> None:
        """Its instants on the scenario's grid, from 0 s, increasing; its datums in the travel."""
        check_probing(self.config, scenario, machine)

    def functionals(self, mm):
        return relative_displacement(mm, mm.machine.tool_point, mm.machine.workpiece_point, _UNIT)

    def posed_points(self, machine):
        return [machine.tool_point, machine.workpiece_point], [(0, 1, d) for d in _UNIT]

    def rows(self, twin, loads):
        """The drift and pose-carry rows, then each screw's line integral at every datum."""
        from twin.observe.interferometer import screw_line_rows
        layout = loads.mm
        blocks = [sp.csr_matrix(twin.displacement_rows(self, layout))]
        for a in self.screws:
            screw = twin.machine.part(twin.machine.roles[feed_drive_role(a.name, "screw")].names[0])
            alpha = twin.materials.get(screw.name, screw.material).expansion
            blocks.append(screw_line_rows(layout, a, self.datums[:, "XYZ".index(a.name)], alpha))
        return sp.vstack(blocks).tocsr()

    def sample_steps(self, times):
        dt = times[1] - times[0] if len(times) > 1 else 1.0
        return np.array([int(round(t / dt)) for t in self.config.times])

    def errors(self, raw: np.ndarray, machine) -> np.ndarray:
        """(n_probings, n_datums, 3) [m] from the raw block of :meth:`rows` (module docstring)."""
        carry, pairs = self._carry(machine)
        n = len(self.datums)
        ncarry = 0 if carry is None else carry.nrows
        out = np.repeat(raw[:, None, :3], n, axis=1)
        if carry is not None:
            names = [a.name for a in carry.axes]
            for j, d in enumerate(self.datums):
                pos = np.tile([d["XYZ".index(a)] for a in names], (len(raw), 1))
                out[:, j] += carry.correction(raw[:, 3:3 + ncarry], pos, pairs)
        screw = raw[:, 3 + ncarry:]
        for i, a in enumerate(self.screws):
            out[:, :, "xyz".index(a.direction)] += carried_sign(machine, a) * screw[:, i * n:(i + 1) * n]
        return out - out[:1]

    def data(self, raw, ctx):
        err = self.errors(raw, ctx.machine) * 1e6
        return ({"probing_error": variable(("probe_time", "datum", "axis"), err, "um",
                                           "apparent shift of the tool relative to each datum, from the baseline"),
                 "datum_position": variable(("datum", "axis"), self.datums * 1e3, "mm", "commanded datum position")},
                {"probe_time": ("probe_time", np.asarray(self.config.times, float),
                                {"units": "s", "long_name": "probing instant"}),
                 "datum": ("datum", np.arange(len(self.datums)), {"long_name": "datum point"}),
                 "axis": ("axis", list(AXES), {"long_name": "machine axis"})})
