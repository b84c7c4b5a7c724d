"""The public names of :mod:`asperity.statmodel`, one line each.

Read by type checkers and editors, and at run time by ``lazy_loader.attach_stub`` in
``__init__.py``, which imports each name on first use (``asperity --help`` then loads no
numba, scipy or h5py); ``__all__`` is these names. ``name as name`` marks a
re-export for type checkers.
"""

from .checks import Check as Check
from .checks import StatmodelWarning as StatmodelWarning
from .effective_resolution import EffectiveResolution as EffectiveResolution
from .effective_resolution import locate_least_misfit as locate_least_misfit
from .effective_resolution import roughness_at_resolution as roughness_at_resolution
from .figures import draw_shear_curve as draw_shear_curve
from .hertz import hertz_contact_radius as hertz_contact_radius
from .hertz import hertz_normal_load as hertz_normal_load
from .hertz import hertz_sliding_tangential_load as hertz_sliding_tangential_load
from .jkr import jkr_contact_radius as jkr_contact_radius
from .jkr import jkr_jump_in_distance as jkr_jump_in_distance
from .jkr import jkr_jump_off_distance as jkr_jump_off_distance
from .jkr import jkr_normal_load as jkr_normal_load
from .jkr import jkr_pull_off_force_fixed_grip as jkr_pull_off_force_fixed_grip
from .jkr import jkr_pull_off_force_load_control as jkr_pull_off_force_load_control
from .jkr import jkr_zero_load_radius as jkr_zero_load_radius
from .options import QuadratureOptions as QuadratureOptions
from .papangelo_ciavarella import pc_contact_radius as pc_contact_radius
from .papangelo_ciavarella import pc_fold_radius as pc_fold_radius
from .papangelo_ciavarella import pc_max_tangential_displacement as pc_max_tangential_displacement
from .papangelo_ciavarella import pc_min_indentation as pc_min_indentation
from .papangelo_ciavarella import pc_normal_load as pc_normal_load
from .papangelo_ciavarella import pc_tangential_load as pc_tangential_load
from .parameters import Material as Material
from .parameters import Roughness as Roughness
from .parameters import TaborWarning as TaborWarning
from .parameters import tabor_parameter as tabor_parameter
from .persson import KAPPA_PERSSON as KAPPA_PERSSON
from .persson import PerssonResult as PerssonResult
from .persson import persson_contact_fraction as persson_contact_fraction
from .persson import persson_psd as persson_psd
from .persson import persson_real_area as persson_real_area
from .persson import persson_small_load_fraction as persson_small_load_fraction
from .persson import psd_rms_slope as psd_rms_slope
from .plausibility import contact_pressure_check as contact_pressure_check
from .plausibility import junction_shear_check as junction_shear_check
from .plausibility import plasticity_index as plasticity_index
from .plausibility import plasticity_index_check as plasticity_index_check
from .plausibility import static_to_sliding_check as static_to_sliding_check
from .preloading import PreloadResult as PreloadResult
from .preloading import preload as preload
from .preloading import pull_off_force as pull_off_force
from .preloading import real_area_at_loads as real_area_at_loads
from .preloading import unloading_pull_off_force as unloading_pull_off_force
from .regimes import FULL_CONTACT_MEANING as FULL_CONTACT_MEANING
from .regimes import FULL_CONTACT_REASON as FULL_CONTACT_REASON
from .regimes import AdhesionRegime as AdhesionRegime
from .regimes import FlatteningEnergy as FlatteningEnergy
from .regimes import adhesion_regime as adhesion_regime
from .regimes import flattening_energy as flattening_energy
from .regimes import full_contact_check as full_contact_check
from .regimes import pastewka_robbins_range_ratio as pastewka_robbins_range_ratio
from .regimes import pastewka_robbins_stickiness as pastewka_robbins_stickiness
from .shear import ShearCurve as ShearCurve
from .shear import shear_curve as shear_curve
from .shear import shear_curve_fixed_separation as shear_curve_fixed_separation
from .status_map import OUT_OF_CONTACT as OUT_OF_CONTACT
from .status_map import SLIDE as SLIDE
from .status_map import STICK as STICK
from .status_map import asperity_status as asperity_status
from .status_map import dimensionless_unstable_boundary as dimensionless_unstable_boundary
from .uncertainty import PredictionUncertainty as PredictionUncertainty
from .uncertainty import propagate_to_predictions as propagate_to_predictions
