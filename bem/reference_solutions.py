"""Reference solutions: the closed forms the BEM is checked against.

Plain functions of SI quantities (m, Pa, N, J/m^2), scalars or broadcast arrays, used by the
tests of :mod:`asperity.bem`, the benchmarks and the documentation examples. Where a
single-asperity law is one the statistical model uses too (:mod:`asperity.single_asperity`:
Hertz, JKR, Maugis-Dugdale, Papangelo-Ciavarella, the ground both packages stand on) it is
reused from there, not written again, and the BEM does not import the model it checks.

Sections
--------
Hertz sphere
    A rigid sphere of radius R on an elastic half-space of reduced modulus E* (or two elastic
    spheres, with R and E* the reduced ones), frictionless, non-adhesive: contact radius,
    approach, peak and mean pressure, the pressure field. Hertz (1882); Johnson, *Contact
    Mechanics* (1985), section 4.2; the paper's E:Hertz_theory.
JKR sphere
    The same sphere with a work of adhesion w, short-range (Tabor parameter large): a(P),
    delta(a), P(a), pull-off. Johnson, Kendall & Roberts (1971), Proc. R. Soc. A 324, 301;
    the paper's E:JKR_indent, E:JKR_load, E:JKR_delta_min_unloading.
Maugis-Dugdale sphere
    The adhesive sphere with a Dugdale cohesive zone, from JKR to DMT: re-exposed from
    :mod:`asperity.single_asperity.maugis_dugdale` (Maugis 1992, J. Colloid Interface Sci. 150, 243;
    notation of Johnson & Greenwood 1997).
Westergaard sinusoid
    A periodic 1D wavy surface h(x) = g cos(2 pi x / lambda) pressed flat against a rigid
    plane, frictionless, non-adhesive: full-contact pressure p*, mean pressure and contact
    half-width in partial contact, pressure field. Westergaard (1939), J. Appl. Mech. 6, A49;
    Johnson (1985), section 13.2.
Shear (nu = 1/2 throughout)
    Cattaneo-Mindlin (Johnson 1985, section 7.2): a Hertz sphere of contact radius a under P,
    with Coulomb friction mu, under a monotonically increasing T < mu P sticks on a central
    disc c / a = (1 - T / (mu P))^(1/3); its tangential displacement (rigid flat, G = E*/4,
    (2 - nu) / G = 6 / E*) is delta_T = 9 mu P / (8 E* a) [1 - (1 - T / (mu P))^(2/3)], whose
    initial slope is Mindlin's full-stick compliance 3 / (4 E* a), i.e. E:PC_T
    T = 4/3 E* a delta_T. The Papangelo-Ciavarella adhesive sphere in fixed grip
    (E:PC_indent, E:PC_P, E:PC_T, E:PC_a_min_1, E:max_disp_PC) and its Hertz sliding state
    (E:Hertz_theory) are those of :mod:`asperity.single_asperity.papangelo_ciavarella`,
    gathered by :func:`pc_sphere`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from asperity.bem.errors import BemInputError
from asperity.single_asperity import papangelo_ciavarella as pc
from asperity.single_asperity.hertz import hertz_normal_load
from asperity.single_asperity.jkr import (
    jkr_jump_off_distance,
    jkr_load_from_radius,
    jkr_pull_off_force_fixed_grip,
    jkr_pull_off_force_load_control,
)
from asperity.single_asperity.maugis_dugdale import (
    MaugisDugdale,
    dimensionless_state,
    maugis_parameter,
)

__all__ = [
    # Hertz sphere
    "hertz_sphere_approach",
    "hertz_sphere_contact_radius",
    "hertz_sphere_force",
    "hertz_sphere_mean_pressure",
    "hertz_sphere_peak_pressure",
    "hertz_sphere_pressure",
    # JKR sphere
    "jkr_jump_off_distance",
    "jkr_pull_off_force_fixed_grip",
    "jkr_pull_off_force_load_control",
    "jkr_sphere_approach",
    "jkr_sphere_contact_radius",
    "jkr_sphere_force",
    # Maugis-Dugdale sphere
    "MaugisDugdale",
    "dimensionless_state",
    "maugis_parameter",
    # Westergaard sinusoid
    "westergaard_contact_half_width",
    "westergaard_full_contact_pressure",
    "westergaard_mean_pressure",
    "westergaard_pressure",
    # Shear
    "PCSphereState",
    "cattaneo_mindlin_displacement",
    "cattaneo_mindlin_force",
    "cattaneo_mindlin_stick_radius",
    "mindlin_tangential_stiffness",
    "pc_sphere",
]


def _out(value: np.ndarray) -> np.ndarray | float:
    """A 0-d result as a float, any other as the array."""
    return value[()] if value.ndim == 0 else value


# --------------------------------------------------------------------------------------------
# Hertz sphere (Johnson 1985, section 4.2; E:Hertz_theory)
# --------------------------------------------------------------------------------------------


def hertz_sphere_contact_radius(
    force: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz contact radius a = (3 P R / (4 E*))^(1/3) of a sphere under the load P.

    Parameters
    ----------
    force : float or array
        Normal load P >= 0, N.
    radius : float or array
        Sphere radius R, m.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        a, m (broadcast shape).
    """
    p, r, e = (np.asarray(v, dtype=float) for v in (force, radius, e_star))
    return _out((3 * p * r / (4 * e)) ** (1 / 3))


