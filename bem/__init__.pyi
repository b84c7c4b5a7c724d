"""The public names of :mod:`asperity.bem`, one line each.

Read by type checkers and editors, and at run time by ``lazy_loader.attach_stub`` in
``__init__.py``, which imports each name on first use (``asperity --help`` then loads no
numba, scipy or h5py); ``__all__`` is these names. ``name as name`` marks a
re-export for type checkers.
"""

from .adhesion import approach_retract as approach_retract
from .adhesion import pull_off_force as pull_off_force
from .discretisation import GridExtrapolation as GridExtrapolation
from .discretisation import UncertaintyBudget as UncertaintyBudget
from .discretisation import combine_in_quadrature as combine_in_quadrature
from .discretisation import half_spread as half_spread
from .discretisation import richardson_extrapolation as richardson_extrapolation
from .errors import BemInputError as BemInputError
from .fft_backend import crop_to_fast_size as crop_to_fast_size
from .fft_backend import fast_size as fast_size
from .maugis import MaugisLaw as MaugisLaw
from .maugis import cohesive_zone_width as cohesive_zone_width
from .maugis import resolving_range as resolving_range
from .options import SolverOptions as SolverOptions
from .pohrt_popov import critical_tension as critical_tension
from .polonsky_keer import solve_contact as solve_contact
from .result import ContactResult as ContactResult
from .result import SolverStatus as SolverStatus
from .sweep import load_sweep as load_sweep
