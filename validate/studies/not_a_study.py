"""What ``python -m`` on a module the studies share says: it is not a study (exit code 2).

A module of its own, importing nothing of the studies, so the shared modules can call it without
an import cycle.
"""

from __future__ import annotations

import sys


def not_a_command(module: str) -> None:
    """``python -m`` on a module the studies share (not a study): one error line, exit code 2,
    instead of a silent exit 0."""
    print(f"error: python -m {module}: a module the studies use, not a study; the studies are listed in the "
          "README (\"Learner studies on the twin\" and the sections that name them)", file=sys.stderr)
    raise SystemExit(2)


if __name__ == "__main__":
    not_a_command("validate.studies.not_a_study")
