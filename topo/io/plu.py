"""Sensofar ``.plu`` reader (confocal / interferometric topography).

Layout (little-endian; facts from Gwyddion's ``sensofar.c`` notes): a 500-byte header:
date text (128 bytes), time (uint32), comment (256 bytes), calibration block at 388
(``yres``, ``xres``, ``N_tall`` as uint32, then ``dy_multip``, um per pixel in x and y,
x/y offsets, um per pixel in z, z offset as float32), measurement configuration at 428
(type: 1 profile, 3 topography; area type), scan settings, then ``num_layers`` at byte
489. Each layer is ``yres``, ``xres`` (uint32) followed by ``xres*yres`` float32 heights in
um (x fastest) and two float32 trailer values. The value 1000001 marks an undefined point
(NaN, counted in ``provenance["missing_pixels"]``); an infinite height is refused, as in
every reader.
After the layers comes the colour (RGB) image, ``3*xres*yres`` bytes, which must be
present in full; the metadata trailer after it has no documented size and is not checked.
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

HEADER_SIZE = 500
_UNDEFINED = 1000001.0
_TOPOGRAPHY = 3


def read_plu(path: str | Path) -> HeightMap:
    """Read the first layer of a Sensofar ``.plu`` topography (heights, pixel sizes in m).

    Parameters
    ----------
    path : str or Path
        The .plu file.

    Returns
    -------
    HeightMap
        Heights in m (NaN = undefined point), pixel sizes in m,
        provenance (instrument, units seen).

    Raises
    ------
    TopographyFileError
        A measurement that is not a topography, grid sizes that disagree between the
        calibration block and the layer, non-positive pixel sizes, or a short file.
    """
    path = Path(path)
    data = read_all_bytes(path)
    nx, ny, um_x, um_y, n_layers = _layer_grid(path, data)
    start = HEADER_SIZE + 8
    check_size(
        path,
        "layer data (xres*yres float32 + 2 trailer values)",
        start + 4 * nx * ny + 8,
        len(data),
    )
    layers_end = HEADER_SIZE + n_layers * (8 + 4 * nx * ny + 8)
    check_size(path, f"{n_layers} layer(s) and the RGB image", layers_end + 3 * nx * ny, len(data))
    raw = np.frombuffer(data, dtype="<f4", count=nx * ny, offset=start)
    heights = _heights_with_missing(raw)
    provenance = make_provenance(
        path,
        "plu",
        instrument="Sensofar",
        date=data[:128].split(b"\x00", 1)[0].decode("latin-1", "replace").strip(),
        channel="layer 0",
        n_layers=int(n_layers),
        invalid_marker=f"{_UNDEFINED:g} or NaN",
        units={"lateral": "um", "height": "um"},
    )
    sizes = (("micrometers per pixel x", um_x * 1e-6), ("micrometers per pixel y", um_y * 1e-6))
    return make_surface(path, heights.reshape(ny, nx).T, sizes, provenance)


def _layer_grid(path: Path, data: bytes) -> tuple[int, int, float, float, int]:
    """(nx, ny, um per pixel x, um per pixel y, number of layers) of a topography, checked.

    The layer's size must be the calibration block's, the pixel sizes (um) finite and > 0.
    """
    check_size(path, "header", HEADER_SIZE + 8, len(data))
    ny_cal, nx_cal, _n_tall = struct.unpack_from("<III", data, 388)
    _dy_mult, um_x, um_y = struct.unpack_from("<fff", data, 400)
    measurement_type, _algorithm, _method, _objective, _area_type = struct.unpack_from(
        "<IIIII", data, 428
    )
    n_layers = data[489]
    if measurement_type != _TOPOGRAPHY:
        raise TopographyFileError(
            path, "measurement type", f"is {measurement_type}; expected 3 (topography)"
        )
    if n_layers < 1:
        raise TopographyFileError(path, "num_layers", "is 0; expected at least one layer")
    ny, nx = struct.unpack_from("<II", data, HEADER_SIZE)
    if (nx, ny) != (nx_cal, ny_cal) or nx < 1 or ny < 1:
        raise TopographyFileError(
            path,
            "layer size",
            f"is {nx} x {ny}; expected the calibration block's {nx_cal} x {ny_cal}",
        )
    require_positive(path, "micrometers per pixel x", um_x, " um")
    require_positive(path, "micrometers per pixel y", um_y, " um")
    return nx, ny, um_x, um_y, n_layers


def _heights_with_missing(raw: np.ndarray) -> np.ndarray:
    """Heights in m from float32 um, NaN where undefined (1000001 or NaN).

    An infinite value is not a missing-point marker of the format: it is kept, so that
    :func:`make_surface` refuses it as every reader does.
    """
    raw = raw.astype(np.float64)
    invalid = (raw == _UNDEFINED) | np.isnan(raw)
    heights = raw * 1e-6
    heights[invalid] = np.nan
    return heights
