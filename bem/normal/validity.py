"""Validity of a BEM contact solve: findings recorded on the result and raised as warnings.

A converged solve can still say little: a contact that became full (every element in contact)
has flattened the whole map, so A_r = A_n measures the load, not the roughness, and no
contact line is left (``extra["cohesive_zone_elements"]`` is then None); a Maugis-Dugdale
cohesive zone narrower than three elements is not resolved by the grid. :func:`contact_findings`
states both (:class:`asperity.validity.Finding`, codes of :data:`asperity.validity.CODES`);
:func:`bem.solve_contact` records them in ``result.extra["validity_codes"]`` and
``result.extra["validity_notes"]`` and raises the full-contact one as a :class:`BemWarning`
(the under-resolved zone is also in ``result.message`` and ``extra["warnings"]``, as before).
"""

from __future__ import annotations

from asperity.bem.normal.maugis import MIN_ZONE_ELEMENTS
from asperity.bem.result import ContactResult
from asperity.validity import Finding, ValidityWarning

__all__ = ["BemWarning", "contact_findings"]


class BemWarning(ValidityWarning):
    """A BEM result outside what it can mean; ``code`` names it (``bem_full_contact``, ...)."""


def contact_findings(result: ContactResult, e_star: float) -> list[Finding]:
    """The validity findings of a solve (empty when the contact is partial and resolved).

    Parameters
    ----------
    result : ContactResult
        A solve of :func:`bem.solve_contact` (contact fraction dimensionless, areas in m^2).
    e_star : float
        The reduced modulus E* of the solve (Pa), quoted beside the mean pressure.

    Returns
    -------
    list of Finding
        ``bem_full_contact`` (invalid) when every element is in contact;
        ``bem_cohesive_zone`` (warning) when a Maugis cohesive zone spans fewer than
        :data:`MIN_ZONE_ELEMENTS` elements.
    """
    findings = []
    fraction = float(result.contact_fraction)
    if fraction >= 1.0:
        findings.append(
            Finding(
                "bem_full_contact",
                "invalid",
                f"contact fraction {fraction:.3g}: full contact (mean pressure "
                f"{result.mean_pressure:.3g} Pa against E* = {e_star:.3g} Pa): the load "
                "flattens the whole map, so A_r = A_n says nothing about its roughness and a "
                "contact-area curve or a fit against it means nothing; use a lower load, a "
                "stiffer material or a rougher map",
                fraction,
                1.0,
            )
        )
    width = result.extra.get("cohesive_zone_elements")
    if result.extra.get("adhesion") == "maugis" and width is not None and width < MIN_ZONE_ELEMENTS:
        findings.append(
            Finding(
                "bem_cohesive_zone",
                "warning",
                f"the Maugis-Dugdale cohesive zone spans {width:.2g} elements (< "
                f"{MIN_ZONE_ELEMENTS:g}): refine the grid or lengthen adhesion_range",
                float(width),
                MIN_ZONE_ELEMENTS,
            )
        )
    return findings
