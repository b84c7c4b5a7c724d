"""JKR theory of a single spherical asperity on a rigid flat (paper, Section 2.1).

Fixed-grip (prescribed indentation) stable branch of E:JKR_indent / E:JKR_load and the
jump-off-contact distance (E:JKR_delta_min_unloading). SI units: m, Pa, J/m^2, N. (Wu's
jump-to-contact distance, E:JKR_delta_min_loading, with the Tabor range it needs, is the
statistical model's: :func:`asperity.statmodel.jkr.jkr_jump_in_distance`.)

Solution method: with a = t^2, E:JKR_indent reads f(t) = t^4/R - k t - delta = 0 with
k = sqrt(2 pi w / E*). f is convex for t > 0; the stable branch (d delta / d a > 0) is the larger
root, t >= t_c = (k R / 4)^(1/3), and exists iff delta >= delta_JKR^unloading = -3/4 k t_c.
Newton's method started to the right of that root (t0 = (R|delta|)^(1/4) + (k R)^(1/3), where
f(t0) >= 0) decreases monotonically onto it; iterates are clamped at t_c so points on the fold are
exact. The scalar kernels are numba ``@njit(cache=True)`` and the public functions are numba
ufuncs (scalars or broadcast arrays).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike

from asperity.single_asperity.newton import newton_solver

__all__ = [
    "jkr_contact_radius",
    "jkr_jump_off_distance",
    "jkr_jump_off_kernel",
    "jkr_load_from_radius",
    "jkr_normal_load",
    "jkr_pull_off_force_fixed_grip",
    "jkr_pull_off_force_load_control",
    "jkr_radius_kernel",
    "jkr_zero_load_radius",
]

_SIG3 = ["float64(float64, float64, float64, float64)"]


@njit(cache=True)
def _jkr_k(work_of_adhesion: float, e_star: float) -> float:
    return math.sqrt(2.0 * math.pi * work_of_adhesion / e_star)


@njit(cache=True)
def _valid_parameters(summit_radius: float, work_of_adhesion: float, e_star: float) -> bool:
    """R > 0, w >= 0, E* > 0, all finite (False for NaN)."""
    return (
        0.0 < summit_radius < math.inf
        and 0.0 <= work_of_adhesion < math.inf
        and 0.0 < e_star < math.inf
    )


@njit(cache=True)
def jkr_jump_off_kernel(summit_radius: float, work_of_adhesion: float, e_star: float) -> float:
    """delta_JKR^unloading = -3/4 k t_c (m), identical to -3/4 pi^(2/3) mu epsilon."""
    if not _valid_parameters(summit_radius, work_of_adhesion, e_star):
        return math.nan
    k = _jkr_k(work_of_adhesion, e_star)
    t_c = (k * summit_radius / 4.0) ** (1.0 / 3.0)
    return -0.75 * k * t_c


@njit(cache=True)
def _jkr_indentation(t: float, params: tuple) -> tuple[float, float]:
    """E:JKR_indent in t = sqrt(a): t^4/R - k t - delta and its derivative; params (k, R, delta)."""
    k, R, delta = params
    return t**4 / R - k * t - delta, 4.0 * t**3 / R - k


_solve_jkr_indentation = newton_solver(_jkr_indentation)


@njit(cache=True)
def jkr_radius_kernel(
    delta: float, summit_radius: float, work_of_adhesion: float, e_star: float
) -> float:
    """Stable-branch contact radius a (m) of E:JKR_indent; NaN below the jump-off indentation."""
    if math.isnan(delta) or not _valid_parameters(summit_radius, work_of_adhesion, e_star):
        return math.nan
    R = summit_radius
    k = _jkr_k(work_of_adhesion, e_star)
    t_c = (k * R / 4.0) ** (1.0 / 3.0)
    delta_off = -0.75 * k * t_c
    if delta < delta_off:
        return math.nan
    if delta == delta_off:
        return t_c * t_c
    if math.isinf(delta):
        return math.inf
    start = (R * abs(delta)) ** 0.25 + (k * R) ** (1.0 / 3.0)
    t, _, _ = _solve_jkr_indentation(start, t_c, (k, R, delta))
    return t * t


@njit(cache=True)
def jkr_load_from_radius(
    a: float, summit_radius: float, work_of_adhesion: float, e_star: float
) -> float:
    """E:JKR_load: P = 4 E* a^3 / (3 R) - sqrt(8 pi E* a^3 w) (N) for a contact radius a (m)."""
    if math.isnan(a):
        return math.nan
    return 4.0 * e_star * a**3 / (3.0 * summit_radius) - math.sqrt(
        8.0 * math.pi * e_star * a**3 * work_of_adhesion
    )


@vectorize(_SIG3, cache=True)
def _jkr_radius_ufunc(delta, summit_radius, work_of_adhesion, e_star):
    return jkr_radius_kernel(delta, summit_radius, work_of_adhesion, e_star)


@vectorize(_SIG3, cache=True)
def _jkr_load_ufunc(delta, summit_radius, work_of_adhesion, e_star):
    a = jkr_radius_kernel(delta, summit_radius, work_of_adhesion, e_star)
    return jkr_load_from_radius(a, summit_radius, work_of_adhesion, e_star)


def jkr_contact_radius(
    delta: ArrayLike, summit_radius: ArrayLike, work_of_adhesion: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Contact radius a (m) on the stable fixed-grip JKR branch (E:JKR_indent).

    Parameters
    ----------
    delta : float or array
        Indentation delta, m (negative: the flat is above the undeformed summit).
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.
    e_star : float or array
        E*, Pa.

    Returns
    -------
    float or ndarray
        a, m (broadcast shape); NaN where delta < delta_JKR^unloading (no stable state), where
        delta is NaN, and for parameters outside R > 0, w >= 0, E* > 0.
    """
    return _jkr_radius_ufunc(delta, summit_radius, work_of_adhesion, e_star)


