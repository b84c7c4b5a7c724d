"""Isotropic surfaces synthesised from a line profile's power spectrum (random phases, seeded).

A profile of an isotropic surface has the 1D PSD ``C1(q)`` (m^3), related to the surface's 2D
PSD ``C2(|q|)`` (m^4; normalisation of :mod:`asperity.topo.psd`) by the Abel transform

    C1(qx) = integral dqy / (2 pi) C2(sqrt(qx^2 + qy^2)),
    C2(q)  = -2 integral_q^inf  C1'(k) / sqrt(k^2 - q^2) dk                 (Abel inversion),

with ``<z^2> = integral dq/(2 pi) C1 = integral d^2q/(2 pi)^2 C2`` (Persson et al. 2005,
J. Phys.: Condens. Matter 17, R1, eq. C.5; the inversion is Abel's). The profile's
periodogram ``C1 = dx/n |FFT z|^2`` is averaged in logarithmic bins of q, taken as piecewise
linear between the bin centres, and inverted exactly for that piecewise-linear form
(``integral s / sqrt(k^2 - q^2) dk = s [acosh(k/q)]``). Negative values (noise) are set to
zero. A map is then Fourier amplitudes ``sqrt(C2)`` times complex Gaussian noise from
``numpy.random.default_rng(seed)``: each seed one realisation, the rms height that of the
spectrum in expectation (not imposed). Wavevectors beyond the profile's Nyquist wavevector
``pi/dx`` (the corners of the 2D grid) get no amplitude: the profile says nothing there.

Everything in SI units: m, m^3 (C1), m^4 (C2), rad/m (q).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.fft

from asperity.errors import InputError
from asperity.topo.heightmap import HeightMap, LineProfile
from asperity.topo.synthetic import check_map_size

#: Logarithmic bins of the profile's periodogram per decade of q.
BINS_PER_DECADE = 20


def profile_psd(profile: LineProfile) -> tuple[np.ndarray, np.ndarray]:
    """Periodogram of a complete profile: ``q`` (rad/m, > 0) and ``C1(q)`` (m^3).

    ``C1 = dx / n |sum_i z_i exp(-i q x_i)|^2`` of the profile without its mean, so that
    ``<z^2> = (1/L) sum_q C1`` over all (positive and negative) q.

    Raises
    ------
    InputError
        A profile with missing points (prepare it with ``missing = "interpolate"``).
    """
    heights = np.asarray(profile.heights)
    if np.isnan(heights).any():
        raise InputError(
            f"{profile.provenance.get('file', 'the profile')}: {profile.n_missing} missing "
            "points; the spectrum needs a complete profile (prepare it with missing = "
            "'interpolate' or crop to a complete part)"
        )
    spectrum = scipy.fft.rfft(heights - heights.mean())
    q = 2 * math.pi * np.fft.rfftfreq(heights.size, profile.dx)
    c1 = profile.dx / heights.size * np.abs(spectrum) ** 2
    return q[1:], c1[1:]


def _binned(q: np.ndarray, c1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean of ``c1`` in logarithmic bins of ``q``; the bin centres are the mean q."""
    n_bins = max(int(BINS_PER_DECADE * math.log10(q[-1] / q[0])), 1)
    edges = np.geomspace(q[0], q[-1] * (1 + 1e-12), n_bins + 1)
    index = np.digitize(q, edges) - 1
    count = np.bincount(index, minlength=n_bins)
    keep = count > 0
    q_mean = np.bincount(index, weights=q, minlength=n_bins)[keep] / count[keep]
    c_mean = np.bincount(index, weights=c1, minlength=n_bins)[keep] / count[keep]
    return q_mean, c_mean


def isotropic_psd(profile: LineProfile, q: np.ndarray) -> np.ndarray:
    """The 2D PSD ``C2(|q|)`` (m^4) of the isotropic surface the profile samples.

    Parameters
    ----------
    profile : LineProfile
        Complete, levelled profile (m).
    q : ndarray
        Wavevector magnitudes (rad/m) at which to evaluate it.

    Returns
    -------
    ndarray
        ``C2(q)`` in m^4 (Abel inversion of the binned periodogram, module docstring); zero
        at q = 0, beyond the last bin centre, and wherever the inversion gives a negative
        value.
    """
    nodes, c1 = _binned(*profile_psd(profile))
    slopes = np.diff(c1) / np.diff(nodes)
    q = np.asarray(q, dtype=np.float64)
    result = np.zeros_like(q)
    inside = (q > 0) & (q < nodes[-1])
    qi = q[inside][:, None]
    lower = np.maximum(nodes[:-1][None, :], qi)
    upper = np.maximum(nodes[1:][None, :], qi)
    span = np.arccosh(upper / qi) - np.arccosh(lower / qi)
    # the drop from C1(last node) to zero beyond it: a step, -C1 delta(k - k_last)
    step = c1[-1] / np.sqrt(nodes[-1] ** 2 - qi[:, 0] ** 2)
    result[inside] = -2.0 * (span @ slopes) + 2.0 * step
    return np.maximum(result, 0.0)


