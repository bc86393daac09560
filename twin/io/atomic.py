"""Output files appear whole or not at all: write to a temporary file beside the target, rename.

Every command that writes a result (NetCDF, pictures, JSON, CSV, HTML) goes through here, so an
error or an interrupt never leaves a half-written file under the requested name.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Callable

from twin.errors import InputError


def check_writable(path: str | os.PathLike, field: str = "output") -> Path:
    """Raise :class:`InputError` naming ``path`` unless its folder exists and is writable."""
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(str(path), field, f"folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK):
        raise InputError(str(path), field, f"folder {str(folder)!r} is not writable")
    return path


def atomic_write(path: str | os.PathLike, write: Callable[[str], object], field: str = "output") -> Path:
    """Call ``write(tmp)`` on a temporary path in the target's folder, then rename it to ``path``."""
    path = check_writable(path, field)
    fd, tmp = tempfile.mkstemp(prefix=".twin-", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def atomic_write_text(path: str | os.PathLike, text: str, field: str = "output") -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"), field)
