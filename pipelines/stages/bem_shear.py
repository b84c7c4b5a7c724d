"""The shear BEM stage (``[bem_shear]``): the statistical model judged under shear by the BEM.

The paper's experiment on the map (Section 5, Figs 4 and 13): the normal force F_z held, the
rigid flat displaced along x up to full sliding. Each curve is
:func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`: the paper's mixed-mode
edge law G_I + lambda G_II = w (E:failure_locus) element by element, and a junction past its
instability (E:max_disp_PC) sliding with tau_0 on its non-adhesive contact (E:Hertz_theory), as
the paper's status map says. The job's E*, w, lambda (the lambda stage's) and tau_0; the loads
``bem_shear.loads``.

Like for like (the default). The model was calibrated at rest against the normal BEM
reference (the ``bem`` stage): its grid (stride) and its adhesive solve at each load (the
Maugis-Dugdale loading branch at its range h_0, or Pohrt-Popov's loading branch). The shear
BEM solves on that grid (``stride = "auto"``: the same decimation and crop,
:func:`asperity.bem.reference.load_sweeps.decimated_grid`) and starts from that state
(``preload = "reference"``): the reference's solve at F_z, its contact bonded and settled under
the mixed-mode law at delta_T = 0, where the criterion is Pohrt-Popov's. The choice: the
mixed-mode law has no cohesive zone, so its partner at rest is not the Maugis-Dugdale law
itself but the Maugis-Dugdale state; on the default map no element of that state detaches or
penetrates when it is settled, so A_r(F_x = 0) is the reference's A_r at the load, stored beside
it (``reference_area``; the verdict warns beyond 5 %, ``bem_shear_preload_mismatch``). On the
sphere (Maugis parameter 0.5, zone resolved) that state is the Maugis-Dugdale closed form's
radius (+0.5 %) and under shear reaches PC's static peak (+0.7 %) (tests/bem). The model side
is the friction stage's curves at the effective resolution. ``preload = "pohrt-popov"`` keeps
0.4's overload-unload preload (its unloading branch carries more contact).

Per load and grid: F_x(delta_T), A_r(delta_T), the stick and slip areas, the junction counts,
the static peak F_s (largest F_x before gross sliding) and where it lies, the sliding
friction F_d (F_x at the first step where every junction slides), the area drop
A_r(peak) / A_r(0) (E:NewFormulation_Ar's reduction, Fig 13), beside the model's (the friction
stage's curves at the effective resolution).

The path: ``steps`` values of delta_T up to the planned end (``max_displacement``, or
:data:`PATH_FACTOR` times the model's sliding displacement), then on with the same step while a
junction sticks, up to ``path_extension`` times the planned end; a curve stops at its first
step of full sliding; where junctions still stick at the bound, the verdict says so.

Grids: the grid used and ``check_grids`` coarser ones (strides x2, x4; fewer than
:data:`MIN_GRID_PIXELS` a side left out, with a note). The grid error of each feature is
Richardson's extrapolation with Roache's grid convergence index over them (formal order 1;
three grids give the observed order), ``|f - f_extrapolated| + GCI``: the band holds the
extrapolated value and the spread of the grids. Decimated grids carry less roughness as well
as larger elements, so the band also holds roughness the coarser grid misses: conservative.
A check grid whose Pohrt-Popov preload sits on its overloaded rim (:data:`RIM_REFUSED`) is
path-dependent and left out; the reference preload is a monotone loading path (rim 0).

Forces and areas are solved on the map and stored scaled to the nominal area A_n of the
experiment (F A_n / A_map, as the BEM reference stage does with the loads), so that they
compare with the model's directly; junction counts are those of the map.

Limits (docs/bem_shear.md): linear elasticity, quasi-static, the mesh-dependent edge law,
nu = 1/2.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from asperity import statmodel, topo
from asperity.bem.errors import BemInputError
from asperity.bem.options import SolverOptions
from asperity.bem.reference.discretisation import richardson_extrapolation
from asperity.bem.reference.load_sweeps import (
    ContactSetup,
    Grid,
    decimated_grid,
    solve_adhesive_loading,
    solve_non_adhesive,
)
from asperity.bem.result import ContactResult
from asperity.bem.shear.mixed_mode import MixedModeLaw
from asperity.bem.shear.rough import ShearCurve
from asperity.bem.shear.rough_mixed_mode import RIM_TOLERANCE, mixed_mode_shear_curve
from asperity.bem.shear.stick_slip import ShearOptions
from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.config import BemShearConfig
from asperity.pipelines.engine.parallel import run_map, worker_threads
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.stages.bem import BEM, BemReference
from asperity.pipelines.stages.friction import FRICTION, MODE_MIXITY, FrictionPrediction
from asperity.pipelines.stages.surface import SURFACE
from asperity.statmodel.plausibility import Threshold

__all__ = [
    "BEM_SHEAR",
    "PATH_FACTOR",
    "SHEAR_THRESHOLDS",
    "BemShearComparison",
    "bem_shear_comparison",
    "compute_bem_shear",
    "curve_features",
]

#: ``max_displacement = "auto"``: the path ends at this multiple of the model's sliding
#: displacement at the load (the BEM's junctions may slide later than the model's: the
#: static peak and the start of full sliding both inside the path on the default surface).
PATH_FACTOR = 2.0

#: Fewest pixels per side of the coarsest grid solved (a few junctions of a few elements).
MIN_GRID_PIXELS = 16

#: The shear BEM's verdict thresholds, with their reasons (the style of
#: :data:`asperity.statmodel.plausibility.THRESHOLDS`): read by
#: :func:`asperity.pipelines.stages.verdict.check_bem_shear`.
SHEAR_THRESHOLDS: dict[str, Threshold] = {
    t.code: t
    for t in (
        Threshold(
            "bem_shear_stall",
            "steps that did not converge / steps",
            0.0,
            0.0,
            "a shear step whose active set or conjugate gradients did not settle is not an "
            "equilibrium: the curve after it is not a result",
        ),
        Threshold(
            "bem_shear_no_sliding",
            "junctions still sticking at the last delta_T (grid used)",
            0.0,
            math.inf,
            "full sliding not reached within the path, extended to bem_shear.path_extension "
            "times its planned end: the BEM's sliding friction there is not a result and its "
            "static peak may lie beyond the path (raise bem_shear.path_extension or "
            "bem_shear.max_displacement)",
        ),
        Threshold(
            "bem_shear_preload_mismatch",
            "max over loads of |A_r(F_x = 0) / A_r(reference) - 1| (grid used)",
            0.05,
            math.inf,
            "the shear BEM's contact before shear differs from the normal BEM reference's at "
            "the same load by more than 5 %: the shear judgement does not start from the state "
            "the model was calibrated on (bem_shear.preload, bem_shear.stride)",
        ),
        Threshold(
            "bem_shear_model_misfit",
            "max over loads of |ln(F_s model / F_s BEM)| beyond the BEM's grid error",
            0.7,
            math.inf,
            "the model's static friction differs from the BEM's by more than a factor 2 at a "
            "load, more than the BEM's two grids differ: the independent-asperity model misses "
            "the shear response of the map (a warning: the BEM's own edge law is mesh-dependent)",
        ),
    )
}


@document_fields
@dataclass
class BemShearComparison:
    """The shear BEM against the statistical model (SI; forces and areas scaled to A_n).

    Dimensions: ``grid`` (0 the grid used, then the check grids x2, x4 coarser, when run),
    ``normal_load`` (the loads sheared), ``step`` (delta_T; NaN past a curve's last step, a
    curve stops at the first step where every junction slides).

    Attributes
    ----------
    normal_load : ndarray
        Experiment loads F_z, N.
    grid_stride, grid_pixel_size, map_area : ndarray
        Per grid: decimation of the map, pixel size (m), area of the map solved (m^2).
    map_normal_load : ndarray, shape (grid, normal_load)
        F_z A_map / A_n, N: the load on the map.
    tangential_displacement : ndarray, shape (normal_load, step)
        delta_T, m (one path per load, both grids).
    tangential_force, real_area, stick_area, slip_area : ndarray, shape (grid, normal_load, step)
        F_x (N) and A_r with its adhesive-stick and sliding parts (m^2), scaled to A_n.
    junctions, sliding_junctions : ndarray, shape (grid, normal_load, step)
        Contact clusters on the map, and those that slide.
    static_friction, static_displacement : ndarray, shape (grid, normal_load)
        F_s (N, scaled) and its delta_T (m): the largest F_x before gross sliding.
    sliding_friction, sliding_displacement : ndarray, shape (grid, normal_load)
        F_x (N, scaled) and delta_T (m) at the first step where every junction slides; NaN
        where none does.
    area_drop : ndarray, shape (grid, normal_load)
        A_r(peak) / A_r(0).
    stuck_junctions : ndarray, shape (grid, normal_load)
        Junctions still sticking at the last step (0: full sliding reached).
    converged : ndarray of bool, shape (grid, normal_load)
        Every step of the curve converged.
    model_static_friction, model_sliding_friction, model_area_drop : ndarray
        The statistical model's F_s, F_d (N) and A_r(peak) / A_r(0) at each load (the friction
        stage's curves).
    static_friction_error, sliding_friction_error, area_drop_error : ndarray or None
        The grid error of the grid used per load (module notes: Richardson and Roache's GCI
        over the grids solved); None without ``grid_check``; NaN where fewer than two grids
        have the feature.
    static_friction_error_order, sliding_friction_error_order, area_drop_error_order
        The order p each error used (observed from three grids and bounded, or 1 assumed).
    grid_error_messages : list of str
        How each error was estimated.
    preload : str
        The state before shear, in words (``bem_shear.preload``).
    preload_rim_fraction : ndarray, shape (grid, normal_load)
        Share of the bonded contact before shear on the rim of a Pohrt-Popov preload's
        overloaded contact (0 for the reference's monotone loading state).
    reference_stride : int
        The normal BEM reference's stride (0: none in the run).
    reference_area, reference_area_uncertainty : ndarray or None
        The reference's adhesive A_r at the loads sheared and its stated uncertainty (m^2,
        scaled to A_n): the partner of ``real_area[0, :, 0]``.
    planned_displacement : ndarray
        The planned end of each path (m); it extends past it while junctions stick, up to
        ``bem_shear.path_extension`` times it.
    """

    normal_load: np.ndarray = array("N", ("normal_load",), "experiment normal load sheared")
    grid_stride: np.ndarray = array("1", ("grid",), "decimation of the map per grid")
    grid_pixel_size: np.ndarray = array("m", ("grid",), "pixel size per grid")
    map_area: np.ndarray = array("m^2", ("grid",), "area of the map solved")
    map_normal_load: np.ndarray = array(
        "N", ("grid", "normal_load"), "load on the map, F_z A_map / A_n"
    )
    tangential_displacement: np.ndarray = array(
        "m", ("normal_load", "step"), "tangential displacement delta_T of the flat"
    )
    tangential_force: np.ndarray = array(
        "N", ("grid", "normal_load", "step"), "BEM F_x scaled to A_n"
    )
    real_area: np.ndarray = array("m^2", ("grid", "normal_load", "step"), "BEM A_r scaled to A_n")
    stick_area: np.ndarray = array(
        "m^2", ("grid", "normal_load", "step"), "BEM adhesive (sticking) area scaled to A_n"
    )
    slip_area: np.ndarray = array(
        "m^2", ("grid", "normal_load", "step"), "BEM sliding contact area scaled to A_n"
    )
    junctions: np.ndarray = array(
        "1", ("grid", "normal_load", "step"), "contact clusters on the map"
    )
    sliding_junctions: np.ndarray = array(
        "1", ("grid", "normal_load", "step"), "sliding contact clusters on the map"
    )
    static_friction: np.ndarray = array("N", ("grid", "normal_load"), "BEM static peak F_s")
    static_displacement: np.ndarray = array("m", ("grid", "normal_load"), "delta_T at F_s")
    sliding_friction: np.ndarray = array(
        "N", ("grid", "normal_load"), "BEM F_x at full sliding (NaN: not reached)"
    )
    sliding_displacement: np.ndarray = array(
        "m", ("grid", "normal_load"), "delta_T at full sliding (NaN: not reached)"
    )
    area_drop: np.ndarray = array("1", ("grid", "normal_load"), "BEM A_r(peak) / A_r(0)")
    stuck_junctions: np.ndarray = array(
        "1", ("grid", "normal_load"), "junctions still sticking at the last step"
    )
    converged: np.ndarray = array("1", ("grid", "normal_load"), "every step converged")
    steps_solved: np.ndarray = array("1", ("grid", "normal_load"), "delta_T steps solved")
    preload_seconds: np.ndarray = array("s", ("grid", "normal_load"), "wall time of the preload")
    curve_seconds: np.ndarray = array("s", ("grid", "normal_load"), "wall time of the shear steps")
    convolutions: np.ndarray = array(
        "1", ("grid", "normal_load"), "FFT conjugate-gradient iterations of the shear steps"
    )
    model_static_friction: np.ndarray = array("N", ("normal_load",), "model static friction")
    model_sliding_friction: np.ndarray = array("N", ("normal_load",), "model sliding friction")
    model_static_displacement: np.ndarray = array(
        "m", ("normal_load",), "model delta_T at its largest F_x"
    )
    model_sliding_displacement: np.ndarray = array(
        "m", ("normal_load",), "model delta_T at full sliding"
    )
    model_area_drop: np.ndarray = array("1", ("normal_load",), "model A_r(peak) / A_r(0)")
    e_star: float = scalar("Pa", "reduced modulus E*")
    work_of_adhesion: float = scalar("J/m^2", "work of adhesion w")
    mode_mixity: float = scalar("1", "mode mixity lambda (the lambda stage's)")
    shear_strength: float = scalar("Pa", "shear strength tau_0 of a sliding junction")
    nominal_area: float = scalar("m^2", "nominal contact area A_n")
    law: str = text("chi_T of the mixed-mode law: pc or cerruti")
    boundary: str = text("periodic or free")
    messages: list[str] = text("messages of curves that did not converge")
    warnings: list[str] = text("warnings of the solves (preload on the loaded rim)")
    preload: str = text(
        "the state before shear", default_factory=lambda: "pohrt-popov overload-unload"
    )
    reference_stride: int = scalar("1", "stride of the BEM reference (0: none)", default=0)
    reference_area: np.ndarray | None = array(
        "m^2", ("normal_load",), "BEM reference's adhesive A_r scaled to A_n", optional=True
    )
    reference_area_uncertainty: np.ndarray | None = array(
        "m^2", ("normal_load",), "its stated uncertainty", optional=True
    )
    preload_rim_fraction: np.ndarray | None = array(
        "1",
        ("grid", "normal_load"),
        "bonded elements before shear on the rim of the overloaded contact / bonded (0: a "
        "monotone loading preload)",
        optional=True,
    )
    planned_displacement: np.ndarray | None = array(
        "m",
        ("normal_load",),
        "planned end of the path (it extends while junctions stick)",
        optional=True,
    )
    grid_error_messages: list[str] = text("how each grid error was estimated", default_factory=list)
    static_friction_error: np.ndarray | None = array(
        "N", ("normal_load",), "grid error of F_s (Richardson + GCI)", optional=True
    )
    sliding_friction_error: np.ndarray | None = array(
        "N", ("normal_load",), "grid error of F_d (Richardson + GCI)", optional=True
    )
    area_drop_error: np.ndarray | None = array(
        "1", ("normal_load",), "grid error of the area drop (Richardson + GCI)", optional=True
    )
    static_friction_error_order: np.ndarray | None = array(
        "1", ("normal_load",), "order p of the F_s grid error", optional=True
    )
    sliding_friction_error_order: np.ndarray | None = array(
        "1", ("normal_load",), "order p of the F_d grid error", optional=True
    )
    area_drop_error_order: np.ndarray | None = array(
        "1", ("normal_load",), "order p of the area-drop grid error", optional=True
    )
    all_converged: bool = scalar("1", "every shear step converged", init=False)

    def __post_init__(self) -> None:
        self.all_converged = bool(np.all(self.converged))

    def table(self) -> list[dict[str, float]]:
        """Per load: F_z, BEM and model F_s, F_d (N) and area drop, with the BEM's grid error
        (NaN without a check grid): the rows of the BEM-vs-model table."""
        nan = np.full(self.normal_load.shape, np.nan)
        errors = {
            "static_friction": self.static_friction_error,
            "sliding_friction": self.sliding_friction_error,
            "area_drop": self.area_drop_error,
        }
        rows = []
        for i, f in enumerate(self.normal_load):
            row = {"normal_load": float(f)}
            for name, error in errors.items():
                row[f"bem_{name}"] = float(getattr(self, name)[0, i])
                row[f"bem_{name}_error"] = float((nan if error is None else error)[i])
                row[f"model_{name}"] = float(getattr(self, f"model_{name}")[i])
            rows.append(row)
        return rows


def curve_features(
    displacement: np.ndarray,
    force: np.ndarray,
    area: np.ndarray,
    sliding: np.ndarray,
) -> dict[str, float]:
    """The static peak, sliding state and area drop of one shear curve (SI).

    Parameters
    ----------
    displacement, force, area : ndarray
        delta_T (m), F_x (N), A_r (m^2) per step.
    sliding : ndarray of bool
        Every junction slides at the step.

    Returns
    -------
    dict
        ``static_friction`` (largest F_x before the first gross-sliding step; over the whole
        curve when none slides), ``static_displacement``, ``sliding_friction`` and
        ``sliding_displacement`` (at the first gross-sliding step; NaN when none),
        ``area_drop`` = A_r(peak) / A_r(0).
    """
    sliding = np.asarray(sliding, dtype=bool)
    slid = np.flatnonzero(sliding)
    end = int(slid[0]) if slid.size else sliding.size
    before = slice(0, max(end, 1))
    peak = int(np.argmax(force[before]))
    return {
        "static_friction": float(force[peak]),
        "static_displacement": float(displacement[peak]),
        "sliding_friction": float(force[end]) if slid.size else math.nan,
        "sliding_displacement": float(displacement[end]) if slid.size else math.nan,
        "area_drop": float(area[peak] / area[0]) if area[0] > 0 else math.nan,
    }


def _preload_state(grid: Grid, map_load: float, setup: ContactSetup) -> ContactResult:
    """The BEM reference's adhesive state at ``map_load`` (N) on ``grid``, made as the
    reference makes it with its ``setup`` (:func:`~asperity.bem.reference.load_sweeps.
    solve_non_adhesive`, then :func:`~asperity.bem.reference.load_sweeps.
    solve_adhesive_loading` from it: the loading branch)."""
    plain = solve_non_adhesive(grid, setup, map_load)
    state = solve_adhesive_loading(grid, setup, plain, map_load)
    for r in (plain, state):
        if not r.converged:
            raise BemInputError(f"preload (the reference's solve) did not converge: {r.message}")
    return state


def _solve_curve(
    grid: Grid,
    map_load: float,
    path: np.ndarray,
    material: statmodel.Material,
    law: str,
    tol: float,
    periodic: bool,
    preload: ContactSetup | None,
) -> dict:
    """One load on one grid (a worker job): the curve on the map, its warnings and time;
    ``material`` gives E* (Pa), w (J/m^2), lambda and tau_0 (Pa); ``preload`` the reference's
    solve set-up (the state before shear is its loading branch), None: the Pohrt-Popov
    overload-unload preload."""
    heights = grid.heights - grid.heights.mean()
    options = ShearOptions(tol=tol, threads=worker_threads())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        initial = None
        if preload is not None:
            initial = _preload_state(dataclasses.replace(grid, heights=heights), map_load, preload)
        curve = mixed_mode_shear_curve(
            heights,
            grid.dx,
            grid.dy,
            material.e_star,
            map_load,
            path,
            MixedModeLaw(material.work_of_adhesion, material.mode_mixity, tangential_energy=law),
            shear_strength=material.shear_strength,
            periodic=periodic,
            normal_options=SolverOptions(tol=tol),
            options=options,
            stop_when_sliding=True,
            initial=initial,
        )
        seconds = time.perf_counter() - t0
    if initial is not None:
        curve = dataclasses.replace(curve, normal_seconds=seconds - float(np.sum(curve.seconds)))
    notes = []
    for c in caught:  # the preload's own warnings are the stage's record; others go on
        if str(c.message).startswith("preload"):
            notes.append(str(c.message))
        else:
            warnings.warn_explicit(c.message, c.category, c.filename, c.lineno)
    return {
        "curve": dataclasses.replace(curve, final_traction=np.zeros(0)),
        "warnings": notes,
        "seconds": seconds,
    }


def _model_features(friction: FrictionPrediction, index: int) -> dict[str, float]:
    """The model's F_s, F_d (N), their delta_T (m) and area drop at load ``index``."""
    force = np.asarray(friction.tangential_force[index], dtype=float)
    area = np.asarray(friction.real_area[index], dtype=float)
    shift = np.asarray(friction.tangential_displacement[index], dtype=float)
    peak = int(np.nanargmax(force))
    return {
        "static_friction": float(friction.static_friction[index]),
        "sliding_friction": float(friction.sliding_friction[index]),
        "static_displacement": float(shift[peak]),
        "sliding_displacement": float(friction.sliding_displacement[index]),
        "area_drop": float(area[peak] / area[0]) if area[0] > 0 else math.nan,
    }


