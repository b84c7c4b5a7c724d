"""One stated preparation of a measured map: crop, form, outliers, missing pixels, and a record.

:func:`prepare_surface` applies, in this order (all lengths in m):

1. **crop** (:class:`CropWindow`, pixels or m, checked against the map);
2. ``missing='refuse'`` refuses a map with missing pixels here, before anything else;
3. **form removal**: least-squares polynomial of order ``form_order`` (0 mean, 1 plane,
   2 quadratic, up to 8; None: none) over the valid pixels (a periodic map: the mean only);
4. **outliers** (:class:`OutlierRule`, default ``|h - median| > 10 x 1.4826 MAD`` of the
   levelled heights): masked (they become missing, and the form is refitted without them)
   or clipped to the bounds;
5. **missing pixels** (measured holes and masked outliers): ``keep`` (summit statistics use
   the valid pixels only), ``refuse``, ``fill-lowest`` or ``interpolate`` (harmonic fill).

The :class:`PreparationRecord` says what was done and warns (strings with reasons) where a
step dominates the result: see :data:`WARN_LIMITS`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from asperity.errors import InputError
from asperity.topo.cleaning import (
    CropWindow,
    OutlierRule,
    OutlierSearch,
    check_missing_policy,
    crop_surface,
    fill_missing,
    find_outliers,
    refuse_missing,
)
from asperity.topo.form import check_order, subtract_polynomial
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.io.limits import MIN_HEIGHT_SPREAD_M
from asperity.topo.levelling import method_order, order_name
from asperity.topo.preparation_checks import WARN_LIMITS, grid_warnings, preparation_warnings

#: Largest fraction of the valid pixels an outlier rule may flag; above it the map is
#: refused (a rule that flags a quarter of a map is removing roughness, not artefacts).
MAX_OUTLIER_FRACTION = 0.25

__all__ = ["WARN_LIMITS", "PreparationOptions", "PreparationRecord", "PreparedSurface"]


@dataclass(frozen=True)
class PreparationOptions:
    """How to prepare a map (frozen; every field checked on construction).

    Parameters
    ----------
    crop : CropWindow or None
        Window kept (None: the whole map).
    missing : {"keep", "refuse", "fill-lowest", "interpolate"}
        Missing-pixel policy (see :func:`asperity.topo.cleaning.fill_missing`). ``keep`` suits
        summit statistics (counted over the valid area); a contact solve needs a complete map
        (``refuse``, ``fill-lowest`` or ``interpolate``).
    outliers : OutlierRule
        Outlier rule and action (default: 10 x MAD, masked).
    form_order : int or None
        Polynomial order of the form removed (0 mean, 1 plane, 2 quadratic, ... 8); None
        removes nothing. :meth:`from_detrend` maps the names ``none|mean|plane|quadratic``.
    """

    crop: CropWindow | None = None
    missing: str = "keep"
    outliers: OutlierRule = field(default_factory=OutlierRule)
    form_order: int | None = 1

    def __post_init__(self) -> None:
        check_missing_policy(self.missing)
        if self.form_order is not None:
            object.__setattr__(self, "form_order", check_order(self.form_order))
        if self.crop is not None and not isinstance(self.crop, CropWindow):
            raise InputError(f"crop: expected a CropWindow or None, got {self.crop!r}")
        if not isinstance(self.outliers, OutlierRule):
            raise InputError(f"outliers: expected an OutlierRule, got {self.outliers!r}")

    @staticmethod
    def order_of(detrend: str | int | None) -> int | None:
        """Polynomial order of a detrend name (``none|mean|plane|quadratic``) or an int."""
        return None if detrend is None else method_order(detrend)


@dataclass(frozen=True)
class PreparationRecord:
    """What :func:`prepare_surface` did (SI units; JSON-ready through :meth:`as_dict`).

    Attributes
    ----------
    source : str
        The file (or "the map").
    measured_shape : tuple of int
        ``(nx, ny)`` before cropping.
    crop : tuple of int or None
        ``(i0, i1, j0, j1)`` pixel window kept (half-open), None when not cropped.
    nx, ny : int
        Grid after cropping.
    dx, dy : float
        Pixel sizes (m) along axis 0 and axis 1.
    levelling : str
        Form removed: ``none``, ``mean``, ``plane``, ``quadratic``, ``polynomial order n``,
        or ``mean (periodic map)``.
    form_order : int or None
        Polynomial order removed (None: none).
    form_rms : float
        rms of the removed form about its mean, over the valid pixels (m).
    roughness_rms : float
        rms of the remaining heights about their mean, valid pixels, before filling (m).
    form_to_roughness : float
        ``form_rms / roughness_rms``.
    next_order, next_order_rms : int or None, float
        The next polynomial order (plane after none/mean, quadratic after plane) and the rms
        it would leave (m); None / NaN from quadratic on and for periodic maps.
    missing_policy : str
        ``keep``, ``refuse``, ``fill-lowest`` or ``interpolate``.
    n_missing, missing_fraction : int, float
        Missing pixels as measured (after cropping) and their fraction of the grid.
    n_filled, filled_fraction : int, float
        Pixels given a height by the missing-pixel policy (measured holes and masked
        outliers) and their fraction of the grid.
    n_missing_left : int
        Pixels still missing in the prepared map (``keep``).
    outlier_rule, outlier_action : str
        The rule in words and ``mask``/``clip``.
    n_outliers, outlier_fraction : int, float
        Pixels changed by the rule and their fraction of the valid pixels.
    rms_before_outliers : float
        The rms height (m) of the levelled map with every pixel kept (before the outlier rule).
    outlier_rms_ratio : float
        ``roughness_rms / rms_before_outliers``: the rule's effect on the rms height, and so
        on eta, R and sigma_s, which scale with the heights (1: no effect; a warning beyond
        :data:`asperity.topo.preparation_checks.WARN_LIMITS` ``"outlier_rms_change"``).
    outlier_low, outlier_high : float
        Bounds of the rule on the levelled heights (m; -inf/inf when no rule).
    warnings : tuple of str
        Each with its reason (see :data:`WARN_LIMITS`).
    """

    source: str
    measured_shape: tuple[int, int]
    crop: tuple[int, int, int, int] | None
    nx: int
    ny: int
    dx: float
    dy: float
    levelling: str
    form_order: int | None
    form_rms: float
    roughness_rms: float
    form_to_roughness: float
    next_order: int | None
    next_order_rms: float
    missing_policy: str
    n_missing: int
    missing_fraction: float
    n_filled: int
    filled_fraction: float
    n_missing_left: int
    outlier_rule: str
    outlier_action: str
    n_outliers: int
    outlier_fraction: float
    outlier_low: float
    outlier_high: float
    warnings: tuple[str, ...] = ()
    rms_before_outliers: float = math.nan
    outlier_rms_ratio: float = 1.0

    def as_dict(self) -> dict:
        """Plain Python values: tuples as lists, non-finite floats as None (JSON null)."""

        def plain(value: object) -> object:
            if isinstance(value, (tuple, list)):
                return [plain(v) for v in value]
            if isinstance(value, float) and not math.isfinite(value):
                return None
            return value

        return {key: plain(value) for key, value in asdict(self).items()}


@dataclass(frozen=True, eq=False)
class PreparedSurface:
    """A prepared map with the record of its preparation.

    Attributes
    ----------
    surface : HeightMap
        The prepared heights (m); ``provenance["preparation"]`` holds ``record.as_dict()``.
    record : PreparationRecord
        What was done.
    outlier_mask : ndarray of bool
        Pixels changed by the outlier rule (grid of ``surface``).
    filled_mask : ndarray of bool
        Pixels whose height was filled (not measured).
    """

    surface: HeightMap
    record: PreparationRecord
    outlier_mask: np.ndarray
    filled_mask: np.ndarray


def _rms_about_mean(heights: np.ndarray) -> float:
    valid = heights[~np.isnan(heights)]
    return float(np.std(valid)) if valid.size else math.nan


def _applied_order(surface: HeightMap, order: int | None) -> tuple[int | None, str]:
    if order is not None and surface.periodic and order > 0:
        return 0, "mean (periodic map)"
    return order, order_name(order)


def _check_enough_pixels(surface: HeightMap, order: int | None) -> None:
    n_valid = surface.nx * surface.ny - surface.n_missing
    source = surface.provenance.get("file", "the map")
    n_terms = 1 if order is None else (order + 1) * (order + 2) // 2
    if n_valid >= n_terms:
        return
    every = "every pixel is missing (NaN): " if n_valid == 0 else ""
    raise InputError(
        f"{source} has {n_valid} valid (non-NaN) pixels; {every}the {order_name(order)} "
        f"levelling needs at least {n_terms}"
    )


def _level(heights: np.ndarray, order: int | None) -> tuple[np.ndarray, float]:
    """Heights minus the form of ``order`` (None: unchanged) and the form's rms (m)."""
    if order is None:
        return np.array(heights, dtype=np.float64), 0.0
    removal = subtract_polynomial(heights, order)
    return removal.heights, removal.form_rms


