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

from pathlib import Path

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
from asperity.topo.io.hdf5 import write_hdf5
from asperity.topo.io.registry import (
    DECODER_FAILURES,
    FORMATS_BY_EXTENSION,
    FORMATS_BY_NAME,
    READERS,
    ReaderEntry,
    detect_format,
    native_formats_text,
    read_text_table,
    reader_for,
)
from asperity.topo.io.surfacetopography import read_with_extra

__all__ = [
    "read_surface",
    "write_hdf5",
    "detect_format",
    "FORMATS_BY_EXTENSION",
    "READERS",
    "ReaderEntry",
    "DECODER_FAILURES",
]


def read_surface(
    path: str | Path,
    *,
    channel: str | int | None = None,
    pixel_size: float | tuple[float, float] | None = None,
    unit: str | None = None,
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
    unit : str, optional
        The length unit ("m", "mm", "um", "nm", ...) of a plain-text file's numbers (matrix,
        x y z or x z columns), which state none: such a file is refused without it, never
        read in a guessed unit. Refused for a format that states its own units.

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
        single-channel format; a ``unit`` that is not a length, or given for a format that
        states its own.
    FileNotFoundError
        If ``path`` does not exist.
    """
    path = Path(path)
    require_topography_file(path)
    if path.stat().st_size == 0:
        raise TopographyFileError(path, "file", "is empty (0 bytes)")
    with np.errstate(all="ignore"):
        try:
            return _read_checked(path, channel, pixel_size, unit)
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


def _read_checked(
    path: Path,
    channel: str | int | None,
    pixel_size: float | tuple[float, float] | None,
    unit: str | None = None,
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
    if unit is not None and detected != "text":
        raise InputError(
            f"{path}: unit {unit!r} given, but a {detected or 'non-native'} file states its own "
            "units; leave unit (--unit) out"
        )
    if detected is None:
        return read_with_extra(path, channel=channel, pixel_size=pixel_size)
    if detected == "text" and path.suffix.lower() not in FORMATS_BY_EXTENSION:
        try:  # text under a foreign extension (.sdf, .nid, .asc exports, ...)
            return read_text_table(path, pixel_size=pixel_size, unit=unit)
        except UnsupportedContentError as exc:
            if "unsupported format" not in exc.problem:
                raise
            return read_with_extra(path, channel=channel, pixel_size=pixel_size)
    _check_arguments(path, detected, channel, pixel_size)
    if detected == "text":
        return read_text_table(path, pixel_size=pixel_size, unit=unit)
    return _read_native(path, detected, channel, pixel_size)


def _read_native(
    path: Path,
    detected: str,
    channel: str | int | None,
    pixel_size: float | tuple[float, float] | None,
) -> HeightMap | LineProfile:
    entry = reader_for(detected)
    return entry.read(path, **entry.options(channel, pixel_size))


def _checked_format(path: Path) -> str | None:
    """The format of the file's content, which its extension (if known) must announce.

    None: content asperity does not recognise under an extension that announces no native
    format (a file for the ``formats`` extra).
    """
    extension = path.suffix.lower()
    announced = FORMATS_BY_EXTENSION.get(extension)
    detected = detect_format(path)
    if announced is not None and reader_for(announced).sniff is None and detected in (None, "text"):
        detected = announced  # no magic (Sensofar .plu): the extension decides
    if detected in FORMATS_BY_NAME and extension in reader_for(detected).also_under:
        announced = detected  # '.dat' is also a common name for plain text tables
    if (detected is None or detected == "zip") and announced is None:
        return None  # for the formats extra
    if detected is None or detected == "zip":
        raise TopographyFileError(
            path,
            "magic bytes",
            f"match no supported format ({native_formats_text()})",
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
    entry = reader_for(detected)
    if channel is not None and not entry.channels:
        raise InputError(
            f"{path}: channel {channel!r} given, but a {detected} file has a single channel"
        )
    if pixel_size is not None and entry.calibrated:
        raise InputError(
            f"{path}: pixel_size {pixel_size!r} given, but the {detected} format carries its "
            "own calibrated pixel size; leave pixel_size (--pixel-size) out"
        )
