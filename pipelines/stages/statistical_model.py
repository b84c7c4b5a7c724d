"""The statistical-model stage: the statistical model at every resolution, and the effective
resolution (Fig 12d).

For each stride of the resolution scan, the summit statistics (eta, R, sigma_s) feed
:func:`statmodel.real_area_at_loads` (E:Ar_Greenwood with the load fixed by E:Fy_Greenwood) at
the job's normal loads. The misfit of a resolution is the root mean square over loads of
ln(A_model / A_reference): a relative error, so light and heavy loads weigh the same. The
reference is the user's measured A_r(F_z) when given (the paper's choice, Section 5), otherwise
the BEM on the map (adhesive when run). The effective resolution is the one of least misfit.

Two pairs are compared when the BEM ran: the adhesive model (JKR asperities, E:JKR_load)
against the adhesive BEM (Maugis-Dugdale by default: adhesive on loading), which chooses the
effective resolution; and the non-adhesive model (w -> 0: Greenwood-Williamson) against the
non-adhesive BEM, whose own least-misfit resolution is stored beside it
(``effective_resolution_non_adhesive``) and reported, not used.
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
from asperity.pipelines.stages._optimum_resolution import OptimumFields, optimum_fields
from asperity.pipelines.stages._pull_off import has_summits, pull_off_forces, roughness_from_scan
from asperity.pipelines.stages.bem import BEM, BemReference
from asperity.pipelines.stages.surface import SCAN, SURFACE, ScanResult

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
        Model A_r (m^2) and A_r/A_n.
    misfit_bem : ndarray
        RMS ln-ratio misfit against the BEM fraction at each stride (NaN without BEM).
    pull_off : ndarray
        Pull-off force at each stride, N.
    basis : str
        What chose the effective resolution: "measured" or "bem".
    effective_index, effective_stride : int
        Index and stride of the effective resolution.
    effective_resolution : float
        Its pixel size, m.
    asperity_density, summit_radius, summit_height_rms : float
        eta (1/m^2), R (m), sigma_s (m) at the effective resolution.
    tabor_parameter : float
        mu at the effective resolution (the located optimum when there is one).
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
    misfit_bem_non_adhesive : ndarray or None
        RMS ln-ratio misfit of the non-adhesive model against the non-adhesive BEM.
    effective_index_non_adhesive : int or None
        Index of that pair's least misfit (reported beside the effective resolution).
    effective_resolution_non_adhesive : float or None
        Its pixel size, m.
    optimum_resolution : float or None
        The effective resolution between the strides (m): the least misfit located by
        :func:`statmodel.effective_resolution.locate_least_misfit` (parabola in ln resolution,
        refined on the map resampled at non-integer steps). ``effective_resolution`` and
        ``effective_stride`` stay the scan's stride of least misfit (Fig 12).
    optimum_interval : ndarray or None
        Its one-sigma interval (finer end, coarser end), m; on an open side the scan's end:
        the profile interval widened by the misfit's scatter between strides
        (:mod:`~asperity.pipelines.stages._optimum_resolution`).
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
        eta (1/m^2), R (m), sigma_s (m) at ``optimum_resolution``: the roughness the lambda
        and friction stages use.
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
    misfit_bem: np.ndarray = array("1", ("stride",), "rms ln(A_model / A_bem) over loads")
    pull_off: np.ndarray = array("N", ("stride",), "pull-off force")
    basis: str = text("what chose the effective resolution: measured or bem")
    effective_index: int = scalar("1", "index of the effective resolution")
    effective_stride: int = scalar("1", "stride of the effective resolution")
    effective_resolution: float = scalar("m", "pixel size of the effective resolution")
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
        """eta, R, sigma_s at the effective resolution: the located optimum between the
        strides when there is one, else the stride of least misfit."""
        if self.optimum_summit_radius is not None:
            return statmodel.Roughness(
                self.optimum_asperity_density,
                self.optimum_summit_radius,
                self.optimum_summit_height_rms,
            )
        return statmodel.Roughness(
            self.asperity_density, self.summit_radius, self.summit_height_rms
        )

    @property
    def roughness_interval(self) -> list[statmodel.Roughness] | None:
        """eta, R, sigma_s at the (finer, coarser) ends of the optimum's interval (None
        without a located optimum; NaN entries where an end is unknown)."""
        if self.interval_summit_radius is None:
            return None
        return [
            statmodel.Roughness(
                float(self.interval_asperity_density[j]),
                float(self.interval_summit_radius[j]),
                float(self.interval_summit_height_rms[j]),
            )
            for j in range(2)
        ]

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
    loads: np.ndarray,
    measured: NormalAreaCurve | None,
    executor: Executor | None,
    progress: bool,
) -> tuple[np.ndarray, np.ndarray | None, list[str]]:
    """Model A_r (m^2) at the loads and at the measured loads, per stride; refusals."""
    n = len(scan.stride)
    load_sets = [loads] if measured is None else [loads, measured.normal_load]
    jobs = [(material, roughness[i], nominal_area, ls) for i in roughness for ls in load_sets]
    results = iter(
        run_map(areas_at_loads, jobs, executor, desc="statistical model", progress=progress)
    )
    tables = [np.full((n, len(ls)), np.nan) for ls in load_sets]
    messages = []
    for i in roughness:
        for table in tables:
            values, message = next(results)
            if message:
                messages.append(f"stride {int(scan.stride[i])}: {message}")
            table[i] = values
    return tables[0], (tables[1] if measured is not None else None), messages


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
    """The statistical-model stage: A_r(F_z) of the statistical model at every resolution; pick the
    best one.

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
        The BEM stage result; its A_r/A_n (adhesive when run) is a reference.
    measured : NormalAreaCurve, optional
        Measured A_r(F_z); when given it chooses the effective resolution.
    surface : topo.HeightMap, optional
        The levelled map (m) the scan decimated: with it the least misfit is also located
        between the strides, with its interval (``optimum_*`` fields,
        :mod:`~asperity.pipelines.stages._optimum_resolution`).
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
    area, at_measured, messages = _model_areas(
        scan, material, roughness, nominal_area, loads, measured, executor, progress
    )
    misfit_bem = _misfit_curve(
        area, roughness, None if bem is None else bem.reference_fraction() * nominal_area
    )
    misfit_measured = None
    if measured is not None:
        misfit_measured = _misfit_curve(at_measured, roughness, measured.real_area)
    basis = "measured" if measured is not None else "bem"
    index = _best_index(misfit_measured if measured is not None else misfit_bem, messages)
    pull_off, pull_off_refusals = pull_off_forces(material, scan, nominal_area)
    best = roughness[index]
    located = {}
    if surface is not None:
        located = _locate_optimum(
            surface, scan, misfit_measured if measured is not None else misfit_bem,
            material, nominal_area, loads, measured, bem,
        )  # fmt: skip
    mu, validity = _validity_at_optimum(located, best, area[index], material, nominal_area)
    for note in validity:
        warnings.warn(note, ModelValidityWarning, stacklevel=2)
    return ResolutionChoice(
        stride=np.asarray(scan.stride),
        normal_load=loads,
        resolution=np.asarray(scan.resolution, dtype=float),
        real_area=area,
        real_area_fraction=area / nominal_area,
        misfit_bem=misfit_bem,
        pull_off=pull_off,
        basis=basis,
        effective_index=index,
        effective_stride=int(scan.stride[index]),
        effective_resolution=float(scan.resolution[index]),
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
        **located,
    )


