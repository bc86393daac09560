"""Output files appear whole or not at all: write to a temporary file beside the target, rename.

Every command that writes a result (NetCDF, pictures, JSON, CSV, HTML) goes through here, so an
error or an interrupt (Ctrl-C, or SIGTERM, which ``twin``'s entry point turns into an interrupt)
never leaves a half-written file under the requested name nor a temporary ``.twin-*`` file
beside it. The target is checked like every output (:func:`twin.io.paths.output_file`): a
directory, a device (``/dev/null``) or another non-regular file is never replaced. A failure to
write (disk full, permission) is an :class:`twin.errors.InputError` naming the file.

The paths written since :func:`forget_completed` are listed by :func:`completed`, so that an
interrupted command can say which of its outputs are whole.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path
from typing import Callable

from twin.errors import InputError
from twin.io.paths import output_file

_completed: list[Path] = []


def check_writable(path: str | os.PathLike, field: str = "output") -> Path:
    """Raise :class:`InputError` naming ``path`` unless it can be written as an output
    (:func:`twin.io.paths.output_file`; commands declare their files to :class:`twin.io.paths.Files`)."""
    return output_file(path, field)


# free space [bytes] a write must leave on its disk: less after writing means a writer may have
# stopped short without an error (Pillow's TIFF writer truncates silently on a full disk)
RESERVE = 1 << 20


def free_space(folder: Path) -> int:
    """Bytes free for this process on the disk holding ``folder``."""
    return shutil.disk_usage(folder).free


def atomic_write(path: str | os.PathLike, write: Callable[[str], object], field: str = "output",
                 size_hint: int | None = None) -> Path:
    """Call ``write(tmp)`` on a temporary path in the target's folder, then rename it to ``path``.

    A full disk is an :class:`InputError`, never a short file: with ``size_hint`` [bytes] (about
    the file's size) the disk must have that much and :data:`RESERVE` free before anything is
    written (HDF5 crashes the process when the disk fills under it), and after writing at least
    :data:`RESERVE` must be left (some writers stop short without an error); the file is synced
    to the disk before it is renamed."""
    return atomic_write_all([(path, write)], field, size_hint)[0]


def atomic_write_all(files, field: str = "output", size_hint: int | None = None) -> list[Path]:
    """Write several files that belong together (a measurement's CSV and its mapping): each
    ``(path, write)`` is written to its temporary file as :func:`atomic_write` does, and only when
    every one is whole are they renamed to their targets, so a failure (a full disk at the second)
    leaves none of them, not the first without the second. ``size_hint``: for all of them together."""
    paths = [output_file(path, field) for path, _ in files]
    if size_hint is not None:
        free = free_space(paths[0].parent)
        if free < size_hint + RESERVE:
            raise InputError(str(paths[0]), field, f"not enough free space on its disk: about "
                                                   f"{_mb(size_hint + RESERVE)} needed, {_mb(free)} free")
    temps: list[str | None] = []
    path = paths[0]                          # the file in hand, named by an OSError
    try:
        for path, (_, write) in zip(paths, files):
            fd, tmp = tempfile.mkstemp(prefix=".twin-", suffix=path.suffix, dir=path.parent)
            os.close(fd)
            temps.append(tmp)
            write(tmp)
            with open(tmp, "rb+") as handle:
                os.fsync(handle.fileno())
            if free_space(path.parent) < RESERVE:
                raise InputError(str(path), field, f"the disk is full (less than {_mb(RESERVE)} left after writing "
                                                   "it): the file may be incomplete and was not kept; free some space")
            os.chmod(tmp, 0o644)
            output_file(path, field)   # still a regular file (or nothing) right before the rename
        for i, path in enumerate(paths):
            os.replace(temps[i], path)
            temps[i] = None
            _completed.append(path)
    except OSError as err:
        raise InputError(str(path), field, f"could not be written ({getattr(err, 'strerror', None) or err})") from None
    finally:
        for tmp in temps:
            if tmp is not None:
                Path(tmp).unlink(missing_ok=True)
    return paths


def _mb(n: int) -> str:
    return f"{n / 1e6:.1f} MB"


def text_writer(text: str) -> Callable[[str], object]:
    """A ``write(tmp)`` for :func:`atomic_write` that writes ``text`` as UTF-8."""
    return lambda tmp: Path(tmp).write_text(text, encoding="utf-8")


def atomic_write_text(path: str | os.PathLike, text: str, field: str = "output") -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write(path, text_writer(text), field)


def completed() -> list[Path]:
    """The files :func:`atomic_write` finished since :func:`forget_completed`, in order."""
    return list(_completed)


def forget_completed() -> None:
    """Start a new list of finished files (the CLI calls it when a command starts)."""
    _completed.clear()


@contextlib.contextmanager
def output_folder(path: str | os.PathLike):
    """Create the folder ``path`` (its parent must exist) for the ``with`` block; if the block
    fails or is interrupted and the folder is still empty, remove it again (a failed command
    leaves no half-made folder). An existing folder is used as it is and never removed."""
    path = Path(path)
    created = not path.exists()
    if created:
        try:
            path.mkdir()
        except OSError as err:
            raise InputError(str(path), "output", f"cannot create the folder ({err.strerror or err})") from None
    try:
        yield path
    except BaseException:
        if created:
            try:
                path.rmdir()   # only when empty
            except OSError:
                pass
        raise
