"""The adhesive loading path: a solve from scratch lies on the loading branch from first contact,
the same branch a load sweep follows, and every result says which branch it is on."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from asperity.bem import SolverStatus, load_sweep, solve_contact
from asperity.bem.normal.validity import BemWarning

W = 0.02  # J/m^2 with E* = 1 Pa and 1 m pixels: Sigma = 0.21 Pa, ~5 x the mean pressure


def test_cold_adhesive_solve_agrees_with_the_end_of_a_loading_sweep(rough, contact_ok):
    h = rough(96, seed=3)
    force = 0.04 * h.size
    cold = solve_contact(h, 1.0, 1.0, 1.0, normal_force=force, work_of_adhesion=W)
    sweep = load_sweep(h, 1.0, 1.0, 1.0, [force / 4, force / 2, force], work_of_adhesion=W)
    assert cold.converged and all(r.converged for r in sweep), cold.message
    assert cold.branch == "loading" and [r.branch for r in sweep] == ["loading"] * 3
    contact_ok(cold, h, force=force)
    assert sweep[-1].real_area == pytest.approx(cold.real_area, rel=1e-3)
    # contact grows along the loading branch
    areas = [r.real_area for r in sweep]
    assert areas == sorted(areas)


def test_a_fine_adhesive_load_ramp_approaches_the_loading_branch(rough):
    """Warm-started adhesive steps (the pre-fix path) overshoot by elements that tension holds
    but the loading never brought into contact; refining the steps converges to the loading
    branch that a solve from scratch returns."""
    h = rough(64, seed=1)
    force = 0.04 * h.size
    cold = solve_contact(h, 1.0, 1.0, 1.0, normal_force=force, work_of_adhesion=W)
    excess = []
    for n in (4, 32):
        forces = force * np.geomspace(1e-3, 1.0, n)
        state = solve_contact(h, 1.0, 1.0, 1.0, normal_force=forces[0])
        for f in forces[1:]:  # a plain array start: no branch knowledge, adhesive steps
            state = solve_contact(
                h, 1.0, 1.0, 1.0, normal_force=f, work_of_adhesion=W, initial=state.pressure
            )
        assert state.branch == "from initial"
        excess.append(state.real_area / cold.real_area - 1)
    assert excess[0] > excess[1] >= -1e-9
    assert excess[1] < 0.3 * excess[0]


def test_unloading_then_reloading_branches():
    h = np.zeros((16, 16))
    h[6:10, 6:10] = 1e-3
    kw = dict(work_of_adhesion=1e-3)
    with pytest.warns(BemWarning, match="full contact"):  # adhesion pulls the bump in flat
        loaded = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.1, **kw)
        unloaded = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.01, initial=loaded, **kw)
        reloaded = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.05, initial=unloaded, **kw)
    assert (loaded.branch, unloaded.branch, reloaded.branch) == (
        "loading",
        "unloading",
        "from initial",
    )


def test_zero_load_first_contact_and_through_zero_on_unloading(rough, contact_ok):
    """F = 0 from scratch is first contact (converged, no pressure); F = 0 reached by unloading
    is a converged adhesive state whose tension and compression cancel (the force check is
    relative to the pressures, not to 1e-300)."""
    h = rough(64, seed=2)
    first = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.0, work_of_adhesion=W)
    assert first.success and first.status == SolverStatus.CONVERGED, first.message
    assert first.normal_force == 0 and np.all(first.pressure == 0)
    assert first.contact_mask[np.unravel_index(np.argmax(h), h.shape)]
    assert first.separation == pytest.approx(h.max())
    top = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.04 * h.size, work_of_adhesion=W)
    zero = solve_contact(h, 1.0, 1.0, 1.0, normal_force=0.0, work_of_adhesion=W, initial=top)
    assert zero.converged and zero.branch == "unloading", zero.message
    contact_ok(zero, h)
    assert zero.pressure.min() < 0 < zero.pressure.max()
    assert abs(zero.normal_force) < 1e-8 * np.abs(zero.pressure).sum()


@pytest.mark.parametrize(
    "heights", [np.zeros((8, 8)), np.array([[0.0, 1.0], [0.2, 0.1]])], ids=["flat", "2x2"]
)
def test_settled_adhesive_states_are_converged(heights, contact_ok):
    """A flat map in full contact and a 2x2 map were reported "stalled at residual 0 > tol"."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", BemWarning)
        res = solve_contact(heights, 1.0, 1.0, 1.0, normal_force=0.1, work_of_adhesion=0.01)
    assert res.converged and res.status == 0, res.message
    full = res.contact_fraction == 1.0  # the flat map: said, as a warning and on the result
    assert [w.message.code for w in caught] == (["bem_full_contact"] if full else [])
    contact_ok(res, heights, force=0.1)