def _next_order_rms(heights: np.ndarray, order: int | None, periodic: bool) -> tuple:
    """The next order (plane after none/mean, quadratic after plane) and the rms it leaves."""
    if periodic or (order is not None and order >= 2):
        return None, math.nan
    following = 1 if order is None or order == 0 else 2
    return following, _rms_about_mean(subtract_polynomial(heights, following).heights)


def prepare_surface(
    surface: HeightMap, options: PreparationOptions | None = None
) -> PreparedSurface:
    """Crop, remove the form, treat outliers and missing pixels; record what was done.

    Parameters
    ----------
    surface : HeightMap
        Heights in m (NaN = missing), e.g. from :func:`asperity.topo.read_surface`.
    options : PreparationOptions, optional
        Default: no crop, plane levelling, 10 x MAD outliers masked, holes kept.

    Returns
    -------
    PreparedSurface
        The prepared map, its :class:`PreparationRecord` (with warnings) and the masks of
        the outliers and of the filled pixels.

    Raises
    ------
    InputError
        A window outside the map; ``missing='refuse'`` with missing pixels (or with outliers
        masked); too few valid pixels for the form; every pixel missing.
    """
    options = options or PreparationOptions()
    surface = require_height_map(surface, "prepare_surface")
    measured_shape = (surface.nx, surface.ny)
    if options.crop is not None:
        surface = crop_surface(surface, options.crop)
    check_height_spread(surface)
    n_missing = int(np.isnan(surface.heights).sum())
    if options.missing == "refuse" and n_missing:
        refuse_missing(surface, n_missing)
    order, applied = _applied_order(surface, options.form_order)
    _check_enough_pixels(surface, order)
    raw, levelled, form_rms, found = _level_and_treat_outliers(surface, order, options, n_missing)
    holes = np.isnan(levelled)
    unfilled = surface.with_heights(levelled)
    prepared = fill_missing(unfilled, options.missing)
    record = _preparation_record(
        surface,
        options,
        measured_shape,
        (order, applied),
        (raw, levelled, form_rms),
        found,
        (n_missing, 0 if prepared is unfilled else int(holes.sum()), prepared.n_missing),
    )
    provenance = dict(surface.provenance, levelling=applied, preparation=record.as_dict())
    return PreparedSurface(
        surface=prepared.with_heights(prepared.heights, provenance=provenance),
        record=record,
        outlier_mask=found.mask,
        filled_mask=holes if prepared is not unfilled else np.zeros_like(holes),
    )


