"""One error type for bad user input.

Every problem with what a user gave us (an unknown name, a malformed file, a value with the wrong
unit, a missing column, a NaN) is raised as :class:`InputError`, naming the *source* (a file path,
``"--set"``, ``"command line"`` ...) and the *field* (a TOML key, a CSV column, a parameter). The CLI
turns it into one line on stderr and exit code 2.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad user input: ``InputError(source, field, message)``.

    ``str(err)`` reads ``"<source>: <field>: <message>"``.
    """

    def __init__(self, source: str, field: str, message: str):
        self.source = str(source)
        self.field = str(field)
        self.message = str(message)
        super().__init__(f"{self.source}: {self.field}: {self.message}")