def jkr_normal_load(
    delta: ArrayLike, summit_radius: ArrayLike, work_of_adhesion: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Normal load P (N) on the stable fixed-grip JKR branch (E:JKR_load at a from E:JKR_indent).

    Parameters as :func:`jkr_contact_radius`. P is negative (tensile) at small indentations and
    NaN below the jump-off indentation.
    """
    return _jkr_load_ufunc(delta, summit_radius, work_of_adhesion, e_star)


@vectorize(["float64(float64, float64, float64)"], cache=True)
def _jkr_jump_off_ufunc(summit_radius, work_of_adhesion, e_star):
    return jkr_jump_off_kernel(summit_radius, work_of_adhesion, e_star)


def jkr_jump_off_distance(
    summit_radius: ArrayLike, work_of_adhesion: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Jump-off-contact indentation delta_JKR^unloading (m, <= 0), E:JKR_delta_min_unloading.

    Equal to -3/4 pi^(2/3) mu epsilon = -3/4 pi^(2/3) (R w^2 / E*^2)^(1/3): the fold of the
    fixed-grip JKR branch, below which no stable contact exists.

    Parameters
    ----------
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.
    e_star : float or array
        E*, Pa.
    """
    return _jkr_jump_off_ufunc(summit_radius, work_of_adhesion, e_star)


def jkr_zero_load_radius(
    summit_radius: ArrayLike, work_of_adhesion: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """JKR contact radius at zero load, a0 = (9 pi w R^2 / (2 E*))^(1/3) (m).

    E:JKR_load with P = 0: 4 E* a^3 / (3 R) = sqrt(8 pi E* a^3 w).

    Parameters
    ----------
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.
    e_star : float or array
        Reduced modulus E*, Pa.

    Returns
    -------
    float or ndarray
        a0, m.
    """
    r, w, e = (np.asarray(v, dtype=float) for v in (summit_radius, work_of_adhesion, e_star))
    return (9 * np.pi * w * r**2 / (2 * e)) ** (1 / 3) + 0.0


def jkr_pull_off_force_load_control(
    summit_radius: ArrayLike, work_of_adhesion: ArrayLike
) -> np.ndarray | float:
    """JKR pull-off force under load control, -3/2 pi w R (N): the minimum of E:JKR_load over a.

    Parameters
    ----------
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.

    Returns
    -------
    float or ndarray
        Force, N (negative: tensile).
    """
    return -1.5 * np.pi * np.asarray(work_of_adhesion) * np.asarray(summit_radius) + 0.0


def jkr_pull_off_force_fixed_grip(
    summit_radius: ArrayLike, work_of_adhesion: ArrayLike
) -> np.ndarray | float:
    """JKR force at the fixed-grip jump-off point, -5/6 pi w R (N), a = (pi w R^2/(8E*))^(1/3).

    The load where the stable branch of E:JKR_indent ends (delta = delta_JKR^unloading).

    Parameters
    ----------
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.

    Returns
    -------
    float or ndarray
        Force, N (negative: tensile).
    """
    return -5.0 / 6.0 * np.pi * np.asarray(work_of_adhesion) * np.asarray(summit_radius) + 0.0
