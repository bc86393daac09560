"""Model vs measurement: residuals per channel, RMSE / max |r| / NSE per channel and per phase.

Channels: every temperature sensor (``T:<sensor>``, K), every probe (``probe:<id>``, um) and the
derived tilts (``tilt:<A|B>``, urad) present in both datasets. The model is read at the measured
instants (linear interpolation in time), using its noise-free variables (``*_true``) when present.
For a channel with measured values m_i and residuals r_i = m_i - y_i (y the model):

    RMSE = sqrt(mean r^2),   max|r|,   NSE = 1 - sum r^2 / sum (m - mean m)^2   (Nash-Sutcliffe),

NSE = 1 is a perfect fit, 0 no better than the measured mean. Phases come from the inputs
(:func:`detect_phases`): spindle off / on / speed change, and ambient rising / falling / steady.
Channels are ranked by the normalised RMSE = RMSE / std(m) (unit-free, sqrt(1 - NSE) over the
whole run); phase cells by RMSE in the phase / std(m) over the run.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from twin.cli.options import add_measurement_options, add_model_options

_GROUPS = (("temperature", "sensor", "T", "K"), ("probe", "probe_id", "probe", "um"),
           ("tilt", "rotation", "tilt", "urad"))


@dataclass
class Phase:
    """A stretch of time [start, end) [s] with one behaviour of the inputs."""

    kind: str     # "spindle" or "ambient"
    label: str    # e.g. "spindle on 9000 rpm", "speed change to 6000 rpm", "ambient rising"
    start: float
    end: float


@dataclass
class Stats:
    rmse: float
    max_abs: float
    nse: float
    n: int


@dataclass
class ChannelResult:
    name: str
    unit: str
    stats: Stats
    spread: float                                   # std of the measured channel over the run
    phases: list[Stats] = field(default_factory=list)  # one per CompareResult.phases entry

    @property
    def normalised_rmse(self) -> float:
        return self.stats.rmse / self.spread if self.spread > 0 else (0.0 if self.stats.rmse == 0 else np.inf)


@dataclass
class CompareResult:
    channels: list[ChannelResult]
    phases: list[Phase]
    residuals: xr.Dataset   # residual(time, channel) = measured - model, with a unit per channel

    def channel(self, name: str) -> ChannelResult:
        return next(c for c in self.channels if c.name == name)

    def ranking(self) -> list[ChannelResult]:
        """Channels, worst (largest normalised RMSE) first."""
        return sorted(self.channels, key=lambda c: -c.normalised_rmse)

    def phase_ranking(self) -> list[tuple[ChannelResult, Phase, Stats, float]]:
        """(channel, phase, stats, RMSE / std(m)) for every phase cell, worst first."""
        cells = [(c, p, s, s.rmse / c.spread if c.spread > 0 else s.rmse)
                 for c in self.channels for p, s in zip(self.phases, c.phases) if s.n]
        return sorted(cells, key=lambda x: -x[3])


def stats(measured: np.ndarray, residual: np.ndarray) -> Stats:
    """RMSE, max |r| and NSE of residuals r for measured values m (NaN-free arrays)."""
    n = len(residual)
    if n == 0:
        return Stats(np.nan, np.nan, np.nan, 0)
    sse = float(np.sum(residual ** 2))
    sst = float(np.sum((measured - measured.mean()) ** 2))
    nse = 1.0 - sse / sst if sst > 0 else (1.0 if sse == 0 else np.nan)
    return Stats(float(np.sqrt(sse / n)), float(np.max(np.abs(residual))), nse, n)


def channels_of(ds: xr.Dataset, prefer_true: bool = False) -> dict[str, tuple[np.ndarray, str]]:
    """{channel name: (values over time, unit)} of a result or measurement."""
    out = {}
    for var, dim, prefix, unit in _GROUPS:
        v = f"{var}_true" if prefer_true and f"{var}_true" in ds else var
        if v in ds and dim in ds[v].dims:
            arr = ds[v].transpose("time", dim)
            for i, label in enumerate(ds[dim].values):
                out[f"{prefix}:{label}"] = (np.asarray(arr.values[:, i], float), unit)
    return out


def _segments(labels: list[str], t: np.ndarray) -> list[tuple[str, float, float]]:
    out = []
    for i, lab in enumerate(labels):
        if out and out[-1][0] == lab:
            out[-1][2] = i
        else:
            out.append([lab, i, i])
    end = lambda j: float(t[j + 1]) if j + 1 < len(t) else float(t[-1]) + (float(t[-1] - t[-2]) if len(t) > 1 else 0.0)
    return [(lab, float(t[i0]), end(i1)) for lab, i0, i1 in out]


def detect_phases(time: np.ndarray, speed: np.ndarray | None = None, ambient: np.ndarray | None = None,
                  speed_tolerance: float = 50.0, ambient_rate: float = 0.1 / 3600.0,
                  smooth: float = 1800.0) -> list[Phase]:
    """Phases of the inputs.

    Spindle: steps of :func:`twin.io.measured_inputs.speed_steps` labelled "spindle off" (0 rpm),
    "spindle on N rpm" (after a stop or at the start) or "speed change to N rpm" (after another
    speed). Ambient: the sign of dT_air/dt [K/s], smoothed by a centred moving average over
    ``smooth`` [s], "rising" above ``ambient_rate`` (default 0.1 K/h), "falling" below its
    negative, else "steady"; ambient stretches shorter than ``smooth`` merge into their predecessor.
    """
    from twin.io.measured_inputs import speed_steps

    t = np.asarray(time, float)
    phases: list[Phase] = []
    if speed is not None:
        prev = 0.0
        for k, (t0, t1, n) in enumerate(speed_steps(t, speed, speed_tolerance)):
            if n == 0:
                label = "spindle off"
            elif prev == 0:
                label = f"spindle on {n:.0f} rpm"
            else:
                label = f"speed change to {n:.0f} rpm"
            end = t1 if t1 > t0 else t0
            phases.append(Phase("spindle", label, t0, end))
            prev = n
        if phases:
            phases[-1].end = float(t[-1]) + (float(t[-1] - t[-2]) if len(t) > 1 else 0.0)
    if ambient is not None and len(t) > 2:
        a = np.asarray(ambient, float)
        dt = float(np.median(np.diff(t)))
        w = max(1, int(round(smooth / dt)))
        kernel = np.ones(w) / w
        pad = np.pad(a, (w // 2, w - 1 - w // 2), mode="edge")
        rate = np.gradient(np.convolve(pad, kernel, mode="valid"), t)
        labels = ["ambient rising" if r > ambient_rate else "ambient falling" if r < -ambient_rate else "ambient steady"
                  for r in rate]
        segs = _segments(labels, t)
        merged: list[list] = []
        for lab, t0, t1 in segs:
            if merged and (t1 - t0 < smooth or merged[-1][0] == lab):
                merged[-1][2] = t1
            else:
                merged.append([lab, t0, t1])
        phases += [Phase("ambient", lab, t0, t1) for lab, t0, t1 in merged]
    return phases


def compare(measured: xr.Dataset, model: xr.Dataset, phases: list[Phase] | None = None,
            model_true: bool = True) -> CompareResult:
    """Residuals measured - model on the measured instants, with per-channel and per-phase stats.

    Both time axes count from their first sample (a measurement logged from t0 is compared with a
    model run from 0). ``model_true``: use the model's noise-free variables where it has them.
    """
    t = np.asarray(measured.time.values, float)
    mod_t = np.asarray(model.time.values, float)
    t_mod = t - t[0] + mod_t[0]
    meas, mod = channels_of(measured), channels_of(model, prefer_true=model_true)
    names = [c for c in meas if c in mod]
    if phases is None:
        phases = detect_phases(t, measured.spindle_speed.values if "spindle_speed" in measured else None,
                               measured.ambient_temperature.values if "ambient_temperature" in measured else None)
    results, res = [], []
    for name in names:
        m, unit = meas[name]
        y = np.interp(t_mod, mod_t, mod[name][0])
        r = m - y
        res.append(r)
        per = [stats(m[sel], r[sel]) for sel in ((t >= p.start) & (t < p.end) for p in phases)]
        results.append(ChannelResult(name, unit, stats(m, r), float(np.std(m)), per))
    data = np.column_stack(res) if res else np.zeros((len(t), 0))
    residuals = xr.Dataset(
        {"residual": (("time", "channel"), data, {"long_name": "measured minus model"})},
        coords={"time": ("time", t, {"units": "s"}), "channel": ("channel", names),
                "unit": ("channel", [meas[n][1] for n in names])})
    return CompareResult(results, phases, residuals)


def format_compare(result: CompareResult, top: int = 8) -> str:
    """A terminal table: per-channel stats, then the worst channels and phase cells."""
    lines = [f"{'channel':<26} {'unit':>5} {'RMSE':>9} {'max|r|':>9} {'NSE':>7}"]
    for c in result.channels:
        s = c.stats
        lines.append(f"{c.name:<26} {c.unit:>5} {s.rmse:9.3g} {s.max_abs:9.3g} {s.nse:7.3f}")
    lines += ["", "phases:"]
    lines += [f"  {p.label:<28} {p.start / 3600:7.2f} h .. {p.end / 3600:7.2f} h" for p in result.phases]
    lines += ["", "worst channels (RMSE / std of the measurement):"]
    lines += [f"  {i + 1}. {c.name:<24} {c.normalised_rmse:7.3f}" for i, c in enumerate(result.ranking()[:top])]
    cells = result.phase_ranking()[:top]
    if cells:
        lines += ["", "worst phases (channel, phase, RMSE / std):"]
        lines += [f"  {i + 1}. {c.name:<24} {p.label:<28} {v:7.3f} (RMSE {s.rmse:.3g} {c.unit})"
                  for i, (c, p, s, v) in enumerate(cells)]
    return "\n".join(lines)


def model_for(measured: xr.Dataset, machine: str, scenario: str | None = None, effects: str | None = None,
              settings: list[str] | None = None, resolution: str = "default", seed: int = 0, progress=None):
    """Simulate the twin at the measurement's sensor sites, driven by its inputs unless a scenario
    is named. Returns (model Dataset, RunResult)."""
    from twin.api import simulate
    from twin.io.measured_inputs import scenario_from_measurement, sensors_of

    sc = scenario if scenario else scenario_from_measurement(measured)
    sensors = sensors_of(measured) or None
    return simulate(machine, sc, effects, settings, resolution, seed, progress=progress, sensors=sensors)


def add_compare_parser(subparsers) -> None:
    """``twin compare MEAS --machine NAME [--mapping TOML] [--scenario S] [--effects ..] [--set ..] [--mesh R]``."""
    p = subparsers.add_parser("compare", help="compare the twin with a measurement: residuals per channel and phase")
    add_measurement_options(p)
    add_model_options(p)
    p.set_defaults(func=run_compare)


def run_compare(args) -> int:
    """CLI body of ``twin compare``: prints the comparison table, returns 0."""
    from twin.io.measurement import read_measurement

    meas = read_measurement(args.measurement, getattr(args, "mapping", None), args.machine)
    model, _ = model_for(meas, args.machine, args.scenario, args.effects, args.set, args.mesh, args.seed)
    print(format_compare(compare(meas, model)))
    return 0
