"""Containers for measured and synthetic topography: :class:`HeightMap` and :class:`LineProfile`.

Conventions (the project's shared contract): heights in metres, NaN marks a missing
pixel; axis 0 of ``heights`` is x (pixel size ``dx``, m), axis 1 is y (pixel size ``dy``, m).
The nominal area is the area of the grid cells, ``A_n = nx*dx * ny*dy`` (m^2), the
``A_n`` of the paper's Appendix A (``eta = N/A_n``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, text


def _as_float_array(values: object, ndim: int, what: str) -> np.ndarray:
    """Return ``values`` as a read-only float64 view with ``ndim`` dimensions, or raise."""
    array = np.asarray(values)
    if array.dtype.kind not in "fiu":
        raise TypeError(f"{what}: expected real numbers (float64), got dtype {array.dtype}")
    if array.ndim != ndim:
        raise InputError(f"{what}: expected a {ndim}D array, got shape {array.shape}")
    if array.dtype != np.float64:
        array = array.astype(np.float64)
    if min(array.shape) < 1:
        raise InputError(f"{what}: expected at least one point along every axis, got {array.shape}")
    view = array.view()
    view.flags.writeable = False
    return view


def _check_spacing(value: object, name: str) -> float:
    """Return ``value`` as a finite positive float (a pixel size in m), or raise."""
    try:
        spacing = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise TypeError(f"{name}: expected a pixel size in metres (float), got {value!r}") from None
    if not math.isfinite(spacing) or spacing <= 0.0:
        raise InputError(f"{name}: expected a finite pixel size > 0 m, got {spacing!r}")
    return spacing


class MapGeometry:
    """Sizes of a map held as ``heights`` (axis 0 is x, axis 1 is y) and pixel sizes ``dx``,
    ``dy`` in m: shared by :class:`HeightMap` and the job's stored surface."""

    heights: np.ndarray
    dx: float
    dy: float

    @property
    def nx(self) -> int:
        """Number of pixels along x (axis 0)."""
        return int(self.heights.shape[0])

    @property
    def ny(self) -> int:
        """Number of pixels along y (axis 1)."""
        return int(self.heights.shape[1])

    @property
    def lx(self) -> float:
        """Physical size along x, ``nx*dx`` (m)."""
        return self.nx * self.dx

    @property
    def ly(self) -> float:
        """Physical size along y, ``ny*dy`` (m)."""
        return self.ny * self.dy

    @property
    def nominal_area(self) -> float:
        """Nominal area ``A_n = lx*ly`` (m^2)."""
        return self.lx * self.ly


@document_fields
@dataclass(frozen=True, eq=False)
class HeightMap(MapGeometry):
    """A height map on a regular grid.

    Parameters
    ----------
    heights : array_like, shape (nx, ny)
        Heights in m (converted to a read-only float64 array); NaN marks a missing pixel.
        Axis 0 is x, axis 1 is y. A float64 array is not copied: the map holds a read-only
        view of it (copy it with ``np.array`` first if you will change the original).
    dx, dy : float
        Pixel sizes in m along axis 0 and axis 1 (finite, > 0; they may differ).
    periodic : bool
        Whether the map repeats itself (synthetic maps); measured maps are not periodic.
    provenance : dict
        Where the map came from: file, format, instrument, channel, units seen, ...
    """

    heights: np.ndarray = array(
        "m", ("x", "y"), "surface heights (larger = closer to the flat, NaN = missing)"
    )
    dx: float = scalar("m", "pixel size along x (axis 0)")
    dy: float = scalar("m", "pixel size along y (axis 1)")
    periodic: bool = scalar("1", "the map is one period of the surface", default=False)
    provenance: dict = text("where the map came from", default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "heights", _as_float_array(self.heights, 2, "HeightMap.heights"))
        object.__setattr__(self, "dx", _check_spacing(self.dx, "HeightMap.dx"))
        object.__setattr__(self, "dy", _check_spacing(self.dy, "HeightMap.dy"))
        object.__setattr__(self, "periodic", bool(self.periodic))
        if not isinstance(self.provenance, dict):
            raise TypeError(f"HeightMap.provenance: expected a dict, got {type(self.provenance)}")
        if np.isinf(self.heights).any():
            raise InputError("HeightMap.heights: infinite heights; mark missing pixels with NaN")

    @property
    def n_missing(self) -> int:
        """Number of missing (NaN) pixels."""
        return int(np.count_nonzero(np.isnan(self.heights)))

    def with_heights(self, heights: np.ndarray, **changes: object) -> HeightMap:
        """Return a copy with new ``heights`` (m) and optionally other fields changed."""
        values = {
            "dx": self.dx,
            "dy": self.dy,
            "periodic": self.periodic,
            "provenance": dict(self.provenance),
        }
        values.update(changes)
        return HeightMap(heights, **values)  # type: ignore[arg-type]


@dataclass(frozen=True, eq=False)
class LineProfile:
    """A 1D height profile (e.g. a stylus line scan).

    Parameters
    ----------
    heights : array_like, shape (n,)
        Heights in m (read-only float64); NaN marks a missing point.
    dx : float
        Sampling distance in m (finite, > 0).
    provenance : dict
        Where the profile came from.
    """

    heights: np.ndarray
    dx: float
    provenance: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "heights", _as_float_array(self.heights, 1, "LineProfile.heights"))
        object.__setattr__(self, "dx", _check_spacing(self.dx, "LineProfile.dx"))
        if not isinstance(self.provenance, dict):
            raise TypeError(f"LineProfile.provenance: expected a dict, got {type(self.provenance)}")

    @property
    def nx(self) -> int:
        """Number of points."""
        return int(self.heights.shape[0])

    @property
    def lx(self) -> float:
        """Profile length ``nx*dx`` (m)."""
        return self.nx * self.dx

    @property
    def n_missing(self) -> int:
        """Number of missing (NaN) points."""
        return int(np.count_nonzero(np.isnan(self.heights)))


def require_height_map(surface: object, what: str) -> HeightMap:
    """Return ``surface`` if it is a :class:`HeightMap`; refuse a line profile clearly.

    Parameters
    ----------
    surface : object
        What the caller passed.
    what : str
        The analysis, named in the message.

    Returns
    -------
    HeightMap
        ``surface`` itself.

    Raises
    ------
    InputError
        For a :class:`LineProfile` (a 1D profile cannot give areal summit statistics).
    TypeError
        For anything else.
    """
    if isinstance(surface, HeightMap):
        return surface
    if isinstance(surface, LineProfile):
        source = surface.provenance.get("file", "this profile")
        raise InputError(
            f"{what} needs a 2D height map, but {source} is a 1D line profile "
            f"({surface.nx} points); summit density, radius and areal statistics "
            "are not defined for a single line"
        )
    raise TypeError(f"{what}: expected a topo.HeightMap, got {type(surface).__name__}")
