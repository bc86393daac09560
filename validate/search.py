"""Fitting candidates to the residual: singles, then pairs, at a bounded number of twin runs.

Every candidate (:mod:`validate.candidates`) is a scalar p with bounds; its response is
g(p) = y(model with p) - y(model) on every channel of every measurement (flat,
:mod:`validate.evidence`). Fits go through :class:`validate.fit.BoundedFitter`, the bounded
nuisance (each material's expansion within its band) fitted jointly with every candidate.

* Linear candidates (heat sources): g(p) = (p - p_0) u with u from one run; the bounded fit is
  exact.
* Nonlinear candidates: one run at the reference value gives the secant s = g(p_ref) / (p_ref -
  p_0); the linearised fit g ~ (p - p_0) s gives a start p_1, and one run there the actual SSE;
  a second secant through the zero and p_1 (on the fit's side of p_0, where p_ref may lie on the
  other) gives p_2, one more run, kept if better (a reciprocal candidate, a contact conductance
  whose g vanishes at p_0 = infinity, is linearised in its resistance: g ~ (1/p - 1/p_0) v). The
  ``refine`` best of them (by that SSE) then get bounded Gauss-Newton
  (:func:`validate.fit.gauss_newton`).
* Pairs (when no single explains ``pair_threshold`` of the residual): every pair of the
  ``pair_pool`` best singles, linearised about each member's single fit (g_i(p) ~ g_i(p_i) +
  J_i (p - p_i), exact for linear members), fitted jointly; the best pair with a nonlinear
  member is refined by Gauss-Newton in both parameters.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from twin.model import ModelSpec
from validate.candidates import Candidate
from validate.fit import BoundedFitter, gauss_newton


@dataclass(eq=False)
class Fit:
    """Fitted candidate(s): values (SI) in the order of ``candidates``, the response g (flat), the
    weighted SSE after (nuisance fitted), and per member the local slope dg/dp (flat) used to
    linearise it in a pair."""

    candidates: tuple[Candidate, ...]
    values: tuple[float, ...]
    response: np.ndarray
    sse: float
    slopes: tuple[np.ndarray, ...] = field(default_factory=tuple)

    @property
    def name(self) -> str:
        return "+".join(c.name for c in self.candidates)

    @property
    def nparams(self) -> int:
        return len(self.candidates)

    @property
    def kind(self) -> str:
        kinds = list(dict.fromkeys(c.kind for c in self.candidates))
        return "+".join(kinds)

    def value_of(self, name: str) -> float:
        return next(v for c, v in zip(self.candidates, self.values) if c.name == name)

    def in_model(self, spec: ModelSpec) -> ModelSpec:
        """``spec`` with every member at its fitted value."""
        for c, v in zip(self.candidates, self.values):
            spec = c.spec(spec, v)
        return spec


class Search:
    """Candidate fits against ``observe(spec) -> flat`` with baseline ``base`` (flat)."""

    def __init__(self, observe, spec, base: np.ndarray, fitter: BoundedFitter, gn_iterations: int = 4,
                 refine: int = 4):
        self.observe, self.spec, self.base, self.fitter = observe, spec, base, fitter
        self.gn_iterations, self.refine = gn_iterations, refine
        self._unit: dict[str, np.ndarray] = {}

    def response(self, cands, values) -> np.ndarray:
        """g for ``cands`` at ``values`` from one twin run."""
        spec = self.spec
        for c, v in zip(cands, values):
            spec = c.spec(spec, v)
        return self.observe(spec) - self.base

    def unit(self, c: Candidate) -> np.ndarray:
        """u = g(p_ref) / (p_ref - p_0): exact slope of a linear candidate, the secant of a nonlinear one."""
        if c.name not in self._unit:
            self._unit[c.name] = self.response([c], [c.reference]) / (c.reference - c.zero)
        return self._unit[c.name]

    def linearised(self, c: Candidate) -> tuple[float, float]:
        """(p, SSE) of the fit g ~ (p - p_0) u within the candidate's bounds (a reciprocal
        candidate: g ~ (1/p - 1/p_0) v), the secant taken through the reference run."""
        return self.along(c, self.unit(c) * (c.reference - c.zero), c.reference)

    def along(self, c: Candidate, g_at: np.ndarray, p_at: float) -> tuple[float, float]:
        """(p, SSE) of the fit g ~ (t(p) - t(p_0)) v, v = g(p_at) / (t(p_at) - t(p_0)): the secant
        through the zero and the run at ``p_at``, in t(p) = p, or t(p) = 1/p for a reciprocal
        candidate; within the candidate's bounds."""
        t = (lambda q: 1.0 / q) if c.reciprocal else (lambda q: q)
        t0 = t(c.zero)
        lo, hi = sorted((t(c.lower) - t0, t(c.upper) - t0))
        x, _, sse = self.fitter.solve((g_at / (t(p_at) - t0))[:, None], [lo], [hi])
        return float(min(max(t(t0 + x[0]), c.lower), c.upper)), sse

    def single(self, c: Candidate, gauss_newton_steps: bool = False) -> Fit:
        """A candidate's fit: exact for a linear one; for a nonlinear one the linearised start,
        evaluated, then one more secant through the zero and that start (on the fit's side of
        p_0, where the reference may lie on the other: a film 0.6x its model value, the secant
        through 2x), evaluated and kept if better; with ``gauss_newton_steps`` refined."""
        p, _ = self.linearised(c)
        u = self.unit(c)
        if c.linear:
            g = (p - c.zero) * u
            return Fit((c,), (p,), g, self.fitter.sse(g), (u,))
        g = self.response([c], [p])
        fit = Fit((c,), (p,), g, self.fitter.sse(g), (u,))
        if abs(p - c.zero) > 1e-6 * (c.upper - c.lower) and np.any(g):
            q, _ = self.along(c, g, p)
            if abs(q - p) > 1e-3 * (c.upper - c.lower):
                g2 = self.response([c], [q])
                sse2 = self.fitter.sse(g2)
                if sse2 < fit.sse:
                    fit = Fit((c,), (q,), g2, sse2, (u,))
        return self.joint((c,), fit.values) if gauss_newton_steps else fit

    def joint(self, cands: tuple[Candidate, ...], start) -> Fit:
        """Bounded Gauss-Newton over ``cands`` from ``start`` (linear members: exact columns)."""
        linear = np.array([c.linear for c in cands])
        cols = {i: self.unit(c) for i, c in enumerate(cands) if c.linear}
        lo = np.array([c.lower for c in cands])
        hi = np.array([c.upper for c in cands])
        ev = lambda p: self.response(cands, p)
        p, g, sse, _ = gauss_newton(self.fitter, ev, np.asarray(start, float), lo, hi, linear, cols,
                                    self.gn_iterations)
        slopes = tuple(self._slope(c, v, g if len(cands) == 1 else None) for c, v in zip(cands, p))
        return Fit(cands, tuple(float(v) for v in p), g, sse, slopes)

    def _slope(self, c: Candidate, value: float, g: np.ndarray | None) -> np.ndarray:
        """dg/dp near ``value``: the unit column of a linear candidate, else the secant from p_0."""
        if c.linear or g is None or abs(value - c.zero) < 1e-9 * (c.upper - c.lower):
            return self.unit(c)
        return g / (value - c.zero)

    def singles(self, cands: list[Candidate], each=None) -> list[Fit]:
        """Every candidate fitted (``each()`` called after each); the ``refine`` best nonlinear
        ones refined by Gauss-Newton. Sorted by SSE."""
        fits = []
        for c in cands:
            fits.append(self.single(c))
            if each is not None:
                each()
        nonlinear = sorted((f for f in fits if not f.candidates[0].linear), key=lambda f: f.sse)
        for f in nonlinear[:self.refine]:
            refined = self.joint(f.candidates, f.values)
            fits[fits.index(f)] = refined if refined.sse <= f.sse else f
        return sorted(fits, key=lambda f: f.sse)

    def pair(self, a: Fit, b: Fit) -> Fit:
        """Two singles fitted jointly, each linearised about its own fit (exact when both are
        linear): g ~ sum_i g_i(p_i) + s_i (q_i - p_i); a reciprocal member in its resistance,
        g_i ~ (1/q_i - 1/p_0) g_i(p_i) / (1/p_i - 1/p_0)."""
        cands = tuple(f.candidates[0] for f in (a, b))
        lines = [self._line(f) for f in (a, b)]
        offset = sum(off for off, *_ in lines)
        cols = np.column_stack([col for _, col, *_ in lines])
        x, _, _ = self.fitter.solve(cols, [lo for *_, (lo, _), _ in lines], [hi for *_, (_, hi), _ in lines],
                                    self.fitter.r - offset)
        g = offset + cols @ x
        # back to each parameter, within its bounds (1 / (1/p_0 + x) at the bound is a rounding off it)
        values = tuple(min(max(float(back(xi)), c.lower), c.upper) for c, (*_, back), xi in zip(cands, lines, x))
        if any(not c.linear for c in cands):   # the linearisation is approximate: evaluate it
            g = self.response(cands, values)
        return Fit(cands, values, g, self.fitter.sse(g), tuple(f.slopes[0] for f in (a, b)))

    @staticmethod
    def _line(f: Fit):
        """A single's linearisation for a pair: (offset, column, (lower, upper) of x, x -> value)
        with g ~ offset + column x about the single's fit; x = q - p_0, or for a reciprocal member
        fitted below p_0, x = 1/q - 1/p_0."""
        c, p, g, s = f.candidates[0], f.values[0], f.response, f.slopes[0]
        if c.reciprocal and p < c.zero:
            t0 = 1.0 / c.zero
            return 0 * g, g / (1.0 / p - t0), (1.0 / c.upper - t0, 1.0 / c.lower - t0), lambda x: 1.0 / (t0 + x)
        offset = 0 * g if c.linear else g - (p - c.zero) * s
        return offset, s, (c.lower - c.zero, c.upper - c.zero), lambda x: c.zero + x
