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

Crash safety: every write builds the new file in memory (the current file, the new group, the
file's provenance, stale groups dropped), writes those bytes to ``.results.h5.<pid>.tmp`` in the
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

import datetime as _dt
import io
import os
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

import h5py
import numpy as np

from asperity.atomic import atomic_output, sync_directory, temporary_path
from asperity.fields import checksum
from asperity.h5 import (
    COMPRESS_ABOVE,
    ResultLayoutError,
    StoredStageError,
    attribute_value,
    read_result,
    write_result,
)

R = TypeVar("R")

__all__ = [
    "COMPRESS_ABOVE",
    "ResultLayoutError",
    "ResultStore",
    "StoredStage",
    "StoredStageError",
    "read_result",
    "sync_directory",
    "write_bytes_synced",
    "write_result",
]


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
    """

    key: str
    checksum: str
    seconds: float


class ResultStore:
    """``results.h5`` of one job: stage groups keyed by what they were computed from.

    Parameters
    ----------
    path : path
        The HDF5 file (created on the first write).
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)

    def _open_read(self) -> h5py.File | None:
        if not self.path.exists():
            return None
        try:
            return h5py.File(self.path, "r")
        except OSError as exc:
            # Not produced by this store (writes are atomic): keep it aside, start afresh.
            aside = self.path.with_suffix(self.path.suffix + ".unreadable")
            os.replace(self.path, aside)
            warnings.warn(
                f"{self.path}: unreadable HDF5 file ({exc}); moved to {aside} and "
                "starting a new result file",
                RuntimeWarning,
                stacklevel=3,
            )
            return None

    def stored(self) -> dict[str, StoredStage]:
        """Every finished stage in the file, by group name."""
        f = self._open_read()
        if f is None:
            return {}
        with f:
            out = {}
            for name, group in f.items():
                a = group.attrs
                if isinstance(group, h5py.Group) and a.get("finished", False):
                    out[name] = StoredStage(
                        str(attribute_value(a.get("stage_key", ""))),
                        str(attribute_value(a.get("checksum", ""))),
                        float(a.get("seconds", np.nan)),
                    )
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
        f = self._open_read()
        if f is None or name not in f:
            if f is not None:
                f.close()
            raise KeyError(f"{self.path}: stage {name!r} is not stored")
        with f:
            group = f[name]
            try:
                result = read_result(group, cls)
            except (OSError, KeyError, TypeError, ValueError) as exc:  # damaged data or layout
                raise StoredStageError(
                    f"{self.path}: stage {name!r} cannot be read back ({type(exc).__name__}: {exc})"
                ) from exc
            expected = str(attribute_value(group.attrs.get("checksum", "")))
        if checksum(result) != expected:
            raise StoredStageError(
                f"{self.path}: stage {name!r} fails its checksum (changed after it was written)"
            )
        return result

    def root_attrs(self) -> dict[str, object]:
        """The file-level provenance attributes."""
        f = self._open_read()
        if f is None:
            return {}
        with f:
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
        image = io.BytesIO()
        readable = self._open_read()
        if readable is not None:
            readable.close()
            image.write(self.path.read_bytes())
            image.seek(0)
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
