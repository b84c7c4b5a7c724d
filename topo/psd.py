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

import numba
import numpy as np
import scipy.fft

from asperity.errors import InputError
from asperity.topo.errors import TopoWarning
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.validity import Finding, raise_findings


def _filled(surface: HeightMap) -> np.ndarray:
    heights = np.asarray(surface.heights)
    if surface.n_missing:
        raise InputError(
            f"PSD: {surface.n_missing} missing pixels; the FFT needs a complete map "
            "(crop to a complete region or fill the holes first)"
        )
    return heights - heights.mean()


def psd_2d(surface: HeightMap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Full 2D PSD ``C(qx, qy)`` (m^4) on the FFT grid (normalisation in the module doc).

    Parameters
    ----------
    surface : HeightMap
        Heights in m, no missing pixel (refused: the FFT needs a complete map). The mean
        height is removed first.

    Returns
    -------
    qx, qy : ndarray
        Wavevectors (rad/m) along axis 0 and axis 1, in FFT order.
    psd : ndarray, shape (nx, ny)
        ``C(qx, qy)`` in m^4.
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

    Parameters
    ----------
    surface : HeightMap
        Heights in m, no missing pixel.
    n_bins : int, optional
        Default: bins centred on ``k * dq`` (width ``dq = 2 pi / max(lx, ly)``) up to the
        largest ``|q|``; otherwise ``n_bins`` equal bins ``[k, k+1) * q_N / n_bins`` up to
        the Nyquist wavevector ``q_N`` of the coarser axis. The ``q = 0`` bin is dropped.

    Returns
    -------
    RadialPSD
        ``q`` (rad/m, mean ``|q|`` of each bin), ``psd`` (m^4), ``count`` (modes per bin).
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
    """Roll-off wavelength (m) estimated from the radial PSD (paper, Section 5: ~600 um).

    Fits ``log C`` with a plateau for ``q < q_r`` joined to a power law for ``q >= q_r``
    (least squares over log-spaced bins), trying every bin centre as ``q_r``, and returns
    ``2 pi / q_r`` for the best fit. Bins more than 12 decades below the maximum (beyond a
    hard short-wavelength cut-off) are ignored.

    Parameters
    ----------
    surface : HeightMap
        Heights in m, no missing pixel.

    Returns
    -------
    float
        The roll-off wavelength ``2 pi / q_r`` in m.
    """
    radial = radial_psd(surface)
    q, c = radial.q, radial.psd
    good = c > 1e-12 * c.max()  # drop bins beyond a hard cut-off (rounding noise only)
    q, c = q[good], c[good]
    if q.size < 6:
        raise InputError("rolloff_wavelength: too few PSD bins for a fit")
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


@numba.njit(cache=True)
def _valid_moments(h):
    """Count, sum and sum of squares of the non-NaN values of a 2D array."""
    count = 0
    total = 0.0
    squares = 0.0
    nx, ny = h.shape
    for i in range(nx):
        for j in range(ny):
            z = h[i, j]
            if not np.isnan(z):
                count += 1
                total += z
                squares += z * z
    return count, total, squares


def rms_height(surface: HeightMap, *, about_mean: bool = True) -> float:
    """Rms height over the valid pixels (m): about the mean (Sq), or about zero.

    One compiled pass, no copies.

    Parameters
    ----------
    surface : HeightMap
        Heights in m; NaN pixels are skipped.
    about_mean : bool
        True: ``sqrt(<(h - <h>)^2>)``; False: ``sqrt(<h^2>)`` of the heights as they are
        (e.g. after a levelling that already set the mean plane to zero).

    Returns
    -------
    float
        Rms height in m (NaN if no pixel is valid).
    """
    surface = require_height_map(surface, "rms_height")
    count, total, squares = _valid_moments(surface.heights)
    if count == 0:
        return float("nan")
    mean_square = squares / count
    if about_mean:
        mean_square = max(mean_square - (total / count) ** 2, 0.0)
    return float(np.sqrt(mean_square))


@numba.njit(cache=True)
def _mean_square_slope(h, dx, dy, periodic):
    nx, ny = h.shape
    total = 0.0
    count = 0
    i_stop = nx if periodic else nx - 1
    j_stop = ny if periodic else ny - 1
    for i in range(i_stop):
        ip = i + 1 if i < nx - 1 else 0
        for j in range(j_stop):
            jp = j + 1 if j < ny - 1 else 0
            gx = (h[ip, j] - h[i, j]) / dx
            gy = (h[i, jp] - h[i, j]) / dy
            value = gx * gx + gy * gy
            if not np.isnan(value):
                total += value
                count += 1
    return total / count if count else np.nan


@numba.njit(cache=True)
def _mean_square_curvature(h, dx, dy, periodic):
    nx, ny = h.shape
    total = 0.0
    count = 0
    i_start, i_stop = (0, nx) if periodic else (1, nx - 1)
    j_start, j_stop = (0, ny) if periodic else (1, ny - 1)
    for i in range(i_start, i_stop):
        im = i - 1 if i > 0 else nx - 1
        ip = i + 1 if i < nx - 1 else 0
        for j in range(j_start, j_stop):
            jm = j - 1 if j > 0 else ny - 1
            jp = j + 1 if j < ny - 1 else 0
            z = h[i, j]
            hxx = (h[ip, j] - 2.0 * z + h[im, j]) / (dx * dx)
            hyy = (h[i, jp] - 2.0 * z + h[i, jm]) / (dy * dy)
            value = 0.25 * (hxx + hyy) ** 2
            if not np.isnan(value):
                total += value
                count += 1
    return total / count if count else np.nan


def rms_slope(surface: HeightMap) -> float:
    """Rms slope ``sqrt(<h_x^2 + h_y^2>)`` from forward differences (dimensionless).

    Differences that touch a missing pixel are skipped; a periodic map wraps around.
    One compiled pass, no temporary arrays.

    Parameters
    ----------
    surface : HeightMap
        Heights in m, pixel sizes dx, dy in m.

    Returns
    -------
    float
        The rms gradient (m/m).
    """
    surface = require_height_map(surface, "rms_slope")
    return float(
        np.sqrt(_mean_square_slope(surface.heights, surface.dx, surface.dy, surface.periodic))
    )


def rms_curvature(surface: HeightMap) -> float:
    """Rms mean curvature ``sqrt(<((h_xx + h_yy)/2)^2>)`` from central differences (1/m).

    Interior pixels only unless periodic; pixels touching a missing pixel are skipped.
    This is SurfaceTopography's ``rms_curvature_from_area`` definition (not the paper's
    summit radius R of Appendix A, see :func:`topo.summit_statistics`). One compiled pass.

    Parameters
    ----------
    surface : HeightMap
        Heights in m, pixel sizes dx, dy in m.

    Returns
    -------
    float
        The rms mean curvature in 1/m.
    """
    surface = require_height_map(surface, "rms_curvature")
    return float(
        np.sqrt(_mean_square_curvature(surface.heights, surface.dx, surface.dy, surface.periodic))
    )


@dataclass(frozen=True)
class HurstEstimate:
    """The Hurst exponent of a power-law PSD ``C(q) ~ q**psd_exponent`` (2D, m^4), if any.

    Attributes
    ----------
    psd_exponent : float
        The fitted slope of log C against log q (dimensionless; -2(1 + H) for a self-affine
        surface).
    slope_hurst : float
        ``-psd_exponent / 2 - 1`` whatever its value (what asperity 0.3 reported as H).
    hurst_exponent : float
        ``slope_hurst`` when it lies in (0, 1), the range of a self-affine surface; NaN
        otherwise (the slope is then no Hurst exponent: see ``validity_notes``).
    validity_codes, validity_notes : tuple of str
        ``("hurst_out_of_range",)`` and its sentence when ``slope_hurst`` is outside (0, 1).
    """

    psd_exponent: float
    slope_hurst: float
    hurst_exponent: float
    validity_codes: tuple[str, ...] = ()
    validity_notes: tuple[str, ...] = ()


def hurst_from_psd_exponent(psd_exponent: float, *, warn: bool = True) -> HurstEstimate:
    """The Hurst exponent H = -psd_exponent/2 - 1 of a 2D PSD slope, only where it is one.

    A self-affine surface has 0 < H < 1, a PSD falling as q^-2 to q^-4. A steeper PSD (H > 1)
    is that of a smooth surface over the fitted band: the band lies at or below the roll-off,
    or a low-pass (the instrument's lateral resolution, a filter, a form left in) dominates it.
    A flatter one (H < 0) is noise-like (a noise floor, spikes). Neither is a Hurst exponent.

    Parameters
    ----------
    psd_exponent : float
        Slope of log C(q) against log q (dimensionless).
    warn : bool
        Raise the ``hurst_out_of_range`` finding as a :class:`asperity.topo.TopoWarning`.

    Returns
    -------
    HurstEstimate
    """
    exponent = float(psd_exponent)
    slope_hurst = -exponent / 2.0 - 1.0
    if not math.isfinite(slope_hurst) or 0.0 < slope_hurst < 1.0:
        return HurstEstimate(exponent, slope_hurst, slope_hurst)
    if slope_hurst >= 1.0:
        what = (
            f"the PSD falls as q^{exponent:.3g}, steeper than q^-4 (the slope's H = "
            f"{slope_hurst:.3g} >= 1 is not a Hurst exponent, which lies in (0, 1)): the "
            "surface is smooth over the fitted band (the band is at or below the roll-off, or "
            "the instrument's lateral resolution, a filter or a form left in dominates it)"
        )
    else:
        what = (
            f"the PSD falls as q^{exponent:.3g}, flatter than q^-2 (the slope's H = "
            f"{slope_hurst:.3g} <= 0 is not a Hurst exponent, which lies in (0, 1)): the "
            "spectrum is noise-like over the fitted band (a noise floor, spikes)"
        )
    finding = Finding("hurst_out_of_range", "invalid", what, slope_hurst, 1.0)
    if warn:
        raise_findings([finding], TopoWarning, stacklevel=3)
    return HurstEstimate(exponent, slope_hurst, math.nan, (finding.code,), (finding.message,))
