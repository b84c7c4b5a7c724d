"""Asperity statistics from a line profile by Nayak's random-process theory.

A stylus profile samples one line of a surface. If the surface is *isotropic* and Gaussian,
the spectral moments of the profile,

    m0 = <z^2>,   m2 = <(dz/dx)^2>,   m4 = <(d^2z/dx^2)^2>      (m^2, 1, 1/m^2),

fix the joint Gaussian distribution of the height z, the slopes and the curvatures
(z_xx, z_yy, z_xy) at any point of the surface: var z_xx = var z_yy = m4,
cov(z_xx, z_yy) = var z_xy = m4/3, cov(z, z_xx) = cov(z, z_yy) = -m2, the slopes independent
of the rest with variance m2 (Longuet-Higgins 1957; Nayak 1971, "Random process model of rough
surfaces", ASME J. Lubr. Technol. 93, 398-407, eqs. 34-38). A summit is a point of zero slope
whose Hessian is negative definite; the summit density and the distribution of summit heights
and curvatures follow (Nayak's eq. 45 and after):

* summit (asperity) density ``eta = m4 / (6 pi sqrt(3) m2)`` (1/m^2; Nayak's D_sum);
* bandwidth parameter ``alpha = m0 m4 / m2^2`` (>= 1.5 for any true spectrum);
* rms summit height sigma_s about the mean summit height (m), and the mean summit height
  above the mean line (m): functions of alpha times ``sqrt(m0)`` (as alpha -> infinity,
  sigma_s -> sqrt(m0); McCool 1986, Wear 107, 37, gives ``sigma_s^2 ~ (1 - 0.8968/alpha) m0``);
* mean summit radius in the paper's convention (Appendix A), ``R = 1/2 <1/|z_xx| + 1/|z_yy|>``
  over the summits (m): a constant times ``1/sqrt(m4)``.

The summit averages are integrals over that Gaussian distribution, weighted by
``|det Hessian|`` (the Kac-Rice density of critical points). They are evaluated by a seeded
Monte Carlo of :data:`MONTE_CARLO_SAMPLES` points (deterministic): it reproduces Nayak's
closed forms (the summit density to 0.7 %, the mean curvature ``(8/3) sqrt(m4/pi)`` to 0.1 %,
McCool's sigma_s to 0.5 %; R varies by 0.3 % with alpha, where the theory has it constant).
The density itself is taken from the closed form. Nayak's profile peak density
``(1/2 pi) sqrt(m4/m2)`` (1/m) is given too, as a check against the peaks counted on the
profile.

The summits are the true ones (a maximum in every direction): the continuum limit of the
8-nearest-neighbour rule of :func:`asperity.topo.summit_statistics`. On isotropic synthetic
maps whose shortest wavelength spans at least 4 samples, profile and 8-neighbour map agree on
eta within 1 %, on R within 2.1 %, on sigma_s within 4.1 %; the paper's 4-neighbour rule also
counts diagonal saddles and finds 1.30-1.36 times more summits, with R 15-21 % larger
(measured; see docs/topo.md).

The moments are those of the sampled profile at the analysed sampling interval
``h = k dx`` (stride k): ``m2 = <((z[i+k] - z[i]) / h)^2>``,
``m4 = <((z[i+k] - 2 z[i] + z[i-k]) / h^2)^2>``, averaged over every start point (all k
sub-profiles) and over the valid ones only (a difference that touches a missing point is left
out). These finite-difference moments are what a sampling instrument can know; they make the
statistics depend on the resolution as the 2D summit statistics do (paper, Fig 12).

The isotropy assumption cannot be checked from one line; every result says so in its
``warnings``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import TypedDict

import numpy as np

from asperity.errors import InputError
from asperity.topo.heightmap import LineProfile

#: Bandwidth parameter below which the profile is dominated by its shortest wavelengths at
#: the analysed sampling interval (warned: the summits then depend strongly on the sampling).
MIN_BANDWIDTH = 5.0
#: Gaussian points of the Monte Carlo evaluation of the summit averages (seeded).
MONTE_CARLO_SAMPLES = 1 << 19
_MONTE_CARLO_SEED = 20221971
#: The assumption every profile result rests on (stated in each result).
ISOTROPY_WARNING = (
    "statistics from a line profile assume an isotropic Gaussian surface (Nayak 1971); "
    "one line cannot check it: measure along a second direction or a map to confirm"
)
#: What the profile's summits compare with (stated in each result).
NEIGHBOUR_RULE_NOTE = (
    "profile summits are true maxima (the 8-neighbour rule of a map); the paper's 4-neighbour "
    "rule counts about 1.3 times more summits on isotropic maps, with R 15-20 % larger"
)
_METHOD = "nayak-profile"


class _Densities(TypedDict):
    """Nayak's closed-form densities: summits per area (1/m^2), profile peaks per length (1/m)."""

    asperity_density: float
    peak_density: float


