"""Dimensionless status map of one asperity: out of contact / stick / slide (Section 2.3, Fig. 2a).

Scaling (paper, Section 2.3): xi = (E* R / w)^(1/3), delta~ = xi^2 delta / R,
delta_T~ = 2 xi^2 delta_T / (3 R), a~ = xi a / R. The unstable boundary is

    delta~_min^PC = a~^2 - sqrt(2 pi a~ - lambda delta_T~^2),
    a~^3 - lambda / (2 pi) delta_T~^2 a~^2 - pi / 8 = 0   (unique positive root a~),

which starts at the JKR jump-off delta~ = -3/4 pi^(2/3) for delta_T~ = 0. A point is

* stick if delta~ >= delta~_min^PC(delta_T~) (a stable root of E:PC_indent exists),
* slide if 0 <= delta~ < delta~_min^PC (Hertz with shear strength tau0, E:Hertz_theory),
* out of contact otherwise (delta~ < min(0, delta~_min^PC)).

The cubic is solved by Newton's method from a point to the right of the root
(a~0 = lambda delta_T~^2 / (2 pi) + (pi/8)^(1/3), monotone convergence).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize
from numpy.typing import ArrayLike

from asperity.errors import InputError
from asperity.statmodel.newton import newton_solver

#: Status codes returned by :func:`asperity_status`.
OUT_OF_CONTACT = 0
STICK = 1
SLIDE = 2

#: Dimensionless JKR jump-off indentation -3/4 pi^(2/3) (E:JKR_delta_min_unloading).
JUMP_OFF_DIMENSIONLESS = -0.75 * math.pi ** (2.0 / 3.0)


@njit(cache=True)
def _fold_cubic_dimensionless(a: float, params: tuple) -> tuple[float, float]:
    """a~^2 (a~ - b) - pi/8 (E:Instable_boundary, dimensionless) and its slope; params (b, q)."""
    b, q = params
    return a * a * (a - b) - q, 3.0 * a * a - 2.0 * b * a


_solve_fold_dimensionless = newton_solver(_fold_cubic_dimensionless)


@njit(cache=True)
def _fold_radius_dimensionless(delta_t_tilde: float, mode_mixity: float) -> float:
    if math.isnan(delta_t_tilde) or not 0.0 <= mode_mixity <= 1.0:
        return math.nan
    # delta_T~^2 capped at 1e300 so that lambda = 0 with an infinite delta_T~ never forms 0 * inf
    b = mode_mixity * min(delta_t_tilde * delta_t_tilde, 1.0e300) / (2.0 * math.pi)
    if b > 1.0e100:
        return math.inf  # a~ > b > 1e100: no stick state at any finite indentation
    q = math.pi / 8.0
    a, _, _ = _solve_fold_dimensionless(b + q ** (1.0 / 3.0), -math.inf, (b, q))
    return a


@njit(cache=True)
def _min_indentation_dimensionless(delta_t_tilde: float, mode_mixity: float) -> float:
    a = _fold_radius_dimensionless(delta_t_tilde, mode_mixity)
    if math.isnan(a) or math.isinf(a):
        return a
    coupling = mode_mixity * min(delta_t_tilde * delta_t_tilde, 1.0e300)
    return a * a - math.sqrt(max(2.0 * math.pi * a - coupling, 0.0))


@vectorize(["float64(float64, float64)"], cache=True)
def _min_indentation_ufunc(delta_t_tilde, mode_mixity):
    return _min_indentation_dimensionless(delta_t_tilde, mode_mixity)


@vectorize(["float64(float64, float64)"], cache=True)
def _fold_radius_ufunc(delta_t_tilde, mode_mixity):
    return _fold_radius_dimensionless(delta_t_tilde, mode_mixity)


@vectorize(["int64(float64, float64, float64)"], cache=True)
def _status_ufunc(delta_tilde, delta_t_tilde, mode_mixity):
    boundary = _min_indentation_dimensionless(delta_t_tilde, mode_mixity)
    if delta_tilde >= boundary:
        return STICK
    if delta_tilde >= 0.0:
        return SLIDE
    return OUT_OF_CONTACT


def scale_factor(summit_radius: float, work_of_adhesion: float, e_star: float) -> float:
    """xi = (E* R / w)^(1/3) (dimensionless); R in m, w in J/m^2, E* in Pa."""
    return (e_star * summit_radius / work_of_adhesion) ** (1.0 / 3.0)


def to_dimensionless(
    delta: ArrayLike,
    delta_t: ArrayLike,
    summit_radius: float,
    work_of_adhesion: float,
    e_star: float,
) -> tuple[np.ndarray | float, np.ndarray | float]:
    """(delta~, delta_T~) from (delta, delta_T) in m; see the module docstring for the scaling."""
    xi = scale_factor(summit_radius, work_of_adhesion, e_star)
    return (
        xi**2 / summit_radius * np.asarray(delta, dtype=float),
        2.0 * xi**2 / (3.0 * summit_radius) * np.asarray(delta_t, dtype=float),
    )


def from_dimensionless(
    delta_tilde: ArrayLike,
    delta_t_tilde: ArrayLike,
    summit_radius: float,
    work_of_adhesion: float,
    e_star: float,
) -> tuple[np.ndarray | float, np.ndarray | float]:
    """(delta, delta_T) in m from the dimensionless (delta~, delta_T~)."""
    xi = scale_factor(summit_radius, work_of_adhesion, e_star)
    return (
        summit_radius / xi**2 * np.asarray(delta_tilde, dtype=float),
        3.0 * summit_radius / (2.0 * xi**2) * np.asarray(delta_t_tilde, dtype=float),
    )


def dimensionless_fold_radius(
    delta_t_tilde: ArrayLike, mode_mixity: ArrayLike
) -> np.ndarray | float:
    """a~_min: the positive root of a~^3 - lambda/(2 pi) delta_T~^2 a~^2 - pi/8 = 0."""
    return _fold_radius_ufunc(delta_t_tilde, mode_mixity)


def dimensionless_unstable_boundary(
    delta_t_tilde: ArrayLike, mode_mixity: ArrayLike
) -> np.ndarray | float:
    """delta~_min^PC(delta_T~), the stick/non-stick boundary of Fig. 2a (dimensionless)."""
    return _min_indentation_ufunc(delta_t_tilde, mode_mixity)


def asperity_status(
    delta_tilde: ArrayLike, delta_t_tilde: ArrayLike, mode_mixity: ArrayLike
) -> np.ndarray | int:
    """Status code of one asperity at (delta~, delta_T~): OUT_OF_CONTACT, STICK or SLIDE.

    Parameters
    ----------
    delta_tilde, delta_t_tilde : float or array
        Dimensionless normal and tangential displacements (see :func:`to_dimensionless`).
    mode_mixity : float or array
        lambda in [0, 1].

    Returns
    -------
    int or ndarray of int64
        0 (out of contact), 1 (stick), 2 (slide), broadcast shape. Points exactly on the
        unstable boundary are STICK (the fold state exists); with lambda = 0 every point above
        the JKR jump-off sticks, whatever delta_T~ (infinite included).

    Raises
    ------
    ValueError
        NaN in an input, or lambda outside [0, 1].
    """
    args = {"delta_tilde": delta_tilde, "delta_t_tilde": delta_t_tilde, "mode_mixity": mode_mixity}
    for name, value in args.items():
        if np.any(np.isnan(np.asarray(value, dtype=float))):
            raise InputError(
                f"asperity_status: {name} contains NaN (no status for an undefined state)"
            )
    lam = np.asarray(mode_mixity, dtype=float)
    if np.any((lam < 0.0) | (lam > 1.0)):
        raise InputError(f"asperity_status: mode_mixity must lie in [0, 1], got {mode_mixity!r}")
    return _status_ufunc(delta_tilde, delta_t_tilde, mode_mixity)