def _level_and_treat_outliers(
    surface: HeightMap, order: int | None, options: PreparationOptions, n_missing: int
) -> tuple[np.ndarray, np.ndarray, float, OutlierSearch]:
    """The form removed (order ``order``) and the outliers masked or clipped.

    Returns the heights the form was fitted to (m, NaN where missing or masked), the levelled
    heights (m), the form's rms (m) and the outliers found (:func:`find_outliers`).
    """
    levelled, form_rms = _level(surface.heights, order)
    found = find_outliers(levelled, options.outliers)
    found = replace(found, rms_before=_rms_about_mean(levelled))
    check_outlier_fraction(surface, found.count, n_missing, options.outliers.describe())
    raw = surface.heights
    if found.count and options.outliers.action == "mask":
        if options.missing == "refuse":
            refuse_missing(surface, found.count, why=" after masking the outliers")
        raw = np.where(found.mask, np.nan, surface.heights)
        levelled, form_rms = _level(raw, order)
    elif found.count:
        levelled = np.clip(levelled, found.low, found.high)
    return raw, levelled, form_rms, found


def _preparation_record(
    surface: HeightMap,
    options: PreparationOptions,
    measured_shape: tuple[int, int],
    form: tuple[int | None, str],
    heights: tuple[np.ndarray, np.ndarray, float],
    found: OutlierSearch,
    counts: tuple[int, int, int],
) -> PreparationRecord:
    """What :func:`prepare_surface` did, with its warnings.

    ``form`` is (order, levelling applied), ``heights`` (fitted raw heights, levelled heights,
    form rms in m), ``counts`` (missing pixels measured, filled, left).
    """
    order, applied = form
    raw, levelled, form_rms = heights
    n_missing, n_filled, n_left = counts
    roughness_rms = _rms_about_mean(levelled)
    next_order, next_rms = _next_order_rms(raw, order, surface.periodic)
    n_total = surface.nx * surface.ny
    n_valid = n_total - n_missing
    record = PreparationRecord(
        source=str(surface.provenance.get("file", "the map")),
        measured_shape=measured_shape,
        crop=tuple(surface.provenance["crop"]) if options.crop is not None else None,
        nx=surface.nx,
        ny=surface.ny,
        dx=surface.dx,
        dy=surface.dy,
        levelling=applied,
        form_order=order,
        form_rms=form_rms,
        roughness_rms=roughness_rms,
        form_to_roughness=form_rms / roughness_rms if roughness_rms > 0 else math.inf,
        next_order=next_order,
        next_order_rms=next_rms,
        missing_policy=options.missing,
        n_missing=n_missing,
        missing_fraction=n_missing / n_total,
        n_filled=n_filled,
        filled_fraction=n_filled / n_total,
        n_missing_left=n_left,
        outlier_rule=options.outliers.describe(),
        outlier_action=options.outliers.action,
        n_outliers=found.count,
        outlier_fraction=found.count / n_valid if n_valid else 0.0,
        outlier_low=found.low,
        outlier_high=found.high,
        rms_before_outliers=found.rms_before,
        outlier_rms_ratio=roughness_rms / found.rms_before if found.rms_before > 0 else 1.0,
    )
    reader_warnings = [str(w) for w in surface.provenance.get("warnings", [])]
    return _with_warnings(record, found.scale, reader_warnings + grid_warnings(levelled))


