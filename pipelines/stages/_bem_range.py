"""The adhesive BEM's law and the Maugis-Dugdale range: the rule that chooses it, and its part
of the BEM's uncertainty.

``[bem] adhesion = "maugis"`` (the job's default) solves the loading branch with a Dugdale
cohesive law (:mod:`asperity.bem.maugis`): a tension ``sigma_0 = w / h_0`` (Pa) wherever the gap
is below the range ``h_0`` (m). The statistical model's asperities are adhesive on loading
(reversible JKR, E:JKR_load), so this is the like-for-like reference. ``"pohrt-popov"`` keeps
the paper's Appendix B (eq:max_sigma), whose loading branch carries no adhesion: its adhesive
areas equal the non-adhesive ones.

The range rule (``[bem] adhesion_range = "auto"`` or absent): a physical range (~nm) gives a
cohesive zone far below a um pixel, so the range is coarse-grained to the grid. It is the
shortest range found whose cohesive zone spans :data:`~asperity.bem.maugis.MIN_ZONE_ELEMENTS`
= 3 elements of the finest grid of the grid check (the map's pixel) at the check load; on a map
larger than 2500^2 pixels, of the finest check grid up to that size
(:func:`asperity.pipelines.stages._bem_grid.range_grid_stride`; the paper case: 4 um, so its
range spans about 6 elements of the 2 um grid: longer than the shortest, to save four Maugis
solves at 5000^2). The
search starts from the JKR-side closed form :func:`asperity.bem.resolving_range` (an upper
estimate of the zone, which is narrower away from the JKR side) and lengthens the range by the
power law of the zones tried (:func:`next_range`; on the default map the zone grows about
linearly with h_0, not as h_0^2 as on a JKR sphere) until the solved zone spans 3 elements, at
most :data:`MAX_RANGE_SEARCH` solves, each warm-started from the non-adhesive solution. The
last solve is the check load's adhesive solve on that grid.

Sensitivity: the check load is solved again at half and double the range on the same grid (from
the same non-adhesive start); ``half_spread`` of the three A_r/A_n
(:func:`asperity.bem.discretisation.half_spread`) is the range part of the BEM's uncertainty,
stored as ``area_range_uncertainty`` (absolute, in A_r/A_n) and as a fraction of A_r.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from asperity import bem
from asperity.bem.discretisation import half_spread
from asperity.bem.maugis import MIN_ZONE_ELEMENTS
from asperity.pipelines.stages._bem_solves import solve_adhesive_loading

#: Most Maugis solves of the range search.
MAX_RANGE_SEARCH = 4
#: Factor on the range step of the search beyond the power law fitted to the zones tried.
SEARCH_MARGIN = 1.05
#: Largest factor of one step of the search.
MAX_RANGE_STEP = 30.0
#: Values of ``[bem] adhesion``.
ADHESION_LAWS = ("maugis", "pohrt-popov")


@dataclass
class RangeChoice:
    """The Maugis range used by the adhesive solves and how it was chosen.

    Attributes
    ----------
    adhesion_range : float
        h_0, m.
    rule : str
        One sentence for the report: the rule, the zone width reached, the solves.
    zone_elements : float
        Mean cohesive-zone width at the check load on the search's grid, elements (NaN if no
        contact line).
    tried : list of tuple
        (h_0 m, zone elements, A_r/A_map) of each search solve.
    sensitivity : tuple of float
        A_r/A_map at h_0 / 2, h_0, 2 h_0 on the search's grid at the check load.
    result : Any
        The adhesive solve at the chosen range (not stored).
    """

    adhesion_range: float
    rule: str
    zone_elements: float
    tried: list = field(default_factory=list)
    sensitivity: tuple = ()
    result: Any = field(default=None, repr=False)

    @property
    def uncertainty(self) -> float:
        """Half the spread of A_r/A_map over h_0 / 2, h_0, 2 h_0 (absolute, 1)."""
        return float(half_spread(*self.sensitivity)) if self.sensitivity else math.nan

    @property
    def law(self) -> dict:
        """:func:`bem.solve_contact`'s ``adhesion`` and ``adhesion_range`` keywords."""
        return {"adhesion": "maugis", "adhesion_range": self.adhesion_range}


def _zone(result: Any) -> float:
    width = result.extra.get("cohesive_zone_elements")
    return math.nan if width is None else float(width)


