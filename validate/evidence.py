"""The evidence a diagnosis weighs: one or several measurements held against one model.

A :class:`Record` is one measurement: its channels (any subset of the temperature sensors, the
ISO 230-3 probes, the laser triangulation sensors and the FBG strain gauges, compensated or raw,
:mod:`validate.channels`), the scenario that drives the twin, and an
:class:`validate.signatures.Engine` observing the twin at exactly those channels on the
measurement's time grid. A measurement with laser-interferometer runs gives a second record of
the same label, the positioning error at its targets on the runs' instants, observed by the same
engine (one twin run serves both). :class:`Evidence` stacks the records into flat vectors (record by
record, each (n_t, n_ch) block row-major), so one set of strengths is fitted to all of them
together: a spindle test and an ambient test separate effects that one run cannot.

Weights (per record and channel group g, so that temperatures, probes, lasers and strains count alike):

    w_c = 1 / (sqrt(s_g^2 + e_c^2) sqrt(m_g)),   s_g = max(RMS of the group's baseline residual, sigma_g),

m_g the group's channel count in the record, e_c the channel's estimated discretisation error
(0 without an estimate) and sigma_g the group's noise level: the median over its channels of
sqrt(mean(diff(y)^2) / 2), floored by half the instrument's quantisation step. So each group
weighs about its record's sample count n_t; the interferometer's record, a few runs of its
measurement, has its weights scaled by sqrt(n_t of the measurement / n_runs) so that its group
weighs as much as each group of the measurement. Its noise comes from the second difference
along the targets, sqrt(mean(d2^2) / 6) (the runs lie minutes apart: a difference in time is
signal), floored at :data:`POSITIONING_FLOOR`.

A twin result carries each FBG gauge twice (``strain``, compensated, and ``strain_raw``); the
diagnosis then uses the compensated reading only (the seed's), so no gauge counts twice; a
measurement with raw readings alone is diagnosed on them (the model then adds k_T dT_g).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from learners.metrics import rms
from twin.errors import InputError
from twin.io.measured_inputs import sensors_of
from twin.io.measurement import check_named_machine
from twin.model import ModelSpec
from validate.channels import RUN_GROUPS, input_phases, resampler, stack, stack_runs
from validate.signatures import Engine

# the channel groups a diagnosis fits (validate.channels), and the instrument whose resolution floors
# each group's noise level: (parameter group, parameter, factor to the channel's unit)
GROUPS = ("temperature", "probe", "laser", "positioning", "strain", "strain_raw")
RESOLUTION = {"temperature": ("temperature_sensor", "quantisation", 1.0), "probe": ("probe", "resolution", 1e6),
              "laser": ("laser_triangulation", "resolution", 1e6), "strain": ("fbg", "quantisation", 1e6),
              "strain_raw": ("fbg", "quantisation", 1e6)}
# [um] the positioning group's noise floor: half a 0.1 um step, the display resolution of ISO 230-2
# positioning software (the laser's own resolution is nanometres; plausible, no seed states one)
POSITIONING_FLOOR = 0.05
ALONG_TARGETS = ("positioning",)   # groups whose noise comes from differences along the channels


def diagnosed_groups(ds) -> tuple[str, ...]:
    """The groups of :data:`GROUPS` a diagnosis reads from ``ds``: ``strain_raw`` only without
    the compensated ``strain`` (each gauge counted once); the interferometer's group, read at its
    runs, has a record of its own (:func:`make_records`)."""
    return tuple(g for g in GROUPS if not (g == "strain_raw" and "strain" in ds) and g not in RUN_GROUPS)


def noise_levels(y: np.ndarray, groups: list[str], spec: ModelSpec) -> dict[str, float]:
    """Group noise sigma_g: median over channels of sqrt(mean(diff(y)^2)/2), floored at half the
    instrument's quantisation step (K, um or um/m; :data:`RESOLUTION`)."""
    floors = {g: 0.5 * spec.params[group][name] * f for g, (group, name, f) in RESOLUTION.items()}
    floors["positioning"] = POSITIONING_FLOOR
    d = np.sqrt(np.mean(np.diff(y, axis=0) ** 2, axis=0) / 2) if len(y) > 1 else np.zeros(y.shape[1])
    g = np.array(groups)
    out = {}
    for k in GROUPS:
        if not np.any(g == k):
            continue
        if k in ALONG_TARGETS:   # second difference along the targets (module docstring)
            block = y[:, g == k]
            level = float(np.sqrt(np.mean(np.diff(block, 2, axis=1) ** 2) / 6)) if block.shape[1] > 2 else 0.0
        else:
            level = float(np.median(d[g == k]))
        out[k] = max(level, floors[k], 1e-12)
    return out


