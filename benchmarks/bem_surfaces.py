"""Benchmark surfaces for bem (self-affine, periodic), generated here so bem needs no topo."""

from __future__ import annotations

import numpy as np


def self_affine_periodic(
    n: int,
    *,
    hurst: float = 0.8,
    short_cutoff_px: float = 8.0,
    rms_slope: float = 1.0,
    pixel_size: float = 1.0,
    seed: int = 0,
) -> np.ndarray:
    """Periodic Gaussian self-affine heights (m) on an n x n grid.

    Isotropic power spectrum C(q) ~ q^(-2(1+H)) for 2 pi / L <= q <= 2 pi / (short_cutoff_px dx),
    zero elsewhere, random phases, scaled to the given rms slope (gradient by spectral
    differentiation).
    """
    rng = np.random.default_rng(seed)
    qx = 2 * np.pi * np.fft.fftfreq(n, d=pixel_size)
    qy = 2 * np.pi * np.fft.rfftfreq(n, d=pixel_size)
    q = np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
    q_min = 2 * np.pi / (n * pixel_size)
    q_max = 2 * np.pi / (short_cutoff_px * pixel_size)
    amp = np.zeros_like(q)
    band = (q >= q_min * 0.999) & (q <= q_max)
    amp[band] = q[band] ** (-(1.0 + hurst))
    spec = amp * (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape))
    h = np.fft.irfft2(spec, s=(n, n))
    gx = np.fft.irfft2(1j * qx[:, None] * spec, s=(n, n))
    gy = np.fft.irfft2(1j * qy[None, :] * spec, s=(n, n))
    slope = np.sqrt(np.mean(gx**2 + gy**2))
    h *= rms_slope / slope
    return h - h.mean()