def _model_fields(friction: FrictionPrediction, index: list[int]) -> dict[str, np.ndarray]:
    """The comparison's ``model_*`` arrays at the loads sheared (their indices among the
    friction stage's): F_s, F_d (N), their delta_T (m), the area drop."""
    model = [_model_features(friction, i) for i in index]
    names = (
        "static_friction",
        "sliding_friction",
        "static_displacement",
        "sliding_displacement",
        "area_drop",
    )
    return {f"model_{name}": np.array([m[name] for m in model]) for name in names}


def _path_end(friction: FrictionPrediction, index: int, settings: BemShearConfig) -> float:
    """The last delta_T (m) at load ``index``: the configured one, else :data:`PATH_FACTOR`
    times the model's sliding displacement (the model's own path end where it has none)."""
    if settings.max_displacement is not None:
        return float(settings.max_displacement)
    slide = float(friction.sliding_displacement[index])
    if math.isfinite(slide) and slide > 0:
        return PATH_FACTOR * slide
    return float(np.nanmax(friction.tangential_displacement[index]))


def _path(friction: FrictionPrediction, index: int, settings: BemShearConfig) -> np.ndarray:
    """delta_T values (m) of load ``index``: ``steps`` up to the planned end
    (:func:`_path_end`), then on with the same step up to ``path_extension`` times it (the
    curve stops at the first step where every junction slides)."""
    end = _path_end(friction, index, settings)
    step = end / (settings.steps - 1)
    extra = int(math.ceil((settings.path_extension - 1.0) * (settings.steps - 1) - 1e-9))
    return step * np.arange(settings.steps + max(extra, 0), dtype=float)


