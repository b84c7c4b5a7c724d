"""The adhesion regime of a rough contact: full contact by Persson-Tosatti, and stickiness.

**Persson-Tosatti.** A rough elastic surface pressed flat against a rigid flat stores the elastic
energy (frictionless full contact, linear elasticity; B.N.J. Persson and E. Tosatti, J. Chem.
Phys. 115, 5597 (2001), "The effect of surface roughness on the adhesion of elastic solids")

    U_el / A0 = (E* / 4) int d^2q |q| C(q) = (pi E* / 2) int_0^inf q^2 C(q) dq       (J/m^2)

with Persson's PSD ``C(q) = (2 pi)^-2 int <h(x) h(0)> exp(-i q.x) d^2x`` (m^4) and
``E* = E / (1 - nu^2)`` (Pa), the same convention as :mod:`asperity.statmodel.persson`.
Derivation: a full contact imposes the displacement ``u = -h`` (plus a constant); the
half-space's surface stiffness is ``p(q) = (E* / 2) |q| u(q)``, so the stored energy per unit
area is ``(1/2) <p u> = (E* / 4) sum_q |q| |h_q|^2`` over the Fourier modes. Check: a sinusoid
``h = h0 cos(2 pi x / L)`` needs the mean pressure ``p* = pi E* h0 / L`` to flatten (K.L. Johnson,
Contact Mechanics (1985), Section 13.2) and stores ``p* h0 / 4 = pi E* h0^2 / (4 L)``; the
formula gives ``(E* / 4) k h0^2 / 2`` with ``k = 2 pi / L``: the same.

Where ``U_el / A0 < w`` (the work of adhesion), the adhesion energy gained by full contact pays for
flattening the surface, so the interface snaps into nearly full contact at any load: the
independent-asperity model and a loading-branch BEM (contact only where the gap closes) describe
another regime. Reason code :data:`FULL_CONTACT_REASON`. The energy is that of the map's own
spectrum: roughness below the map's resolution adds to it and roughness longer than the map
is not in it, so the ratio is the map's, at its resolution.

**From a map** the energy is the sum over the map's FFT modes,
``U_el / A0 = (E* / 4) (1 / A) sum_q |q| C_topo(q)`` with ``C_topo`` of
:func:`asperity.topo.psd.psd_2d` (``C_topo = (2 pi)^2 C``): exact for a periodic map. A
non-periodic map is multiplied by a separable Hann window scaled to keep ``<h^2>`` first
(``window="auto"``), because the jump between its opposite edges otherwise adds a spurious
``q^-2`` tail (without the window the energy is 1.2 times larger on ``x3p-2``, 1.7 on
``di-3`` and ``metropro-1``, 2.0 on ``mi-1``).
**From a radial PSD** (:func:`asperity.topo.radial_psd`, the job's ``psd`` stage) the integral
runs over its rings as whole circles, the spectrum a power law between neighbouring rings: to
the Nyquist wavenumber (``q_cutoff = pi / dx``) it equals the mode sum within 1 %; to the
corners of the spectrum it counts the partial outer rings in full (+3 % on a self-affine map).

**Stickiness.** L. Pastewka and M.O. Robbins, PNAS 111, 3298 (2014), "Contact between rough
surfaces and a criterion for macroscopic adhesion", Eq. 10 with ``kappa_rep = 2`` and the
repulsive contact diameter ``d_rep = 4 h'_rms / h''_rms``:

    S_PR = (E* h'_rms dr / (kappa_rep w)) (h'_rms^2 / (h''_rms dr))^(2/3),

sticky (a finite pull-off force) when ``S_PR < 1``. The theory describes the approach to that
threshold from the non-sticky (DMT-like) side: far below 1, ``S_PR`` says "sticky", not how
sticky. ``dr`` is the range of the adhesive
interaction (m); ``h'_rms`` the rms slope and ``h''_rms`` the rms mean curvature
``sqrt(<(laplacian h / 2)^2>)`` of the surface, both from the same spectrum as the energy. The
theory assumes a range short against the gaps near the contact edges, ``dr / g0 < 0.1`` with
``g0 = (16/3) h'_rms^2 / h''_rms`` (A. Monti, A. Sanner, L. Pastewka, Tribol. Lett.
(2021), doi:10.1007/s11249-021-01454-6); :attr:`AdhesionRegime.range_ratio` reports
``dr / g0``. The equation is taken in the form the ContactEngineering group's Adhesion examples
restate it (the PNAS text was not at hand to check the printed form against).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from asperity.errors import InputError
from asperity.statmodel.checks import Check, positive_number, positive_numbers
from asperity.statmodel.parameters import tabor_parameter
from asperity.statmodel.persson import MIN_PSD_POINTS, _hann_windowed
from asperity.statmodel.spectral_moments import isotropic_moment, validate_spectrum
from asperity.topo.heightmap import HeightMap
from asperity.topo.psd import RadialPSD, psd_2d

__all__ = [
    "FULL_CONTACT_MEANING",
    "FULL_CONTACT_REASON",
    "KAPPA_REP",
    "AdhesionRegime",
    "FlatteningEnergy",
    "adhesion_regime",
    "flattening_energy",
    "pastewka_robbins_range_ratio",
    "pastewka_robbins_stickiness",
]

#: The verdict's reason code when the flattening energy is below the work of adhesion.
FULL_CONTACT_REASON = "adhesion_full_contact"
#: What that reason means.
FULL_CONTACT_MEANING = (
    "expect near-full contact; the asperity model and a loading-branch BEM do not apply"
)
#: Pastewka and Robbins's repulsive-area prefactor (A_rep = kappa_rep F / (E* h'_rms)).
KAPPA_REP = 2.0
#: Pastewka and Robbins's theory assumes dr / g0 below this (Monti, Sanner, Pastewka 2021).
PR_RANGE_LIMIT = 0.1
#: The references of this module, as cited in the checks' ``reference``.
PERSSON_TOSATTI = "B.N.J. Persson, E. Tosatti, J. Chem. Phys. 115, 5597 (2001)"

WindowChoice = Literal["auto", "hann", "none"]


@dataclass(frozen=True)
class FlatteningEnergy:
    """Elastic energy to flatten a surface, and its rms slope and curvature (see module doc).

    Attributes
    ----------
    energy_density : float
        ``U_el / A0``, J/m^2.
    e_star : float
        E*, Pa.
    rms_slope : float
        ``h'_rms = sqrt(<|grad h|^2>)`` of the same spectrum (m/m).
    rms_curvature : float
        ``h''_rms = sqrt(<(laplacian h / 2)^2>)``, 1/m.
    q_min, q_max : float
        Smallest and largest wavenumber included, rad/m.
    n_points : int
        FFT modes (map) or PSD rings (radial PSD) included.
    source : str
        ``"map"`` or ``"radial_psd"``.
    windowed : bool
        Whether a Hann window was applied (maps only).
    """

    energy_density: float
    e_star: float
    rms_slope: float
    rms_curvature: float
    q_min: float
    q_max: float
    n_points: int
    source: str
    windowed: bool


def _map_moments(surface: HeightMap, q_cutoff: float | None, window: WindowChoice):
    """Mode sums ``(1/A) sum |q|^m C_topo`` for m = 1, 2, 4 and the range, of a map."""
    if window not in ("auto", "hann", "none"):
        raise InputError(
            f"flattening_energy: window must be 'auto', 'hann' or 'none', got {window!r}"
        )
    windowed = window == "hann" or (window == "auto" and not surface.periodic)
    if windowed:
        surface = _hann_windowed(surface)
    qx, qy, psd = psd_2d(surface)
    q = np.hypot(qx[:, None], qy[None, :])
    keep = q > 0 if q_cutoff is None else (q > 0) & (q <= q_cutoff)
    q, c = q[keep], psd[keep] / (surface.lx * surface.ly)
    sums = tuple(float(np.sum(q**m * c)) for m in (1, 2, 4))
    return sums, float(q.min()), float(q.max()), int(q.size), windowed


def _radial_moments(radial: RadialPSD, q_cutoff: float | None):
    """The same moments from a radial PSD (topo normalisation), integrated over its rings."""
    q, c = validate_spectrum(radial.q, radial.psd, "flattening_energy")
    c = c / (2.0 * math.pi) ** 2  # Persson's normalisation
    hi = float(q[-1]) if q_cutoff is None else min(q_cutoff, float(q[-1]))
    if hi <= q[0]:
        raise InputError(
            f"flattening_energy: q_cutoff must exceed the first PSD ring {q[0]:.6g} rad/m, "
            f"got {q_cutoff!r}"
        )
    # int d^2q q^m C = 2 pi int q^(m+1) C dq
    sums = tuple(2 * math.pi * isotropic_moment(q, c, m + 1.0, (q[0], hi)) for m in (1, 2, 4))
    n_points = int(np.count_nonzero(q <= hi))
    return sums, float(q[0]), hi, n_points


def flattening_energy(
    surface: HeightMap | RadialPSD,
    e_star: float,
    *,
    q_cutoff: float | None = None,
    window: WindowChoice = "auto",
) -> FlatteningEnergy:
    """Elastic energy per unit area to flatten a rough surface completely (Persson-Tosatti).

    ``U_el / A0 = (E* / 4) int d^2q |q| C(q)`` (module doc), from a height map's FFT modes or a
    radial PSD's rings.

    Parameters
    ----------
    surface : asperity.topo.HeightMap or asperity.topo.psd.RadialPSD
        A height map (heights in m, no missing pixel, levelled), or the radial PSD of
        :func:`asperity.topo.radial_psd` (m^4, topo's normalisation; e.g. the ``psd`` stage's
        ``wavenumber`` and ``psd``).
    e_star : float
        Reduced modulus E* = E / (1 - nu^2), Pa.
    q_cutoff : float, optional
        Leave out wavenumbers above this (rad/m): the energy at a coarser resolution, e.g.
        ``pi / x`` for an effective pixel size x. Default: every mode of the map (up to the
        corners of its spectrum) or every ring of the radial PSD.
    window : {"auto", "hann", "none"}
        Maps only: "auto" windows a non-periodic map (module doc), "hann" always, "none" never.

    Returns
    -------
    FlatteningEnergy
        ``U_el / A0`` (J/m^2) with the rms slope, rms curvature (1/m) and wavenumber range.
    """
    e = positive_number("flattening_energy", "e_star", e_star, "Pa")
    if q_cutoff is not None:
        q_cutoff = positive_number("flattening_energy", "q_cutoff", q_cutoff, "rad/m")
    if isinstance(surface, HeightMap):
        sums, q_min, q_max, n_points, windowed = _map_moments(surface, q_cutoff, window)
        source = "map"
    elif isinstance(surface, RadialPSD):
        sums, q_min, q_max, n_points = _radial_moments(surface, q_cutoff)
        source, windowed = "radial_psd", False
    else:
        raise InputError(
            "flattening_energy: surface must be an asperity.topo.HeightMap or the RadialPSD of "
            f"asperity.topo.radial_psd, got {type(surface).__name__}"
        )
    first, second, fourth = sums
    return FlatteningEnergy(
        energy_density=0.25 * e * first,
        e_star=e,
        rms_slope=math.sqrt(second),
        rms_curvature=0.5 * math.sqrt(fourth),
        q_min=q_min,
        q_max=q_max,
        n_points=n_points,
        source=source,
        windowed=windowed,
    )


def pastewka_robbins_stickiness(
    rms_slope: float,
    rms_curvature: float,
    e_star: float,
    work_of_adhesion: float,
    interaction_range: float,
    *,
    kappa_rep: float = KAPPA_REP,
) -> float:
    """Pastewka and Robbins's stickiness measure ``S_PR`` (PNAS 111, 3298 (2014), Eq. 10).

    ``S_PR = (E* h' dr / (kappa_rep w)) (h'^2 / (h'' dr))^(2/3)``; surfaces are sticky when
    ``S_PR < 1`` (module doc).

    Parameters
    ----------
    rms_slope : float
        h'_rms (m/m), > 0.
    rms_curvature : float
        h''_rms, the rms mean curvature (1/m), > 0.
    e_star : float
        E*, Pa.
    work_of_adhesion : float
        w, J/m^2 (> 0: without adhesion nothing is sticky and S_PR is infinite).
    interaction_range : float
        dr, the range of the adhesive interaction, m.
    kappa_rep : float
        The repulsive-area prefactor (2 in Pastewka and Robbins's simulations).

    Returns
    -------
    float
        S_PR (dimensionless).
    """
    slope, curvature, e, w, dr, kappa = positive_numbers(
        "pastewka_robbins_stickiness",
        ("rms_slope", rms_slope, "m/m"),
        ("rms_curvature", rms_curvature, "1/m"),
        ("e_star", e_star, "Pa"),
        ("work_of_adhesion", work_of_adhesion, "J/m^2"),
        ("interaction_range", interaction_range, "m"),
        ("kappa_rep", kappa_rep, "(dimensionless)"),
    )
    return e * slope * dr / (kappa * w) * (slope**2 / (curvature * dr)) ** (2.0 / 3.0)


def pastewka_robbins_range_ratio(
    rms_slope: float, rms_curvature: float, interaction_range: float
) -> float:
    """``dr / g0`` with ``g0 = (16/3) h'^2 / h''`` (Monti, Sanner, Pastewka 2021; module doc).

    Pastewka and Robbins's theory assumes a short range: ``dr / g0 < 0.1``.

    Parameters
    ----------
    rms_slope : float
        h'_rms (m/m).
    rms_curvature : float
        h''_rms (1/m).
    interaction_range : float
        dr (m).

    Returns
    -------
    float
        dr / g0 (dimensionless).
    """
    slope, curvature, dr = positive_numbers(
        "pastewka_robbins_range_ratio",
        ("rms_slope", rms_slope, "m/m"),
        ("rms_curvature", rms_curvature, "1/m"),
        ("interaction_range", interaction_range, "m"),
    )
    return dr / (16.0 / 3.0 * slope**2 / curvature)


@dataclass(frozen=True)
class AdhesionRegime:
    """The adhesion regime of a map with a material (see :func:`adhesion_regime`).

    Attributes
    ----------
    energy : FlatteningEnergy
        ``U_el / A0`` (J/m^2), rms slope and curvature, wavenumber range.
    work_of_adhesion : float
        w, J/m^2.
    energy_ratio : float
        ``U_el / (A0 w)``: below 1, full contact is expected (Persson-Tosatti).
    full_contact : Check
        The criterion for the verdict: code :data:`FULL_CONTACT_REASON`, value the energy
        ratio, level "invalid" below the threshold 1, else "ok".
    stickiness : float
        Pastewka and Robbins's ``S_PR`` (sticky below 1).
    interaction_range : float
        The range dr used in ``S_PR``, m.
    range_ratio : float
        ``dr / g0``; Pastewka and Robbins's theory assumes it below 0.1.
    tabor_parameter : float
        Tabor's mu at the given summit radius (NaN when none was given).
    success : bool
        True when ``status`` is 0.
    status : int
        0 computed; 3 computed from fewer than 8 spectral points (a coarse estimate).
    message : str
        What the numbers mean.
    nit : int
        0 (closed forms).
    """

    energy: FlatteningEnergy
    work_of_adhesion: float
    energy_ratio: float
    full_contact: Check
    stickiness: float
    interaction_range: float
    range_ratio: float
    tabor_parameter: float
    success: bool
    status: int
    message: str
    nit: int = 0

    @property
    def sticky(self) -> bool:
        """Pastewka and Robbins's criterion: ``S_PR < 1``."""
        return self.stickiness < 1.0

    @property
    def pastewka_robbins_applies(self) -> bool:
        """Whether the range is short enough for Pastewka and Robbins's theory (dr / g0 < 0.1)."""
        return self.range_ratio < PR_RANGE_LIMIT


def full_contact_check(energy_density: float, work_of_adhesion: float) -> Check:
    """Persson-Tosatti's criterion as a :class:`Check`: invalid when ``U_el / A0 < w``.

    Parameters
    ----------
    energy_density : float
        ``U_el / A0``, J/m^2.
    work_of_adhesion : float
        w, J/m^2, > 0.

    Returns
    -------
    Check
        Code :data:`FULL_CONTACT_REASON`, value ``U_el / (A0 w)``, threshold 1.
    """
    w = positive_number("full_contact_check", "work_of_adhesion", work_of_adhesion, "J/m^2")
    ratio = float(energy_density) / w
    full = ratio < 1.0
    numbers = f"U_el/A0 = {energy_density:.3g} J/m^2, w = {w:.3g} J/m^2, ratio {ratio:.3g}"
    message = (
        f"the elastic energy to flatten the map is below the work of adhesion ({numbers} < 1): "
        f"{FULL_CONTACT_MEANING}; check material.E_star, material.work_of_adhesion and the map"
        if full
        else f"flattening the map costs more than the work of adhesion ({numbers} >= 1): "
        "contact stays partial"
    )
    return Check(
        code=FULL_CONTACT_REASON,
        bad_when="below",
        value=ratio,
        threshold=1.0,
        warning_threshold=-math.inf,
        invalid_threshold=1.0,
        level="invalid" if full else "ok",
        message=message,
        parameters=("material.E_star", "material.work_of_adhesion") if full else (),
        reference=PERSSON_TOSATTI,
    )


def adhesion_regime(
    surface: HeightMap | RadialPSD,
    e_star: float,
    work_of_adhesion: float,
    *,
    interaction_range: float = 0.2e-9,
    summit_radius: float | None = None,
    equilibrium_distance: float = 0.2e-9,
    q_cutoff: float | None = None,
    window: WindowChoice = "auto",
) -> AdhesionRegime:
    """Full contact (Persson-Tosatti), stickiness (Pastewka-Robbins) and Tabor's parameter.

    Parameters
    ----------
    surface : asperity.topo.HeightMap or asperity.topo.psd.RadialPSD
        As :func:`flattening_energy` (heights in m; PSD in m^4).
    e_star : float
        E* = E / (1 - nu^2), Pa.
    work_of_adhesion : float
        w, J/m^2, > 0.
    interaction_range : float
        dr of Pastewka and Robbins, m. Default 0.2 nm, the paper's equilibrium distance
        epsilon: the range of van der Waals adhesion between a polymer and glass.
    summit_radius : float, optional
        R (m) for Tabor's parameter (e.g. :func:`asperity.topo.summit_statistics` at the
        effective resolution); None: NaN.
    equilibrium_distance : float
        epsilon of Tabor's parameter, m.
    q_cutoff : float, optional
        Leave out wavenumbers above this (rad/m); see :func:`flattening_energy`.
    window : {"auto", "hann", "none"}
        See :func:`flattening_energy`.

    Returns
    -------
    AdhesionRegime
        The energy ratio and its :class:`Check`, ``S_PR``, ``dr / g0``, Tabor's mu, status.
    """
    w = positive_number("adhesion_regime", "work_of_adhesion", work_of_adhesion, "J/m^2")
    dr = positive_number("adhesion_regime", "interaction_range", interaction_range, "m")
    energy = flattening_energy(surface, e_star, q_cutoff=q_cutoff, window=window)
    check = full_contact_check(energy.energy_density, w)
    stickiness = pastewka_robbins_stickiness(
        energy.rms_slope, energy.rms_curvature, energy.e_star, w, dr
    )
    mu = math.nan
    if summit_radius is not None:
        mu = tabor_parameter(summit_radius, w, energy.e_star, equilibrium_distance, warn=False)
    status = 0 if energy.n_points >= MIN_PSD_POINTS else 3
    message = check.message
    if status:
        message = f"coarse estimate from {energy.n_points} spectral points: {message}"
    return AdhesionRegime(
        energy=energy,
        work_of_adhesion=w,
        energy_ratio=check.value,
        full_contact=check,
        stickiness=stickiness,
        interaction_range=dr,
        range_ratio=pastewka_robbins_range_ratio(energy.rms_slope, energy.rms_curvature, dr),
        tabor_parameter=mu,
        success=status == 0,
        status=status,
        message=message,
    )
