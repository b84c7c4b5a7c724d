"""The separate steps of surface preparation: crop, outlier rule, missing-pixel policy.

Each step is callable on its own; :func:`asperity.topo.prepare_surface` chains them and
records what each changed. Heights and lengths in m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from asperity.errors import InputError
from asperity.topo.heightmap import HeightMap, require_height_map
from asperity.topo.inpainting import harmonic_fill

MISSING_POLICIES = ("keep", "refuse", "fill-lowest", "interpolate")
OUTLIER_METHODS = ("none", "mad", "percentile")
OUTLIER_ACTIONS = ("mask", "clip")
#: Default k of the k x MAD rule (see :class:`OutlierRule`).
DEFAULT_MAD_K = 10.0
#: Normal-consistency factor: 1.4826 x MAD estimates the standard deviation of a Gaussian.
MAD_TO_SIGMA = 1.4826


def _source(surface: HeightMap) -> str:
    return str(surface.provenance.get("file", "the map"))


# ---------------------------------------------------------------------------------------- crop


def _parse_range(text: str, unit: str, what: str) -> tuple[float | None, float | None]:
    parts = text.split(":")
    if len(parts) != 2:
        raise InputError(f"{what}: expected START:STOP, got {text!r}")
    values: list[float | None] = []
    for part in parts:
        if part.strip() == "":
            values.append(None)
            continue
        try:
            value = int(part) if unit == "px" else float(part)
        except ValueError:
            kind = "integer pixel indices" if unit == "px" else "lengths in m"
            raise InputError(f"{what}: expected {kind} START:STOP, got {text!r}") from None
        if not math.isfinite(value):
            raise InputError(f"{what}: expected finite bounds, got {text!r}")
        values.append(value)
    return values[0], values[1]


@dataclass(frozen=True)
class CropWindow:
    """A rectangular window of a map: half-open ranges along axis 0 (x) and axis 1 (y).

    Parameters
    ----------
    x, y : tuple (start, stop)
        Bounds along axis 0 and axis 1; ``None`` for the map's edge. In pixels (integer
        indices, ``start <= i < stop``) or in metres (the pixel ``i`` lies at ``i*dx`` from
        the first one; kept when ``start <= i*dx < stop``).
    unit : {"px", "m"}
        Unit of the bounds.
    """

    x: tuple[float | None, float | None] = (None, None)
    y: tuple[float | None, float | None] = (None, None)
    unit: str = "px"

    def __post_init__(self) -> None:
        if self.unit not in ("px", "m"):
            raise InputError(f"crop unit: expected 'px' or 'm', got {self.unit!r}")

    @classmethod
    def parse(cls, text: str, unit: str = "px") -> CropWindow:
        """``"X0:X1,Y0:Y1"`` (empty bound = edge, e.g. ``"100:,:400"``) in ``unit``."""
        what = "--crop" if unit == "px" else "--crop-m"
        parts = text.split(",")
        if len(parts) != 2:
            raise InputError(f"{what}: expected X0:X1,Y0:Y1, got {text!r}")
        return cls(_parse_range(parts[0], unit, what), _parse_range(parts[1], unit, what), unit)

    def pixels(self, surface: HeightMap) -> tuple[int, int, int, int]:
        """The window as pixel indices ``(i0, i1, j0, j1)`` of ``surface``, checked.

        Raises
        ------
        InputError
            A bound outside the map, an empty or reversed range, or fewer than 3 pixels
            along an axis (no summit could be found).
        """
        i0, i1 = self._axis(self.x, surface.nx, surface.dx, "x (axis 0)", surface)
        j0, j1 = self._axis(self.y, surface.ny, surface.dy, "y (axis 1)", surface)
        return i0, i1, j0, j1

    def _axis(
        self,
        bounds: tuple[float | None, float | None],
        n: int,
        step: float,
        name: str,
        surface: HeightMap,
    ) -> tuple[int, int]:
        start, stop = bounds
        if self.unit == "m":
            extent = f"0 to {n * step:.6g} m ({n} pixels of {step:.6g} m)"
            start_px = 0 if start is None else math.ceil(start / step - 1e-9)
            stop_px = n if stop is None else math.ceil(stop / step - 1e-9)
        else:
            extent = f"pixels 0 to {n}"
            start_px = 0 if start is None else int(start)
            stop_px = n if stop is None else int(stop)
        shown = f"{start}:{stop}" + (" m" if self.unit == "m" else "")
        if not 0 <= start_px < stop_px <= n:
            raise InputError(
                f"crop {name} {shown}: outside {_source(surface)}, which spans {extent} "
                "(expected 0 <= start < stop <= size)"
            )
        if stop_px - start_px < 3:
            raise InputError(
                f"crop {name} {shown}: keeps {stop_px - start_px} pixel(s); at least 3 are "
                "needed for a summit to have a neighbour on each side"
            )
        return start_px, stop_px


def crop_surface(surface: HeightMap, window: CropWindow) -> HeightMap:
    """The part of ``surface`` inside ``window`` (a copy, never periodic).

    Parameters
    ----------
    surface : HeightMap
        Heights in m.
    window : CropWindow
        In pixels or m (checked against the map).

    Returns
    -------
    HeightMap
        Same pixel sizes (m); ``provenance["crop"] = [i0, i1, j0, j1]`` (pixels of the input).
        A cropped periodic map is periodic only if the window is the whole map.
    """
    surface = require_height_map(surface, "crop")
    i0, i1, j0, j1 = window.pixels(surface)
    whole = (i0, i1, j0, j1) == (0, surface.nx, 0, surface.ny)
    provenance = dict(surface.provenance, crop=[i0, i1, j0, j1])
    return surface.with_heights(
        np.array(surface.heights[i0:i1, j0:j1]),
        periodic=surface.periodic and whole,
        provenance=provenance,
    )


# ------------------------------------------------------------------------------------ outliers


@dataclass(frozen=True)
class OutlierRule:
    """A robust rule for pixels that are measurement artefacts (spikes, drop-outs).

    Parameters
    ----------
    method : {"mad", "percentile", "none"}
        ``"mad"``: a pixel is an outlier when its levelled height lies more than
        ``threshold`` robust standard deviations from the median, the robust standard
        deviation being ``1.4826 x MAD`` (median absolute deviation about the median; equal
        to the standard deviation for Gaussian heights and blind to the outliers
        themselves). ``"percentile"``: below the ``threshold``-th or above the
        ``(100 - threshold)``-th percentile (it always changes about ``2 threshold`` % of
        the pixels). ``"none"``: no rule.
    threshold : float
        k of the MAD rule (default 10) or the percentile p in (0, 50) (percent).
    action : {"mask", "clip"}
        ``"mask"``: the outliers become missing pixels, then the missing-pixel policy
        applies (kept as holes, filled with the lowest height, or interpolated);
        ``"clip"``: they are set to the nearest bound.

    Notes
    -----
    Why k = 10 by default: for Gaussian heights a pixel beyond 10 robust standard
    deviations occurs with probability 1.5e-23, so the rule never touches a sound Gaussian
    map of any size; real surfaces have heavier tails (valleys, pores), and on the eight
    real sample files (tests/data) it changes at most 0.04 % of the valid pixels while it
    catches the 638 nm spike of metropro-1.dat (50 robust standard deviations above the
    median after plane levelling). k = 5 would change 0.3 % of mi-1.mi, k = 8 1.1 % of the
    valid pixels of sur-3.sur: real roughness, not artefacts.
    """

    method: str = "mad"
    threshold: float = DEFAULT_MAD_K
    action: str = "mask"

    def __post_init__(self) -> None:
        if self.method not in OUTLIER_METHODS:
            raise InputError(f"outlier rule {self.method!r}: expected one of {OUTLIER_METHODS}")
        if self.action not in OUTLIER_ACTIONS:
            raise InputError(f"outlier action {self.action!r}: expected one of {OUTLIER_ACTIONS}")
        value = float(self.threshold)
        if self.method == "mad" and not (math.isfinite(value) and value > 0):
            raise InputError(f"outlier rule mad:{self.threshold}: expected k > 0")
        if self.method == "percentile" and not 0 < value < 50:
            raise InputError(
                f"outlier rule percentile:{self.threshold}: expected a percentile in (0, 50)"
            )

    @classmethod
    def parse(cls, text: str, action: str = "mask") -> OutlierRule:
        """``"none"``, ``"mad"``, ``"mad:K"``, ``"percentile:P"`` (P in percent)."""
        method, _, parameter = text.partition(":")
        if method not in OUTLIER_METHODS:
            raise InputError(
                f"--outliers {text!r}: expected none, mad[:K] or percentile:P (e.g. mad:10, "
                "percentile:0.01)"
            )
        if method == "percentile" and not parameter:
            raise InputError(f"--outliers {text!r}: percentile needs P, e.g. percentile:0.01")
        if method == "none":
            return cls("none", DEFAULT_MAD_K, action)
        try:
            threshold = float(parameter) if parameter else DEFAULT_MAD_K
        except ValueError:
            raise InputError(f"--outliers {text!r}: {parameter!r} is not a number") from None
        return cls(method, threshold, action)

    def describe(self) -> str:
        """One line: the rule and its parameter."""
        if self.method == "none":
            return "none"
        if self.method == "mad":
            return f"|h - median| > {self.threshold:g} x 1.4826 MAD"
        return f"outside percentiles {self.threshold:g}-{100 - self.threshold:g}"


@dataclass(frozen=True, eq=False)
class OutlierSearch:
    """Where the rule found outliers and the bounds it used (levelled heights, m); the rms
    height (m) of the heights searched, before any outlier is treated."""

    mask: np.ndarray
    low: float
    high: float
    scale: float
    rms_before: float = float("nan")

    @property
    def count(self) -> int:
        """Number of outlier pixels."""
        return int(self.mask.sum())


def find_outliers(heights: np.ndarray, rule: OutlierRule) -> OutlierSearch:
    """Apply ``rule`` to the valid pixels of ``heights`` (levelled heights, m).

    Parameters
    ----------
    heights : ndarray
        Levelled heights in m; NaN pixels are ignored.
    rule : OutlierRule
        The rule.

    Returns
    -------
    OutlierSearch
        ``mask`` (True at the outliers), the bounds ``low``, ``high`` (m) and ``scale`` (m:
        the robust standard deviation for ``mad``; NaN otherwise). A zero MAD (more than
        half the pixels share one height, e.g. a synthetic map) flags nothing.
    """
    valid = heights[~np.isnan(heights)]
    if rule.method == "none" or valid.size == 0:
        return OutlierSearch(np.zeros(heights.shape, dtype=bool), -np.inf, np.inf, math.nan)
    if rule.method == "mad":
        median = float(np.median(valid))
        scale = MAD_TO_SIGMA * float(np.median(np.abs(valid - median)))
        if scale == 0.0:
            return OutlierSearch(np.zeros(heights.shape, dtype=bool), -np.inf, np.inf, 0.0)
        low, high = median - rule.threshold * scale, median + rule.threshold * scale
    else:
        low, high = (float(v) for v in np.percentile(valid, [rule.threshold, 100 - rule.threshold]))
        scale = math.nan
    with np.errstate(invalid="ignore"):
        mask = (heights < low) | (heights > high)
    return OutlierSearch(mask, float(low), float(high), scale)


# ------------------------------------------------------------------------------ missing pixels


def check_missing_policy(policy: str) -> str:
    """Return ``policy`` if it is one of :data:`MISSING_POLICIES`, else raise InputError."""
    if policy not in MISSING_POLICIES:
        raise InputError(f"missing-pixel policy {policy!r}: expected one of {MISSING_POLICIES}")
    return policy


def refuse_missing(surface: HeightMap, n_missing: int, why: str = "") -> None:
    """Raise the ``missing='refuse'`` error for ``n_missing`` missing pixels of ``surface``."""
    total = surface.nx * surface.ny
    raise InputError(
        f"{_source(surface)}: {n_missing} of {total} pixels ({100 * n_missing / total:.3g} %) "
        f"are missing{why}, and the missing-pixel policy is 'refuse'; choose 'interpolate' "
        "(harmonic fill), 'fill-lowest', 'keep' (summit statistics over the valid pixels) or "
        "crop to a complete region"
    )


def fill_missing(surface: HeightMap, policy: str) -> HeightMap:
    """Apply a missing-pixel policy to ``surface`` (heights in m, NaN = missing).

    Parameters
    ----------
    surface : HeightMap
        Heights in m (levelled first, so that "lowest" and the fill refer to the roughness).
    policy : {"keep", "refuse", "fill-lowest", "interpolate"}
        ``keep``: leave the holes (summit statistics skip them); ``refuse``: raise if any
        pixel is missing; ``fill-lowest``: set them to the lowest valid height (a hole then
        never touches a counter-surface); ``interpolate``: harmonic (Laplace) fill,
        :func:`asperity.topo.inpainting.harmonic_fill` (exact on planes).

    Returns
    -------
    HeightMap
        The filled map (``surface`` itself when nothing changes).

    Raises
    ------
    InputError
        An unknown policy; ``refuse`` with missing pixels; every pixel missing.
    """
    check_missing_policy(policy)
    surface = require_height_map(surface, "fill_missing")
    n_missing = surface.n_missing
    if n_missing == 0 or policy == "keep":
        return surface
    if n_missing == surface.nx * surface.ny:
        raise InputError(f"{_source(surface)}: every pixel is missing; nothing to fill from")
    if policy == "refuse":
        refuse_missing(surface, n_missing)
    if policy == "fill-lowest":
        heights = np.where(np.isnan(surface.heights), np.nanmin(surface.heights), surface.heights)
    else:
        heights = harmonic_fill(surface.heights, surface.dx, surface.dy, periodic=surface.periodic)
    return surface.with_heights(heights)
