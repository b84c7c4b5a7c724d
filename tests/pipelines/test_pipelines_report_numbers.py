"""Numbers as the report writes them: the digits the uncertainty supports, SI prefixes, one
spelling of micro, no Python dict reprs (pipelines.report.numbers)."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from asperity.pipelines.report.numbers import (
    PLUS_MINUS,
    format_number,
    format_quantity,
    format_uncertainty,
    plain_text,
    text_unit,
)


@pytest.mark.parametrize(
    ("value", "u", "expected"),
    [
        (0.00613, 0.0021, "0.0061 ± 0.0021"),  # the example
        (12.3456, 0.0123, "12.346 ± 0.012"),
        (1234.5, 87, "1234 ± 87"),  # 1234.5 to the units place: half to even
        (0.0996, 0.0996, "0.10 ± 0.10"),  # u rounds up to the next decade: one digit fewer
        (-3.21e-6, 4.5e-8, "(-3.210 ± 0.045)e-06"),
        (5.0, 0.0, "5 ± 0"),
        (0.52, float("nan"), "0.52 ± ?"),
        (7.014e-5, None, "7.014e-05"),
        (0.2998, 0.0240, "0.300 ± 0.024"),  # issue 39's examples
        (4389.5, 760, "4390 ± 760"),
        (0.29975933910857, None, "0.2998"),  # no u: 4 significant digits
    ],
)
def test_format_number_examples(value, u, expected):
    assert format_number(value, u) == expected


def test_lower_bound_rounds_down_and_is_marked():
    # a lower bound of 1047 is "at least 1000", never "at least 1100"
    assert format_number(3.1, 1047, lower_bound=True) == "0 ± >1000"
    assert format_number(0.5, 0.0199, lower_bound=True) == "0.500 ± >0.019"
    assert format_number(0.5, 0.0199) == "0.500 ± 0.020"


def test_bad_uncertainty_is_refused():
    with pytest.raises(ValueError, match="uncertainty u must be >= 0"):
        format_number(1.0, -0.1)


def _parse(text: str) -> tuple[str, str, int]:
    """(value digits, u digits, power of ten) of ``"v ± u"`` or ``"(v ± u)e+NN"``."""
    match = re.fullmatch(r"\(?(-?[\d.]+) ± >?([\d.]+)\)?(?:e([+-]\d+))?", text)
    assert match, text
    return match.group(1), match.group(2), int(match.group(3) or 0)


def _decimals(text: str) -> int:
    return len(text.split(".")[1]) if "." in text else 0


@given(
    value=st.floats(-1e7, 1e7, allow_nan=False),
    u=st.floats(1e-9, 1e6, allow_nan=False),
    lower_bound=st.booleans(),
)
def test_value_has_the_digits_of_its_uncertainty(value, u, lower_bound):
    """Any value and u > 0 (within a float's 15 digits of each other): u is written to two
    significant digits (rounded down for a lower bound, else to the nearest), the value to
    u's last decimal place, within half a unit of that place of the true value."""
    assume(u >= abs(value) * 1e-12)
    v_text, u_text, power = _parse(format_number(value, u, lower_bound=lower_bound))
    scale = 10.0**power
    decimals = _decimals(u_text)
    assert _decimals(v_text) == decimals
    shown_u = float(u_text)
    place = 10.0**-decimals if decimals else 10.0 ** (math.floor(math.log10(shown_u)) - 1)
    assert 10 <= round(shown_u / place) < 100  # two significant digits
    place *= scale
    shown_u *= scale
    if lower_bound:
        assert shown_u <= u * (1 + 1e-9)
        assert u - shown_u < place * (1 + 1e-6)
    else:
        assert abs(shown_u - u) <= 0.5 * place * (1 + 1e-6)
    assert abs(float(v_text) * scale - value) <= 0.5 * place * (1 + 1e-6) + 1e-12 * abs(value)


@given(value=st.floats(1e-15, 1e12), base=st.sampled_from(["m", "N", "Pa"]))
def test_prefixed_quantities_read_between_1_and_1000(value, base):
    """A length, force or pressure gets the prefix that writes it between 0.1 and 1000 of
    the unit (the plain unit kept between 0.1 and 1000: 0.56 N stays 0.56 N), and the text
    is the same value."""
    text = format_quantity(value, base)
    number, unit = text.split(" ")
    shown = float(number)
    assert 0.1 <= shown < 1000.5
    factor = text_unit([value], base).factor
    assert math.isclose(shown / factor, value, rel_tol=5e-4)
    assert unit.endswith(base)


@pytest.mark.parametrize(
    ("value", "base", "power", "expected"),
    [
        (7.014e-8, "m", 1, "70.14 nm"),  # the 7.014e-05 mm
        (1.18e-3, "m", 1, "1.18 mm"),
        (2.25e6, "m", -2, "2.25 mm\u207b\u00b2"),
        (3.2e-6, "m", 2, "3.2 mm\u00b2"),
        (2.133e6, "Pa", 1, "2.133 MPa"),
        (0.56, "N", 1, "0.56 N"),
        (12e-6, "m", 1, "12 \u00b5m"),
    ],
)
def test_format_quantity_examples(value, base, power, expected):
    assert format_quantity(value, base, power=power) == expected


def test_format_quantity_with_uncertainty():
    assert format_quantity(1.5e-3, "N", 2e-4) == "1.50 ± 0.20 mN"


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("setting {'nodes': 8, 'panels': 4}: F_x", "setting nodes = 8, panels = 4: F_x"),
        ("a 20 um grid (m, mm, um, nm); sum of a spectrum", "a 20 µm grid (m, mm, µm, nm); sum"),
        ("h_0 = 5.08e-05 m (sigma_0 = 788 Pa); R = 0.0001547 m", "h_0 = 50.8 µm"),
        ("R = 0.0001547 m", "R = 154.7 µm"),
        ("dx = 1.277e-07 m, F = 0.56 N, 2.1e6 Pa", "dx = 127.7 nm, F = 0.56 N, 2.1 MPa"),
        ("A_n = 700e-6 m^2 at 2 m/s", "A_n = 700e-6 m^2 at 2 m/s"),
        (
            "an independent-asperity model (E:Ar_Greenwood) neglects",
            "an independent-asperity model (preload real contact area (Eq. 16, E:Ar_Greenwood))",
        ),
        ("tangential force (Eq. 18, E:NewFormulation_Fx)", "tangential force (Eq. 18, E:New"),
    ],
)
def test_plain_text(text, expected):
    assert plain_text(text).startswith(expected)


