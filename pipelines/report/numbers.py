"""Numbers as the report writes them: the digits their uncertainty supports, SI prefixes, one
spelling of micro and no Python reprs (report.md, report.html and the terminal summary).

* :func:`format_number` writes a value (already in its display unit) with its uncertainty: the
  uncertainty to two significant digits, the value to the same decimal place (``0.00613 +-
  0.0021`` is written ``0.0061 ± 0.0021``, ``0.2998 +- 0.0240`` is ``0.300 ± 0.024``); a
  lower-bound uncertainty is rounded down and written ``± >u``, an unknown one ``± ?``. Without
  an uncertainty the value keeps ``digits`` (4) significant digits. It is the one form of a
  value with its uncertainty in the terminal summary, report.md, report.html and the text
  columns of a batch's summary.csv (:data:`PLUS_MINUS` between them).
* :func:`format_quantity` does the same for a value in SI units, with the SI prefix that puts
  the number between 1 and 1000 (``7.014e-08 m`` is ``70.14 nm``) for lengths, forces, pressures
  and areas (``power=2``: mm², µm²).
* :func:`plain_text` is applied to every text the report writes: the unit ``um`` becomes ``µm``
  (messages of other packages say ``um``), a Python dict written into a message (``setting
  {'nodes': 8, 'panels': 4}``) becomes ``nodes = 8, panels = 4`` and a paper label that stands
  as an equation's name gets its name and number beside it.
"""

from __future__ import annotations

import math
import re

import numpy as np
from numpy.typing import ArrayLike

from asperity.equations import name_equations
from asperity.plotting import DisplayUnit, display_unit

#: The sign between a value and its uncertainty, the same in every output.
PLUS_MINUS = "\u00b1"

#: Significant digits of an uncertainty.
UNCERTAINTY_DIGITS = 2

#: Significant digits of a value without an uncertainty.
VALUE_DIGITS = 4

#: A float carries about this many significant decimal digits: never more are written.
_FLOAT_DIGITS = 15

#: Outside 10**-3 <= |x| < 10**5 a number is written with a power of ten.
_PLAIN_RANGE = (-3, 5)

_MICRO = re.compile(r"(?<![\w\u00b5])um(?![a-zA-Z])")
_DICT = re.compile(r"\{('[^'{}]*'\s*:\s*[^{}]*)\}")
_PAIR = re.compile(r"'([^']*)'\s*:\s*([^,]+)")
#: A number in m, N or Pa in running text (not part of a longer word or unit such as m^2).
_SI_NUMBER = re.compile(r"(?<![\w.+-])(-?\d+(?:\.\d*)?(?:[eE][+-]?\d+)?) (m|N|Pa)(?![\w^\u00b2/])")


def _decimal_text(x: float, place: int) -> str:
    """``x`` rounded to 10**place, written without an exponent (no ``-0``)."""
    x = round(x / 10.0**place) * 10.0**place
    if x == 0:
        x = 0.0
    return f"{x:.{max(0, -place)}f}"


def _round_uncertainty(u: float, digits: int, down: bool) -> tuple[float, int]:
    """(u rounded to ``digits`` significant digits, the decimal place of its last digit);
    rounded down when ``down`` (a lower bound must not grow)."""
    place = math.floor(math.log10(u)) - (digits - 1)
    scaled = u / 10.0**place
    kept = math.floor(scaled + 1e-9) if down else round(scaled)
    rounded = kept * 10.0**place
    new_place = math.floor(math.log10(rounded)) - (digits - 1)
    if new_place != place:  # 0.0996 -> 0.10: one digit fewer after the point
        place = new_place
        rounded = round(rounded / 10.0**place) * 10.0**place
    return rounded, place


