"""Papangelo-Ciavarella (PC) adhesive friction model of one asperity in fixed grip (Section 2.2).

For prescribed normal and tangential displacements (delta, delta_T) the stick-state contact radius,
normal and tangential loads follow E:PC_indent, E:PC_P, E:PC_T (nu = 1/2):

    delta = a^2/R - sqrt(k^2 a - c),   k^2 = 2 pi w / E*,   c = 4/9 lambda delta_T^2,
    P = 4 E* a^3 / (3R) - 2 E* a sqrt(k^2 a - c),   T = 4/3 E* a delta_T.

Solution method. g(a) = a^2/R - sqrt(k^2 a - c) - delta is convex on its domain; the stable branch
(d delta / d a > 0) is its larger root, which exists iff delta >= delta_PC^min(delta_T) (the fold).
The fold radius a'_min solves the cubic E:Instable_boundary, k^2 a^3 - c a^2 - (k^2 R / 4)^2 = 0,
itself convex to the right of its only positive root; both are solved by Newton's method started
at a point to the right of the root (monotone convergence, clamped at the fold, so points on the
unstable boundary are returned exactly). delta_T^max(delta) uses E:PC_a_min_1 and E:max_disp_PC.

Edge cases: lambda = 0 gives c = 0 (for any delta_T, infinite included), i.e. JKR exactly, and
delta_T^max = inf; lambda = 1 is the
Savkoor-Briggs model; w = 0 is Hertz for delta_T = 0 and has no stick state for delta_T > 0
(delta_PC^min = +inf, delta_T^max = 0). NaN inputs, or parameters outside R > 0, w >= 0, E* > 0,
lambda in [0, 1], give NaN. SI units: m, Pa, J/m^2, N.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike

from asperity.single_asperity.newton import newton_solver

__all__ = [
    "coupling_term",
    "pc_contact_radius",
    "pc_fold_indentation",
    "pc_fold_radius",
    "pc_fold_radius_kernel",
    "pc_load_from_radius",
    "pc_max_tangential_displacement",
    "pc_max_tangential_displacement_kernel",
    "pc_min_indentation",
    "pc_min_indentation_kernel",
    "pc_normal_load",
    "pc_radius_from_fold",
    "pc_radius_kernel",
    "pc_tangential_load",
    "valid_pc_parameters",
]

_SIG5 = ["float64(float64, float64, float64, float64, float64, float64)"]


@njit(cache=True)
def valid_pc_parameters(
    summit_radius: float, work_of_adhesion: float, e_star: float, mode_mixity: float
) -> bool:
    """R > 0, w >= 0, E* > 0 finite and lambda in [0, 1] (False for NaN)."""
    return (
        0.0 < summit_radius < math.inf
        and 0.0 <= work_of_adhesion < math.inf
        and 0.0 < e_star < math.inf
        and 0.0 <= mode_mixity <= 1.0
    )


@njit(cache=True)
def coupling_term(delta_t: float, mode_mixity: float) -> float:
    """c = 4/9 lambda delta_T^2 (m^2) of E:PC_indent; exactly 0 for lambda = 0, any delta_T.

    delta_T^2 is capped at 1e300 m^2 (c then behaves as infinite: no stick state for lambda > 0)
    so that lambda = 0 with an infinite delta_T never forms 0 * inf.
    """
    return 4.0 / 9.0 * mode_mixity * min(delta_t * delta_t, 1.0e300)


@njit(cache=True)
def _fold_cubic(a: float, params: tuple) -> tuple[float, float]:
    """E:Instable_boundary k^2 a^3 - c a^2 - (k^2 R / 4)^2 and its derivative; params (k2, c, q)."""
    k2, c, q = params
    return k2 * a**3 - c * a * a - q, 3.0 * k2 * a * a - 2.0 * c * a


_solve_fold_cubic = newton_solver(_fold_cubic)


@njit(cache=True)
def _pc_indentation(a: float, params: tuple) -> tuple[float, float]:
    """E:PC_indent a^2/R - sqrt(k^2 a - c) - delta and its derivative; params (k2, c, R, delta)."""
    k2, c, R, delta = params
    s = math.sqrt(max(k2 * a - c, 0.0))
    slope = 2.0 * a / R
    if s > 0.0:
        slope -= 0.5 * k2 / s
    return a * a / R - s - delta, slope


_solve_pc_indentation = newton_solver(_pc_indentation)


@njit(cache=True)
def _fixed_indentation_fold(a: float, params: tuple) -> tuple[float, float]:
    """E:PC_a_min_1 a^3 - delta R a - pi w R^2 / (2 E*) and its derivative; params (delta R, q)."""
    delta_r, q = params
    return a**3 - delta_r * a - q, 3.0 * a * a - delta_r


_solve_fixed_indentation_fold = newton_solver(_fixed_indentation_fold)


@njit(cache=True)
def pc_fold_radius_kernel(
    delta_t: float, summit_radius: float, work_of_adhesion: float, e_star: float, mode_mixity: float
) -> float:
    """a'_min (m): positive root of E:Instable_boundary; +inf where no stick state exists.

    NaN for a NaN delta_T or parameters outside R > 0, w >= 0, E* > 0, lambda in [0, 1].
    """
    if math.isnan(delta_t) or not valid_pc_parameters(
        summit_radius, work_of_adhesion, e_star, mode_mixity
    ):
        return math.nan
    R = summit_radius
    k2 = 2.0 * math.pi * work_of_adhesion / e_star
    c = coupling_term(delta_t, mode_mixity)
    if k2 == 0.0:
        return 0.0 if c == 0.0 else math.inf
    if c > 1.0e100 * k2:
        return math.inf  # a'_min > c / k^2 > 1e100 m: no stick state at any finite indentation
    if c == 0.0:  # JKR fold, closed form: a = t_c^2, t_c = (k R / 4)^(1/3)
        t_c = (math.sqrt(k2) * R / 4.0) ** (1.0 / 3.0)
        return t_c * t_c
    q = (k2 * R / 4.0) ** 2
    a, _, _ = _solve_fold_cubic(c / k2 + (q / k2) ** (1.0 / 3.0), c / k2, (k2, c, q))
    return a


@njit(cache=True)
def pc_fold_indentation(a_f: float, k2: float, c: float, summit_radius: float) -> float:
    """delta_PC^min (m) from the fold radius a_f (m); the JKR closed form -3/4 k t_c when c = 0."""
    if math.isinf(a_f):
        return math.inf
    if c == 0.0:
        k = math.sqrt(k2)
        return -0.75 * k * (k * summit_radius / 4.0) ** (1.0 / 3.0)
    return a_f * a_f / summit_radius - math.sqrt(max(k2 * a_f - c, 0.0))


@njit(cache=True)
def pc_min_indentation_kernel(
    delta_t: float, summit_radius: float, work_of_adhesion: float, e_star: float, mode_mixity: float
) -> float:
    """delta_PC^min (m): E:PC_indent at a'_min; +inf where no stick state exists."""
    a = pc_fold_radius_kernel(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)
    if math.isnan(a):
        return math.nan
    k2 = 2.0 * math.pi * work_of_adhesion / e_star
    c = coupling_term(delta_t, mode_mixity)
    return pc_fold_indentation(a, k2, c, summit_radius)


