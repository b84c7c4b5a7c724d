"""Small helpers shared by the native readers."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError, check_size


def read_all_bytes(path: str | Path) -> bytes:
    """Return the whole file; raise ``TopographyFileError`` for an empty file."""
    data = Path(path).read_bytes()
    if not data:
        raise TopographyFileError(path, "file", "is empty (0 bytes); expected a topography file")
    return data


def unpack_checked(path: str | Path, fmt: str, data: bytes, offset: int, field: str) -> tuple:
    """``struct.unpack_from`` that refuses to read past the end of ``data``."""
    check_size(path, field, offset + struct.calcsize(fmt), len(data))
    return struct.unpack_from(fmt, data, offset)


def decode_text(raw: bytes) -> str:
    """Decode a fixed-width text field (NUL padded, latin-1) and strip it."""
    return raw.split(b"\x00", 1)[0].decode("latin-1").strip()


def make_provenance(path: str | Path, fmt: str, **items: object) -> dict:
    """Provenance dict: file, format and whatever else the reader saw (instrument, units)."""
    provenance: dict = {"file": str(path), "format": fmt}
    provenance.update({key: value for key, value in items.items() if value not in (None, "")})
    return provenance


def require_positive(path: str | Path, field: str, value: float, unit: str = "") -> None:
    """Refuse a size or count that is not a finite number > 0."""
    if not (value > 0 and value < float("inf")):
        raise TopographyFileError(path, field, f"is {value!r}{unit}; expected a finite value > 0")


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
    ValueError
        Not one or two finite lengths > 0 m.
    """
    if pixel_size is None:
        return None
    values = (pixel_size, pixel_size) if np.ndim(pixel_size) == 0 else tuple(pixel_size)  # type: ignore[arg-type]
    if len(values) != 2:
        raise InputError(
            f"{path}: pixel_size: is {pixel_size!r}; expected dx or (dx, dy), in metres"
        )
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
        sizes.append(size)
    return sizes[0], sizes[1]
