"""The Pohrt-Popov mesh-dependent adhesion criterion (paper Appendix B, eq:PohrtPopov_G,
eq:max_sigma).

An element in contact may carry tension down to ``-Sigma``; where ``p < -Sigma`` it delaminates
(p -> 0). ``Sigma`` follows from equating the strain energy released by delaminating one
rectangular element, eq:PohrtPopov_G ``G = p^2 chi / (dx dy E*)``, to the work of adhesion w
(eq:max_sigma). This module holds the criterion only; the approach/retraction driver is
:mod:`asperity.bem.normal.adhesion`.
"""

from __future__ import annotations

import math

from asperity.bem.errors import BemInputError

__all__ = ["critical_tension", "pohrt_popov_chi"]


def pohrt_popov_chi(dx: float, dy: float) -> float:
    """The geometric factor chi (m^3) of eq:PohrtPopov_G for a dx x dy element.

    ``chi = (dx^3 + dy^3 - dx^2 D - dy^2 D) / (3 pi)
    + dx dy / (2 pi) [dx ln((D + dy) / (D - dy)) + dy ln((D + dx) / (D - dx))]``,
    ``D = sqrt(dx^2 + dy^2)``: half the integral over the element of its own Love deflection
    under unit pressure with E* = 1, i.e. ``G dx dy = p^2 chi / E*`` is the elastic energy
    released by unloading it (checked so in ``tests/bem/test_bem_hostile_input.py``).

    Parameters
    ----------
    dx, dy : float
        Element sizes (m), positive and finite.

    Returns
    -------
    float
        chi (m^3), symmetric in dx <-> dy; for a square element
        ``chi = ((2 - 2 sqrt 2) / (3 pi) + 2 asinh(1) / pi) dx^3 = 0.473201 dx^3``.
    """
    if not (dx > 0 and dy > 0 and math.isfinite(dx) and math.isfinite(dy)):
        raise BemInputError(f"pohrt_popov_chi: dx and dy must be positive (m), got {dx}, {dy}")
    d = math.hypot(dx, dy)
    return (dx**3 + dy**3 - dx * dx * d - dy * dy * d) / (3.0 * math.pi) + dx * dy / (
        2.0 * math.pi
    ) * (dx * math.log((d + dy) / (d - dy)) + dy * math.log((d + dx) / (d - dx)))


def critical_tension(work_of_adhesion: float, e_star: float, dx: float, dy: float) -> float:
    """Pohrt-Popov critical tension Sigma (Pa), eq:max_sigma: ``sqrt(dx dy w E* / chi)``.

    Parameters
    ----------
    work_of_adhesion : float
        w (J/m^2), >= 0.
    e_star : float
        Reduced modulus E* (Pa), > 0.
    dx, dy : float
        Element sizes (m).

    Returns
    -------
    float
        Sigma (Pa); an element in contact delaminates where p < -Sigma. For a square element
        ``Sigma = sqrt(w E* / (0.47320 dx))``.
    """
    if not (work_of_adhesion >= 0 and math.isfinite(work_of_adhesion)):
        raise BemInputError(
            f"critical_tension: work_of_adhesion must be >= 0 (J/m^2), got {work_of_adhesion}"
        )
    if not (e_star > 0 and math.isfinite(e_star)):
        raise BemInputError(f"critical_tension: e_star must be > 0 (Pa), got {e_star}")
    return math.sqrt(dx * dy * work_of_adhesion * e_star / pohrt_popov_chi(dx, dy))
