"""The project's own HDF5 height-map file (write and read).

Layout: dataset ``/heights`` (float64, shape ``(nx, ny)``, m, NaN = missing); root
attributes ``format = "asperity-heightmap"``, ``version = 1``, ``dx``, ``dy`` (m),
``periodic`` (bool), ``units = "m"`` and ``provenance`` (JSON text).
"""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np

from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.io._common import require_positive

FORMAT_NAME = "asperity-heightmap"
FORMAT_VERSION = 1


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
    with h5py.File(path, "w") as handle:
        handle.create_dataset(
            "heights",
            data=np.asarray(surface.heights),
            compression="gzip",
            compression_opts=1,
            shuffle=True,
        )
        handle.attrs["format"] = FORMAT_NAME
        handle.attrs["version"] = FORMAT_VERSION
        handle.attrs["dx"] = surface.dx
        handle.attrs["dy"] = surface.dy
        handle.attrs["periodic"] = surface.periodic
        handle.attrs["units"] = "m"
        handle.attrs["provenance"] = json.dumps(surface.provenance, default=str)
    return path


def check_dataset_storage(path: str | Path, dataset: h5py.Dataset, field: str) -> None:
    """Refuse a dataset whose shape promises more data than the file stores.

    HDF5 fills unwritten chunks with a fill value, so a corrupt or hostile shape could
    make a reader allocate terabytes from a small file. gzip (deflate) compresses by
    about 1032:1 at most, so more than 1100 bytes of data per stored byte is refused.

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
    TopographyFileError
        If ``size * itemsize > 1100 * stored bytes + 4096``.
    """
    needed = int(dataset.size) * dataset.dtype.itemsize
    stored = int(dataset.id.get_storage_size())
    if needed > 1100 * stored + 4096:
        raise TopographyFileError(
            path,
            field,
            f"has shape {dataset.shape} ({needed} bytes) but stores only {stored} bytes "
            "(truncated or corrupt file)",
        )


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
    return handle.attrs.get("format") == FORMAT_NAME


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
        Another version, a missing or non-2D ``/heights``, units other than m, or data
        that cannot be read (truncated file).
    """
    version = int(handle.attrs.get("version", -1))
    if version != FORMAT_VERSION:
        raise TopographyFileError(path, "version", f"is {version}; expected {FORMAT_VERSION}")
    dataset = handle.get("heights")
    if not isinstance(dataset, h5py.Dataset) or dataset.ndim != 2:
        raise TopographyFileError(path, "/heights", "is missing or not a 2D dataset")
    if dataset.dtype.kind not in "fiu":
        raise TopographyFileError(
            path, "/heights", f"has dtype {dataset.dtype}; expected real numbers (m)"
        )
    units = handle.attrs.get("units")
    if units != "m":
        raise TopographyFileError(path, "units", f"is {units!r}; expected 'm'")
    spacing = {}
    for name in ("dx", "dy"):
        try:
            spacing[name] = float(np.asarray(handle.attrs[name]).ravel()[0])
        except (KeyError, IndexError, TypeError, ValueError):
            raise TopographyFileError(
                path,
                f"attribute {name!r}",
                "is missing or not a number; expected a pixel size in m",
            ) from None
        require_positive(path, f"attribute {name!r}", spacing[name], " m")
    check_dataset_storage(path, dataset, "/heights")
    try:
        heights = dataset[()]
    except OSError as exc:
        raise TopographyFileError(path, "/heights", f"cannot be read ({exc})") from None
    try:
        provenance = json.loads(handle.attrs.get("provenance", "{}"))
    except json.JSONDecodeError:
        provenance = {}
    provenance = {**provenance, "file": str(path), "stored_format": FORMAT_NAME}
    provenance.setdefault("format", FORMAT_NAME)
    return HeightMap(
        heights, spacing["dx"], spacing["dy"], bool(handle.attrs.get("periodic", False)), provenance
    )