@pytest.mark.parametrize(
    ("u", "percent", "expected"),
    [
        (0.1667, True, "± 17 %"),
        (8.1234e-6, False, "± 8.1e-06"),
        (0.0012345, False, "± 0.0012"),
        (0.0996, False, "± 0.10"),
        (float("nan"), False, "± ?"),
        (0.0, True, "± 0 %"),
    ],
)
def test_an_uncertainty_alone_keeps_two_significant_digits(u, percent, expected):
    assert format_uncertainty(u, percent=percent) == expected


@given(u=st.floats(1e-12, 1e12), lower_bound=st.booleans())
def test_uncertainty_alone_is_its_value_to_two_digits(u, lower_bound):
    """Written alone, u reads back within half its second significant digit (a lower bound:
    never above u, less than one such digit below), with exactly two significant digits."""
    text = format_uncertainty(u, lower_bound=lower_bound)
    assert text.startswith(f"{PLUS_MINUS} ")
    number = text.split(" ")[1].lstrip(">")
    shown = float(number)
    step = 10.0 ** (math.floor(math.log10(shown)) - 1)  # the second significant digit
    mantissa = number.split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    exponent = int(number.split("e")[1]) if "e" in number else 0
    assert 10.0 ** (exponent - decimals) == step or (decimals == 0 and step >= 1), text
    if lower_bound:
        assert shown <= u * (1 + 1e-9) and u - shown < step * (1 + 1e-6)
    else:
        assert abs(shown - u) <= 0.5 * step * (1 + 1e-6)
