"""The shear BEM stage (``[bem_shear]``): the statistical model judged under shear by the BEM.

The paper's experiment on the map (Section 5, Figs 4 and 13): the normal force F_z held, the
rigid flat displaced along x up to full sliding. Each curve is
:func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve`: a Pohrt-Popov preload (JKR
equilibrium before shear), the paper's mixed-mode edge law G_I + lambda G_II = w
(E:failure_locus) element by element, and a junction past its instability (E:max_disp_PC)
sliding with tau_0 on its non-adhesive contact (E:Hertz_theory), as the paper's status map
says. The job's E*, w, lambda (the lambda stage's) and tau_0; the loads ``bem_shear.loads``.

Per load and grid: F_x(delta_T), A_r(delta_T), the stick and slip areas, the junction counts,
the static peak F_s (largest F_x before gross sliding) and where it lies, the sliding
friction F_d (F_x at the first step where every junction slides), the area drop
A_r(peak) / A_r(0) (E:NewFormulation_Ar's reduction, Fig 13), beside the model's (the friction
stage's curves at the effective resolution).

Grids: the map decimated by ``stride`` (the grid used) and, with ``grid_check``, by twice it.
The discretisation error of a quantity is its difference between the two grids (the error of
the finer grid if the error falls as the element size, first order: Richardson with p = 1);
the mesh-dependent edge law and the roughness each grid carries both enter it.

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
from asperity.bem.options import SolverOptions
from asperity.bem.shear.mixed_mode import MixedModeLaw
from asperity.bem.shear.rough import ShearCurve
from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve
from asperity.bem.shear.stick_slip import ShearOptions
from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.config import BemShearConfig
from asperity.pipelines.engine.parallel import run_map, worker_threads
from asperity.pipelines.engine.stage import Stage, StageContext
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
            "full sliding not reached within the path: the BEM's sliding friction there is "
            "not a result and its static peak may lie beyond the path (extend "
            "bem_shear.max_displacement)",
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

    Dimensions: ``grid`` (0 the grid used, 1 the check grid twice as coarse, when run),
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
        |grid 1 - grid 0| per load (the discretisation error of the grid used, first order);
        None without ``grid_check``.
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
    static_friction_error: np.ndarray | None = array(
        "N", ("normal_load",), "|F_s(check grid) - F_s(grid used)|", optional=True
    )
    sliding_friction_error: np.ndarray | None = array(
        "N", ("normal_load",), "|F_d(check grid) - F_d(grid used)|", optional=True
    )
    area_drop_error: np.ndarray | None = array(
        "1", ("normal_load",), "|drop(check grid) - drop(grid used)|", optional=True
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


def _solve_curve(
    heights: np.ndarray,
    dx: float,
    dy: float,
    map_load: float,
    path: np.ndarray,
    material: statmodel.Material,
    law: str,
    tol: float,
    periodic: bool,
) -> dict:
    """One load on one grid (a worker job): the curve on the map, its warnings and time;
    ``material`` gives E* (Pa), w (J/m^2), lambda and tau_0 (Pa)."""
    e_star, w = material.e_star, material.work_of_adhesion
    lam, tau0 = material.mode_mixity, material.shear_strength
    options = ShearOptions(tol=tol, threads=worker_threads())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        curve = mixed_mode_shear_curve(
            heights,
            dx,
            dy,
            e_star,
            map_load,
            path,
            MixedModeLaw(w, lam, tangential_energy=law),
            shear_strength=tau0,
            periodic=periodic,
            normal_options=SolverOptions(tol=tol),
            options=options,
            stop_when_sliding=True,
        )
        seconds = time.perf_counter() - t0
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


def _path_end(friction: FrictionPrediction, index: int, settings: BemShearConfig) -> float:
    """The last delta_T (m) at load ``index``: the configured one, else :data:`PATH_FACTOR`
    times the model's sliding displacement (the model's own path end where it has none)."""
    if settings.max_displacement is not None:
        return float(settings.max_displacement)
    slide = float(friction.sliding_displacement[index])
    if math.isfinite(slide) and slide > 0:
        return PATH_FACTOR * slide
    return float(np.nanmax(friction.tangential_displacement[index]))


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
    periodic: bool = True,
    executor: Executor | None = None,
    progress: bool = False,
) -> BemShearComparison:
    """Shear curves of the map by the BEM at each load, beside the statistical model's.

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
    periodic : bool
        Periodic map (the BEM reference's ``bem.boundary``) or free.
    executor : Executor, optional
        Runs the curves (one per grid and load) in parallel.

    Raises
    ------
    InputError
        A load not among the friction stage's, or a grid of fewer than
        :data:`MIN_GRID_PIXELS` pixels a side (``bem_shear.stride``).
    """
    if work_of_adhesion <= 0:
        raise InputError(
            "material.work_of_adhesion: the shear BEM's mixed-mode law needs w > 0 (J/m^2), got "
            f"{work_of_adhesion}"
        )
    loads, index = _loads_and_model_index(friction, settings)
    strides, grids = _grids(surface, settings)
    paths = np.array(
        [np.linspace(0.0, _path_end(friction, i, settings), settings.steps) for i in index]
    )
    material = statmodel.Material(e_star, work_of_adhesion, mode_mixity, shear_strength)
    map_area = np.array([g.nx * g.dx * g.ny * g.dy for g in grids])
    jobs = [
        (_centred(grid), grid.dx, grid.dy, float(f) * map_area[g] / nominal_area, paths[j],
         material, settings.law, settings.tol, periodic)
        for g, grid in enumerate(grids)
        for j, f in enumerate(loads)
    ]  # fmt: skip
    solved = run_map(_solve_curve, jobs, executor, desc="BEM shear curves", progress=progress)
    fields = _collect_curves(solved, loads, strides, nominal_area / map_area, settings.steps)
    model = [_model_features(friction, i) for i in index]
    return BemShearComparison(
        normal_load=loads,
        grid_stride=np.asarray(strides, dtype=int),
        grid_pixel_size=np.array([g.dx for g in grids]),
        map_area=map_area,
        map_normal_load=map_area[:, None] * loads[None, :] / nominal_area,
        tangential_displacement=paths,
        **fields,
        model_static_friction=np.array([m["static_friction"] for m in model]),
        model_sliding_friction=np.array([m["sliding_friction"] for m in model]),
        model_static_displacement=np.array([m["static_displacement"] for m in model]),
        model_sliding_displacement=np.array([m["sliding_displacement"] for m in model]),
        model_area_drop=np.array([m["area_drop"] for m in model]),
        e_star=float(e_star),
        work_of_adhesion=float(work_of_adhesion),
        mode_mixity=float(mode_mixity),
        shear_strength=float(shear_strength),
        nominal_area=float(nominal_area),
        law=settings.law,
        boundary="periodic" if periodic else "free",
        **_grid_errors(fields, len(grids)),
    )


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


def _grids(surface: topo.HeightMap, settings: BemShearConfig) -> tuple[list[int], list]:
    """The strides solved (``stride``, and twice it with ``grid_check``) and their decimated
    maps; an InputError when the coarsest has fewer than :data:`MIN_GRID_PIXELS` a side."""
    strides = [settings.stride, 2 * settings.stride] if settings.grid_check else [settings.stride]
    grids = [topo.decimate(surface, s) for s in strides]
    if min(min(g.nx, g.ny) for g in grids) < MIN_GRID_PIXELS:
        raise InputError(
            f"bem_shear.stride: expected a stride leaving at least {MIN_GRID_PIXELS} pixels a side "
            f"on the coarsest grid solved ({surface.nx} x {surface.ny} map, strides "
            f"{', '.join(map(str, strides))}), got {settings.stride}"
        )
    return strides, grids


def _centred(grid: topo.HeightMap) -> np.ndarray:
    """The grid's heights (m, float64) less their mean."""
    heights = np.asarray(grid.heights, dtype=np.float64)
    return heights - heights.mean()


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
    if not out["converged"][at]:
        first = int(np.flatnonzero(~np.asarray(curve.converged))[0])
        out["messages"].append(
            f"{where}: step {first} (delta_T = {curve.tangential_displacement[first]:.4g} m) "
            "did not converge"
        )


def _grid_errors(fields: dict, n_grids: int) -> dict:
    """The grid error of each judged feature: |coarse - used| (none with one grid)."""
    if n_grids < 2:
        return {}
    return {
        f"{name}_error": np.abs(fields[name][1] - fields[name][0])
        for name in ("static_friction", "sliding_friction", "area_drop")
    }


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
    inputs=(SURFACE, MODE_MIXITY, FRICTION),
    compute=compute_bem_shear,
    enabled=shear_enabled,
)
