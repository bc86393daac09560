"""The files a command reads and writes, checked before any long work starts.

Every command declares its inputs and outputs to one :class:`Files` object first; each
declaration is checked at once and raises :class:`twin.errors.InputError` ``(path, field,
message)``, ``field`` being the option or argument that named the path:

* an input exists, is a regular file (not a directory, not a device or pipe) and is readable;
  text inputs (scenarios, mappings, CSV) are UTF-8 (a byte-order mark is allowed);
* an output is not a directory, not a device or other non-regular file, not read-only when it
  exists; its folder exists and a file can be created in it (tried, not guessed); its suffix is
  one the writer supports;
* no output is the same file as an input of the command (compared by resolved path, and with
  :func:`os.path.samefile` where both exist, so links and hard links count), and no two outputs
  are the same file;
* an output folder (``--report DIR``, ``demo -o DIR``) is a directory or can be created in an
  existing, writable parent; the files the command will write into it are checked like outputs.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path

from twin.errors import InputError, describe

NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf")


def _kind(mode: int) -> str:
    """A word for a non-regular file's type."""
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISFIFO(mode):
        return "a pipe"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def as_path(path, field: str = "file") -> Path:
    """``path`` (a text or an ``os.PathLike``, not empty, valid UTF-8) as a Path; anything else (a
    number, None, a name whose bytes are not UTF-8) is an :class:`InputError` naming ``field``, not
    pathlib's TypeError or a UnicodeEncodeError when the name is written into a result."""
    if isinstance(path, os.PathLike):
        path = os.fspath(path)
    if not isinstance(path, str) or not path.strip():
        raise InputError("command line", field, f"expected a file path, got {describe(path)}")
    try:
        path.encode("utf-8")
    except UnicodeEncodeError:     # bytes the file system gave that are not UTF-8 (surrogate escapes)
        raise InputError("command line", field, f"the path {ascii(path)} is not valid UTF-8: rename it (a result "
                                                "records its inputs' names as text)") from None
    return Path(path)


def input_file(path: str | os.PathLike, field: str = "file", what: str = "file") -> Path:
    """``path`` as a Path after checking it exists, is a regular file and is readable."""
    path = as_path(path, field)
    try:
        st = path.stat()
    except (FileNotFoundError, NotADirectoryError):
        raise InputError(str(path), field, f"no such {what}") from None
    except (OSError, ValueError) as err:
        raise InputError(str(path), field, f"cannot be read ({_reason(err)})") from None
    if not stat.S_ISREG(st.st_mode):
        raise InputError(str(path), field, f"is {_kind(st.st_mode)}, not a {what}")
    if not os.access(path, os.R_OK):
        raise InputError(str(path), field, "is not readable (permission denied)")
    return path


def read_text(path: str | os.PathLike, field: str = "file", what: str = "file") -> str:
    """The text of a UTF-8 input file (checked by :func:`input_file`; a byte-order mark is dropped)."""
    path = input_file(path, field, what)
    try:
        data = path.read_bytes()
    except OSError as err:
        raise InputError(str(path), field, f"cannot be read ({_reason(err)})") from None
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = data[:err.start].count(b"\n") + 1
        raise InputError(str(path), field, f"is not UTF-8 text (byte 0x{data[err.start]:02x} on line {line}); "
                                           "save it as UTF-8") from None


def read_toml(path: str | os.PathLike, field: str = "file", what: str = "file") -> tuple[dict, str]:
    """(parsed tables, text) of a UTF-8 TOML input file (:func:`read_text`); malformed TOML is an
    :class:`twin.errors.InputError` on the field ``toml``."""
    import tomllib

    text = read_text(path, field, what)
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as err:
        raise InputError(str(path), "toml", f"malformed TOML: {err}") from None


def _reason(err: BaseException) -> str:
    return getattr(err, "strerror", None) or str(err) or type(err).__name__


