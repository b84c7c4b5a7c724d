"""Guards of the solver's cost that do not depend on the machine's speed (issue 28, section 3).

The 5000^2 regression of issue 28 had two parts that counts catch without a clock: the
``"auto"`` FFT backend was timed again for every precision in every process (about 18
convolutions of 0.4-0.7 s at 5000^2), and an iteration's cost is its transforms (a
preconditioned iteration transforms at most 5 times: the stiffness convolution, K t, and
K p instead of K t's inverse after a contact-set change). The wall-clock view of the same
is ``benchmarks/bem_floor.py`` (floor iterations).
"""

from __future__ import annotations

import numpy as np
import pytest

from asperity import bem
from asperity.bem.elastic import fft_backend
from asperity.bem.elastic.fft_backend import Convolution, RadialMultiplier
from asperity.bem.elastic.influence import wavevectors_squared
from asperity.bem.elastic.operators import influence_operator

E_STAR = 2.0e6  # Pa
DX = 1e-6  # m


def _rough(n: int, seed: int) -> np.ndarray:
    """A smooth periodic random surface (m), rms 1 um."""
    rng = np.random.default_rng(seed)
    spec = np.fft.rfft2(rng.standard_normal((n, n)))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.rfftfreq(n), indexing="ij"))
    spec *= 1.0 / (1.0 + (q * 24.0) ** 2)
    spec[0, 0] = 0.0
    h = np.fft.irfft2(spec, s=(n, n))
    return h * (1e-6 / h.std())


def _solve_rough(options: bem.SolverOptions, periodic: bool = True):
    """The 128^2 rough surface (seed 5) pressed at 0.5 % of E* on the mean."""
    h = _rough(128, seed=5)
    return bem.solve_contact(
        h, DX, DX, E_STAR, mean_pressure=0.005 * E_STAR, periodic=periodic, options=options
    )


def test_auto_backend_is_timed_once_per_grid_for_both_precisions(monkeypatch):
    shape = (30, 22)  # a grid no other test uses: its choice is not cached yet
    for key in [k for k in fft_backend._AUTO_CHOICE if k[0] == shape]:
        monkeypatch.delitem(fft_backend._AUTO_CHOICE, key)
    timed = []
    real_timed = fft_backend._timed

    def counting(conv, x, out):
        timed.append(conv.precision)
        return real_timed(conv, x, out)

    monkeypatch.setattr(fft_backend, "_timed", counting)
    qx2, qy2 = wavevectors_squared(*shape, DX, DX)
    mult = RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1)
    Convolution(mult, shape, backend="auto", precision="double")
    first = len(timed)
    assert first > 0  # the choice was timed ...
    Convolution(mult, shape, backend="auto", precision="single")
    Convolution(mult, shape, backend="auto", precision="double")
    assert len(timed) == first  # ... once for both precisions and every later operator


@pytest.mark.parametrize("precision", ["double", "mixed"])
def test_a_preconditioned_iteration_transforms_at_most_five_times(precision):
    res = _solve_rough(bem.SolverOptions(tol=1e-8, precision=precision))
    assert res.converged
    assert res.nit > 5
    transforms = res.extra["fft_transforms"]
    # 5 a iteration; the first K p and, mixed, the exact K p at the switch to double: 2 each
    assert transforms <= 5 * res.nit + 4, (transforms, res.nit)
    if precision == "mixed":
        assert 0 < res.extra["single_precision_transforms"] < transforms


@pytest.mark.parametrize("precision", ["double", "single"])
def test_the_fourier_energy_does_not_depend_on_the_thread_count(precision):
    """The multiplication's Parseval sum runs in parallel rows; the rows are summed in order,
    so one or two threads give the same bits (the solver's step lengths, hence its iterates,
    do not depend on the machine's cores)."""
    n = 96
    qx2, qy2 = wavevectors_squared(n, n, DX, DX)
    x = np.random.default_rng(3).standard_normal((n, n))
    out = {}
    for threads in (1, 2):
        for name, mult in (
            ("kernel", RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1)),
            ("stiffness", RadialMultiplier(qx2, qy2, 0.5 * E_STAR, 1, 1.0)),
            ("stored", RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1).materialise()),
        ):
            conv = Convolution(mult, (n, n), backend="scipy", threads=threads, precision=precision)
            y = conv.empty()
            out[threads, name] = (conv.with_energy(x, y), y)
    for name in ("kernel", "stiffness", "stored"):
        e1, y1 = out[1, name]
        e2, y2 = out[2, name]
        assert e1 == e2
        assert np.array_equal(y1, y2)
    # and the energy is sum(x * y) (Parseval), the quantity the step length needs
    e, y = out[1, "kernel"]
    tol = 1e-12 if precision == "double" else 1e-5
    assert e == pytest.approx(float(np.sum(x * y)), rel=tol)


def test_the_cached_operator_keeps_its_threads_after_a_parallel_multiply():
    """The numba thread count is lowered to the operator's FFT threads inside a transform and
    restored afterwards (no state left behind for the caller's own parallel kernels)."""
    import numba

    before = numba.get_num_threads()
    op = influence_operator((64, 64), DX, DX, E_STAR, "point", True, "scipy", 1)
    x = op.empty()
    x[...] = 1.0
    op.with_energy(x, op.empty())
    assert numba.get_num_threads() == before


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("precondition", [True, False])
def test_an_iteration_transforms_twice_per_convolution_and_once_more_per_set_jump(
    precondition, periodic
):
    """Where every transform goes (issue 36): the search direction's two (t forward with its
    energy, K t back, the gap then by linearity), the preconditioner's two, and one more in an
    iteration whose contact set jumped or whose gap was refreshed (u = K p recomputed instead
    of K t's inverse); the first u = K p and the exact one at the switch to double precision:
    2 each. The free boundary's padded transforms count the same way."""
    options = bem.SolverOptions(tol=1e-8, precision="mixed", precondition=precondition)
    res = _solve_rough(options, periodic=periodic)
    assert res.converged
    ex = res.extra
    assert ex["preconditioner_dropped_at"] is None
    per_iteration = 4 if precondition else 2
    switched = 2 if ex["precision_switched_at"] is not None else 0
    expected = (
        per_iteration * res.nit
        + ex["set_change_recomputations"]
        + ex["refresh_recomputations"]
        + 2
        + switched
    )
    assert ex["fft_transforms"] == expected, (ex, res.nit)
    assert 0 < ex["set_change_recomputations"] < res.nit
