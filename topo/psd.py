"""Power spectral density and rms descriptors of a height map.

Normalisation (stated once, used everywhere): for a map of ``nx x ny`` pixels of size
``dx x dy`` (area ``A = nx dx ny dy``) with discrete Fourier transform
``H(q) = sum_ij h_ij exp(-i q.r_ij)`` (numpy's unnormalised FFT),

    C(q) = dx dy / (nx ny) |H(q)|^2        (m^4),

so that Parseval reads ``<h^2> = (1/A) sum_q C(q)``: the mean square height is the sum of
the PSD over all wavevectors times the wavevector cell ``(2 pi)^2 / A`` divided by
``(2 pi)^2``. The radial average bins ``|q|`` with width ``2 pi / max(lx, ly)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft

from topo.heightmap import HeightMap, require_height_map


def _filled(surface: HeightMap) -> np.ndarray:
    heights = np.asarray(surface.heights)
    if surface.n_missing:
        raise ValueError(
            f"PSD: {surface.n_missing} missing pixels; the FFT needs a complete map "
            "(crop to a complete region or fill the holes first)"
        )
    return heights - heights.mean()


def psd_2d(surface: HeightMap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Full 2D PSD ``C(qx, qy)`` (m^4) on the FFT grid, with ``qx``, ``qy`` (1/m, rad/m).

    The mean height is removed first. Missing pixels are refused.
    """
    surface = require_height_map(surface, "psd_2d")
    heights = _filled(surface)
    spectrum = scipy.fft.fft2(heights)
    psd = (surface.dx * surface.dy / heights.size) * (spectrum.real**2 + spectrum.imag**2)
    qx = 2 * math.pi * np.fft.fftfreq(surface.nx, surface.dx)
    qy = 2 * math.pi * np.fft.fftfreq(surface.ny, surface.dy)
    return qx, qy, psd


@dataclass(frozen=True)
class RadialPSD:
    """Radially averaged PSD: ``q`` (rad/m, bin centres), ``psd`` (m^4), ``count`` per bin."""

    q: np.ndarray
    psd: np.ndarray
    count: np.ndarray


def radial_psd(surface: HeightMap, *, n_bins: int | None = None) -> RadialPSD:
    """Radially averaged PSD (m^4) against ``|q|`` (rad/m); empty bins are dropped.

    Bins are centred on ``k * dq`` (width ``dq = 2 pi / max(lx, ly)``) up to the largest
    ``|q|`` (or ``n_bins`` equal bins ``[k, k+1) * q_N / n_bins`` up to the Nyquist
    wavevector ``q_N`` of the coarser axis). The ``q = 0`` bin is dropped.
    """
    surface = require_height_map(surface, "radial_psd")
    qx, qy, psd = psd_2d(surface)
    q = np.hypot(qx[:, None], qy[None, :]).ravel()
    values = psd.ravel()
    if n_bins is None:
        dq = 2 * math.pi / max(surface.lx, surface.ly)
        index = np.floor(q / dq + 0.5).astype(np.int64)
    else:
        q_max = math.pi / max(surface.dx, surface.dy)
        dq = q_max / n_bins
        index = np.minimum(np.floor(q / dq).astype(np.int64), n_bins)
    counts = np.bincount(index)
    sums = np.bincount(index, weights=values)
    centres = np.bincount(index, weights=q)
    keep = (counts > 0) & (np.arange(counts.size) > 0)
    return RadialPSD(centres[keep] / counts[keep], sums[keep] / counts[keep], counts[keep])


def rolloff_wavelength(surface: HeightMap) -> float:
    """Roll-off wavelength (m) estimated from the radial PSD.

    Fits ``log C`` with a plateau for ``q < q_r`` joined to a power law for ``q >= q_r``
    (least squares over log-spaced bins), trying every bin centre as ``q_r``, and returns
    ``2 pi / q_r`` for the best fit.
    """
    radial = radial_psd(surface)
    q, c = radial.q, radial.psd
    good = c > 0
    q, c = q[good], c[good]
    if q.size < 6:
        raise ValueError("rolloff_wavelength: too few PSD bins for a fit")
    edges = np.geomspace(q[0], q[-1] * 1.0001, min(60, q.size) + 1)
    which = np.digitize(q, edges) - 1
    lq = np.array(
        [np.log(q[which == b]).mean() for b in range(edges.size - 1) if np.any(which == b)]
    )
    lc = np.array(
        [np.log(c[which == b]).mean() for b in range(edges.size - 1) if np.any(which == b)]
    )
    best, best_error = lq[0], math.inf
    for k in range(1, lq.size - 2):
        plateau = lc[:k].mean()
        x, y = lq[k:] - lq[k], lc[k:] - plateau
        slope = float(np.dot(x, y) / np.dot(x, x)) if np.dot(x, x) > 0 else 0.0
        error = np.sum((lc[:k] - plateau) ** 2) + np.sum((y - slope * x) ** 2)
        if slope < 0 and error < best_error:
            best, best_error = lq[k], error
    return float(2 * math.pi / math.exp(best))


def rms_height(surface: HeightMap) -> float:
    """Rms height about the mean over the valid pixels (m)."""
    surface = require_height_map(surface, "rms_height")
    return float(np.nanstd(surface.heights))


def _differences(surface: HeightMap) -> tuple[np.ndarray, np.ndarray]:
    h = np.asarray(surface.heights)
    if surface.periodic:
        return (np.roll(h, -1, 0) - h) / surface.dx, (np.roll(h, -1, 1) - h) / surface.dy
    return np.diff(h, axis=0)[:, :-1] / surface.dx, np.diff(h, axis=1)[:-1, :] / surface.dy


def rms_slope(surface: HeightMap) -> float:
    """Rms slope ``sqrt(<h_x^2 + h_y^2>)`` from forward differences (dimensionless).

    Differences that touch a missing pixel are skipped; a periodic map wraps around.
    """
    surface = require_height_map(surface, "rms_slope")
    gx, gy = _differences(surface)
    return float(np.sqrt(np.nanmean(gx * gx + gy * gy)))


def rms_curvature(surface: HeightMap) -> float:
    """Rms mean curvature ``sqrt(<((h_xx + h_yy)/2)^2>)`` from central differences (1/m).

    Interior pixels only unless periodic; pixels touching a missing pixel are skipped.
    """
    surface = require_height_map(surface, "rms_curvature")
    h = np.asarray(surface.heights)
    if surface.periodic:
        hxx = (np.roll(h, -1, 0) - 2 * h + np.roll(h, 1, 0)) / surface.dx**2
        hyy = (np.roll(h, -1, 1) - 2 * h + np.roll(h, 1, 1)) / surface.dy**2
    else:
        c = h[1:-1, 1:-1]
        hxx = (h[2:, 1:-1] - 2 * c + h[:-2, 1:-1]) / surface.dx**2
        hyy = (h[1:-1, 2:] - 2 * c + h[1:-1, :-2]) / surface.dy**2
    mean_curvature = 0.5 * (hxx + hyy)
    return float(np.sqrt(np.nanmean(mean_curvature**2)))
