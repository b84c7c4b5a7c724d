"""The HDF5 result store: one group per stage, written atomically, readable by xarray.

Layout of ``results.h5``::

    /                       attrs: asperity_version, config_toml (the resolved configuration),
                                   config_source, input_sha256, created (UTC ISO time)
    /<stage>                attrs: stage_key (hash of the configuration parts the stage
                                   depends on), seconds, finished, plus stage scalars
    /<stage>/<dimension>    1D coordinate (an HDF5 dimension scale)
    /<stage>/<variable>     array; attrs ``units`` (SI, "1" for dimensionless), ``long_name``,
                            and its axes attached to the coordinates above (DIMENSION_LIST)

Each group is a self-contained netCDF-4-like dataset: ``xarray.open_dataset(path,
group=stage, engine="h5netcdf")`` opens it with named dimensions and units.

Crash safety: every write copies the current file to a temporary file in the same directory,
writes the new group there, flushes it to disk and renames it over ``results.h5``
(:func:`os.replace` is atomic on POSIX), so an interruption leaves either the old file or the
new one, never a half-written one.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import os
import shutil
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np


@dataclass(frozen=True)
class Variable:
    """One stored array with its unit and named dimensions.

    Attributes
    ----------
    data : array_like
        The values (bool arrays are stored as int8).
    units : str
        SI unit ("m", "Pa", "N", "m^2", "1/m^2", "1" for dimensionless).
    dims : tuple of str
        One dimension name per axis; each must be a coordinate of the record.
    long_name : str
        What the values are.
    """

    data: Any
    units: str
    dims: tuple[str, ...]
    long_name: str = ""


@dataclass
class StageRecord:
    """What one stage stores: coordinates, variables and scalar attributes.

    Attributes
    ----------
    coords : dict of str to Variable
        1D coordinates; a coordinate's only dimension is its own name.
    variables : dict of str to Variable
        Data arrays over those dimensions.
    attrs : dict
        Scalars and short strings (numbers in SI units; the unit in the name or docs).
    """

    coords: dict[str, Variable] = field(default_factory=dict)
    variables: dict[str, Variable] = field(default_factory=dict)
    attrs: dict[str, Any] = field(default_factory=dict)


def _as_array(value: Any) -> np.ndarray:
    array = np.asarray(value)
    if array.dtype == bool:
        return array.astype(np.int8)
    return array


def _attr_value(value: Any) -> Any:
    if value is None:
        return "none"
    if isinstance(value, (bool, np.bool_)):
        return np.int8(value)
    if isinstance(value, Path):
        return str(value)
    return value


def write_record(group: h5py.Group, record: StageRecord) -> None:
    """Write a record into an (empty) HDF5 group with dimension scales and units."""
    scales: dict[str, h5py.Dataset] = {}
    for name, coord in record.coords.items():
        data = _as_array(coord.data)
        if data.ndim != 1 or coord.dims != (name,):
            raise ValueError(f"coordinate {name!r} must be 1D with dims ({name!r},)")
        ds = group.create_dataset(name, data=data)
        ds.attrs["units"] = coord.units
        if coord.long_name:
            ds.attrs["long_name"] = coord.long_name
        ds.make_scale(name)
        scales[name] = ds
    for name, var in record.variables.items():
        data = _as_array(var.data)
        if data.ndim != len(var.dims):
            raise ValueError(f"variable {name!r}: {data.ndim} axes but dims {var.dims}")
        for axis, dim in enumerate(var.dims):
            if dim not in scales:
                raise ValueError(f"variable {name!r}: dimension {dim!r} has no coordinate")
            if data.shape[axis] != scales[dim].shape[0]:
                raise ValueError(
                    f"variable {name!r}: axis {axis} has {data.shape[axis]} "
                    f"entries, coordinate {dim!r} has {scales[dim].shape[0]}"
                )
        compress = {"compression": "gzip", "compression_opts": 4} if data.size > 4096 else {}
        ds = group.create_dataset(name, data=data, **compress)
        ds.attrs["units"] = var.units
        if var.long_name:
            ds.attrs["long_name"] = var.long_name
        for axis, dim in enumerate(var.dims):
            ds.dims[axis].attach_scale(scales[dim])
            ds.dims[axis].label = dim
    for key, value in record.attrs.items():
        group.attrs[key] = _attr_value(value)


def read_record(group: h5py.Group) -> StageRecord:
    """Read a record written by :func:`write_record` (arrays loaded into memory)."""
    record = StageRecord()
    for name, ds in group.items():
        if not isinstance(ds, h5py.Dataset):
            continue
        units = str(ds.attrs.get("units", ""))
        long_name = str(ds.attrs.get("long_name", ""))
        if ds.is_scale:
            record.coords[name] = Variable(ds[()], units, (name,), long_name)
            continue
        dims = tuple(
            h5py.h5ds.get_scale_name(ds.dims[axis][0].id).decode() if len(ds.dims[axis]) else ""
            for axis in range(ds.ndim)
        )
        record.variables[name] = Variable(ds[()], units, dims, long_name)
    for key, value in group.attrs.items():
        if key in ("DIMENSION_LIST", "REFERENCE_LIST", "CLASS", "NAME"):
            continue
        if isinstance(value, bytes):
            value = value.decode()
        if isinstance(value, np.generic):
            value = value.item()
        record.attrs[key] = value
    return record


class ResultStore:
    """``results.h5`` of one job: stage groups keyed by the configuration they depend on.

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

    def stage_key(self, stage: str) -> str | None:
        """The key a finished stage was stored with, or None when it is not stored."""
        f = self._open_read()
        if f is None:
            return None
        with f:
            if stage not in f or not f[stage].attrs.get("finished", 0):
                return None
            return str(f[stage].attrs["stage_key"])

    def has_stage(self, stage: str, key: str) -> bool:
        """True when ``stage`` is stored finished with exactly this key."""
        return self.stage_key(stage) == key

    def read_stage(self, stage: str) -> StageRecord:
        """The stored record of a stage (KeyError when absent)."""
        f = self._open_read()
        if f is None or stage not in f:
            if f is not None:
                f.close()
            raise KeyError(f"{self.path}: stage {stage!r} is not stored")
        with f:
            return read_record(f[stage])

    def stages(self) -> list[str]:
        """Names of the stored, finished stages."""
        f = self._open_read()
        if f is None:
            return []
        with f:
            return [name for name in f if f[name].attrs.get("finished", 0)]

    def root_attrs(self) -> dict[str, Any]:
        """The file-level provenance attributes."""
        f = self._open_read()
        if f is None:
            return {}
        with f:
            return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}

    def write(
        self,
        stage: str | None,
        record: StageRecord | None,
        *,
        key: str = "",
        seconds: float = float("nan"),
        root_attrs: Mapping[str, Any] | None = None,
        drop: Sequence[str] = (),
    ) -> None:
        """Atomically (re)write one stage group and/or the file attributes.

        Parameters
        ----------
        stage, record : str, StageRecord or None
            The group to replace (None: only update the attributes / drop groups).
        key : str
            The stage key (hash of the configuration it depends on).
        seconds : float
            Wall time the stage took, s.
        root_attrs : mapping, optional
            File-level attributes to set (provenance).
        drop : sequence of str
            Groups to delete (stale stages downstream of a recomputed one).
        """
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(f".{self.path.name}.{os.getpid()}.tmp")
        try:
            readable = self._open_read()
            if readable is not None:
                readable.close()
                shutil.copyfile(self.path, tmp)
            with h5py.File(tmp, "a") as f:
                for name in drop:
                    if name in f:
                        del f[name]
                if stage is not None and record is not None:
                    if stage in f:
                        del f[stage]
                    group = f.create_group(stage)
                    write_record(group, record)
                    group.attrs["stage_key"] = key
                    group.attrs["seconds"] = float(seconds)
                    group.attrs["finished"] = np.int8(1)
                for k, v in (root_attrs or {}).items():
                    f.attrs[k] = _attr_value(v)
                f.attrs["modified"] = _dt.datetime.now(_dt.timezone.utc).isoformat()
            with open(tmp, "rb+") as handle:
                os.fsync(handle.fileno())
            os.replace(tmp, self.path)
        finally:
            with contextlib.suppress(FileNotFoundError):
                tmp.unlink()
