"""NumPy ``.npy`` / ``.npz`` height arrays, read without unpickling or trusting the header.

The arrays carry no pixel size: the caller gives ``pixel_size`` (m), unless an ``.npz``
holds scalar ``dx`` and ``dy`` entries beside ``heights``. Heights are taken as metres.

Every ``.npy`` header (alone, or a member of an ``.npz`` archive) is parsed first; its
shape times the item size must fit in the bytes that follow it (and, inside an archive,
in the member's size, which a deflated member cannot exceed 1100 times its compressed
size), so a corrupt header cannot make the reader allocate memory the file does not back;
the data must fill the rest of the file or member exactly (trailing bytes are refused) and
every archive member is read to its end, so its CRC-32 is checked. Encrypted members and
compression methods other than stored and deflate are refused, and so are object (pickled)
arrays, negative dimensions and arrays over the memory budget. An archive member's header is
read (inflating a few hundred bytes) and its shape checked against the budget before the
member is decompressed, so a compressed bomb is refused at once.
"""

from __future__ import annotations

import io
import math
import re
import tokenize
import zipfile
import zlib
from pathlib import Path
from typing import IO

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import CorruptFileError, TopographyFileError, TruncatedFileError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import (
    caller_pixel_size,
    make_provenance,
    make_surface,
    open_zip,
    read_zip_member,
)
from asperity.topo.io.limits import MAX_MAP_BYTES, check_map_points, check_pixel_size

#: What numpy's header parser raises on a damaged header (it evaluates a Python literal).
_HEADER_ERRORS = (
    ValueError,
    EOFError,
    OSError,
    SyntaxError,
    tokenize.TokenError,
    TypeError,
    KeyError,
    RecursionError,
    MemoryError,
    UnicodeDecodeError,
)


#: What reading the start of an archive member can raise on a corrupt archive.
_ZIP_STREAM_ERRORS = (zipfile.BadZipFile, zlib.error, EOFError, OSError, RuntimeError, ValueError)


def _header_refusal(exc: BaseException) -> str:
    """Why an NPY header was refused, in asperity's words: numpy's refusal of an oversized
    header advises ``allow_pickle=True`` (trusting the file), advice a reader of untrusted
    files must not pass on."""
    text = str(exc)
    size = re.search(r"Header info length \((\d+)\)", text)
    if size is not None:
        return (
            f"is {size.group(1)} bytes long, larger than numpy parses safely (a header of a "
            "few hundred bytes describes any array); corrupt or hostile file"
        )
    return f"is unreadable ({text}); truncated or not NPY"


def _npy_header(path: Path, handle: IO[bytes], where: str) -> tuple[tuple, bool, np.dtype]:
    """(shape, Fortran order, dtype) of one NPY stream's header, the type and rank checked."""
    try:
        version = np.lib.format.read_magic(handle)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(handle)
        elif version in ((2, 0), (3, 0)):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(handle)
        else:
            raise ValueError(f"unknown NPY format version {version}")
    except _HEADER_ERRORS as exc:
        raise CorruptFileError(path, f"{where} NPY header", _header_refusal(exc)) from None
    if dtype.hasobject:
        raise TopographyFileError(
            path, f"{where} dtype", f"is {dtype}; object arrays need unpickling, which is refused"
        )
    if dtype.kind not in "fiu":
        raise TopographyFileError(path, f"{where} dtype", f"is {dtype}; expected real numbers")
    if len(shape) not in (0, 1, 2):
        raise TopographyFileError(path, f"{where} shape", f"is {shape}; expected 1D or 2D")
    if any(dim < 0 for dim in shape):
        raise CorruptFileError(path, f"{where} shape", f"is {shape}; negative dimension")
    return shape, fortran, dtype


def _read_npy(path: Path, handle: IO[bytes], available: int, where: str) -> np.ndarray:
    """Parse one NPY stream of ``available`` bytes; check its header before reading data."""
    shape, fortran, dtype = _npy_header(path, handle, where)
    count = math.prod(shape)
    needed = count * dtype.itemsize
    remaining = available - handle.tell()
    if needed > remaining:
        raise TruncatedFileError(
            path,
            f"{where} shape",
            f"is {shape} of {dtype} ({needed} bytes) but only {remaining} bytes follow "
            "the header (truncated file or corrupt header)",
        )
    check_map_points(path, f"{where} shape", *shape)
    if needed < remaining:
        raise CorruptFileError(
            path,
            f"{where} shape",
            f"is {shape} of {dtype} ({needed} bytes) but {remaining} bytes follow the "
            "header; expected exactly the array (corrupt header or trailing data)",
        )
    data = handle.read(needed)
    if len(data) != needed:
        raise TopographyFileError(
            path, f"{where} data", f"has {len(data)} bytes; expected {needed} (truncated)"
        )
    values = np.frombuffer(data, dtype=dtype, count=count)
    return values.reshape(shape, order="F" if fortran else "C")


def _check_member_grid(
    path: Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo, where: str
) -> None:
    """Check an archive member's declared NPY shape against the memory budget, reading (and
    inflating) only its header, so a compressed bomb is refused before it is decompressed.

    An encrypted member or another compression is left to :func:`read_zip_member`, which
    refuses it naming the flag or the method.
    """
    if info.flag_bits & 0x1 or info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
        return
    try:
        with archive.open(info) as stream:
            shape, _, _ = _npy_header(path, stream, where)
    except _ZIP_STREAM_ERRORS as exc:
        raise CorruptFileError(
            path, f"{where} NPY header", f"cannot be extracted ({exc}); corrupt archive"
        ) from None
    check_map_points(path, f"{where} shape", *shape)


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    arrays: dict[str, np.ndarray] = {}
    budget = 2 * MAX_MAP_BYTES
    with open_zip(path, "NPZ") as archive:
        for info in archive.infolist():
            if not info.filename.endswith(".npy"):
                continue
            key = info.filename[: -len(".npy")]
            _check_member_grid(path, archive, info, f"array {key!r}")
            data = read_zip_member(path, archive, info, budget)
            budget -= len(data)
            arrays[key] = _read_npy(path, io.BytesIO(data), len(data), f"array {key!r}")
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
    return check_pixel_size(path, f"array {key!r}", size)


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
    dx: float | None = None
    dy: float | None = None
    key = "array"
    with open(path, "rb") as handle:
        is_archive = handle.read(4) == b"PK\x03\x04"
    if path.suffix.lower() == ".npz" or is_archive:
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
    assert dy is not None  # set together with dx above
    provenance = make_provenance(
        path, path.suffix.lstrip(".").lower(), channel=key, units={"all": "m (assumed)"}
    )
    source = "pixel_size" if given is not None else "array 'dx'"
    if heights.ndim == 1:
        return make_surface(path, heights, ((source, dx),), provenance, profile=True)
    sizes = ((source, dx), (source if given is not None else "array 'dy'", dy))
    return make_surface(path, heights, sizes, provenance)
