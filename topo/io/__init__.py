"""Native readers of measured topography, and :func:`read_surface`, the dispatcher.

Every reader returns heights in m and pixel sizes in m, with missing pixels as NaN, and
refuses truncated, corrupt or mislabelled files with a :class:`topo.errors.TopographyFileError`
(an :class:`asperity.errors.InputError`) naming the file, the field and what was expected.

:func:`read_surface` is the one entry point: nothing but a ``TopographyFileError`` (or an
``InputError`` for a bad ``channel``/``pixel_size`` argument) leaves it for a bad file. The
failures of the decoders the readers use on a file's bytes (zlib, zipfile, struct, text
decoding, numpy's NPY header parser, h5py, arithmetic overflow, recursion, memory) are turned
into a :class:`~asperity.topo.errors.CorruptFileError` (or
:class:`~asperity.topo.errors.OverBudgetError`) naming the file; any other exception is a
defect of the reader and surfaces as itself.
"""

from __future__ import annotations

import struct
import tokenize
import zipfile
import zlib
from pathlib import Path

import h5py
import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import (
    CorruptFileError,
    OverBudgetError,
    TopographyFileError,
    UnsupportedContentError,
)
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.io._common import require_topography_file
from asperity.topo.io.datx import is_datx, read_datx
from asperity.topo.io.dektak import looks_like_dektak, read_dektak
from asperity.topo.io.gwy import read_gwy
from asperity.topo.io.hdf5 import H5PY_ERRORS, is_project_hdf5, read_project_hdf5, write_hdf5
from asperity.topo.io.metropro import MAGICS as _METROPRO_MAGICS
from asperity.topo.io.metropro import read_metropro
from asperity.topo.io.nanoscope import read_nanoscope
from asperity.topo.io.numpy_files import read_numpy
from asperity.topo.io.opd import read_opd
from asperity.topo.io.picoview import read_picoview
from asperity.topo.io.plu import read_plu
from asperity.topo.io.sur import read_sur
from asperity.topo.io.surfacetopography import read_with_extra
from asperity.topo.io.text import read_text
from asperity.topo.io.x3p import read_x3p

__all__ = ["read_surface", "write_hdf5", "detect_format", "FORMATS_BY_EXTENSION"]

#: File extensions and the format each one announces.
FORMATS_BY_EXTENSION = {
    ".x3p": "x3p",
    ".sur": "sur",
    ".dat": "metropro",
    ".datx": "hdf5",
    ".plu": "plu",
    ".apx": "plu",
    ".opd": "opd",
    ".di": "nanoscope",
    ".spm": "nanoscope",
    ".mi": "picoview",
    ".gwy": "gwy",
    ".csv": "text",
    ".txt": "text",
    ".asc": "text",
    ".xyz": "text",
    ".npy": "npy",
    ".npz": "npz",
    ".h5": "hdf5",
    ".hdf5": "hdf5",
}

_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"

#: Exceptions of the decoders run on a file's bytes: a bad file, not a defect of asperity.
DECODER_FAILURES = (
    zlib.error,
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    struct.error,
    UnicodeDecodeError,
    tokenize.TokenError,
    EOFError,
    OverflowError,
    ZeroDivisionError,
    RecursionError,
    OSError,
    np.linalg.LinAlgError,
)


def _looks_like_text(head: bytes) -> bool:
    if b"\x00" in head:
        return False
    try:
        head.decode("utf-8")
    except UnicodeDecodeError:
        try:
            head.decode("latin-1")
        except UnicodeDecodeError:
            return False
    return True


