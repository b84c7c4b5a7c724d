"""The Maugis-Dugdale range of a BEM reference: the rule that chooses it, and its uncertainty.

A Dugdale cohesive law (:mod:`asperity.bem.normal.maugis`) pulls with a tension ``sigma_0 = w /
h_0``
(Pa) wherever the gap is below the range ``h_0`` (m). A physical range (~nm) gives a cohesive
zone far below a um pixel, so the range is coarse-grained to the grid: the rule
(:func:`search_range`) takes the shortest range found whose cohesive zone spans
:data:`~asperity.bem.normal.maugis.MIN_ZONE_ELEMENTS` = 3 elements of the grid at the check load.

The search starts from the JKR-side closed form :func:`bem.resolving_range` (an upper estimate
of the zone, which is narrower away from the JKR side) and lengthens the range by the power
law of the zones tried (:func:`next_range`; on the default map the zone grows about linearly
with h_0, not as h_0^2 as on a JKR sphere) until the solved zone spans 3 elements, at most
:data:`MAX_RANGE_SEARCH` solves, each warm-started from the non-adhesive solution. The last
solve is the check load's adhesive solve on that grid.

Sensitivity (:func:`measure_sensitivity`): the check load is solved again at half and double
the range (from the same non-adhesive start); ``half_spread`` of the three A_r/A_n
(:func:`asperity.bem.reference.discretisation.half_spread`) is the range part of the BEM's
uncertainty
(:attr:`RangeChoice.uncertainty`). At 2 h_0 the zone spans about 6 elements of the search's
grid; at h_0/2 only about 1.5, which under-resolves it (on the default job the three values came
out non-monotone, 0.005001, 0.004992, 0.004998). So h_0/2 is solved on the x2 Fourier-interpolated
grid of the same surface (zone about 3 elements again) and its ratio to h_0 there is applied;
where that grid is not solved (the range grid is not the grid used), it is solved on the
search's grid and the spread is flagged a lower bound (:attr:`RangeChoice.lower_bound`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from asperity.bem.normal.maugis import MIN_ZONE_ELEMENTS, resolving_range
from asperity.bem.reference.discretisation import half_spread
from asperity.bem.reference.load_sweeps import ContactSetup, Grid, solve_adhesive_loading
from asperity.bem.result import ContactResult

__all__ = [
    "ADHESION_LAWS",
    "MAX_RANGE_SEARCH",
    "RangeChoice",
    "RangeTry",
    "given_range",
    "measure_sensitivity",
    "next_range",
    "search_range",
]

#: Most Maugis solves of the range search.
MAX_RANGE_SEARCH = 4
#: Factor on the range step of the search beyond the power law fitted to the zones tried.
SEARCH_MARGIN = 1.05
#: Largest factor of one step of the search.
MAX_RANGE_STEP = 30.0
#: Adhesive laws of a BEM reference (``[bem] adhesion``).
ADHESION_LAWS = ("maugis", "pohrt-popov")


@dataclass(frozen=True)
class RangeTry:
    """One solve of the range search.

    Attributes
    ----------
    adhesion_range : float
        h_0, m.
    zone_elements : float
        Mean cohesive-zone width, elements (NaN without a contact line).
    contact_fraction : float
        A_r / A_map (1).
    """

    adhesion_range: float
    zone_elements: float
    contact_fraction: float


@dataclass
class RangeChoice:
    """The Maugis range chosen for the adhesive solves and how it was chosen.

    Attributes
    ----------
    adhesion_range : float
        h_0, m.
    rule : str
        One sentence for a report: the rule, the zone width reached, the solves.
    zone_elements : float
        Mean cohesive-zone width at the check load on the search's grid, elements (NaN if no
        contact line).
    tried : list of RangeTry
        Each search solve, in order.
    sensitivity : tuple of float
        A_r/A_map at h_0 / 2, h_0, 2 h_0 at the check load on the search's grid (h_0 / 2 from
        its ratio to h_0 on the x2 interpolated grid when resolved there; empty until
        :func:`measure_sensitivity`).
    half_range_zone_elements : float
        Cohesive-zone width of the h_0 / 2 solve, elements of the grid it was solved on.
    sensitivity_resolved : bool
        The h_0 / 2 zone spans at least 3 elements of its grid; False: the spread is a lower
        bound of the range's effect (:attr:`lower_bound`).
    sensitivity_note : str
        One phrase for a report: where h_0 / 2 was solved and its zone.
    result : ContactResult or None
        The adhesive solve at the chosen range (dropped once used: not stored).
    """

    adhesion_range: float
    rule: str
    zone_elements: float
    tried: list[RangeTry] = field(default_factory=list)
    sensitivity: tuple[float, ...] = ()
    half_range_zone_elements: float = math.nan
    sensitivity_resolved: bool = False
    sensitivity_note: str = ""
    result: ContactResult | None = field(default=None, repr=False)

    @property
    def lower_bound(self) -> bool:
        """The sensitivity is a lower bound: h_0 / 2 was solved with an under-resolved zone."""
        return bool(self.sensitivity) and not self.sensitivity_resolved

    @property
    def uncertainty(self) -> float:
        """Half the spread of A_r/A_map over h_0 / 2, h_0, 2 h_0 (absolute, 1)."""
        return float(half_spread(*self.sensitivity)) if self.sensitivity else math.nan

    @property
    def relative_uncertainty(self) -> float:
        """:attr:`uncertainty` over A_r/A_map at h_0 (1; NaN at zero area)."""
        middle = self.sensitivity[1]
        return self.uncertainty / middle if middle > 0 else math.nan

    @property
    def solves(self) -> int:
        """Maugis solves beyond the check load's own adhesive solve: the other search solves
        and the sensitivity's on the search's grid (two, or one when h_0 / 2 was solved on
        the interpolated grid, counted with the refinement)."""
        own = 0 if not self.sensitivity else 1 + int(not self.sensitivity_resolved)
        return len(self.tried) - 1 + own


def _zone(result: ContactResult) -> float:
    width = result.extra.get("cohesive_zone_elements")
    return math.nan if width is None else float(width)


def next_range(tried: list[RangeTry]) -> float:
    """The next range of the search (m) from the tries so far: the zone taken as a power of
    h_0, its exponent from the last two tries in log-log (1 from a single try: the zone of a
    steep rough contact grows about linearly with h_0; 2 on the JKR side), aimed at
    :data:`~asperity.bem.normal.maugis.MIN_ZONE_ELEMENTS` with a margin :data:`SEARCH_MARGIN`, at
    most :data:`MAX_RANGE_STEP` times longer."""
    h0, zone = tried[-1].adhesion_range, max(tried[-1].zone_elements, 1e-3)
    exponent = 1.0
    before = tried[-2] if len(tried) > 1 else None
    if before is not None and before.zone_elements > 0 and zone != before.zone_elements:
        exponent = math.log(zone / before.zone_elements) / math.log(h0 / before.adhesion_range)
        exponent = min(max(exponent, 0.5), 2.0)
    factor = (MIN_ZONE_ELEMENTS / zone) ** (1.0 / exponent) * SEARCH_MARGIN
    return h0 * min(factor, MAX_RANGE_STEP)


def _solve_at(
    grid: Grid, setup: ContactSetup, plain: ContactResult, force: float, h0: float
) -> ContactResult:
    return solve_adhesive_loading(grid, dataclasses.replace(setup, adhesion_range=h0), plain, force)


def search_range(
    grid: Grid, setup: ContactSetup, plain: ContactResult, force: float
) -> RangeChoice:
    """The shortest range whose cohesive zone spans 3 elements of ``grid`` (module notes).

    Parameters
    ----------
    grid : Grid
        Heights (m) and pixel sizes (m) of the grid searched on.
    setup : ContactSetup
        E* (Pa), w (J/m^2, > 0), solver options, boundary (its ``adhesion_range`` is ignored).
    plain : ContactResult
        The non-adhesive solve at ``force`` (N) on ``grid``: every start.
    force : float
        The check load on the grid, N.
    """
    w = setup.work_of_adhesion
    h0 = resolving_range(w, setup.e_star, min(grid.dx, grid.dy), MIN_ZONE_ELEMENTS)
    tried: list[RangeTry] = []
    for _ in range(MAX_RANGE_SEARCH):
        result = _solve_at(grid, setup, plain, force, h0)
        tried.append(RangeTry(h0, _zone(result), float(result.contact_fraction)))
        if not tried[-1].zone_elements < MIN_ZONE_ELEMENTS:  # resolved, or no contact line
            break
        h0 = next_range(tried)
    h0, zone = tried[-1].adhesion_range, tried[-1].zone_elements
    reached = "reached" if not zone < MIN_ZONE_ELEMENTS else "NOT reached"
    rule = (
        f"Maugis-Dugdale range h_0 = {h0:.3g} m (sigma_0 = w / h_0 = {w / h0:.3g} Pa): the "
        f"shortest range whose cohesive zone spans {MIN_ZONE_ELEMENTS:g} elements of the "
        f"{grid.dx * 1e6:.3g} um grid at the check load ({reached}: {zone:.2f} elements after "
        f"{len(tried)} solve{'s' if len(tried) > 1 else ''})"
    )
    return RangeChoice(h0, rule, zone, tried, result=result)


def given_range(
    grid: Grid, setup: ContactSetup, plain: ContactResult, force: float, h0: float
) -> RangeChoice:
    """A given range ``h0`` (m): one solve at ``force`` (N), its zone stated (arguments as
    :func:`search_range`)."""
    result = _solve_at(grid, setup, plain, force, h0)
    zone = _zone(result)
    rule = (
        f"Maugis-Dugdale range h_0 = {h0:.3g} m ([bem] adhesion_range; sigma_0 = "
        f"{setup.work_of_adhesion / h0:.3g} Pa): its cohesive zone spans {zone:.2f} elements "
        f"of the {grid.dx * 1e6:.3g} um grid at the check load"
    )
    tried = [RangeTry(h0, zone, float(result.contact_fraction))]
    return RangeChoice(h0, rule, zone, tried, result=result)


def measure_sensitivity(
    choice: RangeChoice,
    grid: Grid,
    setup: ContactSetup,
    plain: ContactResult,
    force: float,
    resolved_half: tuple[float, float] | None = None,
) -> RangeChoice:
    """Solve ``force`` (N) at half and double the chosen range and store the three A_r/A_map
    in ``choice.sensitivity`` (arguments as :func:`search_range`; ``choice.result`` must still
    hold the solve at h_0 on ``grid``).

    Double the range is solved on ``grid`` (its zone is about twice the 3 elements of h_0).
    Half the range: with ``resolved_half = (ratio, zone)``, the ratio A_r(h_0/2) / A_r(h_0)
    measured on a finer grid of the same surface where the h_0/2 zone spans ``zone`` elements
    (:func:`asperity.bem.reference.interpolated_refinement.refine_by_interpolation`), applied to the
    A_r/A_map at h_0 on ``grid``; otherwise solved on ``grid``, where its zone spans about 1.5
    elements: the sensitivity is then a lower bound (:attr:`RangeChoice.lower_bound`).
    """
    assert choice.result is not None, "measure_sensitivity needs the solve at h_0"
    middle = float(choice.result.contact_fraction)
    result = _solve_at(grid, setup, plain, force, 2.0 * choice.adhesion_range)
    double = float(result.contact_fraction)
    del result
    if resolved_half is not None and math.isfinite(resolved_half[0]):
        half, zone = middle * resolved_half[0], float(resolved_half[1])
        where = "the x2 Fourier-interpolated grid"
    else:
        result = _solve_at(grid, setup, plain, force, 0.5 * choice.adhesion_range)
        half, zone = float(result.contact_fraction), _zone(result)
        where = f"the {grid.dx * 1e6:.3g} um range grid"
        del result
    choice.sensitivity = (half, middle, double)
    choice.half_range_zone_elements = zone
    resolved = not zone < MIN_ZONE_ELEMENTS  # NaN (no contact line) counts as resolved
    choice.sensitivity_resolved = bool(resolved and resolved_half is not None)
    choice.sensitivity_note = f"h_0/2 solved on {where}, cohesive zone {zone:.2f} elements" + (
        "" if choice.sensitivity_resolved else " (under-resolved: the spread is a lower bound)"
    )
    return choice
