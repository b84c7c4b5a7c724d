"""topo: measured and synthetic height maps -> asperity statistics (paper, Appendix A).

Public API (SI units: m, m^2, 1/m^2):

* containers: :class:`HeightMap`, :class:`LineProfile`;
* reading: :func:`read_surface` (X3P, SUR, MetroPro DAT/DATX, PLU, OPD, Nanoscope, PicoView,
  Gwyddion, Dektak CSV, text, NumPy, project HDF5), :func:`write_hdf5`;
* form removal :func:`level`; resampling :func:`decimate`, :func:`block_mean`,
  :func:`fourier_resample`;
* :func:`summit_statistics` (eta, R, sigma_s), :func:`resolution_scan` (Fig 12a-c);
* spectra and rms values in :mod:`topo.psd`; synthetic maps in :mod:`topo.synthetic`.
"""

from topo import synthetic
from topo.errors import TopographyFileError
from topo.heightmap import HeightMap, LineProfile
from topo.io import read_surface, write_hdf5
from topo.levelling import level
from topo.psd import radial_psd, rms_curvature, rms_height, rms_slope, rolloff_wavelength
from topo.resampling import block_mean, decimate, fourier_resample
from topo.scan import ResolutionScan, plot_resolution_scan, resolution_scan, write_scan_hdf5
from topo.summits import SummitStatistics, summit_mask, summit_statistics

__all__ = [
    "HeightMap",
    "LineProfile",
    "ResolutionScan",
    "SummitStatistics",
    "TopographyFileError",
    "block_mean",
    "decimate",
    "fourier_resample",
    "level",
    "plot_resolution_scan",
    "radial_psd",
    "read_surface",
    "resolution_scan",
    "rms_curvature",
    "rms_height",
    "rms_slope",
    "rolloff_wavelength",
    "summit_mask",
    "summit_statistics",
    "synthetic",
    "write_hdf5",
    "write_scan_hdf5",
]
