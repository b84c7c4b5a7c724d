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

from topo.errors import TopographyFileError
from topo.heightmap import HeightMap, require_height_map

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


def is_project_hdf5(handle: h5py.File) -> bool:
    """True if an open HDF5 file is in the project's height-map format."""
    return handle.attrs.get("format") == FORMAT_NAME


def read_project_hdf5(path: str | Path, handle: h5py.File) -> HeightMap:
    """Read the project's HDF5 height map from an open file handle."""
    version = int(handle.attrs.get("version", -1))
    if version != FORMAT_VERSION:
        raise TopographyFileError(path, "version", f"is {version}; expected {FORMAT_VERSION}")
    if "heights" not in handle or handle["heights"].ndim != 2:
        raise TopographyFileError(path, "/heights", "is missing or not 2D")
    units = handle.attrs.get("units")
    if units != "m":
        raise TopographyFileError(path, "units", f"is {units!r}; expected 'm'")
    try:
        heights = handle["heights"][()]
    except OSError as exc:
        raise TopographyFileError(path, "/heights", f"cannot be read ({exc})") from None
    try:
        provenance = json.loads(handle.attrs.get("provenance", "{}"))
    except json.JSONDecodeError:
        provenance = {}
    provenance = {**provenance, "file": str(path), "stored_format": FORMAT_NAME}
    provenance.setdefault("format", FORMAT_NAME)
    return HeightMap(
        heights,
        float(handle.attrs["dx"]),
        float(handle.attrs["dy"]),
        bool(handle.attrs["periodic"]),
        provenance,
    )
