"""Closed forms for the shear tests of the BEM (SI units: m, Pa, N, J/m^2); nu = 1/2 throughout.

Cattaneo-Mindlin (Johnson 1985, section 7.2): a Hertz sphere (radius R, reduced modulus E*,
contact radius a under normal load P) under a monotonically increasing tangential load T < mu P
with Coulomb friction mu sticks on a central disc of radius

    c / a = (1 - T / (mu P))^(1/3),

and its tangential displacement (one elastic body against a rigid flat, shear modulus G = E*/4
for nu = 1/2, so (2 - nu) / G = 6 / E*) is

    delta_T = 3 mu P (2 - nu) / (16 G a) [1 - (1 - T / (mu P))^(2/3)]
            = 9 mu P / (8 E* a) [1 - (1 - T / (mu P))^(2/3)],

whose initial slope is the full-stick compliance ``delta_T / T = 3 / (4 E* a)`` (Mindlin), i.e.
E:PC_T ``T = 4/3 E* a delta_T``. The Hertz state itself: ``a^3 = 3 P R / (4 E*)``,
``delta = a^2 / R``, E:Hertz_theory.

The Papangelo-Ciavarella sphere (E:PC_indent, E:PC_P, E:PC_T, E:PC_a_min_1, E:max_disp_PC) and
JKR (E:JKR_indent, E:JKR_load) are those of :mod:`asperity.statmodel.papangelo_ciavarella` and
:mod:`asperity.statmodel.jkr`; :func:`pc_sphere` gathers them for a fixed-grip state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from asperity.bem.errors import BemInputError

__all__ = [
    "PCSphereState",
    "cattaneo_mindlin_displacement",
    "cattaneo_mindlin_force",
    "cattaneo_mindlin_stick_radius",
    "hertz_contact_radius_from_load",
    "mindlin_tangential_stiffness",
    "pc_sphere",
]


def _positive(name: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0):
        raise BemInputError(f"{name}: expected a positive finite number, got {value}")


def hertz_contact_radius_from_load(normal_force: float, radius: float, e_star: float) -> float:
    """Hertz contact radius a (m) of a sphere (radius R, m) under P (N): (3 P R / (4 E*))^(1/3)."""
    _positive("normal_force", normal_force)
    _positive("radius", radius)
    _positive("e_star", e_star)
    return (3.0 * normal_force * radius / (4.0 * e_star)) ** (1.0 / 3.0)


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
    E:Hertz_theory (from :mod:`asperity.statmodel.papangelo_ciavarella`)."""
    from asperity.statmodel import papangelo_ciavarella as pc

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
