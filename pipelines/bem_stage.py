"""Stage 3: the BEM reference A_r(F_z) on the map (Appendix B; squares of Fig 12d).

The map covers only part of the experiment's nominal area A_n, so each normal load is scaled
to the map at equal nominal pressure, F_map = F_z A_map / A_n, and the result is reported as
the fraction A_r / A_map (equal to A_r / A_n of the experiment). Two warm-started sweeps over
the loads (:func:`bem.load_sweep`): non-adhesive and adhesive (Pohrt-Popov, eq:max_sigma).

Grid choice ("model no more than a scene needs"): the map decimated with stride s is solved
at the median load's nominal pressure and compared with the map at stride s/2, from
``max_stride`` down to 1; the coarsest stride whose real-area fraction changes by less than
``area_tolerance`` (relative) on refinement is used for the sweeps. When no pair agrees, the
full map (stride 1) is used and the report says that the area is not converged under
refinement (usual for self-affine maps, whose contact area keeps shrinking as finer roughness
is resolved).
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from asperity import bem, topo
from asperity.pipelines.fields import array, scalar, text
from asperity.pipelines.parallel import run_map, worker_threads
from asperity.pipelines.stages import Stage, StageContext
from asperity.pipelines.surface_stage import SURFACE

#: The map is solved as one period of a periodic interface, as in the paper (Appendix B: the
#: measured 10 x 10 mm^2 map is a seventh of the nominal area, so the domain is taken periodic).
PERIODIC = True


def solver_grid(surface: topo.HeightMap, stride: int) -> tuple[np.ndarray, float, float]:
    """The BEM grid of a stride: decimated heights (m), cropped to fast FFT sizes, and dx, dy.

    Missing pixels are set to the lowest valid height (they never touch). The crop to sizes
    with prime factors 2, 3, 5, 7 (:func:`bem.crop_to_fast_size`; e.g. 5001 -> 5000) removes at
    most a few trailing rows and columns; loads are scaled to the area actually solved.
    """
    grid = topo.decimate(surface, stride) if stride > 1 else surface
    heights = np.array(bem.crop_to_fast_size(grid.heights, warn=False), dtype=float)
    missing = np.isnan(heights)
    if missing.any():
        heights[missing] = np.nanmin(heights)
    return heights, grid.dx, grid.dy


def bem_sweep(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    map_loads: Sequence[float],
    work_of_adhesion: float,
    tol: float,
    max_iter: int | None,
    periodic: bool,
) -> dict:
    """One warm-started BEM sweep; returns per-load summaries (picklable, no fields).

    Parameters are those of :func:`bem.load_sweep` (heights m, dx/dy m, e_star Pa, loads N,
    work_of_adhesion J/m^2). The contact mask of the last (largest) load is returned too.
    """
    order = np.argsort(map_loads)
    results = bem.load_sweep(
        heights,
        dx,
        dy,
        e_star,
        [float(map_loads[i]) for i in order],
        work_of_adhesion=work_of_adhesion,
        tol=tol,
        max_iter=max_iter,
        periodic=periodic,
        threads=worker_threads(),
    )
    n = len(map_loads)
    out = {
        "real_area": np.empty(n),
        "contact_fraction": np.empty(n),
        "normal_force": np.empty(n),
        "mean_gap": np.empty(n),
        "iterations": np.empty(n, dtype=np.int64),
        "converged": np.empty(n, dtype=bool),
        "seconds": np.empty(n),
        "messages": [""] * n,
    }
    for rank, i in enumerate(order):
        r = results[rank]
        out["real_area"][i] = r.real_area
        out["contact_fraction"][i] = r.contact_fraction
        out["normal_force"][i] = r.normal_force
        out["mean_gap"][i] = r.mean_gap
        out["iterations"][i] = r.nit
        out["converged"][i] = bool(r.converged)
        out["seconds"][i] = r.seconds
        out["messages"][i] = str(r.message)
    out["contact_mask"] = np.asarray(results[-1].contact_mask, dtype=bool)
    return out


def _single_solve(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    load: float,
    work_of_adhesion: float,
    tol: float,
    max_iter: int | None,
    periodic: bool,
) -> tuple[float, bool, int]:
    r = bem.solve_contact(
        heights,
        dx,
        dy,
        e_star,
        normal_force=load,
        work_of_adhesion=work_of_adhesion,
        tol=tol,
        max_iter=max_iter,
        periodic=periodic,
        threads=worker_threads(),
    )
    return float(r.contact_fraction), bool(r.converged), int(r.nit)


@dataclass
class GridChoice:
    """Outcome of the BEM refinement check.

    Attributes
    ----------
    stride : int
        Chosen decimation of the map for the sweeps.
    strides : ndarray
        Strides solved (coarse to fine).
    contact_fraction : ndarray, shape (len(strides), n_modes)
        A_r/A_map at the check pressure for each stride and mode (non-adhesive, adhesive).
    relative_change : ndarray
        Largest relative change of the fraction from each stride to the next finer one (NaN for
        the finest).
    check_pressure : float
        Nominal pressure of the check, Pa (the median load over A_n).
    converged : bool
        Some pair agreed within the tolerance.
    reason : str
        One sentence for the report.
    """

    stride: int
    strides: np.ndarray
    contact_fraction: np.ndarray
    relative_change: np.ndarray
    check_pressure: float
    converged: bool
    reason: str


def choose_bem_grid(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    check_pressure: float,
    *,
    max_stride: int,
    area_tolerance: float,
    tol: float,
    max_iter: int | None = None,
    adhesive: bool = True,
    executor: Executor | None = None,
    progress: bool = False,
) -> GridChoice:
    """Pick the coarsest map decimation whose contact area is converged to ``area_tolerance``.

    Parameters
    ----------
    surface : topo.HeightMap
        The levelled map (m).
    e_star, work_of_adhesion : float
        E* (Pa) and w (J/m^2).
    check_pressure : float
        Nominal pressure of the check solves, Pa.
    max_stride : int
        Coarsest stride tried; halved down to 1.
    area_tolerance : float
        Allowed relative change of A_r/A_map between a stride and the next finer one.
    tol, max_iter
        BEM solver settings.
    adhesive : bool
        Also check the adhesive solve (the larger of the two changes decides).
    executor : Executor, optional
        Runs the check solves in parallel.
    """
    strides = []
    s = max(int(max_stride), 1)
    while True:
        if min(surface.nx, surface.ny) // s >= 8:
            strides.append(s)
        if s == 1:
            break
        s = max(s // 2, 1)
    ws = [0.0, work_of_adhesion] if adhesive and work_of_adhesion > 0 else [0.0]
    jobs = []
    for s in strides:
        h, dx, dy = solver_grid(surface, s)
        load = check_pressure * h.size * dx * dy
        for w in ws:
            jobs.append((h, dx, dy, e_star, load, w, tol, max_iter, PERIODIC))
    solved = run_map(_single_solve, jobs, executor, desc="BEM grid check", progress=progress)
    fraction = np.array([f for f, _, _ in solved]).reshape(len(strides), len(ws))
    change = np.full(len(strides), np.nan)
    for i in range(len(strides) - 1):
        ref = fraction[i + 1]
        change[i] = float(np.max(np.abs(fraction[i] - ref) / np.where(ref > 0, ref, np.nan)))
    chosen, converged = strides[-1], False
    for i in range(len(strides) - 1):
        if change[i] <= area_tolerance:
            chosen, converged = strides[i], True
            break
    if len(strides) == 1:
        reason = "the map is too small to decimate; the full map is used"
    elif converged:
        i = strides.index(chosen)
        reason = (
            f"stride {chosen} (pixel {chosen * surface.dx * 1e6:.3g} um): A_r/A_map changes "
            f"by {change[i]:.2%} when refined to stride {strides[i + 1]}, within the "
            f"requested {area_tolerance:.2%}"
        )
    else:
        finest = np.nanmin(change) if np.isfinite(change).any() else np.nan
        reason = (
            f"no decimation converged to {area_tolerance:.2%} (smallest change on "
            f"refinement {finest:.2%}): the full map (stride 1) is used; the real area of "
            "this surface is not converged under refinement"
        )
    return GridChoice(
        chosen, np.asarray(strides), fraction, change, float(check_pressure), converged, reason
    )


@dataclass
class BemReference:
    """Stage-3 result: the BEM A_r(F_z) reference on the map, and the grid check behind it.

    Attributes
    ----------
    normal_load : ndarray
        Experiment loads F_z, N.
    mode : ndarray
        0 non-adhesive, 1 adhesive (Pohrt-Popov, when run).
    check_stride : ndarray
        Strides solved by the grid refinement check, coarse to fine.
    mask_x, mask_y : ndarray
        Pixel positions of the solved grid, m.
    map_normal_load : ndarray
        Loads on the solved map, F_z A_map / A_n, N.
    contact_fraction : ndarray
        Non-adhesive A_r/A_map (= A_r/A_n of the experiment).
    contact_fraction_adhesive : ndarray or None
        Adhesive (Pohrt-Popov) A_r/A_map; None when not run.
    iterations, converged, solve_seconds : ndarray, shape (n_mode, n_load)
        Per solve: iterations, convergence, wall time (s).
    check_contact_fraction : ndarray, shape (n_check_stride, n_mode)
        A_r/A_map at the check pressure per stride and mode.
    check_relative_change : ndarray
        Largest relative change to the next finer stride (NaN for the finest).
    contact_mask : ndarray of bool
        Contact at the largest load (adhesive when run).
    stride : int
        Chosen decimation of the map for the sweeps.
    dx, dy : float
        Pixel sizes of the solved grid, m.
    check_pressure : float
        Nominal pressure of the check, Pa.
    grid_converged : bool
        Some pair of strides agreed within ``bem.area_tolerance``.
    grid_reason : str
        One sentence for the report.
    messages : list of str
        Solver messages of runs that did not converge.
    all_converged : bool
        Every solve converged (derived).
    """

    normal_load: np.ndarray = array("N", ("normal_load",), "normal load on the nominal area")
    mode: np.ndarray = array("1", ("mode",), "0 non-adhesive, 1 adhesive (Pohrt-Popov)")
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
    contact_fraction_adhesive: np.ndarray | None = array(
        "1", ("normal_load",), "adhesive A_r / A_n", optional=True
    )
    all_converged: bool = scalar("1", "every BEM solve converged", init=False)

    def __post_init__(self) -> None:
        self.all_converged = bool(np.all(self.converged))

    def reference_fraction(self) -> np.ndarray:
        """The A_r/A_n the statistical model is compared with: adhesive when run."""
        if self.contact_fraction_adhesive is not None:
            return self.contact_fraction_adhesive
        return self.contact_fraction


def bem_reference(
    surface: topo.HeightMap,
    e_star: float,
    work_of_adhesion: float,
    normal_loads: Sequence[float],
    nominal_area: float,
    *,
    tol: float = 1e-6,
    max_iter: int | None = None,
    area_tolerance: float = 0.05,
    max_stride: int = 4,
    adhesive: bool = True,
    executor: Executor | None = None,
    progress: bool = False,
) -> BemReference:
    """Stage 3: BEM real contact area against normal load on the map.

    Parameters
    ----------
    surface : topo.HeightMap
        Levelled map, heights in m (larger = closer to the flat).
    e_star : float
        E*, Pa.
    work_of_adhesion : float
        w, J/m^2 (adhesive sweep, Pohrt-Popov).
    normal_loads : sequence of float
        Experiment loads F_z, N (on the nominal area).
    nominal_area : float
        A_n of the experiment, m^2.
    tol, max_iter
        BEM solver settings (:func:`bem.solve_contact`).
    area_tolerance, max_stride
        The grid refinement check (:func:`choose_bem_grid`).
    adhesive : bool
        Run the adhesive sweep too.
    executor : Executor, optional
        Runs the two sweeps (and the check solves) in parallel.
    """
    loads = np.asarray(normal_loads, dtype=float)
    grid = choose_bem_grid(
        surface,
        e_star,
        work_of_adhesion,
        float(np.median(loads)) / nominal_area,
        max_stride=max_stride,
        area_tolerance=area_tolerance,
        tol=tol,
        max_iter=max_iter,
        adhesive=adhesive,
        executor=executor,
        progress=progress,
    )
    h, dx, dy = solver_grid(surface, grid.stride)
    map_loads = loads * (h.size * dx * dy) / nominal_area
    ws = [0.0, work_of_adhesion] if adhesive and work_of_adhesion > 0 else [0.0]
    args = [(h, dx, dy, e_star, map_loads, w, tol, max_iter, PERIODIC) for w in ws]
    sweeps = run_map(bem_sweep, args, executor, desc="BEM sweeps", progress=progress)
    messages = [
        f"{'adhesive' if w > 0 else 'non-adhesive'} F_z={loads[i]:.4g} N: {m}"
        for w, sw in zip(ws, sweeps, strict=True)
        for i, (m, ok) in enumerate(zip(sw["messages"], sw["converged"], strict=True))
        if not ok
    ]
    mask = sweeps[-1]["contact_mask"]
    return BemReference(
        normal_load=loads,
        mode=np.arange(len(ws)),
        check_stride=grid.strides,
        mask_x=np.arange(mask.shape[0]) * dx,
        mask_y=np.arange(mask.shape[1]) * dy,
        map_normal_load=map_loads,
        contact_fraction=sweeps[0]["contact_fraction"],
        iterations=np.array([sw["iterations"] for sw in sweeps]),
        converged=np.array([sw["converged"] for sw in sweeps]),
        solve_seconds=np.array([sw["seconds"] for sw in sweeps]),
        check_contact_fraction=grid.contact_fraction,
        check_relative_change=grid.relative_change,
        contact_mask=mask,
        stride=grid.stride,
        dx=dx,
        dy=dy,
        check_pressure=grid.check_pressure,
        grid_converged=grid.converged,
        grid_reason=grid.reason,
        messages=messages,
        contact_fraction_adhesive=sweeps[1]["contact_fraction"] if len(sweeps) > 1 else None,
    )


def compute_bem(context: StageContext) -> BemReference:
    """Stage 3 of the job: :func:`bem_reference` with ``[bem]``, the material and the loads."""
    config, b = context.config, context.config.bem
    return bem_reference(
        context.result(SURFACE).height_map(),
        config.material.e_star,
        config.material.work_of_adhesion,
        config.loading.normal_loads,
        config.loading.nominal_area,
        tol=b.tol,
        max_iter=b.max_iter,
        area_tolerance=b.area_tolerance,
        max_stride=b.max_stride,
        adhesive=b.adhesive,
        executor=context.executor,
        progress=context.progress,
    )


BEM = Stage(
    name="bem_reference",
    title="3 BEM reference",
    result=BemReference,
    config=(
        "material.E_star",
        "material.work_of_adhesion",
        "loading.nominal_area",
        "loading.normal_loads",
        "bem",
    ),
    inputs=(SURFACE,),
    compute=compute_bem,
    enabled=lambda config: config.bem.enabled,
)
