"""Plausibility of the predicted contact and friction: plasticity, pressure, static peak, shear.

Each function returns a :class:`asperity.statmodel.checks.Check` (value, threshold, level "ok" /
"warning" / "invalid", message naming the parameters to check) that the job's verdict turns
into a reason. SI units: Pa, m, N, m^2.

Plastic deformation (needs the hardness H of the rough solid, Pa):

- **Plasticity index** ``psi = (E* / H) sqrt(sigma_s / R)`` (J.A. Greenwood and J.B.P.
  Williamson, Proc. R. Soc. Lond. A 295, 300 (1966), "Contact of nominally flat surfaces",
  with ``sigma_s`` the rms summit height and ``R`` the summit radius): below 0.6 the asperities
  deform elastically up to very high nominal pressures, above 1 they flow plastically at
  trivial loads. ``psi > 0.6`` is a warning, ``psi > 1`` invalid (the elastic model does not
  apply).
- **Mean contact pressure** ``p_m = F_z / A_r`` against H. Hertz contact first yields when
  ``p_m = 1.1 Y`` (K.L. Johnson, Contact Mechanics (1985), Section 6.2), and a fully plastic
  indentation carries ``p_m = H ~ 2.8 Y`` (D. Tabor, The Hardness of Metals (1951)): yield starts
  at ``p_m ~ 0.39 H`` (warning) and an elastic mean pressure above H cannot exist (invalid).
  With adhesion, ``F_z`` is the net load, so the compressive pressure in the junctions is
  higher still: the check errs on the lenient side.

Friction beyond experiment and beyond what the solid can carry (the parameters to check are
the frictional shear strength ``tau_0``, the mode mixity ``lambda`` and the modulus ``E*``):

- **Static to sliding friction ratio** ``F_s / F_d``. In the adhesive friction experiments the
  model is built on, the static peak is absent (smooth PDMS spheres, Mergel et al. 2019; Weber
  et al. 2019; the paper, Section 4), or a peak followed by stick-slip cycles about the
  sliding level (rough PDMS on glass, Sahli et al., PNAS 115, 471 (2018); the paper's
  Fig. 6a), and static-to-kinetic ratios of solids in general stay within a few (Rabinowicz,
  Friction and Wear of Materials (1995); Baumberger and Caroli, Adv. Phys. 55, 279 (2006),
  with contact ageing). The job's default (the paper's material, lambda = 0.03) gives
  2.53-2.62. A warning above 10 (an order of magnitude beyond those experiments), **invalid
  above 100**: the sliding interface would then carry 1 % of the force the peak needs, so the
  peak is not a friction of the interface the model describes (its junctions shear at
  ``tau_0`` once sliding) but of the fracture criterion alone.
- **Junction shear at the peak** ``tau_peak / tau_0`` with ``tau_peak = F_s / A_r`` (the real
  area at the peak): sliding junctions carry ``tau_0`` (Hertz sliding, E:Hertz_theory) and the
  experiments find the sliding force proportional to the real area (Sahli et al. 2018; the
  constant-shear-strength line of the paper's Fig. 13). The default job gives 2.43-2.51.
  Warning above 10 (the absolute stress is judged by the next check).
- **Junction shear against the solid's shear limit** ``tau_peak / tau_lim``
  (:func:`shear_limit`): the model is linear elastic, so a junction's mean shear stress must
  stay below the stress at which the solid stops being so. With ``material.hardness`` H:
  ``tau_lim = H / (2.8 sqrt(3))`` (H ~ 2.8 Y, Tabor 1951; von Mises shear yield ``Y / sqrt(3)``).
  Without H, from E*: a **glassy** solid (``E* >=`` :data:`GLASSY_MODULUS` = 100 MPa, above the
  rubbery plateau, 0.1-10 MPa, Ferry 1980) yields in shear at ``tau_y = (Y / E) E* / sqrt(3)``
  with ``Y / E =`` :data:`GLASSY_YIELD_STRAIN` = 0.03, the upper end of glassy polymers' tensile
  yield stress over modulus at room temperature (PMMA 0.022-0.025, PC 0.026, PVC 0.017, PS
  0.014; I.M. Ward and J. Sweeney, Mechanical Properties of Solid Polymers (2013), Ch. 11):
  ``tau_y = 0.0173 E*`` (E* >= E makes it larger still, the lenient side; the pressure
  dependence of polymer yield, ~0.1-0.2 p, Bowden and Jukes 1972, is left out, also lenient).
  A **rubbery** solid (E* below 100 MPa) does not yield; its linear-elastic description ends
  at shear strains of order 1: ``tau_lim = G = E* / 4`` (incompressible, nu = 1/2, so
  E = 3G = 0.75 E*). Warning above 0.5 ``tau_lim`` (a junction's edge traction exceeds its
  mean: JKR's is singular, Mindlin's peaks at the edge, so local yield starts first; glassy
  only), **invalid above** ``tau_lim``. The default job (PDMS, E* = 2.13 MPa) gives 0.61 G.
- **Static friction coefficient** ``mu_s = F_s / F_z``. Above 1 a warning: an adhesive soft
  contact can exceed 1 (smooth PDMS spheres at light loads; the friction is carried by the
  junctions' adhesion, not by the load), so the number alone is no error. **Invalid** above 1
  when the junctions' shear is also past the solid's shear limit: then the friction beyond the
  load is carried by stresses the solid cannot bear.

The thresholds with their reasons are the one table :data:`THRESHOLDS`; the constants below
are read from it. A glassy polymer given PDMS's ``tau_0`` (x3p-2 with E* = 3.5 GPa) gives
F_s/F_d ~ 700, a junction shear of ~70 MPa (~540 tau_0, 1.15 tau_y) and mu_s 2.1-2.2: invalid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity.errors import InputError
from asperity.statmodel.checks import Check, Level, positive_number, positive_numbers, upward_check

__all__ = [
    "FRICTION_COEFFICIENT_LIMIT",
    "FRICTION_RATIO_INVALID",
    "FRICTION_RATIO_LIMIT",
    "GLASSY_MODULUS",
    "GLASSY_YIELD_STRAIN",
    "JUNCTION_SHEAR_LIMIT",
    "PLASTICITY_ELASTIC_LIMIT",
    "PLASTICITY_PLASTIC_LIMIT",
    "THRESHOLDS",
    "YIELD_ONSET_PRESSURE_FRACTION",
    "ShearLimit",
    "Threshold",
    "contact_pressure_check",
    "friction_coefficient_check",
    "junction_shear_check",
    "junction_yield_check",
    "plasticity_index",
    "plasticity_index_check",
    "shear_limit",
    "static_to_sliding_check",
]


@dataclass(frozen=True)
class Threshold:
    """One row of :data:`THRESHOLDS`: where a check's level becomes warning and invalid.

    Attributes
    ----------
    code : str
        The reason code the verdict uses.
    quantity : str
        The value compared (dimensionless).
    warning, invalid : float
        Above ``warning`` the level is "warning", above ``invalid`` "invalid" (``inf``: never).
    reason : str
        Why each threshold lies there.
    """

    code: str
    quantity: str
    warning: float
    invalid: float
    reason: str


#: The thresholds of this module, with their reasons (module doc; one table).
THRESHOLDS: dict[str, Threshold] = {
    t.code: t
    for t in (
        Threshold(
            "plastic_asperities",
            "psi = (E*/H) sqrt(sigma_s/R)",
            0.6,
            1.0,
            "Greenwood-Williamson: elastic below 0.6, plastic at trivial loads above 1",
        ),
        Threshold(
            "contact_pressure_above_yield",
            "max(F_z/A_r) / H",
            1.1 / 2.8,
            1.0,
            "first yield of a Hertz contact at p_m = 1.1 Y with H = 2.8 Y; an elastic mean "
            "pressure above H cannot exist",
        ),
        Threshold(
            "static_friction_ratio",
            "max(F_s/F_d)",
            10.0,
            100.0,
            "experiments show ratios of 1 to a few (2.5 in the paper's own case): 10 is an "
            "order of magnitude beyond them; above 100 the sliding interface carries 1 % of "
            "the peak's force, so the peak is not a friction of that interface",
        ),
        Threshold(
            "junction_shear_at_peak",
            "max(F_s/A_r(peak)) / tau_0",
            10.0,
            math.inf,
            "sliding junctions carry tau_0 (ratio 1 in full sliding; 2.5 at the paper's "
            "peak): 10 is an order of magnitude beyond; the absolute stress is judged by "
            "junction_shear_yield",
        ),
        Threshold(
            "junction_shear_yield",
            "max(F_s/A_r(peak)) / tau_lim",
            0.5,
            1.0,
            "a linear-elastic junction cannot carry a mean shear above the solid's shear "
            "limit (glassy: yield 0.0173 E*; rubbery: G = E*/4; with H: H/(2.8 sqrt 3)); "
            "its edge traction exceeds the mean, so local yield starts above 0.5 of it",
        ),
        Threshold(
            "static_friction_coefficient",
            "max(F_s/F_z)",
            1.0,
            1.0,
            "an adhesive soft contact can exceed 1 (a warning); invalid only when the "
            "junction shear is also past the solid's shear limit (junction_shear_yield)",
        ),
    )
}

#: Greenwood-Williamson: elastic below this plasticity index.
PLASTICITY_ELASTIC_LIMIT = THRESHOLDS["plastic_asperities"].warning
#: Greenwood-Williamson: plastic above this plasticity index.
PLASTICITY_PLASTIC_LIMIT = THRESHOLDS["plastic_asperities"].invalid
#: First yield of a Hertz contact, p_m = 1.1 Y, with H = 2.8 Y: p_m / H.
YIELD_ONSET_PRESSURE_FRACTION = THRESHOLDS["contact_pressure_above_yield"].warning
#: Warning above this static-to-sliding friction ratio.
FRICTION_RATIO_LIMIT = THRESHOLDS["static_friction_ratio"].warning
#: Invalid above this static-to-sliding friction ratio.
FRICTION_RATIO_INVALID = THRESHOLDS["static_friction_ratio"].invalid
#: Warning above this junction shear at the static peak over tau_0.
JUNCTION_SHEAR_LIMIT = THRESHOLDS["junction_shear_at_peak"].warning
#: Static friction coefficient mu_s = F_s/F_z above which a warning (invalid with yield).
FRICTION_COEFFICIENT_LIMIT = THRESHOLDS["static_friction_coefficient"].warning
#: E* (Pa) from which a solid is treated as glassy (it yields); below, rubbery.
GLASSY_MODULUS = 100e6
#: Tensile yield stress over Young's modulus of a glassy polymer (upper end; module doc).
GLASSY_YIELD_STRAIN = 0.03
#: Hardness over the uniaxial yield stress of a fully plastic indentation (Tabor).
HARDNESS_OVER_YIELD = 2.8
#: Shear modulus over E* of an incompressible (rubbery) solid: G = E/3, E = 0.75 E*.
RUBBER_SHEAR_MODULUS_FRACTION = 0.25

GREENWOOD_WILLIAMSON = "J.A. Greenwood, J.B.P. Williamson, Proc. R. Soc. Lond. A 295, 300 (1966)"
JOHNSON_TABOR = (
    "K.L. Johnson, Contact Mechanics (1985) Sec. 6.2; D. Tabor, The Hardness of Metals (1951)"
)
FRICTION_EXPERIMENTS = (
    "Sahli et al., PNAS 115, 471 (2018); Mergel et al. 2019; the paper, Secs. 4-5"
)
SHEAR_LIMIT_SOURCES = (
    "I.M. Ward, J. Sweeney, Mechanical Properties of Solid Polymers (2013) Ch. 11; "
    "D. Tabor, The Hardness of Metals (1951); J.D. Ferry, Viscoelastic Properties of "
    "Polymers (1980)"
)
FRICTION_PARAMETERS = ("material.shear_strength", "material.mode_mixity")


def plasticity_index(
    e_star: float, hardness: float, summit_height_rms: float, summit_radius: float
) -> float:
    """Greenwood and Williamson's plasticity index ``psi = (E* / H) sqrt(sigma_s / R)``.

    Parameters
    ----------
    e_star : float
        E* = E / (1 - nu^2), Pa.
    hardness : float
        H of the rough solid, Pa.
    summit_height_rms : float
        sigma_s, the rms summit height, m.
    summit_radius : float
        R, the mean summit radius, m.

    Returns
    -------
    float
        psi (dimensionless).
    """
    e, h, sigma, radius = positive_numbers(
        "plasticity_index",
        ("e_star", e_star, "Pa"),
        ("hardness", hardness, "Pa"),
        ("summit_height_rms", summit_height_rms, "m"),
        ("summit_radius", summit_radius, "m"),
    )
    return e / h * math.sqrt(sigma / radius)


def plasticity_index_check(
    e_star: float, hardness: float, summit_height_rms: float, summit_radius: float
) -> Check:
    """The plasticity index as a :class:`Check`: warning above 0.6, invalid above 1.

    Parameters are those of :func:`plasticity_index` (Pa, Pa, m, m).

    Returns
    -------
    Check
        Code ``"plastic_asperities"``.
    """
    psi = plasticity_index(e_star, hardness, summit_height_rms, summit_radius)

    def meaning(level: Level) -> str:
        return (
            f"plasticity index psi = (E*/H) sqrt(sigma_s/R) = {psi:.3g}: "
            + {
                "ok": "the asperities deform elastically",
                "warning": "between elastic and plastic asperity contact: the elastic model is "
                "marginal",
                "invalid": "the asperities flow plastically at trivial loads: the elastic model "
                "does not apply",
            }[level]
        )

    return upward_check(
        "plastic_asperities",
        psi,
        PLASTICITY_ELASTIC_LIMIT,
        PLASTICITY_PLASTIC_LIMIT,
        meaning,
        advice="; check material.hardness, material.E_star and the resolution (sigma_s, R)",
        parameters=("material.hardness", "material.E_star"),
        reference=GREENWOOD_WILLIAMSON,
    )


def _positive_array(where: str, name: str, values: object, unit: str) -> np.ndarray:
    """A 1D float array whose values are > 0 and finite, or NaN (not computed at that load)."""
    try:
        array = np.atleast_1d(np.asarray(values, dtype=np.float64))
    except (TypeError, ValueError):
        raise InputError(f"{where}: {name} must be numbers in {unit}, got {values!r}") from None
    bad = ~(np.isnan(array) | (np.isfinite(array) & (array > 0)))
    if array.ndim != 1 or array.size == 0 or np.any(bad):
        raise InputError(
            f"{where}: {name} must be a non-empty 1D sequence of finite values > 0 {unit} "
            f"(NaN: not computed), got {values!r}"
        )
    return array


def _where(index: int) -> str:
    """Which load a largest ratio comes from; -1: computed at none."""
    return f"at load index {index}" if index >= 0 else "(not computed at any load)"


def _largest_ratio(where: str, numerator: object, denominator: object, names, units):
    """Largest element-wise ratio of two positive arrays of one length, and its index.

    Loads where either value is NaN (not computed) are left out; with none left the ratio is
    NaN (index -1), which :func:`grade` turns into a warning.
    """
    top = _positive_array(where, names[0], numerator, units[0])
    bottom = _positive_array(where, names[1], denominator, units[1])
    if top.shape != bottom.shape:
        raise InputError(
            f"{where}: {names[0]} and {names[1]} must have the same length, got "
            f"{top.size} and {bottom.size}"
        )
    ratio = top / bottom
    if np.all(np.isnan(ratio)):
        return math.nan, -1
    index = int(np.nanargmax(ratio))
    return float(ratio[index]), index


def contact_pressure_check(normal_load: object, real_area: object, hardness: float) -> Check:
    """The largest mean contact pressure ``F_z / A_r`` over the loads, against the hardness H.

    Warning above ``0.39 H`` (first yield), invalid above ``H`` (fully plastic); module doc.

    Parameters
    ----------
    normal_load : array_like
        F_z per load, N, > 0.
    real_area : array_like
        A_r at each load, m^2, > 0.
    hardness : float
        H, Pa.

    Returns
    -------
    Check
        Code ``"contact_pressure_above_yield"``; value ``max(F_z / A_r) / H``.
    """
    where = "contact_pressure_check"
    h = positive_number(where, "hardness", hardness, "Pa")
    pressure, index = _largest_ratio(
        where, normal_load, real_area, ("normal_load", "real_area"), ("N", "m^2")
    )
    value = pressure / h
    message = (
        f"mean contact pressure F_z/A_r = {pressure:.3g} Pa {_where(index)} is "
        f"{value:.3g} H (H = {h:.3g} Pa; yield starts at {YIELD_ONSET_PRESSURE_FRACTION:.2f} H, "
        "fully plastic at H)"
    )
    return upward_check(
        "contact_pressure_above_yield",
        value,
        YIELD_ONSET_PRESSURE_FRACTION,
        1.0,
        message,
        advice="; check material.hardness, material.E_star and the loads",
        parameters=("material.hardness", "material.E_star"),
        reference=JOHNSON_TABOR,
    )


def _limits_text(threshold: Threshold) -> str:
    """``"warning above 10, invalid above 100"`` (or the warning alone)."""
    text = f"warning above {threshold.warning:g}"
    if math.isfinite(threshold.invalid) and threshold.invalid != threshold.warning:
        text += f", invalid above {threshold.invalid:g}"
    return text


def _friction_check(code: str, value: float, what: str, index: int) -> Check:
    threshold = THRESHOLDS[code]
    return upward_check(
        code,
        value,
        threshold.warning,
        threshold.invalid,
        f"{what} = {value:.3g} {_where(index)} ({_limits_text(threshold)})",
        advice=": not computed, so its plausibility is unknown"
        if math.isnan(value)
        else ": far beyond adhesive friction experiments; check material.shear_strength "
        "(tau_0) and material.mode_mixity (lambda)",
        parameters=FRICTION_PARAMETERS,
        reference=FRICTION_EXPERIMENTS,
    )


def static_to_sliding_check(static_friction: object, sliding_friction: object) -> Check:
    """The largest static-to-sliding friction ratio ``F_s / F_d`` over the loads.

    Warning above 10, invalid above 100 (:data:`THRESHOLDS`, module doc).

    Parameters
    ----------
    static_friction : array_like
        F_s, the peak of F_x per load, N, > 0.
    sliding_friction : array_like
        F_d, the friction in full sliding at the same loads, N, > 0.

    Returns
    -------
    Check
        Code ``"static_friction_ratio"``.
    """
    ratio, index = _largest_ratio(
        "static_to_sliding_check",
        static_friction,
        sliding_friction,
        ("static_friction", "sliding_friction"),
        ("N", "N"),
    )
    what = "static over sliding friction F_s/F_d"
    return _friction_check("static_friction_ratio", ratio, what, index)


def junction_shear_check(
    static_friction: object, real_area_at_peak: object, shear_strength: float
) -> Check:
    """The largest mean junction shear at the static peak over tau_0 (warning > 10).

    Parameters
    ----------
    static_friction : array_like
        F_s per load, N, > 0.
    real_area_at_peak : array_like
        A_r where F_x peaks, at each load, m^2, > 0.
    shear_strength : float
        tau_0, Pa.

    Returns
    -------
    Check
        Code ``"junction_shear_at_peak"``; value ``max(F_s / A_r) / tau_0``; warning only (the
        absolute stress is judged by :func:`junction_yield_check`).
    """
    where = "junction_shear_check"
    tau0 = positive_number(where, "shear_strength", shear_strength, "Pa")
    shear, index = _largest_ratio(
        where,
        static_friction,
        real_area_at_peak,
        ("static_friction", "real_area_at_peak"),
        ("N", "m^2"),
    )
    what = f"mean junction shear at the peak F_s/A_r over tau_0 ({shear:.3g} Pa / {tau0:.3g} Pa)"
    return _friction_check("junction_shear_at_peak", shear / tau0, what, index)


@dataclass(frozen=True)
class ShearLimit:
    """The shear stress a solid carries while it is linear elastic (:func:`shear_limit`).

    Attributes
    ----------
    stress : float
        tau_lim, Pa.
    kind : str
        "hardness" (from H), "glassy" (yield from E*) or "rubbery" (G from E*).
    text : str
        How it was estimated, for messages.
    """

    stress: float
    kind: str
    text: str


def shear_limit(e_star: float, hardness: float | None = None) -> ShearLimit:
    """The solid's shear limit ``tau_lim`` (module doc): the mean shear stress beyond which a
    junction is no longer linear elastic.

    Parameters
    ----------
    e_star : float
        E* = E / (1 - nu^2), Pa.
    hardness : float, optional
        Indentation hardness H, Pa: when given, ``tau_lim = H / (2.8 sqrt(3))``.

    Returns
    -------
    ShearLimit
        Without H: ``0.03 E* / sqrt(3)`` for E* >= 100 MPa (glassy yield), ``E* / 4`` below
        (rubbery: a shear strain of 1).
    """
    e = positive_number("shear_limit", "e_star", e_star, "Pa")
    if hardness is not None:
        h = positive_number("shear_limit", "hardness", hardness, "Pa")
        stress = h / (HARDNESS_OVER_YIELD * math.sqrt(3.0))
        return ShearLimit(
            stress, "hardness", f"shear yield H/(2.8 sqrt 3) = {stress:.3g} Pa (H = {h:.3g} Pa)"
        )
    if e >= GLASSY_MODULUS:
        stress = GLASSY_YIELD_STRAIN * e / math.sqrt(3.0)
        return ShearLimit(
            stress,
            "glassy",
            f"shear yield of a glassy solid {GLASSY_YIELD_STRAIN:g} E*/sqrt(3) = {stress:.3g} Pa "
            f"(E* = {e:.3g} Pa >= {GLASSY_MODULUS:.3g} Pa)",
        )
    stress = RUBBER_SHEAR_MODULUS_FRACTION * e
    return ShearLimit(
        stress,
        "rubbery",
        f"shear modulus of a rubbery solid G = E*/4 = {stress:.3g} Pa, a shear strain of 1 "
        f"(E* = {e:.3g} Pa < {GLASSY_MODULUS:.3g} Pa)",
    )


def junction_yield_check(
    static_friction: object,
    real_area_at_peak: object,
    e_star: float,
    hardness: float | None = None,
) -> Check:
    """The largest mean junction shear at the static peak against the solid's shear limit.

    Warning above 0.5 ``tau_lim`` (glassy or with H; local yield at the junction edges),
    invalid above ``tau_lim`` (:func:`shear_limit`, :data:`THRESHOLDS`).

    Parameters
    ----------
    static_friction : array_like
        F_s per load, N, > 0 (NaN: not computed).
    real_area_at_peak : array_like
        A_r where F_x peaks, at each load, m^2, > 0.
    e_star : float
        E*, Pa.
    hardness : float, optional
        H, Pa.

    Returns
    -------
    Check
        Code ``"junction_shear_yield"``; value ``max(F_s / A_r) / tau_lim``.
    """
    where = "junction_yield_check"
    limit = shear_limit(e_star, hardness)
    shear, index = _largest_ratio(
        where,
        static_friction,
        real_area_at_peak,
        ("static_friction", "real_area_at_peak"),
        ("N", "m^2"),
    )
    threshold = THRESHOLDS["junction_shear_yield"]
    # a rubber does not yield: only the end of linear elasticity (strain 1) is graded
    warning = threshold.invalid if limit.kind == "rubbery" else threshold.warning
    value = shear / limit.stress
    return upward_check(
        "junction_shear_yield",
        value,
        warning,
        threshold.invalid,
        f"mean junction shear at the peak F_s/A_r = {shear:.3g} Pa {_where(index)} is "
        f"{value:.3g} x the solid's {limit.text}",
        advice=": not computed, so its plausibility is unknown"
        if math.isnan(value)
        else ": the junctions would shear the solid beyond what a linear-elastic model "
        "describes; check material.E_star, material.shear_strength (tau_0) and "
        "material.mode_mixity (lambda)",
        parameters=("material.E_star", *FRICTION_PARAMETERS),
        reference=SHEAR_LIMIT_SOURCES,
    )


def friction_coefficient_check(
    static_friction: object, normal_load: object, junction_yield: Check | None = None
) -> Check:
    """The largest static friction coefficient ``mu_s = F_s / F_z`` over the loads.

    Above 1: a warning (an adhesive soft contact can exceed 1), invalid when ``junction_yield``
    (:func:`junction_yield_check`) is invalid too (:data:`THRESHOLDS`, module doc).

    Parameters
    ----------
    static_friction : array_like
        F_s per load, N, > 0 (NaN: not computed).
    normal_load : array_like
        F_z at the same loads, N, > 0.
    junction_yield : Check, optional
        The junction shear against the solid's shear limit.

    Returns
    -------
    Check
        Code ``"static_friction_coefficient"``; value ``max(F_s / F_z)``.
    """
    mu, index = _largest_ratio(
        "friction_coefficient_check",
        static_friction,
        normal_load,
        ("static_friction", "normal_load"),
        ("N", "N"),
    )
    limit = THRESHOLDS["static_friction_coefficient"].warning
    past_yield = junction_yield is not None and junction_yield.level == "invalid"
    why = (
        ", and the junctions' shear is past the solid's shear limit (junction_shear_yield): "
        "the friction beyond the load rests on stresses the solid cannot bear"
        if past_yield
        else ": possible for an adhesive soft contact (the junctions' adhesion carries it), "
        "beyond the usual range otherwise"
    )
    return upward_check(
        "static_friction_coefficient",
        mu,
        limit,
        limit if past_yield else math.inf,
        f"static friction coefficient mu_s = F_s/F_z = {mu:.3g} {_where(index)} "
        f"(warning above {limit:g}; invalid above it when the junction shear is past the "
        "solid's shear limit)",
        advice=": not computed, so its plausibility is unknown"
        if math.isnan(mu)
        else why + "; check material.shear_strength (tau_0) and material.mode_mixity (lambda)",
        parameters=FRICTION_PARAMETERS,
        reference=FRICTION_EXPERIMENTS,
    )
