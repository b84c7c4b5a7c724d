"""Zygo MetroPro ``.dat`` reader (big-endian binary header, then intensity and phase data).

Header facts (MetroPro Reference Guide, section 12): magic ``0x881B036F`` (header format 1),
``...70`` (2) or ``...71`` (3); header size (uint32 at byte 6; 834 or 4096); intensity
array origin/width/height/buckets and byte count at 48-63; connected-phase array
origin/width/height and byte count at 64-75; ``intf_scale_factor`` (S), ``wavelength_in``
(W, m), ``obliquity_factor`` (O) and ``lateral_res`` (pixel size, m) as float32 at
164/168/176/184; ``phase_res`` at 218 (0: R = 4096, 1: 32768, 2: 131072); ``sign`` at 232.
The phase array is big-endian int32, row by row (x fastest); values >= 2147483640 are
invalid (NaN, counted in ``provenance["missing_pixels"]``). Height (m) = phase * S * O * W / R,
negated when ``sign`` is set (the format's own inversion). S, O and W must be finite and > 0 and
within the instrument's range (W 150 nm .. 2 um and equal to ``wavelength_in_1`` when set;
S 0.001 .. 1; O 0.9 .. 2), the resulting height step 1e-24 .. 1 m per count; ``lateral_res``
1 pm .. 1 m. ``phase_res`` cannot be cross-checked (no other field of a format-1 header
repeats it): its three legal values are taken as written. Nor can the phase bytes: the format
carries no checksum, so corrupted data read as heights (only values past the bounds are
refused). Both are said in ``provenance["unchecked"]`` (:data:`UNCHECKED`).
"""

from __future__ import annotations

import re
import struct
from pathlib import Path

import numpy as np

from asperity.topo.errors import (
    CorruptFileError,
    PhysicalBoundsError,
    TopographyFileError,
    check_size,
)
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
#: What no other field of the file can confirm, listed in every map's ``provenance["unchecked"]``.
UNCHECKED = (
    "phase_res: taken as written (no other header field repeats it; a wrong code scales every "
    "height by 1/8, 8, 1/32 or 32)",
    "phase data: the format has no checksum (corrupted bytes read as heights; only values past "
    "the height bounds are refused)",
)
#: Wavelengths of the interferometers' sources accepted, m (UV to near infrared).
WAVELENGTH_BOUNDS_M = (150e-9, 2e-6)
#: Obliquity factors accepted (1 for a low-aperture objective, about 1.2 at NA 0.9).
OBLIQUITY_BOUNDS = (0.9, 2.0)


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
        warnings=_optics_warnings(data, lateral),
        unchecked=list(UNCHECKED),
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
    _check_instrument_range(path, data, wavelength, scale, obliquity)
    resolution = _PHASE_RESOLUTION[phase_res]
    return lateral, scale * obliquity * wavelength / resolution, resolution, sign


def _within(path: Path, field: str, value: float, bounds: tuple[float, float], why: str) -> None:
    """Refuse a header value outside the instrument's range, naming the field."""
    low, high = bounds
    if not low <= value <= high:
        raise PhysicalBoundsError(
            path,
            field,
            f"is {value:.6g}; expected {low:g} .. {high:g} ({why})",
            expected=bounds,
            found=value,
        )


def _check_instrument_range(
    path: Path, data: bytes, wavelength: float, scale: float, obliquity: float
) -> None:
    """Cross-check the height calibration against the instrument's range and itself.

    ``wavelength_in`` must be an optical wavelength (:data:`WAVELENGTH_BOUNDS_M`) and equal
    ``wavelength_in_1`` (byte 386) when that field is set and no wavelength folding
    (``wavelength_fold``, byte 384) is used; ``intf_scale_factor`` is 0.5 (reflection) or
    1 (transmission) in practice: 0.001 .. 1 is accepted; ``obliquity_factor`` corrects for the
    objective's aperture (:data:`OBLIQUITY_BOUNDS`).
    """
    _within(path, "wavelength_in", wavelength, WAVELENGTH_BOUNDS_M, "an optical source, m")
    _within(path, "intf_scale_factor", scale, (1e-3, 1.0), "0.5 reflection, 1 transmission")
    _within(path, "obliquity_factor", obliquity, OBLIQUITY_BOUNDS, "an aperture correction")
    (fold,) = struct.unpack_from(">h", data, 384)
    (first,) = struct.unpack_from(">f", data, 386)
    if fold == 0 and first > 0 and abs(first / wavelength - 1.0) > 1e-4:
        raise CorruptFileError(
            path,
            "wavelength_in",
            f"is {wavelength:.6g} m but wavelength_in_1 is {first:.6g} m (no wavelength "
            "folding): the header contradicts itself",
            expected=first,
            found=wavelength,
        )


def _magnification(text: bytes) -> float | None:
    """The magnification written as e.g. ``b" 20X  Mirau"`` or ``b" 0.5X"``, or None."""
    match = re.match(r"\s*(\d+(?:\.\d+)?)\s*[xX]", text.split(b"\x00", 1)[0].decode("latin-1"))
    return float(match.group(1)) if match and float(match.group(1)) > 0 else None


def _optics_warnings(data: bytes, lateral: float) -> list[str]:
    """A warning when ``lateral_res`` is far (x2) from camera pixel / (objective x zoom).

    The camera's ``pixel_width`` (byte 486), the objective's magnification in ``obj_name``
    (byte 246, e.g. ``20X Mirau``) and the zoom in ``zoom_descr`` (byte 562, e.g.
    ``0.5X``) give the pixel size within the relay optics' factor (1.48 for
    metropro-1.dat); a lateral resolution more than twice off (a damaged exponent: x0.25,
    x4) is flagged. Nothing is said when a field is absent.
    """
    if len(data) < 570:
        return []
    (camera_pixel,) = struct.unpack_from(">f", data, 486)
    objective, zoom = _magnification(data[246:258]), _magnification(data[562:570])
    if not (objective and zoom and 1e-7 < camera_pixel < 1e-3):
        return []
    expected = camera_pixel / (objective * zoom)
    if 0.5 <= lateral / expected <= 2.0:
        return []
    return [
        f"lateral_res is {lateral:.4g} m but the camera pixel ({camera_pixel:.3g} m) over "
        f"the objective ({objective:g}X) and zoom ({zoom:g}X) gives {expected:.3g} m: "
        f"{lateral / expected:.3g} times that (expected within 0.5 .. 2); the pixel size may "
        "be damaged: check it before trusting lengths, eta and R"
    ]


def _phase_heights(raw: np.ndarray, factor: float) -> np.ndarray:
    """Heights in m (``raw * factor``), NaN where the phase is invalid (>= 2147483640)."""
    heights = raw.astype(np.float64) * factor
    heights[raw >= _INVALID_PHASE] = np.nan
    return heights
