"""Small helpers shared by the native readers: bounded reads, zip members, strict numbers,
and :func:`make_surface`, the one place a reader's result is checked and built."""

from __future__ import annotations

import re
import struct
import zipfile
import zlib
from pathlib import Path
from typing import Any, Literal, overload

import numpy as np

from asperity.files import describe_kind, read_bytes_bounded
from asperity.topo.errors import (
    CorruptFileError,
    NumberFormatError,
    OverBudgetError,
    PhysicalBoundsError,
    TopographyFileError,
    UnsupportedContentError,
)
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io.limits import (
    MAX_ABS_HEIGHT_M,
    MAX_DEFLATE_RATIO,
    MAX_FILE_BYTES,
    PIXEL_SIZE_BOUNDS_M,
    check_pixel_size,
)

#: The one number format of text files and text headers: a '.' decimal point, optional
#: exponent; no thousands separators, no '_', no decimal comma.
NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?")
#: Missing-value words accepted where a format allows missing values (text data).
NAN_WORDS = frozenset({"nan", "NaN", "NAN", "-nan", "+nan"})


def require_topography_file(path: str | Path) -> Path:
    """Return ``path`` if it is a regular file; refuse a FIFO, device, directory or socket.

    Parameters
    ----------
    path : str or Path
        The topography file the user named (a symbolic link is followed).

    Returns
    -------
    Path

    Raises
    ------
    TopographyFileError
        Not a regular file, saying what it is (``"is a FIFO (named pipe)"``).
    FileNotFoundError
        Nothing is there.
    """
    path = Path(path)
    kind = describe_kind(path)
    if kind is None:
        raise FileNotFoundError(f"{path}: no such file")
    if kind != "a regular file":
        raise TopographyFileError(
            path, "file", f"is {kind}; expected a regular file (a topography file)"
        )
    return path


def read_all_bytes(path: str | Path) -> bytes:
    """Return the whole file; refuse a special file, an empty one or one over the limit.

    The size limit is :data:`MAX_FILE_BYTES`; the read is bounded by it (a device such as
    ``/dev/zero`` cannot exhaust the memory) and never blocks (a FIFO is refused).
    """
    size = require_topography_file(path).stat().st_size
    if size > MAX_FILE_BYTES:
        raise OverBudgetError(
            path, "file", f"has {size} bytes; the readers read at most {MAX_FILE_BYTES} bytes"
        )
    data = read_bytes_bounded(path, str(path), MAX_FILE_BYTES)
    if not data:
        raise TopographyFileError(path, "file", "is empty (0 bytes); expected a topography file")
    return data


def decode_text(raw: bytes) -> str:
    """Decode a fixed-width text field (NUL padded, latin-1) and strip it."""
    return raw.split(b"\x00", 1)[0].decode("latin-1").strip()


def parse_number(path: str | Path, field: str, text: str, *, allow_nan: bool = False) -> float:
    """Parse ``text`` in the one stated number format, or refuse it naming ``field``.

    Parameters
    ----------
    path : str or Path
        The file (for the message).
    field : str
        Where the text is (header key, or line and column).
    text : str
        The number as written; surrounding blanks are ignored.
    allow_nan : bool
        Accept ``nan`` (any case shown in :data:`NAN_WORDS`) as a missing value.

    Returns
    -------
    float

    Raises
    ------
    NumberFormatError
        Not ``[+-]digits[.digits][e[+-]digits]`` (no ``_``, no decimal comma, no ``inf``).
    """
    token = text.strip()
    if NUMBER.fullmatch(token):
        return float(token)
    if allow_nan and token in NAN_WORDS:
        return float("nan")
    hint = ""
    if re.fullmatch(r"[+-]?\d*,\d+(?:[eE][+-]?\d+)?", token):
        hint = " (a decimal comma: write the decimal point as '.')"
    elif "_" in token:
        hint = " (digit separators '_' are not accepted)"
    raise NumberFormatError(
        path,
        field,
        f"is {token[:40]!r}{hint}; expected a number such as 1.5e-6 "
        "('.' decimal point, optional exponent)",
        expected="number",
        found=token[:40],
    )


def make_provenance(path: str | Path, fmt: str, **items: object) -> dict:
    """Provenance dict: file, format and whatever else the reader saw (instrument, units)."""
    provenance: dict = {"file": str(path), "format": fmt}
    provenance.update({key: value for key, value in items.items() if value not in (None, "")})
    return provenance


