"""The ``twin`` command line: ``list``, ``simulate``, ``plot``, ``frames`` from the core, and every command a
layer above registers through the ``thermal_twin.commands`` entry-point group (``demo``,
``compare``, ``diagnose`` from :mod:`validate`, ``learn`` from :mod:`learners`): the core never
imports them.

Bad input prints one line ``error: <file>: <field>: <message>`` on stderr and exits with code 2;
no partial output file is left behind (results are written to a temporary file, then renamed).
"""

from __future__ import annotations

import argparse
import os
import sys
from importlib.metadata import entry_points

from twin.errors import InputError

COMMAND_GROUP = "thermal_twin.commands"


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line ``error: command line: ...`` and exit code 2, like bad input."""

    def error(self, message):
        self.exit(2, f"error: command line: {self.prog}: {message}\n")


def registered_commands() -> list:
    """The entry points of :data:`COMMAND_GROUP`, sorted by name: each loads to a function
    ``add_parser(subparsers)`` that adds one subcommand and sets its ``func``."""
    return sorted(entry_points(group=COMMAND_GROUP), key=lambda ep: ep.name)


def build_parser() -> argparse.ArgumentParser:
    from twin.cli import cmd_frames, cmd_list, cmd_plot, cmd_simulate

    parser = _Parser(prog="twin", description="thermal-twin: digital twin of CNC machine-tool thermal errors")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for module in (cmd_list, cmd_simulate, cmd_plot, cmd_frames):
        module.add_parser(sub)
    for ep in registered_commands():
        ep.load()(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    try:
        return int(args.func(args) or 0)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader (e.g. `| head`) went away: stop writing, quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
