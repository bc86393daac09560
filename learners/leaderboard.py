"""A leaderboard: learners fitted on training runs and scored against the known truth of test runs.

Each learner is fitted once on the training runs (:func:`learners.runs.fit_runs`: pooled learners
on all rows, time-ordered ones on each run's own sequence) and predicts every test run from its own
start. A row per learner and test set holds, on the residuals ``r = prediction - truth`` of all the
set's runs together, in the target's unit (the row's ``unit``: um for a drift, urad for a tilt):

    RMSE = sqrt(mean r^2),   NSE = 1 - sum r^2 / sum (y - mean y)^2,   R (Pearson),
    max |r|,   p95 |r| (the 95th percentile of |r|, linear interpolation),
    improvement % = 100 (1 - max |r| / max |y|),   MRE %

The wall-clock time of each ``fit`` goes into ``timings`` when one is given (the command shows
it), never into the rows: the same inputs and seed give the same rows, and the same files.

(:mod:`learners.metrics`).

With ``segments = N > 1`` each set also gets a row per time segment k = 1..N: rows
``[(k-1) n / N, k n / N)`` of every run (n its length), pooled over the runs, so a learner that
is good at the start of a run and drifts away later shows it. A learner that refuses the data
(``ValueError``) or predicts non-finite values is an :class:`twin.errors.InputError` naming the
runs and the learner.
"""

from __future__ import annotations

import contextlib
import csv
import time

import numpy as np

from learners.metrics import abs_residual_percentile, score_all
from learners.runs import fit_runs
from twin.errors import InputError
from twin.io.atomic import atomic_write, atomic_write_text
from twin.io.markdown import table

__all__ = ["COLUMNS", "as_input_error", "segments_of", "leaderboard", "fit_note", "notes", "write_csv", "markdown",
           "write_markdown"]

COLUMNS = ["learner", "test", "rmse", "nse", "r", "max_abs_residual", "p95_abs_residual", "improvement_pct", "mre_pct",
           "unit", "inputs", "note"]
HEADINGS = ["learner", "test", "RMSE", "NSE", "R", "max|res|", "p95|res|", "improv. %", "MRE %", "unit", "inputs",
            "note"]
IN_UNIT = ("rmse", "max_abs_residual", "p95_abs_residual")   # the columns in the target's unit


@contextlib.contextmanager
def as_input_error(source, field):
    """A learner or selector refusing the user's data (ValueError) becomes an InputError."""
    try:
        yield
    except ValueError as exc:
        text = exc.message if isinstance(exc, InputError) else str(exc).strip()
        raise InputError(source, field, text.splitlines()[0] if text else type(exc).__name__) from None