class SummitValues(_Densities):
    """The summit statistics of :func:`nayak_statistics` (m, 1/m^2, 1/m; see its docstring)."""

    summit_radius: float
    summit_height_rms: float
    mean_summit_height: float
    mean_curvature_radius: float


@dataclass(frozen=True)
class SpectralMoments:
    """Finite-difference spectral moments of a profile at sampling interval ``spacing``.

    Attributes
    ----------
    m0 : float
        Height variance about the mean (m^2).
    m2 : float
        Mean square slope (dimensionless).
    m4 : float
        Mean square curvature (1/m^2).
    spacing : float
        Sampling interval h (m).
    n_slopes, n_curvatures : int
        Valid first and second differences averaged.
    """

    m0: float
    m2: float
    m4: float
    spacing: float
    n_slopes: int
    n_curvatures: int

    @property
    def bandwidth(self) -> float:
        """Nayak's bandwidth parameter ``alpha = m0 m4 / m2^2``."""
        return self.m0 * self.m4 / self.m2**2 if self.m2 > 0 else math.nan


@dataclass(frozen=True)
class ProfileStatistics:
    """Summit statistics of the surface a profile was cut from (Nayak), SI units.

    The fields shared with :class:`asperity.topo.SummitStatistics` mean the same:
    ``asperity_density`` (1/m^2), ``summit_radius`` (m), ``summit_height_rms`` (m).
    Results are reported like scipy.optimize's: ``success``, integer ``status`` (0 valid, 1
    valid with a warning beyond the isotropy assumption, 2 a statistic undefined), ``message``.

    Attributes
    ----------
    asperity_density, summit_radius, summit_height_rms, mean_summit_height : float
        eta (1/m^2), R (m, paper convention), sigma_s (m), mean summit height above the mean
        line (m).
    mean_curvature_radius : float
        ``1 / <-(z_xx + z_yy)/2>`` over the summits (m): Nayak's mean summit curvature,
        inverted (smaller than R, the mean of the radii).
    peak_density : float
        Nayak's peaks per unit length of the profile (1/m).
    n_peaks : int
        Peaks counted on the analysed profile (points higher than both neighbours).
    moments : SpectralMoments
        The profile's moments at the analysed sampling interval.
    stride : int
        Decimation k (sampling interval ``k dx``).
    warnings : tuple of str
        The isotropy assumption, and any other reservation.
    """

    asperity_density: float
    summit_radius: float
    summit_height_rms: float
    mean_summit_height: float
    mean_curvature_radius: float
    peak_density: float
    n_peaks: int
    moments: SpectralMoments
    stride: int
    success: bool
    status: int
    message: str
    warnings: tuple[str, ...] = field(default=(ISOTROPY_WARNING,))
    method: str = _METHOD

    @property
    def bandwidth(self) -> float:
        """Nayak's bandwidth parameter alpha of the analysed profile."""
        return self.moments.bandwidth


