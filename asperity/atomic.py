"""Writing an output file atomically: the old file or the new one, never a truncated one.

Every file asperity writes (``results.h5``, ``report.md``, ``report.html``, each figure and its
CSV, ``summary.csv``, ``scan --out`` and ``synth --out`` files) goes through
:func:`atomic_output`: the writer fills a temporary file in the same folder
(``.NAME.<pid>.tmp``), which is flushed to the device (``fsync``) and renamed over ``NAME``
(:func:`os.replace`, atomic on POSIX), the rename itself flushed with the folder. Whatever
happens before the rename (a full disk, a quota, ``kill -9``, Ctrl-C, a writer that fails
half-way) leaves the previous ``NAME`` untouched, or no ``NAME`` at all; the temporary is
removed on any error (after ``kill -9``, the next run on that folder removes it:
:func:`asperity.pipelines.engine.outdir.remove_stale_temporaries`).

A failure of the storage (no space, quota, file too large, read-only file system, no
permission, an I/O error) is one :class:`OutputWriteError`, an
:class:`~asperity.errors.InputError` (exit status 2): the user's disk or folder is the cause,
not asperity. Any other exception of the writer passes through unchanged.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from asperity.errors import InputError

__all__ = [
    "STORAGE_ERRNOS",
    "OutputWriteError",
    "atomic_output",
    "open_atomic",
    "storage_errno",
    "sync_directory",
    "temporary_path",
    "write_bytes_atomic",
    "write_error",
    "write_text_atomic",
]

#: Errors of a full, read-only or failing storage device, or of a folder one may not write.
STORAGE_ERRNOS = frozenset(
    (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO, errno.EACCES, errno.EPERM)
)
_STORAGE_WORDS = {
    "no space left on device": errno.ENOSPC,
    "disk quota exceeded": errno.EDQUOT,
    "file too large": errno.EFBIG,
    "read-only file system": errno.EROFS,
    "input/output error": errno.EIO,
    "permission denied": errno.EACCES,
}


class OutputWriteError(InputError):
    """Writing an output file failed for lack of space, quota or access (exit status 2).

    Attributes
    ----------
    errno : int or None
        The operating system's error number, when known.
    """

    def __init__(self, message: str, errno_code: int | None = None):
        super().__init__(message)
        self.errno = errno_code


def storage_errno(exc: BaseException) -> int | None:
    """The storage error number behind ``exc`` (an OSError, or h5py's RuntimeError text).

    Returns None when ``exc`` is not a storage failure (a defect must not be relabelled).
    """
    code = getattr(exc, "errno", None)
    if isinstance(exc, OSError) and code in STORAGE_ERRNOS:
        return code
    if isinstance(exc, OSError | RuntimeError):  # h5py: "... errno = 28, error message = ..."
        text = str(exc).lower()
        match = re.search(r"errno = (\d+)", text)
        if match and int(match.group(1)) in STORAGE_ERRNOS:
            return int(match.group(1))
        for word, number in _STORAGE_WORDS.items():
            if word in text:
                return number
    return None


def write_error(path: Path, exc: BaseException, kept: str) -> OutputWriteError | None:
    """The one-line error for a failed write of ``path``, or None when ``exc`` is a defect.

    Parameters
    ----------
    path : Path
        The file being written.
    exc : exception
        What the write raised.
    kept : str
        What is still intact on disk (said in the message).
    """
    code = storage_errno(exc)
    if code is None:
        return None
    return OutputWriteError(f"{path}: {os.strerror(code)} while writing; {kept}", code)


def temporary_path(path: str | Path) -> Path:
    """Where this process writes the next version of ``path``: ``.NAME.<pid>.tmp`` beside it."""
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


def sync_directory(directory: Path) -> None:
    """Flush a rename in ``directory`` to the device (POSIX; a no-op where unsupported)."""
    if not hasattr(os, "O_DIRECTORY"):
        return
    fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    try:
        with contextlib.suppress(OSError):  # some file systems refuse fsync on a directory
            os.fsync(fd)
    finally:
        os.close(fd)


def _sync_file(path: Path) -> None:
    """Flush a closed file's data to the device (raises OSError, e.g. ENOSPC, EIO)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _kept(path: Path) -> str:
    return f"{path} is unchanged" if path.exists() else "nothing was written"


@contextlib.contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary file name to write ``path`` through; rename it over ``path`` at the end.

    Parameters
    ----------
    path : str or Path
        The output file; its folder must exist. The writer must write the yielded path
        (naming its format explicitly: the temporary's suffix is ``.tmp``) and close it.

    Yields
    ------
    Path
        ``.NAME.<pid>.tmp`` in the same folder.

    Raises
    ------
    OutputWriteError
        No space, quota or access, while writing, syncing or renaming: ``path`` is as it
        was before, and no temporary is left.
    """
    path = Path(path)
    tmp = temporary_path(path)
    try:
        yield tmp
        _sync_file(tmp)
        os.replace(tmp, path)
        sync_directory(path.parent)
    except (OSError, RuntimeError) as exc:
        error = write_error(path, exc, _kept(path))
        if error is None:
            raise
        raise error from exc
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()


@contextlib.contextmanager
def open_atomic(path: str | Path, mode: str = "w", **kwargs: Any) -> Iterator[IO]:
    """``open(path, mode, **kwargs)`` written atomically (:func:`atomic_output`).

    ``mode`` is ``"w"`` (text; pass ``encoding``/``newline``) or ``"wb"``.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"open_atomic: mode {mode!r}; expected 'w' or 'wb'")
    with atomic_output(path) as tmp, open(tmp, mode, **kwargs) as handle:  # noqa: PTH123
        yield handle


def write_bytes_atomic(path: str | Path, data: bytes | memoryview) -> Path:
    """Write ``data`` to ``path`` atomically (:func:`atomic_output`); returns ``path``."""
    with open_atomic(path, "wb") as handle:
        handle.write(data)
    return Path(path)


def write_text_atomic(path: str | Path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (:func:`atomic_output`); returns ``path``."""
    with open_atomic(path, "w", encoding=encoding) as handle:
        handle.write(text)
    return Path(path)
