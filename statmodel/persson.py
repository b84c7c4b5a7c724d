"""Persson's contact theory: the real contact area of a rough elastic contact from its PSD.

A rigid randomly rough surface pressed on an elastic half-space of reduced modulus
``E* = E / (1 - nu^2)`` (Pa) at nominal pressure ``p = F_z / A_n`` (Pa). Persson's theory
follows the probability distribution of the contact pressure as roughness of shorter and
shorter wavelength is added (a diffusion in pressure with an absorbing barrier at p = 0);
with all wavenumbers up to ``q1`` resolved, the contact area ratio is

    A_r / A_n = erf( p / (2 sqrt(G_p)) ),
    G_p = p^2 G(q1) = (pi / 4) E*^2 int_{q0}^{q1} q^3 C(q) dq                     (Pa^2)

(B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), "Theory of rubber friction and contact
mechanics", where ``G(q1) = (pi/4) (E* / p)^2 int q^3 C dq`` is dimensionless and
``P(q1) = erf(1 / (2 sqrt(G)))``; restated in the review B.N.J. Persson, Surf. Sci. Rep. 61,
201 (2006), "Contact mechanics for randomly rough surfaces", Section 3.4). ``C(q)`` is
Persson's isotropic PSD (m^4),

    C(q) = (2 pi)^-2 int <h(x) h(0)> exp(-i q.x) d^2x,    <h^2> = int C(q) d^2q,

so the mean square slope of an isotropic surface is ``h'^2 = 2 pi int q^3 C dq`` and
``G_p = E*^2 h'^2 / 8`` (the full-contact pressure variance is ``E*^2 h'^2 / 4 = 2 G_p``).
Since ``erf(x) -> 2 x / sqrt(pi)``, at small load

    A_r / A_n -> kappa p / (E* h'_rms),    kappa = sqrt(8 / pi) ~ 1.596.

Boundary-element and Green's-function simulations find ``kappa`` near 2 at small contact
fractions (M.H. Muser et al., Tribol. Lett. 65, 118 (2017), "Meeting the contact-mechanics
challenge"), so Persson's theory under-predicts the area there by about 20 %;
``benchmarks/statmodel_persson_vs_bem.py`` measures the ratio against :mod:`asperity.bem`.

From a height map: :func:`asperity.topo.radial_psd` uses ``C_topo = dx dy / (nx ny) |H|^2``
with ``<h^2> = (1/A) sum_q C_topo`` (sum over the FFT modes, A the map area). The modes sit on
a lattice of cell ``(2 pi)^2 / A``, so ``<h^2> = sum_q C_P (2 pi)^2 / A`` gives exactly

    C_P(q) = C_topo(q) / (2 pi)^2.

The integration runs from the smallest wavenumber of the radial PSD (the first ring,
``~2 pi / max(lx, ly)``) to the largest one the map resolves in every direction, the Nyquist
wavenumber ``q1 = pi / max(dx, dy)`` of the coarser axis (or an explicit ``q_cutoff``).

The theory here is non-adhesive. Adhesion only adds attraction, so at a given compressive
load an adhesive contact is at least as large (JKR against Hertz for one asperity, Persson's
adhesive extension and our BEM with ``w > 0`` alike): the curve is a lower bound of the
adhesive ``A_r(F_z)`` and its limit as the work of adhesion goes to zero. The adhesive
extension (Persson 2006, Section 8) is not implemented.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.special import erf

from asperity.errors import InputError
from asperity.statmodel.parameters import checked_number, is_positive
from asperity.statmodel.spectral_moments import isotropic_moment, validate_spectrum
from asperity.topo.heightmap import HeightMap
from asperity.topo.psd import RadialPSD, radial_psd

__all__ = [
    "KAPPA_PERSSON",
    "PerssonResult",
    "persson_contact_fraction",
    "persson_psd",
    "persson_real_area",
    "persson_small_load_fraction",
    "psd_rms_slope",
]

#: Persson's small-load slope: ``A_r / A_n -> kappa p / (E* h'_rms)`` with kappa = sqrt(8/pi).
KAPPA_PERSSON = math.sqrt(8.0 / math.pi)

#: Fewer PSD points than this inside the integration range make the result unreliable.
MIN_PSD_POINTS = 8

ClosedForm = Literal["erf", "small_load"]


@dataclass(frozen=True, eq=False)
class PerssonResult:
    """Real contact area by Persson's theory at each load (see :func:`persson_real_area`).

    Attributes
    ----------
    normal_load : ndarray
        F_z (N), as given.
    nominal_pressure : ndarray
        p = F_z / A_n (Pa).
    real_area : ndarray
        A_r (m^2) at each load.
    contact_fraction : ndarray
        A_r / A_n (-).
    g : ndarray
        Persson's dimensionless ``G(q1) = (pi/4) (E*/p)^2 int q^3 C dq`` at each load (inf
        at zero load).
    rms_slope : float
        ``h'_rms = sqrt(2 pi int q^3 C dq)`` over the integration range (m/m).
    q_min, q_max : float
        Integration range (rad/m, i.e. 2 pi / wavelength).
    n_psd_points : int
        PSD points inside the range.
    closed_form : str
        "erf" (Persson's result) or "small_load" (its linear limit kappa p / (E* h'_rms)).
    nominal_area : float
        A_n (m^2).
    e_star : float
        E* (Pa).
    success : bool
        True when ``status`` is 0.
    status : int
        0: computed; 3: computed, but fewer than ``MIN_PSD_POINTS`` PSD points lie inside
        the range, so the slope integral (and every area) is a coarse estimate.
    message : str
        What ``status`` means for this result.
    nit : int
        0: closed forms, no iteration.
    """

    normal_load: np.ndarray
    nominal_pressure: np.ndarray
    real_area: np.ndarray
    contact_fraction: np.ndarray
    g: np.ndarray
    rms_slope: float
    q_min: float
    q_max: float
    n_psd_points: int
    closed_form: str
    nominal_area: float
    e_star: float
    success: bool
    status: int
    message: str
    nit: int = 0


def _positive(value: object, name: str, unit: str, where: str) -> float:
    return checked_number(
        value,
        is_positive,
        f"{where}: {name} must be a number in {unit}, got {value!r}",
        f"{where}: {name} must be finite and > 0 {unit}, got {value!r}",
    )


def _pressures(values: object, name: str, unit: str, where: str) -> np.ndarray:
    try:
        array = np.atleast_1d(np.asarray(values, dtype=np.float64))
    except (TypeError, ValueError):
        raise InputError(f"{where}: {name} must be numbers in {unit}, got {values!r}") from None
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"{where}: {name} must be a non-empty 1D sequence, shape {array.shape}")
    bad = ~(np.isfinite(array) & (array >= 0))
    if np.any(bad):
        raise InputError(
            f"{where}: {name} must be finite and >= 0 {unit} (the theory is non-adhesive: "
            f"no tensile load), found {array[bad][0]!r} at index {int(np.flatnonzero(bad)[0])}"
        )
    return array


def _q_range(q: np.ndarray, q_range: tuple[float, float] | None, where: str) -> tuple[float, float]:
    if q_range is None:
        return float(q[0]), float(q[-1])
    lo, hi = (float(v) for v in q_range)
    if not (q[0] * (1 - 1e-12) <= lo < hi <= q[-1] * (1 + 1e-12)):
        raise InputError(
            f"{where}: q_range must satisfy q[0] <= q_lo < q_hi <= q[-1] "
            f"({q[0]:.6g}..{q[-1]:.6g} rad/m), got ({lo:.6g}, {hi:.6g})"
        )
    return max(lo, float(q[0])), min(hi, float(q[-1]))


def psd_rms_slope(q: object, c: object, *, q_range: tuple[float, float] | None = None) -> float:
    """Rms slope ``h'_rms = sqrt(2 pi int q^3 C(q) dq)`` of an isotropic surface (m/m).

    Parameters
    ----------
    q : array_like
        Wavenumbers (rad/m), strictly increasing, > 0.
    c : array_like
        Persson's PSD ``C(q)`` (m^4) at ``q`` (``<h^2> = int C d^2q``; see the module doc
        for the conversion from :func:`asperity.topo.radial_psd`).
    q_range : (float, float), optional
        Integration limits (rad/m) inside ``[q[0], q[-1]]``; default the whole range. The
        spectrum is a power law between neighbouring points (exact for piecewise power laws).

    Returns
    -------
    float
        The rms slope (dimensionless).
    """
    q_arr, c_arr = validate_spectrum(q, c, "psd_rms_slope")
    lo, hi = _q_range(q_arr, q_range, "psd_rms_slope")
    return math.sqrt(2.0 * math.pi * isotropic_moment(q_arr, c_arr, 3.0, (lo, hi)))


def persson_small_load_fraction(
    nominal_pressures: object, e_star: float, rms_slope: float
) -> np.ndarray:
    """Small-load limit of Persson's theory: ``A_r / A_n = kappa p / (E* h'_rms)``.

    ``kappa = sqrt(8/pi)`` (:data:`KAPPA_PERSSON`), the slope of ``erf(p / (2 sqrt(G_p)))``
    at p = 0 with ``G_p = E*^2 h'^2 / 8`` (see the module doc). Valid while the result is
    small (a few %); it grows without bound and is not clipped at 1.

    Parameters
    ----------
    nominal_pressures : array_like
        p = F_z / A_n (Pa), >= 0.
    e_star : float
        Reduced modulus E* = E / (1 - nu^2) (Pa).
    rms_slope : float
        h'_rms (m/m), > 0.

    Returns
    -------
    ndarray
        A_r / A_n (-), one per pressure.
    """
    where = "persson_small_load_fraction"
    p = _pressures(nominal_pressures, "nominal_pressures", "Pa", where)
    e = _positive(e_star, "e_star", "Pa", where)
    slope = _positive(rms_slope, "rms_slope", "(m/m)", where)
    return KAPPA_PERSSON * p / (e * slope)


def _fraction_from_slope(
    p: np.ndarray, e_star: float, rms_slope: float, form: ClosedForm
) -> np.ndarray:
    if form == "small_load":
        if rms_slope == 0:
            return np.where(p > 0, np.inf, 0.0)
        return KAPPA_PERSSON * p / (e_star * rms_slope)
    # erf(p / (2 sqrt(G_p))) with G_p = E*^2 h'^2 / 8: the argument is sqrt(2) p / (E* h')
    if rms_slope == 0:
        return np.where(p > 0, 1.0, 0.0)
    return erf(math.sqrt(2.0) * p / (e_star * rms_slope))


def _check_form(form: object, where: str) -> ClosedForm:
    if form not in ("erf", "small_load"):
        raise InputError(f"{where}: form must be 'erf' or 'small_load', got {form!r}")
    return form


def persson_contact_fraction(
    q: object,
    c: object,
    e_star: float,
    nominal_pressures: object,
    *,
    q_range: tuple[float, float] | None = None,
    form: ClosedForm = "erf",
) -> np.ndarray:
    """Persson's ``A_r / A_n`` from an isotropic PSD given at points (non-adhesive).

    ``A_r / A_n = erf(p / (2 sqrt(G_p)))``, ``G_p = (pi/4) E*^2 int_{q0}^{q1} q^3 C dq``
    (Persson 2001; module doc), or with ``form="small_load"`` its limit
    ``sqrt(8/pi) p / (E* h'_rms)``.

    Parameters
    ----------
    q : array_like
        Wavenumbers (rad/m), strictly increasing, > 0.
    c : array_like
        Persson's PSD ``C(q)`` (m^4), ``<h^2> = int C d^2q`` (divide the PSD of
        :func:`asperity.topo.radial_psd` by ``(2 pi)^2``, or use :func:`persson_psd`).
    e_star : float
        Reduced modulus E* = E / (1 - nu^2) (Pa).
    nominal_pressures : array_like
        p = F_z / A_n (Pa), >= 0.
    q_range : (float, float), optional
        Integration range [q0, q1] (rad/m) inside the sampled range; default all of it.
    form : {"erf", "small_load"}
        Persson's full result or its small-load limit.

    Returns
    -------
    ndarray
        A_r / A_n (-), one per pressure.
    """
    where = "persson_contact_fraction"
    q_arr, c_arr = validate_spectrum(q, c, where)
    e = _positive(e_star, "e_star", "Pa", where)
    p = _pressures(nominal_pressures, "nominal_pressures", "Pa", where)
    lo, hi = _q_range(q_arr, q_range, where)
    slope = math.sqrt(2.0 * math.pi * isotropic_moment(q_arr, c_arr, 3.0, (lo, hi)))
    return _fraction_from_slope(p, e, slope, _check_form(form, where))


def _hann_windowed(surface):
    """The map minus its mean times a separable Hann window scaled to keep <h^2>."""
    heights = np.asarray(surface.heights) - np.mean(surface.heights)
    window = np.outer(np.hanning(surface.nx), np.hanning(surface.ny))
    window /= math.sqrt(float(np.mean(window**2)))
    return surface.with_heights(heights * window)


def persson_psd(
    surface: HeightMap, *, window: Literal["auto", "hann", "none"] = "auto"
) -> tuple[np.ndarray, np.ndarray]:
    """Radial PSD of a height map in Persson's normalisation: ``C_P = C_topo / (2 pi)^2``.

    Parameters
    ----------
    surface : asperity.topo.HeightMap
        Heights in m, no missing pixel.
    window : {"auto", "hann", "none"}
        "hann": the mean-free map times a separable Hann window scaled so that the mean
        square height is kept (removes the leakage of a non-periodic map's edges, whose
        mismatch otherwise adds a spurious tail, ``C ~ q^-2.5`` to ``q^-3``, to the radial
        spectrum, i.e. a slope that grows with the resolution); "none": the map as it is;
        "auto" (default): "none" for a periodic map, "hann" otherwise.

    Returns
    -------
    q : ndarray
        Ring centres (rad/m), from :func:`asperity.topo.radial_psd` (rings of width
        ``2 pi / max(lx, ly)``).
    c : ndarray
        Persson's ``C(q)`` (m^4), ``<h^2> = 2 pi int q C dq``.
    """
    if not isinstance(surface, HeightMap):
        raise InputError(f"persson_psd: expected an asperity.topo.HeightMap, got {type(surface)}")
    if surface.n_missing:
        raise InputError(
            f"persson_psd: the map has {surface.n_missing} missing pixels; the PSD needs a "
            "complete map (crop to a complete region or fill the holes first)"
        )
    if window not in ("auto", "hann", "none"):
        raise InputError(f"persson_psd: window must be 'auto', 'hann' or 'none', got {window!r}")
    if window == "hann" or (window == "auto" and not surface.periodic):
        surface = _hann_windowed(surface)
    radial = radial_psd(surface)
    return radial.q, radial.psd / (2.0 * math.pi) ** 2


def _surface_spectrum(surface, q_cutoff: float | None, window: str):
    """(q, C_P, q0, q1) of a map or radial PSD, up to its largest q1 or ``q_cutoff``."""
    if not isinstance(surface, (HeightMap, RadialPSD)):
        raise InputError(
            "persson_real_area: surface must be an asperity.topo.HeightMap or the RadialPSD "
            f"of asperity.topo.radial_psd, got {type(surface).__name__}"
        )
    if isinstance(surface, RadialPSD):
        q, c = validate_spectrum(surface.q, surface.psd, "persson_real_area")
        c = c / (2.0 * math.pi) ** 2
        largest, what = float(q[-1]), "its last ring"
    else:
        q, c = persson_psd(surface, window=window)  # type: ignore[arg-type]
        largest = math.pi / max(surface.dx, surface.dy)
        what = "the Nyquist wavenumber pi / max(dx, dy)"
    q_max = largest if q_cutoff is None else q_cutoff
    if not q[0] < q_max <= largest * (1 + 1e-12):
        raise InputError(
            f"persson_real_area: q_cutoff must lie in ({q[0]:.6g}, {largest:.6g}] rad/m "
            f"(above the first PSD ring, at most {what}), got {q_cutoff!r}"
        )
    q_max = min(q_max, largest)
    # keep one ring beyond q_max so that the integral can reach q_max by interpolation
    stop = min(int(np.searchsorted(q, q_max, side="left")) + 1, q.size)
    q, c = q[:stop], c[:stop]
    return q, c, float(q[0]), min(q_max, float(q[-1]))


def persson_real_area(
    surface: HeightMap | RadialPSD,
    e_star: float,
    normal_loads: object,
    nominal_area: float,
    *,
    q_cutoff: float | None = None,
    form: ClosedForm = "erf",
    window: Literal["auto", "hann", "none"] = "auto",
) -> PerssonResult:
    """Real contact area against load by Persson's theory, from a height map or its PSD.

    ``A_r = A_n erf(p / (2 sqrt(G_p)))``, ``p = F_z / A_n``,
    ``G_p = (pi/4) E*^2 int_{q0}^{q1} q^3 C(q) dq`` (Persson, J. Chem. Phys. 115, 3840
    (2001); Surf. Sci. Rep. 61, 201 (2006), Section 3.4), non-adhesive (a lower bound of the
    adhesive area at the same load; module doc). ``C`` is the map's radial PSD converted to
    Persson's normalisation (:func:`persson_psd`); ``q0`` is its first ring
    (``~2 pi / max(lx, ly)``), ``q1`` the Nyquist wavenumber ``pi / max(dx, dy)`` or
    ``q_cutoff``. The map is the roughness of the whole nominal area: ``A_n`` only turns
    loads into pressures.

    Parameters
    ----------
    surface : asperity.topo.HeightMap or asperity.topo.psd.RadialPSD
        A height map (m, no missing pixel, levelled; a non-periodic map is Hann-windowed, see
        ``window``), or a radial PSD from :func:`asperity.topo.radial_psd` (its normalisation,
        converted here; integrated from its first to its last ring, or to ``q_cutoff``: note
        that its default rings run into the corners of the 2D spectrum, up to
        ``sqrt(2) pi / dx``, which a map resolves only along the diagonals).
    e_star : float
        Reduced modulus E* = E / (1 - nu^2) (Pa).
    normal_loads : array_like
        Normal loads F_z (N), >= 0.
    nominal_area : float
        A_n (m^2), > 0.
    q_cutoff : float, optional
        Upper integration limit q1 (rad/m), at most the Nyquist wavenumber; a coarser
        resolution of the roughness (e.g. ``2 pi / 260e-6`` for the paper's 260 um).
    form : {"erf", "small_load"}
        Persson's result, or its small-load limit ``sqrt(8/pi) p / (E* h'_rms)``.
    window : {"auto", "hann", "none"}
        See :func:`persson_psd` (maps only).

    Returns
    -------
    PerssonResult
        A_r (m^2), A_r/A_n, G, h'_rms, the wavenumber range (rad/m), the form used and the
        scipy-like status fields.
    """
    where = "persson_real_area"
    e = _positive(e_star, "e_star", "Pa", where)
    area = _positive(nominal_area, "nominal_area", "m^2", where)
    loads = _pressures(normal_loads, "normal_loads", "N", where)
    closed_form = _check_form(form, where)
    if q_cutoff is not None:
        q_cutoff = _positive(q_cutoff, "q_cutoff", "rad/m", where)
    q, c, q0, q1 = _surface_spectrum(surface, q_cutoff, window)
    integral = isotropic_moment(q, c, 3.0, (q0, q1))
    slope = math.sqrt(2.0 * math.pi * integral)
    pressure = loads / area
    fraction = _fraction_from_slope(pressure, e, slope, closed_form)
    g_p = 0.25 * math.pi * e * e * integral
    with np.errstate(divide="ignore"):
        g = np.where(pressure > 0, g_p / np.where(pressure > 0, pressure, 1.0) ** 2, np.inf)
    n_points = int(np.count_nonzero((q >= q0) & (q <= q1)))
    status = 0 if n_points >= MIN_PSD_POINTS else 3
    message = (
        "computed"
        if status == 0
        else f"computed from only {n_points} PSD points in [{q0:.4g}, {q1:.4g}] rad/m "
        f"(fewer than {MIN_PSD_POINTS}): the slope integral is a coarse estimate"
    )
    return PerssonResult(
        normal_load=loads,
        nominal_pressure=pressure,
        real_area=fraction * area,
        contact_fraction=fraction,
        g=g,
        rms_slope=slope,
        q_min=q0,
        q_max=q1,
        n_psd_points=n_points,
        closed_form=closed_form,
        nominal_area=area,
        e_star=e,
        success=status == 0,
        status=status,
        message=message,
    )
