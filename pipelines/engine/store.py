"""The HDF5 result store: one group per stage, written atomically, readable by xarray.

Layout of ``results.h5``::

    /                       attrs: asperity_version, config_toml (the resolved configuration),
                                   config_source, input, input_sha256, conventions, modified
    /<stage>                attrs: stage_key (hash of what the stage was computed from),
                                   key_inputs (that document, JSON), checksum (SHA-256 of the
                                   stored values), seconds, finished, attribute_units (JSON map
                                   of the numeric attributes' SI units), plus the stage scalars
    /<stage>/<dimension>    1D coordinate (an HDF5 dimension scale)
    /<stage>/<variable>     array; attrs ``units`` (SI, "1" for dimensionless), ``long_name``,
                            and its axes attached to the coordinates above (DIMENSION_LIST)

Each group is a self-contained netCDF-4-like dataset: ``xarray.open_dataset(path,
group=stage, engine="h5netcdf")`` opens it with named dimensions and units. Booleans are HDF5
booleans. What goes in a group is the stage's result dataclass, field by field, as its
metadata declares (:mod:`asperity.fields`), written and read back by :mod:`asperity.h5`.

Untrusted input: a run folder may come from someone else, so every open checks the file first
(:class:`ResultStore`: a regular file, self-contained, declared sizes bounded, provenance
text); a file that fails is refused naming the object (``asperity report``) or set aside and
recomputed (``asperity run``).

Crash safety: every write builds the new file in memory (the current file up to the end its
superblock declares, never a padded tail; the new group; the file's provenance; stale groups
dropped), writes those bytes to ``.results.h5.<pid>.tmp`` in the
same directory, flushes it to disk and renames it over ``results.h5`` (:mod:`asperity.atomic`,
the one atomic writer of every output file; :func:`os.replace` is atomic on POSIX), so an
interruption leaves either the old file or the new one, never a
half-written one, and the provenance always describes the stages beside it. libhdf5 itself never
writes to disk, so a full disk is one clean :class:`pipelines.engine.outdir.OutputWriteError` (exit
status 2), the previous file intact and the temporary removed, instead of an h5py error and a
crash of libhdf5 at exit. The file is held in memory while it is written (its size: the
stage arrays, compressed above 4096 elements).
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import io
import os
import stat
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

import h5py
import numpy as np

from asperity.atomic import atomic_output, sync_directory, temporary_path
from asperity.fields import checksum
from asperity.files import SpecialFileError, describe_kind
from asperity.h5 import (
    COMPRESS_ABOVE,
    ResultLayoutError,
    StoredStageError,
    UntrustedContentError,
    allocated_size,
    attribute_value,
    check_self_contained,
    read_result,
    write_result,
)
from asperity.schema import clip
from asperity.topo.io.limits import memory_budget_bytes

R = TypeVar("R")

__all__ = [
    "COMPRESS_ABOVE",
    "ResultLayoutError",
    "ResultStore",
    "StoredStage",
    "StoredStageError",
    "UnreadableResultsError",
    "read_result",
    "sync_directory",
    "write_bytes_synced",
    "write_result",
]


#: What h5py and numpy raise on a damaged or foreign object.
READ_ERRORS = (OSError, KeyError, RuntimeError, ValueError, TypeError, AttributeError)
#: Bytes of HDF5 bookkeeping (headers, B-trees, heaps) allowed beyond the declared data when a
#: file is copied to be rewritten.
BOOKKEEPING_BYTES = 64 * 1024**2


class UnreadableResultsError(UntrustedContentError):
    """``results.h5`` does not open as HDF5, is not self-contained, or its provenance is not
    text (an :class:`~asperity.errors.InputError`: exit status 2, the object named)."""


def _text(value: object) -> str:
    """A bookkeeping attribute as text (bytes must be UTF-8)."""
    return str(attribute_value(value))


@contextlib.contextmanager
def _open_checked(
    path: Path, max_bytes: int, checked: set[tuple[int, ...]]
) -> Iterator[tuple[h5py.File, io.BufferedReader]]:
    """``(handle, raw file)`` of a checked ``results.h5`` (:class:`ResultStore`'s docstring).

    libhdf5 gets the descriptor opened here (without blocking: a FIFO swapped in after the
    caller's check is refused, not waited on), never the name. ``checked`` holds the identity
    (device, inode, size, modification time) of the versions already walked: each version is
    walked once (the store replaces the file at every write: a new version, a new identity).
    """
    with open(os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)), "rb") as raw:
        status = os.fstat(raw.fileno())
        if not stat.S_ISREG(status.st_mode):
            raise SpecialFileError(f"{path} is not a regular file")
        identity = (status.st_dev, status.st_ino, status.st_size, status.st_mtime_ns, max_bytes)
        try:
            handle = h5py.File(raw, "r")
        except READ_ERRORS as exc:
            raise UnreadableResultsError(
                f"{path}: unreadable HDF5 file ({clip(str(exc))})"
            ) from None
        with handle:
            if identity not in checked:
                check_self_contained(handle, path, max_bytes)
            for key in handle.attrs:  # provenance: text only (random bytes are refused)
                try:
                    value = attribute_value(handle.attrs[key])
                except READ_ERRORS:
                    value = None
                if not isinstance(value, str):
                    raise UnreadableResultsError(
                        f"{path}: attribute {clip(key)!r} of '/' is not UTF-8 text; refused"
                    )
            checked.add(identity)
            yield handle, raw


@dataclass(frozen=True)
class StoredStage:
    """What the store knows of a finished stage without reading its arrays.

    Attributes
    ----------
    key : str
        The stage key it was computed with.
    checksum : str
        SHA-256 of its stored values at write time.
    seconds : float
        Wall time it took, s.
    key_inputs : str
        The JSON document its key hashes ("" when the file has none).
    """

    key: str
    checksum: str
    seconds: float
    key_inputs: str = ""


class ResultStore:
    """``results.h5`` of one job: stage groups keyed by what they were computed from.

    The file is untrusted input (a run folder may come from someone else): every open checks,
    before reading anything, that it is a regular file (a FIFO would block), that it is
    self-contained (no link other than hard links, no external or virtual storage, declared
    sizes within :data:`MAX_STORED_BYTES` and what the file stores:
    :func:`asperity.h5.check_self_contained`) and that its provenance attributes are text.
    libhdf5 reads it through a descriptor this store opened, never by name.

    Parameters
    ----------
    path : path
        The HDF5 file (created on the first write).
    set_aside : bool
        What to do with a file that fails those checks or does not open as HDF5: False (the
        default, for readers such as ``asperity report``) raises
        :class:`UnreadableResultsError` naming the file and the object; True (``asperity
        run``, which recomputes) renames it to ``results.h5.unreadable`` with a warning and
        starts a new file. A special file (FIFO, device) is refused either way.
    max_bytes : int, optional
        Largest total of declared dataset and attribute bytes read (default: the memory
        budget, :func:`asperity.topo.io.limits.memory_budget_bytes`).
    """

    def __init__(self, path: str | Path, *, set_aside: bool = False, max_bytes: int | None = None):
        self.path = Path(path)
        self.set_aside = set_aside
        self.max_bytes = memory_budget_bytes() if max_bytes is None else int(max_bytes)
        self._checked: set[tuple[int, ...]] = set()

    @contextlib.contextmanager
    def _reading(self) -> Iterator[h5py.File | None]:
        """The checked file, open for reading (None when there is none, or it was set aside).

        Raises
        ------
        UnreadableResultsError
            The file fails the checks of the class docstring (``set_aside`` False).
        SpecialFileError
            ``results.h5`` is a FIFO, a device, a directory or a socket.
        """
        kind = describe_kind(self.path)
        if kind is None:
            yield None
            return
        if kind != "a regular file":
            raise SpecialFileError(f"{self.path} is {kind}, expected a regular file")
        with contextlib.ExitStack() as stack:
            try:
                handle, _ = stack.enter_context(
                    _open_checked(self.path, self.max_bytes, self._checked)
                )
            except UntrustedContentError as exc:
                if not self.set_aside:
                    raise
                aside = self.path.with_suffix(self.path.suffix + ".unreadable")
                os.replace(self.path, aside)
                warnings.warn(
                    f"{exc}; moved to {aside} and starting a new result file",
                    RuntimeWarning,
                    stacklevel=4,
                )
                handle = None
            yield handle

    def stored(self) -> dict[str, StoredStage]:
        """Every finished stage in the file, by group name (a group whose bookkeeping
        attributes do not read as a stage's is not one)."""
        with self._reading() as f:
            if f is None:
                return {}
            out = {}
            for name, group in f.items():
                if not isinstance(group, h5py.Group):
                    continue
                try:
                    a = group.attrs
                    if not bool(a.get("finished", False)):
                        continue
                    out[name] = StoredStage(
                        _text(a.get("stage_key", "")),
                        _text(a.get("checksum", "")),
                        float(a.get("seconds", np.nan)),
                        _text(a.get("key_inputs", "")),
                    )
                except READ_ERRORS:
                    continue
            return out

    def read(self, name: str, cls: type[R]) -> R:
        """The stored result of stage ``name``, checked against its checksum.

        Raises
        ------
        KeyError
            The stage is not stored.
        StoredStageError
            The group does not fit ``cls`` or its values changed since they were written.
        """
        with self._reading() as f:
            if f is None or name not in f:
                raise KeyError(f"{self.path}: stage {name!r} is not stored")
            group = f[name]
            try:
                result = read_result(group, cls)
                expected = _text(group.attrs.get("checksum", ""))
            except READ_ERRORS as exc:  # damaged data or layout
                raise StoredStageError(
                    f"{self.path}: stage {name!r} cannot be read back ({type(exc).__name__}: "
                    f"{clip(str(exc))})"
                ) from exc
        if checksum(result) != expected:
            raise StoredStageError(
                f"{self.path}: stage {name!r} fails its checksum (changed after it was written)"
            )
        return result

    def root_attrs(self) -> dict[str, object]:
        """The file-level provenance attributes (checked to be text or numbers on open)."""
        with self._reading() as f:
            if f is None:
                return {}
            return {k: attribute_value(v) for k, v in f.attrs.items()}

    def write(
        self,
        name: str | None = None,
        result: object = None,
        *,
        key: str = "",
        key_inputs: str = "",
        seconds: float = float("nan"),
        root_attrs: Mapping[str, str] | None = None,
        drop: Sequence[str] = (),
    ) -> None:
        """Atomically write one stage group, the file's provenance and the removal of stale groups.

        Parameters
        ----------
        name, result : str and a result dataclass, or None
            The group to (re)write (None: only update the attributes / drop groups).
        key : str
            The stage key.
        key_inputs : str
            The JSON document the key hashes (provenance of the stage).
        seconds : float
            Wall time the stage took, s.
        root_attrs : mapping, optional
            File-level attributes to set (provenance of the whole run).
        drop : sequence of str
            Groups to delete (stages of another configuration).
        """
        image = self._new_image(name, result, key, key_inputs, seconds, root_attrs, drop)
        self._replace_with(image)

    def _new_image(
        self,
        name: str | None,
        result: object,
        key: str,
        key_inputs: str,
        seconds: float,
        root_attrs: Mapping[str, str] | None,
        drop: Sequence[str],
    ) -> io.BytesIO:
        """The new file's bytes, built in memory: the current file plus the changes.

        libhdf5 never writes to disk here, so a full disk cannot leave it holding a half-closed
        file (which crashed the interpreter at exit: a segfault after the error).
        """
        image = io.BytesIO(self._allocated_bytes())
        with h5py.File(image, "a") as f:
            for stale in drop:
                if stale in f:
                    del f[stale]
            if name is not None:
                if name in f:
                    del f[name]
                group = f.create_group(name)
                write_result(group, result)
                group.attrs.update(
                    stage_key=key,
                    key_inputs=key_inputs,
                    checksum=checksum(result),
                    seconds=float(seconds),
                    finished=True,
                )
            for k, v in (root_attrs or {}).items():
                f.attrs[k] = v
            f.attrs["modified"] = _dt.datetime.now(_dt.timezone.utc).isoformat()
        return image

    def _allocated_bytes(self) -> bytes:
        """The current file's bytes up to the end its superblock declares (b"" without one).

        A tail past that end (padding, a sparse hole) is not read; a file declaring more than
        the declared data allow (:data:`BOOKKEEPING_BYTES` beyond ``max_bytes``) is refused.
        """
        with contextlib.ExitStack() as stack:
            try:
                _, raw = stack.enter_context(
                    _open_checked(self.path, self.max_bytes, self._checked)
                )
            except FileNotFoundError:
                return b""
            except UntrustedContentError:
                if not self.set_aside:
                    raise
                with self._reading():  # sets it aside, with its warning
                    return b""
            raw.seek(0)
            size = allocated_size(raw.read(64)) or os.fstat(raw.fileno()).st_size
            if size > self.max_bytes + BOOKKEEPING_BYTES:
                raise UnreadableResultsError(
                    f"{self.path}: declares {size} bytes, more than its data allow "
                    f"({self.max_bytes} + {BOOKKEEPING_BYTES}); refused"
                )
            raw.seek(0)
            return raw.read(size)

    def _replace_with(self, image: io.BytesIO) -> None:
        """Write ``image`` to a temporary file beside ``results.h5``, sync it, rename it over.

        Raises
        ------
        OutputWriteError
            No space, quota or access: the previous file is intact, no temporary is left.
        """
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_output(self.path) as tmp:
            write_bytes_synced(tmp, image.getbuffer())

    def temporary_path(self) -> Path:
        """Where this process writes the next version of the file (``.results.h5.<pid>.tmp``)."""
        return temporary_path(self.path)


#: Bytes written per ``os.write`` call.
WRITE_CHUNK = 1 << 22


def write_bytes_synced(path: Path, data: memoryview | bytes) -> None:
    """Write ``data`` to a new file ``path`` and flush it to the device (fsync).

    Raises OSError (ENOSPC, EDQUOT, EFBIG, ...) as the operating system reports it.
    """
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_BINARY", 0), 0o644)
    try:
        view = memoryview(data)
        while view:
            written = os.write(fd, view[:WRITE_CHUNK])
            view = view[written:]
        os.fsync(fd)
    finally:
        os.close(fd)