def require_positive(path: str | Path, field: str, value: float, unit: str = "") -> None:
    """Refuse a size or count that is not a finite number > 0."""
    if not (value > 0 and value < float("inf")):
        raise PhysicalBoundsError(
            path, field, f"is {value!r}{unit}; expected a finite value > 0", found=value
        )


@overload
def make_surface(
    path: str | Path,
    heights: np.ndarray,
    pixel_sizes: tuple[tuple[str, float], ...],
    provenance: dict,
    *,
    profile: Literal[False] = False,
) -> HeightMap: ...
@overload
def make_surface(
    path: str | Path,
    heights: np.ndarray,
    pixel_sizes: tuple[tuple[str, float], ...],
    provenance: dict,
    *,
    profile: Literal[True],
) -> LineProfile: ...
@overload
def make_surface(
    path: str | Path,
    heights: np.ndarray,
    pixel_sizes: tuple[tuple[str, float], ...],
    provenance: dict,
    *,
    profile: bool,
) -> HeightMap | LineProfile: ...
def make_surface(
    path: str | Path,
    heights: np.ndarray,
    pixel_sizes: tuple[tuple[str, float], ...],
    provenance: dict,
    *,
    profile: bool = False,
) -> HeightMap | LineProfile:
    """Check a reader's heights and pixel sizes, count missing pixels, build the result.

    Parameters
    ----------
    path : str or Path
        The file (for messages).
    heights : ndarray
        Heights in m, shape ``(nx, ny)`` (or ``(n,)`` for a profile); NaN = missing.
    pixel_sizes : ((field, dx), (field, dy)) or ((field, dx),)
        Pixel sizes in m, each with the header field it comes from.
    provenance : dict
        The reader's provenance; ``missing_pixels`` (the NaN count) is added.
    profile : bool
        Build a :class:`LineProfile` from ``heights.ravel()`` and the first pixel size.

    Returns
    -------
    HeightMap or LineProfile

    Raises
    ------
    PhysicalBoundsError
        A pixel size outside :data:`PIXEL_SIZE_BOUNDS_M`, a height beyond
        :data:`MAX_ABS_HEIGHT_M`.
    CorruptFileError
        Infinite heights.
    """
    sizes = [check_pixel_size(path, field, value) for field, value in pixel_sizes]
    heights = np.asarray(heights, dtype=np.float64)
    infinite = int(np.isinf(heights).sum())
    if infinite:
        raise CorruptFileError(
            path,
            "heights",
            f"hold {infinite} infinite values; expected finite heights (NaN = missing)",
        )
    largest = float(np.max(np.abs(heights), initial=0.0, where=~np.isnan(heights)))
    if largest > MAX_ABS_HEIGHT_M:
        raise PhysicalBoundsError(
            path,
            "heights",
            f"reach {largest:.6g} m; expected |height| <= {MAX_ABS_HEIGHT_M:g} m "
            "(a wrong scale factor or unit?)",
            found=largest,
        )
    provenance = {**provenance, "missing_pixels": int(np.isnan(heights).sum())}
    if profile:
        return LineProfile(heights.ravel(), sizes[0], provenance)
    return HeightMap(heights, sizes[0], sizes[-1], False, provenance)


# --- zip archives (X3P, NPZ) -------------------------------------------------------------

_ZIP_OPEN_ERRORS = (
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    OSError,
    EOFError,
    struct.error,
    UnicodeDecodeError,
    ValueError,
    NotImplementedError,
)
_ZIP_READ_ERRORS = (
    zipfile.BadZipFile,
    zlib.error,
    EOFError,
    OSError,
    RuntimeError,
    NotImplementedError,
    struct.error,
    ValueError,
)


def open_zip(path: str | Path, what: str) -> zipfile.ZipFile:
    """Open a zip archive, refusing an unreadable central directory (``what``: X3P, NPZ)."""
    try:
        return zipfile.ZipFile(path)
    except _ZIP_OPEN_ERRORS as exc:
        raise CorruptFileError(
            path, "zip container", f"is not a readable {what} (ZIP) archive ({exc}); truncated?"
        ) from None


