"""The commands the README (and ``validate/SCALE.md``) show parse: every ``twin ...`` line of a
shell block and every ``python -m validate...`` command (in a block or inline: the inline ``twin``
spans are mostly names of commands, not command lines) with concrete options names options and
choices that exist, so renaming an option cannot leave the documentation behind. Only the parsing
runs (``parse_args`` is stopped once it has succeeded), nothing is simulated."""

from __future__ import annotations

import argparse
import importlib
import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PLACEHOLDER = re.compile(r"\[|\.\.\.|[|<>]|(^|\s)[A-Z]+(\s|$)")    # [--opt], ..., pipes, M, S, N


class _Parsed(Exception):
    """Raised by the patched ``parse_args`` once the command line parsed."""


def _shell_lines(path: Path) -> list[str]:
    """The lines of the ``bash``/``sh``/bare fenced blocks, continuation lines joined, comments cut."""
    lines, block = [], None
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            block = (line.strip() in ("```", "```bash", "```sh")) if block is None else None
            continue
        if block:
            lines.append(line)
    joined = "\n".join(lines).replace("\\\n", " ")
    return [re.split(r"\s#", line)[0].strip() for line in joined.splitlines()]


def _inline_spans(path: Path) -> list[str]:
    """The text's inline code spans (`...` on one line)."""
    return re.findall(r"`([^`\n]+)`", path.read_text(encoding="utf-8"))


def _commands(prefix: str, paths, inline: bool = False) -> list[str]:
    """The commands starting with ``prefix`` in the documents' shell blocks (and, with ``inline``,
    their inline code spans) that hold no placeholder."""
    out = []
    for path in paths:
        for line in _shell_lines(ROOT / path) + (_inline_spans(ROOT / path) if inline else []):
            for part in line.split("&&"):
                part = part.strip()
                if part.startswith(prefix) and not PLACEHOLDER.search(part[len(prefix):]):
                    out.append(part)
    return sorted(set(out))


TWIN = _commands("twin ", ["README.md"])
VALIDATE = _commands("python -m validate", ["README.md", "validate/SCALE.md"], inline=True)


@pytest.fixture
def parse_only(monkeypatch):
    original = argparse.ArgumentParser.parse_args

    def parse_args(self, args=None, namespace=None):
        raise _Parsed(original(self, args, namespace))

    monkeypatch.setattr(argparse.ArgumentParser, "parse_args", parse_args)


def test_the_documents_show_commands_to_check():
    """The collection finds the README's commands (a broken collector would pass every test below)."""
    assert len(TWIN) >= 20 and len(VALIDATE) >= 15
    assert "twin demo" in TWIN and any(c.startswith("python -m validate.benchmark --spacing") for c in VALIDATE)


@pytest.mark.parametrize("command", TWIN)
def test_a_twin_command_of_the_readme_parses(command, parse_only, capsys):
    from twin.cli import main

    args = shlex.split(command)[1:]
    try:
        code = main(args)
    except _Parsed:
        return
    assert code == 0 and "-h" in args, capsys.readouterr().err


@pytest.mark.parametrize("command", VALIDATE)
def test_a_validate_command_of_the_documents_parses(command, parse_only, capsys):
    words = shlex.split(command)
    with pytest.raises(_Parsed):
        importlib.import_module(words[2]).main(words[3:])
