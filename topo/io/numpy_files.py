"""NumPy ``.npy`` / ``.npz`` height arrays, read without unpickling or trusting the header.

The arrays carry no pixel size: the caller gives ``pixel_size`` (m), unless an ``.npz``
holds scalar ``dx`` and ``dy`` entries beside ``heights``. Heights are taken as metres.

Every ``.npy`` header (alone, or a member of an ``.npz`` archive) is parsed first; its
shape times the item size must fit in the bytes that follow it (and, inside an archive,
in the member's size, which a deflated member cannot exceed 1100 times its compressed
size), so a corrupt header cannot make the reader allocate memory the file does not back.
Object (pickled) arrays are refused.
"""

from __future__ import annotations

import math
import zipfile
from pathlib import Path
from typing import IO

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import caller_pixel_size, make_provenance

#: Deflate cannot compress by more than about 1032:1; a member claiming more is corrupt.
_MAX_DEFLATE_RATIO = 1100


def _read_npy(path: Path, handle: IO[bytes], available: int, where: str) -> np.ndarray:
    """Parse one NPY stream of ``available`` bytes; check its header before reading data."""
    try:
        version = np.lib.format.read_magic(handle)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(handle)
        elif version in ((2, 0), (3, 0)):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(handle)
        else:
            raise ValueError(f"unknown NPY format version {version}")
    except (ValueError, EOFError, OSError, SyntaxError) as exc:
        raise TopographyFileError(
            path, f"{where} NPY header", f"is unreadable ({exc}); truncated or not NPY"
        ) from None
    if dtype.hasobject:
        raise TopographyFileError(
            path, f"{where} dtype", f"is {dtype}; object arrays need unpickling, which is refused"
        )
    if dtype.kind not in "fiu":
        raise TopographyFileError(path, f"{where} dtype", f"is {dtype}; expected real numbers")
    if len(shape) not in (0, 1, 2):
        raise TopographyFileError(path, f"{where} shape", f"is {shape}; expected 1D or 2D")
    count = math.prod(shape)
    needed = count * dtype.itemsize
    remaining = available - handle.tell()
    if needed > remaining:
        raise TopographyFileError(
            path,
            f"{where} shape",
            f"is {shape} of {dtype} ({needed} bytes) but only {remaining} bytes follow "
            "the header (truncated file or corrupt header)",
        )
    data = handle.read(needed)
    if len(data) != needed:
        raise TopographyFileError(
            path, f"{where} data", f"has {len(data)} bytes; expected {needed} (truncated)"
        )
    values = np.frombuffer(data, dtype=dtype, count=count)
    return values.reshape(shape, order="F" if fortran else "C")


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        archive = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as exc:
        raise TopographyFileError(
            path, "zip container", f"is not a readable NPZ archive ({exc}); truncated?"
        ) from None
    arrays: dict[str, np.ndarray] = {}
    with archive:
        for info in archive.infolist():
            if not info.filename.endswith(".npy"):
                continue
            key = info.filename[: -len(".npy")]
            where = f"array {key!r}"
            if info.compress_type != zipfile.ZIP_STORED and info.file_size > (
                _MAX_DEFLATE_RATIO * info.compress_size + 4096
            ):
                raise TopographyFileError(
                    path,
                    f"{where} member size",
                    f"claims {info.file_size} bytes from {info.compress_size} compressed "
                    "bytes; corrupt archive",
                )
            try:
                with archive.open(info) as handle:
                    arrays[key] = _read_npy(path, handle, info.file_size, where)
            except (zipfile.BadZipFile, OSError, EOFError) as exc:
                raise TopographyFileError(path, where, f"is corrupt ({exc})") from None
    return arrays


def _scalar_length(path: Path, arrays: dict[str, np.ndarray], key: str) -> float:
    value = arrays[key]
    if value.size != 1:
        raise TopographyFileError(
            path, f"array {key!r}", f"has shape {value.shape}; expected one pixel size in m"
        )
    size = float(value.ravel()[0])
    if not (size > 0 and math.isfinite(size)):
        raise TopographyFileError(
            path, f"array {key!r}", f"is {size!r}; expected a finite pixel size > 0 m"
        )
    return size


def read_numpy(
    path: str | Path, *, pixel_size: float | tuple[float, float] | None = None
) -> HeightMap | LineProfile:
    """Read heights (m) from ``.npy`` or ``.npz`` (key ``heights``, or the only array).

    Parameters
    ----------
    path : str or Path
        The ``.npy`` or ``.npz`` file; heights in m.
    pixel_size : float or (float, float), optional
        Pixel size in m (``dx`` or ``(dx, dy)``); required unless the ``.npz`` has
        ``dx`` (and optionally ``dy``) entries. When given, it replaces those entries.

    Returns
    -------
    HeightMap or LineProfile
        A 2D array is a (non-periodic) HeightMap, a 1D array a LineProfile.

    Raises
    ------
    TopographyFileError
        Truncated or corrupt files, headers that promise more data than the file holds,
        object arrays, more than 2 dimensions, a missing key, a bad ``dx``/``dy`` entry.
    ValueError
        No pixel size available, or an invalid ``pixel_size``.
    """
    path = Path(path)
    dx = dy = None
    if path.suffix.lower() == ".npz" or zipfile.is_zipfile(path):
        arrays = _read_npz(path)
        keys = sorted(arrays)
        if "heights" in arrays:
            key = "heights"
        elif len(keys) == 1:
            key = keys[0]
        else:
            raise TopographyFileError(
                path, "arrays", f"are {keys}; expected a 'heights' array (or a single array)"
            )
        heights = arrays[key]
        if "dx" in arrays and pixel_size is None:
            dx = _scalar_length(path, arrays, "dx")
            dy = _scalar_length(path, arrays, "dy") if "dy" in arrays else dx
    else:
        with open(path, "rb") as handle:
            heights = _read_npy(path, handle, path.stat().st_size, "array")
    if heights.ndim not in (1, 2):
        raise TopographyFileError(path, "shape", f"is {heights.shape}; expected 1D or 2D")
    if min(heights.shape) < 1:
        raise TopographyFileError(path, "shape", f"is {heights.shape}; the array is empty")
    given = caller_pixel_size(path, pixel_size)
    if given is not None:
        dx, dy = given
    if dx is None:
        raise InputError(
            f"{path}: a NumPy array carries no pixel size; give pixel_size= "
            "(or --pixel-size DX on the command line), in metres"
        )
    provenance = make_provenance(
        path, path.suffix.lstrip(".").lower(), units={"all": "m (assumed)"}
    )
    if heights.ndim == 1:
        return LineProfile(heights, float(dx), provenance)
    return HeightMap(heights, float(dx), float(dy), False, provenance)
