"""The public names of :mod:`asperity.bem`, one line each.

Read by type checkers and editors, and at run time by ``lazy_loader.attach_stub`` in
``__init__.py``, which imports each name on first use (``asperity --help`` then loads no
numba, scipy or h5py); ``__all__`` is these names. ``name as name`` marks a
re-export for type checkers.
"""

from .adhesion import approach_retract as approach_retract
from .adhesion import pull_off_force as pull_off_force
from .adhesion_range import RangeChoice as RangeChoice
from .adhesion_range import measure_sensitivity as measure_sensitivity
from .adhesion_range import search_range as search_range
from .array_solver import solve_periodic_array as solve_periodic_array
from .contact import solve_contact as solve_contact
from .discretisation import GridExtrapolation as GridExtrapolation
from .discretisation import UncertaintyBudget as UncertaintyBudget
from .discretisation import combine_in_quadrature as combine_in_quadrature
from .discretisation import combined_uncertainty as combined_uncertainty
from .discretisation import half_spread as half_spread
from .discretisation import richardson_extrapolation as richardson_extrapolation
from .errors import BemInputError as BemInputError
from .fft_backend import crop_to_fast_size as crop_to_fast_size
from .fft_backend import fast_size as fast_size
from .grid_refinement import GridCheck as GridCheck
from .grid_refinement import check_grids as check_grids
from .grid_refinement import discretisation_estimate as discretisation_estimate
from .grid_refinement import edge_mismatch as edge_mismatch
from .grid_refinement import grid_extrapolations as grid_extrapolations
from .grid_refinement import resolution_dependence as resolution_dependence
from .interpolated_refinement import InterpolatedRefinement as InterpolatedRefinement
from .interpolated_refinement import fourier_upsample as fourier_upsample
from .interpolated_refinement import fourier_upsample_window as fourier_upsample_window
from .interpolated_refinement import refine_by_interpolation as refine_by_interpolation
from .load_sweeps import ContactSetup as ContactSetup
from .load_sweeps import Grid as Grid
from .load_sweeps import LoadChain as LoadChain
from .load_sweeps import SolveSummary as SolveSummary
from .load_sweeps import decimated_grid as decimated_grid
from .load_sweeps import solve_chain as solve_chain
from .maugis import MaugisLaw as MaugisLaw
from .maugis import cohesive_zone_width as cohesive_zone_width
from .maugis import resolving_range as resolving_range
from .mixed_mode import MixedModeLaw as MixedModeLaw
from .mixed_mode import adhesive_shear_solve as adhesive_shear_solve
from .mixed_mode import sliding_state as sliding_state
from .mixed_mode import tangential_sweep as tangential_sweep
from .options import SolverOptions as SolverOptions
from .pohrt_popov import critical_tension as critical_tension
from .progress import solve_progress as solve_progress
from .reference import ReferenceSolves as ReferenceSolves
from .reference import solve_reference as solve_reference
from .result import ContactResult as ContactResult
from .result import SolverStatus as SolverStatus
from .rough_mixed_mode import mixed_mode_shear_curve as mixed_mode_shear_curve
from .rough_shear import ShearCurve as ShearCurve
from .rough_shear import label_junctions as label_junctions
from .rough_shear import shear_curve as shear_curve
from .shear import ShearOptions as ShearOptions
from .shear import TangentialResult as TangentialResult
from .shear import solve_tangential as solve_tangential
from .shear import traction_bound as traction_bound
from .sweep import load_sweep as load_sweep
from .tangential_influence import tangential_chi as tangential_chi
from .validity import BemWarning as BemWarning