def _padded(values: np.ndarray, steps: int) -> np.ndarray:
    out = np.full(steps, np.nan)
    out[: values.size] = values
    return out


def bem_shear_comparison(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    mode_mixity: float,
    shear_strength: float,
    nominal_area: float,
    friction: FrictionPrediction,
    settings: BemShearConfig,
    *,
    reference: BemReference | None = None,
    periodic: bool = True,
    executor: Executor | None = None,
    progress: bool = False,
) -> BemShearComparison:
    """Shear curves of the map by the BEM at each load, beside the statistical model's.

    Like for like (module notes): by default on the BEM reference's grid (its stride, the
    same decimation and crop) from the reference's own adhesive state at each load.

    Parameters
    ----------
    surface : topo.HeightMap
        Levelled map, heights in m (larger = closer to the flat).
    e_star, work_of_adhesion, mode_mixity, shear_strength : float
        E* (Pa), w (J/m^2), lambda, tau_0 (Pa): the model's.
    nominal_area : float
        A_n of the experiment, m^2 (loads are scaled to the map by A_map / A_n, forces and
        areas back by A_n / A_map).
    friction : FrictionPrediction
        The model's shear curves (the friction stage), at least at ``settings.loads``.
    settings : BemShearConfig
        The ``[bem_shear]`` table.
    reference : BemReference, optional
        The normal BEM reference (the ``bem`` stage): its stride (``stride = "auto"``), its
        adhesion law (``preload = "reference"``) and its A_r at the loads (the comparison of
        A_r(F_x = 0)). Needed unless ``stride`` is given and ``preload = "pohrt-popov"``.
    periodic : bool
        Periodic map (the BEM reference's ``bem.boundary``) or free.
    executor : Executor, optional
        Runs the curves (one per grid and load) in parallel.

    Raises
    ------
    InputError
        A load not among the friction stage's, a grid used of fewer than
        :data:`MIN_GRID_PIXELS` pixels a side (``bem_shear.stride``), or no reference where
        one is needed.
    """
    if work_of_adhesion <= 0:
        raise InputError(
            "material.work_of_adhesion: the shear BEM's mixed-mode law needs w > 0 (J/m^2), got "
            f"{work_of_adhesion}"
        )
    loads, index = _loads_and_model_index(friction, settings)
    strides, grids, notes = _grids(surface, settings, reference)
    material = statmodel.Material(e_star, work_of_adhesion, mode_mixity, shear_strength)
    preload = _preload_setup(settings, reference, material, periodic)
    paths = np.array([_path(friction, i, settings) for i in index])
    map_area = np.array([g.area for g in grids])
    jobs = [
        (grid, float(f) * map_area[g] / nominal_area, paths[j], material, settings.law,
         settings.tol, periodic, preload)
        for g, grid in enumerate(grids)
        for j, f in enumerate(loads)
    ]  # fmt: skip
    solved = run_map(_solve_curve, jobs, executor, desc="BEM shear curves", progress=progress)
    fields = _collect_curves(solved, loads, strides, nominal_area / map_area, paths.shape[1])
    fields["warnings"] = notes + fields["warnings"]
    errors = _grid_errors(fields, np.array([g.dx for g in grids]))
    return BemShearComparison(
        normal_load=loads,
        grid_stride=np.asarray(strides, dtype=int),
        grid_pixel_size=np.array([g.dx for g in grids]),
        map_area=map_area,
        map_normal_load=map_area[:, None] * loads[None, :] / nominal_area,
        tangential_displacement=paths,
        planned_displacement=np.array([_path_end(friction, i, settings) for i in index]),
        **fields,
        **_model_fields(friction, index),
        e_star=float(e_star),
        work_of_adhesion=float(work_of_adhesion),
        mode_mixity=float(mode_mixity),
        shear_strength=float(shear_strength),
        nominal_area=float(nominal_area),
        law=settings.law,
        boundary="periodic" if periodic else "free",
        preload=_preload_text(settings, reference),
        **_reference_fields(reference, loads, nominal_area),
        **errors,
    )