def _mean_square(values: np.ndarray) -> tuple[float, int]:
    valid = values[~np.isnan(values)]
    return (float(np.mean(valid * valid)), int(valid.size)) if valid.size else (math.nan, 0)


def spectral_moments(profile: LineProfile, *, stride: int = 1) -> SpectralMoments:
    """The moments m0, m2, m4 of a profile sampled every ``stride`` points.

    Parameters
    ----------
    profile : LineProfile
        Heights in m (NaN = missing; level it first: the mean is removed, not a slope).
    stride : int
        Sampling interval ``h = stride * dx`` (m).

    Returns
    -------
    SpectralMoments
        m0 (m^2), m2 (1), m4 (1/m^2), by finite differences over every start point.

    Raises
    ------
    InputError
        ``stride`` not an integer >= 1, or fewer than 3 valid samples at that stride.
    """
    k = _check_stride(profile, stride)
    z = np.asarray(profile.heights)
    h = k * profile.dx
    valid = z[~np.isnan(z)]
    m0 = float(np.mean((valid - valid.mean()) ** 2))
    m2, n_slopes = _mean_square((z[k:] - z[:-k]) / h)
    m4, n_curvatures = _mean_square((z[2 * k :] - 2 * z[k:-k] + z[: -2 * k]) / (h * h))
    if n_curvatures == 0:
        raise InputError(
            f"profile statistics: no three valid points {k} apart in "
            f"{profile.provenance.get('file', 'the profile')}; too many missing points"
        )
    return SpectralMoments(m0, m2, m4, h, n_slopes, n_curvatures)


def _check_stride(profile: LineProfile, stride: int) -> int:
    if not isinstance(profile, LineProfile):
        raise TypeError(f"expected a topo.LineProfile, got {type(profile).__name__}")
    if isinstance(stride, bool) or int(stride) != stride or stride < 1:
        raise InputError(f"stride: expected an integer >= 1, got {stride!r}")
    if 2 * int(stride) >= profile.nx:
        raise InputError(
            f"stride {stride} leaves fewer than 3 points on a profile of {profile.nx} points; "
            f"use at most {max((profile.nx - 1) // 2, 1)}"
        )
    return int(stride)


def count_peaks(profile: LineProfile, *, stride: int = 1) -> int:
    """Points of the decimated profile strictly higher than both neighbours (missing: none)."""
    z = np.asarray(profile.heights)[:: _check_stride(profile, stride)]
    middle = z[1:-1]
    return int(np.count_nonzero((middle > z[:-2]) & (middle > z[2:])))


@functools.cache
def _standard_normals() -> np.ndarray:
    """The seeded standard normal points of the Monte Carlo, shape (samples, 4)."""
    rng = np.random.default_rng(_MONTE_CARLO_SEED)
    return rng.standard_normal((MONTE_CARLO_SAMPLES, 4))


