"""Resolution scan: summit statistics of the map decimated by strides 1..K (paper, Fig 12a-c).

For every stride k the map is decimated (keep one point in k, a strided view) and the
Appendix A statistics are computed. The paper's observations are fitted:

* ``R`` linear in the resolution ``Delta``: ``R = radius_slope * Delta + radius_intercept``;
* ``eta`` a power law: ``eta = density_prefactor * Delta ** density_exponent`` (least
  squares in log-log; the paper finds an exponent of -1.12);
* ``sigma_s`` nearly constant: its mean and relative spread (std/mean).

The resolution of stride k is ``k * sqrt(dx * dy)`` (m), i.e. ``k dx`` for square pixels.
Strides with fewer than ``min_summits`` summits are left out of the fits.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, SupportsFloat

import numpy as np

from asperity import h5
from asperity.errors import InputError
from asperity.fields import array, document_fields, field_specs, scalar
from asperity.plotting import (
    display_unit,
    legend_below,
    new_figure,
    plain_log_ticks,
    save_figure,
)
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.summits import summit_statistics

if TYPE_CHECKING:
    from matplotlib.figure import Figure

ARRAY_FIELDS = (
    "stride",
    "resolution",
    "n_summits",
    "asperity_density",
    "summit_radius",
    "summit_height_rms",
)
FIT_FIELDS = (
    "radius_slope",
    "radius_intercept",
    "density_exponent",
    "density_prefactor",
    "height_rms_mean",
    "height_rms_relative_spread",
    "n_fitted",
)


@document_fields
@dataclass(frozen=True, eq=False)
class ResolutionScan:
    """Summit statistics against resolution, with the paper's fits (SI units).

    Attributes
    ----------
    stride : ndarray of int
        1..K.
    resolution : ndarray
        ``stride * sqrt(dx dy)`` (m).
    n_summits, asperity_density, summit_radius, summit_height_rms : ndarray
        Per stride: N, eta (1/m^2), R (m), sigma_s (m).
    radius_slope : float
        dR/dDelta (m/m) of the linear fit.
    radius_intercept : float
        R at zero resolution (m) of the linear fit.
    density_exponent : float
        Exponent of the power law eta ~ Delta^exponent.
    density_prefactor : float
        Prefactor of that power law (1/m^2 / m^exponent, i.e. eta at Delta = 1 m).
    height_rms_mean : float
        Mean of sigma_s over the fitted strides (m).
    height_rms_relative_spread : float
        Standard deviation / mean of sigma_s over the fitted strides.
    n_fitted : int
        Number of strides used by the fits.
    neighbours : int
        Summit rule (4 or 8).
    nominal_area : ndarray or None
        Per stride, the valid area (m^2) over which the summits are counted (eta = N /
        nominal_area; see :func:`asperity.topo.summit_statistics`).
    """

    stride: np.ndarray = array("1", ("stride",), "decimation stride")
    resolution: np.ndarray = array("m", ("stride",), "pixel size of the decimated map")
    n_summits: np.ndarray = array("1", ("stride",), "number of summits N (neighbours rule)")
    asperity_density: np.ndarray = array("1/m^2", ("stride",), "asperity density eta")
    summit_radius: np.ndarray = array("m", ("stride",), "mean summit radius R")
    summit_height_rms: np.ndarray = array("m", ("stride",), "rms summit height sigma_s")
    radius_slope: float = scalar("m/m", "dR/d(resolution) of the linear fit")
    radius_intercept: float = scalar("m", "R at zero resolution of the linear fit")
    density_exponent: float = scalar("1", "exponent of eta ~ resolution**exponent")
    density_prefactor: float = scalar("1/m^2", "eta at a resolution of 1 m (power law)")
    height_rms_mean: float = scalar("m", "mean sigma_s over the fitted strides")
    height_rms_relative_spread: float = scalar("1", "std / mean of sigma_s over the fits")
    n_fitted: int = scalar("1", "number of strides used by the fits")
    neighbours: int = scalar("1", "summit rule (4 or 8 neighbours)", default=4)
    nominal_area: np.ndarray | None = array(
        "m^2", ("stride",), "valid area over which the summits are counted", optional=True
    )

    def fits(self) -> dict:
        """The fitted parameters as a dict of Python numbers."""
        return {name: _plain(getattr(self, name)) for name in FIT_FIELDS}

    def as_dict(self) -> dict:
        """Arrays (as lists) and fits, JSON-ready."""
        data = {name: getattr(self, name).tolist() for name in ARRAY_FIELDS}
        data.update(self.fits())
        data["neighbours"] = self.neighbours
        if self.nominal_area is not None:
            data["nominal_area"] = self.nominal_area.tolist()
        return data


def _plain(value: SupportsFloat) -> int | float | None:
    if isinstance(value, (np.integer, int)):
        return int(value)
    number = float(value)
    return number if math.isfinite(number) else None


def resolution_scan(
    surface: HeightMap, max_stride: int, *, neighbours: int = 4, min_summits: int = 10
) -> ResolutionScan:
    """Summit statistics for strides 1..``max_stride`` and the paper's fits (Fig 12a-c).

    Parameters
    ----------
    surface : HeightMap
        Heights in m (level first). A LineProfile is refused.
    max_stride : int
        Largest stride K >= 1 (resolution ``K dx``).
    neighbours : {4, 8}
        Summit rule.
    min_summits : int
        Strides with fewer summits are excluded from the fits (still reported).

    Returns
    -------
    ResolutionScan
        Per stride: resolution (m), N, eta (1/m^2, over the valid area of the decimated
        grid: missing pixels and their neighbours are left out of N and of the area alike),
        R (m), sigma_s (m); the fits
        ``R = radius_slope * resolution + radius_intercept`` (Fig 12a),
        ``eta = density_prefactor * resolution**density_exponent`` (Fig 12b) and the mean
        and relative spread of sigma_s (Fig 12c).

    Raises
    ------
    InputError
        A LineProfile, or ``max_stride`` that leaves fewer than 3 points per axis.
    """
    surface = require_height_map(surface, "resolution_scan")
    if isinstance(max_stride, bool) or int(max_stride) != max_stride or max_stride < 1:
        raise InputError(f"max_stride: expected an integer >= 1, got {max_stride!r}")
    limit = min(surface.nx, surface.ny) // 3
    if max_stride > max(limit, 1):
        raise InputError(
            f"max_stride {max_stride} leaves fewer than 3 points per axis on a "
            f"{surface.nx} x {surface.ny} map; use at most {max(limit, 1)}"
        )
    strides = np.arange(1, int(max_stride) + 1)
    rows = [summit_statistics(surface, stride=int(k), neighbours=neighbours) for k in strides]
    resolution = strides * math.sqrt(surface.dx * surface.dy)
    n_summits = np.array([r.n_summits for r in rows], dtype=np.int64)
    density = np.array([r.asperity_density for r in rows])
    radius = np.array([r.summit_radius for r in rows])
    height_rms = np.array([r.summit_height_rms for r in rows])
    counted_area = np.array([r.nominal_area for r in rows])
    use = (n_summits >= min_summits) & np.isfinite(density)
    n_fit = int(use.sum())
    slope = intercept = exponent = prefactor = math.nan
    if n_fit >= 2:
        slope, intercept = np.polyfit(resolution[use], radius[use], 1)
        exponent, log_prefactor = np.polyfit(np.log(resolution[use]), np.log(density[use]), 1)
        prefactor = math.exp(log_prefactor)
    rms_mean = float(np.mean(height_rms[use])) if n_fit else math.nan
    spread = float(np.std(height_rms[use]) / rms_mean) if n_fit else math.nan
    return ResolutionScan(
        stride=strides,
        resolution=resolution,
        n_summits=n_summits,
        asperity_density=density,
        summit_radius=radius,
        summit_height_rms=height_rms,
        radius_slope=float(slope),
        radius_intercept=float(intercept),
        density_exponent=float(exponent),
        density_prefactor=float(prefactor),
        height_rms_mean=rms_mean,
        height_rms_relative_spread=spread,
        n_fitted=n_fit,
        neighbours=int(neighbours),
        nominal_area=counted_area,
    )


def write_scan_hdf5(scan: ResolutionScan, path: str | Path, *, source: dict | None = None) -> Path:
    """Write the scan to HDF5: arrays as datasets (``units`` attribute), fits as attributes.

    Parameters
    ----------
    scan : ResolutionScan
        The scan (SI units).
    path : str or Path
        Output file (overwritten).
    source : dict, optional
        Where the map came from (stored as JSON in the ``source`` attribute).

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    units = {spec.name: spec.units for spec in field_specs(ResolutionScan)}
    with h5.new_file(path) as handle:  # atomic: the old file or the new one, never a part
        for name in ARRAY_FIELDS:
            h5.write_dataset(handle, name, getattr(scan, name), units[name], compression=None)
        if scan.nominal_area is not None:
            h5.write_dataset(
                handle, "nominal_area", scan.nominal_area, units["nominal_area"], compression=None
            )
        fits = {name: np.nan if value is None else value for name, value in scan.fits().items()}
        h5.write_attributes(handle, fits)
        h5.write_attributes(
            handle,
            {
                "neighbours": scan.neighbours,
                "format": "asperity-resolution-scan",
                "source": json.dumps(source or {}, default=str),
            },
        )
    return path