def read_zip_member(
    path: str | Path, archive: zipfile.ZipFile, info: zipfile.ZipInfo, max_bytes: int
) -> bytes:
    """Read one archive member after checking its flags and declared sizes; CRC checked.

    Parameters
    ----------
    path : str or Path
        The archive (for messages).
    archive : zipfile.ZipFile
        The open archive.
    info : zipfile.ZipInfo
        The member.
    max_bytes : int
        Largest uncompressed size accepted (the caller's budget for this member).

    Returns
    -------
    bytes
        The member's uncompressed bytes, exactly ``info.file_size`` of them.

    Raises
    ------
    UnsupportedContentError
        An encrypted member, or a compression other than stored or deflate.
    OverBudgetError
        A declared size over ``max_bytes``.
    CorruptFileError
        A declared size no deflate stream can give, a failed CRC-32 or deflate stream.
    """
    field = f"zip member {info.filename!r}"
    if info.flag_bits & 0x1:
        raise UnsupportedContentError(path, field, "is encrypted; expected a plain member")
    if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
        raise UnsupportedContentError(
            path,
            field,
            f"uses compression method {info.compress_type}; expected 0 (stored) or 8 (deflate)",
        )
    if info.file_size > max_bytes:
        raise OverBudgetError(
            path, field, f"declares {info.file_size} bytes; at most {max_bytes} are accepted"
        )
    if info.compress_type == zipfile.ZIP_STORED and info.file_size != info.compress_size:
        raise CorruptFileError(
            path,
            field,
            f"is stored but declares {info.file_size} bytes from {info.compress_size}",
        )
    if info.file_size > MAX_DEFLATE_RATIO * info.compress_size + 4096:
        raise CorruptFileError(
            path,
            field,
            f"claims {info.file_size} bytes from {info.compress_size} compressed bytes; "
            "corrupt archive",
        )
    try:
        data = archive.read(info)
    except _ZIP_READ_ERRORS as exc:
        raise CorruptFileError(
            path, field, f"cannot be extracted ({exc}); corrupt archive (CRC-32 checked)"
        ) from None
    if len(data) != info.file_size:
        raise CorruptFileError(
            path, field, f"holds {len(data)} bytes; its header declares {info.file_size}"
        )
    return data


def zip_member_info(path: str | Path, archive: zipfile.ZipFile, name: str, field: str):
    """The :class:`zipfile.ZipInfo` of member ``name``, or refuse naming ``field``."""
    try:
        return archive.getinfo(name)
    except KeyError:
        raise CorruptFileError(path, field, f"names {name!r}, not in the archive") from None


def caller_pixel_size(
    path: str | Path, pixel_size: float | tuple[float, float] | None
) -> tuple[float, float] | None:
    """Validate a pixel size given by the caller for a file that carries none.

    Parameters
    ----------
    path : str or Path
        The file being read (named in the message).
    pixel_size : float or (float, float) or None
        ``dx`` (square pixels) or ``(dx, dy)``, in m.

    Returns
    -------
    (float, float) or None
        ``(dx, dy)`` in m, or None when ``pixel_size`` is None.

    Raises
    ------
    InputError
        Not one or two finite lengths within :data:`PIXEL_SIZE_BOUNDS_M`.
    """
    from asperity.errors import InputError

    if pixel_size is None:
        return None
    # The caller's values, checked one by one below (anything may arrive from a command line).
    values: tuple[Any, ...] = (
        (pixel_size, pixel_size) if np.ndim(pixel_size) == 0 else tuple(pixel_size)  # type: ignore[arg-type]
    )
    if len(values) != 2:
        raise InputError(
            f"{path}: pixel_size: is {pixel_size!r}; expected dx or (dx, dy), in metres"
        )
    low, high = PIXEL_SIZE_BOUNDS_M
    sizes = []
    for name, value in zip(("dx", "dy"), values, strict=True):
        try:
            size = float(value)
        except (TypeError, ValueError):
            size = float("nan")
        if not (size > 0 and size < float("inf")):
            raise InputError(
                f"{path}: pixel_size {name}: is {value!r}; expected a finite length > 0 m"
            )
        if not low <= size <= high:
            raise InputError(
                f"{path}: pixel_size {name}: is {value!r}; expected {low:g} m .. {high:g} m"
            )
        sizes.append(size)
    return sizes[0], sizes[1]
