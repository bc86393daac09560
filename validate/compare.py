"""Model vs measurement: residuals per channel, RMSE / max |r| / NSE per channel and per phase.

Channels (:mod:`validate.channels`): every temperature sensor (``temperature:<sensor>``, K), every
probe (``probe:<id>``, um), the derived tilts (``tilt:<A|B>``, urad), lasers and strain gauges of the
measurement; each must be one the model has (a measured channel is never dropped silently). The
interferometer's runs (``positioning_error``) are not compared here (a diagnosis and the ISO 230-3
report read them): the result names them in ``not_compared``.
The model is read at the measured instants (linear interpolation in time), using its noise-free
variables (``*_true``) when present.
For a channel with measured values m_i and residuals r_i = m_i - y_i (y the model):

    RMSE = sqrt(mean r^2),   max|r|,   NSE = 1 - sum r^2 / sum (m - mean m)^2   (Nash-Sutcliffe),

NSE = 1 is a perfect fit, 0 no better than the measured mean. Phases come from the inputs
(:func:`validate.channels.detect_phases`): spindle off / on / speed change, and ambient rising / falling / steady.
Channels are ranked by the normalised RMSE = RMSE / std(m) (unit-free, sqrt(1 - NSE) over the
whole run); phase cells by RMSE in the phase / std(m) over the run.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from learners.metrics import max_abs_residual, nse, rmse
from twin.errors import InputError, describe
from twin.io.measurement import check_measurement, check_named_machine
from twin.io.times import check_times
from twin.io.results import dataset_source
from twin.limits import is_whole
from validate.channels import Phase, input_phases, not_held, stack


# readings a measurement may hold that compare does not hold against the model, and who reads them
READ_ELSEWHERE = (("positioning_error", "the laser interferometer's runs", "twin diagnose and twin report iso230-3 "
                                                                           "--test axis read them"),)


@dataclass
class Stats:
    rmse: float
    max_abs: float
    nse: float
    n: int


def normalised(rmse: float, spread: float) -> float:
    """rmse / spread; a flat measured channel (spread 0) scores 0 when matched and inf when off
    (worst of all: no scale makes its residual small), in the channel ranking and the phase cells
    alike, never a raw RMSE in K or um beside the others' ratios."""
    return rmse / spread if spread > 0 else (0.0 if rmse == 0 else np.inf)


@dataclass
class ChannelResult:
    name: str
    unit: str
    stats: Stats
    spread: float                                   # std of the measured channel over the run
    phases: list[Stats] = field(default_factory=list)  # one per CompareResult.phases entry

    @property
    def normalised_rmse(self) -> float:
        """RMSE / std of the measured channel over the run (:func:`normalised`)."""
        return normalised(self.stats.rmse, self.spread)


@dataclass
class CompareResult:
    channels: list[ChannelResult]
    phases: list[Phase]
    residuals: xr.Dataset   # residual(time, channel) = measured - model, with a unit per channel
    not_compared: list[str] = field(default_factory=list)   # the measurement's readings read elsewhere, and where

    def channel(self, name: str) -> ChannelResult:
        """The result of channel ``name`` (``temperature:<sensor>``, ``probe:<id>``, ...)."""
        found = next((c for c in self.channels if c.name == name), None)
        if found is None:
            raise InputError("compare", "channel", f"no channel {name!r}; compared: "
                                                   f"{', '.join(c.name for c in self.channels)}")
        return found

    def ranking(self) -> list[ChannelResult]:
        """Channels, worst (largest normalised RMSE) first."""
        return sorted(self.channels, key=lambda c: -c.normalised_rmse)

    def phase_ranking(self) -> list[tuple[ChannelResult, Phase, Stats, float]]:
        """(channel, phase, stats, RMSE / std(m)) for every phase cell, worst first."""
        cells = [(c, p, s, normalised(s.rmse, c.spread))
                 for c in self.channels for p, s in zip(self.phases, c.phases) if s.n]
        return sorted(cells, key=lambda x: -x[3])


