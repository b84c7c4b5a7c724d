"""The statistical-model stage: the statistical model at every resolution, and the effective
resolution (Fig 12d).

For each stride of the resolution scan, the summit statistics (eta, R, sigma_s) feed the
statistical model (E:Ar_Greenwood with the load fixed by E:Fy_Greenwood) at the job's normal
loads. The misfit of a resolution is the root mean square over loads of
ln(A_model / A_reference): a relative error, so light and heavy loads weigh the same. The
reference is the user's measured A_r(F_z) when given (the paper's choice, Section 5), compared
with the JKR model; otherwise the BEM on the map, compared with the model under the BEM's own
adhesion law. The effective resolution is the least misfit located between the strides
(:mod:`~asperity.statmodel.effective_resolution`); ``effective_resolution`` and the summit
statistics of the result are those there, and ``effective_stride`` is the scan's stride of least
misfit.

**Like for like** (the calibration against the BEM). Each BEM reference is compared with the
statistical model under the same law:

* the Maugis-Dugdale BEM (``[bem] adhesion = "maugis"``) with the Maugis-Dugdale statistical
  model at the BEM's range h_0 and cohesive stress sigma_0 = w / h_0
  (:func:`statmodel.maugis_rough.maugis_rough_contact`, ``real_area_bem_law``): this pair
  chooses the effective resolution;
* the non-adhesive BEM with Greenwood-Williamson (w = 0, ``real_area_non_adhesive``), whose own
  least-misfit stride is stored beside it (``effective_resolution_non_adhesive``);
* a Pohrt-Popov BEM (``adhesion = "pohrt-popov"``, no adhesion on its loading branch) or a BEM
  without its adhesive solves with Greenwood-Williamson, which then chooses.

The JKR/PC model (``real_area``, E:JKR_load) is the one that makes the predictions (the friction
stage) at that effective resolution; the BEM at a grid-resolved range cannot check its larger
adhesive gain, and the report says so (:func:`statmodel.maugis_rough.asperity_law_regime`).

**The reference's uncertainty.** With a BEM reference the effective resolution is also located
against the reference times (1 - u) and (1 + u), u its relative one-sigma or grid-convergence
band per load (``BemReference.reference_fraction_uncertainty``), and the interval is the union of
the misfit interval with those two optima (``optimum_reference_shift``); the predictions' error
bars follow from the interval's ends (the friction stage).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from asperity import statmodel, topo
from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.config import ConfigError, JobConfig
from asperity.pipelines.engine.parallel import run_map
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.engine.views import ConfigView, DeclaredView
from asperity.pipelines.measured import NormalAreaCurve
from asperity.pipelines.stages._pull_off import has_summits, pull_off_forces, roughness_from_scan
from asperity.pipelines.stages.bem import BEM, BemReference
from asperity.pipelines.stages.surface import SCAN, SURFACE, ScanResult
from asperity.statmodel.effective_resolution import OptimumFields, optimum_fields
from asperity.statmodel.maugis_rough import asperity_law_regime, maugis_rough_contact

#: Above this A_r/A_n the asperities of the statistical model would overlap: independent
#: asperities (the Greenwood-Williamson / Fuller-Tabor picture) are no longer a fair model.
MAX_AREA_FRACTION = 0.1
#: Below this Tabor parameter the JKR asperity laws do not apply (paper, Section 2).
MIN_TABOR_PARAMETER = 5.0


class ModelValidityWarning(UserWarning):
    """The statistical model is used outside the range where its assumptions hold."""


def validity_notes(real_area_fraction: np.ndarray, tabor_parameter: float) -> list[str]:
    """Sentences saying where the model is outside its validity (empty when all is well).

    Parameters
    ----------
    real_area_fraction : ndarray
        Model A_r/A_n at the effective resolution, one per load.
    tabor_parameter : float
        mu at the effective resolution.
    """
    notes = []
    top = float(np.nanmax(real_area_fraction)) if np.size(real_area_fraction) else math.nan
    if top > MAX_AREA_FRACTION:
        notes.append(
            f"the statistical model gives A_r/A_n up to {top:.3g} (> "
            f"{MAX_AREA_FRACTION:g}): its asperities overlap, so the independent-"
            "asperity model is outside its validity at these loads"
        )
    if tabor_parameter < MIN_TABOR_PARAMETER:
        notes.append(
            f"Tabor parameter mu = {tabor_parameter:.3g} < {MIN_TABOR_PARAMETER:g}: "
            "the JKR asperity laws (E:JKR_indent, E:PC_indent) do not apply"
        )
    return notes


def material_from_config(
    material: statmodel.Material, mode_mixity: float | None = None
) -> statmodel.Material:
    """The configured :class:`statmodel.Material` (``config.material``), optionally with
    another lambda."""
    if mode_mixity is None:
        return material
    return dataclasses.replace(material, mode_mixity=mode_mixity)


def areas_at_loads(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_loads: Sequence[float],
) -> tuple[np.ndarray, str]:
    """A_r (m^2) at the loads, or NaNs and the error message when the model refuses them."""
    try:
        return (
            np.asarray(
                statmodel.real_area_at_loads(
                    material, roughness, nominal_area, np.asarray(normal_loads, dtype=float)
                ),
                dtype=float,
            ),
            "",
        )
    except (ValueError, ArithmeticError) as exc:
        return np.full(len(normal_loads), np.nan), str(exc)


#: ``ResolutionChoice.bem_law`` values: the statistical model's law paired with the BEM reference.
MAUGIS_DUGDALE, GREENWOOD_WILLIAMSON = "maugis-dugdale", "greenwood-williamson"


def bem_law_of(bem: BemReference | None, work_of_adhesion: float) -> tuple[str, float | None]:
    """The statistical model's law that the BEM reference is compared with, and its range (m).

    ``(MAUGIS_DUGDALE, h_0)`` for a Maugis-Dugdale BEM with its adhesive solves (w > 0);
    ``(GREENWOOD_WILLIAMSON, None)`` otherwise: a Pohrt-Popov BEM (its loading branch carries
    no adhesion), a BEM without adhesive solves, or w = 0.
    """
    if (
        bem is not None
        and work_of_adhesion > 0
        and getattr(bem, "adhesion", None) == "maugis"
        and bem.contact_fraction_adhesive is not None
        and getattr(bem, "adhesion_range", None)
    ):
        return MAUGIS_DUGDALE, float(bem.adhesion_range)
    return GREENWOOD_WILLIAMSON, None


def bem_law_areas_at_loads(
    material: statmodel.Material,
    roughness: statmodel.Roughness,
    nominal_area: float,
    normal_loads: Sequence[float],
    adhesion_range: float | None,
) -> tuple[np.ndarray, str]:
    """A_r (m^2) of the statistical model under the BEM's law at the loads, and a refusal.

    With ``adhesion_range`` h_0 (m): Maugis-Dugdale asperities at sigma_0 = w / h_0
    (:func:`statmodel.maugis_rough.maugis_rough_contact`, the BEM's loading branch); with None:
    Greenwood-Williamson (w = 0, E:Ar_Greenwood with Hertzian asperities). NaN where the model
    gives no value, with its message.
    """
    if adhesion_range is None:
        plain = dataclasses.replace(material, work_of_adhesion=0.0)
        return areas_at_loads(plain, roughness, nominal_area, normal_loads)
    try:
        out = maugis_rough_contact(
            roughness,
            material.e_star,
            material.work_of_adhesion,
            adhesion_range,
            nominal_area,
            np.asarray(normal_loads, dtype=float),
        )
    except (ValueError, ArithmeticError) as exc:
        return np.full(len(normal_loads), np.nan), str(exc)
    area = np.where(out.success, out.real_area, np.nan)
    failed = [m for m, ok in zip(out.message, out.success, strict=True) if not ok]
    return area, "; ".join(sorted(set(failed)))


def log_misfit(model: np.ndarray, reference: np.ndarray) -> float:
    """Root mean square of ln(model / reference) over entries where both are positive.

    Returns inf when the model gives no positive area where the reference has one.
    """
    model = np.asarray(model, dtype=float)
    reference = np.asarray(reference, dtype=float)
    ref_ok = reference > 0
    if not ref_ok.any():
        return math.nan
    if not np.all(model[ref_ok] > 0):
        return math.inf
    return float(np.sqrt(np.mean(np.log(model[ref_ok] / reference[ref_ok]) ** 2)))


@document_fields
@dataclass
class ResolutionChoice:
    """Stage-4 result: the statistical model at every resolution and the effective one.

    Attributes
    ----------
    stride, resolution : ndarray
        The scan's strides and pixel sizes (m).
    normal_load : ndarray
        F_z, N.
    real_area, real_area_fraction : ndarray, shape (n_stride, n_load)
        JKR model A_r (m^2) and A_r/A_n: the model that makes the predictions.
    misfit_bem : ndarray
        RMS ln-ratio misfit of the model under the BEM's law (``real_area_bem_law``) against
        the BEM reference at each stride (NaN without BEM).
    pull_off : ndarray
        Pull-off force at each stride, N.
    basis : str
        What chose the effective resolution: "measured" or "bem".
    effective_index, effective_stride : int
        Index and stride of the scan's stride of least misfit.
    effective_resolution : float
        The effective resolution, m: the least misfit located between the strides when the
        map was given (``optimum_resolution``), else the stride of least misfit's pixel size.
    asperity_density, summit_radius, summit_height_rms : float
        eta (1/m^2), R (m), sigma_s (m) at ``effective_resolution`` (the map resampled there).
    tabor_parameter : float
        mu at ``effective_resolution``.
    nominal_area : float
        A_n, m^2.
    messages : list of str
        Model refusals per stride.
    validity : list of str
        Where the model is outside its validity at the effective resolution (the located
        optimum when there is one; :func:`validity_notes`); empty when it is not.
    measured_normal_load, measured_real_area : ndarray or None
        The measured A_r(F_z) (N, m^2) when given.
    model_real_area_at_measured : ndarray or None
        Model A_r (m^2) at the measured loads, shape (n_stride, n_measured).
    misfit_measured : ndarray or None
        RMS ln-ratio misfit against the measured A_r(F_z).
    real_area_non_adhesive : ndarray or None
        Non-adhesive (w -> 0, Greenwood-Williamson) model A_r (m^2), shape (n_stride, n_load).
    bem_law : str or None
        The statistical model's law paired with the BEM reference: ``"maugis-dugdale"`` (a
        Maugis-Dugdale BEM) or ``"greenwood-williamson"`` (Pohrt-Popov, no adhesive solves).
    bem_law_adhesion_range : float or None
        Its range h_0 (m), the BEM stage's (sigma_0 = w / h_0); None for Greenwood-Williamson.
    real_area_bem_law : ndarray or None
        The model under the BEM's law, A_r (m^2), shape (n_stride, n_load): the BEM
        reference's like-for-like partner (its misfit is ``misfit_bem``).
    effective_real_area_bem_law, effective_real_area_non_adhesive : ndarray or None
        The model under the BEM's law and Greenwood-Williamson at ``effective_resolution``,
        A_r (m^2) per load (Fig 12d's pairs; their ratio is the model's adhesive gain).
    maugis_parameter : float or None
        The BEM's Maugis parameter lambda at the effective resolution's summit radius.
    adhesion_statement : str or None
        The BEM's law beside the JKR model's Tabor parameter, and what follows for the
        predictions (:func:`statmodel.maugis_rough.asperity_law_regime`).
    reference_relative_uncertainty : ndarray or None
        The BEM reference's relative uncertainty per reference load (1), propagated into the
        effective resolution's interval.
    optimum_misfit_interval : ndarray or None
        The interval from the misfit alone (finer, coarser end), m.
    optimum_reference_shift : ndarray or None
        The effective resolution located against the reference times (1 - u) and (1 + u), m.
    optimum_kept_sample : bool or None
        The parabola's vertex fitted worse than a resolution measured (a stride or a refined
        sample): that resolution is reported instead.
    misfit_bem_non_adhesive : ndarray or None
        RMS ln-ratio misfit of the non-adhesive model against the non-adhesive BEM.
    effective_index_non_adhesive : int or None
        Index of that pair's least misfit (reported beside the effective resolution).
    effective_resolution_non_adhesive : float or None
        Its pixel size, m.
    optimum_resolution : float or None
        The effective resolution between the strides (m): the least misfit located by
        :func:`statmodel.effective_resolution.locate_least_misfit` (parabola in ln resolution,
        refined on the map resampled at non-integer steps); equal to ``effective_resolution``.
    optimum_interval : ndarray or None
        Its one-sigma interval (finer end, coarser end), m; on an open side the scan's end:
        the profile interval widened by the misfit's scatter between strides, united with the
        optima against the reference's band (:mod:`~asperity.statmodel.effective_resolution`).
    optimum_profile_interval : ndarray or None
        The profile interval of the loads' residuals alone, m.
    optimum_sampling_half_width : float or None
        The half-width (ln resolution, 1) added in quadrature for the scatter.
    optimum_misfit : float or None
        The least misfit there (rms ln ratio, 1).
    optimum_open_finer, optimum_open_coarser : bool or None
        The interval reaches the finest / coarsest resolution scanned without closing.
    optimum_direction : str or None
        ``"finer"`` / ``"coarser"`` when the optimum is at that end of the scan (where the
        data point), else "".
    optimum_status : int or None
        0 closed interval, 1 an open side or an optimum at an end, 2 no interval (one load).
    optimum_message : str or None
        One sentence: the optimum, its interval and any open side.
    optimum_asperity_density, optimum_summit_radius, optimum_summit_height_rms : float or None
        eta (1/m^2), R (m), sigma_s (m) at ``optimum_resolution`` (the same as
        ``asperity_density``, ``summit_radius``, ``summit_height_rms``).
    interval_asperity_density, interval_summit_radius, interval_summit_height_rms : ndarray
        The same at the interval's (finer, coarser) ends (NaN where unknown).
    optimum_real_area : ndarray or None
        Model A_r (m^2) at the job's loads at ``optimum_resolution``.
    sampled_resolution, sampled_misfit : ndarray or None
        Every resolution the location used, strides and refinement (m, ascending), and its
        misfit (1).
    """

    stride: np.ndarray = array("1", ("stride",), "decimation stride")
    normal_load: np.ndarray = array("N", ("normal_load",), "normal load")
    resolution: np.ndarray = array("m", ("stride",), "pixel size")
    real_area: np.ndarray = array(
        "m^2", ("stride", "normal_load"), "statistical-model real contact area"
    )
    real_area_fraction: np.ndarray = array("1", ("stride", "normal_load"), "A_r / A_n")
    misfit_bem: np.ndarray = array("1", ("stride",), "rms ln(A_model,BEM law / A_bem) over loads")
    pull_off: np.ndarray = array("N", ("stride",), "pull-off force")
    basis: str = text("what chose the effective resolution: measured or bem")
    effective_index: int = scalar("1", "index of the stride of least misfit")
    effective_stride: int = scalar("1", "stride of least misfit")
    effective_resolution: float = scalar("m", "effective resolution (located between strides)")
    asperity_density: float = scalar("1/m^2", "eta at the effective resolution")
    summit_radius: float = scalar("m", "R at the effective resolution")
    summit_height_rms: float = scalar("m", "sigma_s at the effective resolution")
    tabor_parameter: float = scalar("1", "Tabor parameter at the effective resolution")
    nominal_area: float = scalar("m^2", "nominal contact area A_n")
    messages: list[str] = text("model refusals per stride")
    validity: list[str] = text("where the model is outside its validity")
    measured_normal_load: np.ndarray | None = array(
        "N", ("measured_normal_load",), "measured normal load", optional=True
    )
    measured_real_area: np.ndarray | None = array(
        "m^2", ("measured_normal_load",), "measured A_r", optional=True
    )
    model_real_area_at_measured: np.ndarray | None = array(
        "m^2",
        ("stride", "measured_normal_load"),
        "model A_r at the measured loads",
        optional=True,
    )
    misfit_measured: np.ndarray | None = array(
        "1", ("stride",), "rms ln(A_model / A_measured) over loads", optional=True
    )
    real_area_non_adhesive: np.ndarray | None = array(
        "m^2",
        ("stride", "normal_load"),
        "non-adhesive (Greenwood-Williamson) model A_r",
        optional=True,
    )
    misfit_bem_non_adhesive: np.ndarray | None = array(
        "1", ("stride",), "rms ln(A_model,w=0 / A_bem,non-adhesive) over loads", optional=True
    )
    bem_law: str | None = text("the model's law paired with the BEM reference", optional=True)
    bem_law_adhesion_range: float | None = scalar(
        "m", "Maugis-Dugdale range h_0 of that law", optional=True
    )
    real_area_bem_law: np.ndarray | None = array(
        "m^2", ("stride", "normal_load"), "model A_r under the BEM's adhesion law", optional=True
    )
    effective_real_area_bem_law: np.ndarray | None = array(
        "m^2",
        ("normal_load",),
        "model A_r under the BEM's law at the effective resolution",
        optional=True,
    )
    effective_real_area_non_adhesive: np.ndarray | None = array(
        "m^2",
        ("normal_load",),
        "Greenwood-Williamson A_r at the effective resolution",
        optional=True,
    )
    maugis_parameter: float | None = scalar(
        "1", "BEM's Maugis parameter at the effective resolution's summit radius", optional=True
    )
    adhesion_statement: str | None = text(
        "the BEM's law beside the JKR model, and what follows", optional=True
    )
    reference_relative_uncertainty: np.ndarray | None = array(
        "1", ("reference_load",), "relative uncertainty of the BEM reference", optional=True
    )
    optimum_misfit_interval: np.ndarray | None = array(
        "m", ("interval_end",), "interval from the misfit alone", optional=True
    )
    optimum_reference_shift: np.ndarray | None = array(
        "m",
        ("interval_end",),
        "optima against the reference times (1 - u), (1 + u)",
        optional=True,
    )
    optimum_kept_sample: bool | None = scalar(
        "1", "a measured resolution fitted better than the parabola's vertex", optional=True
    )
    effective_index_non_adhesive: int | None = scalar(
        "1", "index of the non-adhesive pair's least misfit", optional=True
    )
    effective_resolution_non_adhesive: float | None = scalar(
        "m", "pixel size of the non-adhesive pair's least misfit", optional=True
    )
    optimum_resolution: float | None = scalar(
        "m", "effective resolution located between the strides", optional=True
    )
    optimum_interval: np.ndarray | None = array(
        "m", ("interval_end",), "one-sigma interval of the effective resolution", optional=True
    )
    optimum_profile_interval: np.ndarray | None = array(
        "m", ("interval_end",), "profile interval over the loads' residuals", optional=True
    )
    optimum_sampling_half_width: float | None = scalar(
        "1", "ln-resolution half-width from the misfit's scatter between strides", optional=True
    )
    optimum_misfit: float | None = scalar("1", "least misfit between strides", optional=True)
    optimum_open_finer: bool | None = scalar("1", "interval open on the fine side", optional=True)
    optimum_open_coarser: bool | None = scalar(
        "1", "interval open on the coarse side", optional=True
    )
    optimum_direction: str | None = text("finer/coarser: where the data point", optional=True)
    optimum_status: int | None = scalar("1", "status of the located optimum", optional=True)
    optimum_message: str | None = text("the located optimum in one sentence", optional=True)
    optimum_asperity_density: float | None = scalar(
        "1/m^2", "eta at the located optimum", optional=True
    )
    optimum_summit_radius: float | None = scalar("m", "R at the located optimum", optional=True)
    optimum_summit_height_rms: float | None = scalar(
        "m", "sigma_s at the located optimum", optional=True
    )
    interval_asperity_density: np.ndarray | None = array(
        "1/m^2", ("interval_end",), "eta at the interval's ends", optional=True
    )
    interval_summit_radius: np.ndarray | None = array(
        "m", ("interval_end",), "R at the interval's ends", optional=True
    )
    interval_summit_height_rms: np.ndarray | None = array(
        "m", ("interval_end",), "sigma_s at the interval's ends", optional=True
    )
    optimum_real_area: np.ndarray | None = array(
        "m^2", ("normal_load",), "model A_r at the located optimum", optional=True
    )
    sampled_resolution: np.ndarray | None = array(
        "m", ("sample",), "resolutions used to locate the optimum", optional=True
    )
    sampled_misfit: np.ndarray | None = array(
        "1", ("sample",), "misfit at those resolutions", optional=True
    )

    @property
    def index(self) -> int:
        """Index of the effective resolution (same as ``effective_index``)."""
        return self.effective_index

    @property
    def roughness(self) -> statmodel.Roughness:
        """eta (1/m^2), R (m), sigma_s (m) at the effective resolution."""
        return statmodel.Roughness(
            self.asperity_density, self.summit_radius, self.summit_height_rms
        )

    @property
    def roughness_interval(self) -> list[statmodel.Roughness | None] | None:
        """eta, R, sigma_s at the (finer, coarser) ends of the optimum's interval (None
        without a located optimum; a None entry where an end is unknown, e.g. a job with one
        load, whose misfit has no scatter to size an interval from)."""
        if self.interval_summit_radius is None:
            return None
        ends: list[statmodel.Roughness | None] = []
        for j in range(2):
            values = (
                float(self.interval_asperity_density[j]),
                float(self.interval_summit_radius[j]),
                float(self.interval_summit_height_rms[j]),
            )
            ends.append(statmodel.Roughness(*values) if np.all(np.isfinite(values)) else None)
        return ends

    @property
    def interval_open(self) -> bool:
        """The optimum's interval is open on a side (its uncertainties are lower bounds)."""
        return bool(self.optimum_open_finer or self.optimum_open_coarser)

    @property
    def measured(self) -> NormalAreaCurve | None:
        """The measured A_r(F_z) when given."""
        if self.measured_normal_load is None or self.measured_real_area is None:
            return None
        return NormalAreaCurve(self.measured_normal_load, self.measured_real_area, "stored")

    @property
    def misfit(self) -> np.ndarray:
        """The misfit curve that chose the resolution."""
        if self.basis == "measured" and self.misfit_measured is not None:
            return self.misfit_measured
        return self.misfit_bem