def summit_averages(alpha: float) -> dict[str, float]:
    """Nayak's summit averages of an isotropic Gaussian surface, in standardised units.

    Heights in units of ``sqrt(m0)``, curvatures in units of ``sqrt(m4)``: the joint
    distribution of (z, z_xx, z_yy, z_xy) then depends on ``alpha`` only (correlation
    ``-1/sqrt(alpha)`` between z and z_xx or z_yy). Summits are the points whose Hessian is
    negative definite, weighted by ``|det Hessian|``.

    Parameters
    ----------
    alpha : float
        Bandwidth parameter ``m0 m4 / m2^2``; at least 1.5.

    Returns
    -------
    dict
        ``density`` (E[|det H| ; summit], so that ``eta = density / (2 pi m2) * m4``),
        ``mean_height`` and ``height_rms`` (units of sqrt(m0)), ``mean_curvature`` and
        ``inverse_curvature`` (``<(1/|z_xx| + 1/|z_yy|)/2>``, in units of sqrt(m4) and
        1/sqrt(m4)).

    Raises
    ------
    InputError
        ``alpha < 1.5``: no Gaussian surface has such moments.
    """
    if not alpha >= 1.5:
        raise InputError(
            f"bandwidth alpha = {alpha!r}: expected >= 1.5 (m0 m4 >= 1.5 m2^2 for any spectrum)"
        )
    rho = -1.0 / math.sqrt(alpha)
    covariance = np.array(
        [[1, rho, rho, 0], [rho, 1, 1 / 3, 0], [rho, 1 / 3, 1, 0], [0, 0, 0, 1 / 3]]
    )
    # alpha = 1.5 exactly is a singular (degenerate) Gaussian: nudge it to stay factorable
    points = _standard_normals() @ np.linalg.cholesky(covariance + 1e-12 * np.eye(4)).T
    z, zxx, zyy, zxy = points.T
    determinant = zxx * zyy - zxy * zxy
    weight = np.where((zxx < 0) & (determinant > 0), determinant, 0.0)
    total = weight.sum()
    mean_height = float(np.dot(weight, z) / total)
    summit = weight > 0
    inverse = np.zeros_like(z)
    inverse[summit] = 0.5 * (1 / np.abs(zxx[summit]) + 1 / np.abs(zyy[summit]))
    return {
        "density": float(total / z.size),
        "mean_height": mean_height,
        "height_rms": float(math.sqrt(np.dot(weight, (z - mean_height) ** 2) / total)),
        "mean_curvature": float(np.dot(weight, -(zxx + zyy) / 2) / total),
        "inverse_curvature": float(np.dot(weight, inverse) / total),
    }


def nayak_statistics(moments: SpectralMoments) -> SummitValues:
    """Nayak's summit statistics of an isotropic surface from its profile moments.

    Parameters
    ----------
    moments : SpectralMoments
        m0 (m^2), m2 (1), m4 (1/m^2), with ``alpha >= 1.5``.

    Returns
    -------
    SummitValues (a dict)
        ``asperity_density`` (1/m^2, the closed form), ``summit_radius`` (m, paper
        convention ``1/2 <1/|z_xx| + 1/|z_yy|>``), ``summit_height_rms`` (m),
        ``mean_summit_height`` (m), ``mean_curvature_radius`` (m, ``1 / <-(z_xx+z_yy)/2>``),
        ``peak_density`` (1/m); the theory in the module docstring.
    """
    m0, m4 = moments.m0, moments.m4
    averages = summit_averages(moments.bandwidth)
    return SummitValues(
        **_densities(moments),
        summit_radius=averages["inverse_curvature"] / math.sqrt(m4),
        summit_height_rms=averages["height_rms"] * math.sqrt(m0),
        mean_summit_height=averages["mean_height"] * math.sqrt(m0),
        mean_curvature_radius=1.0 / (averages["mean_curvature"] * math.sqrt(m4)),
    )


def _densities(moments: SpectralMoments) -> _Densities:
    """Nayak's closed forms: summits per area (1/m^2) and profile peaks per length (1/m)."""
    return {
        "asperity_density": moments.m4 / (6.0 * math.pi * math.sqrt(3.0) * moments.m2),
        "peak_density": math.sqrt(moments.m4 / moments.m2) / (2.0 * math.pi),
    }


#: Largest rms of the straight line through a profile over the rms about it, for a profile
#: that did not go through :func:`asperity.topo.prepare_profile`: above it the tilt, not the
#: roughness, would set the moments (dektak-1.csv as read: 50).
MAX_UNLEVELLED_TILT = 1.0