def _preload_setup(
    settings: BemShearConfig,
    reference: BemReference | None,
    material: statmodel.Material,
    periodic: bool,
) -> ContactSetup | None:
    """The reference's solve set-up for the preload (``preload = "reference"``: its
    Maugis-Dugdale range h_0, m, or Pohrt-Popov's criterion where it made no Maugis solve;
    E*, w and ``bem_shear.tol``), None for the Pohrt-Popov overload-unload preload; an
    InputError without a reference."""
    if settings.preload != "reference":
        return None
    if reference is None:
        raise InputError(
            'bem_shear.preload: "reference" needs the BEM reference stage (bem.enabled = true); '
            'got no reference: set bem_shear.preload = "pohrt-popov" and a bem_shear.stride'
        )
    h0 = float(reference.adhesion_range) if reference.adhesion == "maugis" else None
    return ContactSetup(
        material.e_star, material.work_of_adhesion, SolverOptions(tol=settings.tol), periodic,
        adhesion_range=h0,
    )  # fmt: skip


def _preload_text(settings: BemShearConfig, reference: BemReference | None) -> str:
    """How the state before shear was made, in words."""
    if settings.preload != "reference":
        return "pohrt-popov overload-unload"
    if reference is not None and reference.adhesion == "maugis":
        return (
            f"the reference's Maugis-Dugdale loading branch (h_0 = "
            f"{float(reference.adhesion_range):.3g} m)"
        )
    return "the reference's Pohrt-Popov loading branch"


