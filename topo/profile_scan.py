"""Resolution scan of a line profile: Nayak's statistics at sampling intervals k dx.

The profile counterpart of :func:`asperity.topo.resolution_scan` (paper, Fig 12a-c): for every
stride k = 1..K the statistics of :func:`~asperity.topo.nayak.profile_statistics`
at sampling interval ``k dx`` (m), and the paper's fits: R linear in the resolution, eta a
power law, sigma_s its mean and relative spread. The result is a
:class:`~asperity.topo.ResolutionScan` (same arrays, fits, JSON keys, HDF5 layout and figure),
in which ``n_summits`` holds the *peaks counted on the decimated profile* (points higher than
both neighbours: the sample size behind the estimate), plus ``bandwidth`` and ``status`` per
stride and ``method = "nayak-profile"``. Strides with fewer than ``min_peaks`` peaks, or whose
statistics are undefined (status 2), are left out of the fits.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from asperity.errors import InputError
from asperity.topo.heightmap import LineProfile
from asperity.topo.nayak import ISOTROPY_WARNING, profile_statistics
from asperity.topo.scan import ResolutionScan


@dataclass(frozen=True, eq=False)
class ProfileResolutionScan(ResolutionScan):
    """A :class:`ResolutionScan` of a line profile (``n_summits``: peaks on the profile).

    Attributes
    ----------
    bandwidth : ndarray
        Nayak's alpha per stride.
    status : ndarray of int
        Per stride: 0 valid, 1 valid with a warning, 2 R and sigma_s undefined.
    warnings : tuple of str
        The isotropy assumption and the reservations of the strides.
    method : str
        ``"nayak-profile"``.
    """

    bandwidth: np.ndarray = field(default_factory=lambda: np.zeros(0))
    status: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    warnings: tuple[str, ...] = (ISOTROPY_WARNING,)
    method: str = "nayak-profile"

    def as_dict(self) -> dict:
        """Arrays (as lists), fits, ``method``, ``bandwidth``, ``status`` and ``warnings``."""
        data = super().as_dict()
        data["method"] = self.method
        data["counted"] = "profile peaks"
        data["bandwidth"] = [float(v) if math.isfinite(v) else None for v in self.bandwidth]
        data["status"] = [int(v) for v in self.status]
        data["warnings"] = list(self.warnings)
        return data


def _power_fits(resolution: np.ndarray, radius: np.ndarray, density: np.ndarray) -> tuple:
    """(slope, intercept) of R against resolution and (exponent, prefactor) of eta."""
    if resolution.size < 2:
        return math.nan, math.nan, math.nan, math.nan
    slope, intercept = np.polyfit(resolution, radius, 1)
    exponent, log_prefactor = np.polyfit(np.log(resolution), np.log(density), 1)
    return float(slope), float(intercept), float(exponent), math.exp(log_prefactor)


def _stride_ranges(strides: list[int]) -> str:
    """``[1, 2, 3, 7, 9, 10]`` as ``"1-3, 7, 9-10"``."""
    runs: list[list[int]] = []
    for k in strides:
        if runs and k == runs[-1][-1] + 1:
            runs[-1].append(k)
        else:
            runs.append([k])
    return ", ".join(f"{r[0]}-{r[-1]}" if len(r) > 1 else f"{r[0]}" for r in runs)


def _failed_strides(rows: list) -> list[str]:
    """One warning per kind of failure, naming the strides it hit (not one line per stride).

    The kind is the message with its numbers taken out (the bandwidth differs at every stride;
    the thresholds do not); the first stride's full message is quoted.
    """
    kinds: dict[str, tuple[str, list[int]]] = {}
    for r in rows:
        if r.status:
            kind = re.sub(r"= [-+0-9.e]+", "=", r.message)
            kinds.setdefault(kind, (r.message, []))[1].append(int(r.stride))
    return [
        f"strides {_stride_ranges(strides)} ({len(strides)}): {first} (at stride {strides[0]})"
        for first, strides in kinds.values()
    ]


def profile_resolution_scan(
    profile: LineProfile, max_stride: int, *, min_peaks: int = 10
) -> ProfileResolutionScan:
    """Nayak's eta, R, sigma_s of a profile for strides 1..``max_stride`` and the paper's fits.

    Parameters
    ----------
    profile : LineProfile
        Heights in m, levelled.
    max_stride : int
        Largest stride K >= 1 (sampling interval ``K dx``, m); at most ``(nx - 1) // 2``.
    min_peaks : int
        Strides whose decimated profile has fewer peaks are left out of the fits.

    Returns
    -------
    ProfileResolutionScan
        Per stride: resolution (m), peaks, eta (1/m^2), R (m), sigma_s (m), alpha, status;
        the fits of :func:`asperity.topo.resolution_scan`.

    Raises
    ------
    InputError
        ``max_stride`` not an integer >= 1, or leaving fewer than 3 points.
    """
    if isinstance(max_stride, bool) or int(max_stride) != max_stride or max_stride < 1:
        raise InputError(f"max_stride: expected an integer >= 1, got {max_stride!r}")
    if 2 * int(max_stride) >= profile.nx:
        raise InputError(
            f"max_stride {max_stride} leaves fewer than 3 points on a profile of {profile.nx} "
            f"points; use at most {max((profile.nx - 1) // 2, 1)}"
        )
    strides = np.arange(1, int(max_stride) + 1)
    rows = [profile_statistics(profile, stride=int(k)) for k in strides]
    resolution = strides * profile.dx
    peaks = np.array([r.n_peaks for r in rows], dtype=np.int64)
    density = np.array([r.asperity_density for r in rows])
    radius = np.array([r.summit_radius for r in rows])
    height_rms = np.array([r.summit_height_rms for r in rows])
    status = np.array([r.status for r in rows], dtype=np.int64)
    use = (peaks >= min_peaks) & (status < 2)
    slope, intercept, exponent, prefactor = _power_fits(resolution[use], radius[use], density[use])
    rms_mean = float(np.mean(height_rms[use])) if use.any() else math.nan
    warnings = dict.fromkeys(w for r in rows for w in r.warnings[:2])
    warnings.update(dict.fromkeys(_failed_strides(rows)))
    return ProfileResolutionScan(
        stride=strides,
        resolution=resolution,
        n_summits=peaks,
        asperity_density=density,
        summit_radius=radius,
        summit_height_rms=height_rms,
        radius_slope=slope,
        radius_intercept=intercept,
        density_exponent=exponent,
        density_prefactor=prefactor,
        height_rms_mean=rms_mean,
        height_rms_relative_spread=float(np.std(height_rms[use]) / rms_mean)
        if use.any()
        else math.nan,
        n_fitted=int(use.sum()),
        neighbours=8,
        nominal_area=None,
        bandwidth=np.array([r.bandwidth for r in rows]),
        status=status,
        warnings=tuple(warnings),
    )
