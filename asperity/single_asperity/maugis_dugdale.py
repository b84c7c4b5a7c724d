"""Maugis-Dugdale adhesive contact of a sphere with a flat: the closed form (reference solution).

Maugis (1992), in the notation of Johnson & Greenwood (1997): K = 4 E* / 3 (Pa), contact radius
a, radius c of the edge of the Dugdale zone (the tension sigma_0 = w / h_0 acts on a < r < c),
m = c / a, and the dimensionless

    A = a / (pi w R^2 / K)^(1/3),  P = F / (pi w R),  Delta = delta / (pi^2 w^2 R / K^2)^(1/3),
    lambda = 2 sigma_0 / (pi w K^2 / R)^(1/3)  (the Maugis parameter, 1.16 x Tabor's mu).

With s = sqrt(m^2 - 1):

    (i)   lambda A^2 / 2 [s + (m^2 - 2) arctan s] + 4 lambda^2 A / 3 [s arctan s - m + 1] = 1
    (ii)  P = A^3 - lambda A^2 [s + m^2 arctan s]
    (iii) Delta = A^2 - 4 lambda A s / 3

(i) is quadratic in A, so the solution is explicit in the parameter m. lambda -> infinity is
JKR (P = A^3 - sqrt(6 A^3), pull-off -3/2), lambda -> 0 is DMT (P = A^3 - 2, pull-off -2).
Some texts write the parameter with E* in place of K: that lambda is (16/9)^(1/3) = 1.21 times
this one.

Units: SI (m, Pa, N, J/m^2) in every function taking dimensional arguments.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

__all__ = [
    "MaugisDugdale",
    "MaugisScales",
    "dimensionless_state",
    "maugis_parameter",
]

#: Largest m the root searches consider (the DMT side: the Dugdale zone far outside the contact).
M_MAX = 1e6


def maugis_parameter(cohesive_stress: float, radius: float, work: float, e_star: float) -> float:
    """lambda = 2 sigma_0 (R / (pi w K^2))^(1/3), K = 4 E* / 3 (dimensionless).

    sigma_0 in Pa, R in m, w in J/m^2, E* in Pa.
    """
    k = 4.0 * e_star / 3.0
    return 2.0 * cohesive_stress * (radius / (math.pi * work * k * k)) ** (1.0 / 3.0)


def _brackets(m: float) -> tuple[float, float]:
    s = math.sqrt(max(m * m - 1.0, 0.0))
    at = math.atan(s)
    return s + (m * m - 2.0) * at, s * at - m + 1.0


def _radius_from_m(m: float, lam: float) -> float:
    """A solving (i) for this m (the positive root of the quadratic)."""
    b1, b2 = _brackets(m)
    alpha = lam * b1 / 2.0
    beta = 4.0 * lam * lam * b2 / 3.0
    if alpha <= 0.0:
        return 1.0 / beta if beta > 0 else math.inf
    return 2.0 / (beta + math.sqrt(beta * beta + 4.0 * alpha))


def _m_from_radius(a_bar: float, lam: float) -> float:
    """m solving (i) for this A (the left side of (i) grows with m from 0 at m = 1)."""

    def residual(m: float) -> float:
        b1, b2 = _brackets(m)
        return lam * a_bar**2 / 2.0 * b1 + 4.0 * lam * lam * a_bar / 3.0 * b2 - 1.0

    hi = 2.0
    while residual(hi) < 0.0 and hi < M_MAX:
        hi *= 2.0
    return brentq(residual, 1.0, hi, xtol=1e-15, rtol=1e-14)


def dimensionless_state(a_bar: float, lam: float) -> tuple[float, float, float]:
    """(m, P, Delta) on the Maugis-Dugdale curve at the dimensionless contact radius A."""
    m = _m_from_radius(a_bar, lam)
    s = math.sqrt(m * m - 1.0)
    p = a_bar**3 - lam * a_bar**2 * (s + m * m * math.atan(s))
    delta = a_bar**2 - 4.0 * lam * a_bar * s / 3.0
    return m, p, delta


class MaugisScales:
    """The Maugis-Dugdale scales of a sphere with ``radius`` R (m), ``e_star`` E* (Pa),
    ``work`` w (J/m^2) and ``adhesion_range`` h_0 (m) (the attributes of the classes that
    inherit them: :class:`MaugisDugdale`, ``statmodel.maugis_rough.MaugisAsperity``)."""

    radius: float
    e_star: float
    work: float
    adhesion_range: float

    @property
    def k(self) -> float:
        """K = 4 E* / 3 (Pa)."""
        return 4.0 * self.e_star / 3.0

    @property
    def lam(self) -> float:
        """The Maugis parameter lambda = 2 sigma_0 (R / (pi w K^2))^(1/3) (dimensionless),
        sigma_0 = w / h_0."""
        return maugis_parameter(
            self.work / self.adhesion_range, self.radius, self.work, self.e_star
        )

    @property
    def length_scale(self) -> float:
        """l = (pi w R^2 / K)^(1/3) (m), the unit of a and c."""
        return (math.pi * self.work * self.radius**2 / self.k) ** (1.0 / 3.0)

    @property
    def force_scale(self) -> float:
        """pi w R (N), the unit of F."""
        return math.pi * self.work * self.radius


@dataclass(frozen=True)
class MaugisDugdale(MaugisScales):
    """A sphere of radius R (m) on a flat, reduced modulus E* (Pa), work of adhesion w (J/m^2)
    and Dugdale range h_0 (m): sigma_0 = w / h_0 (Pa)."""

    radius: float
    e_star: float
    work: float
    adhesion_range: float

    @property
    def approach_scale(self) -> float:
        """(pi^2 w^2 R / K^2)^(1/3) (m), the unit of the approach delta."""
        return (math.pi**2 * self.work**2 * self.radius / self.k**2) ** (1.0 / 3.0)

    def state(self, contact_radius: float) -> dict:
        """Force F (N), approach delta (m) and Dugdale-zone radius c (m) at contact radius a
        (m), eqs. (i)-(iii) of the module docstring."""
        a_bar = contact_radius / self.length_scale
        m, p, delta = dimensionless_state(a_bar, self.lam)
        return {
            "force": p * self.force_scale,
            "approach": delta * self.approach_scale,
            "zone_radius": m * contact_radius,
        }

    def _minimum_force_radius(self) -> float:
        """A at the most tensile force (dimensionless): the pull-off point under load
        control; the loading branch is A above it."""
        lam = self.lam

        def force(log_a: float) -> float:
            return dimensionless_state(math.exp(log_a), lam)[1]

        best = minimize_scalar(
            force,
            bounds=(math.log(1e-4), math.log(10.0)),
            method="bounded",
            options={"xatol": 1e-10},
        )
        return math.exp(best.x)

    def pull_off_force(self) -> float:
        """The most tensile force on the curve (N, negative): -3/2 pi w R for JKR (lambda ->
        infinity), -2 pi w R for DMT (lambda -> 0)."""
        a_min = self._minimum_force_radius()
        return dimensionless_state(a_min, self.lam)[1] * self.force_scale

    def contact_radius(self, force: float) -> float:
        """Contact radius a (m) at force F (N) on the stable branch (dF/da > 0), the loading
        branch for F above the pull-off force; NaN below it."""
        lam = self.lam
        target = force / self.force_scale
        a_lo = self._minimum_force_radius()
        if target < dimensionless_state(a_lo, lam)[1]:
            return math.nan
        a_hi = max(2.0 * a_lo, 1.0)
        while dimensionless_state(a_hi, lam)[1] < target:
            a_hi *= 2.0

        def gap(a_bar: float) -> float:
            return dimensionless_state(a_bar, lam)[1] - target

        return brentq(gap, a_lo, a_hi, xtol=1e-14, rtol=1e-13) * self.length_scale

    def zero_approach(self) -> dict:
        """Contact radius a (m) and force F (N) at delta = 0 (the flat at the undeformed apex),
        on the branch with a > 0: (iii) gives A = 4 lambda s / 3."""
        lam = self.lam

        def residual(log_m1: float) -> float:
            m = 1.0 + math.exp(log_m1)
            s = math.sqrt(m * m - 1.0)
            return _radius_from_m(m, lam) - 4.0 * lam * s / 3.0

        log_m1 = brentq(residual, math.log(1e-12), math.log(M_MAX), xtol=1e-13)
        m = 1.0 + math.exp(log_m1)
        a_bar = _radius_from_m(m, lam)
        _, p, _ = dimensionless_state(a_bar, lam)
        return {"contact_radius": a_bar * self.length_scale, "force": p * self.force_scale}

    def curve(self, radii: np.ndarray) -> np.ndarray:
        """Rows (a, F, delta, c) (m, N, m, m) at the given contact radii (m)."""
        rows = []
        for a in np.asarray(radii, dtype=float):
            st = self.state(float(a))
            rows.append((a, st["force"], st["approach"], st["zone_radius"]))
        return np.array(rows)
