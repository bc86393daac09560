"""The ``twin`` command line: ``list``, ``simulate``, ``plot``, ``frames``, ``dataset`` from the core, and every command a
layer above registers through the ``thermal_twin.commands`` entry-point group (``demo``,
``compare``, ``diagnose`` from :mod:`validate`, ``learn`` from :mod:`learners`): the core never
imports them.

Bad input prints one line ``error: <file>: <field>: <message>`` on stderr and exits with code 2;
no partial output file is left behind (results are written to a temporary file, then renamed).
An option that takes one value refuses a second one (argparse would silently keep the last) and an
empty one (it read as "not given").
Ctrl-C and SIGTERM stop the command, remove its temporary file and say in one line which outputs
are complete (exit code 130 and 143), also when they land inside a finaliser (:func:`_redeliver`).
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
from importlib.metadata import entry_points

from twin.errors import InputError
from twin.io import atomic

COMMAND_GROUP = "thermal_twin.commands"


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where the program is so that every cleanup (``finally``) runs."""


class _Once(argparse._StoreAction):
    """``store`` that refuses a second value (``--seed 1 --seed 2`` is an error, not seed 2) and
    an empty one (``--json ""`` read as "not given" wrote nothing and said nothing)."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_options_given", set())
        if option_string is not None and self.dest in seen:
            again = f" (again as {values!r})" if isinstance(values, str) else ""    # typed; a converted value reads as another
            raise argparse.ArgumentError(self, f"given more than once{again}; give it once")
        if option_string is not None and isinstance(values, str) and not values.strip():
            raise argparse.ArgumentError(self, "is empty: give a value, or leave the option out")
        seen.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


class Parser(argparse.ArgumentParser):
    """Usage errors as one line ``error: command line: <option>: <message>`` and exit code 2, like
    bad input; single-valued options refuse to be repeated."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.register("action", None, _Once)
        self.register("action", "store", _Once)

    def error(self, message):
        if message.endswith("required: command"):     # a bare ``twin``: say which commands there are
            commands = next(a.choices for a in self._actions if isinstance(a, argparse._SubParsersAction))
            message = f"give a command: {', '.join(commands)} (`twin -h` says what each does)"
        field, sep, rest = message.partition(": ") if message.startswith("argument ") else ("", "", message)
        field = field.removeprefix("argument ") if sep else self.prog
        self.exit(2, f"error: command line: {field}: {rest if sep else message}\n")


def registered_commands() -> list:
    """The entry points of :data:`COMMAND_GROUP`, sorted by name: each loads to a function
    ``add_parser(subparsers)`` that adds one subcommand and sets its ``func``."""
    return sorted(entry_points(group=COMMAND_GROUP), key=lambda ep: ep.name)


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The ``twin`` parser. Given the command line ``argv`` whose first word names a command, only
    that command's parser is built: the registered commands' modules (the learners import
    scikit-learn, the diagnosis scipy.stats) then load only when asked for, which halves the
    start of ``twin simulate``; otherwise (``twin --help``, an unknown word) every command."""
    from twin.cli import cmd_dataset, cmd_frames, cmd_list, cmd_plot, cmd_simulate
    from twin.version import package_version

    parser = Parser(prog="twin", description="thermal-twin: digital twin of CNC machine-tool thermal errors")
    parser.add_argument("--version", action="version", version=f"thermal-twin {package_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    builtin = {"list": cmd_list, "simulate": cmd_simulate, "plot": cmd_plot, "frames": cmd_frames,
               "dataset": cmd_dataset}
    registered = registered_commands()
    word = argv[0] if argv else None
    only = word if word in builtin or word in {ep.name for ep in registered} else None
    for name, module in builtin.items():
        if only is None or only == name:
            module.add_parser(sub)
    for ep in registered:
        if only is None or only == ep.name:
            ep.load()(sub)
    return parser


def _terminate(signum, frame):
    raise Terminated()


def _interrupted(err: KeyboardInterrupt) -> int:
    done = atomic.completed()
    whole = f"{', '.join(map(str, done))} complete, nothing else written" if done else "no output written"
    fresh_line = "\n" if sys.stderr.isatty() else ""   # after a progress bar
    print(f"{fresh_line}interrupted: {whole}", file=sys.stderr)
    return 143 if isinstance(err, Terminated) else 130


def _redeliver(previous_hook):
    """A :data:`sys.unraisablehook` that hands an interrupt back to the main thread: Ctrl-C or
    SIGTERM landing inside a finaliser or a weakref callback (the import system's module locks
    have one) is reported as "Exception ignored in ..." with a traceback and swallowed, and the
    command ran on to the end; it is raised again where the program is, through the signal's own
    handler (``_thread.interrupt_main``). A helper thread trips it 10 ms later: tripped from the
    hook itself, the handler would run inside the hook and be swallowed again."""
    import _thread
    import threading

    def hook(unraisable):
        exc = unraisable.exc_value
        if isinstance(exc, KeyboardInterrupt):
            sig = signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT
            threading.Timer(0.01, _thread.interrupt_main, (sig,)).start()
            return
        previous_hook(unraisable)

    return hook


def main(argv: list[str] | None = None) -> int:
    atomic.forget_completed()
    previous = None
    if signal.getsignal(signal.SIGTERM) is not signal.SIG_IGN:   # an ignored SIGTERM stays ignored
        try:
            previous = signal.signal(signal.SIGTERM, _terminate)
        except ValueError:  # not the main thread: leave signals alone
            pass
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _redeliver(previous_hook)
    try:
        return _main(argv)
    except KeyboardInterrupt as err:
        return _interrupted(err)
    finally:
        sys.unraisablehook = previous_hook
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:
        return int(exit_.code or 0)
    try:
        return int(args.func(args) or 0)
    except InputError as err:
        done = atomic.completed()   # a late failure (a full disk): say which outputs were made, whole
        also = f" (written before the error, each whole: {', '.join(map(str, done))})" if done else ""
        print(f"error: {err}{also}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader (e.g. `| head`) went away: stop writing, quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