def synthesise_from_profile(
    profile: LineProfile, *, n: int | None = None, seed: int = 0
) -> HeightMap:
    """A periodic isotropic map with the profile's spectrum and random phases (m).

    Parameters
    ----------
    profile : LineProfile
        Complete, levelled profile (heights and dx in m).
    n : int, optional
        Pixels per side (pixel size ``profile.dx``); default ``min(profile.nx, 2048)``.
    seed : int
        Seed of ``numpy.random.default_rng``: one realisation per seed.

    Returns
    -------
    HeightMap
        ``periodic=True``, zero mean, ``dx = dy = profile.dx``; the provenance names the
        profile, the seed and the method.
    """
    n = min(profile.nx, 2048) if n is None else int(n)
    if n < 3:
        raise InputError(f"synthesise_from_profile: n must be >= 3 pixels, got {n}")
    check_map_size(n, n, "synthesise_from_profile: n")
    dx = profile.dx
    qx = 2 * math.pi * np.fft.fftfreq(n, dx)
    qy = 2 * math.pi * np.fft.rfftfreq(n, dx)
    q = np.hypot(qx[:, None], qy[None, :])
    radial = np.linspace(0.0, q.max(), 4096)
    c2 = np.interp(q, radial, isotropic_psd(profile, radial))
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal((n, qy.size, 2)) @ np.array([1.0, 1j]) / math.sqrt(2.0)
    amplitude = np.sqrt(c2 * n * n / (dx * dx))
    heights = scipy.fft.irfft2(amplitude * noise, s=(n, n))
    heights -= heights.mean()
    provenance = {
        "format": "synthetic",
        "generator": "asperity.topo.profile_synthesis.synthesise_from_profile",
        "profile": profile.provenance.get("file", "a profile"),
        "seed": int(seed),
        "method": "isotropic, random phases, 2D PSD by Abel inversion of the profile's PSD",
        "units": {"lateral": "m", "height": "m"},
    }
    return HeightMap(heights, dx, dx, True, provenance)


@dataclass(frozen=True)
class RealisationSpread:
    """A statistic over maps synthesised from one profile with different seeds.

    Attributes
    ----------
    values : ndarray
        The statistic of each realisation (its own unit).
    seeds : tuple of int
        The seed of each realisation.
    mean, std : float
        Mean and sample standard deviation of ``values`` (std NaN for one realisation).
    n : int
        Pixels per side of every map.
    """

    values: np.ndarray
    seeds: tuple[int, ...]
    mean: float
    std: float
    n: int

    @property
    def relative_spread(self) -> float:
        """``std / |mean|`` (NaN when undefined)."""
        return self.std / abs(self.mean) if self.mean else math.nan


def realisation_spread(
    profile: LineProfile,
    statistic: Callable[[HeightMap], float],
    *,
    realisations: int = 5,
    seed: int = 0,
    n: int | None = None,
) -> RealisationSpread:
    """Evaluate ``statistic`` on ``realisations`` maps synthesised from the profile.

    Parameters
    ----------
    profile : LineProfile
        Complete, levelled profile (m).
    statistic : callable
        ``HeightMap -> float`` (e.g. ``lambda m: summit_statistics(m).asperity_density``).
    realisations : int
        Number of maps (seeds ``seed, seed + 1, ...``), >= 1.
    seed : int
        First seed.
    n : int, optional
        Pixels per side (see :func:`synthesise_from_profile`).

    Returns
    -------
    RealisationSpread
    """
    if isinstance(realisations, bool) or int(realisations) != realisations or realisations < 1:
        raise InputError(f"realisations: expected an integer >= 1, got {realisations!r}")
    seeds = tuple(range(int(seed), int(seed) + int(realisations)))
    maps = (synthesise_from_profile(profile, n=n, seed=s) for s in seeds)
    values = np.array([float(statistic(m)) for m in maps])
    std = float(np.std(values, ddof=1)) if values.size > 1 else math.nan
    size = min(profile.nx, 2048) if n is None else int(n)
    return RealisationSpread(values, seeds, float(values.mean()), std, size)