def detect_format(path: str | Path) -> str | None:
    """The format named by the first bytes of a file (magic numbers).

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    str or None
        ``"x3p"``, ``"sur"``, ``"metropro"``, ``"hdf5"``, ``"gwy"``, ``"nanoscope"``,
        ``"picoview"``, ``"npy"``, ``"npz"``, ``"opd"``, ``"text"``, ``"zip"`` (another
        archive), or None if unknown.
    """
    with open(path, "rb") as handle:
        head = handle.read(4096)
    if head.startswith(b"DIGITAL SURF"):
        return "sur"
    if head[:4] in _METROPRO_MAGICS:
        return "metropro"
    if head.startswith(_HDF5_MAGIC):
        return "hdf5"
    if head.startswith(b"GWYP"):
        return "gwy"
    if head.startswith(b"\\*File list"):
        return "nanoscope"
    if head.startswith(b"fileType"):
        return "picoview"
    if head.startswith(b"\x93NUMPY"):
        return "npy"
    if head.startswith(b"\x01\x00Directory"):
        return "opd"
    if head.startswith(b"PK\x03\x04"):
        try:
            with zipfile.ZipFile(path) as archive:
                names = archive.namelist()
        except (*DECODER_FAILURES, ValueError, NotImplementedError):
            return "zip"
        if "main.xml" in names:
            return "x3p"
        if names and all(name.endswith(".npy") for name in names):
            return "npz"
        return "zip"
    if head and _looks_like_text(head):
        return "text"
    return None


def _read_hdf5(path: Path) -> HeightMap:
    try:
        handle = h5py.File(path, "r")
    except H5PY_ERRORS as exc:
        raise CorruptFileError(
            path, "HDF5 container", f"cannot be opened ({exc}); truncated?"
        ) from None
    with handle:
        if is_project_hdf5(handle):
            return read_project_hdf5(path, handle)
        if is_datx(handle):
            return read_datx(path, handle)
    raise UnsupportedContentError(
        path, "HDF5 layout", "is neither an asperity height map nor a Zygo DATX file"
    )


def read_surface(
    path: str | Path,
    *,
    channel: str | int | None = None,
    pixel_size: float | tuple[float, float] | None = None,
) -> HeightMap | LineProfile:
    """Read a measured surface; heights and pixel sizes in metres, missing pixels NaN.

    The format comes from the file's magic bytes; the extension must agree with it (a
    ``.sur`` that holds X3P data is refused as mislabelled). Formats without magic (Sensofar
    ``.plu``) go by extension and are validated field by field.

    Parameters
    ----------
    path : str or Path
        The file: .x3p, .sur, .dat (MetroPro), .datx, .plu, .opd, .di/.spm, .mi, .gwy,
        .csv (Dektak profile), .txt/.asc/.xyz (matrix or x y z), .npy, .npz, .h5 (project).
    channel : str or int, optional
        Channel of a multi-channel file (Nanoscope, PicoView, Gwyddion): index or name.
        Default: the height channel.
    pixel_size : float or (float, float), optional
        Pixel size ``dx`` or ``(dx, dy)`` in m (finite, > 0) for formats that do not carry
        one (.npy, .npz, text matrix); refused for files with their own calibration.

    Returns
    -------
    HeightMap or LineProfile

    Raises
    ------
    TopographyFileError (an InputError)
        Unknown, truncated, corrupt, over-budget, out-of-bounds or mislabelled files, a
        ``channel`` that does not exist (the message names the file, the field and what
        was expected; subclasses in :mod:`asperity.topo.errors`).
    InputError
        A missing, invalid or superfluous ``pixel_size``; a ``channel`` given for a
        single-channel format.
    FileNotFoundError
        If ``path`` does not exist.
    """
    path = Path(path)
    require_topography_file(path)
    if path.stat().st_size == 0:
        raise TopographyFileError(path, "file", "is empty (0 bytes)")
    with np.errstate(all="ignore"):
        try:
            return _read_checked(path, channel, pixel_size)
        except InputError:
            raise
        except MemoryError:
            raise OverBudgetError(
                path, "file", "needs more memory than is available; refused"
            ) from None
        except DECODER_FAILURES as exc:
            raise CorruptFileError(
                path,
                f"{path.suffix.lower() or 'file'} content",
                f"cannot be decoded ({type(exc).__name__}: {exc}); corrupt or truncated file",
            ) from None


#: Readers of the single-channel formats that carry their own pixel size.
_READERS = {
    "x3p": read_x3p,
    "sur": read_sur,
    "metropro": read_metropro,
    "hdf5": _read_hdf5,
    "plu": read_plu,
    "opd": read_opd,
}
#: Readers of the multi-channel formats (``channel=`` argument).
_CHANNEL_READERS = {"nanoscope": read_nanoscope, "picoview": read_picoview, "gwy": read_gwy}


