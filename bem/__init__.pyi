"""The public names of :mod:`asperity.bem`, one line each.

Read by type checkers and editors, and at run time by ``lazy_loader.attach_stub`` in
``__init__.py``, which imports each name on first use (``asperity --help`` then loads no
numba, scipy or h5py); ``__all__`` is these names. ``name as name`` marks a
re-export for type checkers.
"""

from .elastic.fft_backend import crop_to_fast_size as crop_to_fast_size
from .elastic.fft_backend import fast_size as fast_size
from .elastic.pohrt_popov import critical_tension as critical_tension
from .elastic.tangential_influence import tangential_chi as tangential_chi
from .errors import BemInputError as BemInputError
from .normal.adhesion import approach_retract as approach_retract
from .normal.adhesion import pull_off_force as pull_off_force
from .normal.array_solver import solve_periodic_array as solve_periodic_array
from .normal.contact import solve_contact as solve_contact
from .normal.maugis import MaugisLaw as MaugisLaw
from .normal.maugis import cohesive_zone_width as cohesive_zone_width
from .normal.maugis import resolving_range as resolving_range
from .normal.sweep import load_sweep as load_sweep
from .normal.validity import BemWarning as BemWarning
from .options import SolverOptions as SolverOptions
from .progress import solve_progress as solve_progress
from .reference.adhesion_range import RangeChoice as RangeChoice
from .reference.adhesion_range import measure_sensitivity as measure_sensitivity
from .reference.adhesion_range import search_range as search_range
from .reference.discretisation import GridExtrapolation as GridExtrapolation
from .reference.discretisation import UncertaintyBudget as UncertaintyBudget
from .reference.discretisation import combine_in_quadrature as combine_in_quadrature
from .reference.discretisation import combined_uncertainty as combined_uncertainty
from .reference.discretisation import half_spread as half_spread
from .reference.discretisation import richardson_extrapolation as richardson_extrapolation
from .reference.grid_refinement import GridCheck as GridCheck
from .reference.grid_refinement import check_grids as check_grids
from .reference.grid_refinement import discretisation_estimate as discretisation_estimate
from .reference.grid_refinement import edge_mismatch as edge_mismatch
from .reference.grid_refinement import grid_extrapolations as grid_extrapolations
from .reference.grid_refinement import resolution_dependence as resolution_dependence
from .reference.interpolated_refinement import InterpolatedRefinement as InterpolatedRefinement
from .reference.interpolated_refinement import fourier_upsample as fourier_upsample
from .reference.interpolated_refinement import fourier_upsample_window as fourier_upsample_window
from .reference.interpolated_refinement import refine_by_interpolation as refine_by_interpolation
from .reference.load_sweeps import ContactSetup as ContactSetup
from .reference.load_sweeps import Grid as Grid
from .reference.load_sweeps import LoadChain as LoadChain
from .reference.load_sweeps import SolveSummary as SolveSummary
from .reference.load_sweeps import decimated_grid as decimated_grid
from .reference.load_sweeps import solve_chain as solve_chain
from .reference.solve import ReferenceSolves as ReferenceSolves
from .reference.solve import solve_reference as solve_reference
from .result import ContactResult as ContactResult
from .result import SolverStatus as SolverStatus
from .shear.mixed_mode import MixedModeLaw as MixedModeLaw
from .shear.mixed_mode import adhesive_shear_solve as adhesive_shear_solve
from .shear.mixed_mode import sliding_state as sliding_state
from .shear.mixed_mode import tangential_sweep as tangential_sweep
from .shear.rough import ShearCurve as ShearCurve
from .shear.rough import label_junctions as label_junctions
from .shear.rough import shear_curve as shear_curve
from .shear.rough_mixed_mode import mixed_mode_shear_curve as mixed_mode_shear_curve
from .shear.stick_slip import ShearOptions as ShearOptions
from .shear.stick_slip import TangentialResult as TangentialResult
from .shear.stick_slip import solve_tangential as solve_tangential
from .shear.stick_slip import traction_bound as traction_bound
