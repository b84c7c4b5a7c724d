"""The BEM stage (3), the BEM reference A_r(F_z) on the map (Appendix B; Fig 12d's squares):
its ``[bem]`` keys (:data:`SETTINGS`, :class:`~asperity.pipelines.config.BemConfig`'s fields),
its input (the levelled map), its stored fields (:class:`BemReference`). The numerics are
:func:`asperity.bem.solve_reference`'s (:mod:`asperity.bem.reference.grid_refinement`, the grid
check and
its Richardson extrapolation; :mod:`~asperity.bem.reference.adhesion_range`, the Maugis range rule;
:mod:`~asperity.bem.reference.load_sweeps`, the load chains)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from asperity import topo
from asperity.bem.options import SolverOptions
from asperity.bem.reference.adhesion_range import RangeChoice
from asperity.bem.reference.discretisation import combined_uncertainty
from asperity.bem.reference.grid_refinement import (
    GridCheck,
    boundary_warning,
    discretisation_estimate,
    edge_mismatch,
    resolution_dependence,
)
from asperity.bem.reference.interpolated_refinement import InterpolatedRefinement
from asperity.bem.reference.load_sweeps import ContactSetup, LoadChain
from asperity.bem.reference.solve import ChainMap, ReferenceSolves, solve_reference
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.config import BemConfig, bem_settings
from asperity.pipelines.engine.parallel import run_map, share, worker_threads
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.stages.surface import SURFACE

__all__ = ["BEM", "SETTINGS", "BemReference", "bem_reference", "compute_bem"]


@document_fields
@dataclass
class BemReference:
    """Stage-3 result: the BEM A_r(F_z) reference on the map, and the grid check behind it.

    Attributes
    ----------
    mode : ndarray
        0 non-adhesive, 1 adhesive (``adhesion``, when run).
    contact_fraction : ndarray
        Non-adhesive A_r/A_map (= A_r/A_n of the experiment).
    contact_fraction_adhesive : ndarray or None
        Adhesive A_r/A_map (law ``adhesion``); None when not run.
    contact_mask : ndarray of bool
        Contact at the largest load (adhesive when run).
    grid_converged : bool
        The two finest grids solved agree within ``bem.area_tolerance`` (the finest grid's
        area looks converged); True when a single grid was solved.
    convolutions : ndarray, shape (n_mode, n_load)
        FFT convolutions per solve (an adhesive solve's non-adhesive start included).
    branch : list of list of str
        Per mode and load: the branch of the solve (``"unique"`` non-adhesive, ``"loading"``).
    check_load : float
        Experiment load of the check, N (one of ``normal_load``: its solve at the chosen
        stride is the sweep's).
    grid_error : float
        Error of the grid used against the finest grid solved (0 when it is the finest).
    all_converged : bool
        Every solve converged (derived).
    range_zone_elements : float or None
        Mean cohesive-zone width at the check load on the range search's grid, elements.
    range_sensitivity : ndarray or None
        A_r/A_n at the check load on the range search's grid at h_0 / 2, h_0, 2 h_0.
    area_range_uncertainty : float or None
        Half the spread of ``range_sensitivity`` (absolute A_r/A_n): the range part of the
        BEM's uncertainty (:func:`asperity.bem.reference.discretisation.half_spread`).
    check_contact_fraction, check_error, check_relative_change : ndarray
        The decimation sequence (strides of the map): how A_r/A_n depends on the resolution,
        i.e. on the roughness each grid carries. It chooses the grid (``area_tolerance``) but is
        not the error bar.
    resolution_dependence : ndarray or None
        Per mode: relative move of the check load's A_r/A_n from the next coarser stride to the
        grid used, ``(f_coarse - f) / f`` (roughness the coarser grid does not carry); NaN when
        the grid used is the coarsest. ``resolution_message`` says it in words.
    refinement_factor, refinement_pixel_size, refinement_contact_fraction : ndarray or None
        The discretisation check: the grid used Fourier-interpolated by these factors (same
        roughness; 1 is the grid used, or its window when ``refinement_windowed``), their pixel
        size (m) and the check load's A_r/A_n per (level, mode)
        (:mod:`asperity.bem.reference.interpolated_refinement`).
    check_extrapolated_fraction, check_extrapolation_uncertainty : ndarray or None
        Per mode: the refinement's A_r/A_n extrapolated to zero pixel size and its band
        (:func:`bem.richardson_extrapolation`, Roache's grid convergence index, about 95 %).
    discretisation_relative_uncertainty : ndarray or None
        Per mode: the relative uncertainty of the A_r/A_n of the grid the sweeps use,
        ``(|f - f_0| + u) / f`` over the interpolated refinement (the band holds the whole
        extrapolated band), measured at the check load and applied to every load of the same
        grid (stated, not solved per load).
    range_sensitivity_resolved : bool or None
        The h_0 / 2 solve of ``range_sensitivity`` resolved its cohesive zone (>= 3 elements,
        on the x2 interpolated grid); False: the range part is a lower bound.
    contact_fraction_discretisation_uncertainty : ndarray or None, shape (n_mode, n_load)
        A_r/A_n discretisation part per mode and load.
    contact_fraction_adhesion_range_uncertainty : ndarray or None, shape (n_load,)
        The adhesive A_r/A_n's sensitivity to the adhesion range, ``bem.half_spread`` of the
        solves at half and double the range (None until those solves are made).
    contact_fraction_uncertainty : ndarray or None, shape (n_mode, n_load)
        The parts in quadrature (:func:`bem.combine_in_quadrature`; derived): discretisation
        for both modes, with the adhesion-range part for the adhesive one when given.
    """

    normal_load: np.ndarray = array("N", ("normal_load",), "normal load on the nominal area")
    mode: np.ndarray = array("1", ("mode",), "0 non-adhesive, 1 adhesive")
    check_stride: np.ndarray = array("1", ("check_stride",), "strides of the grid refinement check")
    mask_x: np.ndarray = array("m", ("mask_x",), "x")
    mask_y: np.ndarray = array("m", ("mask_y",), "y")
    map_normal_load: np.ndarray = array("N", ("normal_load",), "load on the map, F_z A_map / A_n")
    contact_fraction: np.ndarray = array("1", ("normal_load",), "non-adhesive A_r / A_n")
    iterations: np.ndarray = array("1", ("mode", "normal_load"), "solver iterations")
    converged: np.ndarray = array("1", ("mode", "normal_load"), "solver converged")
    solve_seconds: np.ndarray = array("s", ("mode", "normal_load"), "wall time of each solve")
    check_contact_fraction: np.ndarray = array(
        "1", ("check_stride", "mode"), "A_r / A_map at the check pressure"
    )
    check_relative_change: np.ndarray = array(
        "1", ("check_stride",), "relative change to the next finer stride"
    )
    contact_mask: np.ndarray = array("1", ("mask_x", "mask_y"), "contact at the largest load")
    stride: int = scalar("1", "decimation of the map used by the sweeps")
    dx: float = scalar("m", "pixel size of the solved grid along x")
    dy: float = scalar("m", "pixel size of the solved grid along y")
    check_pressure: float = scalar("Pa", "nominal pressure of the grid check")
    grid_converged: bool = scalar("1", "the grid check found a converged stride")
    grid_reason: str = text("why this grid")
    messages: list[str] = text("messages of solves that did not converge")
    convolutions: np.ndarray = array("1", ("mode", "normal_load"), "FFT convolutions per solve")
    branch: list[list[str]] = text("branch of each solve, per mode and load")
    check_error: np.ndarray = array(
        "1", ("check_stride",), "relative A_r/A_n difference from the finest grid solved"
    )
    check_iterations: np.ndarray = array("1", ("check_stride", "mode"), "check solve iterations")
    check_convolutions: np.ndarray = array(
        "1", ("check_stride", "mode"), "check solve FFT convolutions"
    )
    check_seconds: np.ndarray = array("s", ("check_stride", "mode"), "check solve wall time")
    check_branch: list[list[str]] = text("branch of each check solve, per stride and mode")
    check_load: float = scalar("N", "experiment load of the grid check")
    grid_error: float = scalar("1", "error of the grid used against the finest grid solved")
    boundary: str = text("periodic or free")
    edge_mismatch: float = scalar("1", "rms seam height jump over rms height")
    warnings: list[str] = text("report lines about the BEM")
    solves: int = scalar("1", "BEM solves made by the stage")
    total_iterations: int = scalar("1", "iterations of all solves of the stage")
    total_convolutions: int = scalar("1", "FFT convolutions of all solves of the stage")
    contact_fraction_adhesive: np.ndarray | None = array(
        "1", ("normal_load",), "adhesive A_r / A_n", optional=True
    )
    all_converged: bool = scalar("1", "every BEM solve converged", init=False)
    area_tolerance: float | None = scalar(
        "1", "relative A_r tolerance of the grid check ([bem] area_tolerance)", optional=True
    )
    adhesion: str | None = text("law of the adhesive solves: maugis or pohrt-popov", optional=True)
    adhesion_range: float | None = scalar("m", "Maugis-Dugdale range h_0", optional=True)
    range_rule: str | None = text("how the Maugis range was chosen", optional=True)
    range_zone_elements: float | None = scalar(
        "1", "cohesive-zone width at the check load on the range grid, elements", optional=True
    )
    range_sensitivity: np.ndarray | None = array(
        "1", ("range_factor",), "A_r / A_n at h_0 / 2, h_0, 2 h_0 (check load)", optional=True
    )
    area_range_uncertainty: float | None = scalar(
        "1", "half spread of A_r / A_n over h_0 / 2 .. 2 h_0 (check load)", optional=True
    )
    range_solves: int = scalar("1", "Maugis solves of the range search and sensitivity", default=0)
    range_sensitivity_resolved: bool | None = scalar(
        "1", "the h_0 / 2 solve resolved its cohesive zone (else a lower bound)", optional=True
    )
    range_half_zone_elements: float | None = scalar(
        "1", "cohesive-zone width of the h_0 / 2 solve, elements of its grid", optional=True
    )
    range_sensitivity_note: str | None = text("where h_0 / 2 was solved", optional=True)
    resolution_dependence: np.ndarray | None = array(
        "1",
        ("mode",),
        "A_r / A_n move from the next coarser stride to the grid used",
        optional=True,
    )
    resolution_message: str | None = text("what the decimation sequence shows", optional=True)
    refinement_factor: np.ndarray | None = array(
        "1", ("refinement_level",), "Fourier-interpolation factors of the grid used", optional=True
    )
    refinement_pixel_size: np.ndarray | None = array(
        "m", ("refinement_level",), "pixel size of each refinement level", optional=True
    )
    refinement_contact_fraction: np.ndarray | None = array(
        "1", ("refinement_level", "mode"), "check A_r / A_n per refinement level", optional=True
    )
    refinement_windowed: bool | None = scalar(
        "1", "the refinement was solved on a window of the grid used", optional=True
    )
    refinement_message: str | None = text("how the discretisation was checked", optional=True)
    refinement_seconds: float | None = scalar(
        "s", "wall time of the refinement solves", optional=True
    )
    check_extrapolated_fraction: np.ndarray | None = array(
        "1", ("mode",), "check A_r / A_n extrapolated to zero pixel size", optional=True
    )
    check_extrapolation_uncertainty: np.ndarray | None = array(
        "1", ("mode",), "grid convergence index band of the extrapolated A_r / A_n", optional=True
    )
    extrapolation_order: np.ndarray | None = array(
        "1", ("mode",), "order p of the Richardson extrapolation", optional=True
    )
    extrapolation_safety_factor: np.ndarray | None = array(
        "1", ("mode",), "safety factor of the grid convergence index", optional=True
    )
    extrapolation_messages: list[str] | None = text(
        "how the extrapolation's order was chosen, per mode", optional=True
    )
    discretisation_relative_uncertainty: np.ndarray | None = array(
        "1", ("mode",), "relative A_r uncertainty of the grid used", optional=True
    )
    contact_fraction_discretisation_uncertainty: np.ndarray | None = array(
        "1", ("mode", "normal_load"), "A_r / A_n discretisation uncertainty", optional=True
    )
    contact_fraction_adhesion_range_uncertainty: np.ndarray | None = array(
        "1", ("normal_load",), "adhesive A_r / A_n sensitivity to the adhesion range", optional=True
    )
    contact_fraction_uncertainty: np.ndarray | None = array(
        "1",
        ("mode", "normal_load"),
        "A_r / A_n uncertainty, parts in quadrature",
        optional=True,
        init=False,
    )

    def __post_init__(self) -> None:
        self.all_converged = bool(np.all(self.converged))
        self.contact_fraction_uncertainty = combined_uncertainty(
            self.contact_fraction_discretisation_uncertainty,
            self.contact_fraction_adhesion_range_uncertainty,
        )

    def reference_fraction_uncertainty(self) -> np.ndarray | None:
        """The uncertainty of :meth:`reference_fraction` (1), None when not estimated."""
        if self.contact_fraction_uncertainty is None:
            return None
        return self.contact_fraction_uncertainty[-1]

    def reference_fraction(self) -> np.ndarray:
        """The A_r/A_n the adhesive statistical model is compared with: adhesive when run
        (Maugis-Dugdale by default: adhesive on loading, like the model)."""
        if self.contact_fraction_adhesive is not None:
            return self.contact_fraction_adhesive
        return self.contact_fraction


#: The ``[bem]`` keys the BEM reference reads: the fields of :class:`BemConfig` but
#: ``enabled`` (which only switches the stage on or off).
SETTINGS: tuple[str, ...] = tuple(
    f.name for f in dataclasses.fields(BemConfig) if f.name != "enabled"
)

#: The report line of a Pohrt-Popov run.
POHRT_POPOV_NOTE = (
    '[bem] adhesion = "pohrt-popov" (the paper\'s Appendix B, eq:max_sigma): its loading '
    "branch carries no adhesion (an element joins only where its gap closes), so the adhesive "
    "BEM areas equal the non-adhesive ones; the statistical model is adhesive on loading "
    '(E:JKR_load): use adhesion = "maugis" for a like-for-like calibration'
)


def _with_worker_threads(setup: ContactSetup) -> ContactSetup:
    """``setup`` with this process's FFT thread cap (:func:`worker_threads`)."""
    options = dataclasses.replace(setup.options, threads=worker_threads())
    return dataclasses.replace(setup, options=options)


def _in_worker(function: Callable[..., LoadChain], grid, setup, *job) -> LoadChain:
    return function(grid, _with_worker_threads(setup), *job)


def _chain_map(executor: Executor | None, progress: bool) -> ChainMap:
    """Runs the load chains through ``executor``, the map and start shipped to each worker once."""

    def map_chains(function: Callable[..., LoadChain], jobs: list[tuple]) -> list[LoadChain]:
        grid, start = share(executor, jobs[0][0]), share(executor, jobs[0][3])
        jobs = [(function, grid, setup, forces, start, mask) for _, setup, forces, _, mask in jobs]
        return run_map(_in_worker, jobs, executor, desc="BEM sweeps", progress=progress)

    return map_chains


def bem_reference(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    normal_loads: Sequence[float],
    nominal_area: float,
    settings: BemConfig | None = None,
    *,
    executor: Executor | None = None,
    progress: bool = False,
    **deprecated_settings: object,
) -> BemReference:
    """The BEM real contact area against normal load on the map (:func:`bem.solve_reference`).

    Parameters
    ----------
    surface : topo.HeightMap
        Levelled map, heights in m (larger = closer to the flat).
    e_star : float
        E*, Pa.
    work_of_adhesion : float
        w, J/m^2 (adhesive solves on the loading branch when ``settings.adhesive``).
    normal_loads : sequence of float
        Experiment loads F_z, N (on the nominal area).
    nominal_area : float
        A_n of the experiment, m^2.
    settings : BemConfig, optional
        The ``[bem]`` table (default ``BemConfig()``): the solver's ``tol`` and ``max_iter``,
        the grid check's ``max_stride``, ``area_tolerance``, ``coarsen``, the ``boundary``,
        ``adhesive``, the law ``adhesion`` and its range ``adhesion_range`` (m; None: the rule
        of :func:`bem.reference.adhesion_range.search_range`), the discretisation check's
        ``max_refinement`` and ``refinement_pixels``.
    executor : Executor, optional
        Runs the two load chains in parallel.
    **deprecated_settings
        The settings as keywords (0.3): a DeprecationWarning, removed in 0.5.
    """
    settings = bem_settings(settings, "bem_reference", deprecated_settings)
    loads = np.asarray(normal_loads, dtype=float)
    w = work_of_adhesion if settings.adhesive and work_of_adhesion > 0 else 0.0
    run = _solve_on_map(surface, e_star, w, loads, nominal_area, settings, executor, progress)
    fraction = run.field("contact_fraction")
    return BemReference(
        normal_load=loads,
        boundary=settings.boundary,
        area_tolerance=float(settings.area_tolerance),
        **_map_fields(run, loads, fraction, w),
        **_check_fields(run, loads, nominal_area, settings.area_tolerance),
        **_discretisation_fields(run.check, surface.dx, fraction),
        **_note_fields(run.grid, settings, w),
        **_refinement_fields(run.check.refinement),
        **_range_fields(run.check.range_choice, fraction[-1]),
    )


def _solve_on_map(
    surface: topo.HeightMap,
    e_star: float,
    w: float,
    loads: np.ndarray,
    nominal_area: float,
    settings: BemConfig,
    executor: Executor | None,
    progress: bool,
) -> ReferenceSolves:
    """The reference's solves (:func:`bem.solve_reference`) at ``loads`` (N) with the work of
    adhesion ``w`` (J/m^2; 0: non-adhesive) and the ``[bem]`` settings."""
    options = SolverOptions(tol=settings.tol, max_iter=settings.max_iter)
    setup = ContactSetup(e_star, w, options, periodic=settings.boundary == "periodic")
    return solve_reference(
        surface.heights, surface.dx, surface.dy, _with_worker_threads(setup), loads,
        nominal_area, max_stride=settings.max_stride, area_tolerance=settings.area_tolerance,
        coarsen=settings.coarsen, adhesion=settings.adhesion,
        adhesion_range=settings.adhesion_range, max_refinement=settings.max_refinement,
        refinement_pixels=settings.refinement_pixels, map_chains=_chain_map(executor, progress),
    )  # fmt: skip


def _map_fields(run: ReferenceSolves, loads: np.ndarray, fraction: np.ndarray, w: float) -> dict:
    """The fields of :class:`BemReference` from the solves on the chosen grid: the contact
    fraction per load (its adhesive mode when ``w`` > 0), the solver's record, the mask."""
    grid = run.grid
    solves, iterations, convolutions = run.totals()
    return {
        "mode": np.arange(len(run.solves)),
        "mask_x": np.arange(run.mask.shape[0]) * grid.dx,
        "mask_y": np.arange(run.mask.shape[1]) * grid.dy,
        "map_normal_load": run.map_loads,
        "contact_fraction": fraction[0],
        "iterations": run.field("iterations", int),
        "converged": run.field("converged", bool),
        "solve_seconds": run.field("seconds"),
        "contact_mask": run.mask,
        "messages": run.messages(loads),
        "convolutions": run.field("convolutions", int),
        "branch": [[s.branch for s in row] for row in run.solves],
        "solves": solves,
        "total_iterations": iterations,
        "total_convolutions": convolutions,
        "contact_fraction_adhesive": fraction[1] if w > 0 else None,
    }


def _check_fields(
    run: ReferenceSolves, loads: np.ndarray, nominal_area: float, area_tolerance: float
) -> dict:
    """The grid check's fields of :class:`BemReference`: its strides, areas, solver record and
    choice, at the check load (N; its pressure over ``nominal_area``, Pa)."""
    check, grid, k = run.check, run.grid, run.check_index
    return {
        "check_stride": check.strides,
        "check_contact_fraction": check.fractions(),
        "check_relative_change": check.relative_change,
        "stride": check.stride,
        "dx": grid.dx,
        "dy": grid.dy,
        "check_pressure": float(loads[k]) / nominal_area,
        "grid_converged": check.converged(area_tolerance),
        "grid_reason": check.reason,
        "check_error": check.error,
        "check_iterations": check.field("iterations", int),
        "check_convolutions": check.field("convolutions", int),
        "check_seconds": check.field("seconds"),
        "check_branch": [[s.branch for s in row] for row in check.solves],
        "check_load": float(loads[k]),
        "grid_error": float(check.error[check.chosen]),
    }


def _discretisation_fields(check: GridCheck, dx: float, fraction: np.ndarray) -> dict:
    """The discretisation estimate's fields of :class:`BemReference` (the map's pixel ``dx``,
    m): the extrapolated fraction and its uncertainty, the resolution dependence."""
    extrapolations, relative = discretisation_estimate(check, dx)
    dependence, dependence_message = resolution_dependence(check, dx)
    return {
        "check_extrapolated_fraction": np.array([e.value for e in extrapolations]),
        "check_extrapolation_uncertainty": np.array([e.uncertainty for e in extrapolations]),
        "extrapolation_order": np.array([e.order for e in extrapolations]),
        "extrapolation_safety_factor": np.array([e.safety_factor for e in extrapolations]),
        "extrapolation_messages": [e.message for e in extrapolations],
        "discretisation_relative_uncertainty": relative,
        "contact_fraction_discretisation_uncertainty": relative[:, None] * fraction,
        "resolution_dependence": dependence,
        "resolution_message": dependence_message,
    }


def _note_fields(grid: topo.HeightMap, settings: BemConfig, w: float) -> dict:
    """The boundary's edge mismatch, the law used (None: non-adhesive) and the notes on both."""
    mismatch = edge_mismatch(grid.heights)
    law = settings.adhesion if w > 0 else None
    notes = (
        boundary_warning(settings.boundary, mismatch),
        law == "pohrt-popov" and POHRT_POPOV_NOTE,
    )
    return {"edge_mismatch": mismatch, "warnings": [n for n in notes if n], "adhesion": law}


def _refinement_fields(refinement: InterpolatedRefinement | None) -> dict:
    """The interpolated refinement's fields of :class:`BemReference` (none without one)."""
    if refinement is None:
        return {}
    return {
        "refinement_factor": np.asarray(refinement.factors, dtype=int),
        "refinement_pixel_size": np.asarray(refinement.pixel_size, dtype=float),
        "refinement_contact_fraction": refinement.fractions(),
        "refinement_windowed": bool(refinement.windowed),
        "refinement_message": refinement.message,
        "refinement_seconds": float(refinement.seconds),
    }


def _range_fields(choice: RangeChoice | None, adhesive: np.ndarray) -> dict:
    """The Maugis range's fields of :class:`BemReference` (none for Pohrt-Popov or w = 0); its
    sensitivity, measured at the check load, applies as the same relative part at every load."""
    if choice is None:
        return {}
    return {
        "adhesion_range": choice.adhesion_range,
        "range_rule": choice.rule,
        "range_zone_elements": choice.zone_elements,
        "range_sensitivity": np.asarray(choice.sensitivity, dtype=float),
        "area_range_uncertainty": choice.uncertainty,
        "range_solves": choice.solves,
        "range_sensitivity_resolved": bool(choice.sensitivity_resolved),
        "range_half_zone_elements": float(choice.half_range_zone_elements),
        "range_sensitivity_note": choice.sensitivity_note,
        "contact_fraction_adhesion_range_uncertainty": choice.relative_uncertainty * adhesive,
    }


def compute_bem(context: StageContext) -> BemReference:
    """The job's BEM stage: :func:`bem_reference` with ``[bem]``, the material and the loads."""
    config = context.config
    return bem_reference(
        context.result(SURFACE).height_map(),
        config.material.e_star,
        config.material.work_of_adhesion,
        config.loading.normal_loads,
        config.loading.nominal_area,
        config.bem,
        executor=context.executor,
        progress=context.progress,
    )


BEM = Stage(
    name="bem_reference",
    title="BEM reference",
    attribute="bem",
    result=BemReference,
    config=(
        "material.E_star",
        "material.work_of_adhesion",
        "loading.nominal_area",
        "loading.normal_loads",
        *(f"bem.{name}" for name in SETTINGS),
    ),
    inputs=(SURFACE,),
    compute=compute_bem,
    enabled=lambda config: config.bem.enabled,
)
