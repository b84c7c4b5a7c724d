"""Bruker / Veeco / Digital Instruments Nanoscope (``.di``, ``.spm``, ``.001``) reader.

Facts (public Nanoscope file notes): a text header of ``\\key: value`` lines grouped in
``\\*Section`` blocks, ending with ``\\*File list end``; one ``\\*Ciao image list`` section
per channel with ``Data offset``, ``Data length``, ``Bytes/pixel`` (2 or 4), ``Samps/line``
(nx), ``Number of lines`` (ny), ``Scan Size: sx sy unit`` and
``@2:Image Data: S [key] "label"``. Heights: raw integer * hard scale * soft scale, where
the hard scale is the last value of ``@2:Z scale: V [Sens. key] (v V/LSB) value V`` divided
by 65536 (and by another 65536 for 4-byte data), and the soft scale is the value of
``@Sens. key: V s nm/V`` found in the scanner sections. Data is little-endian, line by line.

Checks: every image's ``Data offset`` must lie past the header (the ``Data length`` of the
``\\*File list`` section, and the ``\\*File list end`` line), so the header is never read as
heights; the height factor (Z scale times sensitivity) must be > 0 and finite (1e-24 .. 1 m
per count) and the pixel size ``Scan Size / Samps/line`` 1 pm .. 1 m; ``Data length`` must be
exactly ``Samps/line * Number of lines * Bytes/pixel`` and ``Valid data len X/Y`` (when
present) the grid, and no two images' data blocks may overlap (an offset pointing into
another image is refused). The default channel is the calibrated ``Height Sensor``
(``ZSensor``), else the one named ``Height`` (label or key); a file without either (unless
it has a single channel) is refused with the list of channels, never read from another
channel silently. Orientation: the file stores the lines from the bottom of the image up;
see :func:`read_nanoscope`.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.topo.errors import (
    ChannelNotFoundError,
    CorruptFileError,
    TopographyFileError,
    check_size,
)
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, make_surface, parse_number, read_all_bytes
from asperity.topo.io.limits import check_height_step, check_map_points
from asperity.topo.io.units import length_unit_in_metres

MAGIC = b"\\*File list"
_Z_SCALE = re.compile(
    r"^V\s*(?:\[(?P<key>[^\]]*)\])?\s*\((?P<lsb>[-+0-9.eE]+) (?P<lsbunit>\S+)/LSB\)"
    r"\s*(?P<value>[-+0-9.eE]+)\s*(?P<unit>\S*)"
)
_IMAGE_DATA = re.compile(r'^S\s*\[(?P<key>[^\]]*)\]\s*"(?P<label>[^"]*)"')
_INTEGER = re.compile(r"[+-]?\d+")
_END = b"\\*File list end"
#: The default channel, in order of preference (label or key, case-insensitive): the
#: calibrated Z sensor ("Height Sensor", key ZSensor) measures the height with the
#: closed-loop sensor, free of piezo creep and hysteresis; the "Height" channel (the piezo
#: drive signal) only when the file has no sensor channel.
DEFAULT_CHANNELS = ("zsensor", "height sensor", "height")


def _parse_header(path: Path, data: bytes) -> list[tuple[str, dict[str, str]]]:
    end = data.find(_END)
    if end < 0:
        raise TopographyFileError(path, "header", "has no '\\*File list end' line (truncated?)")
    sections: list[tuple[str, dict[str, str]]] = []
    for line in data[:end].decode("latin-1").splitlines():
        line = line.strip()
        if not line:
            continue
        if line.startswith("\\*"):
            sections.append((line[2:].strip().lower(), {}))
        elif line.startswith("\\") and sections:
            key, _, value = line[1:].partition(": ")
            sections[-1][1][key.strip().lower()] = value.strip()
        else:
            raise TopographyFileError(
                path, "header", f"line {line[:40]!r} does not start with '\\'"
            )
    if not sections or sections[0][0] != "file list":
        raise TopographyFileError(path, "header", "does not start with the '\\*File list' section")
    return sections


def _int_field(path: Path, section: dict[str, str], key: str, channel: int | str) -> int:
    text = section.get(key, "").strip()
    if not _INTEGER.fullmatch(text):
        raise TopographyFileError(
            path, f"image {channel} '{key}'", f"is {section.get(key)!r}; expected an integer"
        )
    return int(text)


def _header_end(path: Path, data: bytes, sections: list[tuple[str, dict[str, str]]]) -> int:
    """First byte after the header: past the end line and the declared header length."""
    end_line = data.find(_END)
    declared = sections[0][1].get("data length")
    length = _int_field(path, sections[0][1], "data length", "file list") if declared else 0
    return max(end_line + len(_END), length)


def _channels(path: Path, data: bytes) -> list[dict]:
    """Every ``\\*Ciao image list`` section of the header, checked, as a channel dict."""
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:11]!r}; expected '\\*File list'")
    sections = _parse_header(path, data)
    header_end = _header_end(path, data, sections)
    scanner = _scanner_values(sections)
    images = [section for name, section in sections if name == "ciao image list"]
    channels = [
        _channel(path, section, index, header_end, len(data), scanner)
        for index, section in enumerate(images)
    ]
    if not channels:
        raise TopographyFileError(path, "'\\*Ciao image list'", "no image section found")
    _check_blocks_apart(path, channels)
    return channels


def _scanner_values(sections: list[tuple[str, dict[str, str]]]) -> dict[str, str]:
    """The keys of every section but the image sections (the ``@Sens.`` values live there)."""
    scanner: dict[str, str] = {}
    for name, values in sections:
        if name != "ciao image list":
            scanner.update(values)
    return scanner


def _channel(
    path: Path,
    section: dict[str, str],
    index: int,
    header_end: int,
    file_size: int,
    scanner: dict[str, str],
) -> dict:
    """One image section as a channel dict (see :func:`_channels`); sizes in m."""
    nx, ny, offset, itemsize = _image_layout(path, section, index, header_end, file_size)
    sx, sy = _scan_size(path, section, index)
    image = _IMAGE_DATA.match(section.get("@2:image data", ""))
    key = image.group("key") if image else f"channel {index}"
    label = image.group("label") if image else key
    height_unit, height_factor, sens_key = _height_scale(path, section, index, itemsize, scanner)
    return {
        "index": index,
        "key": key,
        "label": label,
        "nx": nx,
        "ny": ny,
        "itemsize": itemsize,
        "offset": offset,
        "dx": sx / nx,
        "dy": sy / ny,
        "height_unit": height_unit,
        "height_factor": height_factor,
        "height_factor_field": f"image {index} '@2:Z scale' x '@{sens_key}'",
        "line_direction": section.get("line direction", ""),
    }


def _image_layout(
    path: Path, section: dict[str, str], index: int, header_end: int, file_size: int
) -> tuple[int, int, int, int]:
    """(nx, ny, data offset, bytes per pixel) of one image, its data block checked.

    The block must hold ``nx*ny`` items of 2 or 4 bytes, start past the header (never read
    the header as heights) and end within the file of ``file_size`` bytes.
    """
    nx = _int_field(path, section, "samps/line", index)
    ny = _int_field(path, section, "number of lines", index)
    offset = _int_field(path, section, "data offset", index)
    length = _int_field(path, section, "data length", index)
    itemsize = _int_field(path, section, "bytes/pixel", index)
    if itemsize not in (2, 4):
        raise TopographyFileError(
            path, f"image {index} 'Bytes/pixel'", f"is {itemsize}; expected 2 or 4"
        )
    if nx < 1 or ny < 1 or length != nx * ny * itemsize:
        raise TopographyFileError(
            path,
            f"image {index} 'Data length'",
            f"is {length}; expected 'Samps/line' * 'Number of lines' * 'Bytes/pixel' = "
            f"{nx}*{ny}*{itemsize} = {nx * ny * itemsize} (a grid or length field is wrong)",
        )
    _check_valid_lengths(path, section, index, nx, ny)
    check_map_points(path, f"image {index} 'Samps/line' x 'Number of lines'", nx, ny)
    if offset < header_end:
        raise CorruptFileError(
            path,
            f"image {index} 'Data offset'",
            f"is {offset}, inside the header (which ends at byte {header_end}); "
            "expected an offset past the header",
            expected=f">= {header_end}",
            found=offset,
        )
    check_size(path, f"image {index} 'Data offset' + data", offset + nx * ny * itemsize, file_size)
    return nx, ny, offset, itemsize


def _check_valid_lengths(path: Path, section: dict[str, str], index: int, nx: int, ny: int) -> None:
    """``Valid data len X/Y`` (when present) must be the grid (``Samps/line``, lines)."""
    for key, value in (("valid data len x", nx), ("valid data len y", ny)):
        if key in section and _int_field(path, section, key, index) != value:
            raise TopographyFileError(
                path,
                f"image {index} '{key.capitalize()}'",
                f"is {section[key]}; the grid ('Samps/line' x 'Number of lines') is "
                f"{nx} x {ny}: the header contradicts itself",
            )


def _check_blocks_apart(path: Path, channels: list[dict]) -> None:
    """Refuse two images whose data blocks overlap (an offset pointing into another image)."""
    blocks = sorted(
        (c["offset"], c["offset"] + c["nx"] * c["ny"] * c["itemsize"], c["index"]) for c in channels
    )
    for (_, end, first), (start, _, second) in zip(blocks, blocks[1:], strict=False):
        if start < end:
            raise CorruptFileError(
                path,
                f"image {second} 'Data offset'",
                f"is {start}, inside the data of image {first} (bytes up to {end}); "
                "expected each image's data in its own block",
                found=start,
            )


def _scan_size(path: Path, section: dict[str, str], index: int) -> tuple[float, float]:
    """(sx, sy) in m from ``Scan Size: sx sy unit`` (unit nm when absent), both > 0."""
    size = section.get("scan size", "").split()
    if len(size) < 2:
        raise TopographyFileError(
            path,
            f"image {index} 'Scan Size'",
            f"is {section.get('scan size')!r}; expected 'sx sy unit'",
        )
    sx = parse_number(path, f"image {index} 'Scan Size' x", size[0])
    sy = parse_number(path, f"image {index} 'Scan Size' y", size[1])
    lateral_unit = size[2] if len(size) > 2 else "nm"
    lateral_factor = length_unit_in_metres(lateral_unit)
    if lateral_factor is None or sx <= 0 or sy <= 0:
        raise TopographyFileError(
            path,
            f"image {index} 'Scan Size'",
            f"is {' '.join(size)!r}; expected positive lengths",
        )
    return sx * lateral_factor, sy * lateral_factor


def _height_scale(
    path: Path, section: dict[str, str], index: int, itemsize: int, scanner: dict[str, str]
) -> tuple[str, float | None, str | None]:
    """(height unit, m per raw count or None, sensitivity key) of one image.

    Hard scale: the ``@2:Z scale`` value / 65536 (/ 65536 again for 4-byte data); soft scale:
    the ``@Sens. key: V s unit/V`` value of the scanner sections. The factor is None when the
    soft scale's unit is not a length (or there is no soft scale).
    """
    scale = _Z_SCALE.match(section.get("@2:z scale", ""))
    if scale is None:
        raise TopographyFileError(path, f"image {index} '@2:Z scale'", "is missing or malformed")
    z_scale = parse_number(path, f"image {index} '@2:Z scale'", scale.group("value"))
    hard = z_scale / 65536.0 / (65536.0 if itemsize == 4 else 1.0)
    height_factor = None
    height_unit = scale.group("unit")
    sens_key = scale.group("key")
    if sens_key:
        sens = scanner.get("@" + sens_key.lower(), "").split()
        if len(sens) >= 3 and sens[0] == "V" and "/" in sens[2]:
            soft_unit = sens[2].split("/")[0]
            factor = length_unit_in_metres(soft_unit)
            height_unit = soft_unit
            if factor is not None:
                sensitivity = parse_number(path, f"'@{sens_key}'", sens[1])
                height_factor = hard * sensitivity * factor
    return height_unit, height_factor, sens_key


def choose_channel(path: Path, channels: list[dict], channel: str | int | None) -> dict:
    """Pick a channel by index or name (label or key, case-insensitive); default: ``Height``.

    Parameters
    ----------
    path : Path
        The file (for messages).
    channels : list of dict
        As returned by :func:`_channels`.
    channel : str or int or None
        Index, label or key; None picks the calibrated ``Height Sensor`` (``ZSensor``)
        channel, else the channel named ``Height`` (label or key), else the only channel of
        a single-channel file (:data:`DEFAULT_CHANNELS`). There is no other fallback.

    Returns
    -------
    dict
        The chosen channel.

    Raises
    ------
    ChannelNotFoundError
        An unknown channel, or no ``Height`` channel in a multi-channel file (the message
        lists the channels).
    """
    names = ", ".join(f"{c['index']}: {c['label']} [{c['key']}]" for c in channels)
    if channel is None:
        for wanted in DEFAULT_CHANNELS:
            for candidate in channels:
                if wanted in (candidate["label"].lower(), candidate["key"].lower()):
                    return candidate
        if len(channels) == 1:
            return channels[0]
        raise ChannelNotFoundError(
            path,
            "channel",
            "no channel is named 'Height Sensor' (ZSensor) or 'Height'; choose one by name "
            "(channel=, --channel); "
            f"available channels: {names}",
        )
    if isinstance(channel, int) or str(channel).isdigit():
        index = int(channel)
        if 0 <= index < len(channels):
            return channels[index]
    else:
        for candidate in channels:
            if str(channel).lower() in (candidate["label"].lower(), candidate["key"].lower()):
                return candidate
    raise ChannelNotFoundError(
        path, "channel", f"{channel!r} not found; available channels: {names}"
    )


def read_nanoscope(path: str | Path, *, channel: str | int | None = None) -> HeightMap:
    """Read one channel of a Nanoscope file (default: the height channel) in m.

    Parameters
    ----------
    path : str or Path
        The file.
    channel : str or int, optional
        Index, label (e.g. ``"Height Sensor"``) or key (e.g. ``"ZSensor"``). Default: the
        calibrated ``Height Sensor`` (``ZSensor``) channel, else ``Height``, else the only
        channel of a single-channel file.

    Returns
    -------
    HeightMap
        Heights in m, pixel sizes from ``Scan Size`` in m; provenance lists the channels.
        ``heights[ix, iy]``: ``ix`` along the scan lines, ``iy`` from the top line of the
        image as Nanoscope and Gwyddion display it (the file stores the bottom line first).

    Raises
    ------
    TopographyFileError
        Header problems, data blocks beyond the end of the file, non-length channels.
    ChannelNotFoundError
        A ``channel`` that is not in the file, or no ``Height`` channel (the message lists
        the channels).
    """
    path = Path(path)
    data = read_all_bytes(path)
    channels = _channels(path, data)
    chosen = choose_channel(path, channels, channel)
    if chosen["height_factor"] is None:
        raise TopographyFileError(
            path,
            f"channel {chosen['label']!r}",
            f"has unit {chosen['height_unit']!r}, not a length; choose a height channel",
        )
    factor = check_height_step(path, chosen["height_factor_field"], chosen["height_factor"])
    dtype = np.dtype("<i2") if chosen["itemsize"] == 2 else np.dtype("<i4")
    nx, ny = chosen["nx"], chosen["ny"]
    raw = np.frombuffer(data, dtype=dtype, count=nx * ny, offset=chosen["offset"])
    # the file stores the lines from the bottom of the image up: flip to iy 0 = top line
    heights = np.ascontiguousarray(raw.astype(np.float64).reshape(ny, nx).T[:, ::-1]) * factor
    provenance = make_provenance(
        path,
        "nanoscope",
        instrument="Bruker/Veeco Nanoscope",
        channel=chosen["label"],
        channel_key=chosen["key"],
        channels=[c["label"] for c in channels],
        units={"height": chosen["height_unit"], "lateral": "m"},
    )
    field = f"image {chosen['index']} 'Scan Size' / "
    sizes = ((field + "'Samps/line'", chosen["dx"]), (field + "'Number of lines'", chosen["dy"]))
    return make_surface(path, heights, sizes, provenance)
