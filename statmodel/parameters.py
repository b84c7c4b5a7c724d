"""Material and roughness inputs of the statistical model, and Tabor's parameter.

All quantities are SI: Pa, J/m^2, m, 1/m^2. The dataclasses are frozen and validate their
fields on construction; a bad value raises :class:`asperity.errors.InputError` naming the field,
the expected range with its reason, and the value found. The ranges are written once, in
:data:`asperity.quantities.QUANTITIES` (shared with the TOML files and the command line): physical,
wide enough for every real interface and narrow enough that the model's arithmetic stays finite
(``e_star = 1e308`` used to exhaust the memory).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, fields

from asperity.errors import InputError
from asperity.quantities import quantity
from asperity.statmodel.checks import StatmodelWarning

#: Below this Tabor parameter the JKR limit no longer applies (paper, Section 2).
TABOR_JKR_LIMIT = 5.0


class TaborWarning(StatmodelWarning):
    """The Tabor parameter is below 5: the JKR-based asperity laws are outside their validity
    (a :class:`~asperity.statmodel.checks.StatmodelWarning` with code ``"tabor"``)."""

    code = "tabor"
    level = "invalid"


#: (class, field) -> the key of its bound in :data:`asperity.quantities.QUANTITIES`, where the
#: range, unit and reason of each are written once (shared with the TOML files and the CLIs).
FIELD_QUANTITIES: dict[tuple[str, str], str] = {
    ("Material", "e_star"): "material.E_star",
    ("Material", "work_of_adhesion"): "material.work_of_adhesion",
    ("Material", "mode_mixity"): "material.mode_mixity",
    ("Material", "shear_strength"): "material.shear_strength",
    ("Material", "equilibrium_distance"): "material.equilibrium_distance",
    ("Roughness", "asperity_density"): "roughness.asperity_density",
    ("Roughness", "summit_radius"): "roughness.summit_radius",
    ("Roughness", "summit_height_rms"): "roughness.summit_height_rms",
}

#: (class, field) -> (lowest, highest, unit, why the range): a view of the shared bounds.
PHYSICAL_BOUNDS: dict[tuple[str, str], tuple[float, float, str, str]] = {
    field: (quantity(key).low, quantity(key).high, quantity(key).unit, quantity(key).why)
    for field, key in FIELD_QUANTITIES.items()
}


def _check_fields(instance: object) -> None:
    """Check (and convert to float) every field of a frozen dataclass against its bound."""
    owner = type(instance).__name__
    for f in fields(instance):  # type: ignore[arg-type]
        bound = quantity(FIELD_QUANTITIES[(owner, f.name)])
        value = bound.check(getattr(instance, f.name), f"{owner}.{f.name}")
        object.__setattr__(instance, f.name, value)


@dataclass(frozen=True)
class Material:
    """Elastic, adhesive and frictional properties of the asperity-flat interface.

    Parameters
    ----------
    e_star : float
        Reduced (contact) modulus E* = E / (1 - nu^2), Pa, in [1e2, 1e13].
    work_of_adhesion : float
        Work of adhesion w, J/m^2, in [0, 10] (w = 0 is the Hertz limit).
    mode_mixity : float
        Mode-mixity parameter lambda of the failure locus E:failure_locus, in [0, 1]
        (0: pure JKR, the tangential work is fully dissipated; 1: Savkoor-Briggs).
    shear_strength : float
        Frictional shear strength tau0 of sliding junctions (E:Hertz_theory), Pa, in [0, 1e11].
    equilibrium_distance : float
        Equilibrium interatomic distance epsilon, m, in [1e-11, 1e-8] (default 0.2 nm).
    """

    e_star: float
    work_of_adhesion: float
    mode_mixity: float
    shear_strength: float
    equilibrium_distance: float = 0.2e-9

    def __post_init__(self) -> None:
        _check_fields(self)


@dataclass(frozen=True)
class Roughness:
    """Greenwood-Williamson / Fuller-Tabor summit statistics of the rough surface.

    Parameters
    ----------
    asperity_density : float
        Number of summits per unit nominal area eta, 1/m^2, in [1e-6, 1e20].
    summit_radius : float
        Common summit radius of curvature R, m, in [1e-10, 1e2].
    summit_height_rms : float
        Standard deviation sigma_s of the (Gaussian) summit heights, m, in [1e-12, 1].
    """

    asperity_density: float
    summit_radius: float
    summit_height_rms: float

    def __post_init__(self) -> None:
        _check_fields(self)


def tabor_parameter(
    summit_radius: float,
    work_of_adhesion: float,
    e_star: float,
    equilibrium_distance: float = 0.2e-9,
    *,
    warn: bool = True,
) -> float:
    """Tabor's parameter mu = (R w^2 / (E*^2 epsilon^3))^(1/3) (paper, Section 2; dimensionless).

    Each argument is bounded as the field of :class:`Material` or :class:`Roughness` it stands
    for (:mod:`asperity.quantities`); a value outside raises ``InputError`` naming it.

    Parameters
    ----------
    summit_radius : float
        Asperity radius R, m.
    work_of_adhesion : float
        Work of adhesion w, J/m^2.
    e_star : float
        Reduced modulus E*, Pa.
    equilibrium_distance : float
        Equilibrium distance epsilon, m.
    warn : bool
        Emit a :class:`TaborWarning` when 0 < mu < 5 (adhesive but outside the JKR limit).
        With w = 0 there is no adhesion and the Hertz limit holds: no warning.

    Returns
    -------
    float
        mu (dimensionless).
    """
    summit_radius, w, e_star, equilibrium_distance = (
        quantity(key).check(value, f"tabor_parameter: {name}")
        for key, name, value in (
            ("roughness.summit_radius", "summit_radius", summit_radius),
            ("material.work_of_adhesion", "work_of_adhesion", work_of_adhesion),
            ("material.E_star", "e_star", e_star),
            ("material.equilibrium_distance", "equilibrium_distance", equilibrium_distance),
        )
    )
    mu = (summit_radius * w**2 / (e_star**2 * equilibrium_distance**3)) ** (1.0 / 3.0)
    if warn and w > 0.0 and mu < TABOR_JKR_LIMIT:
        warnings.warn(
            f"Tabor parameter mu = {mu:.3g} < {TABOR_JKR_LIMIT:g}: the JKR-based asperity laws "
            "(E:JKR_indent, E:PC_indent) are outside their range of validity",
            TaborWarning,
            stacklevel=2,
        )
    return mu


def material_tabor_parameter(
    material: Material, roughness: Roughness, *, warn: bool = True
) -> float:
    """Tabor's parameter of a (material, roughness) pair; see :func:`tabor_parameter`."""
    return tabor_parameter(
        roughness.summit_radius,
        material.work_of_adhesion,
        material.e_star,
        material.equilibrium_distance,
        warn=warn,
    )


def checked_number(
    value: object, accept: Callable[[float], bool], not_a_number: str, refused: str
) -> float:
    """``value`` as a float (SI, as given); an InputError with the message ``not_a_number``
    when it is not a number, ``refused`` when ``accept`` refuses it."""
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(not_a_number) from None
    if not accept(number):
        raise InputError(refused)
    return number


def finite_number(value: object, name: str, unit: str, noun: str) -> float:
    """``value`` as a float; an InputError naming ``name`` when it is not a number (in
    ``unit``, e.g. "N" or "m") or not finite (a ``noun``, e.g. "load")."""
    return checked_number(
        value,
        math.isfinite,
        f"{name}: expected a number in {unit}, got {value!r}",
        f"{name}: expected a finite {noun} in {unit}, got {value!r}",
    )


def is_positive(number: float) -> bool:
    """Finite and > 0."""
    return math.isfinite(number) and number > 0
