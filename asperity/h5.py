"""HDF5 writing and reading of asperity's results, in one place.

Every HDF5 file asperity writes goes through this module: the job's ``results.h5``
(:mod:`asperity.pipelines.engine.store`, one group per stage through :func:`write_result`),
the project's height-map format (:func:`asperity.topo.io.hdf5.write_hdf5`), the resolution
scan (:func:`asperity.topo.write_scan_hdf5`), the friction curves of ``asperity friction``
(:mod:`asperity.statmodel.results_io`) and the data of the paper's figures
(:mod:`asperity.statmodel.figures`). A dataset always carries its SI ``units`` attribute
(:func:`write_dataset`); a result dataclass is written field by field as its declarations in
:mod:`asperity.fields` say (:func:`write_result`):

* an array field is a dataset with ``units`` and ``long_name``, its axes attached to the
  dimension scales named by its ``dims`` (a field whose only dimension is its own name is that
  scale; a dimension without one gets an index 0..n-1), so ``xarray.open_dataset(path,
  group=..., engine="h5netcdf")`` opens the group with named dimensions;
* a number or boolean is a group attribute, its unit in the JSON map ``attribute_units``;
* a string is an attribute as is, a list or dict an attribute holding JSON text.

:func:`read_result` reads the same declaration back. A new file is built in memory and written
atomically (:func:`new_file`): a full disk or an interruption leaves the previous file or none,
never a truncated one, and libhdf5 never holds a half-written file on a full disk.
"""

from __future__ import annotations

import contextlib
import io
import json
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

import h5py
import numpy as np

from asperity.atomic import write_bytes_atomic
from asperity.fields import FieldSpec, canonical, field_specs

R = TypeVar("R")

#: Arrays larger than this many elements are gzip-compressed (``compression="auto"``).
COMPRESS_ABOVE = 4096


class StoredStageError(RuntimeError):
    """A stored group does not match its declaration or its checksum."""


class ResultLayoutError(RuntimeError):
    """A result's arrays disagree with their declared dimensions (a defect in a result type)."""


@contextlib.contextmanager
def new_file(path: str | Path) -> Iterator[h5py.File]:
    """A new HDF5 file to fill, written to ``path`` atomically when the block ends.

    The file is built in memory, then its bytes go through
    :func:`asperity.atomic.write_bytes_atomic` (temporary beside ``path``, fsync, rename).
    An exception inside the block writes nothing.

    Parameters
    ----------
    path : str or Path
        The output file (replaced); its folder must exist.

    Raises
    ------
    asperity.atomic.OutputWriteError
        No space, quota or access: ``path`` is as it was, no temporary is left.
    """
    image = io.BytesIO()
    with h5py.File(image, "w") as handle:
        yield handle
    write_bytes_atomic(path, image.getbuffer())


def attribute_value(value: Any) -> Any:
    """An HDF5 attribute as Python gives it back: bytes decoded to str."""
    return value.decode() if isinstance(value, bytes) else value


def write_attributes(obj: h5py.HLObject, values: Mapping[str, Any]) -> None:
    """Set attributes of a file, group or dataset (numbers, booleans, strings as given)."""
    for key, value in values.items():
        obj.attrs[key] = value


def _dimension_lengths(specs: Sequence[FieldSpec], values: Mapping[str, Any]) -> dict[str, int]:
    lengths: dict[str, int] = {}
    for spec in specs:
        data = values[spec.name]
        if spec.kind != "array" or data is None:
            continue
        if data.ndim != len(spec.dims):
            raise ResultLayoutError(f"{spec.name!r}: {data.ndim} axes but dims {spec.dims}")
        for dim, n in zip(spec.dims, data.shape, strict=True):
            if lengths.setdefault(dim, n) != n:
                raise ResultLayoutError(
                    f"{spec.name!r}: dimension {dim!r} has {n} entries here and "
                    f"{lengths[dim]} elsewhere"
                )
    return lengths


def write_dataset(
    group: h5py.Group,
    name: str,
    data: Any,
    units: str,
    long_name: str = "",
    *,
    compression: str | Mapping[str, Any] | None = "auto",
) -> h5py.Dataset:
    """Create dataset ``name`` in ``group`` with its ``units`` (SI) and ``long_name`` attributes.

    Parameters
    ----------
    group : h5py.Group
        Where to write (a file is a group).
    name : str
        Dataset name.
    data : array_like
        The values (numbers in SI ``units``).
    units : str
        SI unit ("1" for dimensionless), the ``units`` attribute every reader looks for.
    long_name : str
        Description (not written when empty).
    compression : "auto", mapping or None
        "auto": gzip level 4 above :data:`COMPRESS_ABOVE` elements; a mapping: h5py's
        ``create_dataset`` filter options as given; None: uncompressed.
    """
    data = np.asarray(data)
    if compression == "auto":
        large = data.size > COMPRESS_ABOVE
        options = {"compression": "gzip", "compression_opts": 4} if large else {}
    else:
        options = dict(compression or {})
    ds = group.create_dataset(name, data=data, **options)
    ds.attrs["units"] = units
    if long_name:
        ds.attrs["long_name"] = long_name
    return ds


def write_result(group: h5py.Group, result: Any) -> None:
    """Write a result dataclass into an empty HDF5 group, as its field metadata declares.

    Raises
    ------
    ResultLayoutError
        An array's axes disagree with its dims, or one dimension has two lengths.
    """
    specs = field_specs(type(result))
    values = {s.name: canonical(s, getattr(result, s.name)) for s in specs}
    lengths = _dimension_lengths(specs, values)
    coords = {s.name: s for s in specs if s.is_coordinate and values[s.name] is not None}
    scales = {}
    for dim, n in lengths.items():
        if dim in coords:
            spec = coords[dim]
            ds = write_dataset(group, dim, values[dim], spec.units, spec.long_name)
        else:
            ds = write_dataset(group, dim, np.arange(n), "1", f"index along {dim}")
        ds.make_scale(dim)
        scales[dim] = ds
    units = {}
    for spec in specs:
        value = values[spec.name]
        if value is None or spec.name in coords:
            continue
        if spec.kind == "array":
            ds = write_dataset(group, spec.name, value, spec.units, spec.long_name)
            for axis, dim in enumerate(spec.dims):
                ds.dims[axis].attach_scale(scales[dim])
        elif spec.kind == "json":
            group.attrs[spec.name] = json.dumps(value)
        else:
            group.attrs[spec.name] = value
            if spec.kind == "number":
                units[spec.name] = spec.units
    group.attrs["attribute_units"] = json.dumps(units)


def read_result(group: h5py.Group, cls: type[R]) -> R:
    """Read a result dataclass written by :func:`write_result` (arrays loaded into memory).

    Raises
    ------
    StoredStageError
        A required field is missing (the group was written for another declaration).
    """
    kwargs, derived = {}, {}
    for spec in field_specs(cls):
        if spec.kind == "array":
            value = group[spec.name][()] if spec.name in group else None
        elif spec.name in group.attrs:
            value = attribute_value(group.attrs[spec.name])
            value = json.loads(value) if spec.kind == "json" else canonical(spec, value)
        else:
            value = None
        if value is None and not spec.optional:
            raise StoredStageError(f"group {group.name!r} has no {spec.name!r}")
        (kwargs if spec.init else derived)[spec.name] = value
    result = cls(**kwargs)
    for name, value in derived.items():  # stored copies of derived values must agree
        object.__setattr__(result, name, value)
    return result
