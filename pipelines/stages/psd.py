"""The PSD stage: the map's radially averaged PSD, its roll-off and Hurst exponent, and Persson's
A_r.

The paper (Section 5) justifies its effective resolution from the PSD: roughness of wavelength
shorter than the roll-off carries the self-affine spectrum ``C(q) ~ q^(-2(1+H))``, and the
statistical model resolves wavelengths down to the Nyquist wavelength ``2 x`` of its effective
pixel size ``x``. This stage stores the PSD (:func:`asperity.topo.radial_psd`), the roll-off
wavelength (:func:`asperity.topo.rolloff_wavelength`), the Hurst exponent fitted to the power
law above the roll-off, and Persson's non-adhesive real contact area
(:func:`asperity.statmodel.persson_real_area`) at the job's loads: a third estimate of
A_r(F_z) beside the BEM and the statistical model (Fig 12d), a lower bound of the adhesive area
(see :mod:`asperity.statmodel.persson`).

Persson's theory integrates the PSD up to the map's Nyquist wavenumber ``pi / dx`` (the same
roughness the BEM sees) and, separately, up to the effective resolution's ``pi / x``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity import topo
from asperity.fields import array, document_fields, scalar, text
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.stages.statistical_model import STATISTICAL_MODEL, ResolutionChoice
from asperity.pipelines.stages.surface import SURFACE, LevelledSurface
from asperity.statmodel.persson import persson_real_area

#: Log-spaced bins of the power-law fit of the PSD (equal weight per decade).
FIT_BINS = 40


@document_fields
@dataclass
class PsdResult:
    """Stage-7 result: PSD, roll-off, Hurst exponent and Persson's A_r(F_z) (SI).

    Attributes
    ----------
    wavenumber : ndarray
        |q| of each ring of the radial PSD, rad/m.
    psd : ndarray
        Radially averaged PSD C(q), m^4 (normalisation of :func:`asperity.topo.psd_2d`).
    rolloff_wavelength : float
        2 pi / q_r of the plateau + power-law fit, m.
    hurst_exponent : float
        The Hurst exponent H of ``C ~ q^(-2(1+H))`` fitted between q_r and the Nyquist
        wavenumber where it is one, inside (0, 1) (a self-affine surface); NaN otherwise
        (:func:`asperity.topo.hurst_from_psd_exponent`). The slope itself is kept as
        ``psd_fit_exponent``: ``-psd_fit_exponent / 2 - 1`` is 1.35 on the default job's
        surface, which is smooth over the fitted band, not self-affine.
    psd_fit_prefactor, psd_fit_exponent : float
        The power law ``C = prefactor * q**exponent`` (SI: m^4 (rad/m)^-exponent; 1).
    nyquist_wavenumber : float
        pi / max(dx, dy) of the map, rad/m.
    effective_resolution : float
        Pixel size x chosen by the statistical-model stage, m.
    effective_nyquist_wavelength : float
        2 x: the shortest wavelength the statistical model resolves, m.
    normal_load : ndarray
        F_z, N.
    persson_real_area : ndarray
        Persson's A_r (m^2) with the PSD integrated to the map's Nyquist wavenumber.
    persson_real_area_effective : ndarray
        The same, integrated to the effective resolution's pi / x.
    persson_rms_slope : float
        h'_rms over the map's range, m/m.
    persson_status : int
        :class:`asperity.statmodel.PerssonResult` status (0 computed, 3 coarse estimate).
    persson_message : str
        Its message, and that the theory is non-adhesive.
    note : str
        How the map was treated (missing pixels filled with the mean for the FFT).
    """

    wavenumber: np.ndarray = array("rad/m", ("wavenumber",), "|q| of the PSD ring")
    psd: np.ndarray = array("m^4", ("wavenumber",), "radially averaged PSD C(q)")
    rolloff_wavelength: float = scalar("m", "roll-off wavelength 2 pi / q_r")
    hurst_exponent: float = scalar(
        "1", "Hurst exponent H of C ~ q^(-2(1+H)) above q_r; NaN outside (0, 1)"
    )
    psd_fit_prefactor: float = scalar("m^4", "prefactor of the power law (q in rad/m)")
    psd_fit_exponent: float = scalar("1", "exponent of C ~ q^exponent above q_r")
    nyquist_wavenumber: float = scalar("rad/m", "pi / pixel size of the map")
    effective_resolution: float = scalar(
        "m", "effective resolution x (the statistical-model stage)"
    )
    effective_nyquist_wavelength: float = scalar("m", "2 x, shortest resolved wavelength")
    normal_load: np.ndarray = array("N", ("normal_load",), "normal load")
    persson_real_area: np.ndarray = array(
        "m^2", ("normal_load",), "Persson A_r (non-adhesive), map resolution"
    )
    persson_real_area_effective: np.ndarray = array(
        "m^2", ("normal_load",), "Persson A_r (non-adhesive), cut at the effective resolution"
    )
    persson_rms_slope: float = scalar("m/m", "rms slope h' of the map's PSD")
    persson_status: int = scalar("1", "0 computed, 3 coarse estimate (few PSD points)")
    persson_message: str = text("Persson's status message")
    note: str = text("how the map was prepared for the FFT")


def complete_map(surface: LevelledSurface) -> tuple[topo.HeightMap, str]:
    """The map with missing pixels set to the mean height (the FFT needs every pixel)."""
    heights = np.array(surface.heights, dtype=float)
    missing = np.isnan(heights)
    note = "complete map"
    if missing.any():
        heights[missing] = float(np.nanmean(heights))
        note = f"{int(missing.sum())} missing pixels set to the mean height for the FFT"
    return topo.HeightMap(heights, dx=surface.dx, dy=surface.dy, periodic=surface.periodic), note


def fit_power_law(q: np.ndarray, c: np.ndarray, q_low: float, q_high: float) -> tuple[float, float]:
    """``C = prefactor * q**exponent`` fitted in log-log between ``q_low`` and ``q_high``.

    The rings are averaged in :data:`FIT_BINS` log-spaced bins first, so every decade weighs
    the same. Returns (prefactor, exponent); NaN when fewer than 3 bins hold data.
    """
    keep = (q >= q_low) & (q <= q_high) & (c > 0)
    if np.count_nonzero(keep) < 3:
        return math.nan, math.nan
    lq, lc = np.log(q[keep]), np.log(c[keep])
    edges = np.linspace(lq[0], lq[-1] + 1e-12, FIT_BINS + 1)
    which = np.digitize(lq, edges) - 1
    filled = [b for b in range(FIT_BINS) if np.any(which == b)]
    if len(filled) < 3:
        return math.nan, math.nan
    x = np.array([lq[which == b].mean() for b in filled])
    y = np.array([lc[which == b].mean() for b in filled])
    exponent, log_prefactor = np.polyfit(x, y, 1)
    return float(math.exp(log_prefactor)), float(exponent)


def psd_and_persson(
    surface: LevelledSurface,
    resolution: ResolutionChoice,
    e_star: float,
    nominal_area: float,
    normal_loads: np.ndarray,
) -> PsdResult:
    """The PSD stage: PSD, roll-off, Hurst exponent and Persson's A_r at the loads.

    Parameters
    ----------
    surface : LevelledSurface
        The read-and-level stage (heights in m).
    resolution : ResolutionChoice
        The statistical-model stage (its effective resolution, m).
    e_star : float
        E*, Pa.
    nominal_area : float
        A_n, m^2.
    normal_loads : ndarray
        F_z, N (>= 0; Persson's theory has no tensile branch).
    """
    height_map, note = complete_map(surface)
    radial = topo.radial_psd(height_map)
    nyquist = math.pi / max(surface.dx, surface.dy)
    rolloff = topo.rolloff_wavelength(height_map)
    prefactor, exponent = fit_power_law(radial.q, radial.psd, 2 * math.pi / rolloff, nyquist)
    loads = np.clip(np.asarray(normal_loads, dtype=float), 0.0, None)
    full = persson_real_area(height_map, e_star, loads, nominal_area)
    cut = min(math.pi / resolution.effective_resolution, nyquist)
    effective = persson_real_area(height_map, e_star, loads, nominal_area, q_cutoff=cut)
    return PsdResult(
        wavenumber=np.asarray(radial.q, dtype=float),
        psd=np.asarray(radial.psd, dtype=float),
        rolloff_wavelength=float(rolloff),
        hurst_exponent=float(topo.hurst_from_psd_exponent(exponent, warn=False).hurst_exponent),
        psd_fit_prefactor=prefactor,
        psd_fit_exponent=exponent,
        nyquist_wavenumber=nyquist,
        effective_resolution=float(resolution.effective_resolution),
        effective_nyquist_wavelength=2 * float(resolution.effective_resolution),
        normal_load=np.asarray(normal_loads, dtype=float),
        persson_real_area=np.asarray(full.real_area, dtype=float),
        persson_real_area_effective=np.asarray(effective.real_area, dtype=float),
        persson_rms_slope=float(full.rms_slope),
        persson_status=int(max(full.status, effective.status)),
        persson_message=f"non-adhesive (a lower bound of the adhesive area): {full.message}",
        note=note,
    )


def compute_psd(context: StageContext) -> PsdResult:
    """The job's PSD stage: :func:`psd_and_persson` on the levelled map."""
    config = context.config
    return psd_and_persson(
        context.result(SURFACE),
        context.result(STATISTICAL_MODEL),
        config.material.e_star,
        config.loading.nominal_area,
        np.asarray(config.loading.normal_loads, dtype=float),
    )


PSD = Stage(
    name="psd",
    title="PSD and Persson's theory",
    result=PsdResult,
    config=("material.E_star", "loading.nominal_area", "loading.normal_loads"),
    inputs=(SURFACE, STATISTICAL_MODEL),
    compute=compute_psd,
)
