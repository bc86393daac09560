"""The diagnosing model's discretisation-error estimate: the model run on another mesh, less the
model on the diagnosing mesh, per channel over the record's grid,

    m_c(t) = y_c(model, other mesh; t) - y_c(model, diagnosing mesh; t),   e_c = RMS_t m_c,

for the baseline (:func:`mesh_error`) and, once a candidate is named, for the model *with* that
candidate at its fitted values (:func:`error_with`). The residual left after a candidate is held
against the error of the model that leaves it: a named cause whose own response the mesh resolves
less well (a nut heating a screw that the baseline lacks entirely, 14 um RMS on the interferometer
where the baseline's own error is 0.07 um) carries that error with it, which an estimate from the
baseline alone cannot hold.
"""

from __future__ import annotations

import numpy as np

from learners.metrics import rms
from twin.model import ModelSpec
from validate.signatures import Engine


def mesh_error(record, machine, spec: ModelSpec, resolution: str, other: Engine | None = None) -> np.ndarray:
    """(model on ``resolution``) - (model on the record's mesh) (times, channels), on the
    record's grid: the estimate of the diagnosing model's discretisation error, signed
    (``other``: an engine on ``resolution`` for the record's scenario and sensors, to reuse)."""
    other = other or Engine(machine, record.scenario, resolution, sensors=record.sensor_points)
    return record.interp(other.observe(spec)[:, record.columns]) - record.observe(spec)


def error_with(evidence, machine, spec: ModelSpec, resolution: str) -> np.ndarray:
    """Flat (every channel of every record, broadcast over its samples) RMS over time of
    :func:`mesh_error` of the model ``spec`` on each record, through the record's engine on the
    other mesh (``Record.error_engine``, kept from the baseline's estimate)."""
    blocks = []
    for rec in evidence.records:
        e = rms(mesh_error(rec, machine, spec, resolution, rec.error_engine), axis=0)
        blocks.append(np.broadcast_to(e, rec.measured.shape))
    return evidence.flat(blocks)
