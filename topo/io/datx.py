"""Zygo ``.datx`` reader (HDF5 container written by Mx).

Facts (public notes on DATX): a ``/MetaData`` table of (source, link, destination) byte
strings describes the tree; ``Root -> Measurement -> Surface -> Path`` gives the surface
dataset. That dataset carries the attributes ``No Data`` (the missing-value marker),
``Unit`` (height unit) and ``X Converter``/``Y Converter``/``Z Converter`` (compound:
category, base unit, parameters; for lateral axes ``parameters[1]`` is the pixel size in
m). The dataset is stored row by row (C order ``(ny, nx)``, x fastest). ``No Data`` values
and non-finite values become NaN, counted in ``provenance["missing_pixels"]``. Links are
resolved as in :mod:`asperity.topo.io.hdf5` (no external storage, links or plugins).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, make_surface
from asperity.topo.io.hdf5 import (
    H5PY_ERRORS,
    read_attribute,
    read_dataset,
    resolve_dataset,
)
from asperity.topo.io.units import length_unit_in_metres


def _text(value: object) -> str:
    if isinstance(value, bytes):
        return value.decode("latin-1")
    if isinstance(value, np.ndarray) and value.size == 1:
        return _text(value.ravel()[0])
    return str(value)


def is_datx(handle: h5py.File) -> bool:
    """Whether an open HDF5 file looks like a Zygo DATX file (has a ``/MetaData`` table).

    Parameters
    ----------
    handle : h5py.File
        The open file.

    Returns
    -------
    bool
    """
    try:
        return "MetaData" in handle
    except H5PY_ERRORS:
        return False


def _surface_path(path: Path, handle: h5py.File) -> str:
    links: dict[str, dict[str, str]] = {}
    table = read_dataset(path, resolve_dataset(path, handle, "/MetaData"), "/MetaData")
    try:
        for row in table.ravel():
            source, link, destination = (_text(item) for item in tuple(row)[:3])
            links.setdefault(source, {})[link] = destination
    except (TypeError, ValueError, KeyError) as exc:
        raise TopographyFileError(
            path, "/MetaData", f"is not a (source, link, destination) table ({exc})"
        ) from None
    node = "Root"
    for step in ("Measurement", "Surface", "Path"):
        following = links.get(node, {}).get(step)
        if following is None:
            raise TopographyFileError(
                path, "/MetaData", f"has no '{step}' entry on the way to the surface"
            )
        node = following
    return node


def _converter_step(path: Path, dataset: h5py.Dataset, name: str) -> float:
    value = read_attribute(path, dataset, name)
    if value is None:
        raise TopographyFileError(path, name, "attribute is missing")
    try:
        record = np.asarray(value).ravel()[0]
        parameters = np.asarray(tuple(record)[-1], dtype=float).ravel()
        step = float(parameters[1])
    except (ValueError, IndexError, TypeError):
        raise TopographyFileError(path, name, "has no pixel size in its parameters") from None
    if not step > 0:
        raise TopographyFileError(path, name, f"pixel size is {step!r}; expected > 0 m")
    return step


def read_datx(path: str | Path, handle: h5py.File) -> HeightMap:
    """Read the surface of an open Zygo DATX file; heights and pixel sizes in m.

    Parameters
    ----------
    path : str or Path
        The ``.datx`` file (for messages and provenance).
    handle : h5py.File
        The file, open for reading.

    Returns
    -------
    HeightMap
        Heights in m (``No Data`` and non-finite values NaN), pixel sizes in m.

    Raises
    ------
    TopographyFileError
        A missing metadata link, converter or unit; a non-length height unit.
    """
    path = Path(path)
    surface_path = _surface_path(path, handle)
    dataset = resolve_dataset(path, handle, surface_path)
    if dataset.ndim != 2:
        raise TopographyFileError(path, surface_path, f"has shape {dataset.shape}; expected 2D")
    unit = _text(read_attribute(path, dataset, "Unit", b"")).strip()
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise TopographyFileError(
            path, f"{surface_path} Unit", f"is {unit!r}; expected a length unit"
        )
    dx = _converter_step(path, dataset, "X Converter")
    dy = _converter_step(path, dataset, "Y Converter")
    if dataset.dtype.kind not in "fiu":
        raise TopographyFileError(
            path, surface_path, f"has dtype {dataset.dtype}; expected real numbers"
        )
    raw = read_dataset(path, dataset, surface_path).astype(np.float64)
    invalid = ~np.isfinite(raw)
    no_data = np.asarray(read_attribute(path, dataset, "No Data", np.nan))
    if no_data.dtype.kind not in "fiu" or no_data.size < 1:
        raise TopographyFileError(
            path, f"{surface_path} No Data", f"is {no_data!r}; expected a number"
        )
    invalid |= raw == float(no_data.ravel()[0])
    heights = raw * factor
    heights[invalid] = np.nan
    provenance = make_provenance(
        path,
        "datx",
        instrument="Zygo (DATX)",
        channel=surface_path,
        units={"height": unit, "lateral": "m"},
        invalid_marker="'No Data' value or non-finite",
    )
    sizes = (("X Converter pixel size", dx), ("Y Converter pixel size", dy))
    return make_surface(path, heights.T, sizes, provenance)
