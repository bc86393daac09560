"""Progress bars for the command line (the library reports progress through callbacks)."""

from __future__ import annotations

import sys


def progress_bar(label: str, unit: str = "step"):
    """A ``progress(done, total)`` callback drawing a tqdm bar on stderr (only on a terminal);
    ``total`` may grow between calls (a diagnosis that goes on to try pairs)."""
    from tqdm import tqdm

    bar = {"tqdm": None}

    def update(done: int, total: int):
        if bar["tqdm"] is None:
            bar["tqdm"] = tqdm(total=total, desc=label, unit=unit, leave=False, file=sys.stderr,
                               disable=not sys.stderr.isatty())
        if total != bar["tqdm"].total:
            bar["tqdm"].total = total
        bar["tqdm"].update(done - bar["tqdm"].n)
        if done >= total:
            bar["tqdm"].close()

    return update
