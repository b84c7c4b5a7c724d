"""The model's shear path and quadrature: how far to shear, and how finely to integrate.

The statistical model's F_x(delta_T) and A_r(delta_T) (E:NewFormulation_Fy, E:NewFormulation_Fx,
E:NewFormulation_Ar; :func:`~asperity.statmodel.shear.shear_curve`) need a path delta_T = 0..max
and a quadrature. Both are chosen here, as functions a notebook user calls (the job's lambda and
friction stages call them too). SI units: m, N, m^2, Pa, J/m^2.

The shear path delta_T = 0..max is given, or found automatically ("auto"): a first curve on a
guessed path gives the model's sliding displacement (the statistical model finds it even
beyond the path), and the path is then set to :data:`SLIDING_MARGIN` times it, so that the steps
resolve the stick part, the static peak and the start of full sliding. When sliding never
completes (lambda = 0) the guessed path is kept.

Quadrature ("model no more than a scene needs"): :func:`choose_quadrature` evaluates the
heaviest load's curve with each setting of :data:`QUADRATURE_LADDER` (coarse to fine) and keeps
the coarsest whose F_x and A_r differ from the next finer one by less than the requested
relative tolerance (relative to the curve's maximum).

The lambda fit's model curve on the stick branch, :func:`model_shear_area`, ends at the static
peak so that its nodes move smoothly with lambda (paper Section 5, Fig 13).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from asperity.statmodel.drive import DriveCurve, drive_curve
from asperity.statmodel.jkr import jkr_zero_load_radius
from asperity.statmodel.parameters import Material, Roughness
from asperity.statmodel.shear import ShearCurve, shear_curve

__all__ = [
    "PEAK_SEARCH_STEPS",
    "QUADRATURE_LADDER",
    "SLIDING_MARGIN",
    "QuadratureChoice",
    "choose_quadrature",
    "initial_displacement_guess",
    "model_drive_curve",
    "model_shear_area",
    "shear_curve_auto",
]

#: Quadrature settings of :func:`~asperity.statmodel.shear.shear_curve` (its ``nodes``
#: Gauss-Legendre nodes per panel and ``panels`` per population range), coarse to fine; the
#: fourth is the model's default.
QUADRATURE_LADDER: tuple[dict[str, float], ...] = (
    {"nodes": 4, "panels": 1},
    {"nodes": 6, "panels": 2},
    {"nodes": 8, "panels": 4},
    {"nodes": 16, "panels": 4},
    {"nodes": 24, "panels": 8},
)

#: The automatic shear path ends at this multiple of the sliding displacement.
SLIDING_MARGIN = 1.25


def initial_displacement_guess(material: Material, roughness: Roughness) -> float:
    """A first guess of the shear path length, m.

    Four times tau0 a0 / E*, with a0 = (9 pi w R^2 / (2 E*))^(1/3) the JKR contact radius at
    zero load (E:JKR_indent, E:JKR_load); at least 1e-7 m. Only a starting point: the path is
    then extended or trimmed by :func:`shear_curve_auto`.
    """
    e = material.e_star
    a0 = float(
        jkr_zero_load_radius(roughness.summit_radius, max(material.work_of_adhesion, 1e-6), e)
    )
    tau = max(material.shear_strength, 1e-3 * e)
    return max(4 * tau * a0 / e, 1e-7)


def shear_curve_auto(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    normal_load: float,
    *,
    max_tangential_displacement: float | None = None,
    steps: int = 201,
    knobs: Mapping[str, float] | None = None,
) -> ShearCurve:
    """:func:`~asperity.statmodel.shear.shear_curve` on a given or automatically found shear path.

    Parameters
    ----------
    material, roughness : Material, Roughness
        Model inputs (SI).
    nominal_area : float
        A_n, m^2.
    normal_load : float
        F_z, N.
    max_tangential_displacement : float or None
        Largest delta_T, m; None finds it (see module docstring).
    steps : int
        Number of delta_T steps, the first at delta_T = 0.
    knobs : mapping, optional
        Accuracy knobs passed to :func:`~asperity.statmodel.shear.shear_curve`.

    Returns
    -------
    ShearCurve
    """
    knobs = dict(knobs or {})

    def run(max_dt: float) -> ShearCurve:
        path = np.linspace(0.0, max_dt, steps)
        return shear_curve(material, roughness, nominal_area, normal_load, path, **knobs)

    if max_tangential_displacement is not None:
        return run(float(max_tangential_displacement))
    max_dt = initial_displacement_guess(material, roughness)
    curve = run(max_dt)
    sliding = float(curve.sliding_displacement)  # found by the model even beyond the path
    if math.isfinite(sliding) and sliding > 0 and not 0.6 * max_dt <= sliding <= max_dt:
        curve = run(SLIDING_MARGIN * sliding)
    return curve


#: delta_T steps of the first curve of :func:`model_shear_area`, which only finds the static peak
#: (the model refines the peak of the continuous F_x(delta_T) between grid points).
PEAK_SEARCH_STEPS = 51


def _peak_search(
    mode_mixity: float,
    normal_load: float,
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    max_tangential_displacement: float | None,
    steps: int,
    knobs: Mapping[str, float],
) -> tuple[Material, ShearCurve]:
    """The material at ``mode_mixity`` and its first curve at F_z (N) on the given or automatic
    path with ``steps`` steps, whose ``static_displacement`` (m) is the static peak delta_s the
    model curves of the lambda fits end or turn at."""
    changed = dataclasses.replace(material, mode_mixity=float(mode_mixity))
    first = shear_curve_auto(
        changed,
        roughness,
        nominal_area,
        normal_load,
        max_tangential_displacement=max_tangential_displacement,
        steps=steps,
        knobs=knobs,
    )
    return changed, first


def model_shear_area(
    mode_mixity: float,
    normal_load: float,
    *,
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    max_tangential_displacement: float | None,
    steps: int,
    knobs: Mapping[str, float],
) -> tuple[np.ndarray, np.ndarray]:
    """Model A_r(F_x) on its stick branch for one lambda and load: (F_x N, A_r m^2).

    A first curve (on the given or automatic path, :data:`PEAK_SEARCH_STEPS` steps) finds the
    static peak delta_s (:func:`~asperity.statmodel.shear.static_friction_peak`, the continuous
    curve's peak); the returned curve has ``steps`` equal steps from delta_T = 0 to delta_s, so its
    last point is the static peak (F_x = static friction) and every node moves smoothly with
    lambda. The lambda fit interpolates this curve at the measured F_x: its objective is then
    smooth in lambda (on a path of fixed nodes in delta_T the interpolation nodes and the
    grid peak jump as lambda moves, and the objective is jagged at the 1e-3 level). Where the
    first curve finds no peak inside its path, that curve is returned.
    """
    changed, first = _peak_search(
        mode_mixity, normal_load, material, roughness, nominal_area,
        max_tangential_displacement, min(steps, PEAK_SEARCH_STEPS), knobs,
    )  # fmt: skip
    peak = float(first.static_displacement)
    path = np.asarray(first.tangential_displacement, dtype=float)
    if not (math.isfinite(peak) and 0 < peak < path[-1]):
        return np.asarray(first.tangential_force, float), np.asarray(first.real_area, float)
    curve = shear_curve(
        changed, roughness, nominal_area, normal_load, np.linspace(0.0, peak, steps), **knobs
    )
    return np.asarray(curve.tangential_force, float), np.asarray(curve.real_area, float)


def model_drive_curve(
    mode_mixity: float,
    normal_load: float,
    *,
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    drive_stiffness: float | None,
    max_tangential_displacement: float | None,
    steps: int,
    knobs: Mapping[str, float],
) -> DriveCurve:
    """The model's F_x for one lambda and load seen from the drive (stiffness k N/m, None:
    rigid): :func:`~asperity.statmodel.drive.drive_curve` (drive = delta_T + F_x / k, stick-slip
    jumps).

    As :func:`model_shear_area`, a first curve finds the static peak delta_s; the curve mapped
    has ``steps`` equal steps from 0 to delta_s and ``steps`` more from there to the path's end
    (the model's full sliding on the automatic path), so its nodes move smoothly with lambda
    (a smooth fit objective) and its fall after the peak, where a jump starts, is resolved.
    """
    changed, first = _peak_search(
        mode_mixity, normal_load, material, roughness, nominal_area,
        max_tangential_displacement, PEAK_SEARCH_STEPS, knobs,
    )  # fmt: skip
    peak = float(first.static_displacement)
    end = float(np.asarray(first.tangential_displacement)[-1])
    curve = first
    if math.isfinite(peak) and 0 < peak < end:
        path = np.concatenate([np.linspace(0.0, peak, steps), np.linspace(peak, end, steps)[1:]])
        curve = shear_curve(changed, roughness, nominal_area, normal_load, path, **knobs)
    k = math.inf if drive_stiffness is None else float(drive_stiffness)
    return drive_curve(curve, k)


@dataclass
class QuadratureChoice:
    """Outcome of the statistical model's refinement check.

    Attributes
    ----------
    knobs : dict
        The chosen accuracy knobs of :func:`~asperity.statmodel.shear.shear_curve`.
    ladder : list of dict
        Settings tried, coarse to fine.
    relative_change : ndarray
        Largest relative change of F_x and A_r from each setting to the next finer one.
    seconds : ndarray
        Time of each setting's curve, s.
    reason : str
        One sentence for the report.
    """

    knobs: dict[str, float]
    ladder: list[dict[str, float]]
    relative_change: np.ndarray
    seconds: np.ndarray
    reason: str


def _ladder_curves(
    case: tuple, ladder: list[dict], max_tangential_displacement: float | None, steps: int
) -> tuple[list[ShearCurve], np.ndarray]:
    """The shear curve of ``case`` (material, roughness, A_n m^2, F_z N) at every setting, and
    the seconds each took; the finest runs first and fixes the shear path of the others."""
    curves, seconds = [], []
    max_dt = max_tangential_displacement
    for knobs in ladder[::-1]:
        t0 = time.perf_counter()
        curve = shear_curve_auto(
            *case, max_tangential_displacement=max_dt, steps=steps, knobs=knobs
        )
        seconds.append(time.perf_counter() - t0)
        if max_dt is None:
            max_dt = float(np.asarray(curve.tangential_displacement)[-1])
        curves.append(curve)
    return curves[::-1], np.array(seconds[::-1])


def _refinement_change(curves: Sequence[ShearCurve]) -> np.ndarray:
    """Largest relative change of F_x and A_r from each curve to the next finer (NaN last)."""
    change = np.full(len(curves), np.nan)
    for i in range(len(curves) - 1):
        worst = 0.0
        for name in ("tangential_force", "real_area"):
            a = np.asarray(getattr(curves[i], name), float)
            b = np.asarray(getattr(curves[i + 1], name), float)
            scale = np.max(np.abs(b)) or 1.0
            worst = max(worst, float(np.max(np.abs(a - b)) / scale))
        change[i] = worst
    return change


def choose_quadrature(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    normal_load: float,
    *,
    tolerance: float,
    max_tangential_displacement: float | None,
    steps: int,
    ladder: Sequence[Mapping[str, float]] = QUADRATURE_LADDER,
) -> QuadratureChoice:
    """The coarsest quadrature setting whose curve agrees with the next finer one.

    Parameters
    ----------
    material, roughness, nominal_area, normal_load
        The heaviest case of the job (SI).
    tolerance : float
        Allowed relative change of F_x and A_r (relative to each curve's maximum).
    max_tangential_displacement, steps
        The shear path (see :func:`shear_curve_auto`).
    ladder : sequence of dict
        Knob settings, coarse to fine.
    """
    settings = [dict(k) for k in ladder]
    if len(settings) == 1:
        return QuadratureChoice(
            settings[0],
            settings,
            np.array([np.nan]),
            np.array([np.nan]),
            "statmodel's default quadrature (no coarser setting offered)",
        )
    case = (material, roughness, nominal_area, normal_load)
    curves, seconds = _ladder_curves(case, settings, max_tangential_displacement, steps)
    change = _refinement_change(curves)
    for i in range(len(settings) - 1):
        if change[i] <= tolerance:
            return QuadratureChoice(
                settings[i],
                settings,
                change,
                seconds,
                f"setting {settings[i] or 'default'}: F_x and A_r change by "
                f"{change[i]:.2g} (relative) on refinement, within "
                f"{tolerance:.2g}; {seconds[i]:.3g} s per curve",
            )
    return QuadratureChoice(
        settings[-1],
        settings,
        change,
        seconds,
        f"no coarser setting met {tolerance:.2g}: the finest ({settings[-1] or 'default'}) is used",
    )