def _read_checked(
    path: Path, channel: str | int | None, pixel_size: float | tuple[float, float] | None
) -> HeightMap | LineProfile:
    """Detect the format, check the arguments against it, and run its reader.

    A file asperity does not read natively (content it does not recognise, or text with a
    header it does not know, under an extension that announces no native format: .vk4,
    .ibw, .nid, .al3d, .sdf, ...) goes to
    SurfaceTopography's readers (the ``formats`` extra), or is refused with one line naming
    the extra when it is not installed. A file under a native extension (.txt, .csv, .dat,
    .h5, ...) stays with the native reader, which refuses what it cannot read (a damaged
    file is never handed to readers that are not hardened against hostile input); read
    such a file with :func:`asperity.topo.io.surfacetopography.read_with_extra` directly.
    """
    detected = _checked_format(path)
    if detected is None:
        return read_with_extra(path, channel=channel, pixel_size=pixel_size)
    if detected == "text" and path.suffix.lower() not in FORMATS_BY_EXTENSION:
        try:  # text under a foreign extension (.sdf, .nid, .asc exports, ...)
            return _read_text_table(path, pixel_size)
        except UnsupportedContentError as exc:
            if "unsupported format" not in exc.problem:
                raise
            return read_with_extra(path, channel=channel, pixel_size=pixel_size)
    _check_arguments(path, detected, channel, pixel_size)
    return _read_native(path, detected, channel, pixel_size)


def _read_native(
    path: Path,
    detected: str,
    channel: str | int | None,
    pixel_size: float | tuple[float, float] | None,
) -> HeightMap | LineProfile:
    if detected in _READERS:
        return _READERS[detected](path)
    if detected in _CHANNEL_READERS:
        return _CHANNEL_READERS[detected](path, channel=channel)
    if detected in ("npy", "npz"):
        return read_numpy(path, pixel_size=pixel_size)
    return _read_text_table(path, pixel_size)


def _checked_format(path: Path) -> str | None:
    """The format of the file's content, which its extension (if known) must announce.

    None: content asperity does not recognise under an extension that announces no native
    format (a file for the ``formats`` extra).
    """
    extension = path.suffix.lower()
    announced = FORMATS_BY_EXTENSION.get(extension)
    detected = detect_format(path)
    if announced == "plu" and detected in (None, "text"):
        detected = "plu"
    if extension == ".dat" and detected == "text":
        announced = "text"  # '.dat' is also a common name for plain text tables
    if (detected is None or detected == "zip") and announced is None:
        return None  # for the formats extra
    if detected is None or detected == "zip":
        raise TopographyFileError(
            path,
            "magic bytes",
            "match no supported format (x3p, sur, dat, datx, plu, opd, di, "
            "mi, gwy, csv/txt, npy/npz, h5)",
        )
    if announced is not None and announced != detected:
        raise TopographyFileError(
            path,
            "extension",
            f"{extension!r} announces {announced} but the content is {detected} (mislabelled file)",
        )
    return detected


def _check_arguments(
    path: Path,
    detected: str,
    channel: str | int | None,
    pixel_size: float | tuple[float, float] | None,
) -> None:
    """Refuse a ``channel`` for a single-channel format, a ``pixel_size`` for a calibrated one."""
    if channel is not None and detected not in _CHANNEL_READERS:
        raise InputError(
            f"{path}: channel {channel!r} given, but a {detected} file has a single channel"
        )
    if pixel_size is not None and detected not in ("text", "npy", "npz"):
        raise InputError(
            f"{path}: pixel_size {pixel_size!r} given, but the {detected} format carries its "
            "own calibrated pixel size; leave pixel_size (--pixel-size) out"
        )


def _read_text_table(
    path: Path, pixel_size: float | tuple[float, float] | None
) -> HeightMap | LineProfile:
    """A text file: a Dektak CSV profile (own lateral positions) or a matrix / x y z table."""
    with open(path, "rb") as handle:
        head = handle.read(8192)
    if looks_like_dektak(head):
        if pixel_size is not None:
            raise InputError(
                f"{path}: pixel_size {pixel_size!r} given, but a Dektak CSV file carries its "
                "own lateral positions; leave pixel_size (--pixel-size) out"
            )
        return read_dektak(path)
    return read_text(path, pixel_size=pixel_size)
