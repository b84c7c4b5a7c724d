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

import lazy_loader

# The public names are the imports in __init__.pyi (also what type checkers read); each is
# imported on first use, so that `asperity --help` and light sub-commands load no numba kernel.
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