@njit(cache=True)
def pc_radius_from_fold(
    delta: float, k2: float, c: float, summit_radius: float, a_f: float, delta_f: float
) -> float:
    """Stable root a (m) of E:PC_indent given k^2 = 2 pi w/E*, c = 4/9 lambda delta_T^2, the fold.

    ``a_f``/``delta_f`` are a'_min and delta_PC^min for the same delta_T (precomputed by the caller
    so the statistical integrals solve the cubic once per delta_T). NaN below the fold.
    """
    if math.isnan(delta) or delta < delta_f:
        return math.nan
    if delta == delta_f:
        return a_f
    if math.isinf(delta):
        return math.inf
    R = summit_radius
    # Upper bound: the JKR root (c = 0) of the same delta lies to the right of the PC root, and
    # t0 = (R|delta|)^(1/4) + (k R)^(1/3) lies to the right of the JKR root.
    t = (R * abs(delta)) ** 0.25 + (math.sqrt(k2) * R) ** (1.0 / 3.0)
    a = t * t
    if a < a_f:
        a = a_f
    a, _, _ = _solve_pc_indentation(a, a_f, (k2, c, R, delta))
    return a


@njit(cache=True)
def pc_radius_kernel(
    delta: float,
    delta_t: float,
    summit_radius: float,
    work_of_adhesion: float,
    e_star: float,
    mode_mixity: float,
) -> float:
    """Stable-branch contact radius a (m) of E:PC_indent; NaN where no stable root exists."""
    if math.isnan(delta) or math.isnan(delta_t):
        return math.nan
    R = summit_radius
    k2 = 2.0 * math.pi * work_of_adhesion / e_star
    c = coupling_term(delta_t, mode_mixity)
    a_f = pc_fold_radius_kernel(delta_t, R, work_of_adhesion, e_star, mode_mixity)
    if math.isinf(a_f) or math.isnan(a_f):
        return math.nan
    delta_f = pc_fold_indentation(a_f, k2, c, R)
    return pc_radius_from_fold(delta, k2, c, R, a_f, delta_f)


