"""Validity findings of a library result: a code, a level and a sentence, also a Python warning.

A result of :mod:`asperity.topo`, :mod:`asperity.bem` or :mod:`asperity.statmodel` that is
computed correctly but means nothing physically (A_r > A_n from the independent-asperity model,
a BEM contact that became full, a Tabor parameter below the JKR limit, a PSD slope that is no
Hurst exponent) says so itself, whoever called it: the result carries its :class:`Finding` codes
and messages, and each finding is also raised as a warning of the package's
:class:`ValidityWarning` subclass (``topo.TopoWarning``, ``bem.BemWarning``,
``statmodel.StatmodelWarning``), whose ``code`` attribute is the finding's code.

The codes are those of the job's verdict (:mod:`asperity.pipelines.stages.verdict`) where the
verdict has one (``area_fraction``, ``tabor``, ``adhesion_full_contact``, ...), so that the
verdict can take them over instead of re-deriving them; :data:`CODES` lists every code a library
result may carry and what it means.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

__all__ = ["CODES", "Finding", "ValidityWarning", "raise_findings"]

Level = Literal["warning", "invalid"]

#: Every code a library result may carry -> what it means. Codes shared with the job's verdict
#: keep the verdict's name.
CODES: dict[str, str] = {
    "area_fraction": "the model's A_r/A_n is beyond what independent asperities can mean "
    "(junctions merge; invalid above 0.15, and A_r > A_n is impossible)",
    "tabor": "Tabor parameter below 5: the JKR asperity laws do not apply",
    "bem_full_contact": "the BEM contact is full (contact fraction 1): the load flattens the "
    "whole map, A_r = A_n says nothing about the roughness",
    "bem_cohesive_zone": "the Maugis-Dugdale cohesive zone spans fewer than 3 elements",
    "hurst_out_of_range": "the PSD's power-law exponent gives no Hurst exponent in (0, 1): the "
    "spectrum is not that of a self-affine surface over the fitted band",
    "outlier_effect": "masking outliers changed the rms height (and so eta, R, sigma_s) by more "
    "than a few per cent: the outliers decide the statistics",
}


@dataclass(frozen=True)
class Finding:
    """One validity finding of a result.

    Attributes
    ----------
    code : str
        A key of :data:`CODES` (a verdict reason code where one exists).
    level : {"warning", "invalid"}
        ``"invalid"``: the number means nothing under the model; ``"warning"``: it is to be
        read with care.
    message : str
        The sentence: the number, the threshold and what to do.
    value, threshold : float
        The quantity checked and the threshold it crossed (NaN where not a single number).
    """

    code: str
    level: Level
    message: str
    value: float = math.nan
    threshold: float = math.nan

    @property
    def severity(self) -> Level:
        """``level`` under the name a verdict reason had (asperity 0.4's ``Reason``)."""
        return self.level

    @property
    def text(self) -> str:
        """``message`` under the name a verdict reason had (asperity 0.4's ``Reason``)."""
        return self.message


class ValidityWarning(UserWarning):
    """A result outside what its model means; ``code`` and ``level`` say which (see
    :data:`CODES`). Each package raises its own subclass."""

    #: The code and level of a warning raised with a message only (a subclass may set them).
    code: str = ""
    level: Level = "warning"

    def __init__(self, message: str, code: str | None = None, level: Level | None = None) -> None:
        super().__init__(message)
        if code is not None:
            self.code = code
        if level is not None:
            self.level = level


def raise_findings(
    findings: Iterable[Finding], category: type[ValidityWarning], stacklevel: int = 3
) -> None:
    """Raise each finding as a ``category`` warning (its code and level attached).

    ``stacklevel`` 3 points at the caller of the function that calls this one.
    """
    for finding in findings:
        warnings.warn(category(finding.message, finding.code, finding.level), stacklevel=stacklevel)