def _folder(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def _check_creatable(folder: Path, target: Path, field: str) -> None:
    """Raise unless ``folder`` is an existing directory in which a file can be created."""
    if not folder.exists():
        raise InputError(str(target), field, f"folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise InputError(str(target), field, f"{str(folder)!r} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(str(target), field, f"folder {str(folder)!r} is not writable")
    try:  # permissions are not the whole story (read-only mounts, quotas, ACLs): try it
        fd, probe = tempfile.mkstemp(prefix=".twin-", dir=folder)
    except OSError as err:
        raise InputError(str(target), field, f"cannot create a file in {str(folder)!r} ({_reason(err)})") from None
    os.close(fd)
    os.unlink(probe)


def output_file(path: str | os.PathLike, field: str = "output", suffixes: tuple[str, ...] | None = None,
                folder_may_be_created: bool = False) -> Path:
    """``path`` as a Path after checking it can be written as a new regular file (see the module
    doc). ``suffixes``: the ones the writer supports (None: any). ``folder_may_be_created``: the
    folder need not exist yet (it is checked by :func:`output_folder`). A path that ends in a
    separator (``out.nc/``) names a folder: refused (pathlib would drop the slash and write a file)."""
    raw = os.fspath(path) if isinstance(path, (str, os.PathLike)) else path
    path = as_path(path, field)
    if isinstance(raw, str) and raw.endswith(("/", os.sep)) and not path.is_dir():   # a folder: said below
        raise InputError(str(path), field, f"{raw!r} ends in a path separator, a folder's name; an output file "
                                           f"needs a file name (write {str(path)!r})")
    try:
        return _output_file(path, field, suffixes, folder_may_be_created)
    except InputError:
        raise
    except (OSError, ValueError) as err:   # a name too long, a loop of links, a NUL byte ...
        raise InputError(str(path), field, f"cannot be used as an output ({_reason(err)})") from None


def _output_file(path: Path, field: str, suffixes, folder_may_be_created: bool) -> Path:
    if path.is_symlink() and not path.exists():
        raise InputError(str(path), field, "is a dangling link")
    if path.exists():
        mode = path.stat().st_mode
        if not stat.S_ISREG(mode):
            raise InputError(str(path), field, f"is {_kind(mode)}; an output must be a regular file")
        if not os.access(path, os.W_OK):
            raise InputError(str(path), field, "exists and is read-only")
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise InputError(str(path), field, f"unsupported suffix {path.suffix or '(none)'!r}; use "
                                           f"{', '.join(suffixes)}")
    if not (folder_may_be_created and not _folder(path).exists()):
        _check_creatable(_folder(path), path, field)
    return path


def output_folder(path: str | os.PathLike, field: str = "output") -> Path:
    """``path`` as a Path after checking it is an existing writable folder, or can be created in
    an existing writable folder."""
    path = as_path(path, field)
    try:
        return _output_folder(path, field)
    except InputError:
        raise
    except (OSError, ValueError) as err:
        raise InputError(str(path), field, f"cannot be used as an output folder ({_reason(err)})") from None


def _output_folder(path: Path, field: str) -> Path:
    if path.exists() or path.is_symlink():
        if not path.is_dir():
            raise InputError(str(path), field, "exists and is not a folder")
        _check_creatable(path, path, field)
    else:
        _check_creatable(_folder(path), path, field)
    return path


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether ``a`` and ``b`` name the same file: equal resolved paths, or the same inode."""
    a, b = Path(a), Path(b)
    try:
        if a.resolve() == b.resolve():
            return True
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except (OSError, RuntimeError, ValueError):   # a loop of links, a name too long: not comparable
        return a == b


def within(path: str | os.PathLike, folder: str | os.PathLike) -> bool:
    """Whether ``path`` is ``folder`` or lies anywhere below it: ``folder`` compared with ``path``
    and each of its parent folders by :func:`same_file` (resolved path, then inode), so a link,
    a second spelling or a bind mount of ``folder`` counts as ``folder``."""
    here = Path(path).absolute()
    return any(same_file(ancestor, folder) for ancestor in (here, *here.parents))


class Files:
    """The inputs and outputs of one command, each checked when it is declared (module doc).

    Declare everything before the long work starts; the order does not matter: each new path is
    compared with every path declared before it.
    """

    def __init__(self):
        self.inputs: list[tuple[Path, str]] = []
        self.outputs: list[tuple[Path, str]] = []
        self.folders: list[tuple[Path, str]] = []

    def _clash(self, path: Path, field: str, output: bool) -> None:
        if not output:
            for out, out_field in self.outputs:
                if same_file(path, out):
                    raise InputError(str(out), out_field, f"is the input {str(path)!r} ({field}); an output never "
                                                          "replaces an input")
            return
        for other, other_field in self.inputs:
            if same_file(path, other):
                raise InputError(str(path), field, f"is the input {str(other)!r} ({other_field}); an output "
                                                   "never replaces an input")
        for other, other_field in self.outputs + self.folders:
            if same_file(path, other):
                raise InputError(str(path), field, f"is also the output of {other_field}")

    def input(self, path: str | os.PathLike, field: str, what: str = "file", once: bool = False) -> Path:
        """Declare a file the command reads; returns it checked (:func:`input_file`). ``once``:
        no other input of ``field`` is the same file (by any spelling, a link included: a run
        given twice would weigh twice)."""
        path = input_file(path, field, what)
        if once:
            for other, other_field in self.inputs:
                if other_field == field and same_file(path, other):
                    raise InputError(str(path), field, f"is the same file as {str(other)!r}, given before: give each "
                                                       "file once")
        self._clash(path, field, output=False)
        self.inputs.append((path, field))
        return path

    def output(self, path: str | os.PathLike, field: str, suffixes: tuple[str, ...] | None = None,
               folder_may_be_created: bool = False) -> Path:
        """Declare a file the command writes; returns it checked (:func:`output_file`)."""
        self._clash(as_path(path, field), field, output=True)
        path = output_file(path, field, suffixes, folder_may_be_created)
        self.outputs.append((path, field))
        return path

    def check_output(self, path: str | os.PathLike, field: str) -> None:
        """Check ``path`` like a declared output's clashes (never an input, never another declared
        output or folder) without recording it: for the many files of one kind whose first is
        declared (a camera's frames), where recording each would make every check compare with
        all the others."""
        self._clash(as_path(path, field), field, output=True)

    def folder(self, path: str | os.PathLike, field: str, contents: tuple[str, ...] = ()) -> Path:
        """Declare an output folder and the files (relative names, e.g. ``"report/index.html"``)
        the command writes into it; returns the folder checked (:func:`output_folder`)."""
        self._clash(as_path(path, field), field, output=True)
        folder = output_folder(path, field)
        self.folders.append((folder, field))
        for name in contents:
            self.output(folder / name, field, folder_may_be_created=True)
        return folder