def hertz_sphere_approach(
    force: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz approach (indentation) delta = a^2 / R of a sphere under the load P.

    Parameters as :func:`hertz_sphere_contact_radius`.

    Returns
    -------
    float or ndarray
        delta, m: how far the rigid flat moves past the undeformed apex.
    """
    a = np.asarray(hertz_sphere_contact_radius(force, radius, e_star))
    return _out(a**2 / np.asarray(radius, dtype=float))


def hertz_sphere_force(
    approach: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz load P = 4/3 E* sqrt(R) delta^(3/2) at the approach delta (0 for delta < 0).

    The law of :func:`asperity.single_asperity.hertz.hertz_normal_load` (E:Hertz_theory).

    Parameters
    ----------
    approach : float or array
        Approach (indentation) delta, m.
    radius : float or array
        Sphere radius R, m.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        P, N.
    """
    return hertz_normal_load(approach, radius, e_star)


def hertz_sphere_peak_pressure(
    force: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz peak (central) pressure p0 = 3 P / (2 pi a^2).

    Parameters as :func:`hertz_sphere_contact_radius`.

    Returns
    -------
    float or ndarray
        p0, Pa.
    """
    a = np.asarray(hertz_sphere_contact_radius(force, radius, e_star))
    return _out(3 * np.asarray(force, dtype=float) / (2 * np.pi * a**2))


def hertz_sphere_mean_pressure(
    force: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz mean contact pressure P / (pi a^2) = 2 p0 / 3.

    Parameters as :func:`hertz_sphere_contact_radius`.

    Returns
    -------
    float or ndarray
        Mean pressure over the contact disc, Pa.
    """
    a = np.asarray(hertz_sphere_contact_radius(force, radius, e_star))
    return _out(np.asarray(force, dtype=float) / (np.pi * a**2))


def hertz_sphere_pressure(
    r: ArrayLike, force: ArrayLike, radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz pressure field p(r) = p0 sqrt(1 - r^2 / a^2) inside the contact, 0 outside.

    Parameters
    ----------
    r : float or array
        Distance from the contact centre, m.
    force, radius, e_star
        As :func:`hertz_sphere_contact_radius` (N, m, Pa).

    Returns
    -------
    float or ndarray
        p, Pa (compressive positive; broadcast shape).
    """
    a = np.asarray(hertz_sphere_contact_radius(force, radius, e_star))
    p0 = np.asarray(hertz_sphere_peak_pressure(force, radius, e_star))
    ratio = np.asarray(r, dtype=float) / a
    return _out(p0 * np.sqrt(np.clip(1 - ratio**2, 0, None)))


# --------------------------------------------------------------------------------------------
# JKR sphere (Johnson, Kendall & Roberts 1971; E:JKR_indent, E:JKR_load)
# Re-exposed from statmodel.jkr: jkr_pull_off_force_load_control (-3/2 pi w R, N),
# jkr_pull_off_force_fixed_grip (-5/6 pi w R, N), jkr_jump_off_distance (the fixed-grip
# jump-off approach -3/4 (pi^2 w^2 R / E*^2)^(1/3), m; E:JKR_delta_min_unloading).
# --------------------------------------------------------------------------------------------


def jkr_sphere_contact_radius(
    force: ArrayLike, radius: ArrayLike, work: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """JKR contact radius under the load P, on the stable load-controlled branch.

    a^3 = R / K (P + 3 pi w R + sqrt(6 pi w R P + (3 pi w R)^2)), K = 4 E* / 3 (Johnson,
    Kendall & Roberts 1971): E:JKR_load solved for a. w = 0 gives Hertz.

    Parameters
    ----------
    force : float or array
        Normal load P, N (negative: tensile), at least the pull-off load -3/2 pi w R.
    radius : float or array
        Sphere radius R, m.
    work : float or array
        Work of adhesion w >= 0, J/m^2.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        a, m; NaN below the pull-off load (no stable state under load control).
    """
    p, r, w, e = (np.asarray(v, dtype=float) for v in (force, radius, work, e_star))
    adhesion = 3 * np.pi * w * r
    with np.errstate(invalid="ignore"):
        root = np.sqrt(2 * adhesion * p + adhesion**2)
        return _out((3 * r / (4 * e) * (p + adhesion + root)) ** (1 / 3))


def jkr_sphere_force(
    contact_radius: ArrayLike, radius: ArrayLike, work: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """JKR load P = 4 E* a^3 / (3 R) - sqrt(8 pi E* a^3 w) at the contact radius a.

    E:JKR_load, by :func:`asperity.single_asperity.jkr.jkr_load_from_radius`.

    Parameters
    ----------
    contact_radius : float or array
        a, m.
    radius : float or array
        Sphere radius R, m.
    work : float or array
        Work of adhesion w, J/m^2.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        P, N (negative: tensile).
    """
    law = np.vectorize(jkr_load_from_radius, otypes=[float])
    return _out(np.asarray(law(contact_radius, radius, work, e_star)))


def jkr_sphere_approach(
    contact_radius: ArrayLike, radius: ArrayLike, work: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """JKR approach delta = a^2 / R - sqrt(2 pi w a / E*) at the contact radius a.

    E:JKR_indent, whose inverse (the stable fixed-grip branch a(delta)) is
    :func:`asperity.single_asperity.jkr.jkr_contact_radius`.

    Parameters
    ----------
    contact_radius : float or array
        a, m.
    radius : float or array
        Sphere radius R, m.
    work : float or array
        Work of adhesion w, J/m^2.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        delta, m (negative: the flat above the undeformed apex).
    """
    a, r, w, e = (np.asarray(v, dtype=float) for v in (contact_radius, radius, work, e_star))
    return _out(a**2 / r - np.sqrt(2 * np.pi * w * a / e))


# --------------------------------------------------------------------------------------------
# Maugis-Dugdale sphere: MaugisDugdale, dimensionless_state, maugis_parameter, re-exposed from
# asperity.single_asperity.maugis_dugdale (Maugis 1992; Johnson & Greenwood 1997).
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# Westergaard sinusoid (Westergaard 1939; Johnson 1985, section 13.2)
# h(x) = g cos(2 pi x / lambda), x from a crest; p* = pi E* g / lambda.
# --------------------------------------------------------------------------------------------


def westergaard_full_contact_pressure(
    amplitude: ArrayLike, wavelength: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """p* = pi E* g / lambda, the mean pressure that closes the last gap (full contact).

    Parameters
    ----------
    amplitude : float or array
        Amplitude g of the sinusoid (half the peak-to-valley height), m.
    wavelength : float or array
        lambda, m.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        p*, Pa.
    """
    g, lam, e = (np.asarray(v, dtype=float) for v in (amplitude, wavelength, e_star))
    return _out(np.pi * e * g / lam)


def westergaard_mean_pressure(
    half_width: ArrayLike, amplitude: ArrayLike, wavelength: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Mean pressure p_mean = p* sin^2(pi a / lambda) at the contact half-width a.

    Parameters
    ----------
    half_width : float or array
        Contact half-width a, m (0 <= a <= lambda / 2).
    amplitude, wavelength, e_star
        As :func:`westergaard_full_contact_pressure` (m, m, Pa).

    Returns
    -------
    float or ndarray
        p_mean, Pa (the load per unit nominal area).
    """
    p_star = westergaard_full_contact_pressure(amplitude, wavelength, e_star)
    a, lam = np.asarray(half_width, dtype=float), np.asarray(wavelength, dtype=float)
    return _out(p_star * np.sin(np.pi * a / lam) ** 2)


def westergaard_contact_half_width(
    mean_pressure: ArrayLike, amplitude: ArrayLike, wavelength: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Contact half-width a = lambda / pi arcsin(sqrt(p_mean / p*)); lambda / 2 from p* on.

    Parameters
    ----------
    mean_pressure : float or array
        p_mean >= 0, Pa.
    amplitude, wavelength, e_star
        As :func:`westergaard_full_contact_pressure` (m, m, Pa).

    Returns
    -------
    float or ndarray
        a, m.
    """
    p_star = westergaard_full_contact_pressure(amplitude, wavelength, e_star)
    ratio = np.clip(np.asarray(mean_pressure, dtype=float) / p_star, 0, 1)
    return _out(np.asarray(wavelength, dtype=float) / np.pi * np.arcsin(np.sqrt(ratio)))


def westergaard_pressure(
    x: ArrayLike,
    mean_pressure: ArrayLike,
    amplitude: ArrayLike,
    wavelength: ArrayLike,
    e_star: ArrayLike,
) -> np.ndarray | float:
    """Pressure field of the sinusoid pressed to p_mean.

    Partial contact (p_mean < p*), s^2 = p_mean / p* = sin^2(pi a / lambda):
    p(x) = 2 p_mean cos(pi x / lambda) sqrt(s^2 - sin^2(pi x / lambda)) / s^2 for |x| < a
    (x measured from a crest, within one period), 0 elsewhere. Full contact (p_mean >= p*):
    p(x) = p_mean + p* cos(2 pi x / lambda). The two agree at p_mean = p*.

    Parameters
    ----------
    x : float or array
        Position from a crest, m (|x| <= lambda / 2).
    mean_pressure : float or array
        p_mean > 0, Pa.
    amplitude, wavelength, e_star
        As :func:`westergaard_full_contact_pressure` (m, m, Pa).

    Returns
    -------
    float or ndarray
        p, Pa (compressive positive; broadcast shape).
    """
    p_star = np.asarray(westergaard_full_contact_pressure(amplitude, wavelength, e_star))
    p_mean = np.asarray(mean_pressure, dtype=float)
    phase = np.pi * np.asarray(x, dtype=float) / np.asarray(wavelength, dtype=float)
    s2 = np.minimum(p_mean / p_star, 1.0)
    partial = 2 * p_mean * np.cos(phase) * np.sqrt(np.clip(s2 - np.sin(phase) ** 2, 0, None)) / s2
    full = p_mean + p_star * np.cos(2 * phase)
    return _out(np.where(p_mean >= p_star, full, partial))


# --- Shear (nu = 1/2) ---------------------------------------------------------------------
def _positive(name: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0):
        raise BemInputError(f"{name}: expected a positive finite number, got {value}")


def mindlin_tangential_stiffness(contact_radius: float, e_star: float) -> float:
    """Full-stick tangential stiffness dT/d delta_T = 4/3 E* a (N/m) of a circular contact."""
    _positive("contact_radius", contact_radius)
    _positive("e_star", e_star)
    return 4.0 / 3.0 * e_star * contact_radius


def _ratio(tangential_force: float, friction_coefficient: float, normal_force: float) -> float:
    _positive("friction_coefficient", friction_coefficient)
    _positive("normal_force", normal_force)
    r = tangential_force / (friction_coefficient * normal_force)
    if not (0.0 <= r <= 1.0):
        raise BemInputError(
            f"tangential_force: expected 0 <= T <= mu P = {friction_coefficient * normal_force} N, "
            f"got {tangential_force}"
        )
    return r


def cattaneo_mindlin_stick_radius(
    tangential_force: float, friction_coefficient: float, normal_force: float, contact_radius: float
) -> float:
    """Stick radius c = a (1 - T / (mu P))^(1/3) (m)."""
    r = _ratio(tangential_force, friction_coefficient, normal_force)
    return contact_radius * (1.0 - r) ** (1.0 / 3.0)


def cattaneo_mindlin_displacement(
    tangential_force: float,
    friction_coefficient: float,
    normal_force: float,
    contact_radius: float,
    e_star: float,
) -> float:
    """Tangential displacement (m) at T (N): 9 mu P / (8 E* a) [1 - (1 - T/(mu P))^(2/3)]."""
    r = _ratio(tangential_force, friction_coefficient, normal_force)
    _positive("contact_radius", contact_radius)
    _positive("e_star", e_star)
    scale = 9.0 * friction_coefficient * normal_force / (8.0 * e_star * contact_radius)
    return scale * (1.0 - (1.0 - r) ** (2.0 / 3.0))


def cattaneo_mindlin_force(
    tangential_displacement: float,
    friction_coefficient: float,
    normal_force: float,
    contact_radius: float,
    e_star: float,
) -> float:
    """Tangential force T (N) at delta_T (m), the inverse of :func:`cattaneo_mindlin_displacement`
    (``mu P`` from the gross-slip displacement ``9 mu P / (8 E* a)`` on)."""
    _positive("friction_coefficient", friction_coefficient)
    _positive("normal_force", normal_force)
    _positive("contact_radius", contact_radius)
    _positive("e_star", e_star)
    if not (math.isfinite(tangential_displacement) and tangential_displacement >= 0):
        raise BemInputError(
            f"tangential_displacement: expected a finite number >= 0 (m), "
            f"got {tangential_displacement}"
        )
    scale = 9.0 * friction_coefficient * normal_force / (8.0 * e_star * contact_radius)
    x = min(tangential_displacement / scale, 1.0)
    return friction_coefficient * normal_force * (1.0 - (1.0 - x) ** 1.5)


@dataclass(frozen=True)
class PCSphereState:
    """Stick state of the Papangelo-Ciavarella sphere in fixed grip (SI units).

    Attributes
    ----------
    contact_radius : float
        a (m), stable root of E:PC_indent (NaN past the fold).
    normal_force : float
        P (N), E:PC_P.
    tangential_force : float
        T = 4/3 E* a delta_T (N), E:PC_T.
    max_tangential_displacement : float
        delta_T^max (m) at this indentation, E:PC_a_min_1 and E:max_disp_PC.
    hertz_sliding_force : float
        T = tau_0 pi a_H^2 (N) of the sliding state, E:Hertz_theory (NaN if tau_0 not given or
        delta <= 0).
    """

    contact_radius: float
    normal_force: float
    tangential_force: float
    max_tangential_displacement: float
    hertz_sliding_force: float


def pc_sphere(
    indentation: float,
    tangential_displacement: float,
    radius: float,
    work_of_adhesion: float,
    e_star: float,
    mode_mixity: float,
    shear_strength: float | None = None,
) -> PCSphereState:
    """The PC sphere at fixed (delta, delta_T): E:PC_indent, E:PC_P, E:PC_T, E:max_disp_PC,
    E:Hertz_theory (from :mod:`asperity.single_asperity.papangelo_ciavarella`)."""
    args = (radius, work_of_adhesion, e_star, mode_mixity)
    a = float(pc.pc_contact_radius(indentation, tangential_displacement, *args))
    p = float(pc.pc_normal_load(indentation, tangential_displacement, *args))
    t = float(pc.pc_tangential_load(indentation, tangential_displacement, *args))
    dt_max = float(pc.pc_max_tangential_displacement(indentation, *args))
    if shear_strength is not None and indentation > 0:
        sliding = shear_strength * math.pi * radius * indentation
    else:
        sliding = math.nan
    return PCSphereState(a, p, t, dt_max, sliding)
