"""Wyko / Veeco Vision ``.opd`` reader.

Layout (little-endian; facts from public notes on the Vision OPD format): two bytes
(``01 00``), then a directory block. Every directory entry is 24 bytes: name (16 bytes,
NUL padded), type (int16), length (int32), attributes (uint16). The first entry is the
directory itself, its length is the directory size (a multiple of 24). Block contents
follow the directory back to back, in directory order, for entries of length > 0. The
data block (``RAW DATA``, ``RAW_DATA``, ``OPD`` or ``Raw``) starts with ``nx``, ``ny``,
item size (uint16) and holds ``nx*ny`` items with the x index varying slowest. Heights
are in units of ``Wavelength`` (nm) / ``Mult``; ``Pixel_size`` is in mm, ``Aspect`` scales y.
Undefined points are stored as huge finite values (|v| >= 1e32) or NaN; they become NaN,
counted in ``provenance["missing_pixels"]``. An infinite value is refused, as in every reader.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from asperity.topo.errors import PhysicalBoundsError, TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import (
    make_provenance,
    make_surface,
    read_all_bytes,
    require_positive,
)
from asperity.topo.io.limits import check_height_step

_ENTRY = struct.Struct("<16shlH")
_DATA_BLOCKS = ("RAW DATA", "RAW_DATA", "OPD", "Raw")
_DTYPES: dict[int, np.dtype] = {1: np.dtype("i1"), 2: np.dtype("<i2"), 4: np.dtype("<f4")}


def read_opd(path: str | Path) -> HeightMap:
    """Read a Wyko ``.opd`` file (heights and pixel sizes in m, undefined points NaN).

    Parameters
    ----------
    path : str or Path
        The .opd file.

    Returns
    -------
    HeightMap
        Heights in m (NaN = undefined point), pixel sizes in m,
        provenance (instrument, units seen). ``heights[ix, iy]``: ``iy`` from the top line
        of the image as Vision and Gwyddion display it (the file stores it last).

    Raises
    ------
    TopographyFileError
        A missing directory, a directory length that is not a multiple of 24, blocks that
        run past the end of the file, a data block whose length disagrees with its
        ``nx*ny*itemsize``, or missing ``Wavelength``/``Pixel_size`` blocks.
    """
    path = Path(path)
    data = read_all_bytes(path)
    blocks = _directory(path, data)
    values = _scale_values(path, data, blocks)
    mult = values["Mult"]
    name, offset, nx, ny, itemsize = _data_block(path, data, blocks)
    raw = np.frombuffer(data, dtype=_DTYPES[itemsize], count=nx * ny, offset=offset + 6)
    step = check_height_step(path, "Wavelength / Mult", values["Wavelength"] * 1e-9 / mult)
    heights = _heights_with_missing(raw, step)
    pixel = values["Pixel_size"] * 1e-3
    provenance = make_provenance(
        path,
        "opd",
        instrument="Wyko Vision",
        channel=name,
        invalid_marker="finite |value| >= 1e32 or NaN",
        units={
            "lateral": "mm",
            "height": f"wavelength/{mult} (wavelength {values['Wavelength']} nm)",
        },
    )
    sizes = (("Pixel_size", pixel), ("Pixel_size * Aspect", pixel * values["Aspect"]))
    # the columns run from the bottom of the image up: flip to iy 0 = top line
    heights = np.ascontiguousarray(heights.reshape(nx, ny)[:, ::-1])
    return make_surface(path, heights, sizes, provenance)


def _directory(path: Path, data: bytes) -> dict[str, tuple[int, int]]:
    """Block name -> (offset, length) in bytes, from the directory (first entry of a name wins)."""
    check_size(path, "directory entry", 2 + _ENTRY.size, len(data))
    name, _kind, dir_length, _attr = _ENTRY.unpack_from(data, 2)
    if name.split(b"\x00", 1)[0] != b"Directory":
        raise TopographyFileError(
            path, "directory", f"first block is {name!r}; expected 'Directory'"
        )
    if dir_length <= 0 or dir_length % _ENTRY.size:
        raise TopographyFileError(
            path, "directory length", f"is {dir_length}; expected a positive multiple of 24"
        )
    check_size(path, "directory length", 2 + dir_length, len(data))
    position = 2 + dir_length
    blocks: dict[str, tuple[int, int]] = {}
    for index in range(1, dir_length // _ENTRY.size):
        raw_name, _kind, length, _attr = _ENTRY.unpack_from(data, 2 + index * _ENTRY.size)
        if length <= 0:
            continue
        block_name = raw_name.split(b"\x00", 1)[0].decode("latin-1")
        check_size(path, f"block {block_name!r} length", position + length, len(data))
        blocks.setdefault(block_name, (position, length))
        position += length
    return blocks


def _scale_values(path: Path, data: bytes, blocks: dict[str, tuple[int, int]]) -> dict:
    """The scale values of their blocks, checked.

    ``Wavelength`` (nm, > 0) and ``Pixel_size`` (mm, > 0) are required; ``Mult`` (>= 1)
    defaults to 1 and ``Aspect`` (> 0) to 1.0.
    """
    values = {}
    for key, fmt in (("Wavelength", "<f"), ("Mult", "<H"), ("Aspect", "<f"), ("Pixel_size", "<f")):
        if key in blocks:
            offset, length = blocks[key]
            if length < struct.calcsize(fmt):
                raise TopographyFileError(path, f"block {key!r}", f"has {length} bytes; too short")
            values[key] = struct.unpack_from(fmt, data, offset)[0]
    for key in ("Wavelength", "Pixel_size"):
        if key not in values:
            raise TopographyFileError(path, f"block {key!r}", "is missing; needed for the scale")
    require_positive(path, "Wavelength", values["Wavelength"], " nm")
    require_positive(path, "Pixel_size", values["Pixel_size"], " mm")
    values.setdefault("Mult", 1)
    if values["Mult"] < 1:
        mult = values["Mult"]
        raise PhysicalBoundsError(path, "block 'Mult'", f"is {mult}; expected >= 1", found=mult)
    values.setdefault("Aspect", 1.0)
    require_positive(path, "Aspect", values["Aspect"])
    return values


def _data_block(
    path: Path, data: bytes, blocks: dict[str, tuple[int, int]]
) -> tuple[str, int, int, int, int]:
    """(name, offset, nx, ny, itemsize) of the data block, its length checked."""
    name = next((candidate for candidate in _DATA_BLOCKS if candidate in blocks), None)
    if name is None:
        raise TopographyFileError(path, "data block", f"none of {_DATA_BLOCKS} found")
    offset, length = blocks[name]
    if length < 6:
        raise TopographyFileError(
            path, f"block {name!r} length", f"is {length}; expected 6 + nx*ny*itemsize"
        )
    nx, ny, itemsize = struct.unpack_from("<HHH", data, offset)
    if itemsize not in _DTYPES:
        raise TopographyFileError(
            path, f"block {name!r} item size", f"is {itemsize}; expected 1, 2, 4"
        )
    if length != 6 + nx * ny * itemsize or nx < 1 or ny < 1:
        raise TopographyFileError(
            path,
            f"block {name!r} length",
            f"is {length}; expected 6 + {nx}*{ny}*{itemsize} = {6 + nx * ny * itemsize}",
        )
    return name, offset, nx, ny, itemsize


def _heights_with_missing(raw: np.ndarray, step: float) -> np.ndarray:
    """Heights in m (``raw * step``), NaN where undefined (finite |v| >= 1e32, or NaN).

    An infinite value is not the format's marker: it is kept, and refused by
    :func:`make_surface` as in every reader.
    """
    raw = raw.astype(np.float64)
    invalid = np.isnan(raw) | (np.isfinite(raw) & (np.abs(raw) >= 1e32))
    heights = raw * step
    heights[invalid] = np.nan
    return heights
