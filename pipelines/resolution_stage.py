"""Stage 4: the statistical model at every resolution, and the effective resolution (Fig 12d).

For each stride of the resolution scan, the summit statistics (eta, R, sigma_s) feed
:func:`statmodel.real_area_at_loads` (E:Ar_Greenwood with the load fixed by E:Fy_Greenwood) at
the job's normal loads. The misfit of a resolution is the root mean square over loads of
ln(A_model / A_reference): a relative error, so light and heavy loads weigh the same. The
reference is the user's measured A_r(F_z) when given (the paper's choice, Section 5), otherwise
the BEM on the map (adhesive when run). The effective resolution is the one of least misfit.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from asperity import statmodel
from asperity.pipelines.bem_stage import BemReference
from asperity.pipelines.config import MaterialConfig
from asperity.pipelines.measured import NormalAreaCurve
from asperity.pipelines.parallel import run_map
from asperity.pipelines.store import StageRecord, Variable

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
    config: MaterialConfig, mode_mixity: float | None = None
) -> statmodel.Material:
    """The :class:`statmodel.Material` of the configuration (SI), optionally with another lambda."""
    return statmodel.Material(
        e_star=config.E_star,
        work_of_adhesion=config.work_of_adhesion,
        mode_mixity=config.mode_mixity if mode_mixity is None else mode_mixity,
        shear_strength=config.shear_strength,
        equilibrium_distance=config.equilibrium_distance,
    )


def roughness_from_scan(scan: Any, index: int) -> statmodel.Roughness:
    """The :class:`statmodel.Roughness` (eta 1/m^2, R m, sigma_s m) at one scan entry."""
    return statmodel.Roughness(
        asperity_density=float(scan.asperity_density[index]),
        summit_radius=float(scan.summit_radius[index]),
        summit_height_rms=float(scan.summit_height_rms[index]),
    )


def _usable(scan: Any, index: int) -> bool:
    values = (
        scan.asperity_density[index],
        scan.summit_radius[index],
        scan.summit_height_rms[index],
    )
    return all(np.isfinite(v) and v > 0 for v in values)


def pull_off_forces(material: statmodel.Material, scan: Any, nominal_area: float) -> np.ndarray:
    """Pull-off force of the statistical model at each scan resolution, N (negative)."""
    out = np.full(len(scan.stride), np.nan)
    for i in range(len(scan.stride)):
        if _usable(scan, i):
            try:
                out[i] = statmodel.pull_off_force(
                    material, roughness_from_scan(scan, i), nominal_area
                )
            except ValueError:
                pass
    return out


def check_loads_above_pull_off(
    material: statmodel.Material, scan: Any, nominal_area: float, normal_loads: Sequence[float]
) -> np.ndarray:
    """Raise ValueError naming ``loading.normal_loads`` if a load is below a pull-off force.

    Returns
    -------
    ndarray
        The pull-off force at each resolution, N.
    """
    pull_off = pull_off_forces(material, scan, nominal_area)
    worst = np.nanmax(pull_off) if np.isfinite(pull_off).any() else -math.inf
    low = [f for f in normal_loads if f <= worst]
    if low:
        i = int(np.nanargmax(pull_off))
        raise ValueError(
            f"loading.normal_loads: {low[0]:g} N is at or below the statistical model's pull-off "
            f"force {worst:.4g} N (at resolution {scan.resolution[i] * 1e6:.4g} um); every load "
            "must exceed the pull-off force"
        )
    return pull_off


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


@dataclass
class ResolutionChoice:
    """Stage-4 result.

    Attributes
    ----------
    stride, resolution : ndarray
        The scan's strides and pixel sizes (m).
    normal_load : ndarray
        F_z, N.
    real_area : ndarray, shape (n_stride, n_load)
        Model A_r, m^2.
    misfit_bem : ndarray
        RMS ln-ratio misfit against the BEM fraction at each stride (NaN without BEM).
    misfit_measured : ndarray or None
        Same against the measured A_r(F_z).
    basis : str
        What chose the effective resolution: "measured" or "bem".
    index : int
        Index of the effective resolution.
    roughness : statmodel.Roughness
        eta, R, sigma_s at the effective resolution.
    tabor_parameter : float
        mu at the effective resolution.
    pull_off : ndarray
        Pull-off force at each stride, N.
    measured : NormalAreaCurve or None
        The measured A_r(F_z) when given.
    model_at_measured : ndarray or None
        Model A_r (m^2) at the measured loads, shape (n_stride, n_measured).
    messages : list of str
        Model refusals per stride.
    validity : list of str
        Where the model is outside its validity at the effective resolution
        (:func:`validity_notes`); empty when it is not.
    """

    stride: np.ndarray
    resolution: np.ndarray
    normal_load: np.ndarray
    real_area: np.ndarray
    misfit_bem: np.ndarray
    misfit_measured: np.ndarray | None
    basis: str
    index: int
    roughness: statmodel.Roughness
    tabor_parameter: float
    pull_off: np.ndarray
    measured: NormalAreaCurve | None = None
    model_at_measured: np.ndarray | None = None
    messages: list[str] = field(default_factory=list)
    validity: list[str] = field(default_factory=list)

    @property
    def effective_stride(self) -> int:
        """Stride of the effective resolution."""
        return int(self.stride[self.index])

    @property
    def effective_resolution(self) -> float:
        """Pixel size of the effective resolution, m."""
        return float(self.resolution[self.index])

    @property
    def misfit(self) -> np.ndarray:
        """The misfit curve that chose the resolution."""
        return self.misfit_measured if self.basis == "measured" else self.misfit_bem


def statistical_model_scan(
    scan: Any,
    material: statmodel.Material,
    nominal_area: float,
    normal_loads: Sequence[float],
    *,
    bem: BemReference | None = None,
    measured: NormalAreaCurve | None = None,
    executor: Executor | None = None,
    progress: bool = False,
) -> ResolutionChoice:
    """Stage 4: A_r(F_z) of the statistical model at every resolution; pick the best one.

    Parameters
    ----------
    scan : topo.ResolutionScan
        Summit statistics per stride (stage 2).
    material : statmodel.Material
        E* (Pa), w (J/m^2), ... (lambda plays no part at delta_T = 0).
    nominal_area : float
        A_n, m^2.
    normal_loads : sequence of float
        F_z, N.
    bem : BemReference, optional
        Stage 3 result; its A_r/A_n (adhesive when run) is a reference.
    measured : NormalAreaCurve, optional
        Measured A_r(F_z); when given it chooses the effective resolution.
    executor : Executor, optional
        Runs the strides in parallel.

    Returns
    -------
    ResolutionChoice
    """
    if bem is None and measured is None:
        raise ValueError("statistical_model_scan: needs a BEM reference or a measured A_r(F_z)")
    loads = np.asarray(normal_loads, dtype=float)
    n = len(scan.stride)
    usable = [i for i in range(n) if _usable(scan, i)]
    if not usable:
        raise ValueError("statistical_model_scan: no resolution of the scan has summits")
    roughness = {i: roughness_from_scan(scan, i) for i in usable}
    load_sets = [loads] if measured is None else [loads, measured.normal_load]
    jobs = [(material, roughness[i], nominal_area, ls) for i in usable for ls in load_sets]
    results = run_map(areas_at_loads, jobs, executor, desc="statistical model", progress=progress)
    area = np.full((n, len(loads)), np.nan)
    at_measured = None if measured is None else np.full((n, len(measured.normal_load)), np.nan)
    messages = []
    k = 0
    for i in usable:
        for j, _ in enumerate(load_sets):
            values, message = results[k]
            k += 1
            if message:
                messages.append(f"stride {int(scan.stride[i])}: {message}")
            if j == 0:
                area[i] = values
            else:
                at_measured[i] = values
    misfit_bem = np.full(n, np.nan)
    if bem is not None:
        reference = bem.reference_fraction() * nominal_area
        for i in usable:
            misfit_bem[i] = log_misfit(area[i], reference)
    misfit_measured = None
    if measured is not None:
        misfit_measured = np.full(n, np.nan)
        for i in usable:
            misfit_measured[i] = log_misfit(at_measured[i], measured.real_area)
    basis = "measured" if measured is not None else "bem"
    curve = misfit_measured if measured is not None else misfit_bem
    if not np.isfinite(curve).any():
        raise ValueError(
            "statistical_model_scan: the model gave no finite misfit at any "
            "resolution: " + "; ".join(messages[:3])
        )
    index = int(np.nanargmin(np.where(np.isfinite(curve), curve, np.nan)))
    best = roughness[index]
    with warnings.catch_warnings():  # reported below, with the area check, as one warning
        warnings.simplefilter("ignore")
        mu = statmodel.tabor_parameter(
            best.summit_radius,
            material.work_of_adhesion,
            material.e_star,
            material.equilibrium_distance,
        )
    validity = validity_notes(area[index] / nominal_area, float(mu))
    for note in validity:
        warnings.warn(note, ModelValidityWarning, stacklevel=2)
    return ResolutionChoice(
        stride=np.asarray(scan.stride),
        resolution=np.asarray(scan.resolution, dtype=float),
        normal_load=loads,
        real_area=area,
        misfit_bem=misfit_bem,
        misfit_measured=misfit_measured,
        basis=basis,
        index=index,
        roughness=best,
        tabor_parameter=float(mu),
        pull_off=pull_off_forces(material, scan, nominal_area),
        measured=measured,
        model_at_measured=at_measured,
        messages=messages,
        validity=validity,
    )


def resolution_record(choice: ResolutionChoice, nominal_area: float) -> StageRecord:
    """Stage-4 record."""
    r = choice.roughness
    record = StageRecord(
        coords={
            "stride": Variable(choice.stride, "1", ("stride",), "decimation stride"),
            "normal_load": Variable(choice.normal_load, "N", ("normal_load",), "normal load"),
        },
        variables={
            "resolution": Variable(choice.resolution, "m", ("stride",), "pixel size"),
            "real_area": Variable(
                choice.real_area,
                "m^2",
                ("stride", "normal_load"),
                "statistical-model real contact area",
            ),
            "real_area_fraction": Variable(
                choice.real_area / nominal_area, "1", ("stride", "normal_load"), "A_r / A_n"
            ),
            "misfit_bem": Variable(
                choice.misfit_bem, "1", ("stride",), "rms ln(A_model / A_bem) over loads"
            ),
            "pull_off": Variable(choice.pull_off, "N", ("stride",), "pull-off force"),
        },
        attrs={
            "basis": choice.basis,
            "effective_index": choice.index,
            "effective_stride": choice.effective_stride,
            "effective_resolution": choice.effective_resolution,
            "asperity_density": r.asperity_density,
            "summit_radius": r.summit_radius,
            "summit_height_rms": r.summit_height_rms,
            "tabor_parameter": choice.tabor_parameter,
            "nominal_area": nominal_area,
            "messages": "\n".join(choice.messages),
            "validity": "\n".join(choice.validity),
        },
    )
    if choice.measured is not None:
        record.coords["measured_normal_load"] = Variable(
            choice.measured.normal_load, "N", ("measured_normal_load",), "measured normal load"
        )
        record.variables["measured_real_area"] = Variable(
            choice.measured.real_area, "m^2", ("measured_normal_load",), "measured A_r"
        )
        record.variables["model_real_area_at_measured"] = Variable(
            choice.model_at_measured,
            "m^2",
            ("stride", "measured_normal_load"),
            "model A_r at the measured loads",
        )
        record.variables["misfit_measured"] = Variable(
            choice.misfit_measured, "1", ("stride",), "rms ln(A_model / A_measured) over loads"
        )
    return record


def resolution_from_record(record: StageRecord) -> ResolutionChoice:
    """Rebuild the stage-4 result from its stored record."""
    v, a = record.variables, record.attrs
    measured = None
    if "measured_real_area" in v:
        measured = NormalAreaCurve(
            record.coords["measured_normal_load"].data, v["measured_real_area"].data, "stored"
        )
    return ResolutionChoice(
        stride=record.coords["stride"].data,
        resolution=v["resolution"].data,
        normal_load=record.coords["normal_load"].data,
        real_area=v["real_area"].data,
        misfit_bem=v["misfit_bem"].data,
        misfit_measured=v["misfit_measured"].data if measured is not None else None,
        basis=str(a["basis"]),
        index=int(a["effective_index"]),
        roughness=statmodel.Roughness(
            float(a["asperity_density"]), float(a["summit_radius"]), float(a["summit_height_rms"])
        ),
        tabor_parameter=float(a["tabor_parameter"]),
        pull_off=v["pull_off"].data,
        measured=measured,
        model_at_measured=(v["model_real_area_at_measured"].data if measured is not None else None),
        messages=[m for m in str(a.get("messages", "")).split("\n") if m],
        validity=[m for m in str(a.get("validity", "")).split("\n") if m],
    )
