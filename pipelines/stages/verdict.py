"""The verdict stage (the last stage): the validity verdict of a job, "valid", "warnings"
or "invalid", with reasons.

Every reason states the number, the threshold and why (:class:`Reason`). A result is
**invalid** when the model is used where its assumptions fail, or when the data it was
calibrated on cannot be right:

* ``area_fraction`` (model or measured A_r/A_n above :data:`MAX_AREA_FRACTION` = 0.15;
  a warning above :data:`WARN_AREA_FRACTION` = 0.10): the model is one of independent
  asperities (Fuller-Tabor / Greenwood, E:Ar_Greenwood), "neglecting the coalescence and
  interaction of neighboring asperities" (paper, Section 3); Section 5 shows that even at the
  few-percent A_r/A_n of Fig 12d such a model underestimates the area because of junction
  coalescence, which the effective resolution absorbs only while junctions stay apart. Beyond
  10-15 % contact the junctions merge into clusters (the BEM picture of Appendix B), and no
  resolution of independent spheres describes them.
* ``adhesion_full_contact`` (Persson-Tosatti: the elastic energy per unit area to flatten the
  map, U_el/A0, below the work of adhesion w; :func:`asperity.statmodel.regimes.adhesion_regime`
  on the levelled map): the interface snaps into nearly full contact at any load, so the
  asperity model and a loading-branch BEM do not apply. It takes the place of the
  ``area_fraction`` reason (the model's large A_r/A_n is then a symptom of this regime, not
  junction coalescence); Tabor's parameter and Pastewka and Robbins's stickiness are stated
  beside it (:func:`check_adhesion_regime`).
* ``tabor`` (mu < 5): the JKR asperity laws (E:JKR_indent, E:PC_indent) hold for
  Tabor parameters above 5 (paper, Section 2).
* ``misfit`` (rms ln(A_model / A_reference) above :data:`MAX_MISFIT` = 0.7, a factor 2;
  a warning above :data:`WARN_MISFIT` = 0.2), and ``resolution_at_edge`` (the least misfit
  at the first or last stride of the scan: a warning alone, invalid with a misfit above
  :data:`WARN_MISFIT`: no resolution of the scan fits, the optimum is not bracketed). Its
  message gives the direction the data point to (:func:`edge_direction`): beyond the end
  (a finer measurement, or coarser strides), or between the end stride and its neighbour
  when the model's mean ln(A_model / A_reference) changes sign between them.
* ``lambda_at_bound`` / ``lambda_uncertainty``: the fitted lambda lies on a bound of the
  search interval (the bound chose it, not the data) or its uncertainty is not finite.
* ``lambda_sources_disagree`` (a warning): lambda fitted to the A_r(F_x) curves alone and to
  the friction tests F_x(drive) alone differ by more than two combined standard deviations
  (:func:`asperity.statmodel.lambda_fit_friction.compare_sources`): the two measurements,
  through this model and this loading-system stiffness, do not agree on lambda
  (:func:`check_lambda_sources`).
* ``measured_area_above_nominal``: a measured A_r > A_n.
* ``no_full_sliding``: a shear curve did not reach full sliding (its sliding friction is
  not a result), or reached no finite sliding displacement within the range (the separation
  solve stopped before full sliding, or junctions never slide): the curve does not show the
  sliding it reports.
* ``bem_stall``: a BEM solve did not converge (read from the BEM stage's convergence fields).
* ``shape_scale``: the shape fit's factor c of a measured curve outside [0.50, 2.01]
  (|ln c| > :data:`MAX_MISFIT`; a warning beyond :data:`WARN_MISFIT`, [0.82, 1.22]):
  :func:`check_shape_scale`.
* ``measured_area_scale`` / ``measured_area_offset`` (warnings): a measured curve's level 10 %
  or more from the model's at F_x = 0 beyond the model's own uncertainty (an area calibration
  error or an additive offset, which the shape cannot tell apart: lambda's interval is
  widened over both readings), and an additive offset that fits better than a scale factor:
  :func:`check_calibration` (:mod:`asperity.pipelines.stages.calibration_checks`).
* ``plastic_asperities`` / ``contact_pressure_above_yield`` (with ``material.hardness``): the
  plasticity index above 1 (a warning above 0.6), the mean contact pressure above H (a warning
  above 0.39 H): :func:`check_hardness`, thresholds in :mod:`asperity.statmodel.plausibility`.
* ``static_friction_ratio`` (F_s/F_d above 100; a warning above 10), ``junction_shear_yield``
  (the mean junction shear at the static peak above the solid's shear limit: glassy yield
  0.0173 E*, rubbery G = E*/4, or H/(2.8 sqrt 3); a warning above half of it) and
  ``static_friction_coefficient`` (mu_s = F_s/F_z above 1 with the junction shear past that
  limit; a warning above 1 otherwise): :func:`check_friction_plausibility`, the thresholds
  and their reasons in :data:`asperity.statmodel.plausibility.THRESHOLDS`.
* ``bem_adhesive_range`` (:func:`check_bem_adhesive_range`): in the full-contact regime, or
  where the adhesive BEM's A_r/A_n reaches 0.9, the adhesive BEM column is decided by its
  Maugis-Dugdale range h_0 (grid-sized with ``"auto"``), not by the roughness; invalid when
  the effective resolution was chosen against the BEM, else a warning. Its cells are marked
  ``range-decided:`` (:func:`asperity.pipelines.report.verdict_marks.mark_adhesive_bem`).

The adhesion regime is also judged before the BEM stage runs (:func:`preview_adhesion_regime`,
the stage's :class:`~asperity.pipelines.engine.stage.Preview`): one terminal line and the
preliminary reason stored in ``results.h5`` (file attribute :data:`PREVIEW_ATTRIBUTE`).

Warnings: ``measured_load_unmatched`` (a measured curve at a load more than
:data:`LOAD_MATCH` from every configured load; the job refuses such a curve before any stage,
:func:`asperity.pipelines.measured.check_curve_loads`), ``bem_grid`` (the grid check found no
converged stride), ``lambda_fit`` (the optimiser did not report success),
``surface_preparation`` (the preparation record's warnings), ``junction_shear_at_peak`` (the
junction shear at the peak over tau_0 above 10, naming tau_0 and lambda:
:func:`check_friction_plausibility`), ``profile_isotropy`` (always
for a line profile as input: its statistics and the maps synthesised from it assume an
isotropic surface, which one line cannot check).

The shear BEM (``[bem_shear]``, :func:`check_bem_shear`; thresholds and reasons in
:data:`asperity.pipelines.stages.bem_shear.SHEAR_THRESHOLDS`): ``bem_shear_stall`` (a shear
step did not converge: invalid, and the exit status says it as for any solver),
``bem_shear_no_sliding`` (junctions still stick at the end of the path on the grid used: its
sliding friction is not a result; a warning), ``bem_shear_model_misfit`` (the model's static
friction more than a factor 2 from the BEM's beyond the BEM's grid error; a warning).

The exit status (:func:`exit_status`): 1 (:attr:`ExitStatus.NOT_CONVERGED`) when a solver
did not converge, else 3 (:attr:`ExitStatus.INVALID_RESULT`) when the verdict is invalid,
else 0. Non-convergence takes precedence: it is the first thing to fix (more iterations, a
cleaner map), and the verdict lists it among its reasons anyway.

A warning of the BEM reference's boundary: ``bem_edge_mismatch``, a periodic BEM solve of a
map whose opposite edges do not meet (the seam's rms height jump over the rms height above
:data:`~asperity.bem.reference.grid_refinement.EDGE_MISMATCH_LIMIT` = 0.5 adds a cliff along two
edges of the reference contact; :func:`check_edge_mismatch`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from asperity.bem.reference.grid_refinement import EDGE_MISMATCH_LIMIT
from asperity.errors import ExitStatus
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines import measured
from asperity.pipelines.engine.stage import Preview, PreviewNote, Stage, StageContext
from asperity.pipelines.stages import calibration_checks
from asperity.pipelines.stages import early_verdict as early
from asperity.pipelines.stages.bem import BEM, BemReference
from asperity.pipelines.stages.bem_shear import BEM_SHEAR, SHEAR_THRESHOLDS, BemShearComparison
from asperity.pipelines.stages.friction import (
    FRICTION,
    MODE_MIXITY,
    FrictionPrediction,
    ModeMixityChoice,
)
from asperity.pipelines.stages.psd import complete_map
from asperity.pipelines.stages.statistical_model import STATISTICAL_MODEL, ResolutionChoice
from asperity.pipelines.stages.surface import SCAN, SURFACE, LevelledSurface
from asperity.statmodel import Material, Roughness, plausibility
from asperity.statmodel.checks import Check
from asperity.statmodel.regimes import AdhesionRegime, adhesion_regime
from asperity.validity import Finding

#: A_r/A_n above which an independent-asperity model cannot mean anything (junctions merge).
MAX_AREA_FRACTION = 0.15
#: A_r/A_n above which junction coalescence starts to matter (a warning).
WARN_AREA_FRACTION = 0.10
#: Tabor parameter below which the JKR asperity laws do not apply (paper, Section 2).
MIN_TABOR_PARAMETER = 5.0
#: rms ln(A_model/A_reference) above which the model misses the reference by a factor > 2.
MAX_MISFIT = 0.7
#: rms ln ratio above which the fit is poor (22 %): a warning.
WARN_MISFIT = 0.2
#: Relative difference within which a measured normal load matches a configured one.
LOAD_MATCH = measured.LOAD_MATCH

#: Verdicts, best first.
VERDICTS: tuple[str, ...] = ("valid", "warnings", "invalid")


#: One reason of a verdict: an :class:`asperity.validity.Finding` (code, level "invalid" or
#: "warning", message: the number, the threshold and why; value and threshold where a single
#: number decides), the one validity type of bem, statmodel and the verdict.
Reason = Finding


@document_fields
@dataclass
class Verdict:
    """Stage-7 result: is the result one the report can stand behind?

    Attributes
    ----------
    verdict : str
        "valid", "warnings" or "invalid".
    reasons : list of str
        One sentence per reason (the number, the threshold and why), invalid ones first.
    codes : list of str
        The code of each reason (module docstring).
    severities : list of str
        "invalid" or "warning", per reason.
    adhesion_energy_ratio, stickiness, regime_tabor_parameter : float or None
        The adhesion regime of the map (:func:`check_adhesion_regime`): U_el / (A0 w)
        (Persson-Tosatti), S_PR (Pastewka-Robbins) and Tabor's mu; None without adhesion.
    stages_skipped : list of str or None
        The stages the job did not compute because this verdict was known before them
        (:mod:`asperity.pipelines.stages.early_verdict`); None when every stage ran.
    full_contact_normal_load : ndarray or None
        The job's loads F_z (N) at which that limit is stated (early verdict only).
    full_contact_real_area, full_contact_sliding_friction : float or None
        With a verdict known early in the full-contact regime: what that regime predicts,
        A_r -> A_n (m^2) and the sliding friction tau_0 A_n (N) of the constant-shear-strength
        law (E:Hertz_theory's T = tau_0 pi a^2 summed over a closed interface).
    full_contact_test : str or None
        That limit held against the measured A_r/A_n (or why it could not be).
    """

    verdict: str = text("valid, warnings or invalid")
    reasons: list[str] = text("the number, the threshold and why, per reason")
    codes: list[str] = text("code per reason")
    severities: list[str] = text("invalid or warning, per reason")
    adhesion_energy_ratio: float | None = scalar(
        "1",
        "U_el / (A0 w): elastic energy to flatten the map over w (Persson-Tosatti)",
        optional=True,
    )
    stickiness: float | None = scalar(
        "1", "Pastewka-Robbins stickiness S_PR (sticky below 1)", optional=True
    )
    regime_tabor_parameter: float | None = scalar(
        "1", "Tabor parameter at the effective resolution's summit radius", optional=True
    )
    stages_skipped: list[str] | None = text(
        "stages not computed: the verdict was known before them (run.compute_all)",
        optional=True,
    )
    full_contact_normal_load: np.ndarray | None = array(
        "N", ("normal_load",), "the loads the full-contact limit is stated at", optional=True
    )
    full_contact_real_area: float | None = scalar(
        "m^2", "the full-contact limit's real area A_r -> A_n", optional=True
    )
    full_contact_sliding_friction: float | None = scalar(
        "N", "the full-contact limit's sliding friction tau_0 A_n", optional=True
    )
    full_contact_test: str | None = text(
        "the full-contact limit against the measured A_r/A_n", optional=True
    )

    @classmethod
    def from_reasons(cls, reasons: Sequence[Reason]) -> Verdict:
        """The verdict of a list of reasons (invalid ones listed first)."""
        ordered = sorted(reasons, key=lambda r: r.level != "invalid")
        if any(r.level == "invalid" for r in ordered):
            verdict = "invalid"
        else:
            verdict = "warnings" if ordered else "valid"
        return cls(
            verdict,
            [r.message for r in ordered],
            [r.code for r in ordered],
            [r.level for r in ordered],
        )

    @property
    def invalid(self) -> bool:
        """The verdict is "invalid"."""
        return self.verdict == "invalid"


# ------------------------------------------------------------------------------------------
# the checks: plain numbers in, reasons out
# ------------------------------------------------------------------------------------------


def check_area_fraction(fraction: np.ndarray, what: str) -> list[Reason]:
    """A_r/A_n (model or measured) against the independent-asperity limits."""
    values = np.asarray(fraction, dtype=float)
    values = values[np.isfinite(values)]
    if not values.size:
        return []
    top = float(values.max())
    why = (
        "an independent-asperity model (E:Ar_Greenwood) neglects the coalescence of "
        "junctions, which dominates beyond 10-15 % contact (paper, Section 5)"
    )
    if top > MAX_AREA_FRACTION:
        return [
            Reason(
                "area_fraction",
                "invalid",
                f"{what} A_r/A_n reaches {top:.3g} > {MAX_AREA_FRACTION:g}: {why}",
            )
        ]
    if top > WARN_AREA_FRACTION:
        return [
            Reason(
                "area_fraction",
                "warning",
                f"{what} A_r/A_n reaches {top:.3g} > {WARN_AREA_FRACTION:g}: {why}",
            )
        ]
    return []


def check_tabor(tabor_parameter: float) -> list[Reason]:
    """Tabor parameter mu against the JKR limit (paper, Section 2)."""
    if tabor_parameter >= MIN_TABOR_PARAMETER:
        return []
    return [
        Reason(
            "tabor",
            "invalid",
            f"Tabor parameter mu = {tabor_parameter:.3g} < {MIN_TABOR_PARAMETER:g}: the JKR "
            "asperity laws (E:JKR_indent, E:PC_indent) hold for mu > 5 (paper, Section 2)",
        )
    ]


def check_resolution(
    misfit_curve: np.ndarray, index: int, basis: str, direction: str = ""
) -> list[Reason]:
    """The effective resolution: misfit level, and the optimum at an end of the scan.

    Parameters
    ----------
    misfit_curve : ndarray
        rms ln ratio per stride of the scan (NaN where the model has no value, inf where it
        gives no area at a load where the reference has one).
    index : int
        Index of the effective resolution.
    basis : str
        "measured" or "bem".
    direction : str
        Where the data point when the least misfit is at an end of the scan
        (:func:`edge_direction`): "finer", "coarser", "between" (the optimum lies between the
        end stride and its neighbour) or "" (not known: the end's own direction is assumed).
    """
    curve = np.asarray(misfit_curve, dtype=float)
    misfit = float(curve[index])
    basis = {"bem": "BEM"}.get(basis, basis)
    scored = np.flatnonzero(~np.isnan(curve))  # inf: evaluated, and no area where needed
    reasons = []
    if not math.isfinite(misfit) or misfit > MAX_MISFIT:
        reasons.append(
            Reason(
                "misfit",
                "invalid",
                f"the statistical model misses the {basis} A_r(F_z) by an rms ln ratio of "
                f"{misfit:.3g} (> {MAX_MISFIT:g}, a factor e^{MAX_MISFIT:g} = "
                f"{math.exp(MAX_MISFIT):.2g}) even at its best resolution",
            )
        )
    elif misfit > WARN_MISFIT:
        reasons.append(
            Reason(
                "misfit",
                "warning",
                f"the statistical model misses the {basis} A_r(F_z) by an rms ln ratio of "
                f"{misfit:.3g} (> {WARN_MISFIT:g}) at its best resolution",
            )
        )
    if scored.size > 0 and index in (int(scored[0]), int(scored[-1])):
        reasons.append(_edge_reason(index, scored, len(curve), misfit, direction))
    return reasons


def _edge_reason(
    index: int, scored: np.ndarray, n_strides: int, misfit: float, direction: str
) -> Reason:
    """``resolution_at_edge``: which end, and where the data point (or that nothing fits)."""
    end = "finest" if index == int(scored[0]) else "coarsest"
    if scored.size == 1:
        end = "only scored resolution"
    where = f"the effective resolution is the {end} of the scan (stride {index + 1} of {n_strides})"
    if not math.isfinite(misfit) or misfit > WARN_MISFIT:
        return Reason(
            "resolution_at_edge",
            "invalid",
            f"{where}: the least misfit is not bracketed, and its misfit {misfit:.3g} > "
            f"{WARN_MISFIT:g}: no resolution of the scan fits",
        )
    if direction == "between" and scored.size > 1:
        neighbour = int(scored[1]) if end == "finest" else int(scored[-2])
        low, high = sorted((index + 1, neighbour + 1))
        advice = (
            f", but the model's mean ln(A_model / A_reference) changes sign between strides "
            f"{low} and {high}: the optimum lies between them, inside the scan (not beyond "
            "it); the effective resolution is known to within that step"
        )
    elif direction == "coarser" or (not direction and end == "coarsest"):
        advice = (
            ": the least misfit is not bracketed and the data point to coarser resolutions; "
            "a wider scan (surface.max_stride) may fit better"
        )
    else:
        advice = (
            ": the least misfit is not bracketed and the data point to finer resolutions; "
            "a finer measurement may fit better"
        )
    return Reason("resolution_at_edge", "warning", where + advice)


def mean_log_ratio(model: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Signed mean over loads of ln(A_model / A_reference), per stride (1).

    Parameters
    ----------
    model : ndarray, shape (n_stride, n_load)
        Model A_r, m^2 (NaN where the model gives none).
    reference : ndarray, shape (n_load,)
        Reference A_r at the same loads, m^2.

    Returns
    -------
    ndarray
        Per stride: the mean over loads where both are positive (NaN where none is).
    """
    model = np.asarray(model, dtype=float)
    reference = np.broadcast_to(np.asarray(reference, dtype=float), model.shape)
    usable = (model > 0) & (reference > 0)
    counts = usable.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        logs = np.where(usable, np.log(model / reference), 0.0)
        return np.where(counts > 0, logs.sum(axis=1) / np.maximum(counts, 1), np.nan)


def edge_direction(ratio: np.ndarray, misfit_curve: np.ndarray, index: int) -> str:
    """Where the data point when the least misfit is at an end of the scanned strides.

    Parameters
    ----------
    ratio : ndarray
        Signed mean ln(A_model / A_reference) per stride (:func:`mean_log_ratio`).
    misfit_curve : ndarray
        The misfit per stride (NaN: not scored).
    index : int
        Index of the least misfit.

    Returns
    -------
    str
        "between" when the mean log ratio changes sign between the end stride and its scored
        neighbour (the optimum lies between them), else "finer" at the finest end and
        "coarser" at the coarsest; "" when the least misfit is not at an end.
    """
    scored = np.flatnonzero(~np.isnan(np.asarray(misfit_curve, dtype=float)))
    if scored.size < 2 or index not in (int(scored[0]), int(scored[-1])):
        return ""
    neighbour = int(scored[1]) if index == int(scored[0]) else int(scored[-2])
    here, there = float(ratio[index]), float(ratio[neighbour])
    if math.isfinite(here) and math.isfinite(there) and here * there < 0:
        return "between"
    return "finer" if index == int(scored[0]) else "coarser"


def check_lambda(choice: ModeMixityChoice) -> list[Reason]:
    """The fitted lambda: at a bound, non-finite uncertainty, optimiser failure."""
    if choice is None or not choice.fitted:
        return []
    reasons = []
    if choice.at_bound:
        reasons.append(
            Reason(
                "lambda_at_bound",
                "invalid",
                f"the fitted lambda = {choice.mode_mixity:.3g} lies on a bound of the search "
                "interval (fit.mode_mixity_bounds): the bound, not the data, chose it",
            )
        )
    std = choice.mode_mixity_std
    if std is None or not math.isfinite(std):
        reasons.append(
            Reason(
                "lambda_uncertainty",
                "invalid",
                f"the uncertainty of lambda = {choice.mode_mixity:.3g} is not finite: the "
                "residual does not rise by one sigma^2 within the bounds, so the measured "
                "curves do not determine lambda",
            )
        )
    if choice.success is False:
        reasons.append(Reason("lambda_fit", "warning", f"the lambda fit reports: {choice.message}"))
    return reasons


def check_lambda_sources(choice: ModeMixityChoice) -> list[Reason]:
    """The area-only and friction-only lambdas disagree (both measured): a warning."""
    if choice is None or not getattr(choice, "lambda_sources_disagree", None):
        return []
    return [
        Reason(
            "lambda_sources_disagree",
            "warning",
            f"{choice.lambda_sources_comparison} (lambda used: the {choice.fit_source} fit); "
            "check the loading-system stiffness (loading.drive_stiffness) and the drive's "
            "origin of the friction tests",
        )
    ]


def check_measured_area(area: np.ndarray, nominal_area: float, what: str) -> list[Reason]:
    """A measured A_r above A_n is impossible."""
    values = np.asarray(area, dtype=float)
    if not values.size or float(values.max()) <= nominal_area:
        return []
    return [
        Reason(
            "measured_area_above_nominal",
            "invalid",
            f"{what}: measured A_r = {float(values.max()):.3g} m^2 > A_n = {nominal_area:.3g} "
            "m^2 (loading.nominal_area), physically impossible (units?)",
        )
    ]


def check_measured_loads(measured: Sequence[float], configured: Sequence[float]) -> list[Reason]:
    """Measured curves at loads that match no configured load (within :data:`LOAD_MATCH`)."""
    loads = np.asarray(configured, dtype=float)
    reasons = []
    for load in measured:
        nearest = float(loads[np.argmin(np.abs(loads - load))])
        if abs(nearest - load) > LOAD_MATCH * abs(load):
            reasons.append(
                Reason(
                    "measured_load_unmatched",
                    "warning",
                    f"a measured A_r(F_x) curve at F_z = {load:.4g} N matches no configured "
                    f"load (nearest {nearest:.4g} N, more than {100 * LOAD_MATCH:g} % away): "
                    "it calibrates lambda, but no prediction is compared with it",
                )
            )
    return reasons


def check_sliding(friction: FrictionPrediction) -> list[Reason]:
    """Shear curves that did not reach full sliding."""
    missed = [
        float(f)
        for f, ok, slide in zip(
            friction.normal_load, friction.converged, friction.sliding_friction, strict=True
        )
        if not ok or not math.isfinite(float(slide))
    ]
    return _no_full_sliding(
        missed,
        "full sliding not reached at F_z = {loads} N: the sliding friction there is not a "
        "result (loading.max_tangential_displacement too short, or the solver stopped)",
    )


def _no_full_sliding(missed: list[float], template: str) -> list[Reason]:
    """The ``no_full_sliding`` reason naming the loads (N) in ``template``'s ``{loads}``."""
    if not missed:
        return []
    loads = ", ".join(f"{f:.4g}" for f in missed)
    return [Reason("no_full_sliding", "invalid", template.format(loads=loads))]


def check_sliding_displacement(friction: FrictionPrediction) -> list[Reason]:
    """Converged shear curves with a finite sliding friction but no finite sliding displacement.

    A NaN delta_T at full sliding means the separation solve stopped before the expected
    number of sticking junctions fell to one; inf means junctions never slide. Either way the
    curve does not reach the full sliding whose friction it reports. (A curve that did not
    converge, or has no sliding friction, is reported by :func:`check_sliding`.)
    """
    missed = [
        float(f)
        for f, ok, slide, shift in zip(
            friction.normal_load,
            friction.converged,
            friction.sliding_friction,
            friction.sliding_displacement,
            strict=True,
        )
        if ok and math.isfinite(float(slide)) and not math.isfinite(float(shift))
    ]
    return _no_full_sliding(
        missed,
        f"no finite sliding displacement at F_z = {{loads}} N ({len(missed)} of "
        f"{np.size(friction.normal_load)} loads): full sliding is not reached within the "
        "shear path, so the sliding friction and delta_T there are not results",
    )


def check_edge_mismatch(bem: BemReference) -> list[Reason]:
    """A periodic BEM solve of a map whose opposite edges do not meet (a warning)."""
    if bem is None or getattr(bem, "boundary", None) != "periodic":
        return []
    mismatch = float(getattr(bem, "edge_mismatch", math.nan))
    if not mismatch > EDGE_MISMATCH_LIMIT:
        return []
    return [
        Reason(
            "bem_edge_mismatch",
            "warning",
            f"the BEM reference wraps the map periodically, but its opposite edges do not "
            f"meet: rms height jump across the seam {mismatch:.2f} x the rms height (> "
            f"{EDGE_MISMATCH_LIMIT:g}); the seam adds a cliff along two edges of the contact "
            '([bem] boundary = "free" if the map is the whole contacting body)',
        )
    ]


def check_bem(bem: BemReference) -> list[Reason]:
    """The BEM stage's convergence fields: stalls and the grid check."""
    if bem is None:
        return []
    reasons = []
    failed = int(np.size(bem.converged) - np.sum(bem.converged))
    if failed:
        first = f": {bem.messages[0]}" if bem.messages else ""
        reasons.append(
            Reason(
                "bem_stall",
                "invalid",
                f"{failed} of {np.size(bem.converged)} BEM solves did not converge{first}",
            )
        )
    if not bem.grid_converged:
        reasons.append(Reason("bem_grid", "warning", f"BEM grid check: {bem.grid_reason}"))
    return reasons


def check_bem_shear(shear: BemShearComparison | None) -> list[Reason]:
    """The shear BEM stage's failures and its judgement of the model (none when not run)."""
    if shear is None:
        return []
    reasons = []
    stall = SHEAR_THRESHOLDS["bem_shear_stall"]
    failed = int(np.size(shear.converged) - np.sum(shear.converged))
    if failed:
        first = f": {shear.messages[0]}" if shear.messages else ""
        reasons.append(
            Reason(
                stall.code,
                "invalid",
                f"{failed} of {np.size(shear.converged)} shear BEM curves did not converge"
                f"{first} ({stall.reason})",
            )
        )
    stuck = np.asarray(shear.stuck_junctions[0])
    slide = SHEAR_THRESHOLDS["bem_shear_no_sliding"]
    if np.any(stuck > slide.warning):
        where = ", ".join(
            f"{f:.4g} N ({int(n)} at {shear.tangential_displacement[i, -1] * 1e6:.3g} um)"
            for i, (f, n) in enumerate(zip(shear.normal_load, stuck, strict=True))
            if n > slide.warning
        )
        reasons.append(
            Reason(
                slide.code,
                "warning",
                f"shear BEM (stride {int(shear.grid_stride[0])}): junctions still stick at the "
                f"end of the path at F_z = {where}: {slide.reason}",
            )
        )
    reasons += _preload_mismatch(shear)
    misfit = SHEAR_THRESHOLDS["bem_shear_model_misfit"]
    bem = np.asarray(shear.static_friction[0], dtype=float)
    model = np.asarray(shear.model_static_friction, dtype=float)
    error = shear.static_friction_error
    error = np.zeros_like(bem) if error is None else np.nan_to_num(np.asarray(error), nan=0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        gap = np.abs(np.log(model / bem))
        band = np.log1p(error / bem)
    beyond = np.where(np.isfinite(gap), gap - np.nan_to_num(band, nan=0.0), np.nan)
    if np.any(beyond > misfit.warning):
        i = int(np.nanargmax(beyond))
        reasons.append(
            Reason(
                misfit.code,
                "warning",
                f"static friction at F_z = {shear.normal_load[i]:.4g} N: model "
                f"{model[i]:.4g} N, BEM {bem[i]:.3g} ± {error[i]:.2g} N (|ln ratio| "
                f"{gap[i]:.2f} > {misfit.warning:g} beyond the grid error): {misfit.reason}",
            )
        )
    return reasons


def _preload_mismatch(shear: BemShearComparison) -> list[Reason]:
    """The shear BEM's A_r(F_x = 0) against the normal reference's at the same loads (none
    where the reference has no area at a load sheared)."""
    reference = getattr(shear, "reference_area", None)
    if reference is None or not np.any(np.isfinite(reference)):
        return []
    threshold = SHEAR_THRESHOLDS["bem_shear_preload_mismatch"]
    with np.errstate(divide="ignore", invalid="ignore"):
        gap = np.abs(np.asarray(shear.real_area[0, :, 0]) / np.asarray(reference) - 1.0)
    if not np.nanmax(gap) > threshold.warning:
        return []
    i = int(np.nanargmax(gap))
    return [
        Reason(
            threshold.code,
            "warning",
            f"shear BEM A_r(F_x = 0) at F_z = {shear.normal_load[i]:.4g} N is "
            f"{gap[i]:.1%} from the normal BEM reference's ({shear.preload}, stride "
            f"{int(shear.grid_stride[0])} against {int(shear.reference_stride)}): "
            f"{threshold.reason}",
        )
    ]


def check_surface(preparation: dict | None) -> list[Reason]:
    """The surface preparation record's warnings."""
    if not preparation:
        return []
    return [
        Reason("surface_preparation", "warning", f"surface: {w}")
        for w in preparation.get("warnings") or []
    ]


def check_profile_isotropy(surface: LevelledSurface) -> list[Reason]:
    """For a line profile as input, the isotropy assumption (always a warning)."""
    if getattr(surface, "profile_heights", None) is None:
        return []
    synthesis = (surface.provenance or {}).get("profile_synthesis") or {}
    size = synthesis.get("map_size")
    maps = f" and the {size:.3g} m maps synthesised from its spectrum" if size else ""
    return [
        Reason(
            "profile_isotropy",
            "warning",
            f"the input is a line profile of {np.size(surface.profile_heights)} points: its "
            f"Nayak statistics{maps} assume an isotropic Gaussian surface, which one line "
            "cannot check (measure profiles in two directions, or a map, to test it)",
        )
    ]


def adhesion_regime_of(
    surface: LevelledSurface, material: Material, summit_radius: float | None
) -> AdhesionRegime | None:
    """:func:`asperity.statmodel.regimes.adhesion_regime` of the levelled map (missing pixels
    at the mean height) with E* (Pa), w (J/m^2) and, as the range of Pastewka and Robbins and
    of Tabor's parameter, epsilon (m); Tabor's mu at ``summit_radius`` (m; None: NaN). None
    when w = 0."""
    if material.work_of_adhesion <= 0:
        return None
    heights, _ = complete_map(surface)
    return adhesion_regime(
        heights,
        material.e_star,
        material.work_of_adhesion,
        interaction_range=material.equilibrium_distance,
        summit_radius=summit_radius,
        equilibrium_distance=material.equilibrium_distance,
    )


def check_adhesion_regime(regime: AdhesionRegime | None) -> list[Reason]:
    """Persson-Tosatti's full-contact criterion: invalid ``adhesion_full_contact`` when the
    elastic energy to flatten the map is below w, with Tabor's parameter (Tabor 1977) and
    Pastewka and Robbins's stickiness (PNAS 2014) beside it (docs/pipelines.md)."""
    if regime is None or regime.full_contact.level != "invalid":
        return []
    check = regime.full_contact
    mu = (
        f"{regime.tabor_parameter:.3g}"
        if math.isfinite(regime.tabor_parameter)
        else "not known (no summit radius before the statistical model)"
    )
    text_ = (
        f"{check.message} ({check.reference}; threshold {check.threshold:g} on "
        f"U_el/(A0 w)). Beside it: Tabor parameter mu = {mu} "
        f"(D. Tabor, J. Colloid Interface Sci. 58, 2 (1977)); Pastewka-Robbins stickiness "
        f"S_PR = {regime.stickiness:.3g} (sticky below 1; L. Pastewka, M.O. Robbins, PNAS "
        "111, 3298 (2014))"
    )
    return [Reason(check.code, "invalid", text_)]


#: Reason code: the adhesive BEM column is decided by the Maugis-Dugdale range, not physics.
RANGE_DECIDED_REASON = "bem_adhesive_range"
#: The adhesive BEM's A_r/A_n from which its contact counts as closed over the map.
BEM_FULL_CONTACT_FRACTION = 0.9


def check_bem_adhesive_range(
    bem: BemReference | None,
    regime: AdhesionRegime | None,
    configured_range: float | None = None,
    basis: str = "",
) -> list[Reason]:
    """``bem_adhesive_range``: the adhesive BEM's A_r/A_n is decided by its range h_0.

    In the full-contact regime (Persson-Tosatti, :func:`check_adhesion_regime`), or where the
    adhesive BEM's A_r/A_n reaches :data:`BEM_FULL_CONTACT_FRACTION` = 0.9, the loading-branch
    Maugis-Dugdale solve closes every gap the cohesive zone reaches: how far the contact
    spreads is set by the range h_0 (the zone's reach), not by the roughness. With
    ``[bem] adhesion_range = "auto"`` h_0 is chosen by the grid (a cohesive zone of 3 pixels),
    so the column measures the grid. The column is marked in the load table
    (:func:`asperity.pipelines.report.verdict_marks.mark_adhesive_bem`).

    Parameters
    ----------
    bem : BemReference or None
        The BEM stage's result (A_r/A_n, the range h_0 in m and its sensitivity).
    regime : AdhesionRegime or None
        The map's adhesion regime.
    configured_range : float or None
        ``[bem] adhesion_range`` (m); None: "auto" (chosen by the grid).
    basis : str
        What chose the effective resolution ("bem" or "measured"): against the BEM the
        reason is invalid (the calibration rests on the range-decided column), else a warning.

    Returns
    -------
    list of Reason
        Empty when the adhesive column is not Maugis-Dugdale, or neither condition holds.
    """
    if bem is None or getattr(bem, "adhesion", None) != "maugis":
        return []
    adhesive = getattr(bem, "contact_fraction_adhesive", None)
    if adhesive is None or not np.isfinite(adhesive).any():
        return []
    top = float(np.nanmax(adhesive))
    full = regime is not None and regime.full_contact.level == "invalid"
    if not full and top < BEM_FULL_CONTACT_FRACTION:
        return []
    why = []
    if full:
        why.append(
            "the map's adhesion regime is full contact "
            f"(U_el/(A0 w) = {regime.energy_ratio:.3g} < 1)"
        )
    if top >= BEM_FULL_CONTACT_FRACTION:
        why.append(
            f"the adhesive BEM's A_r/A_n reaches {top:.3g} (>= {BEM_FULL_CONTACT_FRACTION:g})"
        )
    h0 = getattr(bem, "adhesion_range", None)
    source = (
        'chosen by the grid ([bem] adhesion_range = "auto": a cohesive zone of 3 pixels)'
        if configured_range is None
        else "[bem] adhesion_range"
    )
    spread = getattr(bem, "range_sensitivity", None)
    moves = ""
    if spread is not None and np.size(spread) == 3:
        moves = (
            f"; at the check load A_r/A_n = {spread[0]:.3g}, {spread[1]:.3g}, {spread[2]:.3g} "
            "at h_0/2, h_0, 2 h_0"
        )
    range_text = "its range" if h0 is None else f"its range h_0 = {h0:.3g} m"
    severity = "invalid" if basis == "bem" else "warning"
    consequence = (
        "; the effective resolution was chosen against it, so the calibration rests on the range"
        if severity == "invalid"
        else ""
    )
    return [
        Reason(
            RANGE_DECIDED_REASON,
            severity,
            f"the adhesive BEM column (A_r/A_n BEM adh., marked 'range-decided') is decided by "
            f"{range_text}, {source}, not by the physics of the rough contact: "
            f"{' and '.join(why)}, so the loading-branch Maugis-Dugdale solve closes the gaps "
            f"its cohesive zone reaches{moves}{consequence}",
        )
    ]


def in_place_of_coalescence(reasons: list[Reason], regime: list[Reason]) -> list[Reason]:
    """``reasons`` with the adhesion-regime reasons in place of the junction-coalescence
    (``area_fraction``) ones when the regime is full contact; unchanged otherwise."""
    if not regime:
        return reasons
    kept = [r for r in reasons if r.code != "area_fraction"]
    return regime + kept


def check_shape_scale(choice: ResolutionChoice) -> list[Reason]:
    """The shape fit's factor c per measured A_r(F_x) curve against 1.

    In mode ``shape`` each measured curve is compared with the model curve at its own load
    times a free factor c (:mod:`statmodel.lambda_fit`). The effective resolution already
    makes the model's A_r(F_z) agree with its reference; a measured level off by more than
    the misfit the verdict accepts on A_r(F_z) means the curve is not what the model at that
    load describes (areas or loads in another unit, the curve of another load or specimen),
    and lambda fitted to it is not a result. Invalid when ``|ln c| >`` :data:`MAX_MISFIT`
    (c outside [0.50, 2.01]), a warning when ``|ln c| >`` :data:`WARN_MISFIT` (outside
    [0.82, 1.22]): the same bounds as the rms ln misfit of A_r(F_z).
    """
    scales = getattr(choice, "shape_scale", None)
    if choice is None or not choice.fitted or scales is None or choice.fit_mode == "absolute":
        return []
    scales = np.asarray(scales, dtype=float)
    loads = np.asarray(choice.shape_scale_normal_load, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        distance = np.abs(np.log(scales))
    distance = np.where(np.isfinite(distance), distance, math.inf)
    worst = int(np.argmax(distance))
    if distance[worst] <= WARN_MISFIT:
        return []
    severity = "invalid" if distance[worst] > MAX_MISFIT else "warning"
    limit = MAX_MISFIT if severity == "invalid" else WARN_MISFIT
    listed = ", ".join(f"{c:.3g} at {f:.4g} N" for c, f in zip(scales, loads, strict=True))
    return [
        Reason(
            "shape_scale",
            severity,
            f"the shape fit scales the model's A_r(F_x) by c = {scales[worst]:.3g} at F_z = "
            f"{loads[worst]:.4g} N (outside [{math.exp(-limit):.2f}, {math.exp(limit):.2f}], "
            f"|ln c| > {limit:g}, the misfit bound of A_r(F_z); all: {listed}): the measured "
            "level disagrees with the model at that load, so the curve is not what the model "
            "describes there (units of real_area or normal_load? another load?)",
        )
    ]


def check_calibration(choice: ModeMixityChoice, friction: FrictionPrediction) -> list[Reason]:
    """The measured curves' consistency beyond one scale factor: ``measured_area_scale``
    (a level 10 % or more from the model's beyond its own uncertainty at F_x = 0) and
    ``measured_area_offset`` (an additive offset fits better):
    :mod:`asperity.pipelines.stages.calibration_checks`."""
    found = calibration_checks.scale_reasons(choice, friction)
    found += calibration_checks.offset_reasons(choice)
    return [Reason(code, severity, text_) for code, severity, text_ in found]


def _reasons_from_checks(checks: Sequence[Check]) -> list[Reason]:
    """A reason per :class:`statmodel.checks.Check` whose level is not "ok" (its source cited)."""
    return [Reason(c.code, c.level, f"{c.message} ({c.reference})") for c in checks if not c.ok]


def _positive_or_nan(values: ArrayLike) -> np.ndarray:
    """Values > 0 and finite kept, every other one NaN (not a result at that load)."""
    array = np.asarray(values, dtype=float)
    return np.where(np.isfinite(array) & (array > 0), array, np.nan)


def check_friction_plausibility(
    friction: FrictionPrediction, e_star: float | None = None, hardness: float | None = None
) -> list[Reason]:
    """Static over sliding friction, the junction shear at the peak, and mu_s = F_s/F_z.

    Per load (:mod:`statmodel.plausibility`, thresholds and reasons in its ``THRESHOLDS``):
    F_s/F_d (:func:`~statmodel.plausibility.static_to_sliding_check`: warning above 10,
    invalid above 100); (F_s / A_r at the peak) / tau_0
    (:func:`~statmodel.plausibility.junction_shear_check`: warning above 10); with E* (Pa) the
    same junction shear against the solid's shear limit
    (:func:`~statmodel.plausibility.junction_yield_check`: glassy yield 0.0173 E*, rubbery G =
    E*/4, or H/(2.8 sqrt 3) with the hardness H in Pa; invalid above it) and mu_s
    (:func:`~statmodel.plausibility.friction_coefficient_check`: warning above 1, invalid
    above 1 when the junction shear is past the shear limit). Nothing is said where no load
    has a static or sliding friction (``no_full_sliding`` covers that).
    """
    static = _positive_or_nan(friction.static_friction)
    sliding = _positive_or_nan(friction.sliding_friction)
    forces = np.asarray(friction.tangential_force, dtype=float)
    areas = np.asarray(friction.real_area, dtype=float)
    area_at_peak = np.array(
        [
            areas[i, int(np.nanargmax(f))] if np.isfinite(f).any() else np.nan
            for i, f in enumerate(forces)
        ]
    )
    checks = []
    if np.isfinite(static / sliding).any():
        checks.append(plausibility.static_to_sliding_check(static, sliding))
    area_at_peak = _positive_or_nan(area_at_peak)
    sheared = np.isfinite(static / area_at_peak).any()
    if friction.shear_strength > 0 and sheared:
        checks.append(
            plausibility.junction_shear_check(static, area_at_peak, friction.shear_strength)
        )
    yield_check = None
    if e_star is not None and sheared:
        yield_check = plausibility.junction_yield_check(static, area_at_peak, e_star, hardness)
        checks.append(yield_check)
    load = _positive_or_nan(friction.normal_load)
    if np.isfinite(static / load).any():
        checks.append(plausibility.friction_coefficient_check(static, load, yield_check))
    return _reasons_from_checks(checks)


def check_hardness(
    hardness: float | None,
    e_star: float,
    roughness: Roughness,
    friction: FrictionPrediction,
) -> list[Reason]:
    """With ``material.hardness`` H (Pa): the plasticity index and the mean contact pressure.

    ``e_star`` is E* (Pa), ``roughness`` the summit statistics at the effective resolution
    (sigma_s and R in m), ``friction`` the friction stage's result (F_z in N, A_r in m^2).

    psi = (E*/H) sqrt(sigma_s/R) at the effective resolution (Greenwood-Williamson; warning
    above 0.6, invalid above 1) and max F_z/A_r at rest against H (warning above 0.39 H,
    first yield; invalid above H): :mod:`statmodel.plausibility`. Nothing without a hardness.
    """
    if hardness is None:
        return []
    checks = [
        plausibility.plasticity_index_check(
            e_star, hardness, roughness.summit_height_rms, roughness.summit_radius
        )
    ]
    area = _positive_or_nan(np.asarray(friction.real_area, dtype=float)[:, 0])
    load = _positive_or_nan(friction.normal_load)
    if np.isfinite(load / area).any():
        checks.append(plausibility.contact_pressure_check(load, area, hardness))
    return _reasons_from_checks(checks)


# ------------------------------------------------------------------------------------------
# the stage
# ------------------------------------------------------------------------------------------


def check_prediction_uncertainty(friction: FrictionPrediction) -> list[Reason]:
    """Predictions written "± ?": the model's uncertainty could not be estimated (e.g. one
    load: the misfit has no scatter to size the effective resolution's interval from)."""
    u = friction.static_friction_uncertainty
    if u is None or bool(np.all(np.isfinite(np.asarray(u, dtype=float)))):
        return []
    why = friction.uncertainty_message or "its interval is unknown"
    return [
        Reason(
            "prediction_uncertainty_unknown",
            "warning",
            f"the model's predictions carry no uncertainty (± ?): {why}; add normal loads "
            "(the effective resolution's interval comes from the misfit's scatter over them)",
        )
    ]


def job_reasons(context: StageContext) -> list[Reason]:
    """Every check on the results of the read-and-level to friction stages and the measurements."""
    config, measured = context.config, context.measured
    res, lam = context.result(STATISTICAL_MODEL), context.result(MODE_MIXITY)
    a_n = config.loading.nominal_area
    reasons = check_surface(context.result(SURFACE).preparation)
    reasons += check_bem(context.result(BEM))
    reasons += check_edge_mismatch(context.result(BEM))
    reasons += check_area_fraction(res.real_area[res.index] / a_n, "the statistical model's")
    if measured.normal_area is not None:
        reasons += check_measured_area(measured.normal_area.real_area, a_n, "A_r(F_z)")
        reasons += check_area_fraction(measured.normal_area.real_area / a_n, "the measured")
    for curve in measured.shear_area:
        reasons += check_measured_area(curve.real_area, a_n, f"A_r(F_x) at {curve.normal_load} N")
    reasons += check_tabor(res.tabor_parameter)
    reasons += check_resolution(
        res.misfit, res.index, res.basis, resolution_direction(res, context.result(BEM))
    )
    reasons += check_measured_loads(
        sorted({c.normal_load for c in measured.shear_area}), config.loading.normal_loads
    )
    reasons += check_lambda(lam)
    reasons += check_lambda_sources(lam)
    reasons += check_sliding_displacement(context.result(FRICTION))
    reasons += check_sliding(context.result(FRICTION))
    reasons += check_prediction_uncertainty(context.result(FRICTION))
    reasons += check_shape_scale(lam)
    reasons += check_calibration(lam, context.result(FRICTION))
    reasons += check_friction_plausibility(
        context.result(FRICTION), config.material.e_star, config.material.hardness
    )
    reasons += check_hardness(
        config.material.hardness, config.material.e_star, res.roughness, context.result(FRICTION)
    )
    reasons += check_profile_isotropy(context.result(SURFACE))
    reasons += check_bem_shear(context.result(BEM_SHEAR))
    return reasons


#: Fields a statistical-model result may store with the direction of its least misfit
#: ("finer", "coarser", or "" when it lies between strides).
DIRECTION_FIELDS: tuple[str, ...] = ("optimum_direction", "resolution_direction", "direction")


def resolution_direction(res: ResolutionChoice, bem: BemReference | None) -> str:
    """Where the data point when the least misfit is at an end of the scan.

    Read from the statistical-model result when it stores a direction
    (:data:`DIRECTION_FIELDS`: "" there means the optimum lies between strides), else from the
    sign of the mean ln(A_model / A_reference) (:func:`edge_direction`) against the reference
    that chose the resolution (the measured A_r(F_z), or the BEM).
    """
    for name in DIRECTION_FIELDS:
        stored = getattr(res, name, None)
        if isinstance(stored, str) and stored in ("finer", "coarser", ""):
            return stored or "between"
    if res.basis == "measured" and res.model_real_area_at_measured is not None:
        ratio = mean_log_ratio(res.model_real_area_at_measured, res.measured_real_area)
    elif bem is not None:
        ratio = mean_log_ratio(res.real_area, bem.reference_fraction() * res.nominal_area)
    else:
        return ""
    return edge_direction(ratio, res.misfit, res.index)


def compute_verdict(context: StageContext) -> Verdict:
    """The job's PSD stage: :func:`job_reasons` summed up, the adhesion regime in place of
    junction coalescence where it is full contact, and the adhesive BEM column marked where
    the range decides it (:func:`check_bem_adhesive_range`)."""
    res = context.result(STATISTICAL_MODEL)
    if res is None:  # the job stopped where the verdict was known (stages.early_verdict)
        return early_verdict(context)
    regime = adhesion_regime_of(context.result(SURFACE), context.config.material, res.summit_radius)
    reasons = in_place_of_coalescence(job_reasons(context), check_adhesion_regime(regime))
    reasons += check_bem_adhesive_range(
        context.result(BEM), regime, context.config.bem.adhesion_range, res.basis
    )
    verdict = Verdict.from_reasons(reasons)
    if regime is not None:
        verdict.adhesion_energy_ratio = float(regime.energy_ratio)
        verdict.stickiness = float(regime.stickiness)
        verdict.regime_tabor_parameter = float(regime.tabor_parameter)
    return verdict


def early_reasons(context: StageContext) -> list[Reason]:
    """The checks that need no model: the adhesion regime (summit radius unknown: Tabor's mu
    NaN), the surface preparation, the measured areas and loads, a line profile's isotropy."""
    config, measured = context.config, context.measured
    a_n = config.loading.nominal_area
    surface = context.result(SURFACE)
    regime = adhesion_regime_of(surface, config.material, None)
    reasons = check_adhesion_regime(regime) + check_surface(surface.preparation)
    if measured.normal_area is not None:
        reasons += check_measured_area(measured.normal_area.real_area, a_n, "A_r(F_z)")
    for curve in measured.shear_area:
        reasons += check_measured_area(curve.real_area, a_n, f"A_r(F_x) at {curve.normal_load} N")
    reasons += check_measured_loads(
        sorted({c.normal_load for c in measured.shear_area}), config.loading.normal_loads
    )
    return reasons + check_profile_isotropy(surface)


def early_verdict(context: StageContext) -> Verdict:
    """The verdict stage when the job skipped the stages that cannot change the verdict
    (:data:`~asperity.pipelines.stages.early_verdict.SKIPPED_WHEN_KNOWN`; the statistical
    model's result is None): :func:`early_reasons`, the full-contact limit
    (:func:`~asperity.pipelines.stages.early_verdict.full_contact_limit`, A_r -> A_n in m^2,
    F_d -> tau_0 A_n in N, E:Hertz_theory) and its test against the measurement."""
    config = context.config
    a_n = config.loading.nominal_area
    fractions = early.measured_fractions(context.measured, a_n)
    sentence, found = early.full_contact_test(fractions)
    test_reasons = [Reason(code, severity, text_) for code, severity, text_ in found]
    verdict = Verdict.from_reasons(early_reasons(context) + test_reasons)
    regime = adhesion_regime_of(context.result(SURFACE), config.material, None)
    if regime is not None:
        verdict.adhesion_energy_ratio = float(regime.energy_ratio)
        verdict.stickiness = float(regime.stickiness)
    skipped = ["bem_reference"] if config.bem.enabled else []
    verdict.stages_skipped = [*skipped, "statistical_model", "mode_mixity", "friction", "psd"]
    area, sliding = early.full_contact_limit(a_n, config.material.shear_strength)
    verdict.full_contact_real_area, verdict.full_contact_sliding_friction = area, sliding
    verdict.full_contact_test = sentence
    verdict.full_contact_normal_load = np.asarray(config.loading.normal_loads, dtype=float)
    return verdict


#: The file attribute of results.h5 holding the regime judged before the BEM (JSON).
PREVIEW_ATTRIBUTE = "preview_adhesion_regime"


def preview_adhesion_regime(context: StageContext) -> PreviewNote:
    """The adhesion regime judged from the levelled map before the BEM stage (a second,
    against the BEM's minutes): one log line, and the preliminary reason stored at once in
    ``results.h5`` (file attribute :data:`PREVIEW_ATTRIBUTE`, JSON with ``codes``,
    ``severities``, ``reasons``, ``adhesion_energy_ratio``, ``stickiness``). An invalid reason
    here makes the job skip the stages that cannot change the verdict unless
    ``run.compute_all`` (:mod:`asperity.pipelines.stages.early_verdict`); the final verdict
    repeats the reason.
    Without adhesion (w = 0) no line, and a record without reasons (it replaces one a former
    run of the same folder stored)."""
    config = context.config
    regime = adhesion_regime_of(context.result(SURFACE), config.material, None)
    if regime is None:
        empty = {"codes": [], "severities": [], "reasons": []}
        return PreviewNote([], {**empty, "adhesion_energy_ratio": None, "stickiness": None})
    reasons = check_adhesion_regime(regime)
    numbers = (
        f"U_el/(A0 w) = {regime.energy_ratio:.3g} (Persson-Tosatti, threshold 1), "
        f"stickiness S_PR = {regime.stickiness:.3g}"
    )
    if reasons:
        bem = (
            "; the adhesive BEM's A_r/A_n will be decided by its range h_0, not by the roughness"
            if config.bem.adhesive and config.bem.adhesion == "maugis"
            else ""
        )
        line = (
            f"adhesion regime judged from the map: FULL CONTACT expected at any load ({numbers}"
            f"): the asperity model and a loading-branch BEM do not apply{bem}. The verdict "
            f"will be INVALID ({reasons[0].code}); "
            + (
                "every stage runs as configured (run.compute_all = true)"
                if config.run.compute_all
                else "the BEM and the model stages, which cannot change it, are skipped "
                "(run.compute_all = true, asperity run --compute-all, computes them)"
            )
        )
    else:
        line = f"adhesion regime judged from the map: partial contact ({numbers})"
    record = {
        "codes": [r.code for r in reasons],
        "severities": [r.level for r in reasons],
        "reasons": [r.message for r in reasons],
        "adhesion_energy_ratio": float(regime.energy_ratio),
        "stickiness": float(regime.stickiness),
    }
    return PreviewNote([line], record)


def exit_status(converged: bool, verdict: Verdict | None) -> ExitStatus:
    """1 when a solver did not converge, else 3 when the verdict is invalid, else 0."""
    if not converged:
        return ExitStatus.NOT_CONVERGED
    if verdict is not None and verdict.invalid:
        return ExitStatus.INVALID_RESULT
    return ExitStatus.OK


#: The words of each verdict, everywhere it is shown (terminal, report.md, report.html,
#: figure stamps and CSV headers).
VERDICT_WORDS: dict[str, str] = {
    "valid": "valid",
    "warnings": "valid, with warnings",
    "invalid": "INVALID",
}
#: The word of each reason's severity, everywhere it is shown.
SEVERITY_WORDS: dict[str, str] = {"invalid": "INVALID", "warning": "warning"}


def verdict_wording(verdict: Verdict | str) -> str:
    """``"Verdict: INVALID"``, ``"Verdict: valid, with warnings"`` or ``"Verdict: valid"``:
    the one wording of the verdict in the terminal, the reports, the figures and the CSVs."""
    word = verdict if isinstance(verdict, str) else verdict.verdict
    return f"Verdict: {VERDICT_WORDS.get(word, word)}"


def severity_label(severity: str) -> str:
    """The word of a reason's severity ("INVALID" or "warning")."""
    return SEVERITY_WORDS.get(severity, severity)


def reason_line(severity: str, code: str, reason: str) -> str:
    """One reason as text: ``"INVALID (tabor): mu = 2.6 < 5 ..."``."""
    return f"{severity_label(severity)} ({code}): {reason}"


def first_reason(verdict: Verdict) -> str:
    """The first (most severe) reason as :func:`reason_line` ("" when there is none)."""
    if not verdict.reasons:
        return ""
    return reason_line(verdict.severities[0], verdict.codes[0], verdict.reasons[0])


def verdict_lines(verdict: Verdict) -> list[str]:
    """The verdict as lines of text (the terminal summary; never truncated): the words of
    :func:`verdict_wording` under a capitalised label a terminal user can search for."""
    lines = [verdict_wording(verdict).replace("Verdict:", "VERDICT:", 1)]
    for severity, code, reason in zip(
        verdict.severities, verdict.codes, verdict.reasons, strict=True
    ):
        lines.append(f"  - {reason_line(severity, code, reason)}")
    return lines


def verdict_markdown(verdict: Verdict) -> list[str]:
    """The verdict block at the top of report.md."""
    tail = {
        "valid": " Every check passed.",
        "warnings": "",
        "invalid": " The numbers below are outside the model's validity; they are marked "
        "*invalid* and are not results.",
    }.get(verdict.verdict, "")
    if getattr(verdict, "full_contact_real_area", None) is not None:
        tail = (
            " The job stopped where the verdict was known: the numbers below are the "
            "full-contact limit this regime predicts, not the asperity model's."
        )
    lines = [f"**{verdict_wording(verdict)}.**{tail}", ""]
    for severity, code, reason in zip(
        verdict.severities, verdict.codes, verdict.reasons, strict=True
    ):
        lines.append(f"- **{severity_label(severity)}** (`{code}`): {reason}")
    return [*lines, ""] if verdict.reasons else lines


def mark(value: str, verdict: Verdict | None) -> str:
    """A table cell: ``invalid: <value>`` when the verdict is invalid, else the value."""
    if getattr(verdict, "verdict", None) != "invalid" or value in ("-", ""):
        return value
    return f"invalid: {value}"


VERDICT = Stage(
    name="verdict",
    title="validity verdict",
    result=Verdict,
    config=(
        "measured",
        "loading.normal_loads",
        "loading.nominal_area",
        "material.hardness",
        "material.E_star",
        "material.work_of_adhesion",
        "material.equilibrium_distance",
        "material.shear_strength",
        "bem.adhesion_range",
        "bem.enabled",
    ),
    inputs=(SURFACE, SCAN, BEM, STATISTICAL_MODEL, MODE_MIXITY, FRICTION, BEM_SHEAR),
    compute=compute_verdict,
    preview=Preview(
        name="adhesion_regime",
        before=BEM.name,
        config=(
            "material.E_star",
            "material.work_of_adhesion",
            "material.equilibrium_distance",
            "bem.adhesive",
            "bem.adhesion",
            "run.compute_all",
        ),
        inputs=(SURFACE,),
        run=preview_adhesion_regime,
    ),
)