def stats(measured: np.ndarray, residual: np.ndarray) -> Stats:
    """RMSE, max |r| and NSE (:mod:`learners.metrics`) of residuals r for measured values m; NSE is
    1 for a perfect fit of a constant channel (nothing to explain, nothing missed)."""
    n = len(residual)
    if n == 0:
        return Stats(np.nan, np.nan, np.nan, 0)
    model = measured - residual
    nse_ = nse(measured, model)
    if np.isnan(nse_) and not np.any(residual):
        nse_ = 1.0
    return Stats(rmse(measured, model), max_abs_residual(measured, model), nse_, n)


def compare(measured: xr.Dataset, model: xr.Dataset, phases: list[Phase] | None = None,
            model_true: bool = True) -> CompareResult:
    """Residuals measured - model on the measured instants, with per-channel and per-phase stats.

    Both time axes count from their first sample (a measurement logged from t0 is compared with a
    model run from 0). ``model_true``: use the model's noise-free variables where it has them.
    ``measured`` is checked as :func:`twin.io.measurement.read_measurement` checks a file (finite
    values, two or more increasing times), ``model`` is a twin result (a Dataset with increasing
    times) whose compared channels are finite; at least one channel must be in both.
    """
    source = dataset_source(measured)
    modelled = getattr(model, "attrs", {}).get("machine")
    if modelled is not None:
        check_named_machine(measured, str(modelled), source, "the model of")
    measured = check_measurement(measured, _named_machine(measured, model), source)
    if not isinstance(model, xr.Dataset) or "time" not in model.variables:
        raise InputError("compare", "model", f"expected a twin result (an xarray.Dataset with a time axis), got "
                                             f"{describe(model)}")
    check_times(np.asarray(model.time.values, float), "model", "time")
    if phases is not None and (not isinstance(phases, (list, tuple)) or not all(isinstance(p, Phase) for p in phases)):
        raise InputError("compare", "phases", f"expected a list of validate.channels.Phase, got {describe(phases)}")
    if not isinstance(model_true, bool):
        raise InputError("compare", "model_true", f"expected true or false, got {describe(model_true)}")
    t = np.asarray(measured.time.values, float)
    mod_t = np.asarray(model.time.values, float)
    t_mod = t - t[0] + mod_t[0]
    if t_mod[-1] > mod_t[-1] + 1e-6 * max(1.0, abs(mod_t[-1])):
        raise InputError(source, "time", f"the measurement spans {(t[-1] - t[0]) / 3600:g} h, the model "
                                         f"{(mod_t[-1] - mod_t[0]) / 3600:g} h: it must cover the whole measurement")
    meas, mod = stack(measured), stack(model, prefer_true=model_true)
    names = [c for c in meas.names if c in mod.names]
    if not names:
        raise InputError(source, "channels", f"no channel in common with the model: measured "
                                             f"{', '.join(meas.names[:6]) or 'none'}; modelled {', '.join(mod.names[:6])}"
                                             f"{' ...' if len(mod.names) > 6 else ''}")
    lacking = [c for c in meas.names if c not in mod.names]
    if lacking:     # a measured channel is never dropped without a word
        kind = lacking[0].split(":", 1)[0]
        alike = [c.split(":", 1)[1] for c in mod.names if c.startswith(kind + ":")]
        raise InputError(source, lacking[0], f"the model has no such channel ({len(lacking)} of the measurement's "
                                             f"{len(meas.names)} channels are not in it; the model's {kind} channels: "
                                             f"{', '.join(alike) or 'none'})")
    bad = [n for n in names if not np.all(np.isfinite(mod.values[:, mod.names.index(n)]))]
    if bad:
        raise InputError("model", bad[0], "is not finite (NaN or inf) in the model")
    if phases is None:
        phases = input_phases(measured, t)
    results, res = [], []
    for name in names:
        k = meas.names.index(name)
        m, unit = meas.values[:, k], meas.units[k]
        y = np.interp(t_mod, mod_t, mod.values[:, mod.names.index(name)])
        r = m - y
        res.append(r)
        per = [stats(m[sel], r[sel]) for sel in (p.mask(t) for p in phases)]
        results.append(ChannelResult(name, unit, stats(m, r), float(np.std(m)), per))
    data = np.column_stack(res) if res else np.zeros((len(t), 0))
    residuals = xr.Dataset(
        {"residual": (("time", "channel"), data, {"long_name": "measured minus model"})},
        coords={"time": ("time", t, {"units": "s"}), "channel": ("channel", names),
                "unit": ("channel", [meas.units[meas.names.index(n)] for n in names])})
    elsewhere = ([f"{var} ({what}; {where})" for var, what, where in READ_ELSEWHERE if var in measured]
                 + [f"{r}: no command holds it against the model yet" for r in not_held(measured)])
    return CompareResult(results, phases, residuals, elsewhere)


