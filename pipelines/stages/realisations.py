"""The realisations stage: the spread of the BEM's A_r(F_z) over maps synthesised from a line
profile.

A line profile fixes the spectrum of the isotropic surface it samples, not its phases: the BEM
reference of a profile job (:mod:`asperity.pipelines.stages.bem`) is solved on one map
synthesised with random phases (realisation 0, seed ``surface.profile_seed``). This stage
synthesises ``surface.profile_realisations - 1`` more (seeds ``profile_seed + 1, ...``), solves
each at the job's loads on the BEM stage's grid (its decimation stride, boundary, tolerance, and
its adhesive solve when the BEM ran one: the same law, Maugis-Dugdale with the range the BEM
stage chose, or Pohrt-Popov, eq:max_sigma) with
:func:`bem.load_sweep`, and stores A_r/A_n of every realisation, their mean, sample standard
deviation and relative spread per load. The spread is how much the BEM reference owes to the
phases the profile cannot give; the report states it with the number of realisations.

Enabled only for a line profile as input with the BEM on and more than one realisation. Loads
are scaled to the map at equal nominal pressure, F_map = F_z A_map / A_n, as in the BEM stage.
SI units: N, m, m^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity import bem
from asperity.bem.reference.load_sweeps import decimated_grid
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.config import JobConfig
from asperity.pipelines.engine.parallel import run_map
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.stages._profile import input_is_profile, synthesised_map
from asperity.pipelines.stages.bem import BEM, BemReference
from asperity.pipelines.stages.surface import SURFACE

__all__ = ["REALISATIONS", "RealisationSpread", "compute_realisations", "solve_realisation"]


@document_fields
@dataclass
class RealisationSpread:
    """Realisations-stage result: A_r/A_n of the BEM over maps synthesised from one profile.

    Realisation 0 is the BEM stage's own map (its values are copied from it); the others are
    solved here on the same grid.
    """

    normal_load: np.ndarray = array("N", ("normal_load",), "normal load on the nominal area")
    seed: np.ndarray = array("1", ("realisation",), "seed of each synthesised map")
    contact_fraction: np.ndarray = array(
        "1", ("realisation", "normal_load"), "BEM A_r / A_n of each realisation"
    )
    converged: np.ndarray = array(
        "1", ("realisation", "normal_load"), "every solve of that realisation and load converged"
    )
    mean_fraction: np.ndarray = array("1", ("normal_load",), "mean A_r / A_n over realisations")
    std_fraction: np.ndarray = array(
        "1", ("normal_load",), "sample standard deviation of A_r / A_n over realisations"
    )
    relative_spread: np.ndarray = array(
        "1", ("normal_load",), "std / mean of A_r / A_n over realisations"
    )
    realisations: int = scalar("1", "maps synthesised and solved (the BEM stage's included)")
    map_pixels: int = scalar("1", "pixels per side of each synthesised map")
    pixel_size: float = scalar("m", "pixel size of each synthesised map (the profile's dx)")
    stride: int = scalar("1", "decimation of the maps solved (the BEM stage's)")
    max_relative_spread: float = scalar("1", "largest relative spread over the loads")
    mode: str = text("which BEM area: adhesive (its law and range) or non-adhesive")
    messages: list[str] = text("messages of solves that did not converge")


def solve_realisation(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    map_loads: np.ndarray,
    solver: dict,
    work_of_adhesion: float,
    adhesion: tuple[str, float | None] = ("pohrt-popov", None),
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """A_r/A_map of one map at every load, non-adhesive, then adhesive when ``w > 0``.

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Heights of the solved grid, m.
    dx, dy : float
        Pixel sizes, m.
    e_star : float
        E*, Pa.
    map_loads : ndarray
        Loads on the map, N (any order).
    solver : dict
        ``options`` (a :class:`bem.SolverOptions`) and ``periodic`` of
        :func:`bem.solve_contact`.
    work_of_adhesion : float
        w, J/m^2; 0 for the non-adhesive solve alone.
    adhesion : (str, float or None)
        The BEM stage's adhesion law and its range h_0 (m) for ``"maugis"``
        (:func:`bem.solve_contact`'s ``adhesion`` and ``adhesion_range``), so that every
        realisation is solved as the reference map was.

    Returns
    -------
    fraction, converged, messages
        A_r/A_map and convergence per load (in the order of ``map_loads``; the adhesive
        solve's when run), and the messages of solves that did not converge.
    """
    order = np.argsort(map_loads, kind="stable")
    forces = [float(map_loads[i]) for i in order]
    plain = bem.load_sweep(heights, dx, dy, e_star, forces, **solver)
    results = plain
    if work_of_adhesion > 0:
        start = plain if all(r.success for r in plain) else None  # else solved from scratch
        results = bem.load_sweep(
            heights, dx, dy, e_star, forces, non_adhesive=start,
            work_of_adhesion=work_of_adhesion, adhesion=adhesion[0],
            adhesion_range=adhesion[1], **solver,
        )  # fmt: skip
    fraction = np.empty(len(forces))
    converged = np.empty(len(forces), dtype=bool)
    for i, a, b in zip(order, plain, results, strict=True):
        fraction[i] = b.contact_fraction
        converged[i] = bool(a.success and b.success)
    messages = [r.message for r in (*plain, *results) if not r.success]
    return fraction, converged, list(dict.fromkeys(messages))


def spread_over(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean, sample standard deviation (NaN for one row) and std / mean over axis 0."""
    mean = values.mean(axis=0)
    std = values.std(axis=0, ddof=1) if values.shape[0] > 1 else np.full(mean.shape, math.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(mean > 0, std / mean, math.nan)
    return mean, std, relative


def _jobs(context: StageContext, reference: BemReference) -> list[tuple]:
    """One :func:`solve_realisation` call per realisation after the first."""
    config = context.config
    profile = context.result(SURFACE).line_profile()
    w = config.material.work_of_adhesion
    w = w if config.bem.adhesive and reference.contact_fraction_adhesive is not None else 0.0
    solver = {
        "options": bem.SolverOptions(tol=config.bem.tol, max_iter=config.bem.max_iter),
        "periodic": config.bem.boundary == "periodic",
    }
    jobs = []
    for index in range(1, config.surface.profile_realisations):
        surface = synthesised_map(profile, config.surface, index)
        grid = decimated_grid(surface.heights, surface.dx, surface.dy, int(reference.stride))
        map_loads = reference.normal_load * grid.area / config.loading.nominal_area
        law = (config.bem.adhesion, reference.adhesion_range)
        jobs.append(
            (grid.heights, grid.dx, grid.dy, config.material.e_star, map_loads, solver, w, law)
        )
    return jobs


def compute_realisations(context: StageContext) -> RealisationSpread:
    """The job's realisations stage (module docstring)."""
    config = context.config
    reference = context.result(BEM)
    jobs = _jobs(context, reference)
    solved = run_map(
        solve_realisation, jobs, context.executor, desc="realisations", progress=context.progress
    )
    fractions = np.vstack([reference.reference_fraction(), *(s[0] for s in solved)])
    converged = np.vstack([np.all(reference.converged, axis=0), *(s[1] for s in solved)])
    mean, std, relative = spread_over(fractions)
    adhesive = reference.contact_fraction_adhesive is not None
    return RealisationSpread(
        normal_load=np.asarray(reference.normal_load, dtype=float),
        seed=config.surface.profile_seed + np.arange(fractions.shape[0]),
        contact_fraction=fractions,
        converged=converged,
        mean_fraction=mean,
        std_fraction=std,
        relative_spread=relative,
        realisations=int(fractions.shape[0]),
        map_pixels=int(config.surface.profile_synthesis_n),
        pixel_size=float(context.result(SURFACE).dx),
        stride=int(reference.stride),
        max_relative_spread=float(np.nanmax(relative)) if np.isfinite(relative).any() else math.nan,
        mode=_mode(config.bem.adhesion, reference.adhesion_range) if adhesive else "non-adhesive",
        messages=[m for s in solved for m in s[2]],
    )


def _mode(adhesion: str, adhesion_range: float | None) -> str:
    """Which BEM area the spread is of, in words (the reference map's law and range)."""
    if adhesion == "maugis":
        return f"adhesive (Maugis-Dugdale, range {adhesion_range:.3g} m)"
    return "adhesive (Pohrt-Popov)"


def realisations_enabled(config: JobConfig) -> bool:
    """A line profile as input, the BEM on, and more than one realisation asked for."""
    return (
        config.bem.enabled
        and config.surface.profile_realisations > 1
        and input_is_profile(config.surface)
    )


REALISATIONS = Stage(
    name="realisations",
    title="profile realisations",
    result=RealisationSpread,
    config=(
        "surface.profile_synthesis_n",
        "surface.profile_seed",
        "surface.profile_realisations",
        "material.E_star",
        "material.work_of_adhesion",
        "loading.nominal_area",
        "bem.tol",
        "bem.max_iter",
        "bem.adhesive",
        "bem.adhesion",
        "bem.boundary",
    ),
    inputs=(SURFACE, BEM),
    compute=compute_realisations,
    enabled=realisations_enabled,
)
