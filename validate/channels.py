"""One channel vocabulary for compare, diagnose, report and JSON, and the input phases.

A *channel* is one measured signal of a result or measurement, named ``<group>:<label>``:

* ``temperature:<sensor>`` (degC as read; residuals in K) from ``temperature(time, sensor)``;
* ``probe:<id>`` [um] from ``probe(time, probe_id)``;
* ``tilt:<A|B>`` [urad] from ``tilt(time, rotation)``;
* ``laser:<id>`` [um] from ``laser(time, laser_id)`` (laser triangulation on a test bar);
* ``strain:<gauge>`` [um/m] from ``strain(time, gauge)`` (FBG, compensated with the nearest
  temperature sensor) and ``strain_raw:<gauge>`` [um/m] from ``strain_raw(time, gauge)`` (the
  grating's reading, with its temperature cross-sensitivity);
* ``positioning:<target mm>`` [um] from ``positioning_error(run_time, target, direction)`` (the
  laser interferometer's thermal positioning error, ISO 230-2 runs), the mean of the two
  directions; read at its runs, not on the ``time`` grid (:data:`RUN_GROUPS`).

:func:`stack` reads any subset of the groups from a Dataset into one (n_t, n_ch) array with names,
groups and units, using the noise-free ``*_true`` variables on request. The strain groups have
none: a result's ``strain_true`` is the strain itself, without the grating's cross-sensitivity
and its compensation, so the model's reading (with its instrument noise) stands for it. Phases of the inputs
(spindle on/off/speed change, ambient rising/falling/steady) come from :func:`detect_phases`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from twin.io.measured_inputs import speed_steps

# group -> (dimension of the variable besides time, unit of a residual)
GROUPS: dict[str, tuple[str, str]] = {"temperature": ("sensor", "K"), "probe": ("probe_id", "um"),
                                      "tilt": ("rotation", "urad"), "laser": ("laser_id", "um"),
                                      "strain": ("gauge", "um/m"), "strain_raw": ("gauge", "um/m")}
NO_TRUE = ("strain", "strain_raw")   # groups whose *_true variable is not the same reading
# groups read at instants of their own: group -> (variable, channel dimension, time dimension, unit)
RUN_GROUPS: dict[str, tuple[str, str, str, str]] = {"positioning": ("positioning_error", "target", "run_time", "um")}


# readings a measurement may hold that neither a comparison nor a diagnosis holds against the model
# yet: variable -> what it is (each command names them, never drops them without a word)
NOT_HELD = {"probing_error": "the probing cycles' datum errors"}


def not_held(ds) -> list[str]:
    """The :data:`NOT_HELD` readings of ``ds``, each as 'variable (what it is)'."""
    return [f"{var} ({what})" for var, what in NOT_HELD.items() if var in ds]


def residual_unit(group: str) -> str:
    """The unit of a residual of channel ``group`` (:data:`GROUPS` and :data:`RUN_GROUPS`)."""
    return GROUPS[group][1] if group in GROUPS else RUN_GROUPS[group][3]


def channel(group: str, label) -> str:
    """The channel name of ``label`` in ``group`` (``"probe:Y1"``)."""
    return f"{group}:{label}"


def split(name: str) -> tuple[str, str]:
    """(group, label) of a channel name."""
    group, label = name.split(":", 1)
    return group, label


@dataclass
class Channels:
    """Stacked channels: ``values`` (n_t, n_ch), and per channel its name, group and unit."""

    values: np.ndarray
    names: list[str]
    groups: list[str]
    units: list[str]

    def index(self, group: str) -> list[int]:
        """Columns of the channels in ``group``."""
        return [i for i, g in enumerate(self.groups) if g == group]


def stack(ds, groups=tuple(GROUPS), prefer_true: bool = False) -> Channels:
    """The channels of ``groups`` present in ``ds`` (a result or a measurement), in group order.
    ``prefer_true``: read ``<group>_true`` where the Dataset has it (the model's noise-free truth)."""
    cols, names, gs, units = [], [], [], []
    for group in groups:
        dim, unit = GROUPS[group]
        var = f"{group}_true" if prefer_true and f"{group}_true" in ds and group not in NO_TRUE else group
        if var not in ds or dim not in ds[var].dims:
            continue
        cols.append(np.asarray(ds[var].transpose("time", dim).values, float))
        labels = [str(v) for v in ds[dim].values]
        names += [channel(group, v) for v in labels]
        gs += [group] * len(labels)
        units += [unit] * len(labels)
    values = np.hstack(cols) if cols else np.zeros((ds.sizes.get("time", 0), 0))
    return Channels(values, names, gs, units)


def target_label(position_mm: float) -> str:
    """The label of an interferometer target at ``position_mm`` [mm] (``"30"``)."""
    return f"{float(position_mm):.6g}"


def stack_runs(ds, group: str = "positioning") -> tuple[np.ndarray, Channels]:
    """(instants [s], channels) of a group of :data:`RUN_GROUPS` in ``ds`` (None, None when absent):
    the interferometer's positioning error per run and target [um], the mean of both directions
    (the twin has no reversal error; a measured one cancels in the mean)."""
    var, dim, tdim, unit = RUN_GROUPS[group]
    if var not in ds:
        return None, None
    v = ds[var]
    if "direction" in v.dims:
        v = v.mean("direction")
    values = np.asarray(v.transpose(tdim, dim).values, float)
    labels = [target_label(t) for t in ds[dim].values]
    return (np.asarray(ds[tdim].values, float),
            Channels(values, [channel(group, t) for t in labels], [group] * len(labels), [unit] * len(labels)))


@dataclass
class Phase:
    """A stretch of time [start, end) [s] with one behaviour of the inputs; the record's last
    phase of its kind ends at the last sample and holds it ([start, end], ``closed``)."""

    kind: str     # "spindle" or "ambient"
    label: str    # e.g. "spindle on 9000 rpm", "speed change to 6000 rpm", "ambient rising"
    start: float
    end: float
    closed: bool = False

    def mask(self, t: np.ndarray) -> np.ndarray:
        """Which of the instants ``t`` [s] fall in the phase."""
        t = np.asarray(t, float)
        return (t >= self.start) & ((t <= self.end) if self.closed else (t < self.end))


def _segments(labels: list[str], t: np.ndarray) -> list[tuple[str, float, float]]:
    out = []
    for i, lab in enumerate(labels):
        if out and out[-1][0] == lab:
            out[-1][2] = i
        else:
            out.append([lab, i, i])
    end = lambda j: float(t[j + 1]) if j + 1 < len(t) else float(t[-1])
    return [(lab, float(t[i0]), end(i1)) for lab, i0, i1 in out]


def detect_phases(time: np.ndarray, speed: np.ndarray | None = None, ambient: np.ndarray | None = None,
                  speed_tolerance: float = 50.0, ambient_rate: float = 0.1 / 3600.0,
                  smooth: float = 1800.0, c_axis: np.ndarray | None = None) -> list[Phase]:
    """Phases of the inputs.

    Spindle: steps of :func:`twin.io.measured_inputs.speed_steps` labelled "spindle off" (0 rpm),
    "spindle on N rpm" (after a stop or at the start) or "speed change to N rpm" (after another
    speed); the C axis (``c_axis``: its speed [rpm] where it turns, when it turns at all) likewise,
    kind ``c_axis``, "C axis off" / "C axis on N rpm" (then without spindle phases when the spindle
    never turns). Ambient: the sign of dT_air/dt [K/s], smoothed by a centred moving average over
    ``smooth`` [s], "rising" above ``ambient_rate`` (default 0.1 K/h), "falling" below its
    negative, else "steady"; ambient stretches shorter than ``smooth`` merge into their predecessor.
    """
    t = np.asarray(time, float)
    phases: list[Phase] = []
    axes = [("spindle", "spindle", speed)]
    if c_axis is not None and np.any(np.asarray(c_axis) > 0):
        axes.append(("c_axis", "C axis", c_axis))
        if speed is None or not np.any(np.asarray(speed) > speed_tolerance):
            axes = axes[1:]   # a C-axis test: the spindle at rest throughout says nothing
    for kind, name, trace in axes:
        if trace is None:
            continue
        prev, mine = 0.0, []
        for t0, t1, n in speed_steps(t, trace, speed_tolerance):
            if n == 0:
                label = f"{name} off"
            elif prev == 0:
                label = f"{name} on {n:.0f} rpm"
            else:
                label = f"speed change to {n:.0f} rpm" if kind == "spindle" else f"{name} speed change to {n:.0f} rpm"
            mine.append(Phase(kind, label, t0, t1 if t1 > t0 else t0))
            prev = n
        if mine:
            mine[-1].end, mine[-1].closed = float(t[-1]), True
        phases += mine
    if ambient is not None and len(t) > 2:
        a = np.asarray(ambient, float)
        dt = float(np.median(np.diff(t)))
        w = max(1, int(round(smooth / dt)))
        kernel = np.ones(w) / w
        pad = np.pad(a, (w // 2, w - 1 - w // 2), mode="edge")
        rate = np.gradient(np.convolve(pad, kernel, mode="valid"), t)
        labels = ["ambient rising" if r > ambient_rate else "ambient falling" if r < -ambient_rate else "ambient steady"
                  for r in rate]
        merged: list[list] = []
        for lab, t0, t1 in _segments(labels, t):
            if merged and (t1 - t0 < smooth or merged[-1][0] == lab):
                merged[-1][2] = t1
            else:
                merged.append([lab, t0, t1])
        phases += [Phase("ambient", lab, t0, t1, closed=k == len(merged) - 1) for k, (lab, t0, t1) in enumerate(merged)]
    return phases


def resampler(t_model: np.ndarray, t_meas: np.ndarray):
    """A function taking model outputs (n_model, k) on ``t_model`` [s] to the measurement's
    instants ``t_meas`` (linear in time); identity when the grids agree. ValueError if the
    measurement reaches outside the model's time span."""
    if len(t_model) == len(t_meas) and np.allclose(t_model, t_meas):
        return lambda y: y
    if t_meas.min() < t_model[0] - 1e-9 or t_meas.max() > t_model[-1] + 1e-9:
        raise ValueError("measurement times lie outside the scenario's duration")
    return lambda y: np.column_stack([np.interp(t_meas, t_model, y[:, k]) for k in range(y.shape[1])])


def input_phases(ds, t: np.ndarray, scenario=None) -> list[Phase]:
    """Phases of the inputs on the grid ``t`` [s]: the Dataset's logged spindle speed, C-axis speed
    (where its duty is not 0) and room air where it has them, else the ``scenario``'s (no phases of an
    input neither gives)."""
    def signal(var, of_scenario):
        if var in ds:
            return np.asarray(ds[var].values, float)
        return None if scenario is None or of_scenario is None else np.asarray(of_scenario(t), float)

    c_sched = getattr(scenario, "c_axis", None)
    c_axis = (np.asarray(ds.c_axis_speed.values, float) * (np.asarray(ds.c_axis_duty.values, float) > 0
                                                            if "c_axis_duty" in ds else 1.0)
              if "c_axis_speed" in ds else
              (c_sched.speed(t) * (c_sched.duty(t) > 0) if c_sched is not None else None))
    return detect_phases(t, signal("spindle_speed", getattr(scenario, "spindle_speed", None)),
                         signal("ambient_temperature", getattr(scenario, "ambient_temperature", None)),
                         c_axis=c_axis)
