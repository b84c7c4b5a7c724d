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

Friction beyond experiment (warnings only; the parameters to check are the frictional shear
strength ``tau_0`` and the mode mixity ``lambda``):

- **Static to sliding friction ratio** ``F_s / F_d``. In the adhesive friction experiments the
  model is built on, the static peak is absent (smooth PDMS spheres, Mergel et al. 2019; Weber
  et al. 2019; the paper, Section 4), or a peak followed by stick-slip cycles about the
  sliding level (rough PDMS on glass, Sahli et al., PNAS 115, 471 (2018); the paper's
  Fig. 6a). The job's default (the paper's material, lambda = 0.03) gives 2.53-2.62.
  Warning above :data:`FRICTION_RATIO_LIMIT` = 10: an order of magnitude beyond those
  experiments and four times the default.
- **Junction shear at the peak** ``tau_peak / tau_0`` with ``tau_peak = F_s / A_r`` (the real
  area at the peak): sliding junctions carry ``tau_0`` (Hertz sliding, E:Hertz_theory) and the
  experiments find the sliding force proportional to the real area (Sahli et al. 2018; the
  constant-shear-strength line of the paper's Fig. 13). The default job gives 2.43-2.51.
  Warning above :data:`JUNCTION_SHEAR_LIMIT` = 10, for the same reason.

The limits of 10 are decisions, with a margin of 4 over the paper's own case; a glassy polymer
given PDMS's ``tau_0`` (x3p-2 with E* = 4 GPa) gives ratios of several hundred.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.errors import InputError
from asperity.statmodel.checks import Check, Level, positive_number, positive_numbers, upward_check

__all__ = [
    "FRICTION_RATIO_LIMIT",
    "JUNCTION_SHEAR_LIMIT",
    "PLASTICITY_ELASTIC_LIMIT",
    "PLASTICITY_PLASTIC_LIMIT",
    "YIELD_ONSET_PRESSURE_FRACTION",
    "contact_pressure_check",
    "junction_shear_check",
    "plasticity_index",
    "plasticity_index_check",
    "static_to_sliding_check",
]

#: Greenwood-Williamson: elastic below this plasticity index.
PLASTICITY_ELASTIC_LIMIT = 0.6
#: Greenwood-Williamson: plastic above this plasticity index.
PLASTICITY_PLASTIC_LIMIT = 1.0
#: First yield of a Hertz contact, p_m = 1.1 Y, with H = 2.8 Y: p_m / H.
YIELD_ONSET_PRESSURE_FRACTION = 1.1 / 2.8
#: Warning above this static-to-sliding friction ratio.
FRICTION_RATIO_LIMIT = 10.0
#: Warning above this junction shear at the static peak over tau_0.
JUNCTION_SHEAR_LIMIT = 10.0

GREENWOOD_WILLIAMSON = "J.A. Greenwood, J.B.P. Williamson, Proc. R. Soc. Lond. A 295, 300 (1966)"
JOHNSON_TABOR = (
    "K.L. Johnson, Contact Mechanics (1985) Sec. 6.2; D. Tabor, The Hardness of Metals (1951)"
)
FRICTION_EXPERIMENTS = (
    "Sahli et al., PNAS 115, 471 (2018); Mergel et al. 2019; the paper, Secs. 4-5"
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


def _friction_check(code: str, value: float, what: str, limit: float, index: int) -> Check:
    return upward_check(
        code,
        value,
        limit,
        math.inf,
        f"{what} = {value:.3g} {_where(index)} (warning above {limit:g})",
        advice=": not computed, so its plausibility is unknown"
        if math.isnan(value)
        else ": far beyond adhesive friction experiments; check material.shear_strength "
        "(tau_0) and material.mode_mixity (lambda)",
        parameters=FRICTION_PARAMETERS,
        reference=FRICTION_EXPERIMENTS,
    )


def static_to_sliding_check(static_friction: object, sliding_friction: object) -> Check:
    """The largest static-to-sliding friction ratio ``F_s / F_d`` over the loads (warning > 10).

    Parameters
    ----------
    static_friction : array_like
        F_s, the peak of F_x per load, N, > 0.
    sliding_friction : array_like
        F_d, the friction in full sliding at the same loads, N, > 0.

    Returns
    -------
    Check
        Code ``"static_friction_ratio"``; warning only (module doc).
    """
    ratio, index = _largest_ratio(
        "static_to_sliding_check",
        static_friction,
        sliding_friction,
        ("static_friction", "sliding_friction"),
        ("N", "N"),
    )
    what = "static over sliding friction F_s/F_d"
    return _friction_check("static_friction_ratio", ratio, what, FRICTION_RATIO_LIMIT, index)


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
        Code ``"junction_shear_at_peak"``; value ``max(F_s / A_r) / tau_0``; warning only.
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
    return _friction_check(
        "junction_shear_at_peak", shear / tau0, what, JUNCTION_SHEAR_LIMIT, index
    )
