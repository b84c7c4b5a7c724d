"""Agilent / Molecular Imaging PicoView ``.mi`` reader (image files).

Facts (public notes on the MI format): a text header of lines with a 14-character key
column, starting with ``fileType Image``; ``xPixels``/``yPixels``, ``xLength``/``yLength``
(m). Each channel ("buffer") is a block starting with ``bufferLabel`` and giving
``bufferRange`` and ``bufferUnit``. The header ends with the line ``data BINARY`` (int16)
or ``data BINARY_32`` (int32); the buffers follow back to back, line by line (x fastest),
and a value is ``raw / 2**15`` (or ``/ 2**31``) times ``bufferRange`` in ``bufferUnit``.
``bufferRange`` must be > 0 (a zero range would flatten the map) and the pixel sizes
``xLength/xPixels``, ``yLength/yPixels`` 1 pm .. 1 m. The bytes after the header must be
exactly the declared buffers (a type or grid that does not match the data is refused).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.topo.errors import ChannelNotFoundError, TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, make_surface, parse_number, read_all_bytes
from asperity.topo.io.limits import check_height_step
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
        provenance lists the channels. ``heights[ix, iy]``: ``iy`` from the top line of the
        image as PicoView and Gwyddion display it (the file stores the bottom line first).

    Raises
    ------
    TopographyFileError
        Not an image file, text data, missing sizes, or data shorter than
        ``buffers * xPixels * yPixels * itemsize``.
    ChannelNotFoundError
        A ``channel`` that is not in the file (the message lists the channels).
    """
    path = Path(path)
    data = read_all_bytes(path)
    header, buffers, start, itemsize = _image_header(path, data)
    nx, ny, lx, ly = _grid(path, header)
    if not buffers:
        raise TopographyFileError(path, "bufferLabel", "no buffer (channel) declared")
    block = nx * ny * itemsize
    check_size(
        path,
        f"data ({len(buffers)} buffers of {nx} x {ny} x {itemsize} bytes)",
        start + len(buffers) * block,
        len(data),
    )
    _check_data_length(path, header, len(data) - start, len(buffers) * block)
    labels = [b.get("bufferLabel", "") for b in buffers]
    index = _choose_buffer(path, buffers, labels, channel)
    unit, step = _height_step(path, buffers[index], labels[index], itemsize)
    dtype = np.dtype("<i4") if itemsize == 4 else np.dtype("<i2")
    raw = np.frombuffer(data, dtype=dtype, count=nx * ny, offset=start + index * block)
    # the buffers store the lines from the bottom of the image up: flip to iy 0 = top line
    heights = np.ascontiguousarray(raw.astype(np.float64).reshape(ny, nx).T[:, ::-1]) * step
    provenance = make_provenance(
        path,
        "picoview",
        instrument=header.get("version", "PicoView"),
        channel=labels[index],
        channels=labels,
        units={"height": unit, "lateral": "m"},
    )
    sizes = (("xLength / xPixels", lx / nx), ("yLength / yPixels", ly / ny))
    return make_surface(path, heights, sizes, provenance)


def _image_header(path: Path, data: bytes) -> tuple[dict[str, str], list[dict[str, str]], int, int]:
    """(header, buffers, first data byte, bytes per value) of an image file, binary data only."""
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
    itemsize = 4 if encoding == "BINARY_32" else 2
    return header, buffers, start, itemsize


def _check_data_length(path: Path, header: dict[str, str], found: int, declared: int) -> None:
    """The data after the header must be exactly the declared buffers (type x grid)."""
    if found == declared:
        return
    hint = ""
    if found == 2 * declared and header.get("data") != "BINARY_32":
        hint = " (exactly twice: the values look like int32, 'BINARY_32', not int16)"
    raise TopographyFileError(
        path,
        "data",
        f"is {header.get('data')!r} and the header declares {declared} bytes of data "
        f"(buffers x xPixels x yPixels x bytes per value) but {found} bytes follow the "
        f"header{hint}; the type or the grid is wrong",
        expected=declared,
        found=found,
    )


def _grid(path: Path, header: dict[str, str]) -> tuple[int, int, float, float]:
    """(xPixels, yPixels, xLength m, yLength m), all > 0."""
    for key in ("xPixels", "yPixels"):
        if not re.fullmatch(r"[+-]?\d+", header.get(key, "")):
            raise TopographyFileError(
                path, key, f"is {header.get(key)!r}; expected a number of pixels"
            )
    nx, ny = int(header["xPixels"]), int(header["yPixels"])
    lx = parse_number(path, "xLength", header.get("xLength", ""))
    ly = parse_number(path, "yLength", header.get("yLength", ""))
    if nx < 1 or ny < 1 or not (lx > 0 and ly > 0):
        raise TopographyFileError(
            path, "xPixels/xLength", f"are {nx}, {ny}, {lx}, {ly}; expected > 0"
        )
    return nx, ny, lx, ly


def _choose_buffer(
    path: Path, buffers: list[dict[str, str]], labels: list[str], channel: str | int | None
) -> int:
    """Index of the buffer named by ``channel`` (see :func:`read_picoview`)."""
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
        return index
    if isinstance(channel, int) or str(channel).isdigit():
        index = int(channel)
        if not 0 <= index < len(buffers):
            raise ChannelNotFoundError(path, "channel", f"{channel} not found; available: {labels}")
        return index
    matches = [i for i, label in enumerate(labels) if label.lower() == str(channel).lower()]
    if not matches:
        raise ChannelNotFoundError(path, "channel", f"{channel!r} not found; available: {labels}")
    return matches[0]


def _height_step(
    path: Path, buffer: dict[str, str], label: str, itemsize: int
) -> tuple[str, float]:
    """(bufferUnit, m per raw count): ``bufferRange / 2**15`` (``2**31`` for int32) in m."""
    unit = buffer.get("bufferUnit", "")
    factor = length_unit_in_metres(unit)
    if factor is None:
        raise TopographyFileError(
            path,
            f"buffer {label!r} bufferUnit",
            f"is {unit!r}, not a length; not a height map",
        )
    full_scale = 2.0**31 if itemsize == 4 else 2.0**15
    range_field = f"buffer {label!r} bufferRange"
    value_range = parse_number(path, range_field, buffer.get("bufferRange", ""))
    return unit, check_height_step(path, range_field, value_range / full_scale * factor)
