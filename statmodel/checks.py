"""One checked quantity for the validity verdict: its value, thresholds, level and message.

The adhesion regime (:mod:`asperity.statmodel.regimes`) and the plausibility of the
predicted friction (:mod:`asperity.statmodel.plausibility`) each return a :class:`Check` (an
:class:`asperity.validity.Finding` with its thresholds: one validity type); the
job's verdict turns a level into a reason (``"warning"`` or ``"invalid"``) with the check's code,
number, threshold and message. Units are those of the quantity checked (stated per check).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

from asperity.quantities import Quantity
from asperity.validity import Finding, ValidityWarning

__all__ = [
    "MAX_AREA_FRACTION",
    "WARN_AREA_FRACTION",
    "Check",
    "Level",
    "StatmodelWarning",
    "area_fraction_finding",
    "grade",
    "positive_number",
    "positive_numbers",
    "upward_check",
]

#: A_r/A_n above which independent asperities mean nothing (junctions merge): "invalid". The
#: job's verdict uses the same value (``pipelines.stages.verdict.MAX_AREA_FRACTION``).
MAX_AREA_FRACTION = 0.15
#: A_r/A_n above which junction coalescence starts to matter: a warning.
WARN_AREA_FRACTION = 0.10


class StatmodelWarning(ValidityWarning):
    """A statistical-model result outside the model's validity; ``code`` names the reason
    (:data:`asperity.validity.CODES`: ``area_fraction``, ``tabor``, ...)."""


def area_fraction_finding(fraction: float, what: str = "the model's") -> Finding | None:
    """The ``area_fraction`` finding of an A_r/A_n (dimensionless), or None below 0.10.

    Invalid above :data:`MAX_AREA_FRACTION` (and always above 1: a real area larger than the
    nominal one is impossible), a warning above :data:`WARN_AREA_FRACTION` (paper, Section 5:
    an independent-asperity model, E:Ar_Greenwood, neglects junction coalescence).
    """
    if not math.isfinite(fraction) or fraction <= WARN_AREA_FRACTION:
        return None
    why = (
        "an independent-asperity model (E:Ar_Greenwood) neglects the coalescence of junctions, "
        "which dominates beyond 10-15 % contact (paper, Section 5)"
    )
    if fraction > 1.0:
        why = (
            "a real contact area larger than the nominal one is impossible: the summit "
            "statistics (eta, R, sigma_s) or the load are far outside the model's range; "
            "check the map's units, its levelling and the resolution of the statistics"
        )
    invalid = fraction > MAX_AREA_FRACTION
    threshold = MAX_AREA_FRACTION if invalid else WARN_AREA_FRACTION
    return Finding(
        "area_fraction",
        "invalid" if invalid else "warning",
        f"{what} A_r/A_n reaches {fraction:.3g} > {threshold:g}: {why}",
        fraction,
        threshold,
    )


Level = Literal["ok", "warning", "invalid"]


@dataclass(frozen=True)
class Check(Finding):
    """A quantity compared with its thresholds (see the module doc): a
    :class:`asperity.validity.Finding` (the one validity type of bem, statmodel and the
    verdict) that also carries how it was graded, and may be ``"ok"``.

    Attributes
    ----------
    code : str
        The reason code the verdict uses (e.g. ``"adhesion_full_contact"``).
    level : {"ok", "warning", "invalid"}
        The outcome.
    message : str
        What the value means and, when not ok, the parameters to check.
    value : float
        The quantity (dimensionless unless the check says otherwise).
    threshold : float
        The threshold that decided the level: the invalid one when crossed, else the warning
        one (the invalid one for a check without a warning level).
    bad_when : {"above", "below"}
        The direction in which a threshold is crossed: a value above it (most checks) or below
        it (the energy ratio of the full-contact criterion).
    warning_threshold, invalid_threshold : float
        Where the level becomes "warning" and "invalid" (``inf`` or ``-inf``: never).
    parameters : tuple of str
        The configuration keys or inputs to check when the level is not ok.
    reference : str
        Where the formula and the thresholds come from.
    """

    level: Level  # type: ignore[assignment]  # a Finding that may also be "ok"
    bad_when: Literal["above", "below"] = "above"
    warning_threshold: float = math.inf
    invalid_threshold: float = math.inf
    parameters: tuple[str, ...] = ()
    reference: str = ""

    @property
    def ok(self) -> bool:
        """True when the level is "ok"."""
        return self.level == "ok"


def grade(value: float, warning_threshold: float, invalid_threshold: float) -> tuple[Level, float]:
    """The level of ``value`` against thresholds crossed upwards, and the threshold that decided.

    A check whose bad side is below its thresholds grades ``-value`` against the negated
    thresholds.

    Parameters
    ----------
    value : float
        The quantity; NaN grades as "warning" (a quantity that could not be computed is
        never silently accepted).
    warning_threshold, invalid_threshold : float
        ``value > invalid_threshold`` is "invalid", ``value > warning_threshold`` "warning".

    Returns
    -------
    (level, threshold)
    """
    if math.isnan(value):
        return "warning", warning_threshold
    if value > invalid_threshold:
        return "invalid", invalid_threshold
    if value > warning_threshold:
        return "warning", warning_threshold
    return "ok", warning_threshold if math.isfinite(warning_threshold) else invalid_threshold


def positive_number(owner: str, name: str, value: object, unit: str) -> float:
    """``value`` as a finite float > 0, or :class:`asperity.errors.InputError` naming it.

    The check is the bounds registry's own (:class:`asperity.quantities.Quantity`), over the
    open interval (0, inf) in ``unit``.
    """
    positive = Quantity(
        f"{owner}.{name}",
        unit,
        0.0,
        math.inf,
        "a positive finite number",
        open_low=True,
        open_high=True,
    )
    return positive.check(value, f"{owner}.{name}")


def positive_numbers(owner: str, *named: tuple[str, object, str]) -> tuple[float, ...]:
    """:func:`positive_number` of each ``(name, value, unit)``, in order."""
    return tuple(positive_number(owner, name, value, unit) for name, value, unit in named)


def upward_check(
    code: str,
    value: float,
    warning_threshold: float,
    invalid_threshold: float,
    message: str | Callable[[Level], str],
    *,
    advice: str,
    parameters: tuple[str, ...],
    reference: str,
) -> Check:
    """A :class:`Check` whose value is bad above its thresholds, graded by :func:`grade`.

    Parameters
    ----------
    code : str
        The reason code.
    value : float
        The quantity checked.
    warning_threshold, invalid_threshold : float
        As in :func:`grade` (``inf``: no such level).
    message : str or callable
        What the value means, or a function of the level that says it.
    advice : str
        Appended to the message when the level is not "ok" (the parameters to check).
    parameters : tuple of str
        The keys to check, kept only when the level is not "ok".
    reference : str
        The source of the formula and thresholds.

    Returns
    -------
    Check
    """
    level, threshold = grade(value, warning_threshold, invalid_threshold)
    text = message(level) if callable(message) else message
    bad = level != "ok"
    return Check(
        code=code,
        bad_when="above",
        value=value,
        threshold=threshold,
        warning_threshold=warning_threshold,
        invalid_threshold=invalid_threshold,
        level=level,
        message=text + (advice if bad else ""),
        parameters=parameters if bad else (),
        reference=reference,
    )