def next_range(tried: list) -> float:
    """The next range of the search (m) from the (h_0, zone) tried so far: the zone taken as
    a power of h_0, its exponent from the last two tries in log-log (1 from a single try: the
    zone of a steep rough contact grows about linearly with h_0; 2 on the JKR side), aimed at
    3 elements with a margin :data:`SEARCH_MARGIN`, at most :data:`MAX_RANGE_STEP` times
    longer."""
    h0, zone = tried[-1][0], max(tried[-1][1], 1e-3)
    exponent = 1.0
    if len(tried) > 1 and tried[-2][1] > 0 and zone != tried[-2][1]:
        exponent = math.log(zone / tried[-2][1]) / math.log(h0 / tried[-2][0])
        exponent = min(max(exponent, 0.5), 2.0)
    factor = (MIN_ZONE_ELEMENTS / zone) ** (1.0 / exponent) * SEARCH_MARGIN
    return h0 * min(factor, MAX_RANGE_STEP)


def search_range(
    grid: tuple, e_star: float, plain: Any, force: float, w: float, solver: dict
) -> RangeChoice:
    """The shortest range whose cohesive zone spans 3 elements (module notes).

    Parameters
    ----------
    grid : tuple
        (heights m, dx m, dy m) of the finest grid of the check.
    e_star, w : float
        E* (Pa) and the work of adhesion (J/m^2).
    plain : bem.ContactResult
        The non-adhesive solve at ``force`` (N) on that grid: every start.
    solver : dict
        :func:`bem.solve_contact` keywords (tol, max_iter, periodic).
    """
    heights, dx, dy = grid
    h0 = bem.resolving_range(w, e_star, min(dx, dy), MIN_ZONE_ELEMENTS)
    tried = []
    for _ in range(MAX_RANGE_SEARCH):
        law = {"adhesion": "maugis", "adhesion_range": h0}
        result = solve_adhesive_loading(heights, dx, dy, e_star, plain, force, w, solver, law)
        zone = _zone(result)
        tried.append((h0, zone, float(result.contact_fraction)))
        if not zone < MIN_ZONE_ELEMENTS:  # resolved, or no contact line (NaN)
            break
        h0 = next_range(tried)
    h0, zone, _ = tried[-1]
    reached = "reached" if not zone < MIN_ZONE_ELEMENTS else "NOT reached"
    rule = (
        f"Maugis-Dugdale range h_0 = {h0:.3g} m (sigma_0 = w / h_0 = {w / h0:.3g} Pa): the "
        f"shortest range whose cohesive zone spans {MIN_ZONE_ELEMENTS:g} elements of the "
        f"{dx * 1e6:.3g} um grid at the check load ({reached}: {zone:.2f} elements after "
        f"{len(tried)} solve{'s' if len(tried) > 1 else ''})"
    )
    return RangeChoice(h0, rule, zone, tried, result=result)


def given_range(
    grid: tuple, e_star: float, plain: Any, force: float, w: float, solver: dict, h0: float
) -> RangeChoice:
    """The configured range ``h0`` (m): one solve at the check load, its zone stated."""
    heights, dx, dy = grid
    law = {"adhesion": "maugis", "adhesion_range": h0}
    result = solve_adhesive_loading(heights, dx, dy, e_star, plain, force, w, solver, law)
    zone = _zone(result)
    rule = (
        f"Maugis-Dugdale range h_0 = {h0:.3g} m ([bem] adhesion_range; sigma_0 = "
        f"{w / h0:.3g} Pa): its cohesive zone spans {zone:.2f} elements of the "
        f"{dx * 1e6:.3g} um grid at the check load"
    )
    return RangeChoice(h0, rule, zone, [(h0, zone, float(result.contact_fraction))], result=result)


def measure_sensitivity(
    choice: RangeChoice,
    grid: tuple,
    e_star: float,
    plain: Any,
    force: float,
    w: float,
    solver: dict,
) -> RangeChoice:
    """Solve the check load at half and double the chosen range (same grid and start) and
    store the three A_r/A_map in ``choice.sensitivity``."""
    heights, dx, dy = grid
    fractions = []
    for factor in (0.5, 2.0):
        law = {"adhesion": "maugis", "adhesion_range": factor * choice.adhesion_range}
        result = solve_adhesive_loading(heights, dx, dy, e_star, plain, force, w, solver, law)
        fractions.append(float(result.contact_fraction))
        del result
    choice.sensitivity = (fractions[0], float(choice.result.contact_fraction), fractions[1])
    return choice
