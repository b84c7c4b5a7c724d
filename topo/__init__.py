"""topo: measured and synthetic height maps -> asperity statistics (paper, Appendix A).

Public API (SI units: m, m^2, 1/m^2):

* containers: :class:`HeightMap`, :class:`LineProfile`;
* reading: :func:`read_surface` (X3P, SUR, MetroPro DAT/DATX, PLU, OPD, Nanoscope, PicoView,
  Gwyddion, Dektak CSV, text, NumPy, project HDF5; some forty more through the ``formats``
  extra), :func:`write_hdf5`;
* preparation :func:`prepare_surface` (crop, form removal, outliers, missing pixels, with a
  record and warnings; the steps separately: :func:`crop_surface`, :func:`find_outliers`,
  :func:`fill_missing`, :func:`harmonic_fill`); form removal :func:`level`;
  resampling :func:`decimate`, :func:`block_mean`, :func:`fourier_resample`;
* :func:`summit_statistics` (eta, R, sigma_s), :func:`resolution_scan` (Fig 12a-c);
* line profiles (Nayak's theory, isotropy assumed): :func:`prepare_profile`,
  :func:`profile_statistics`, :func:`profile_resolution_scan`; isotropic maps from a profile's
  spectrum: :func:`synthesise_from_profile`, :func:`realisation_spread`;
* spectra and rms values in :mod:`topo.psd`; synthetic maps in :mod:`topo.synthetic`.
"""

from __future__ import annotations

import importlib
from typing import Any

# Public names and the module that defines each; imported on first use so that
# `asperity --help` and light sub-commands do not load numba kernels they never call.
_EXPORTS: dict[str, str] = {
    "synthetic": "asperity.topo.synthetic",
    "TopographyFileError": "asperity.topo.errors",
    "HeightMap": "asperity.topo.heightmap",
    "LineProfile": "asperity.topo.heightmap",
    "read_surface": "asperity.topo.io",
    "write_hdf5": "asperity.topo.io",
    "level": "asperity.topo.levelling",
    "CropWindow": "asperity.topo.cleaning",
    "OutlierRule": "asperity.topo.cleaning",
    "crop_surface": "asperity.topo.cleaning",
    "fill_missing": "asperity.topo.cleaning",
    "find_outliers": "asperity.topo.cleaning",
    "harmonic_fill": "asperity.topo.inpainting",
    "PreparationOptions": "asperity.topo.preparation",
    "PreparationRecord": "asperity.topo.preparation",
    "PreparedSurface": "asperity.topo.preparation",
    "prepare_surface": "asperity.topo.preparation",
    "radial_psd": "asperity.topo.psd",
    "rms_curvature": "asperity.topo.psd",
    "rms_height": "asperity.topo.psd",
    "rms_slope": "asperity.topo.psd",
    "rolloff_wavelength": "asperity.topo.psd",
    "block_mean": "asperity.topo.resampling",
    "decimate": "asperity.topo.resampling",
    "fourier_resample": "asperity.topo.resampling",
    "ResolutionScan": "asperity.topo.scan",
    "draw_resolution_scan": "asperity.topo.scan",
    "plot_resolution_scan": "asperity.topo.scan",
    "resolution_scan": "asperity.topo.scan",
    "write_scan_hdf5": "asperity.topo.scan",
    "ProfileStatistics": "asperity.topo.nayak",
    "profile_statistics": "asperity.topo.nayak",
    "ProfileResolutionScan": "asperity.topo.profile_scan",
    "profile_resolution_scan": "asperity.topo.profile_scan",
    "prepare_profile": "asperity.topo.profile_preparation",
    "RealisationSpread": "asperity.topo.profile_synthesis",
    "realisation_spread": "asperity.topo.profile_synthesis",
    "synthesise_from_profile": "asperity.topo.profile_synthesis",
    "SummitStatistics": "asperity.topo.summits",
    "summit_mask": "asperity.topo.summits",
    "summit_statistics": "asperity.topo.summits",
    "fractional_resample": "asperity.topo.fractional_resampling",
    "fractional_summit_statistics": "asperity.topo.fractional_resampling",
}

__all__ = [
    "CropWindow",
    "HeightMap",
    "LineProfile",
    "OutlierRule",
    "PreparationOptions",
    "PreparationRecord",
    "PreparedSurface",
    "ProfileResolutionScan",
    "ProfileStatistics",
    "RealisationSpread",
    "ResolutionScan",
    "SummitStatistics",
    "TopographyFileError",
    "block_mean",
    "crop_surface",
    "decimate",
    "draw_resolution_scan",
    "fill_missing",
    "find_outliers",
    "fourier_resample",
    "harmonic_fill",
    "level",
    "plot_resolution_scan",
    "prepare_profile",
    "prepare_surface",
    "profile_resolution_scan",
    "profile_statistics",
    "radial_psd",
    "read_surface",
    "realisation_spread",
    "resolution_scan",
    "rms_curvature",
    "rms_height",
    "rms_slope",
    "rolloff_wavelength",
    "summit_mask",
    "summit_statistics",
    "synthesise_from_profile",
    "synthetic",
    "write_hdf5",
    "write_scan_hdf5",
    "fractional_resample",
    "fractional_summit_statistics",
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