def channel_weights(residual: np.ndarray, groups: list[str], sigma: dict[str, float],
                    model_error: np.ndarray | None = None, rows: int | None = None) -> np.ndarray:
    """w_c = 1 / (sqrt(s_g^2 + e_c^2) sqrt(m_g)), s_g = max(group residual RMS, sigma_g), e_c the
    RMS of the estimated model (discretisation) error of channel c (0 without an estimate); times
    sqrt(rows / n_t) when the record counts as ``rows`` samples (module docstring)."""
    g = np.array(groups)
    w = np.zeros(len(groups))
    e = np.zeros(len(groups)) if model_error is None else np.asarray(model_error, float)
    for k, s in sigma.items():
        m = g == k
        r = max(float(rms(residual[:, m])), s)
        w[m] = 1.0 / (np.sqrt(r ** 2 + e[m] ** 2) * np.sqrt(m.sum()))
    return w * (np.sqrt(rows / max(len(residual), 1)) if rows else 1.0)


def effective_samples(res: np.ndarray) -> float:
    """AR(1) effective sample size N (1 - rho) / (1 + rho), rho pooled lag-1 autocorrelation."""
    x = res - res.mean(axis=0)
    num = float(np.sum(x[1:] * x[:-1]))
    den = float(np.sum(x * x)) or 1.0
    rho = min(max(num / den, 0.0), 0.999)
    return max(res.size * (1 - rho) / (1 + rho), 2.0)


@dataclass
class Record:
    """One measurement held against the model: channels (n_ch) on its time grid (n_t) [s from its
    start; ``t0`` the log's own time of its first sample, which what a user reads (phases, worst
    times, plots) adds back], the engine observing the twin there, and (after :meth:`Evidence.baseline`) the
    baseline model, weights, noise levels and the model-error estimate per channel (its RMS, and
    the signed series when it came from another mesh)."""

    label: str
    ds: object
    scenario: object
    engine: Engine
    times: np.ndarray
    channels: list[str]
    groups: list[str]
    measured: np.ndarray
    columns: np.ndarray          # the engine's output columns of the channels
    phases: list = field(default_factory=list)
    t0: float = 0.0
    model: np.ndarray | None = None
    weights: np.ndarray | None = None
    noise: dict = field(default_factory=dict)
    model_error: np.ndarray | None = None
    model_error_series: np.ndarray | None = None
    error_engine: Engine | None = None   # the engine on the model-error mesh (when estimated from one)
    counts_as: int | None = None   # samples its groups weigh as (the interferometer's record), else n_t

    def __post_init__(self):
        self.interp = resampler(self.engine.times, self.times)

    @property
    def sensor_points(self) -> list:
        return self.engine.sensors

    def observe(self, spec: ModelSpec) -> np.ndarray:
        """(n_t, n_ch) the model's channels (sensor lag and bias, no noise) on the record's grid."""
        return self.interp(self.engine.observe(spec)[:, self.columns])

    def observe_with_expansion(self, spec: ModelSpec, materials: list[str]):
        """:meth:`observe` and the response (k, n_t, n_ch) to a unit relative change of each
        material's expansion coefficient, from one run."""
        out, resp = self.engine.observe_with_expansion(spec, materials)
        return self.interp(out[:, self.columns]), np.array([self.interp(r[:, self.columns]) for r in resp])