def _reference_fields(
    reference: BemReference | None, loads: np.ndarray, nominal_area: float
) -> dict:
    """The reference's stride and its adhesive A_r (m^2, scaled to A_n) +- its stated
    uncertainty at the loads sheared (NaN where it has none)."""
    nan = np.full(loads.shape, np.nan)
    if reference is None:
        return {"reference_stride": 0, "reference_area": nan, "reference_area_uncertainty": nan}
    ref_loads = np.asarray(reference.normal_load, dtype=float)
    mode = 1 if reference.contact_fraction_adhesive is not None else 0
    fraction = reference.contact_fraction_adhesive if mode else reference.contact_fraction
    band = reference.contact_fraction_uncertainty
    area, error = nan.copy(), nan.copy()
    for j, f in enumerate(loads):
        match = np.flatnonzero(np.isclose(ref_loads, f, rtol=1e-9, atol=0.0))
        if match.size:
            area[j] = float(np.asarray(fraction)[match[0]]) * nominal_area
            if band is not None:
                error[j] = float(np.asarray(band)[mode, match[0]]) * nominal_area
    return {
        "reference_stride": int(reference.stride),
        "reference_area": area,
        "reference_area_uncertainty": error,
    }


def _loads_and_model_index(
    friction: FrictionPrediction, settings: BemShearConfig
) -> tuple[np.ndarray, list[int]]:
    """The loads to shear (N; ``settings.loads`` or all the friction stage's) and the index of
    each among the friction stage's loads (an InputError names a load that is not one)."""
    model_loads = np.asarray(friction.normal_load, dtype=float)
    loads = np.asarray(settings.loads if settings.loads else model_loads, dtype=float)
    index = []
    for f in loads:
        match = np.flatnonzero(np.isclose(model_loads, f, rtol=1e-9, atol=0.0))
        if not match.size:
            raise InputError(f"bem_shear.loads: {f} N is not a load of the friction stage")
        index.append(int(match[0]))
    return loads, index


