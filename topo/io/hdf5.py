"""The project's own HDF5 height-map file (write and read).

Layout: dataset ``/heights`` (float64, shape ``(nx, ny)``, m, NaN = missing; its ``units``
attribute "m", written by :func:`asperity.h5.write_dataset`); root attributes ``format =
"asperity-heightmap"``, ``version = 1``, ``dx``, ``dy`` (m), ``periodic`` (bool), ``units =
"m"`` and ``provenance`` (JSON text).

Reading never opens a file the user did not name and never loads code: datasets with
external raw storage, virtual datasets, external (and user-defined) links and filters other
than HDF5's built-in ones (deflate, shuffle, fletcher32, n-bit, scale-offset, and h5py's
LZF) are refused; soft links are followed at most :data:`MAX_SOFT_LINKS` times (a loop is
refused). ``periodic`` must be a boolean or the integer 0 or 1 (a string such as ``"no"``
is refused, never read as True); ``provenance`` must be JSON text of an object.
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np

from asperity import h5
from asperity.topo.errors import CorruptFileError, TopographyFileError, UnsupportedContentError
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.io._common import make_surface, require_positive
from asperity.topo.io.limits import MAX_DEFLATE_RATIO, check_map_points

FORMAT_NAME = "asperity-heightmap"
FORMAT_VERSION = 1
#: Most soft links followed while resolving one path.
MAX_SOFT_LINKS = 16
#: HDF5 filters built into libhdf5 and h5py (no plugin is loaded from disk for these).
_BUILTIN_FILTERS = {1: "deflate", 2: "shuffle", 3: "fletcher32", 5: "nbit", 6: "scaleoffset"}
_BUILTIN_FILTERS[32000] = "lzf"
#: What h5py raises on damaged files or unreadable objects.
H5PY_ERRORS = (OSError, KeyError, RuntimeError, ValueError, TypeError)


def write_hdf5(surface: HeightMap, path: str | Path) -> Path:
    """Write ``surface`` to the project's HDF5 format (layout in the module docstring).

    Parameters
    ----------
    surface : HeightMap
        Heights and pixel sizes in m.
    path : str or Path
        Output file (overwritten).

    Returns
    -------
    Path
        The file written; :func:`topo.read_surface` reads it back exactly.
    """
    surface = require_height_map(surface, "write_hdf5")
    path = Path(path)
    compression = {"compression": "gzip", "compression_opts": 1, "shuffle": True}
    with h5.new_file(path) as handle:  # atomic: the old file or the new one, never a part
        h5.write_dataset(handle, "heights", surface.heights, "m", compression=compression)
        h5.write_attributes(
            handle,
            {
                "format": FORMAT_NAME,
                "version": FORMAT_VERSION,
                "dx": surface.dx,
                "dy": surface.dy,
                "periodic": surface.periodic,
                "units": "m",
                "provenance": json.dumps(surface.provenance, default=str),
            },
        )
    return path


def resolve_dataset(path: str | Path, handle: h5py.File, name: str) -> h5py.Dataset:
    """The dataset at ``name``, following only hard links and in-file soft links.

    Parameters
    ----------
    path : str or Path
        The file (for messages).
    handle : h5py.File
        The open file.
    name : str
        The dataset's path inside the file.

    Returns
    -------
    h5py.Dataset
        The dataset, checked with :func:`check_dataset_storage`.

    Raises
    ------
    UnsupportedContentError
        An external or user-defined link on the way, or a dataset that stores its data
        outside the file, is virtual, or needs a filter plugin.
    CorruptFileError
        A missing object, a soft-link loop (more than :data:`MAX_SOFT_LINKS` hops), or an
        object that is not a dataset.
    """
    target, hops = name, 0
    node: h5py.Group | h5py.Dataset = handle
    parts = [part for part in target.split("/") if part]
    while parts:
        part = parts.pop(0)
        if not isinstance(node, h5py.Group):
            raise CorruptFileError(path, name, f"passes through {node.name!r}, not a group")
        try:
            link = node.get(part, getlink=True)
        except H5PY_ERRORS as exc:
            raise CorruptFileError(path, name, f"cannot be resolved ({exc})") from None
        if link is None:
            raise CorruptFileError(path, name, f"has no member {part!r}; expected a dataset")
        if isinstance(link, h5py.SoftLink):
            hops += 1
            if hops > MAX_SOFT_LINKS:
                raise CorruptFileError(
                    path, name, f"follows more than {MAX_SOFT_LINKS} soft links (a link loop)"
                )
            rest = link.path.split("/") if link.path.startswith("/") else [node.name, link.path]
            parts = [p for p in "/".join(rest).split("/") if p] + parts
            node = handle
            continue
        if not isinstance(link, h5py.HardLink):
            raise UnsupportedContentError(
                path,
                name,
                f"goes through a {type(link).__name__} at {part!r}; a reader never opens "
                "another file: only links inside the file are followed",
            )
        try:
            node = node[part]
        except H5PY_ERRORS as exc:
            raise CorruptFileError(path, name, f"cannot be opened ({exc})") from None
    if not isinstance(node, h5py.Dataset):
        raise CorruptFileError(path, name, "is not a dataset")
    check_dataset_storage(path, node, name)
    return node


def check_dataset_storage(path: str | Path, dataset: h5py.Dataset, field: str) -> None:
    """Refuse a dataset stored outside the file, or promising more data than it stores.

    HDF5 fills unwritten chunks with a fill value, so a corrupt or hostile shape could
    make a reader allocate terabytes from a small file. gzip (deflate) compresses by
    about 1032:1 at most, so more than 1100 bytes of data per stored byte is refused.
    External raw storage (which would read another file, e.g. ``/etc/passwd``), virtual
    datasets and filters that need a plugin are refused.

    Parameters
    ----------
    path : str or Path
        The file (for the message).
    dataset : h5py.Dataset
        The dataset about to be read.
    field : str
        Its name, for the message.

    Raises
    ------
    UnsupportedContentError
        External storage, a virtual dataset, or a filter that is not built in.
    OverBudgetError
        More points than the memory budget.
    CorruptFileError
        If ``size * itemsize > 1100 * stored bytes + 4096``.
    """
    try:
        external = dataset.external
        virtual = dataset.is_virtual
        plist = dataset.id.get_create_plist()
        filters = [plist.get_filter(i)[0] for i in range(plist.get_nfilters())]
        shape = tuple(int(n) for n in dataset.shape or ())
        itemsize = dataset.dtype.itemsize
        stored = int(dataset.id.get_storage_size())
    except H5PY_ERRORS as exc:
        raise CorruptFileError(path, field, f"cannot be inspected ({exc})") from None
    if external:
        raise UnsupportedContentError(
            path,
            field,
            f"stores its data in another file ({external[0][0]!r}); a reader never opens a "
            "file the user did not name",
        )
    if virtual:
        raise UnsupportedContentError(
            path, field, "is a virtual dataset (data in other files); refused"
        )
    unknown = [f for f in filters if f not in _BUILTIN_FILTERS]
    if unknown:
        raise UnsupportedContentError(
            path,
            field,
            f"uses HDF5 filter {unknown[0]}, which needs a plugin; expected built-in "
            f"filters only ({', '.join(_BUILTIN_FILTERS.values())})",
        )
    needed = int(np.prod(shape, dtype=object)) * itemsize if shape else itemsize
    if needed > MAX_DEFLATE_RATIO * stored + 4096:
        raise CorruptFileError(
            path,
            field,
            f"has shape {dataset.shape} ({needed} bytes) but stores only {stored} bytes "
            "(truncated or corrupt file)",
        )
    check_map_points(path, f"{field} shape", *shape)


def read_dataset(path: str | Path, dataset: h5py.Dataset, field: str) -> np.ndarray:
    """All values of a checked dataset, or a :class:`CorruptFileError` naming ``field``."""
    try:
        return np.asarray(dataset[()])
    except H5PY_ERRORS as exc:
        raise CorruptFileError(path, field, f"cannot be read ({exc})") from None


def read_attribute(path: str | Path, obj: h5py.HLObject, name: str, default: object = None):
    """Attribute ``name`` of ``obj`` (``default`` if absent), or refuse an unreadable one."""
    try:
        if name not in obj.attrs:
            return default
        return obj.attrs[name]
    except H5PY_ERRORS as exc:
        raise CorruptFileError(path, f"attribute {name!r}", f"cannot be read ({exc})") from None


def _as_text(value: object) -> str | None:
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.ravel()[0]
    if isinstance(value, bytes | np.bytes_):
        return bytes(value).decode("utf-8", "replace")
    if isinstance(value, str):
        return value
    return None


def is_project_hdf5(handle: h5py.File) -> bool:
    """Whether an open HDF5 file is in the project's height-map format.

    Parameters
    ----------
    handle : h5py.File
        The open file.

    Returns
    -------
    bool
        True if its ``format`` attribute is ``"asperity-heightmap"``.
    """
    return _as_text(read_attribute(handle.filename, handle, "format")) == FORMAT_NAME


def _periodic(path: str | Path, value: object) -> bool:
    """The ``periodic`` attribute: a boolean or the integer 0 or 1, nothing else."""
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.ravel()[0]
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer) and int(value) in (0, 1):
        return bool(int(value))
    raise CorruptFileError(
        path,
        "attribute 'periodic'",
        f"is {value!r}; expected a boolean (True/False) or the integer 0 or 1",
        expected="bool",
        found=value,
    )


def _provenance(path: str | Path, value: object) -> dict:
    """The stored provenance: JSON text of an object."""
    if value is None:
        return {}
    text = _as_text(value)
    try:
        provenance = json.loads(text) if text is not None else None
    except (json.JSONDecodeError, RecursionError):
        provenance = None
    if not isinstance(provenance, dict):
        raise CorruptFileError(
            path,
            "attribute 'provenance'",
            f"is {type(value).__name__} {str(value)[:40]!r}; expected JSON text of an object",
        )
    return provenance


def _version(path: str | Path, value: object) -> int:
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.ravel()[0]
    if isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_):
        if int(value) == FORMAT_VERSION:
            return FORMAT_VERSION
    raise TopographyFileError(path, "version", f"is {value!r}; expected {FORMAT_VERSION}")


def read_project_hdf5(path: str | Path, handle: h5py.File) -> HeightMap:
    """Read the project's HDF5 height map from an open file handle.

    Parameters
    ----------
    path : str or Path
        The file (for messages and provenance).
    handle : h5py.File
        The file, open for reading.

    Returns
    -------
    HeightMap
        Heights, ``dx``, ``dy`` in m, the stored ``periodic`` flag and provenance.

    Raises
    ------
    TopographyFileError
        Another version, a missing or non-2D ``/heights``, units other than m, a
        ``periodic`` that is not a boolean, provenance that is not JSON, refused storage
        or links (see the module docstring), or data that cannot be read.
    """
    _version(path, read_attribute(path, handle, "version", -1))
    dataset = resolve_dataset(path, handle, "/heights")
    if dataset.ndim != 2:
        raise TopographyFileError(path, "/heights", "is missing or not a 2D dataset")
    if dataset.dtype.kind not in "fiu":
        raise TopographyFileError(
            path, "/heights", f"has dtype {dataset.dtype}; expected real numbers (m)"
        )
    units = _as_text(read_attribute(path, handle, "units"))
    if units != "m":
        raise TopographyFileError(path, "units", f"is {units!r}; expected 'm'")
    spacing = {}
    for name in ("dx", "dy"):
        value = np.asarray(read_attribute(path, handle, name))
        if value.dtype.kind not in "fiu" or value.size != 1:
            raise TopographyFileError(
                path,
                f"attribute {name!r}",
                "is missing or not a number; expected a pixel size in m",
            )
        spacing[name] = float(value.ravel()[0])
        require_positive(path, f"attribute {name!r}", spacing[name], " m")
    periodic = _periodic(path, read_attribute(path, handle, "periodic", False))
    provenance = _provenance(path, read_attribute(path, handle, "provenance"))
    heights = read_dataset(path, dataset, "/heights")
    provenance = {**provenance, "file": str(path), "stored_format": FORMAT_NAME}
    provenance.setdefault("format", FORMAT_NAME)
    provenance.setdefault("channel", "/heights")
    sizes = (("attribute 'dx'", spacing["dx"]), ("attribute 'dy'", spacing["dy"]))
    surface = make_surface(path, heights, sizes, provenance)
    return HeightMap(surface.heights, surface.dx, surface.dy, periodic, surface.provenance)
