"""Zygo MetroPro ``.dat`` reader (big-endian binary header, then intensity and phase data).

Header facts (MetroPro Reference Guide, section 12): magic ``0x881B036F`` (header format 1),
``...70`` (2) or ``...71`` (3); header size (uint32 at byte 6; 834 or 4096); intensity
array origin/width/height/buckets and byte count at 48-63; connected-phase array
origin/width/height and byte count at 64-75; ``intf_scale_factor`` (S), ``wavelength_in``
(W, m), ``obliquity_factor`` (O) and ``lateral_res`` (pixel size, m) as float32 at
164/168/176/184; ``phase_res`` at 218 (0: R = 4096, 1: 32768, 2: 131072); ``sign`` at 232.
The phase array is big-endian int32, row by row (x fastest); values >= 2147483640 are
invalid (NaN, counted in ``provenance["missing_pixels"]``). Height (m) = phase * S * O * W / R,
negated when ``sign`` is set (the format's own inversion). S, O and W must be finite and > 0,
and the resulting height step 1e-24 .. 1 m per count; ``lateral_res`` 1 pm .. 1 m.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from asperity.topo.errors import TopographyFileError, check_size
from asperity.topo.heightmap import HeightMap
from asperity.topo.io._common import (
    make_provenance,
    make_surface,
    read_all_bytes,
    require_positive,
)
from asperity.topo.io.limits import check_height_step

MAGICS = (b"\x88\x1b\x03\x6f", b"\x88\x1b\x03\x70", b"\x88\x1b\x03\x71")
_PHASE_RESOLUTION = {0: 4096, 1: 32768, 2: 131072}
_INVALID_PHASE = 2147483640


def read_metropro(path: str | Path) -> HeightMap:
    """Read a Zygo MetroPro ``.dat`` file: the connected phase map as heights (m).

    Parameters
    ----------
    path : str or Path
        The MetroPro .dat file.

    Returns
    -------
    HeightMap
        Heights in m (NaN = invalid phase), pixel sizes in m,
        provenance (instrument, units seen).

    Raises
    ------
    TopographyFileError
        Wrong magic, inconsistent header size or array byte counts, unknown phase
        resolution, non-positive lateral resolution, or a file shorter than its arrays.
    """
    path = Path(path)
    data = read_all_bytes(path)
    header_format, header_size = _header_size(path, data)
    ac_bytes, cn_w, cn_h, cn_bytes = _array_sizes(path, data)
    lateral, step, resolution, sign = _calibration(path, data)
    start = header_size + ac_bytes
    check_size(path, "cn_n_bytes (phase data)", start + cn_bytes, len(data))
    raw = np.frombuffer(data, dtype=">i4", count=cn_w * cn_h, offset=start)
    factor = check_height_step(
        path,
        "intf_scale_factor * obliquity_factor * wavelength_in / phase resolution",
        step,
    )
    heights = _phase_heights(raw, -factor if sign else factor)
    provenance = make_provenance(
        path,
        "metropro",
        instrument="Zygo MetroPro",
        header_format=int(header_format),
        channel="connected phase",
        invalid_marker=f"phase >= {_INVALID_PHASE}",
        inverted=bool(sign),
        units={"lateral": "m", "wavelength": "m", "phase_resolution": resolution},
    )
    sizes = (("lateral_res", lateral), ("lateral_res", lateral))
    return make_surface(path, heights.reshape(cn_h, cn_w).T, sizes, provenance)


def _header_size(path: Path, data: bytes) -> tuple[int, int]:
    """(header format, header size in bytes): the magic and the size it implies, checked."""
    if data[:4] not in MAGICS:
        raise TopographyFileError(
            path, "magic", f"is {data[:4].hex()}; expected 881b036f, 881b0370 or 881b0371"
        )
    check_size(path, "header", 834, len(data))
    header_format, header_size = struct.unpack_from(">HI", data, 4)
    expected_header = 4096 if data[:4] == MAGICS[2] else 834
    if header_size != expected_header:
        raise TopographyFileError(
            path, "header_size", f"is {header_size}; expected {expected_header} for this magic"
        )
    check_size(path, "header_size", header_size, len(data))
    return header_format, header_size


def _array_sizes(path: Path, data: bytes) -> tuple[int, int, int, int]:
    """(intensity bytes, phase width, phase height, phase bytes), consistent with each other."""
    ac_w, ac_h, ac_buckets, _ac_range, ac_bytes = struct.unpack_from(">HHHhI", data, 52)
    cn_w, cn_h, cn_bytes = struct.unpack_from(">HHI", data, 68)
    if ac_bytes != 2 * ac_w * ac_h * ac_buckets:
        raise TopographyFileError(
            path,
            "ac_n_bytes",
            f"is {ac_bytes}; expected 2*width*height*buckets = {2 * ac_w * ac_h * ac_buckets}",
        )
    if cn_w < 1 or cn_h < 1:
        raise TopographyFileError(path, "cn_org_width/height", f"are {cn_w} x {cn_h}; no phase map")
    if cn_bytes != 4 * cn_w * cn_h:
        raise TopographyFileError(
            path, "cn_n_bytes", f"is {cn_bytes}; expected 4*width*height = {4 * cn_w * cn_h}"
        )
    return ac_bytes, cn_w, cn_h, cn_bytes


def _calibration(path: Path, data: bytes) -> tuple[float, float, int, int]:
    """(pixel size m, height per phase count m, phase resolution R, sign flag).

    The height per count is S * O * W / R (unchecked here: the caller bounds it); S, O, W and
    the pixel size must be finite and > 0.
    """
    scale, wavelength, obliquity = (
        struct.unpack_from(">f", data, 164)[0],
        struct.unpack_from(">f", data, 168)[0],
        struct.unpack_from(">f", data, 176)[0],
    )
    lateral = struct.unpack_from(">f", data, 184)[0]
    (phase_res,) = struct.unpack_from(">h", data, 218)
    (sign,) = struct.unpack_from(">h", data, 232)
    if phase_res not in _PHASE_RESOLUTION:
        raise TopographyFileError(path, "phase_res", f"is {phase_res}; expected 0, 1 or 2")
    require_positive(path, "lateral_res", lateral, " m")
    require_positive(path, "wavelength_in", wavelength, " m")
    require_positive(path, "intf_scale_factor", scale)
    require_positive(path, "obliquity_factor", obliquity)
    resolution = _PHASE_RESOLUTION[phase_res]
    return lateral, scale * obliquity * wavelength / resolution, resolution, sign


def _phase_heights(raw: np.ndarray, factor: float) -> np.ndarray:
    """Heights in m (``raw * factor``), NaN where the phase is invalid (>= 2147483640)."""
    heights = raw.astype(np.float64) * factor
    heights[raw >= _INVALID_PHASE] = np.nan
    return heights