def _significant(x: float, digits: int) -> str:
    """``x`` to ``digits`` significant digits (the ``g`` format: no trailing zeros)."""
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def format_number(
    value: float,
    u: float | None = None,
    *,
    lower_bound: bool = False,
    digits: int = VALUE_DIGITS,
) -> str:
    """A value and its uncertainty with the digits the uncertainty supports.

    Parameters
    ----------
    value : float
        The value, in its display unit (the caller has applied any SI prefix).
    u : float or None
        Its standard uncertainty (>= 0) in the same unit; None: not estimated (the value alone
        to ``digits`` significant digits); NaN or inf: not known (``± ?``).
    lower_bound : bool
        ``u`` is only a lower bound: rounded down and written ``± >u``.
    digits : int
        Significant digits of a value written without an uncertainty.

    Returns
    -------
    str
        E.g. ``"0.0061 ± 0.0021"``, ``"12.35"``, ``"3.1 ± >1.0"``, ``"(4.20 ± 0.13)e-06"``
        (a power of ten outside 1e-3 <= |x| < 1e5), ``"0.52 ± ?"``.

    Raises
    ------
    ValueError
        A negative uncertainty, or ``digits`` < 1.
    """
    if digits < 1:
        raise ValueError(f"format_number: digits must be >= 1, got {digits}")
    v = float(value)
    if not math.isfinite(v):
        return f"{v}"
    if u is None:
        return _significant(v, digits)
    u = float(u)
    if math.isfinite(u) and u < 0:
        raise ValueError(f"format_number: uncertainty u must be >= 0, got {u!r}")
    if not math.isfinite(u):
        return f"{_significant(v, digits)} {PLUS_MINUS} ?"
    if u == 0:
        return f"{_significant(v, digits)} {PLUS_MINUS} 0"
    size = max(abs(v), u)
    exponent = math.floor(math.log10(size))
    if _PLAIN_RANGE[0] <= exponent < _PLAIN_RANGE[1]:
        return _pair(v, u, lower_bound, 0)
    return f"({_pair(v, u, lower_bound, exponent)})e{exponent:+03d}"


def _pair(v: float, u: float, lower_bound: bool, exponent: int) -> str:
    """``v ± u`` scaled by 10**-exponent, v to u's last digit (at most a float's digits)."""
    v, u = v / 10.0**exponent, u / 10.0**exponent
    u_rounded, place = _round_uncertainty(u, UNCERTAINTY_DIGITS, lower_bound)
    if v != 0:
        place = max(place, math.floor(math.log10(abs(v))) - (_FLOAT_DIGITS - 1))
    mark = ">" if lower_bound else ""
    return f"{_decimal_text(v, place)} {PLUS_MINUS} {mark}{_decimal_text(u_rounded, place)}"


def format_uncertainty(u: float, *, percent: bool = False, lower_bound: bool = False) -> str:
    """An uncertainty written alone, to its two significant digits (``± 17 %``, ``± 8.1e-06``).

    Parameters
    ----------
    u : float
        The uncertainty (>= 0), in its display unit, or relative (1) with ``percent``.
    percent : bool
        Write ``u`` (relative, 1) as a percentage.
    lower_bound : bool
        ``u`` is only a lower bound: rounded down and written ``± >u``.

    Returns
    -------
    str
        ``"± 17 %"``, ``"± 0.0012"``, ``"± ?"`` (not finite), ``"± 0"``.
    """
    u = float(u) * (100.0 if percent else 1.0)
    unit = " %" if percent else ""
    if not math.isfinite(u):
        return f"{PLUS_MINUS} ?"
    if u < 0:
        raise ValueError(f"format_uncertainty: uncertainty u must be >= 0, got {u!r}")
    if u == 0:
        return f"{PLUS_MINUS} 0{unit}"
    rounded, place = _round_uncertainty(u, UNCERTAINTY_DIGITS, lower_bound)
    mark = ">" if lower_bound else ""
    exponent = math.floor(math.log10(rounded))
    if _PLAIN_RANGE[0] <= exponent < _PLAIN_RANGE[1]:
        return f"{PLUS_MINUS} {mark}{_decimal_text(rounded, place)}{unit}"
    return f"{PLUS_MINUS} {mark}{rounded:.{UNCERTAINTY_DIGITS - 1}e}{unit}"


#: A table keeps the plain SI unit (N, m) while its largest value lies in this range: the
#: paper's 0.56 N stays 0.56 N, not 560 mN.
_PLAIN_UNIT_RANGE = (0.1, 1000.0)