def segments_of(label: str, lengths: list[int], n: int):
    """(label, [slice per run]) of the whole runs, then, for ``n > 1``, of each time segment k:
    rows ``[k len / n, (k + 1) len / n)`` of every run."""
    yield label, [slice(None)] * len(lengths)
    if n > 1:
        for k in range(n):
            yield f"{label} [segment {k + 1}/{n}]", [slice(k * m // n, (k + 1) * m // n) for m in lengths]


def leaderboard(learners: dict, train_runs: list, test_sets: list, *, segments: int = 1, inputs: str = "",
                train_label: str = "training runs", progress=None, unit: str = "",
                timings: dict | None = None) -> list[dict]:
    """Rows (``COLUMNS``) for ``learners`` = {name: unfitted estimator}, ``train_runs`` =
    [(X, y), ...] and ``test_sets`` = [(label, [(X, y), ...]), ...] (module doc). ``inputs``: the
    input names written in each row; ``unit``: the target's unit, written in each row ("" when
    not known); ``progress(done, total)`` is called after each learner; ``timings`` (a dict)
    receives each learner's fit time [s, wall clock]."""
    rows = []
    for done, (name, est) in enumerate(learners.items(), start=1):
        start = time.perf_counter()
        with as_input_error(train_label, name):
            fit_runs(est, train_runs, name)
        if timings is not None:
            timings[name] = time.perf_counter() - start
        note = fit_note(est)
        for label, runs in test_sets:
            with as_input_error(label, name):
                preds = [np.asarray(est.predict(X), dtype=float).ravel() for X, _ in runs]   # each run from its start
            if not all(np.all(np.isfinite(p)) for p in preds):
                raise InputError(str(label), name, "the learner's predictions are not finite (it diverged on "
                                                   "these data); no scores are written")
            truth = [np.asarray(y, dtype=float).ravel() for _, y in runs]
            for seg_label, pick in segments_of(str(label), [len(y) for y in truth], segments):
                z = np.concatenate([y[s] for y, s in zip(truth, pick)])
                p = np.concatenate([q[s] for q, s in zip(preds, pick)])
                scores = _defined_scores(z, p, seg_label, name, segment=seg_label != str(label))
                rows.append({"learner": name, "test": seg_label, **scores,
                             "p95_abs_residual": abs_residual_percentile(z, p), "unit": unit, "inputs": inputs,
                             "note": note})
        if progress is not None:
            progress(done, len(learners))
    return rows


def fit_note(estimator) -> str:
    """What a fitted learner says of its own fit that its scores do not ("" when nothing): a
    coefficient pinned at its search range's end is not a fitted one (``at_bound_``: the grey
    models' development coefficient, or the parameters a learner's ``bound_subject`` names), and
    a training set thinned to ``max_samples`` rows (``thinned_``, LS-SVM) is not the whole one,
    and a learner that reads no input (``uses_inputs`` False, GM(1,1)) is not one of them."""
    notes = []
    bound = getattr(estimator, "at_bound_", "") or ""
    if bound:
        subject = getattr(estimator, "bound_subject", "its development coefficient sits")
        notes.append(f"{subject} {bound}: pinned at the bound, not determined by the data")
    thinned = getattr(estimator, "thinned_", "") or ""
    if thinned:
        notes.append(thinned)
    if getattr(estimator, "uses_inputs", True) is False:
        notes.append("uses none of the inputs listed: it extrapolates the target's own training series (a test "
                     "table's rows set only the horizon)")
    return "; ".join(notes)


def notes(rows) -> list[str]:
    """One line per learner with a :func:`fit_note`, in the rows' order."""
    return [f"{learner}: {note}" for learner, note in dict.fromkeys((r["learner"], r.get("note", "")) for r in rows) if note]


MIN_SEGMENT_ROWS = 3    # rows a scored segment needs (NSE and R compare a segment's spread)


def check_segments(test_sets: list, n: int, source: str, option: str = "--segments") -> None:
    """Before any learner runs: every time segment of every test set ([(label, [(X, y), ...])],
    :func:`segments_of`) holds at least :data:`MIN_SEGMENT_ROWS` rows; else one
    :class:`InputError` naming ``source`` (the test data), the segment, and the most segments
    these runs allow."""
    if n <= 1:
        return
    lengths = [[len(y) for _, y in runs] for _, runs in test_sets]

    def rows(m: int, ls: list[int]) -> int:   # the fewest rows of the m segments segments_of cuts
        cuts = list(segments_of("", ls, m))[1:] or [("", [slice(None)] * len(ls))]
        return min(sum(len(range(L)[s]) for L, s in zip(ls, slices)) for _, slices in cuts)
    for (label, _), ls in zip(test_sets, lengths):
        if rows(n, ls) < MIN_SEGMENT_ROWS:
            most = max((m for m in range(1, n) if all(rows(m, x) >= MIN_SEGMENT_ROWS for x in lengths)), default=1)
            raise InputError(source, option, f"{n} segments leave {rows(n, ls)} row(s) in a segment of {label}; a "
                                             f"scored segment needs at least {MIN_SEGMENT_ROWS}: give {option} {most} "
                                             "or fewer")


def _defined_scores(z: np.ndarray, p: np.ndarray, label: str, learner: str, segment: bool) -> dict:
    """score_all(z, p) as floats; an :class:`InputError` where the test data leave the scores
    undefined (a segment of fewer than :data:`MIN_SEGMENT_ROWS` rows, a constant target: NSE and
    R divide by its spread), never a NaN score for them. R of a constant prediction (a baseline
    that predicts nothing) stays undefined: that is the learner's answer, not the data's."""
    field = "--segments" if segment else learner
    if segment and len(z) < MIN_SEGMENT_ROWS:
        raise InputError(label, field, f"holds {len(z)} row(s); a scored segment needs at least {MIN_SEGMENT_ROWS}: "
                                       "use fewer segments")
    if np.ptp(z) == 0:
        raise InputError(label, field, f"the target is constant there ({z[0]:g}): NSE and R are undefined"
                                       + ("; use fewer segments" if segment else ""))
    return {k: float(v) for k, v in score_all(z, p).items()}


def write_csv(path, rows, field: str = "-o"):
    """Write ``rows`` (``COLUMNS``) as CSV, atomically (10 significant digits)."""
    def write(tmp):
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(COLUMNS)
            for r in rows:
                writer.writerow([f"{r[c]:.10g}" if isinstance(r[c], float) else r[c] for c in COLUMNS])

    return atomic_write(path, write, field=field)


def _cell(value, column):
    if not isinstance(value, float):
        return str(value)
    if not np.isfinite(value):
        return "nan"
    return f"{value:.2f}" if column in ("improvement_pct", "mre_pct") else f"{value:.4g}"


def unit_heading(unit: str) -> str:
    """How a heading names the target's unit: "um", or "(target's unit)" when not known."""
    return unit or "(target's unit)"


def markdown(rows, title: str = "Leaderboard", note: str = "") -> str:
    """A Markdown page: ``title``, ``note``, then one table per test set (its whole runs first,
    then its segments), each table's learners sorted by their RMSE in it (a segment's table by
    the segment's RMSE: the best learner of a segment may not be the best overall); the inputs listed once, the
    target's unit in the headings (the rows' ``unit``)."""
    lines = [f"# {title}", ""]
    if note:
        lines += [note, ""]
    inputs = sorted({r["inputs"] for r in rows})
    units = sorted({r["unit"] for r in rows})
    if len(units) > 1:
        raise ValueError(f"the rows are in different units ({', '.join(units)}); one table needs one unit")
    unit = unit_heading(units[0] if units else "")
    cols = [c for c in COLUMNS if c not in ("test", "inputs", "unit", "note")]
    heads = [(h if c not in IN_UNIT else f"{h} {unit}") for h, c in zip(HEADINGS, COLUMNS) if c in cols]
    for test in dict.fromkeys(r["test"] for r in rows):
        part = sorted((r for r in rows if r["test"] == test), key=lambda r: (np.nan_to_num(r["rmse"], nan=np.inf)))
        lines += [f"## {test}", "", *table(heads, [[_cell(r[c], c) for c in cols] for r in part])]
        lines.append("")
    if len(inputs) == 1 and inputs[0]:
        lines += [f"Inputs: {inputs[0].replace(';', ', ')}.", ""]
    remarks = notes(rows)
    lines += [f"Note: {line}." for line in remarks] + ([""] if remarks else [])
    return "\n".join(lines)


def write_markdown(path, rows, field: str = "-o", **kwargs):
    """Write :func:`markdown` of ``rows`` to ``path``, atomically."""
    return atomic_write_text(path, markdown(rows, **kwargs), field=field)