def check_levelled(profile: LineProfile) -> None:
    """Refuse a profile that was not prepared and whose tilt dominates its roughness.

    ``asperity stats`` levels a profile (a straight line removed, the outlier rule applied)
    before the statistics; called on a profile as read, :func:`profile_statistics` would
    describe the tilt instead (dektak-1.csv: sigma_s 4.77 um against the command's 94 nm).
    A profile from :func:`asperity.topo.prepare_profile` (``provenance["preparation"]``) is
    taken as prepared; any other is refused when the rms of its least-squares line exceeds
    :data:`MAX_UNLEVELLED_TILT` times the rms about it (heights in m).
    """
    if "preparation" in profile.provenance:
        return
    heights = np.asarray(profile.heights, dtype=float)
    valid = np.flatnonzero(~np.isnan(heights))
    if valid.size < 3:
        return
    line = np.polyval(np.polyfit(valid.astype(float), heights[valid], 1), valid.astype(float))
    tilt, rough = float(np.std(line)), float(np.std(heights[valid] - line))
    if tilt > MAX_UNLEVELLED_TILT * rough:
        raise InputError(
            f"profile statistics: {profile.provenance.get('file', 'the profile')} is not "
            f"levelled: its straight-line trend has rms {tilt:.3g} m, {tilt / rough:.3g} times "
            f"the roughness about it ({rough:.3g} m), so the statistics would describe the "
            "tilt; prepare it first, as `asperity stats` does: "
            "topo.profile_statistics(topo.prepare_profile(profile, "
            "topo.PreparationOptions())[0])"
        )


def profile_statistics(profile: LineProfile, *, stride: int = 1) -> ProfileStatistics:
    """Asperity density, summit radius and rms summit height from a line profile (Nayak).

    Parameters
    ----------
    profile : LineProfile
        Heights in m, levelled (NaN = missing point).
    stride : int
        Keep one point in ``stride``: sampling interval ``stride * dx`` (m).

    Returns
    -------
    ProfileStatistics
        eta (1/m^2), R (m), sigma_s (m) of the isotropic surface the profile samples, with
        the moments, the bandwidth alpha, status and warnings (the isotropy assumption and
        the summit rule always; a bandwidth below :data:`MIN_BANDWIDTH`; alpha < 1.5).

    Raises
    ------
    InputError
        A stride that leaves fewer than 3 points; a flat profile (m2 or m4 zero); a profile
        not levelled (:func:`check_levelled`), whose statistics would describe its tilt.
    """
    moments = spectral_moments(profile, stride=stride)
    if not (moments.m2 > 0 and moments.m4 > 0):
        raise InputError(
            f"profile statistics: {profile.provenance.get('file', 'the profile')} is flat at "
            f"sampling interval {moments.spacing:.4g} m (no slope or curvature)"
        )
    check_levelled(profile)
    warnings, status = [ISOTROPY_WARNING, NEIGHBOUR_RULE_NOTE], 0
    alpha = moments.bandwidth
    if alpha >= 1.5:
        values = nayak_statistics(moments)
    else:
        status = 2
        values = SummitValues(
            **_densities(moments),
            summit_radius=math.nan,
            summit_height_rms=math.nan,
            mean_summit_height=math.nan,
            mean_curvature_radius=math.nan,
        )
        warnings.append(
            f"bandwidth alpha = {alpha:.3g} < 1.5: no Gaussian surface has these moments (the "
            "profile is dominated by noise at this sampling interval); R and sigma_s undefined"
        )
    if 1.5 <= alpha < MIN_BANDWIDTH:
        status = 1
        warnings.append(
            f"bandwidth alpha = {alpha:.3g} < {MIN_BANDWIDTH:g}: the shortest sampled "
            "wavelengths dominate the curvatures; the summits depend strongly on the sampling"
        )
    message = "valid" if status == 0 else "; ".join(warnings[2:])
    return ProfileStatistics(
        **values,
        n_peaks=count_peaks(profile, stride=stride),
        moments=moments,
        stride=int(stride),
        success=status < 2,
        status=status,
        message=message,
        warnings=tuple(warnings),
    )