@njit(cache=True)
def pc_load_from_radius(
    a: float,
    delta_t: float,
    summit_radius: float,
    work_of_adhesion: float,
    e_star: float,
    mode_mixity: float,
) -> float:
    """E:PC_P: normal load P (N) at contact radius a (m) and tangential displacement delta_t (m)."""
    if math.isnan(a):
        return math.nan
    s2 = 8.0 * math.pi * e_star * a**3 * work_of_adhesion - 4.0 * (e_star * a) ** 2 * coupling_term(
        delta_t, mode_mixity
    )
    return 4.0 * e_star * a**3 / (3.0 * summit_radius) - math.sqrt(max(s2, 0.0))


@njit(cache=True)
def pc_max_tangential_displacement_kernel(
    delta: float, summit_radius: float, work_of_adhesion: float, e_star: float, mode_mixity: float
) -> float:
    """delta_T^max (m) from E:PC_a_min_1 and E:max_disp_PC; NaN below the JKR jump-off.

    Rounded down to the last delta_T (within a few ulps) at which E:PC_indent has its stable root.
    """
    if math.isnan(delta) or not valid_pc_parameters(
        summit_radius, work_of_adhesion, e_star, mode_mixity
    ):
        return math.nan
    R = summit_radius
    k2 = 2.0 * math.pi * work_of_adhesion / e_star
    t_c = (math.sqrt(k2) * R / 4.0) ** (1.0 / 3.0)
    delta_off = -0.75 * math.sqrt(k2) * t_c
    if delta < delta_off:
        return math.nan
    if mode_mixity == 0.0 or math.isinf(delta):
        return math.inf
    q = k2 * R * R / 4.0  # pi w R^2 / (2 E*)
    start = math.sqrt(max(delta, 0.0) * R) + q ** (1.0 / 3.0)
    a, _, _ = _solve_fixed_indentation_fold(start, -math.inf, (delta * R, q))
    gap = a * a / R - delta
    bracket = k2 * a - gap * gap
    if bracket <= 0.0:
        return 0.0
    dt_max = math.sqrt(9.0 / (4.0 * mode_mixity) * bracket)
    # The fold at fixed delta (E:PC_a_min_1) and at fixed delta_T (E:Instable_boundary) are two
    # round-offs of the same curve: step delta_T^max down (a few ulps) until the stick state of
    # E:PC_indent provably exists there, so that delta_T^max is a stick point, never one past.
    step = 2.220446049250313e-16 * dt_max
    for _ in range(100):
        if pc_min_indentation_kernel(dt_max, R, work_of_adhesion, e_star, mode_mixity) <= delta:
            break
        dt_max -= step
        step *= 2.0
    return dt_max