def _model_areas(
    scan: ScanResult,
    material: statmodel.Material,
    roughness: dict[int, statmodel.Roughness],
    nominal_area: float,
    load_sets: list[np.ndarray],
    executor: Executor | None,
    progress: bool,
    adhesion_range: float | None | bool = False,
) -> tuple[list[np.ndarray], list[str]]:
    """Model A_r (m^2) per stride at each set of loads (one table per set), and the refusals.

    ``adhesion_range`` False: the JKR model (:func:`areas_at_loads`); None or h_0 (m): the model
    under the BEM's law (:func:`bem_law_areas_at_loads`: Greenwood-Williamson, Maugis-Dugdale).
    """
    n = len(scan.stride)
    if adhesion_range is False:
        function, extra, desc = areas_at_loads, (), "statistical model"
    else:
        function, extra, desc = bem_law_areas_at_loads, (adhesion_range,), "model, BEM's law"
    jobs = [
        (material, roughness[i], nominal_area, ls, *extra) for i in roughness for ls in load_sets
    ]
    results = iter(run_map(function, jobs, executor, desc=desc, progress=progress))
    tables = [np.full((n, len(ls)), np.nan) for ls in load_sets]
    messages = []
    for i in roughness:
        for table in tables:
            values, message = next(results)
            if message:
                messages.append(f"stride {int(scan.stride[i])}: {message}")
            table[i] = values
    return tables, messages


