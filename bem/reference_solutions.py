"""Reference solutions: the closed forms the BEM is checked against.

Plain functions of SI quantities (m, Pa, N, J/m^2), scalars or broadcast arrays, used by the
tests of :mod:`asperity.bem`, the benchmarks and the documentation examples. Where the paper's
statistical model already holds a law (:mod:`asperity.statmodel.hertz`,
:mod:`asperity.statmodel.jkr`, :mod:`asperity.statmodel.maugis_dugdale`) it is reused here, not
written again.

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
    :mod:`asperity.statmodel.maugis_dugdale` (Maugis 1992, J. Colloid Interface Sci. 150, 243;
    notation of Johnson & Greenwood 1997).
Westergaard sinusoid
    A periodic 1D wavy surface h(x) = g cos(2 pi x / lambda) pressed flat against a rigid
    plane, frictionless, non-adhesive: full-contact pressure p*, mean pressure and contact
    half-width in partial contact, pressure field. Westergaard (1939), J. Appl. Mech. 6, A49;
    Johnson (1985), section 13.2.
Shear
    The tangential solutions (Cattaneo-Mindlin sphere, Papangelo-Ciavarella adhesive sphere)
    are added to this module, in this section, by the shear issue.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from asperity.statmodel.hertz import hertz_normal_load
from asperity.statmodel.jkr import (
    jkr_jump_off_distance,
    jkr_load_from_radius,
    jkr_pull_off_force_fixed_grip,
    jkr_pull_off_force_load_control,
)
from asperity.statmodel.maugis_dugdale import MaugisDugdale, dimensionless_state, maugis_parameter

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

    The law of :func:`asperity.statmodel.hertz.hertz_normal_load` (E:Hertz_theory).

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

    E:JKR_load, by :func:`asperity.statmodel.jkr.jkr_load_from_radius`.

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
    :func:`asperity.statmodel.jkr.jkr_contact_radius`.

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
# asperity.statmodel.maugis_dugdale (Maugis 1992; Johnson & Greenwood 1997).
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
