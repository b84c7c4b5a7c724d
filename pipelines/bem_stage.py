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

import time
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field

import numpy as np

from asperity import bem, topo
from asperity.pipelines.parallel import run_map, worker_threads
from asperity.pipelines.store import StageRecord, Variable

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
    """Stage-3 result: the BEM A_r(F_z) reference on the map.

    Attributes
    ----------
    normal_load : ndarray
        Experiment loads F_z, N.
    map_normal_load : ndarray
        Loads on the solved map, F_z A_map / A_n, N.
    contact_fraction : ndarray
        Non-adhesive A_r/A_map.
    contact_fraction_adhesive : ndarray or None
        Adhesive (Pohrt-Popov) A_r/A_map; None when not run.
    iterations, converged : ndarray
        Per load, non-adhesive then adhesive (shape (n_modes, n_loads)).
    grid : GridChoice
        The refinement check and the chosen stride.
    dx, dy : float
        Pixel sizes of the solved grid, m.
    contact_mask : ndarray
        Contact mask at the largest load (adhesive when run).
    messages : list of str
        Solver messages of runs that did not converge.
    """

    normal_load: np.ndarray
    map_normal_load: np.ndarray
    contact_fraction: np.ndarray
    contact_fraction_adhesive: np.ndarray | None
    iterations: np.ndarray
    converged: np.ndarray
    grid: GridChoice
    dx: float
    dy: float
    contact_mask: np.ndarray
    messages: list[str] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def all_converged(self) -> bool:
        """Every BEM solve converged."""
        return bool(np.all(self.converged))

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
    start = time.perf_counter()
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
    return BemReference(
        normal_load=loads,
        map_normal_load=map_loads,
        contact_fraction=sweeps[0]["contact_fraction"],
        contact_fraction_adhesive=sweeps[1]["contact_fraction"] if len(sweeps) > 1 else None,
        iterations=np.array([sw["iterations"] for sw in sweeps]),
        converged=np.array([sw["converged"] for sw in sweeps]),
        grid=grid,
        dx=dx,
        dy=dy,
        contact_mask=sweeps[-1]["contact_mask"],
        messages=messages,
        seconds=time.perf_counter() - start,
    )


def bem_record(ref: BemReference) -> StageRecord:
    """Stage-3 record."""
    modes = ["non_adhesive", "adhesive"][: ref.iterations.shape[0]]
    mask = ref.contact_mask
    record = StageRecord(
        coords={
            "normal_load": Variable(
                ref.normal_load, "N", ("normal_load",), "normal load on the nominal area"
            ),
            "mode": Variable(
                np.arange(len(modes)), "1", ("mode",), "0 non-adhesive, 1 adhesive (Pohrt-Popov)"
            ),
            "check_stride": Variable(
                ref.grid.strides, "1", ("check_stride",), "strides of the grid refinement check"
            ),
            "mask_x": Variable(np.arange(mask.shape[0]) * ref.dx, "m", ("mask_x",), "x"),
            "mask_y": Variable(np.arange(mask.shape[1]) * ref.dy, "m", ("mask_y",), "y"),
        },
        variables={
            "map_normal_load": Variable(
                ref.map_normal_load, "N", ("normal_load",), "load on the map, F_z A_map / A_n"
            ),
            "contact_fraction": Variable(
                ref.contact_fraction, "1", ("normal_load",), "non-adhesive A_r / A_n"
            ),
            "iterations": Variable(
                ref.iterations, "1", ("mode", "normal_load"), "solver iterations"
            ),
            "converged": Variable(
                ref.converged, "1", ("mode", "normal_load"), "solver converged (1) or not (0)"
            ),
            "check_contact_fraction": Variable(
                ref.grid.contact_fraction,
                "1",
                ("check_stride", "mode"),
                "A_r / A_map at the check pressure",
            ),
            "check_relative_change": Variable(
                ref.grid.relative_change,
                "1",
                ("check_stride",),
                "relative change to the next finer stride",
            ),
            "contact_mask": Variable(
                mask, "1", ("mask_x", "mask_y"), "contact at the largest load"
            ),
        },
        attrs={
            "stride": ref.grid.stride,
            "dx": ref.dx,
            "dy": ref.dy,
            "check_pressure": ref.grid.check_pressure,
            "grid_converged": ref.grid.converged,
            "grid_reason": ref.grid.reason,
            "messages": "\n".join(ref.messages),
            "all_converged": ref.all_converged,
        },
    )
    if ref.contact_fraction_adhesive is not None:
        record.variables["contact_fraction_adhesive"] = Variable(
            ref.contact_fraction_adhesive, "1", ("normal_load",), "adhesive A_r / A_n"
        )
    return record


def bem_from_record(record: StageRecord) -> BemReference:
    """Rebuild the stage-3 result from its stored record."""
    v, a = record.variables, record.attrs
    messages = [m for m in str(a.get("messages", "")).split("\n") if m]
    grid = GridChoice(
        int(a["stride"]),
        record.coords["check_stride"].data,
        v["check_contact_fraction"].data,
        v["check_relative_change"].data,
        float(a["check_pressure"]),
        bool(a["grid_converged"]),
        str(a["grid_reason"]),
    )
    adhesive = v.get("contact_fraction_adhesive")
    return BemReference(
        normal_load=record.coords["normal_load"].data,
        map_normal_load=v["map_normal_load"].data,
        contact_fraction=v["contact_fraction"].data,
        contact_fraction_adhesive=None if adhesive is None else adhesive.data,
        iterations=v["iterations"].data,
        converged=v["converged"].data.astype(bool),
        grid=grid,
        dx=float(a["dx"]),
        dy=float(a["dy"]),
        contact_mask=v["contact_mask"].data.astype(bool),
        messages=messages,
    )