def non_adhesive_pair(
    choice: ResolutionChoice,
    scan: ScanResult,
    material: statmodel.Material,
    bem: BemReference | None,
    executor: Executor | None = None,
) -> ResolutionChoice:
    """``choice`` with the non-adhesive pair: the model at w -> 0 (Greenwood-Williamson,
    E:Ar_Greenwood with Hertzian asperities) at every resolution against the non-adhesive BEM,
    and that pair's least-misfit resolution (stored beside the effective one, not used).
    Unchanged without a BEM or when the model is already non-adhesive."""
    if bem is None or material.work_of_adhesion == 0:
        return choice
    plain = dataclasses.replace(material, work_of_adhesion=0.0)
    roughness = _scan_roughness(scan)
    area, _, messages = _model_areas(
        scan, plain, roughness, choice.nominal_area, choice.normal_load, None, executor, False
    )
    misfit = _misfit_curve(area, roughness, bem.contact_fraction * choice.nominal_area)
    choice.real_area_non_adhesive = area
    choice.misfit_bem_non_adhesive = misfit
    if np.isfinite(misfit).any():
        index = _best_index(misfit, messages)
        choice.effective_index_non_adhesive = index
        choice.effective_resolution_non_adhesive = float(scan.resolution[index])
    return choice


def _validity_at_optimum(
    located: OptimumFields,
    stride_best: statmodel.Roughness,
    stride_area: np.ndarray,
    material: statmodel.Material,
    nominal_area: float,
) -> tuple[float, list[str]]:
    """The Tabor parameter (1) and the validity notes at the roughness the later stages use:
    the located optimum when there is one, else the stride of least misfit."""
    area = stride_area
    best = stride_best
    if located:
        area = located["optimum_real_area"]
        best = statmodel.Roughness(
            located["optimum_asperity_density"],
            located["optimum_summit_radius"],
            located["optimum_summit_height_rms"],
        )
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
) -> OptimumFields:
    """The ``optimum_*`` fields: the least misfit between strides against the same reference
    (measured A_r(F_z) when given, else the BEM), and the model's A_r (m^2) at the job's loads
    there."""
    if measured is not None:
        ref_loads, reference = measured.normal_load, measured.real_area
    else:
        ref_loads, reference = loads, bem.reference_fraction() * nominal_area
    n_loads = int(np.sum(np.asarray(reference) > 0))

    def areas(roughness: statmodel.Roughness) -> np.ndarray:
        return areas_at_loads(material, roughness, nominal_area, ref_loads)[0]

    fields = optimum_fields(
        surface, np.asarray(scan.resolution, float), misfit, n_loads, areas, reference, log_misfit
    )
    if fields:
        best = statmodel.Roughness(
            fields["optimum_asperity_density"],
            fields["optimum_summit_radius"],
            fields["optimum_summit_height_rms"],
        )
        fields["optimum_real_area"] = areas_at_loads(material, best, nominal_area, loads)[0]
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
    material = normal_contact_material(config.material)
    choice = statistical_model_scan(
        context.result(SCAN),
        material,
        config.loading.nominal_area,
        config.loading.normal_loads,
        bem=context.result(BEM),
        measured=context.measured.normal_area,
        surface=context.result(SURFACE).scanned_height_map(),
        executor=context.executor,
        progress=context.progress,
    )
    return non_adhesive_pair(
        choice, context.result(SCAN), material, context.result(BEM), context.executor
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
