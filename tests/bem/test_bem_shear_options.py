"""One route for the knobs of the mixed-mode shear curve: ShearOptions carries them; the old loose
keywords of :func:`asperity.bem.shear.rough_mixed_mode.mixed_mode_shear_curve` still work, with a
DeprecationWarning, and give the same curve."""

import dataclasses

import numpy as np
import pytest

from asperity.bem.errors import BemInputError
from asperity.bem.shear.stick_slip import ShearOptions
from tests._helpers import shear_cap_curve as _curve


def _same(a, b) -> bool:
    skip = {"seconds", "normal_seconds"}
    return all(
        np.array_equal(getattr(a, f.name), getattr(b, f.name))
        for f in dataclasses.fields(a)
        if f.name not in skip
    )


def test_loose_keywords_warn_and_match_options():
    """Each old keyword warns (DeprecationWarning naming it) and gives the curve of the same knob
    in ShearOptions; the knobs change the curve (a collapse fraction near 1 slides earlier)."""
    knobs = {"collapse_fraction": 0.95, "slide_margin": 1, "preload_load_factor": 6.0}
    with pytest.warns(DeprecationWarning, match="collapse_fraction, preload_load_factor"):
        loose = _curve(**knobs)
    routed = _curve(options=ShearOptions(**knobs))
    assert _same(loose, routed)
    default = _curve()
    assert not _same(default, routed)
    first_slide = [int(np.argmax(c.sliding)) if c.sliding.any() else 99 for c in (default, routed)]
    assert first_slide[1] <= first_slide[0]


def test_loose_keyword_overrides_options():
    with pytest.warns(DeprecationWarning, match="max_active_set"):
        curve = _curve(options=ShearOptions(max_active_set=500), max_active_set=1)
    assert not curve.success  # one active-set iteration cannot settle a receding edge


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("preload_load_factor", 1.0),
        ("collapse_fraction", 1.0),
        ("slide_margin", -1),
        ("slide_margin", 1.5),
        ("load_tolerance", 0.0),
        ("max_active_set", 0),
        ("max_step_halvings", 9),
        ("rebond_slides", 1),
    ],
)
def test_bad_knob_names_its_key(key, value):
    with pytest.raises(BemInputError, match=key):
        ShearOptions(**{key: value})