@vectorize(_SIG5, cache=True)
def _pc_radius_ufunc(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity):
    return pc_radius_kernel(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


@vectorize(_SIG5, cache=True)
def _pc_load_ufunc(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity):
    a = pc_radius_kernel(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)
    return pc_load_from_radius(a, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


@vectorize(_SIG5, cache=True)
def _pc_tangential_ufunc(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity):
    a = pc_radius_kernel(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)
    return 4.0 / 3.0 * e_star * a * delta_t


_SIG4 = ["float64(float64, float64, float64, float64, float64)"]


@vectorize(_SIG4, cache=True)
def _pc_fold_radius_ufunc(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity):
    return pc_fold_radius_kernel(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


@vectorize(_SIG4, cache=True)
def _pc_min_indentation_ufunc(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity):
    return pc_min_indentation_kernel(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


@vectorize(_SIG4, cache=True)
def _pc_dt_max_ufunc(delta, summit_radius, work_of_adhesion, e_star, mode_mixity):
    return pc_max_tangential_displacement_kernel(
        delta, summit_radius, work_of_adhesion, e_star, mode_mixity
    )


def pc_contact_radius(
    delta: ArrayLike,
    delta_t: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Stick-state contact radius a (m), stable root of E:PC_indent.

    Parameters
    ----------
    delta : float or array
        Normal indentation delta, m.
    delta_t : float or array
        Tangential displacement delta_T, m (the model depends on delta_T^2).
    summit_radius : float or array
        R, m.
    work_of_adhesion : float or array
        w, J/m^2.
    e_star : float or array
        E*, Pa.
    mode_mixity : float or array
        lambda in [0, 1].

    Returns
    -------
    float or ndarray
        a, m; NaN where delta < delta_PC^min(delta_T) (no stick state: the junction slides or
        separates, see :mod:`statmodel.status_map`).
    """
    return _pc_radius_ufunc(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


def pc_normal_load(
    delta: ArrayLike,
    delta_t: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Stick-state normal load P (N), E:PC_P at the stable root; parameters as pc_contact_radius."""
    return _pc_load_ufunc(delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


def pc_tangential_load(
    delta: ArrayLike,
    delta_t: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Stick-state tangential load T = 4/3 E* a delta_T (N), E:PC_T; parameters as above."""
    return _pc_tangential_ufunc(
        delta, delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity
    )


def pc_fold_radius(
    delta_t: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Contact radius a'_min (m) on the unstable boundary for a given delta_T (E:Instable_boundary).

    +inf where no stick state exists at all (w = 0 with lambda delta_T^2 > 0).
    """
    return _pc_fold_radius_ufunc(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


def pc_min_indentation(
    delta_t: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Minimum indentation delta_PC^min(delta_T) (m) of the stick state (E:Instable_boundary).

    E:PC_indent evaluated at a'_min. Equals delta_JKR^unloading at delta_T = 0 or lambda = 0,
    increases with delta_T otherwise; +inf where no stick state exists (w = 0, delta_T > 0).
    """
    return _pc_min_indentation_ufunc(delta_t, summit_radius, work_of_adhesion, e_star, mode_mixity)


def pc_max_tangential_displacement(
    delta: ArrayLike,
    summit_radius: ArrayLike,
    work_of_adhesion: ArrayLike,
    e_star: ArrayLike,
    mode_mixity: ArrayLike,
) -> np.ndarray | float:
    """Largest tangential displacement delta_T^max (m) of the stick state at fixed delta.

    a_min from the cubic E:PC_a_min_1, then E:max_disp_PC, rounded down by a few ulps where
    needed so that the stick state exists at delta_T^max itself (pc_contact_radius is finite
    there). Returns +inf for lambda = 0 (pure JKR: no shear-induced instability) and NaN for
    delta < delta_JKR^unloading (no stable contact even without shear).
    """
    return _pc_dt_max_ufunc(delta, summit_radius, work_of_adhesion, e_star, mode_mixity)