def text_unit(values: ArrayLike, base: str, power: int = 1) -> DisplayUnit:
    """The unit ``values`` (SI, ``base**power``) are written in: the plain SI unit when the
    largest finite magnitude lies in [0.1, 1000) and the power is 1, else the SI prefix the
    figures use (:func:`asperity.plotting.display_unit`: 1 to 999 of it). Its plain-text
    symbol is ``.text`` (``"µm"``, ``"mm²"``)."""
    v = np.abs(np.asarray(values, dtype=float)).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    if power == 1 and v.size and _PLAIN_UNIT_RANGE[0] <= v.max() < _PLAIN_UNIT_RANGE[1]:
        return DisplayUnit(1.0, base)
    return display_unit(values, base, power)


def format_quantity(
    value: float,
    base: str,
    u: float | None = None,
    *,
    power: int = 1,
    lower_bound: bool = False,
    digits: int = VALUE_DIGITS,
) -> str:
    """A value in SI units with its SI-prefixed unit and its uncertainty's digits.

    Parameters
    ----------
    value : float
        In ``base**power`` (SI: m, N, Pa, m^2 with ``power=2``, 1/m^2 with ``power=-2``).
    base : str
        The SI base unit's symbol, e.g. ``"m"``, ``"N"``, ``"Pa"``.
    u : float or None
        Its uncertainty in the same unit (see :func:`format_number`).
    power : int
        The power of ``base``; the prefix applies to the base (mm², mm⁻²).
    lower_bound, digits
        As for :func:`format_number`.

    Returns
    -------
    str
        E.g. ``"70.14 nm"``, ``"1.18 ± 0.05 mm"``, ``"2.25 mm⁻²"``.
    """
    known = [abs(float(value))] + ([] if u is None or not math.isfinite(u) else [float(u)])
    unit = text_unit(known, base, power)
    number = format_number(
        unit(value),
        None if u is None else float(unit(u)),
        lower_bound=lower_bound,
        digits=digits,
    )
    return f"{number} {unit.text}".rstrip()


def _prefixed(match: re.Match[str]) -> str:
    """An SI number in running text (``5.08e-05 m``) with its prefix (``50.8 µm``), the
    significant digits it was written with kept; left as it is where the plain unit reads well
    (0.1 to 1000 of it)."""
    number, unit = match.group(1), match.group(2)
    value = float(number)
    if value == 0 or _PLAIN_UNIT_RANGE[0] <= abs(value) < _PLAIN_UNIT_RANGE[1]:
        return match.group(0)
    mantissa = number.lower().split("e")[0].lstrip("-").replace(".", "").lstrip("0")
    shown = text_unit([value], unit)
    v = float(shown(value))
    whole = math.floor(math.log10(abs(v))) + 1  # digits before the point: never an exponent
    return f"{_significant(v, max(1, len(mantissa), whole))} {shown.text}"


def plain_text(text: str) -> str:
    """A report text with readable SI prefixes, ``um`` spelt ``µm``, every Python dict repr
    written as words and each bare paper label named.

    A label is named by :func:`asperity.equations.name_equations` (``E:Ar_Greenwood`` ->
    ``preload real contact area (Eq. 16, E:Ar_Greenwood)``).

    ``"setting {'nodes': 8, 'panels': 4}"`` -> ``"setting nodes = 8, panels = 4"``;
    ``"a 20 um grid"`` -> ``"a 20 µm grid"`` (words such as "sum" or "spectrum" untouched);
    ``"h_0 = 5.08e-05 m"`` -> ``"h_0 = 50.8 µm"`` and ``"R = 0.0001547 m"`` -> ``"R = 154.7 µm"``
    (a number in m, N or Pa outside 0.1 to 1000 of the unit; the digits written are kept).
    """

    def words(match: re.Match[str]) -> str:
        return ", ".join(f"{k} = {v.strip()}" for k, v in _PAIR.findall(match.group(1)))

    text = name_equations(_DICT.sub(words, str(text)))
    return _MICRO.sub("\u00b5m", _SI_NUMBER.sub(_prefixed, text))