def draw_resolution_scan(fig: Figure, scan: ResolutionScan, *, title: str = "") -> Figure:
    """Draw the paper's Fig 12(a-c) on ``fig``: R, eta and sigma_s against the resolution.

    Three panels side by side, each with the data and the fit of the module docstring: (a) the
    mean summit radius R with its linear fit, (b) the asperity density eta with its power law
    (log-log), (c) the rms summit height sigma_s with its mean. Units carry the SI prefix that
    suits the data (um for the resolution of most maps, mm for R, mm^-2 for eta).

    Parameters
    ----------
    fig : Figure
        A blank :class:`matplotlib.figure.Figure` (e.g. ``asperity.plotting.new_figure(13, 4.8)``).
    scan : ResolutionScan
        The scan (SI units: m, 1/m^2).
    title : str
        Figure title (e.g. the file name); none when empty.

    Returns
    -------
    Figure
        ``fig``, drawn on.
    """
    u_res = display_unit(scan.resolution, "m")
    res = u_res(scan.resolution)
    x_label = u_res.label(r"resolution $\Delta$")
    ax_r, ax_eta, ax_sigma = fig.subplots(1, 3)
    u_r = display_unit(scan.summit_radius, "m")
    ax_r.plot(res, u_r(scan.summit_radius), "o", ms=3, label="data")
    if math.isfinite(scan.radius_slope):
        fit = scan.radius_slope * scan.resolution + scan.radius_intercept
        positive = fit > 0  # a radius is positive: the line is drawn where it is
        label = f"linear fit, dR/d$\\Delta$ = {scan.radius_slope:.3g} m/m"
        if positive.any():
            clipped = "" if positive.all() else " (drawn where R > 0)"
            ax_r.plot(res[positive], u_r(fit[positive]), "-", label=label + clipped)
    ax_r.set_ylabel(u_r.label("mean summit radius $R$"))
    positive = scan.asperity_density > 0
    u_eta = display_unit(scan.asperity_density[positive], "m", -2)
    ax_eta.loglog(res[positive], u_eta(scan.asperity_density[positive]), "o", ms=3, label="data")
    if math.isfinite(scan.density_exponent):
        fit = scan.density_prefactor * scan.resolution**scan.density_exponent
        label = f"power law, exponent {scan.density_exponent:.3g}"
        ax_eta.loglog(res, u_eta(fit), "-", label=label)
    ax_eta.set_ylabel(u_eta.label(r"asperity density $\eta$"))
    # labels at 1, 2, 5 x 10^k: readable whether the scan spans one decade or three
    plain_log_ticks(ax_eta.xaxis, (1.0, 2.0, 5.0))
    plain_log_ticks(ax_eta.yaxis, (1.0, 2.0, 5.0))  # 0.05, 0.1, 0.2: no 6 x 10^-2
    u_sigma = display_unit(scan.summit_height_rms, "m")
    ax_sigma.plot(res, u_sigma(scan.summit_height_rms), "o", ms=3, label="data")
    if math.isfinite(scan.height_rms_mean):
        spread = f"mean, spread {100 * scan.height_rms_relative_spread:.1f} %"
        ax_sigma.axhline(u_sigma(scan.height_rms_mean), color="C1", label=spread)
    ax_sigma.set_ylabel(u_sigma.label(r"rms summit height $\sigma_s$"))
    for ax, tag in zip((ax_r, ax_eta, ax_sigma), "abc", strict=True):
        ax.set_xlabel(x_label)
        ax.set_title(f"({tag})")
        legend_below(ax, fontsize=9)  # under the axis: it hides no point and no tick
    if title:
        fig.suptitle(title)
    return fig


def plot_resolution_scan(scan: ResolutionScan, path: str | Path, *, title: str = "") -> Path:
    """Save the paper's Fig 12(a-c) panels (:func:`draw_resolution_scan`), 150 dpi.

    Parameters
    ----------
    scan : ResolutionScan
        The scan (SI units; drawn with SI-prefixed units chosen from the data).
    path : str or Path
        Output file; the suffix picks the format (``.png``, ``.svg``, ``.pdf``).
    title : str
        Figure title (e.g. the file name).

    Returns
    -------
    Path
        The file written.
    """
    return save_figure(draw_resolution_scan(new_figure(13, 4.8), scan, title=title), path)
