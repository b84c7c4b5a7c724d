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
import dataclasses
import io
import json
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

import h5py
import numpy as np

from asperity.atomic import write_bytes_atomic
from asperity.errors import InputError
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
    elif not compression:
        options = {}
    elif isinstance(compression, str):
        raise ValueError(f"compression: 'auto', a mapping or None expected, found {compression!r}")
    else:
        options = dict(compression)
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

    A field the group lacks reads as None where it is optional, and as its declared default
    where it has one (a file written before the field was added: asperity 0.4's shear stage
    has no ``preload``).

    Raises
    ------
    StoredStageError
        A required field is missing (the group was written for another declaration).
    """
    kwargs: dict[str, Any] = {}
    derived: dict[str, Any] = {}
    defaulted = {
        f.name
        for f in dataclasses.fields(cls)  # type: ignore[arg-type]
        if f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING
    }
    for spec in field_specs(cls):
        if spec.kind == "array":
            value = group[spec.name][()] if spec.name in group else None
        elif spec.name in group.attrs:
            value = attribute_value(group.attrs[spec.name])
            value = json.loads(value) if spec.kind == "json" else canonical(spec, value)
        else:
            value = None
        if value is None and not spec.optional:
            if spec.name in defaulted and spec.init:
                continue  # an older file: the declared default
            raise StoredStageError(f"group {group.name!r} has no {spec.name!r}")
        (kwargs if spec.init else derived)[spec.name] = value
    result = cls(**kwargs)
    for name, value in derived.items():  # stored copies of derived values must agree
        object.__setattr__(result, name, value)
    return result


class UntrustedContentError(InputError):
    """An HDF5 file that would make a reader open another file, loop, or read more than it holds.

    Raised before anything is read from the file (:func:`check_self_contained`); the message
    names the file and the object.
    """


#: HDF5 filters built into libhdf5 and h5py (deflate, shuffle, fletcher32, n-bit,
#: scale-offset, LZF): nothing is loaded from disk to decode them.
BUILTIN_FILTERS = frozenset((1, 2, 3, 5, 6, 32000))
#: Largest number of objects (groups, datasets, attributes) walked in one file.
MAX_OBJECTS = 100_000
#: Deflate cannot expand more than about 1032 bytes per stored byte.
MAX_EXPANSION = 1100
#: Most bytes a whole file may declare per byte it is, beyond :data:`FILE_EXPANSION_SLACK`:
#: asperity's results hold float maps that compress little (a 650^2 run declares 1.1 x its
#: size), so a file declaring hundreds of times its size is a compression bomb, refused
#: before anything is decompressed.
MAX_FILE_EXPANSION = 64
#: Declared bytes every file may hold whatever its size (64 MiB: read in well under a second).
FILE_EXPANSION_SLACK = 64 * 1024**2


def _declared_bytes(shape: tuple[int, ...] | None, itemsize: int) -> int:
    """Bytes an array of ``shape`` (None: scalar) and ``itemsize`` takes in memory."""
    count = 1
    for n in shape or ():
        count *= int(n)
    return count * int(itemsize)


def check_self_contained(handle: h5py.File, where: str | Path, max_bytes: int) -> int:
    """Refuse an HDF5 file whose reading would leave it, loop, or allocate beyond a bound.

    Every object is visited through the low-level API without following any link that is
    not a hard link, before any value is read, so an untrusted file (a ``results.h5``
    received from someone else) cannot make libhdf5 open another file or a reader allocate
    more than the file declares and holds. Refused, naming the object:

    * a soft, external or user-defined link (asperity writes hard links only; a soft link
      can loop, an external link opens another file);
    * a dataset with external raw storage (reads another file, e.g. ``/etc/passwd``), a
      virtual dataset, or a filter that needs a plugin;
    * a dataset that declares more than :data:`MAX_EXPANSION` bytes per stored byte (a
      1e12-element chunked dataset with no chunk written reads as fill values);
    * more than ``max_bytes`` of declared datasets and attributes in all, or more than
      :data:`MAX_OBJECTS` objects;
    * declared datasets and attributes of more than :data:`MAX_FILE_EXPANSION` times the
      file's size plus :data:`FILE_EXPANSION_SLACK` (a compression bomb: every chunk may
      stay within deflate's ratio while the whole inflates to gigabytes), judged from the
      declarations alone, before any chunk is decompressed.

    Parameters
    ----------
    handle : h5py.File
        The open file (nothing has been read from it yet).
    where : str or Path
        The file, for the messages.
    max_bytes : int
        Largest total of declared dataset and attribute bytes accepted.

    Returns
    -------
    int
        The declared bytes of every dataset and attribute (at most ``max_bytes``).

    Raises
    ------
    UntrustedContentError (an InputError)
        The first offending object, named.
    """
    total, count, seen = 0, 0, set()
    stack: list[tuple[str, Any]] = [("/", handle.id)]
    file_bytes = _file_size(handle)
    bomb_limit = MAX_FILE_EXPANSION * file_bytes + FILE_EXPANSION_SLACK

    def refuse(name: str, why: str) -> UntrustedContentError:
        return UntrustedContentError(f"{where}: object {name!r} {why}; refused")

    def add(name: str, nbytes: int) -> None:
        nonlocal total, count
        total, count = total + nbytes, count + 1
        if total > max_bytes:
            raise refuse(name, f"takes the declared data past {max_bytes} bytes")
        if total > bomb_limit:
            raise refuse(
                name,
                f"takes the declared data to {total} bytes, {total / max(file_bytes, 1):.0f} "
                f"times the file's {file_bytes} bytes (a compression bomb: at most "
                f"{MAX_FILE_EXPANSION} times plus {FILE_EXPANSION_SLACK // 1024**2} MiB)",
            )
        if count > MAX_OBJECTS:
            raise refuse(name, f"is past the {MAX_OBJECTS}th object of the file")

    try:
        while stack:
            name, obj = stack.pop()
            for index in range(h5py.h5a.get_num_attrs(obj)):
                attr = h5py.h5a.open(obj, index=index)
                label = f"{name} (attribute {attr.name.decode(errors='replace')!r})"
                add(label, _declared_bytes(attr.shape, attr.dtype.itemsize))
            if not isinstance(obj, h5py.h5g.GroupID):
                continue
            members: list[bytes] = []
            obj.links.iterate(members.append)
            for member in members:
                child = f"{name.rstrip('/')}/{member.decode(errors='replace')}"
                kind = obj.links.get_info(member).type
                if kind != h5py.h5l.TYPE_HARD:
                    words = {h5py.h5l.TYPE_SOFT: "a soft", h5py.h5l.TYPE_EXTERNAL: "an external"}
                    raise refuse(
                        child,
                        f"is {words.get(kind, 'a user-defined')} link; only hard links are "
                        "read (a reader never opens another file nor follows a link loop)",
                    )
                target = h5py.h5o.open(obj, member)
                if hash(target) in seen:  # a second hard link to one object (or a cycle)
                    continue
                seen.add(hash(target))
                if isinstance(target, h5py.h5d.DatasetID):
                    add(child, _check_dataset(target, refuse, child))
                stack.append((child, target))
    except UntrustedContentError:
        raise
    except (OSError, KeyError, RuntimeError, ValueError, TypeError) as exc:
        raise UntrustedContentError(f"{where}: cannot be inspected ({exc}); refused") from None
    return total


def _file_size(handle: h5py.File) -> int:
    """The size of the open file, bytes (its end-of-file address when libhdf5 cannot say)."""
    try:
        return int(handle.id.get_filesize())
    except (OSError, RuntimeError, ValueError):
        return 0


def _check_dataset(dataset: Any, refuse: Any, name: str) -> int:
    """The declared bytes of a low-level dataset, after refusing foreign storage."""
    plist = dataset.get_create_plist()
    if plist.get_layout() == h5py.h5d.VIRTUAL:
        raise refuse(name, "is a virtual dataset (its data live in other files)")
    if plist.get_external_count() > 0:
        raise refuse(name, "stores its data in another file (external raw storage)")
    filters = [plist.get_filter(i)[0] for i in range(plist.get_nfilters())]
    unknown = [f for f in filters if f not in BUILTIN_FILTERS]
    if unknown:
        raise refuse(name, f"needs HDF5 filter {unknown[0]}, a plugin (built-in filters only)")
    needed = _declared_bytes(dataset.shape, dataset.dtype.itemsize)
    stored = int(dataset.get_storage_size())
    if needed > MAX_EXPANSION * stored + 4096:
        raise refuse(
            name,
            f"declares shape {dataset.shape} ({needed} bytes) but stores {stored} bytes "
            "(truncated, corrupt or hostile)",
        )
    return needed


#: The HDF5 format signature that starts a superblock.
SIGNATURE = b"\x89HDF\r\n\x1a\n"


def allocated_size(head: bytes) -> int | None:
    """The end-of-file address an HDF5 superblock at offset 0 declares, bytes.

    libhdf5 reads nothing past it, so bytes beyond (a padded or sparse tail) are not part of
    the file and need not be copied when the file is rewritten.

    Parameters
    ----------
    head : bytes
        The first bytes of the file (64 are enough).

    Returns
    -------
    int or None
        The size, or None when ``head`` does not start with a superblock of version 0 to 3
        with 2-, 4- or 8-byte offsets and a zero base address.
    """
    if not head.startswith(SIGNATURE) or len(head) < 16:
        return None
    version = head[8]
    if version in (0, 1):
        offsets, start = head[13], 24 + 4 * version
    elif version in (2, 3):
        offsets, start = head[9], 12
    else:
        return None
    if offsets not in (2, 4, 8) or len(head) < start + 3 * offsets:
        return None
    fields = [
        int.from_bytes(head[start + i * offsets : start + (i + 1) * offsets], "little")
        for i in range(3)
    ]
    base, eof = fields[0], fields[2]
    return eof if base == 0 else None