def _misfit_curve(
    area: np.ndarray, roughness: dict[int, statmodel.Roughness], reference: np.ndarray | None
) -> np.ndarray:
    """:func:`log_misfit` per stride (NaN without summits or without a reference)."""
    misfit = np.full(area.shape[0], np.nan)
    if reference is not None:
        for i in roughness:
            misfit[i] = log_misfit(area[i], reference)
    return misfit


def _quiet_tabor_parameter(roughness: statmodel.Roughness, material: statmodel.Material) -> float:
    """mu (dimensionless); its warning is reported with the validity notes instead."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return float(
            statmodel.tabor_parameter(
                roughness.summit_radius,
                material.work_of_adhesion,
                material.e_star,
                material.equilibrium_distance,
            )
        )


def _scan_roughness(scan: ScanResult) -> dict[int, statmodel.Roughness]:
    """The summit statistics (eta 1/m^2, R m, sigma_s m) of every scan entry that has summits."""
    roughness = {
        i: roughness_from_scan(scan, i) for i in range(len(scan.stride)) if has_summits(scan, i)
    }
    if not roughness:
        raise InputError(
            "surface: expected summits at some resolution of the scan, found none (a flat or "
            "too small map)"
        )
    return roughness


def _best_index(curve: np.ndarray, messages: list[str]) -> int:
    """The stride of least misfit; refuses the loads when the model carries them nowhere."""
    if not np.isfinite(curve).any():
        raise ConfigError(
            "loading.normal_loads: expected loads the statistical model can carry at some "
            "resolution of the scan, got none: " + "; ".join(messages[:3])
        )
    return int(np.nanargmin(np.where(np.isfinite(curve), curve, np.nan)))


def _bem_pairs(
    scan: ScanResult,
    material: statmodel.Material,
    roughness: dict[int, statmodel.Roughness],
    nominal_area: float,
    loads: np.ndarray,
    bem: BemReference,
    executor: Executor | None,
    progress: bool,
) -> tuple[dict, list[str]]:
    """The like-for-like pairs' fields: Greenwood-Williamson against the non-adhesive BEM, and
    the model under the BEM's law (``real_area_bem_law``) against the BEM reference."""
    law, h0 = bem_law_of(bem, material.work_of_adhesion)
    (plain,), messages = _model_areas(
        scan, material, roughness, nominal_area, [loads], executor, progress, None
    )
    fields: dict = {"bem_law": law, "bem_law_adhesion_range": h0, "real_area_non_adhesive": plain}
    if law == MAUGIS_DUGDALE:
        (with_law,), more = _model_areas(
            scan, material, roughness, nominal_area, [loads], executor, progress, h0
        )
        messages += more
    else:
        with_law = plain
    fields["real_area_bem_law"] = with_law
    fields["misfit_bem"] = _misfit_curve(
        with_law, roughness, bem.reference_fraction() * nominal_area
    )
    misfit_plain = _misfit_curve(plain, roughness, bem.contact_fraction * nominal_area)
    fields["misfit_bem_non_adhesive"] = misfit_plain
    if np.isfinite(misfit_plain).any():
        index = _best_index(misfit_plain, messages)
        fields["effective_index_non_adhesive"] = index
        fields["effective_resolution_non_adhesive"] = float(scan.resolution[index])
    return fields, messages


