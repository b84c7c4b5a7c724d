"""Fixtures of the bem tests: geometries (from tests/_helpers.py) and the contact-conditions
check."""

from __future__ import annotations

import numpy as np
import pytest

from tests._helpers import random_surface, sphere_heights


def check_contact_conditions(
    res, heights=None, *, rel_gap: float = 1e-5, rel_force: float = 1e-9, force=None
) -> None:
    """Assert force balance and complementarity on a ContactResult.

    p >= 0 (or >= -Sigma with adhesion) everywhere, p = 0 outside the contact set, |g| small in
    contact and g >= -small outside (relative to the peak-to-valley of ``heights``), the
    reported force equals sum p dx dy, and it equals ``force`` when given.
    """
    p, g, m = res.pressure, res.gap, res.contact_mask
    assert np.all(np.isfinite(p)) and np.all(np.isfinite(g))
    sigma = res.critical_tension
    scale = float(np.ptp(heights if heights is not None else g)) or 1e-300
    assert p.min() >= -sigma * (1 + 1e-12) - 1e-300, "pressure below the lower bound"
    assert np.all(p[~m] == 0.0), "pressure outside the contact set"
    if m.any():
        assert np.abs(g[m]).max() <= rel_gap * scale, "gap does not close in contact"
    if (~m).any():
        assert g[~m].min() >= -rel_gap * scale, "penetration outside the contact set"
    total = p.sum() * res.dx * res.dy
    assert res.normal_force == pytest.approx(total, rel=1e-12, abs=1e-300)
    assert res.real_area == pytest.approx(m.sum() * res.dx * res.dy)
    assert res.contact_fraction == pytest.approx(m.mean())
    if force is not None:
        assert res.normal_force == pytest.approx(force, rel=rel_force)


@pytest.fixture
def contact_ok():
    return check_contact_conditions


@pytest.fixture
def sphere():
    return sphere_heights


@pytest.fixture
def rough():
    return random_surface
