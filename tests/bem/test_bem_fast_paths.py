"""The fast paths of the paper-scale solver give the answers of the reference paths on small grids.

* mixed precision (float32 transforms, then double) against double throughout: same contact
  set up to the elements at the tolerance, pressures within the tolerance;
* a single-precision convolution against a double one: float32 round-off only;
* an adhesive sweep given the non-adhesive sweep (``non_adhesive=``) against the adhesive sweep
  that solves its loading branch itself: bit-identical (the same non-adhesive starts);
* the adhesive sweep on the loading branch against solves from scratch at each load.
"""

from __future__ import annotations

import numpy as np
import pytest

from asperity.bem import SolverOptions, load_sweep, solve_contact
from asperity.bem.elastic.fft_backend import Convolution, available_backends
from asperity.bem.elastic.influence import influence_multiplier
from asperity.bem.errors import BemInputError

W = 0.02  # J/m^2 on the unit-modulus, unit-pixel test surfaces (about 5 % contact)


@pytest.mark.parametrize("tol", [1e-6, 1e-9])
def test_mixed_precision_gives_the_double_contact_set(rough, contact_ok, tol):
    h = rough(256, seed=11)
    load = 0.04 * h.size
    double = solve_contact(
        h, 1.0, 1.0, 1.0, normal_force=load, options=SolverOptions(tol=tol, precision="double")
    )
    mixed = solve_contact(
        h, 1.0, 1.0, 1.0, normal_force=load, options=SolverOptions(tol=tol, precision="mixed")
    )
    assert double.converged and mixed.converged, (double.message, mixed.message)
    contact_ok(mixed, h, force=load)
    # the single-precision phase really ran, and the solve ended in double precision
    assert mixed.extra["single_precision_convolutions"] > 0
    assert mixed.extra["precision_switched_at"] is not None
    assert double.extra["single_precision_convolutions"] == 0
    assert mixed.residual < tol
    # same contact set up to elements at the tolerance; pressures agree to the tolerance
    assert np.count_nonzero(mixed.contact_mask != double.contact_mask) <= 2
    scale = double.pressure.max()
    assert np.abs(mixed.pressure - double.pressure).max() < 1e3 * tol * scale


def test_precision_auto_is_double_on_small_grids(rough):
    h = rough(64, seed=1)
    res = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(tol=1e-8))
    assert res.converged
    assert res.extra["single_precision_convolutions"] == 0
    assert SolverOptions().mixed_precision((512, 512))
    assert not SolverOptions().mixed_precision((256, 256))
    assert not SolverOptions(precision="double").mixed_precision((4096, 4096))


def test_precision_is_validated():
    with pytest.raises(BemInputError, match="precision"):
        SolverOptions(precision="half")
    with pytest.raises(BemInputError, match="precision"):
        Convolution(np.ones((8, 5)), (8, 8), backend="scipy", precision="float16")


@pytest.mark.parametrize("backend", available_backends())
def test_single_precision_convolution_is_float32_accurate(rough, backend):
    h = rough(96, seed=4)
    mult, grid = influence_multiplier(h.shape, 1.0, 1.0, 1.0, kernel="point", periodic=True)
    double = Convolution(mult, grid, backend=backend, threads=1)
    single = Convolution(mult, grid, backend=backend, threads=1, precision="single")
    x = double.empty()
    x[...] = np.abs(h)
    u64, u32 = double.empty(), double.empty()
    e64 = double.with_energy(x, u64)
    e32 = single.with_energy(x, u32)
    assert u32.dtype == np.float64  # callers keep float64 arrays
    err = np.abs(u32 - u64).max() / np.abs(u64).max()
    assert 1e-12 < err < 1e-5  # float32 round-off: neither exact nor worse than ~1e-6
    assert e32 == pytest.approx(e64, rel=1e-5)


def test_adhesive_sweep_from_the_non_adhesive_sweep_is_bit_identical(rough, contact_ok):
    h = rough(96, seed=7)
    forces = [0.02 * h.size * 1.3**k for k in range(4)]
    plain = load_sweep(h, 1.0, 1.0, 1.0, forces, options=SolverOptions(tol=1e-9))
    alone = load_sweep(
        h, 1.0, 1.0, 1.0, forces, work_of_adhesion=W, options=SolverOptions(tol=1e-9)
    )
    reused = load_sweep(
        h,
        1.0,
        1.0,
        1.0,
        forces,
        work_of_adhesion=W,
        non_adhesive=plain,
        options=SolverOptions(tol=1e-9),
    )
    for a, b, f in zip(alone, reused, forces, strict=True):
        assert a.converged and b.converged, (a.message, b.message)
        assert a.branch == b.branch == "loading"
        contact_ok(b, h, force=f)
        np.testing.assert_array_equal(a.pressure, b.pressure)
        np.testing.assert_array_equal(a.contact_mask, b.contact_mask)
    # reusing the non-adhesive solutions leaves only the adhesive checks: far fewer FFTs
    cost_alone = sum(r.extra["loading_start"]["convolutions"] for r in alone)
    assert all("loading_start" not in r.extra for r in reused)
    assert cost_alone > 0


def test_adhesive_sweep_is_the_loading_branch_of_solves_from_scratch(rough):
    h = rough(96, seed=7)
    forces = [0.02 * h.size * 1.3**k for k in range(3)]
    sweep = load_sweep(
        h, 1.0, 1.0, 1.0, forces, work_of_adhesion=W, options=SolverOptions(tol=1e-9)
    )
    for res, f in zip(sweep, forces, strict=True):
        scratch = solve_contact(
            h, 1.0, 1.0, 1.0, normal_force=f, work_of_adhesion=W, options=SolverOptions(tol=1e-9)
        )
        assert scratch.branch == res.branch == "loading"
        assert np.count_nonzero(scratch.contact_mask != res.contact_mask) <= 1
        np.testing.assert_allclose(res.pressure, scratch.pressure, atol=1e-6 * f)


def test_non_adhesive_results_are_checked(rough):
    h = rough(32, seed=1)
    forces = [0.02 * h.size, 0.03 * h.size]
    plain = load_sweep(h, 1.0, 1.0, 1.0, forces)
    with pytest.raises(BemInputError, match="results for"):
        load_sweep(h, 1.0, 1.0, 1.0, forces, work_of_adhesion=W, non_adhesive=plain[:1])
    with pytest.raises(BemInputError, match="order of normal_forces"):
        load_sweep(h, 1.0, 1.0, 1.0, forces, work_of_adhesion=W, non_adhesive=plain[::-1])