def _grids(
    surface: topo.HeightMap, settings: BemShearConfig, reference: BemReference | None
) -> tuple[list[int], list[Grid], list[str]]:
    """The strides solved (the grid used: ``stride``, or the reference's; then x2, x4, ...
    for ``check_grids``), their grids (the reference's decimation and crop,
    :func:`asperity.bem.reference.load_sweeps.decimated_grid`), and notes on the check grids
    left out for having fewer than :data:`MIN_GRID_PIXELS` a side; an InputError when the
    grid used has fewer, or when ``stride = "auto"`` has no reference."""
    stride = settings.stride
    if stride is None:
        if reference is None:
            raise InputError(
                'bem_shear.stride: "auto" is the BEM reference\'s stride and needs the BEM '
                "reference stage (bem.enabled = true); got no reference: give a stride"
            )
        stride = int(reference.stride)
    heights = np.asarray(surface.heights, dtype=np.float64)
    strides, grids, notes = [], [], []
    for k in range(settings.coarser_grids + 1):
        s = stride * 2**k
        grid = decimated_grid(heights, surface.dx, surface.dy, s)
        if min(grid.heights.shape) >= MIN_GRID_PIXELS:
            strides.append(s)
            grids.append(grid)
        elif k == 0:
            raise InputError(
                f"bem_shear.stride: expected a stride leaving at least {MIN_GRID_PIXELS} pixels "
                f"a side ({surface.nx} x {surface.ny} map), got {s}"
            )
        else:
            notes.append(
                f"check grid at stride {s} left out: fewer than {MIN_GRID_PIXELS} pixels a side"
            )
    return strides, grids, notes


