"""The transactional step of the mixed-mode shear curve: a step that fails is undone and retried
in 2, 4, ... sub-steps of delta_T (``ShearOptions.max_step_halvings``), and the result says so."""

import numpy as np
import pytest

from asperity.bem.shear import rough_mixed_mode as rmm
from asperity.bem.shear.mixed_mode import MixedModeLaw
from asperity.bem.shear.stick_slip import ShearOptions
from tests._helpers import SHEAR_CAP_E_STAR as E_STAR
from tests._helpers import SHEAR_CAP_W as W
from tests._helpers import shear_cap as _cap
from tests._helpers import shear_cap_curve as _curve
from tests._helpers import shear_cap_load

P_CAP = shear_cap_load()

D_T = np.linspace(0.0, 2e-3, 9)  # m, the path of tests._helpers.shear_cap_curve


@pytest.fixture(scope="module")
def before_step_four():
    """The free cap's state at D_T[3], reached with the default knobs: (problem, state)."""
    h, dx = _cap()
    law = MixedModeLaw(W, 0.2)
    prob = rmm._problem(h, dx, dx, E_STAR, P_CAP, law, False, ShearOptions(), 1e-3, None)
    st, _ = rmm._preload(prob, None)
    rmm._settle(prob, st, 0.0, check_junctions=False)
    for value in D_T[1:4]:
        assert rmm._settle(prob, st, float(value), check_junctions=True)["status"] == 0
    return prob, st


def _fields(st):
    return (st.c, st.slide, st.p, st.q, st.s, np.array(st.d))


def test_failed_step_is_undone_and_retried_smaller(before_step_four):
    """With 3 active-set iterations the step D_T[3] -> D_T[4] fails at once and holds in two
    halves; the retried step ends exactly where the two half steps taken from the untouched
    state end: the failed attempt left nothing behind."""
    prob, start = before_step_four
    prob.opts = ShearOptions(max_active_set=3, max_step_halvings=0)
    once = start.copy()
    assert rmm._settle(prob, once, float(D_T[4]), check_junctions=True)["status"] == 1

    prob.normal.slope = None
    halves = start.copy()
    for value in (0.5 * (D_T[3] + D_T[4]), D_T[4]):
        assert rmm._settle(prob, halves, float(value), check_junctions=True)["status"] == 0

    prob.normal.slope = None
    prob.opts = ShearOptions(max_active_set=3, max_step_halvings=3)
    retried = start.copy()
    row = rmm._transactional_step(prob, retried, float(D_T[3]), float(D_T[4]))
    assert row["status"] == 0 and row["substeps"] == 2
    assert all(np.array_equal(a, b) for a, b in zip(_fields(retried), _fields(halves), strict=True))


def test_curve_reports_substeps_and_converges_more():
    """On the whole path the retries turn failed steps into converged ones, and the curve says
    how many sub-steps each step took (1 where it held at once); the default knobs need none."""
    tight = ShearOptions(max_active_set=3, max_step_halvings=0)
    retried = ShearOptions(max_active_set=3, max_step_halvings=3)
    plain, redone = _curve(options=tight), _curve(options=retried)
    assert np.all(plain.substeps == 1)
    assert redone.converged.sum() > plain.converged.sum()
    assert np.all(redone.substeps[redone.converged & ~plain.converged] > 1)
    assert np.all(_curve().substeps == 1)
