"""asperity.bem: FFT boundary elements for the normal contact of rough elastic surfaces.

Polonsky-Keer constrained conjugate gradients (load or displacement control) with the
Pohrt-Popov mesh-dependent adhesion criterion (paper Appendix B, eqs. E:BEM_eq1..E:BEM_eq4,
eq:PohrtPopov_G, eq:max_sigma). Works on plain arrays of heights (m) with pixel sizes (m).
"""

from __future__ import annotations

import importlib
from typing import Any

# Public names and the module that defines each; imported on first use so that
# `asperity --help` and light sub-commands do not load numba kernels they never call.
_EXPORTS: dict[str, str] = {
    "approach_retract": "asperity.bem.adhesion",
    "critical_tension": "asperity.bem.pohrt_popov",
    "pull_off_force": "asperity.bem.adhesion",
    "crop_to_fast_size": "asperity.bem.fft_backend",
    "fast_size": "asperity.bem.fft_backend",
    "solve_contact": "asperity.bem.contact",
    "ContactResult": "asperity.bem.result",
    "SolverOptions": "asperity.bem.options",
    "SolverStatus": "asperity.bem.result",
    "BemInputError": "asperity.bem.errors",
    "load_sweep": "asperity.bem.sweep",
    "MaugisLaw": "asperity.bem.maugis",
    "cohesive_zone_width": "asperity.bem.maugis",
    "resolving_range": "asperity.bem.maugis",
    "GridExtrapolation": "asperity.bem.discretisation",
    "UncertaintyBudget": "asperity.bem.discretisation",
    "combine_in_quadrature": "asperity.bem.discretisation",
    "half_spread": "asperity.bem.discretisation",
    "richardson_extrapolation": "asperity.bem.discretisation",
    "combined_uncertainty": "asperity.bem.discretisation",
    "ContactSetup": "asperity.bem.load_sweeps",
    "Grid": "asperity.bem.load_sweeps",
    "LoadChain": "asperity.bem.load_sweeps",
    "SolveSummary": "asperity.bem.load_sweeps",
    "decimated_grid": "asperity.bem.load_sweeps",
    "solve_chain": "asperity.bem.load_sweeps",
    "GridCheck": "asperity.bem.grid_refinement",
    "check_grids": "asperity.bem.grid_refinement",
    "edge_mismatch": "asperity.bem.grid_refinement",
    "grid_extrapolations": "asperity.bem.grid_refinement",
    "RangeChoice": "asperity.bem.adhesion_range",
    "search_range": "asperity.bem.adhesion_range",
    "measure_sensitivity": "asperity.bem.adhesion_range",
    "ReferenceSolves": "asperity.bem.reference",
    "solve_reference": "asperity.bem.reference",
    "discretisation_estimate": "asperity.bem.grid_refinement",
    "resolution_dependence": "asperity.bem.grid_refinement",
    "InterpolatedRefinement": "asperity.bem.interpolated_refinement",
    "fourier_upsample": "asperity.bem.interpolated_refinement",
    "fourier_upsample_window": "asperity.bem.interpolated_refinement",
    "refine_by_interpolation": "asperity.bem.interpolated_refinement",
}

__all__ = [
    "BemInputError",
    "ContactResult",
    "SolverOptions",
    "SolverStatus",
    "approach_retract",
    "critical_tension",
    "crop_to_fast_size",
    "fast_size",
    "MaugisLaw",
    "cohesive_zone_width",
    "load_sweep",
    "pull_off_force",
    "resolving_range",
    "solve_contact",
    "GridExtrapolation",
    "UncertaintyBudget",
    "combine_in_quadrature",
    "half_spread",
    "richardson_extrapolation",
    "combined_uncertainty",
    "ContactSetup",
    "Grid",
    "LoadChain",
    "SolveSummary",
    "decimated_grid",
    "solve_chain",
    "GridCheck",
    "check_grids",
    "edge_mismatch",
    "grid_extrapolations",
    "RangeChoice",
    "search_range",
    "measure_sensitivity",
    "ReferenceSolves",
    "solve_reference",
    "discretisation_estimate",
    "resolution_dependence",
    "InterpolatedRefinement",
    "fourier_upsample",
    "fourier_upsample_window",
    "refine_by_interpolation",
]


def __getattr__(name: str) -> Any:
    module_name = _EXPORTS.get(name)
    if module_name is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = importlib.import_module(module_name)
    value = module if module_name == f"{__name__}.{name}" else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