#: Per-step fields of :class:`BemShearComparison` (grid, load, step).
PER_STEP_FIELDS = (
    "tangential_force",
    "real_area",
    "stick_area",
    "slip_area",
    "junctions",
    "sliding_junctions",
)
#: Per-curve features (grid, load), from :func:`curve_features`.
FEATURE_FIELDS = (
    "static_friction",
    "static_displacement",
    "sliding_friction",
    "sliding_displacement",
    "area_drop",
)


def _collect_curves(
    solved: list[dict], loads: np.ndarray, strides: list[int], scale: np.ndarray, steps: int
) -> dict:
    """The solved curves (grid-major, then load) as the comparison's arrays: forces and areas
    scaled to A_n (``scale`` = A_n / A_map per grid), features, solver records, messages."""
    shape = (len(strides), loads.size)
    out: dict = {name: np.full((*shape, steps), np.nan) for name in PER_STEP_FIELDS}
    out |= {name: np.full(shape, np.nan) for name in FEATURE_FIELDS}
    out |= {
        "stuck_junctions": np.zeros(shape, dtype=int),
        "converged": np.zeros(shape, dtype=bool),
        "steps_solved": np.zeros(shape, dtype=int),
        "preload_seconds": np.zeros(shape),
        "curve_seconds": np.zeros(shape),
        "convolutions": np.zeros(shape, dtype=int),
        "preload_rim_fraction": np.zeros(shape),
        "messages": [],
        "warnings": [],
    }
    for k, solution in enumerate(solved):
        g, j = divmod(k, loads.size)
        where = f"F_z = {loads[j]:.4g} N, stride {strides[g]}"
        _store_curve(out, (g, j), solution["curve"], scale[g], steps, where)
        out["warnings"] += [f"{where}: {w}" for w in dict.fromkeys(solution["warnings"])]
    return out


