"""The radial multiplier's kernel (multiplier, energy and product in separate passes per row) gives
the bits of the stored-table kernel on the same values, for any grid, both powers of |q| and both
precisions: the speed-up of issue 36 changes no result."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.bem.elastic.fft_backend import (
    RadialMultiplier,
    _multiply_radial,
    _multiply_stored,
)
from asperity.bem.elastic.influence import wavevectors_squared


@settings(max_examples=40, deadline=None)
@given(
    nx=st.integers(1, 33),
    ny=st.integers(1, 33),
    power=st.sampled_from([-1, 1]),
    q00=st.sampled_from([0.0, 0.37]),
    single=st.booleans(),
    energy=st.booleans(),
    seed=st.integers(0, 2**16),
)
def test_radial_kernel_equals_the_stored_table_bit_for_bit(
    nx: int, ny: int, power: int, q00: float, single: bool, energy: bool, seed: int
) -> None:
    qx2, qy2 = wavevectors_squared(nx, ny, 1.3e-6, 0.7e-6)
    radial = RadialMultiplier(qx2, qy2, 2.5e-7 if power < 0 else 4.1e6, power, q00)
    nn = float(nx * ny)
    table = radial.materialise() / nn  # the same operations in the same order: (coef op q) / nn
    rng = np.random.default_rng(seed)
    cdtype = np.complex64 if single else np.complex128
    spec = (rng.standard_normal(table.shape) + 1j * rng.standard_normal(table.shape)).astype(cdtype)
    a, b = spec.copy(), spec.copy()
    ea = _multiply_radial(a, radial, nn, ny, energy)
    eb = _multiply_stored(b, table, ny)
    assert np.array_equal(a, b)
    assert np.isfinite(a).all()  # the q = 0 element is patched, never inf * spectrum
    assert ea == (eb if energy else 0.0)