def _reference_relative_uncertainty(bem: BemReference) -> np.ndarray | None:
    """The BEM reference's relative uncertainty per load (1), None when not estimated."""
    u = bem.reference_fraction_uncertainty()
    if u is None:
        return None
    reference = np.asarray(bem.reference_fraction(), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(reference > 0, np.asarray(u, dtype=float) / reference, np.nan)


def statistical_model_scan(
    scan: ScanResult,
    material: statmodel.Material,
    nominal_area: float,
    normal_loads: Sequence[float],
    *,
    bem: BemReference | None = None,
    measured: NormalAreaCurve | None = None,
    surface: topo.HeightMap | None = None,
    executor: Executor | None = None,
    progress: bool = False,
) -> ResolutionChoice:
    """The statistical-model stage: A_r(F_z) of the statistical model at every resolution; the
    effective resolution.

    Parameters
    ----------
    scan : topo.ResolutionScan
        Summit statistics per stride (the resolution-scan stage).
    material : statmodel.Material
        E* (Pa), w (J/m^2), ... (lambda plays no part at delta_T = 0).
    nominal_area : float
        A_n, m^2.
    normal_loads : sequence of float
        F_z, N.
    bem : BemReference, optional
        The BEM stage result: its adhesive A_r/A_n (when run) is the reference of the model
        under its law, its non-adhesive one that of Greenwood-Williamson (module notes).
    measured : NormalAreaCurve, optional
        Measured A_r(F_z); when given it chooses the effective resolution (JKR model).
    surface : topo.HeightMap, optional
        The levelled map (m) the scan decimated: with it the least misfit is located between
        the strides, with its interval (``optimum_*`` fields,
        :mod:`~asperity.statmodel.effective_resolution`), and the effective resolution
        and its statistics are those there.
    executor : Executor, optional
        Runs the strides in parallel.

    Returns
    -------
    ResolutionChoice
    """
    if bem is None and measured is None:
        raise InputError("statistical_model_scan: expected bem= or measured=, got neither")
    loads = np.asarray(normal_loads, dtype=float)
    roughness = _scan_roughness(scan)
    area, at_measured, pairs, messages = _areas_and_pairs(
        scan, material, roughness, nominal_area, loads, bem, measured, executor, progress
    )
    misfit_measured = None
    if measured is not None:
        misfit_measured = _misfit_curve(at_measured, roughness, measured.real_area)
    basis = "measured" if measured is not None else "bem"
    misfit = misfit_measured if measured is not None else pairs["misfit_bem"]
    index = _best_index(misfit, messages)
    pull_off, pull_off_refusals = pull_off_forces(material, scan, nominal_area)
    best, effective, located = _effective_statistics(
        surface, scan, misfit, material, nominal_area, loads, measured, bem, pairs, at_measured,
        index, roughness[index],
    )  # fmt: skip
    mu, validity = _validity_at(located, best, area[index], material, nominal_area)
    located.update(_regime_fields(best, material, pairs))
    for note in validity:
        warnings.warn(note, ModelValidityWarning, stacklevel=2)
    return ResolutionChoice(
        stride=np.asarray(scan.stride),
        normal_load=loads,
        resolution=np.asarray(scan.resolution, dtype=float),
        real_area=area,
        real_area_fraction=area / nominal_area,
        pull_off=pull_off,
        basis=basis,
        effective_index=index,
        effective_stride=int(scan.stride[index]),
        effective_resolution=effective,
        asperity_density=best.asperity_density,
        summit_radius=best.summit_radius,
        summit_height_rms=best.summit_height_rms,
        tabor_parameter=mu,
        nominal_area=float(nominal_area),
        messages=messages + pull_off_refusals,
        validity=validity,
        measured_normal_load=None if measured is None else measured.normal_load,
        measured_real_area=None if measured is None else measured.real_area,
        model_real_area_at_measured=at_measured,
        misfit_measured=misfit_measured,
        **pairs,
        **located,
    )


def _areas_and_pairs(
    scan: ScanResult,
    material: statmodel.Material,
    roughness: dict[int, statmodel.Roughness],
    nominal_area: float,
    loads: np.ndarray,
    bem: BemReference | None,
    measured: NormalAreaCurve | None,
    executor: Executor | None,
    progress: bool,
) -> tuple[np.ndarray, np.ndarray | None, dict, list[str]]:
    """The model's A_r (m^2) per stride at ``loads`` (N) and at the measured loads (None
    without a measured curve), the fields paired with the BEM reference (its misfit NaN
    without one) and the messages so far."""
    load_sets = [loads] if measured is None else [loads, measured.normal_load]
    tables, messages = _model_areas(
        scan, material, roughness, nominal_area, load_sets, executor, progress
    )
    area, at_measured = tables[0], (tables[1] if measured is not None else None)
    pairs: dict = {"misfit_bem": np.full(len(scan.stride), np.nan)}
    if bem is not None:
        found, more = _bem_pairs(
            scan, material, roughness, nominal_area, loads, bem, executor, progress
        )
        pairs.update(found)
        messages += more
    return area, at_measured, pairs, messages


def _effective_statistics(
    surface: topo.HeightMap | None,
    scan: ScanResult,
    misfit: np.ndarray,
    material: statmodel.Material,
    nominal_area: float,
    loads: np.ndarray,
    measured: NormalAreaCurve | None,
    bem: BemReference | None,
    pairs: dict,
    at_measured: np.ndarray | None,
    index: int,
    at_index: statmodel.Roughness,
) -> tuple[statmodel.Roughness, float, OptimumFields]:
    """The effective statistics (eta 1/m^2, R m, sigma_s m), resolution (m) and the located
    optimum's fields: between the strides when the map is given, else at scan entry ``index``
    (statistics ``at_index``; with the BEM pairs there when a BEM reference is)."""
    located: OptimumFields = {}
    if surface is not None:
        located = _locate_optimum(
            surface, scan, misfit, material, nominal_area, loads, measured, bem, pairs,
            at_measured,
        )  # fmt: skip
    best = at_index
    effective = float(scan.resolution[index])
    if located:
        best = _located_roughness(located)
        effective = float(located["optimum_resolution"])
        located.update(_pairs_at(best, material, nominal_area, loads, pairs))
    elif bem is not None:
        located.update(_pairs_at(best, material, nominal_area, loads, pairs))
    return best, effective, located


def _located_roughness(located: OptimumFields) -> statmodel.Roughness:
    """eta (1/m^2), R (m), sigma_s (m) at the located optimum."""
    return statmodel.Roughness(
        located["optimum_asperity_density"],
        located["optimum_summit_radius"],
        located["optimum_summit_height_rms"],
    )


def _pairs_at(
    roughness: statmodel.Roughness,
    material: statmodel.Material,
    nominal_area: float,
    loads: np.ndarray,
    pairs: dict,
) -> dict:
    """The model under the BEM's law and Greenwood-Williamson at the effective resolution's
    statistics, A_r (m^2) per load (empty without a BEM)."""
    if "bem_law" not in pairs:
        return {}
    plain = bem_law_areas_at_loads(material, roughness, nominal_area, loads, None)[0]
    h0 = pairs["bem_law_adhesion_range"]
    with_law = (
        plain
        if h0 is None
        else bem_law_areas_at_loads(material, roughness, nominal_area, loads, h0)[0]
    )
    return {"effective_real_area_bem_law": with_law, "effective_real_area_non_adhesive": plain}


def _regime_fields(
    roughness: statmodel.Roughness, material: statmodel.Material, pairs: dict
) -> dict:
    """The BEM's Maugis parameter at the effective summit radius and the statement beside the
    JKR model's Tabor parameter (empty without a Maugis-Dugdale BEM)."""
    if pairs.get("bem_law") != MAUGIS_DUGDALE:
        return {}
    regime = asperity_law_regime(
        roughness.summit_radius,
        material.e_star,
        material.work_of_adhesion,
        pairs["bem_law_adhesion_range"],
        material.equilibrium_distance,
    )
    return {
        "maugis_parameter": float(regime.maugis_parameter),
        "adhesion_statement": regime.statement,
    }


def _validity_at(
    located: OptimumFields,
    stride_best: statmodel.Roughness,
    stride_area: np.ndarray,
    material: statmodel.Material,
    nominal_area: float,
) -> tuple[float, list[str]]:
    """The Tabor parameter (1) and the validity notes at the effective resolution: the located
    optimum when there is one, else the stride of least misfit."""
    area, best = stride_area, stride_best
    if "optimum_real_area" in located:
        area, best = located["optimum_real_area"], _located_roughness(located)
    mu = _quiet_tabor_parameter(best, material)
    return mu, validity_notes(np.asarray(area) / nominal_area, mu)


def _locate_optimum(
    surface: topo.HeightMap,
    scan: ScanResult,
    misfit: np.ndarray,
    material: statmodel.Material,
    nominal_area: float,
    loads: np.ndarray,
    measured: NormalAreaCurve | None,
    bem: BemReference | None,
    pairs: dict,
    at_measured: np.ndarray | None,
) -> OptimumFields:
    """The ``optimum_*`` fields: the least misfit between strides against the same reference
    as the strides (measured A_r(F_z) with the JKR model when given, else the BEM with the
    model under its law, with the BEM's uncertainty), and the JKR model's A_r (m^2) at the
    job's loads there."""
    relative = None
    if measured is not None:
        ref_loads, reference, stride_areas = measured.normal_load, measured.real_area, at_measured

        def areas(roughness: statmodel.Roughness) -> np.ndarray:
            return areas_at_loads(material, roughness, nominal_area, ref_loads)[0]

    else:
        reference = bem.reference_fraction() * nominal_area
        stride_areas, h0 = pairs["real_area_bem_law"], pairs["bem_law_adhesion_range"]
        relative = _reference_relative_uncertainty(bem)

        def areas(roughness: statmodel.Roughness) -> np.ndarray:
            return bem_law_areas_at_loads(material, roughness, nominal_area, loads, h0)[0]

    n_loads = int(np.sum(np.asarray(reference) > 0))
    fields = optimum_fields(
        surface,
        np.asarray(scan.resolution, float),
        misfit,
        n_loads,
        areas,
        reference,
        log_misfit,
        stride_areas=stride_areas,
        reference_relative_uncertainty=relative,
    )
    if fields:
        best = _located_roughness(fields)
        fields["optimum_real_area"] = areas_at_loads(material, best, nominal_area, loads)[0]
        if relative is not None:
            fields["reference_relative_uncertainty"] = np.asarray(relative, dtype=float)
    return fields


def compute_statistical_model(context: StageContext) -> ResolutionChoice:
    """The job's statistical-model stage: :func:`statistical_model_scan` against the BEM and/or
    measurement.

    Its :class:`ModelValidityWarning` is not raised here: the notes stay in ``validity`` and
    the job's verdict (:mod:`pipelines.stages.verdict`) reports them as lines, not as a traceback.
    """
    config = context.config
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        return _statistical_model_of_job(context, config)


def normal_contact_material(material: statmodel.Material | DeclaredView) -> statmodel.Material:
    """The :class:`statmodel.Material` of the normal-contact model, from the keys it reads.

    The preload (E:Fy_Greenwood with the JKR asperity laws, E:JKR_load) and the Tabor
    parameter depend on E* (Pa), w (J/m^2) and epsilon (m) only; lambda and tau0 (Pa) act under
    shear alone. They are set to 0 here, a value no normal-contact formula reads (a test holds
    the areas and pull-off forces unchanged for other values), so that this stage declares,
    and is keyed by, the three it uses.
    """
    return statmodel.Material(
        e_star=material.e_star,
        work_of_adhesion=material.work_of_adhesion,
        equilibrium_distance=material.equilibrium_distance,
        mode_mixity=0.0,
        shear_strength=0.0,
    )


def _statistical_model_of_job(
    context: StageContext, config: JobConfig | ConfigView
) -> ResolutionChoice:
    return statistical_model_scan(
        context.result(SCAN),
        normal_contact_material(config.material),
        config.loading.nominal_area,
        config.loading.normal_loads,
        bem=context.result(BEM),
        measured=context.measured.normal_area,
        surface=context.result(SURFACE).scanned_height_map(),
        executor=context.executor,
        progress=context.progress,
    )


STATISTICAL_MODEL = Stage(
    name="statistical_model",
    title="statistical model / resolution",
    attribute="resolution",
    result=ResolutionChoice,
    config=(
        "material.E_star",
        "material.work_of_adhesion",
        "material.equilibrium_distance",
        "loading.nominal_area",
        "loading.normal_loads",
        "measured.normal_area",
    ),
    inputs=(SURFACE, SCAN, BEM),
    compute=compute_statistical_model,
)
