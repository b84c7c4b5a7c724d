"""Agilent / Molecular Imaging PicoView ``.mi`` reader (image files).

Facts (public notes on the MI format): a text header of lines with a 14-character key
column, starting with ``fileType Image``; ``xPixels``/``yPixels``, ``xLength``/``yLength``
(m). Each channel ("buffer") is a block starting with ``bufferLabel`` and giving
``bufferRange`` and ``bufferUnit``. The header ends with the line ``data BINARY`` (int16)
or ``data BINARY_32`` (int32); the buffers follow back to back, line by line (x fastest),
and a value is ``raw / 2**15`` (or ``/ 2**31``) times ``bufferRange`` in ``bufferUnit``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, read_all_bytes
from asperity.topo.io.units import length_unit_in_metres

MAGIC = b"fileType"
_KEY_WIDTH = 14


def _parse(path: Path, data: bytes) -> tuple[dict[str, str], list[dict[str, str]], int]:
    header: dict[str, str] = {}
    buffers: list[dict[str, str]] = []
    position = 0
    while True:
        end = data.find(b"\n", position)
        if end < 0:
            raise TopographyFileError(path, "header", "ends before the 'data' line (truncated?)")
        line = data[position:end].decode("latin-1").rstrip("\r")
        position = end + 1
        if not line or line.startswith(" "):
            continue
        key, value = line[:_KEY_WIDTH].strip(), line[_KEY_WIDTH:].strip()
        if key == "bufferLabel":
            buffers.append({})
        if key == "data":
            header["data"] = value
            return header, buffers, position
        (buffers[-1] if buffers else header)[key] = value
        if key == "bufferLabel":
            buffers[-1]["bufferLabel"] = value


def read_picoview(path: str | Path, *, channel: str | int | None = None) -> HeightMap:
    """Read one channel of a PicoView ``.mi`` image (default: the first length channel), in m.

    Parameters
    ----------
    channel : str or int, optional
        Buffer index or label (e.g. ``"Topography"``, ``"Friction"``), case-insensitive;
        a label shared by several buffers picks the first. Default: first buffer whose unit
        is a length.

    Returns
    -------
    HeightMap
        Heights in m, pixel sizes ``xLength/xPixels``, ``yLength/yPixels`` in m;
        provenance lists the channels.

    Raises
    ------
    TopographyFileError
        Not an image file, text data, missing sizes, or data shorter than
        ``buffers * xPixels * yPixels * itemsize``.
    ValueError
        A ``channel`` that is not in the file (the message lists the channels).
    """
    path = Path(path)
    data = read_all_bytes(path)
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:8]!r}; expected 'fileType'")
    header, buffers, start = _parse(path, data)
    if header.get("fileType") != "Image":
        raise TopographyFileError(
            path, "fileType", f"is {header.get('fileType')!r}; expected 'Image'"
        )
    encoding = header.get("data", "")
    if encoding not in ("BINARY", "BINARY_32", ""):
        raise TopographyFileError(path, "data", f"is {encoding!r}; expected BINARY or BINARY_32")
    itemsize, full_scale = (4, 2.0**31) if encoding == "BINARY_32" else (2, 2.0**15)
    try:
        nx, ny = int(header["xPixels"]), int(header["yPixels"])
        lx, ly = float(header["xLength"]), float(header["yLength"])
    except (KeyError, ValueError):
        raise TopographyFileError(
            path, "xPixels/yPixels/xLength/yLength", "missing or not numbers"
        ) from None
    if nx < 1 or ny < 1 or not (lx > 0 and ly > 0):
        raise TopographyFileError(
            path, "xPixels/xLength", f"are {nx}, {ny}, {lx}, {ly}; expected > 0"
        )
    if not buffers:
        raise TopographyFileError(path, "bufferLabel", "no buffer (channel) declared")
    block = nx * ny * itemsize
    check_size(
        path,
        f"data ({len(buffers)} buffers of {nx} x {ny} x {itemsize} bytes)",
        start + len(buffers) * block,
        len(data),
    )
    labels = [b.get("bufferLabel", "") for b in buffers]
    if channel is None:
        index = next(
            (
                i
                for i, b in enumerate(buffers)
                if length_unit_in_metres(b.get("bufferUnit", "")) is not None
            ),
            None,
        )
        if index is None:
            raise TopographyFileError(path, "bufferUnit", "no buffer has a length unit")
    elif isinstance(channel, int) or str(channel).isdigit():
        index = int(channel)
        if not 0 <= index < len(buffers):
            raise InputError(f"{path}: channel {channel} not found; available: {labels}")
    else:
        matches = [i for i, label in enumerate(labels) if label.lower() == str(channel).lower()]
        if not matches:
            raise InputError(f"{path}: channel {channel!r} not found; available: {labels}")
        index = matches[0]
    chosen = buffers[index]
    unit = chosen.get("bufferUnit", "")
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise TopographyFileError(
            path,
            f"buffer {labels[index]!r} bufferUnit",
            f"is {unit!r}, not a length; not a height map",
        )
    try:
        value_range = float(chosen["bufferRange"])
    except (KeyError, ValueError):
        raise TopographyFileError(
            path, f"buffer {labels[index]!r} bufferRange", "missing"
        ) from None
    dtype = np.dtype("<i4") if itemsize == 4 else np.dtype("<i2")
    raw = np.frombuffer(data, dtype=dtype, count=nx * ny, offset=start + index * block)
    heights = raw.astype(np.float64).reshape(ny, nx).T * (value_range / full_scale * factor)
    provenance = make_provenance(
        path,
        "picoview",
        instrument=header.get("version", "PicoView"),
        channel=labels[index],
        channels=labels,
        units={"height": unit, "lateral": "m"},
    )
    return HeightMap(heights, lx / nx, ly / ny, False, provenance)