def make_records(label: str, ds, scenario, machine, twin) -> list[Record]:
    """The :class:`Record` of measurement ``ds`` driven by ``scenario`` on the prepared ``twin``,
    and, when ``ds`` has laser-interferometer runs, the record of their positioning error (same
    label, same engine; module docstring); InputError when it has no channel to diagnose, when it
    outlasts the scenario, or when its interferometer runs are not the scenario's."""
    check_named_machine(ds, machine.name, label, "the diagnosing model of")
    stacked = stack(ds, diagnosed_groups(ds))
    run_times, runs = stack_runs(ds)
    if not stacked.names and runs is None:
        raise InputError(label, "channels", "the measurement has no temperature sensor, probe, laser, strain "
                                            "gauge or interferometer run to diagnose")
    t = np.asarray(ds["time"].values, float)
    t0 = t[0]
    engine = Engine(machine, scenario, mm=twin.mm, sensors=sensors_of(ds, machine, label), prepared=twin)
    if runs is not None and engine.positioning is None:
        raise InputError(label, "positioning_error", "the measurement has laser-interferometer runs but the scenario "
                                                     "driving the twin has no [interferometer]: give --scenario with it")
    names = engine.names
    out = []
    for chans, times in ((stacked, t - t0), (runs, None if runs is None else run_times - t0)):
        if chans is None or not chans.names:
            continue
        missing = [c for c in chans.names if c not in names]
        if missing:
            what = "such instrument" if chans is stacked else "interferometer target there (the scenario's targets differ)"
            raise InputError(label, missing[0], f"machine {machine.name} has no {what}")
        columns = np.array([names.index(c) for c in chans.names], int)
        try:
            rec = Record(label, ds, scenario, engine, times, chans.names, chans.groups, chans.values, columns)
        except ValueError as err:
            raise InputError(label, "run_time" if chans is runs else "time", str(err)) from None
        rec.phases = input_phases(ds, t - t0, scenario) if chans is stacked else []
        rec.t0 = float(t0)
        out.append(rec)
    if len(out) > 1:
        out[1].counts_as = len(out[0].times)
    return out


class Evidence:
    """Records stacked into flat vectors (see the module docstring)."""

    def __init__(self, records: list[Record]):
        self.records = records
        self.sizes = [r.measured.size for r in records]
        self.offsets = np.concatenate([[0], np.cumsum(self.sizes)]).astype(int)

    @property
    def labels(self) -> list[str]:
        """The measurements' labels, each once (an interferometer record shares its measurement's)."""
        return list(dict.fromkeys(r.label for r in self.records))

    @property
    def multiple(self) -> bool:
        """Several measurements (a measurement's interferometer record shares its label)."""
        return len(self.labels) > 1

    def flat(self, blocks) -> np.ndarray:
        """One flat vector from per-record (n_t, n_ch) blocks."""
        return np.concatenate([np.asarray(b, float).ravel() for b in blocks]) if blocks else np.zeros(0)

    def split(self, vector: np.ndarray) -> list[np.ndarray]:
        """Per-record (n_t, n_ch) blocks of a flat vector."""
        return [vector[a:b].reshape(r.measured.shape) for r, a, b in zip(self.records, self.offsets[:-1], self.offsets[1:])]

    def observe(self, spec: ModelSpec) -> np.ndarray:
        """The model's channels of every record, flat."""
        return self.flat([r.observe(spec) for r in self.records])

    def observe_with_expansion(self, spec: ModelSpec, materials: list[str]):
        """(flat model, (k, N) flat expansion responses)."""
        outs = [r.observe_with_expansion(spec, materials) for r in self.records]
        model = self.flat([o for o, _ in outs])
        resp = np.array([self.flat([rs[k] for _, rs in outs]) for k in range(len(materials))])
        return model, resp.reshape(len(materials), model.size)

    @property
    def measured(self) -> np.ndarray:
        return self.flat([r.measured for r in self.records])

    def group_mask(self, group: str) -> np.ndarray:
        """Flat boolean mask of the samples of channel group ``group``."""
        return self.flat([np.broadcast_to(np.array(r.groups) == group, r.measured.shape) for r in self.records]) > 0

    def channel_names(self) -> list[str]:
        """Channel names over all records; with several records each ends in ``@label``."""
        if not self.multiple:
            return [c for r in self.records for c in r.channels]
        return [f"{c}@{r.label}" for r in self.records for c in r.channels]

    def per_channel(self, vector: np.ndarray, reduce=lambda x: rms(x, axis=0)) -> np.ndarray:
        """A per-channel statistic (default RMS over time) of a flat vector, channels in the order of
        :meth:`channel_names`."""
        return np.concatenate([reduce(b) for b in self.split(vector)]) if self.records else np.zeros(0)

    @property
    def runs(self) -> int:
        return sum(r.engine.runs for r in self.records)

    def effective_samples(self, residual_flat: np.ndarray) -> float:
        """Sum over records of :func:`effective_samples` of each record's residual."""
        return float(sum(effective_samples(b) for b in self.split(residual_flat)))

    def groups(self) -> list[str]:
        """The channel groups present, in :data:`GROUPS` order."""
        present = {g for r in self.records for g in r.groups}
        return [g for g in GROUPS if g in present]