def _named_machine(measured, model):
    """The registered machine the measurement (else the model) names, for its limits; None when
    neither names one (the values are then checked against the limits of any machine)."""
    from geometries import MACHINES, build_machine

    names = [getattr(ds, "attrs", {}).get("machine") for ds in (measured, model)]
    name = next((str(n) for n in names if n is not None), None)
    return build_machine(name) if name in MACHINES else None


def format_compare(result: CompareResult, top: int = 8) -> str:
    """A terminal table: per-channel stats, then the worst channels and phase cells; the name
    columns as wide as their longest entry, so long sensor names keep the columns aligned;
    ``top``: how many worst channels and phase cells to list (an integer >= 1)."""
    if not is_whole(top) or top < 1:
        raise InputError("format_compare", "top", f"expected an integer >= 1, got {describe(top)}")
    w = max([26] + [len(c.name) for c in result.channels])
    pw = max([28] + [len(p.label) for p in result.phases])
    lines = [f"{'channel':<{w}} {'unit':>5} {'RMSE':>9} {'max|r|':>9} {'NSE':>7}"]
    for c in result.channels:
        s = c.stats
        lines.append(f"{c.name:<{w}} {c.unit:>5} {s.rmse:9.3g} {s.max_abs:9.3g} {s.nse:7.3f}")
    lines += ["", "phases:"]
    lines += [f"  {p.label:<{pw}} {p.start / 3600:7.2f} h .. {p.end / 3600:7.2f} h" for p in result.phases]
    lines += ["", "worst channels (RMSE / std of the measurement):"]
    ranked = result.ranking()[:top]
    lines += [f"  {f'{i + 1}.':<3} {c.name:<{w}} {c.normalised_rmse:7.3f}" for i, c in enumerate(ranked)]
    cells = result.phase_ranking()[:top]
    if cells:
        lines += ["", "worst phases (channel, phase, RMSE / std):"]
        lines += [f"  {f'{i + 1}.':<3} {c.name:<{w}} {p.label:<{pw}} {v:7.3f} (RMSE {s.rmse:.3g} {c.unit})"
                  for i, (c, p, s, v) in enumerate(cells)]
    if result.not_compared:
        lines += ["", "not compared here: " + "; ".join(result.not_compared)]
    return "\n".join(lines)


def model_for(measured: xr.Dataset, machine: str, scenario=None, effects: str | None = None,
              settings: list[str] | None = None, resolution: str = "default", seed: int = 0, progress=None,
              effects_file: str | None = None, prepared=None):
    """Simulate the twin at the measurement's sensor sites, driven by its inputs unless a scenario
    (a name, a path or a Scenario) is given; the custom effects of ``effects_file`` are switched
    on; ``prepared``: a :class:`twin.physics.prepared.PreparedTwin` of the machine on
    ``resolution`` to reuse (:func:`twin.api.simulate`). Returns (model Dataset, RunResult)."""
    from twin.api import machine_by_name, simulate
    from twin.io.measured_inputs import scenario_from_measurement, sensors_of

    source = dataset_source(measured)
    mach = machine_by_name(machine)
    check_named_machine(measured, mach.name, source)
    check_measurement(measured, mach, source)
    sc = scenario if scenario is not None else scenario_from_measurement(measured)
    sensors = sensors_of(measured, mach, source) or None
    return simulate(machine, sc, effects, settings, resolution, seed, progress=progress, sensors=sensors,
                    effects_file=effects_file, prepared=prepared)
