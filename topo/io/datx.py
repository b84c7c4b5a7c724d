"""Zygo ``.datx`` reader (HDF5 container written by Mx).

Facts (public notes on DATX): a ``/MetaData`` table of (source, link, destination) byte
strings describes the tree; ``Root -> Measurement -> Surface -> Path`` gives the surface
dataset. That dataset carries the attributes ``No Data`` (the missing-value marker),
``Unit`` (height unit) and ``X Converter``/``Y Converter``/``Z Converter`` (compound:
category, base unit, parameters; for lateral axes ``parameters[1]`` is the pixel size in
m). The dataset is stored row by row (C order ``(ny, nx)``, x fastest).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance
from asperity.topo.io.hdf5 import check_dataset_storage
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
    return "MetaData" in handle


def _surface_path(path: Path, handle: h5py.File) -> str:
    links: dict[str, dict[str, str]] = {}
    try:
        for row in handle["MetaData"][()]:
            source, link, destination = (_text(item) for item in tuple(row)[:3])
            links.setdefault(source, {})[link] = destination
    except (TypeError, ValueError, KeyError) as exc:
        raise TopographyFileError(
            path, "/MetaData", f"is not a (source, link, destination) table ({exc})"
        ) from None
    node = "Root"
    for step in ("Measurement", "Surface", "Path"):
        node = links.get(node, {}).get(step)
        if node is None:
            raise TopographyFileError(
                path, "/MetaData", f"has no '{step}' entry on the way to the surface"
            )
    if node not in handle:
        raise TopographyFileError(
            path, "/MetaData Surface Path", f"names {node!r}, not in the file"
        )
    return node


def _converter_step(path: Path, attrs: h5py.AttributeManager, name: str) -> float:
    if name not in attrs:
        raise TopographyFileError(path, name, "attribute is missing")
    record = np.asarray(attrs[name]).ravel()[0]
    fields = tuple(record)
    try:
        parameters = np.asarray(fields[-1], dtype=float).ravel()
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
    dataset = handle[surface_path]
    if dataset.ndim != 2:
        raise TopographyFileError(path, surface_path, f"has shape {dataset.shape}; expected 2D")
    attrs = dataset.attrs
    unit = _text(attrs.get("Unit", b"")).strip()
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise TopographyFileError(
            path, f"{surface_path} Unit", f"is {unit!r}; expected a length unit"
        )
    dx = _converter_step(path, attrs, "X Converter")
    dy = _converter_step(path, attrs, "Y Converter")
    if dataset.dtype.kind not in "fiu":
        raise TopographyFileError(
            path, surface_path, f"has dtype {dataset.dtype}; expected real numbers"
        )
    check_dataset_storage(path, dataset, surface_path)
    try:
        raw = np.asarray(dataset[()], dtype=np.float64)
    except OSError as exc:
        raise TopographyFileError(path, surface_path, f"cannot be read ({exc})") from None
    invalid = ~np.isfinite(raw)
    if "No Data" in attrs:
        invalid |= raw == float(np.asarray(attrs["No Data"]).ravel()[0])
    heights = raw * factor
    heights[invalid] = np.nan
    provenance = make_provenance(
        path,
        "datx",
        instrument="Zygo (DATX)",
        channel=surface_path,
        units={"height": unit, "lateral": "m"},
    )
    return HeightMap(heights.T, dx, dy, False, provenance)