def _store_curve(
    out: dict, at: tuple[int, int], curve: ShearCurve, scale: float, steps: int, where: str
) -> None:
    """One curve's steps, features and solver records into ``out`` at (grid, load)."""
    values = {
        "tangential_force": curve.tangential_force * scale,
        "real_area": curve.real_area * scale,
        "stick_area": curve.stick_area * scale,
        "slip_area": curve.slip_area * scale,
        "junctions": curve.junctions.astype(float),
        "sliding_junctions": curve.sliding_junctions.astype(float),
    }
    for name, v in values.items():
        out[name][at] = _padded(np.asarray(v, dtype=float), steps)
    found = curve_features(
        curve.tangential_displacement, values["tangential_force"], values["real_area"],
        curve.sliding,
    )  # fmt: skip
    for name, v in found.items():
        out[name][at] = v
    out["stuck_junctions"][at] = int(curve.junctions[-1] - curve.sliding_junctions[-1])
    out["converged"][at] = bool(np.all(curve.converged))
    out["steps_solved"][at] = curve.tangential_displacement.size
    out["preload_seconds"][at] = curve.normal_seconds
    out["curve_seconds"][at] = float(np.sum(curve.seconds))
    out["convolutions"][at] = int(np.sum(curve.convolutions))
    rim = curve.preload_rim_fraction
    out["preload_rim_fraction"][at] = math.nan if rim is None else float(rim)
    if not out["converged"][at]:
        first = int(np.flatnonzero(~np.asarray(curve.converged))[0])
        out["messages"].append(
            f"{where}: step {first} (delta_T = {curve.tangential_displacement[first]:.4g} m) "
            "did not converge"
        )


#: A check grid whose Pohrt-Popov preload has more than this share of its bonded contact on
#: the loaded rim depends on the path (:data:`RIM_TOLERANCE` is the preload's own goal): its
#: difference from the grid used is not a discretisation error, and it is left out.
RIM_REFUSED = 5 * RIM_TOLERANCE


def _grid_errors(fields: dict, pixel_size: np.ndarray) -> dict:
    """The grid error of each judged feature per load (same unit as the feature): from the
    grid used and the coarser ones, Richardson's extrapolation with Roache's grid convergence
    index (:func:`asperity.bem.reference.discretisation.richardson_extrapolation`, formal
    order 1: three grids give the observed order, two assume it with safety factor 3); the
    error is ``|f_used - f_extrapolated| + GCI``, so the band f_used +- error holds the
    whole GCI band. Check grids whose preload depends on the path (:data:`RIM_REFUSED`) or
    whose feature is NaN are left out; NaN with the grid used alone. Empty with one grid."""
    if pixel_size.size < 2:
        return {}
    rim = np.asarray(fields["preload_rim_fraction"])
    out: dict = {"grid_error_messages": []}
    for name in ("static_friction", "sliding_friction", "area_drop"):
        values = np.asarray(fields[name])
        error = np.full(values.shape[1], np.nan)
        order = np.full(values.shape[1], np.nan)
        for j in range(values.shape[1]):
            keep = [0] + [
                g
                for g in range(1, values.shape[0])
                if math.isfinite(values[g, j]) and not rim[g, j] > RIM_REFUSED
            ]
            if len(keep) < 2 or not math.isfinite(values[0, j]):
                continue
            ext = richardson_extrapolation(pixel_size[keep], values[keep, j], formal_order=1.0)
            error[j] = ext.finest_error
            order[j] = ext.order
            out["grid_error_messages"].append(f"{name}, load {j}: {ext.message}")
        out[f"{name}_error"] = error
        out[f"{name}_error_order"] = order
    return out


def compute_bem_shear(context: StageContext) -> BemShearComparison:
    """The job's shear BEM stage: :func:`bem_shear_comparison` with ``[bem_shear]``, the
    material, lambda (the lambda stage's) and the model's curves (the friction stage's)."""
    config = context.config
    material = config.material
    return bem_shear_comparison(
        context.result(SURFACE).height_map(),
        material.e_star,
        material.work_of_adhesion,
        context.result(MODE_MIXITY).mode_mixity,
        material.shear_strength,
        config.loading.nominal_area,
        context.result(FRICTION),
        config.bem_shear,
        reference=context.result(BEM),
        periodic=config.bem.boundary == "periodic",
        executor=context.executor,
        progress=context.progress,
    )


def shear_enabled(config: object) -> bool:
    """The stage runs: a ``[bem_shear]`` table with ``enabled = true``."""
    settings = getattr(config, "bem_shear", None)
    return settings is not None and bool(settings.enabled)


BEM_SHEAR = Stage(
    name="bem_shear",
    title="shear BEM",
    result=BemShearComparison,
    config=(
        "bem_shear",
        "bem.boundary",
        "material.E_star",
        "material.work_of_adhesion",
        "material.shear_strength",
        "loading.nominal_area",
    ),
    inputs=(SURFACE, BEM, MODE_MIXITY, FRICTION),
    compute=compute_bem_shear,
    enabled=shear_enabled,
)
