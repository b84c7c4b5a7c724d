"""The one check of every file a user names: a regular file to read, a plain path to write.

asperity opens a file because a user named it (a height map, a job or friction TOML, a
measured CSV, an ``--out`` file). A FIFO would block the read forever, ``/dev/zero`` would
fill the memory, a directory or a socket cannot be read: each is refused at once, in one
line that says what the path is, e.g.
``surface.file: /tmp/f is a FIFO (named pipe), expected a regular file``. Symbolic links
are followed and the target judged (a link to a FIFO is refused as a FIFO, and the message
says it is a link). Files are opened without blocking (``O_NONBLOCK``) and the kind is
checked again on the open descriptor, so a FIFO swapped in after the check cannot hang a
read either.
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
from pathlib import Path

from asperity.errors import InputError

__all__ = [
    "MAX_CONFIG_BYTES",
    "SpecialFileError",
    "describe_kind",
    "require_regular_file",
    "require_output_path",
    "require_output_dir",
    "read_bytes_bounded",
]


#: Largest configuration (job or friction TOML) read, bytes (16 MiB; a job file is a few kB).
MAX_CONFIG_BYTES = 16 * 1024**2


class SpecialFileError(InputError):
    """A path names a FIFO, a device, a directory or a socket where a regular file is needed."""


#: The kinds of file, in words, with the ``stat`` test that recognises each.
_KINDS = (
    (stat.S_ISREG, "a regular file"),
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _kind_of_mode(mode: int) -> str:
    """What a ``st_mode`` is, in words (``"a FIFO (named pipe)"``, ``"a directory"``, ...)."""
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def describe_kind(path: str | Path) -> str | None:
    """What ``path`` is, in words, or None if nothing is there.

    Parameters
    ----------
    path : str or Path
        Any path; a symbolic link is followed (and said: ``"a symlink to a FIFO ..."``).

    Returns
    -------
    str or None
        ``"a regular file"``, ``"a directory"``, ``"a FIFO (named pipe)"``,
        ``"a character device"``, ``"a block device"``, ``"a socket"``, ``"a broken
        symlink"``; None when the path does not exist.
    """
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return "a broken symlink" if path.is_symlink() else None
    except OSError as exc:
        return f"unreadable ({exc.strerror})"
    kind = _kind_of_mode(mode)
    if path.is_symlink() and not stat.S_ISREG(mode):
        return f"a symlink to {kind} ({os.path.realpath(path)})"
    return kind


def require_regular_file(path: str | Path, what: str) -> Path:
    """Return ``path`` if it is a regular file (or a link to one); refuse anything else.

    Parameters
    ----------
    path : str or Path
        The file the user named.
    what : str
        What it is for, first in the message (``"surface.file"``, ``"job file"``).

    Returns
    -------
    Path

    Raises
    ------
    SpecialFileError (an InputError)
        A FIFO, a device, a directory, a socket, a broken link:
        ``"{what}: {path} is a FIFO (named pipe), expected a regular file"``.
    FileNotFoundError
        Nothing is there (``errno.ENOENT``, as ``open`` raises it).
    """
    path = Path(path)
    kind = describe_kind(path)
    if kind is None:
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), str(path))
    if kind != "a regular file":
        raise SpecialFileError(f"{what}: {path} is {kind}, expected a regular file")
    return path


def require_output_path(path: str | Path, what: str) -> Path:
    """Return ``path`` (the output file named by option ``what``, e.g. ``--out``) if a file
    may be written there: nothing yet, or a regular file to replace.

    Raises
    ------
    SpecialFileError (an InputError)
        An empty name, a path naming a directory, a FIFO, a device or a socket, or a
        parent that is not an existing directory; ``what`` comes first in the message.
    """
    if str(path) == "":
        raise SpecialFileError(f"{what}: is empty; expected a file name")
    path = Path(path)
    kind = describe_kind(path)
    if kind is not None and kind != "a regular file":
        raise SpecialFileError(f"{what}: {path} is {kind}, expected a regular file to write")
    parent = path.parent
    if not parent.is_dir():
        found = describe_kind(parent) or "missing"
        raise SpecialFileError(
            f"{what}: {path}: its folder {parent} is {found}; expected an existing directory"
        )
    return path


def require_output_dir(path: str | Path, what: str, *, probe: bool = True) -> Path:
    """Return the output folder ``path`` (option ``what``, e.g. ``--out``) once a file can be
    written in it, or, when it does not exist yet, in the folder it would be created in.

    Parameters
    ----------
    path : str or Path
        The folder the user named.
    what : str
        The option, first in the message.
    probe : bool
        Create and remove a temporary file in the folder (or its nearest existing parent;
        nothing else is created), so that a read-only folder or file system, or one without
        permission, is refused before any work (False: only the name and the kind of path
        are checked).

    Raises
    ------
    SpecialFileError (an InputError)
        An empty name (it would mean the current folder), a path that is not a directory,
        a folder that cannot be created or written: one line naming it and the reason.
    """
    if str(path).strip() == "":
        raise SpecialFileError(f"{what}: is empty; expected a folder name")
    path = Path(path)
    kind = describe_kind(path)
    if kind is not None and kind != "a directory" and not kind.startswith("unreadable"):
        raise SpecialFileError(f"{what} {path}: is {kind}, expected a directory")
    if not probe:
        return path
    existing = next(p for p in (path, *path.absolute().parents) if p.exists())
    try:
        descriptor, name = tempfile.mkstemp(prefix=".asperity-probe-", dir=existing)
        os.close(descriptor)
        os.unlink(name)
    except OSError as exc:
        raise SpecialFileError(
            f"{what} {path}: cannot write in {existing} ({exc.strerror or exc})"
        ) from exc
    return path


def read_bytes_bounded(path: str | Path, what: str, max_bytes: int) -> bytes:
    """Read a regular file whole, refusing a special file or one over ``max_bytes`` bytes.

    The file is opened without blocking and its kind checked on the open descriptor, then
    at most ``min(size, max_bytes) + 1`` bytes are read (one more than it holds, to see a
    file that grew), so neither a FIFO nor a device such as
    ``/dev/zero`` can hang the read or exhaust the memory.

    Parameters
    ----------
    path : str or Path
        The file the user named.
    what : str
        What it is for, first in the message.
    max_bytes : int
        Largest size accepted, bytes.

    Returns
    -------
    bytes

    Raises
    ------
    SpecialFileError (an InputError)
        Not a regular file, or larger than ``max_bytes``.
    FileNotFoundError
        Nothing is there.
    """
    path = require_regular_file(path, what)
    descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    with os.fdopen(descriptor, "rb") as handle:
        status = os.fstat(handle.fileno())
        if not stat.S_ISREG(status.st_mode):
            kind = _kind_of_mode(status.st_mode)
            raise SpecialFileError(f"{what}: {path} is {kind}, expected a regular file")
        data = handle.read(min(status.st_size, max_bytes) + 1)
    if len(data) > max_bytes:
        raise SpecialFileError(
            f"{what}: {path} holds more than {max_bytes} bytes; expected at most {max_bytes}"
        )
    return data
