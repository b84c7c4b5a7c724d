"""Bruker / Veeco / Digital Instruments Nanoscope (``.di``, ``.spm``, ``.001``) reader.

Facts (public Nanoscope file notes): a text header of ``\\key: value`` lines grouped in
``\\*Section`` blocks, ending with ``\\*File list end``; one ``\\*Ciao image list`` section
per channel with ``Data offset``, ``Data length``, ``Bytes/pixel`` (2 or 4), ``Samps/line``
(nx), ``Number of lines`` (ny), ``Scan Size: sx sy unit`` and
``@2:Image Data: S [key] "label"``. Heights: raw integer * hard scale * soft scale, where
the hard scale is the last value of ``@2:Z scale: V [Sens. key] (v V/LSB) value V`` divided
by 65536 (and by another 65536 for 4-byte data), and the soft scale is the value of
``@Sens. key: V s nm/V`` found in the scanner sections. Data is little-endian, line by line.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from asperity.errors import InputError
from asperity.topo.errors import TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import make_provenance, read_all_bytes
from asperity.topo.io.units import length_unit_in_metres

MAGIC = b"\\*File list"
_Z_SCALE = re.compile(
    r"^V\s*(?:\[(?P<key>[^\]]*)\])?\s*\((?P<lsb>[-+0-9.eE]+) (?P<lsbunit>\S+)/LSB\)"
    r"\s*(?P<value>[-+0-9.eE]+)\s*(?P<unit>\S*)"
)
_IMAGE_DATA = re.compile(r'^S\s*\[(?P<key>[^\]]*)\]\s*"(?P<label>[^"]*)"')


def _parse_header(path: Path, data: bytes) -> list[tuple[str, dict[str, str]]]:
    end = data.find(b"\\*File list end")
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


def _int_field(path: Path, section: dict[str, str], key: str, channel: int) -> int:
    try:
        return int(section[key])
    except (KeyError, ValueError):
        raise TopographyFileError(
            path, f"image {channel} '{key}'", f"is {section.get(key)!r}; expected an integer"
        ) from None


def list_channels(path: str | Path) -> list[dict]:
    """Describe every image channel of a Nanoscope file.

    Parameters
    ----------
    path : str or Path
        The Nanoscope file.

    Returns
    -------
    list of dict
        Per channel: ``index``, ``key``, ``label``, ``nx``, ``ny``, ``dx``, ``dy`` (m),
        ``height_unit``, ``height_factor`` (m per raw count, None for a non-length channel).
    """
    path = Path(path)
    data = read_all_bytes(path)
    return _channels(path, data)


def _channels(path: Path, data: bytes) -> list[dict]:
    if not data.startswith(MAGIC):
        raise TopographyFileError(path, "magic", f"is {data[:11]!r}; expected '\\*File list'")
    sections = _parse_header(path, data)
    scanner: dict[str, str] = {}
    for name, values in sections:
        if name != "ciao image list":
            scanner.update(values)
    channels = []
    for name, section in sections:
        if name != "ciao image list":
            continue
        index = len(channels)
        nx = _int_field(path, section, "samps/line", index)
        ny = _int_field(path, section, "number of lines", index)
        offset = _int_field(path, section, "data offset", index)
        length = _int_field(path, section, "data length", index)
        itemsize = _int_field(path, section, "bytes/pixel", index)
        if itemsize not in (2, 4):
            raise TopographyFileError(
                path, f"image {index} 'Bytes/pixel'", f"is {itemsize}; expected 2 or 4"
            )
        if nx < 1 or ny < 1 or length < nx * ny * itemsize:
            raise TopographyFileError(
                path,
                f"image {index} 'Data length'",
                f"is {length}; expected at least {nx}*{ny}*{itemsize} = {nx * ny * itemsize}",
            )
        check_size(
            path, f"image {index} 'Data offset' + data", offset + nx * ny * itemsize, len(data)
        )
        size = section.get("scan size", "").split()
        try:
            sx, sy = float(size[0]), float(size[1])
        except (IndexError, ValueError):
            raise TopographyFileError(
                path,
                f"image {index} 'Scan Size'",
                f"is {section.get('scan size')!r}; expected 'sx sy unit'",
            ) from None
        lateral_unit = size[2] if len(size) > 2 else "nm"
        lateral_factor = length_unit_in_metres(lateral_unit)
        if lateral_factor is None or sx <= 0 or sy <= 0:
            raise TopographyFileError(
                path,
                f"image {index} 'Scan Size'",
                f"is {' '.join(size)!r}; expected positive lengths",
            )
        image = _IMAGE_DATA.match(section.get("@2:image data", ""))
        key = image.group("key") if image else f"channel {index}"
        label = image.group("label") if image else key
        scale = _Z_SCALE.match(section.get("@2:z scale", ""))
        if scale is None:
            raise TopographyFileError(
                path, f"image {index} '@2:Z scale'", "is missing or malformed"
            )
        hard = float(scale.group("value")) / 65536.0 / (65536.0 if itemsize == 4 else 1.0)
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
                    height_factor = hard * float(sens[1]) * factor
        channels.append(
            {
                "index": index,
                "key": key,
                "label": label,
                "nx": nx,
                "ny": ny,
                "itemsize": itemsize,
                "offset": offset,
                "dx": sx * lateral_factor / nx,
                "dy": sy * lateral_factor / ny,
                "height_unit": height_unit,
                "height_factor": height_factor,
                "line_direction": section.get("line direction", ""),
            }
        )
    if not channels:
        raise TopographyFileError(path, "'\\*Ciao image list'", "no image section found")
    return channels


def choose_channel(path: Path, channels: list[dict], channel: str | int | None) -> dict:
    """Pick a channel by index or name (label or key, case-insensitive); default: height.

    Parameters
    ----------
    path : Path
        The file (for messages).
    channels : list of dict
        As returned by :func:`list_channels`.
    channel : str or int or None
        Index, label or key; None picks ``Height``, else ``Height Sensor``/``ZSensor``,
        else the first length channel.

    Returns
    -------
    dict
        The chosen channel.

    Raises
    ------
    ValueError
        An unknown channel (the message lists the channels).
    """
    if channel is None:
        heights = [c for c in channels if c["height_factor"] is not None]
        for wanted in ("height", "zsensor", "height sensor"):
            for candidate in heights:
                if wanted in (candidate["label"].lower(), candidate["key"].lower()):
                    return candidate
        if heights:
            return heights[0]
        raise TopographyFileError(path, "channels", "no channel with height (length) units")
    names = [f"{c['index']}: {c['label']} [{c['key']}]" for c in channels]
    if isinstance(channel, int) or str(channel).isdigit():
        index = int(channel)
        if 0 <= index < len(channels):
            return channels[index]
    else:
        for candidate in channels:
            if str(channel).lower() in (candidate["label"].lower(), candidate["key"].lower()):
                return candidate
    raise InputError(
        f"{path}: channel {channel!r} not found; available channels: {', '.join(names)}"
    )


def read_nanoscope(path: str | Path, *, channel: str | int | None = None) -> HeightMap:
    """Read one channel of a Nanoscope file (default: the height channel) in m.

    Parameters
    ----------
    path : str or Path
        The file.
    channel : str or int, optional
        Index, label (e.g. ``"Height Sensor"``) or key (e.g. ``"ZSensor"``). Default: the
        channel labelled ``Height``, else ``Height Sensor``, else the first length channel.

    Returns
    -------
    HeightMap
        Heights in m, pixel sizes from ``Scan Size`` in m; provenance lists the channels.

    Raises
    ------
    TopographyFileError
        Header problems, data blocks beyond the end of the file, non-length channels.
    ValueError
        A ``channel`` that is not in the file (the message lists the channels).
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
    dtype = np.dtype("<i2") if chosen["itemsize"] == 2 else np.dtype("<i4")
    nx, ny = chosen["nx"], chosen["ny"]
    raw = np.frombuffer(data, dtype=dtype, count=nx * ny, offset=chosen["offset"])
    heights = raw.astype(np.float64).reshape(ny, nx).T * chosen["height_factor"]
    provenance = make_provenance(
        path,
        "nanoscope",
        instrument="Bruker/Veeco Nanoscope",
        channel=chosen["label"],
        channels=[c["label"] for c in channels],
        units={"height": chosen["height_unit"], "lateral": "m"},
    )
    return HeightMap(heights, chosen["dx"], chosen["dy"], False, provenance)