def check_outlier_fraction(surface: HeightMap, n_outliers: int, n_missing: int, rule: str) -> None:
    """Refuse an outlier rule that flags more than :data:`MAX_OUTLIER_FRACTION` of the pixels.

    Such a rule removes the surface, not artefacts: masking half a map can leave a flat
    remainder whose rms is 0 m, a confident wrong answer.

    Raises
    ------
    InputError
        Naming the map, the rule, the count and the limit.
    """
    n_valid = surface.nx * surface.ny - n_missing
    if n_valid and n_outliers > MAX_OUTLIER_FRACTION * n_valid:
        raise InputError(
            f"{surface.provenance.get('file', 'the map')}: outliers: the rule ({rule}) flags "
            f"{n_outliers} of {n_valid} valid pixels ({100 * n_outliers / n_valid:.3g} %), "
            f"more than {100 * MAX_OUTLIER_FRACTION:g} %: it would remove the surface, not "
            "artefacts; use a larger threshold or no outlier rule"
        )


def check_height_spread(surface: HeightMap) -> None:
    """Refuse heights (m) that vary, but by less than ``MIN_HEIGHT_SPREAD_M`` (1 fm).

    Their rms is below what any instrument resolves, and their squares underflow in floating
    point (heights of 1e-300 m would give an rms of 0 and summit radii of 1e293 m).

    Raises
    ------
    InputError
        Naming the map and the spread found.
    """
    valid = surface.heights[~np.isnan(surface.heights)]
    if valid.size < 2:
        return
    spread = float(valid.max() - valid.min())
    if 0.0 < spread < MIN_HEIGHT_SPREAD_M:
        raise InputError(
            f"{surface.provenance.get('file', 'the map')}: heights: vary by only "
            f"{spread:.3g} m (max - min); expected a spread of at least "
            f"{MIN_HEIGHT_SPREAD_M:g} m: no instrument resolves less, and the rms of such "
            "heights is not resolved in floating point (a wrong unit or scale?)"
        )


def _with_warnings(
    record: PreparationRecord, outlier_scale: float, extra: list[str]
) -> PreparationRecord:
    from dataclasses import replace

    warnings = preparation_warnings(record, outlier_scale) + extra
    return replace(record, warnings=tuple(warnings))
