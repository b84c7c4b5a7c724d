"""Seeded synthetic rough surfaces (periodic, self-affine with a roll-off).

The isotropic power spectral density (normalisation as in :mod:`topo.psd`) is

    C(q) = C0                                   for q0 <= q < q_r   (plateau)
    C(q) = C0 (q / q_r)^(-2(1 + H))             for q_r <= q <= q_s (self-affine)
    C(q) = 0                                    for q > q_s or q = 0

with ``q_r = 2 pi / rolloff_wavelength``, ``q_s = 2 pi / short_cutoff`` and Hurst exponent
H. Fourier amplitudes are ``sqrt(C)`` times complex Gaussian noise from
``numpy.random.default_rng(seed)``; the map is scaled to the requested rms height exactly.
The roll-off, cut-off and rms height are physical (m), so they do not change with the
number of pixels.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft

from topo.heightmap import HeightMap

_ROWS_PER_BLOCK = 256


def self_affine(
    n: int,
    pixel_size: float,
    *,
    rms_height: float,
    rolloff_wavelength: float,
    hurst: float = 0.8,
    short_cutoff: float | None = None,
    seed: int = 0,
    ny: int | None = None,
) -> HeightMap:
    """A periodic self-affine height map with a roll-off (heights in m).

    Parameters
    ----------
    n : int
        Pixels along x (and along y unless ``ny`` is given).
    pixel_size : float
        dx = dy (m).
    rms_height : float
        Rms height of the map (m), imposed exactly.
    rolloff_wavelength : float
        Wavelength (m) below which the spectrum follows the power law; longer wavelengths
        form the plateau.
    hurst : float
        Hurst exponent H, 0 < H <= 1 (PSD ~ q^(-2(1+H))).
    short_cutoff : float, optional
        Shortest wavelength kept (m); default: none (up to the Nyquist wavelength 2 dx).
    seed : int
        Seed of ``numpy.random.default_rng``; the same seed gives the same map.
    ny : int, optional
        Pixels along y (default ``n``).

    Returns
    -------
    HeightMap
        ``periodic=True``, zero mean, provenance records every parameter.
    """
    nx = int(n)
    ny = nx if ny is None else int(ny)
    if nx < 2 or ny < 2:
        raise ValueError(f"self_affine: need at least 2 x 2 pixels, got {nx} x {ny}")
    for name, value in (
        ("pixel_size", pixel_size),
        ("rms_height", rms_height),
        ("rolloff_wavelength", rolloff_wavelength),
    ):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"self_affine: {name} must be a finite value > 0 m, got {value!r}")
    if not 0 < hurst <= 1:
        raise ValueError(f"self_affine: hurst must be in (0, 1], got {hurst!r}")
    if short_cutoff is not None and not short_cutoff > 0:
        raise ValueError(f"self_affine: short_cutoff must be > 0 m, got {short_cutoff!r}")
    q_r = 2 * math.pi / rolloff_wavelength
    q_s = math.inf if short_cutoff is None else 2 * math.pi / short_cutoff
    rng = np.random.default_rng(seed)
    qx = 2 * math.pi * np.fft.fftfreq(nx, pixel_size)
    qy = 2 * math.pi * np.fft.rfftfreq(ny, pixel_size)
    spectrum = np.empty((nx, qy.size), dtype=np.complex128)
    exponent = -(1.0 + hurst)  # amplitude ~ sqrt(C) ~ q^-(1+H)
    for start in range(0, nx, _ROWS_PER_BLOCK):
        stop = min(start + _ROWS_PER_BLOCK, nx)
        q = np.hypot(qx[start:stop, None], qy[None, :])
        amplitude = np.where(q < q_r, 1.0, (np.maximum(q, q_r) / q_r) ** exponent)
        amplitude[(q > q_s) | (q == 0)] = 0.0
        noise = rng.standard_normal((stop - start, qy.size, 2))
        spectrum[start:stop] = amplitude * (noise[..., 0] + 1j * noise[..., 1])
    heights = scipy.fft.irfft2(spectrum, s=(nx, ny), overwrite_x=True)
    del spectrum
    heights -= heights.mean()
    rms = float(np.sqrt(np.mean(heights * heights)))
    if rms == 0:
        raise ValueError("self_affine: the band between roll-off and cut-off holds no mode")
    heights *= rms_height / rms
    provenance = {
        "format": "synthetic",
        "generator": "topo.synthetic.self_affine",
        "seed": int(seed),
        "hurst": float(hurst),
        "rms_height": float(rms_height),
        "rolloff_wavelength": float(rolloff_wavelength),
        "short_cutoff": None if short_cutoff is None else float(short_cutoff),
        "units": {"lateral": "m", "height": "m"},
    }
    return HeightMap(heights, pixel_size, pixel_size, True, provenance)


def paper_like(
    *,
    n: int = 5000,
    pixel_size: float = 2e-6,
    seed: int = 0,
    hurst: float = 0.8,
    rms_height: float = 50e-6,
    rolloff_wavelength: float = 600e-6,
    short_cutoff: float | None = 20e-6,
) -> HeightMap:
    """A surface like the one of the paper (Section 5, Appendix A): 10 mm square at 2 um.

    Defaults: 5000 x 5000 pixels of 2 um (10 mm x 10 mm), roll-off wavelength 600 um, rms
    height 50 um (the paper: rms/sqrt(2) ~ 36 um), Hurst exponent 0.8 and a short cut-off
    of 20 um, chosen so that at 2 um resolution the 4-neighbour asperity density is close
    to the paper's 652 mm^-2 (about 630 mm^-2 for seed 0). Roll-off, rms and
    cut-off are in metres and do not depend on ``n``: a smaller ``n`` (or larger
    ``pixel_size``) gives a smaller (or coarser) patch of the same kind of surface.

    Returns
    -------
    HeightMap
        Periodic, heights in m.
    """
    surface = self_affine(
        n,
        pixel_size,
        rms_height=rms_height,
        rolloff_wavelength=rolloff_wavelength,
        hurst=hurst,
        short_cutoff=short_cutoff,
        seed=seed,
    )
    provenance = dict(surface.provenance, generator="topo.synthetic.paper_like")
    return surface.with_heights(surface.heights, provenance=provenance)
