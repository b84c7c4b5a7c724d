"""Coarser versions of a height map: the paper's decimation and two anti-aliased options.

====================  ==============================================  ======================
function              what a coarse pixel is                          aliasing
====================  ==============================================  ======================
``decimate``          every k-th sample in x and y (Section 5: "one   short wavelengths fold
                      out of two, three, four, etc sampling points")  into long ones
``block_mean``        mean of a k x k block of valid pixels            attenuated (box filter)
``fourier_resample``  spectrum truncated at the new Nyquist            none for periodic maps
====================  ==============================================  ======================

``decimate`` is what the paper uses for Fig 12 and is a strided view (no copy). The
other two low-pass filter first: summits then belong to the smoothed surface rather than
to a sparse subset of the measured points.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from asperity.errors import InputError
from asperity.topo.heightmap import HeightMap, require_height_map


def _check_stride(stride: int) -> int:
    if isinstance(stride, bool) or int(stride) != stride or int(stride) < 1:
        raise InputError(f"stride: expected an integer >= 1, got {stride!r}")
    return int(stride)


def decimate(surface: HeightMap, stride: int) -> HeightMap:
    """Keep one point in ``stride`` along x and along y (the paper's resampling, Section 5).

    Parameters
    ----------
    surface : HeightMap
        The map (heights in m).
    stride : int
        k >= 1; the new pixel sizes are ``k*dx`` and ``k*dy`` (m).

    Returns
    -------
    HeightMap
        ``heights[::k, ::k]`` as a read-only *view* of the input (no copy). Periodic only
        if the input is periodic and k divides both ``nx`` and ``ny``.
    """
    surface = require_height_map(surface, "decimate")
    k = _check_stride(stride)
    if k == 1:
        return surface
    periodic = surface.periodic and surface.nx % k == 0 and surface.ny % k == 0
    provenance = dict(surface.provenance)
    provenance["decimation"] = provenance.get("decimation", 1) * k
    return HeightMap(
        surface.heights[::k, ::k], surface.dx * k, surface.dy * k, periodic, provenance
    )


def block_mean(surface: HeightMap, factor: int) -> HeightMap:
    """Average non-overlapping ``factor x factor`` blocks (NaN-aware; anti-aliased option).

    Parameters
    ----------
    surface : HeightMap
        Heights in m.
    factor : int
        Block size k >= 1 (pixels per side).

    Returns
    -------
    HeightMap
        ``nx//k x ny//k`` block means (m), pixel sizes ``k*dx`` and ``k*dy`` (m). Trailing
        rows/columns that do not fill a whole block are dropped; a block with no valid
        pixel is NaN. Periodic only if the input is and k divides ``nx`` and ``ny``.
    """
    surface = require_height_map(surface, "block_mean")
    k = _check_stride(factor)
    nx, ny = surface.nx // k, surface.ny // k
    if nx < 1 or ny < 1:
        raise InputError(f"block_mean: factor {k} exceeds the map size {surface.heights.shape}")
    blocks = surface.heights[: nx * k, : ny * k].reshape(nx, k, ny, k)
    valid = ~np.isnan(blocks)
    counts = valid.sum(axis=(1, 3))
    sums = np.where(valid, blocks, 0.0).sum(axis=(1, 3))
    with np.errstate(invalid="ignore", divide="ignore"):
        heights = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    periodic = surface.periodic and surface.nx % k == 0 and surface.ny % k == 0
    provenance = dict(surface.provenance, block_mean=k)
    return HeightMap(heights, surface.dx * k, surface.dy * k, periodic, provenance)


def fourier_resample(surface: HeightMap, factor: int) -> HeightMap:
    """Resample onto ``nx//factor x ny//factor`` points by truncating the Fourier spectrum.

    Exact for band-limited periodic maps (every wavelength longer than two new pixels is
    kept, everything shorter is removed). For a non-periodic map the implied periodic
    continuation adds edge ringing.

    Parameters
    ----------
    surface : HeightMap
        Heights in m, no missing pixel.
    factor : int
        Reduction k >= 1 of the number of points per axis.

    Returns
    -------
    HeightMap
        Heights in m on ``nx//k x ny//k`` points; pixel sizes ``lx/(nx//k)`` and
        ``ly/(ny//k)`` (m).
    """
    surface = require_height_map(surface, "fourier_resample")
    k = _check_stride(factor)
    if surface.n_missing:
        raise InputError(
            f"fourier_resample: {surface.n_missing} missing pixels; fill or crop first"
        )
    mx, my = surface.nx // k, surface.ny // k
    if mx < 2 or my < 2:
        raise InputError(f"fourier_resample: factor {k} leaves fewer than 2 points per axis")
    spectrum = scipy.fft.fft2(surface.heights)
    kept = np.zeros((mx, my), dtype=complex)
    fx = np.fft.fftfreq(surface.nx, 1.0 / surface.nx).astype(int)
    fy = np.fft.fftfreq(surface.ny, 1.0 / surface.ny).astype(int)
    keep_x = np.abs(fx) < (mx + 1) // 2 if mx % 2 else np.abs(fx) < mx // 2
    keep_y = np.abs(fy) < (my + 1) // 2 if my % 2 else np.abs(fy) < my // 2
    ix, iy = fx[keep_x] % mx, fy[keep_y] % my
    kept[np.ix_(ix, iy)] = spectrum[np.ix_(np.flatnonzero(keep_x), np.flatnonzero(keep_y))]
    heights = scipy.fft.ifft2(kept).real * (mx * my) / (surface.nx * surface.ny)
    provenance = dict(surface.provenance, fourier_resample=k)
    return HeightMap(heights, surface.lx / mx, surface.ly / my, surface.periodic, provenance)
