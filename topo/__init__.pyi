"""The public names of :mod:`asperity.topo`, one line each.

Read by type checkers and editors, and at run time by ``lazy_loader.attach_stub`` in
``__init__.py``, which imports each name on first use (``asperity --help`` then loads no
numba, scipy or h5py); ``__all__`` is these names. ``name as name`` marks a
re-export for type checkers.
"""

from . import synthetic as synthetic
from .cleaning import CropWindow as CropWindow
from .cleaning import OutlierRule as OutlierRule
from .cleaning import crop_surface as crop_surface
from .cleaning import fill_missing as fill_missing
from .cleaning import find_outliers as find_outliers
from .errors import TopographyFileError as TopographyFileError
from .errors import TopoWarning as TopoWarning
from .fractional_resampling import fractional_resample as fractional_resample
from .fractional_resampling import fractional_summit_statistics as fractional_summit_statistics
from .heightmap import HeightMap as HeightMap
from .heightmap import LineProfile as LineProfile
from .inpainting import harmonic_fill as harmonic_fill
from .io import read_surface as read_surface
from .io import write_hdf5 as write_hdf5
from .levelling import level as level
from .nayak import ProfileStatistics as ProfileStatistics
from .nayak import profile_statistics as profile_statistics
from .preparation import PreparationOptions as PreparationOptions
from .preparation import PreparationRecord as PreparationRecord
from .preparation import PreparedSurface as PreparedSurface
from .preparation import prepare_surface as prepare_surface
from .profile_preparation import prepare_profile as prepare_profile
from .profile_scan import ProfileResolutionScan as ProfileResolutionScan
from .profile_scan import profile_resolution_scan as profile_resolution_scan
from .profile_synthesis import RealisationSpread as RealisationSpread
from .profile_synthesis import realisation_spread as realisation_spread
from .profile_synthesis import synthesise_from_profile as synthesise_from_profile
from .psd import HurstEstimate as HurstEstimate
from .psd import hurst_from_psd_exponent as hurst_from_psd_exponent
from .psd import radial_psd as radial_psd
from .psd import rms_curvature as rms_curvature
from .psd import rms_height as rms_height
from .psd import rms_slope as rms_slope
from .psd import rolloff_wavelength as rolloff_wavelength
from .resampling import block_mean as block_mean
from .resampling import decimate as decimate
from .resampling import fourier_resample as fourier_resample
from .scan import ResolutionScan as ResolutionScan
from .scan import draw_resolution_scan as draw_resolution_scan
from .scan import plot_resolution_scan as plot_resolution_scan
from .scan import resolution_scan as resolution_scan
from .scan import write_scan_hdf5 as write_scan_hdf5
from .summits import SummitStatistics as SummitStatistics
from .summits import summit_mask as summit_mask
from .summits import summit_statistics as summit_statistics
