"""Hertz contact of a sliding asperity with a uniform frictional shear strength (E:Hertz_theory).

A junction in the sliding state carries the Hertzian normal load and the tangential load
tau0 * pi a^2 of a uniform shear stress tau0 over its Hertzian contact area:

    a = sqrt(R delta),   P = 4/3 E* sqrt(R) delta^(3/2),   T = pi a^2 tau0   (delta >= 0),

and nothing for delta < 0. SI units: m, Pa, N. Also the w -> 0 limit of the JKR laws.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "hertz_contact_radius",
    "hertz_normal_load",
    "hertz_sliding_tangential_load",
]


def hertz_contact_radius(delta: ArrayLike, summit_radius: ArrayLike) -> np.ndarray | float:
    """Hertz contact radius a = sqrt(R delta) of a sliding junction (E:Hertz_theory).

    Parameters
    ----------
    delta : float or array
        Indentation, m (no contact, a = 0, for delta < 0).
    summit_radius : float or array
        R, m.

    Returns
    -------
    float or ndarray
        a, m (broadcast shape; NaN stays NaN).
    """
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    out = np.sqrt(np.asarray(summit_radius, dtype=float) * d)
    return out[()] if out.ndim == 0 else out


def hertz_normal_load(
    delta: ArrayLike, summit_radius: ArrayLike, e_star: ArrayLike
) -> np.ndarray | float:
    """Hertz normal load P = 4/3 E* sqrt(R) delta^(3/2) of a sliding junction (E:Hertz_theory).

    Parameters
    ----------
    delta : float or array
        Indentation, m (P = 0 for delta < 0).
    summit_radius : float or array
        R, m.
    e_star : float or array
        E*, Pa.

    Returns
    -------
    float or ndarray
        P, N (broadcast shape).
    """
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    out = (
        4.0
        / 3.0
        * np.asarray(e_star, dtype=float)
        * np.sqrt(np.asarray(summit_radius, dtype=float))
        * d**1.5
    )
    return out[()] if out.ndim == 0 else out


def hertz_sliding_tangential_load(
    delta: ArrayLike, summit_radius: ArrayLike, shear_strength: ArrayLike
) -> np.ndarray | float:
    """Sliding tangential load T = pi a^2 tau0 = pi R delta tau0 (E:Hertz_theory).

    Parameters
    ----------
    delta : float or array
        Indentation, m (T = 0 for delta < 0).
    summit_radius : float or array
        R, m.
    shear_strength : float or array
        Frictional shear strength tau0, Pa.

    Returns
    -------
    float or ndarray
        T, N (broadcast shape).
    """
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    out = np.pi * np.asarray(summit_radius, dtype=float) * d * np.asarray(shear_strength, float)
    return out[()] if out.ndim == 0 else out
