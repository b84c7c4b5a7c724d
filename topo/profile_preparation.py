"""Preparation of a line profile before its statistics: crop, form removal, outliers, missing.

The profile counterpart of :func:`asperity.topo.prepare_surface`, with the same options
(:class:`~asperity.topo.preparation.PreparationOptions`): the crop's x range (axis 0; a y
range is refused), the least-squares polynomial of order ``form_order`` in x removed over the
valid points (0 mean, 1 line, 2 parabola, ... 8), the outlier rule on the levelled heights
(:func:`~asperity.topo.find_outliers`), and the missing-point policy: ``keep`` (statistics
over the valid points), ``refuse``, ``fill-lowest`` or ``interpolate`` (linear between the
nearest valid points: the 1D harmonic fill). Heights and lengths in m.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from asperity.errors import InputError
from asperity.topo.cleaning import find_outliers
from asperity.topo.heightmap import LineProfile

if TYPE_CHECKING:
    from asperity.topo.cleaning import CropWindow
    from asperity.topo.preparation import PreparationOptions

#: Missing-point fraction above which the record warns (as for maps).
MISSING_WARN_FRACTION = 0.05


def _cropped(
    profile: LineProfile, crop: CropWindow | None
) -> tuple[LineProfile, tuple[int, int] | None]:
    """The profile restricted to the crop window's x range (pixels or m)."""
    if crop is None:
        return profile, None
    if crop.y != (None, None):
        raise InputError(f"--crop: a line profile has no y axis; got the y range {crop.y}")
    scale = 1.0 if crop.unit == "px" else 1.0 / profile.dx
    start = 0 if crop.x[0] is None else int(round(crop.x[0] * scale))
    stop = profile.nx if crop.x[1] is None else int(round(crop.x[1] * scale))
    if not 0 <= start < stop <= profile.nx or stop - start < 3:
        raise InputError(
            f"--crop: x range {crop.x} ({crop.unit}) keeps points {start}:{stop} of a profile "
            f"of {profile.nx} points; expected at least 3 points within it"
        )
    heights = np.asarray(profile.heights)[start:stop]
    return LineProfile(heights, profile.dx, dict(profile.provenance)), (start, stop)


def _form(heights: np.ndarray, order: int | None) -> np.ndarray:
    """The least-squares polynomial of ``order`` in x over the valid points (zeros: none)."""
    if order is None:
        return np.zeros_like(heights)
    x = np.linspace(-1.0, 1.0, heights.size)
    valid = ~np.isnan(heights)
    if np.count_nonzero(valid) <= order:
        raise InputError(
            f"form removal of order {order} needs more than {order} valid points; "
            f"the profile has {np.count_nonzero(valid)}"
        )
    fit = np.polynomial.Legendre.fit(x[valid], heights[valid], order, domain=[-1, 1])
    return fit(x)


def _filled(heights: np.ndarray, policy: str, source: str) -> tuple[np.ndarray, int]:
    """Apply the missing-point policy; return the heights and the number of points filled."""
    missing = np.isnan(heights)
    count = int(missing.sum())
    if count == 0 or policy == "keep":
        return heights, 0
    if policy == "refuse":
        raise InputError(
            f"{source}: {count} missing points and --missing refuse; choose keep, "
            "fill-lowest or interpolate"
        )
    filled = heights.copy()
    if policy == "fill-lowest":
        filled[missing] = np.nanmin(heights)
    else:
        index = np.arange(heights.size)
        filled[missing] = np.interp(index[missing], index[~missing], heights[~missing])
    return filled, count


def prepare_profile(profile: LineProfile, options: PreparationOptions) -> tuple[LineProfile, dict]:
    """Crop, level, treat outliers and missing points of a profile, as ``options`` say.

    Parameters
    ----------
    profile : LineProfile
        Heights in m.
    options : PreparationOptions
        ``crop`` (x range only), ``form_order``, ``outliers``, ``missing``.

    Returns
    -------
    LineProfile, dict
        The prepared profile (m) and its record: ``source``, ``crop`` (start, stop) or None,
        ``nx``, ``dx`` (m), ``levelling``, ``form_order``, ``form_rms`` (m),
        ``roughness_rms`` (m), ``missing_policy``, ``n_missing``, ``missing_fraction``,
        ``n_filled``, ``outlier_rule``, ``outlier_action``, ``n_outliers``,
        ``outlier_fraction``, ``warnings``.

    Raises
    ------
    InputError
        A crop with a y range or outside the profile; ``missing = "refuse"`` with missing
        points; no valid point.
    """
    source = profile.provenance.get("file", "the profile")
    profile, window = _cropped(profile, options.crop)
    heights = np.asarray(profile.heights, dtype=np.float64)
    if np.isnan(heights).all():
        raise InputError(f"{source}: every point of the profile is missing")
    n_missing = int(np.isnan(heights).sum())
    form = _form(heights, options.form_order)
    levelled = heights - form
    search = find_outliers(levelled, options.outliers)
    n_outliers = int(search.mask.sum())
    if options.outliers.action == "clip":
        levelled = np.clip(levelled, search.low, search.high)
    else:
        levelled = np.where(search.mask, np.nan, levelled)
    prepared, n_filled = _filled(levelled, options.missing, source)
    valid = ~np.isnan(heights)
    record = {
        "source": source,
        "crop": window,
        "nx": int(heights.size),
        "dx": profile.dx,
        "levelling": "none" if options.form_order is None else f"order {options.form_order}",
        "form_order": options.form_order,
        "form_rms": float(np.std(form[valid])),
        "roughness_rms": float(np.nanstd(levelled)),
        "missing_policy": options.missing,
        "n_missing": n_missing,
        "missing_fraction": n_missing / heights.size,
        "n_filled": n_filled,
        "outlier_rule": options.outliers.describe(),
        "outlier_action": options.outliers.action,
        "n_outliers": n_outliers,
        "outlier_fraction": n_outliers / max(int(valid.sum()), 1),
        "warnings": _warnings(n_missing, heights.size, n_outliers),
    }
    provenance = dict(profile.provenance, preparation=record)
    return LineProfile(prepared, profile.dx, provenance), record


def _warnings(n_missing: int, n_points: int, n_outliers: int) -> list[str]:
    warnings = []
    if n_missing > MISSING_WARN_FRACTION * n_points:
        warnings.append(
            f"{n_missing} of {n_points} points missing (> {100 * MISSING_WARN_FRACTION:g} %): "
            "the statistics are those of the valid points"
        )
    if n_outliers:
        warnings.append(f"{n_outliers} outlier points treated by the outlier rule")
    return warnings
