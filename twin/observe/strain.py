"""FBG strain gauges: the mean strain over a grating's length along its fibre, as the grating reads it.

A grating glued along the unit vector d between the ends a and b (length L) follows the surface's
total strain (thermal plus elastic) along d; its mean over the gauge length is exact from the end
displacements,

    eps = (1/L) int_a^b d . (du/ds) ds = d . (u(b) - u(a)) / L,

a linear functional of u (:mod:`twin.observe.displacement`: rows by one adjoint solve). The grating
itself also shifts with its own temperature (thermo-optic effect): the raw reading is

    eps_raw = eps + k_T (T_g - T_g,0),   k_T = 8.64 um/m/K (seed 000 L3939-3976),

T_g the mean temperature over the grating (five Gauss points). The seed compensated it with its
low-cost temperature sensors instead of reference gratings: the compensated reading subtracts k_T
times the change the nearest glued temperature sensor records (the run's ``temperature`` reading
of that sensor; its own draw of the sensor model when the run does not record it),

    eps_comp = eps_raw - k_T (T_s - T_s,0).

Variables (um/m): ``strain`` (compensated, as measured), ``strain_raw`` (the grating's reading, as
measured) and ``strain_true`` (eps, noise-free), per ``gauge`` with its position ``gauge_x/y/z`` [m],
direction ``gauge_dx/dy/dz``, ``gauge_length`` [m], ``gauge_part`` and ``gauge_sensor`` (the sensor
that compensates it). Changes from the start of the run, which is also the zero-strain state.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from twin import limits
from twin.errors import InputError
from twin.fem.points import displacement_functional, interpolation_matrix
from twin.observe.base import variable
from twin.observe.displacement import DisplacementObserver
from twin.observe.instruments import quantise, temperature_reading
from twin.observe.temperature import RECORDED

_GAUSS = np.polynomial.legendre.leggauss(5)


def nearest_sensor(machine, xyz) -> str:
    """The glued temperature sensor site of ``machine`` nearest to ``xyz`` [m]."""
    sites = [machine.point(n) for n in machine.sensor_sites]
    return min(sites, key=lambda p: float(np.linalg.norm(np.subtract(p.xyz, xyz)))).name


def grating_points(gauge) -> np.ndarray:
    """(5, 3) Gauss points [m] along the grating (their mean is its mean temperature)."""
    a, b = (np.asarray(e, float) for e in gauge.ends)
    s = 0.5 * (_GAUSS[0] + 1.0)
    return a[None, :] + s[:, None] * (b - a)[None, :]


class StrainGauges(DisplacementObserver):
    """The machine's FBG strain gauges (``Machine.strain_gauges``); see the module docstring."""

    key = "strain"
    raw_unit = "m/m"

    def __init__(self, gauges):
        from geometries.base import StrainGauge

        if isinstance(gauges, (str, bytes)) or not isinstance(gauges, (list, tuple)) or not gauges or not all(
                isinstance(g, StrainGauge) for g in gauges):
            raise InputError("command line", "gauges", f"expected a list of one or more geometries.base.StrainGauge "
                                                       f"(a machine's strain_gauges), got {gauges!r}")
        self.gauges = list(gauges)

    def cache_key(self) -> tuple:
        return (type(self).__name__, tuple((g.name, g.xyz, g.direction, g.length) for g in self.gauges))

    def functionals(self, mm):
        rows = []
        for g in self.gauges:
            a, b = g.ends
            P = interpolation_matrix(mm, [a, b], [g.name + " start", g.name + " end"], field="mesh")
            rows.append(displacement_functional(P[1] - P[0], np.asarray(g.direction)) / g.length)
        return sp.vstack(rows).tocsr()

    def rows(self, twin, loads):
        layout, machine = loads.mm, loads.mm.machine
        for i, g in enumerate(self.gauges):    # built in Python: on its part of this machine
            limits.check_position(machine, g.xyz, g.part, "StrainGauges", f"gauges[{i}] {g.name}")
        strain = twin.displacement_rows(self, layout)
        weights = 0.5 * _GAUSS[1]
        grating = sp.vstack([sp.csr_matrix(weights @ interpolation_matrix(layout, grating_points(g),
                                                                           [g.name] * 5).toarray())
                             for g in self.gauges])
        sites = [machine.point(nearest_sensor(machine, g.xyz)) for g in self.gauges]
        sensor = interpolation_matrix(layout, [p.xyz for p in sites], [p.name for p in sites])
        return sp.vstack([sp.csr_matrix(strain), grating, sensor]).tocsr()

    def compensating_readings(self, true: np.ndarray, ctx) -> np.ndarray:
        """(n_t, n_gauge) readings [degC] of each gauge's compensating sensor: what the run's
        temperature sensors recorded there (the same values as the result's ``temperature``), or,
        when the run does not record that sensor, its own draw of the sensor model on ``true``."""
        recorded = ctx.extra.get(RECORDED, {})
        names = [nearest_sensor(ctx.machine, g.xyz) for g in self.gauges]
        if all(n in recorded for n in names):
            return np.column_stack([recorded[n] for n in names])
        return temperature_reading(true, ctx.scenario.sample_interval, ctx.spec.params["temperature_sensor"], ctx.rng)

    def data(self, raw, ctx):
        k = len(self.gauges)
        p = ctx.spec.params["fbg"]
        true = (raw[:, :k] - raw[0, :k]) * 1e6
        grating = raw[:, k:2 * k] - raw[0, k:2 * k]
        sensor = self.compensating_readings(raw[:, 2 * k:], ctx)
        kt = p["cross_sensitivity"] * 1e6
        apparent = true + kt * grating
        measured = quantise(apparent + p["noise"] * 1e6 * ctx.rng.standard_normal(true.shape), p["quantisation"] * 1e6)
        compensated = measured - kt * (sensor - sensor[0])
        gs, machine = self.gauges, ctx.machine
        data = {"strain": variable(("time", "gauge"), compensated, "um/m",
                                   "FBG strain compensated with the nearest temperature sensor, as measured"),
                "strain_raw": variable(("time", "gauge"), measured, "um/m",
                                       "FBG reading with the grating's temperature cross-sensitivity, as measured"),
                "strain_true": variable(("time", "gauge"), true, "um/m",
                                        "true mean strain over the gauge length along the fibre")}
        coords = {"gauge": ("gauge", [g.name for g in gs], {"long_name": "FBG strain gauge"}),
                  "gauge_length": ("gauge", [g.length for g in gs], {"units": "m", "long_name": "gauge length"}),
                  "gauge_part": ("gauge", [g.part for g in gs], {"long_name": "part carrying the gauge"}),
                  "gauge_sensor": ("gauge", [nearest_sensor(machine, g.xyz) for g in gs],
                                   {"long_name": "temperature sensor compensating the gauge"})}
        for i, c in enumerate("xyz"):
            coords[f"gauge_{c}"] = ("gauge", [g.xyz[i] for g in gs], {"units": "m", "long_name": f"gauge centre {c}"})
            coords[f"gauge_d{c}"] = ("gauge", [g.direction[i] for g in gs],
                                     {"units": "1", "long_name": f"fibre direction, {c} component"})
        return data, coords
