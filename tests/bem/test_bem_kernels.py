"""Property tests of the influence kernels, the fused solver kernels and the FFT backends."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from asperity.bem import critical_tension, crop_to_fast_size, fast_size
from asperity.bem.elastic.fft_backend import Convolution, available_backends
from asperity.bem.elastic.influence import (
    influence_multiplier,
    love_patch_deflection,
    padded_love_multiplier,
    point_force_multiplier,
)
from asperity.bem.elastic.pohrt_popov import pohrt_popov_chi
from asperity.bem.normal import kernels as kr
from tests._helpers import mirrored_patch_values, modulus_strategy, pixel_size_strategy

sizes, moduli = pixel_size_strategy(), modulus_strategy()


@given(dx=sizes, ratio=st.floats(0.2, 5.0), e_star=moduli)
@settings(max_examples=40, deadline=None)
def test_love_patch_symmetry_and_far_field(dx, ratio, e_star):
    dy = dx * ratio
    u = mirrored_patch_values(love_patch_deflection, dx, dy, e_star)
    pts = np.array([0.3, 1.7, 4.0]) * dx
    # swapping the axes together with the patch sides
    assert np.allclose(u, love_patch_deflection(pts[::-1], pts, dy, dx, e_star), rtol=1e-10)
    assert np.all(u > 0)
    # far field: a point force dx*dy at distance r: u = dx dy / (pi E* r)
    r = 200.0 * max(dx, dy)
    far = love_patch_deflection(np.array([r]), np.array([0.0]), dx, dy, e_star)[0]
    assert far == pytest.approx(dx * dy / (np.pi * e_star * r), rel=1e-4)


def test_love_patch_centre_of_square():
    # Johnson (1985): centre of a uniformly loaded square of side dx: 1.1222 dx p / E*
    assert love_patch_deflection(np.array(0.0), np.array(0.0), 1.0, 1.0, 1.0) == pytest.approx(
        4 * 2 * 0.5 * math.asinh(1.0) / math.pi, rel=1e-14
    )
    assert 4 * math.asinh(1.0) / math.pi == pytest.approx(1.1222, abs=1e-4)


@given(nx=st.integers(2, 40), ny=st.integers(2, 40), dx=sizes, e_star=moduli)
@settings(max_examples=40, deadline=None)
def test_point_multiplier_properties(nx, ny, dx, e_star):
    k = point_force_multiplier(nx, ny, dx, 1.5 * dx, e_star)
    assert k.shape == (nx, ny // 2 + 1)
    assert k[0, 0] == 0.0
    assert np.all(k.ravel()[1:] > 0)
    # 2 / (E* q) for the first x wavevector
    if nx > 2:
        assert k[1, 0] == pytest.approx(2.0 / (e_star * 2 * np.pi / (nx * dx)), rel=1e-12)
    # stiffer material, smaller compliance
    assert np.allclose(point_force_multiplier(nx, ny, dx, 1.5 * dx, 2 * e_star), k / 2)


@given(nx=st.integers(2, 12), ny=st.integers(2, 12))
@settings(max_examples=20, deadline=None)
def test_padded_kernel_is_free_space_convolution(nx, ny):
    """Circular convolution on the doubled grid == direct sum of Love patch deflections."""
    rng = np.random.default_rng(nx * 100 + ny)
    p = rng.random((nx, ny))
    dx, dy = 1.0, 0.7
    k = padded_love_multiplier(nx, ny, dx, dy, 1.0)
    big = np.zeros((2 * nx, 2 * ny))
    big[:nx, :ny] = p
    u = np.fft.irfft2(k * np.fft.rfft2(big), s=big.shape)[:nx, :ny]
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    direct = np.zeros((nx, ny))
    for a in range(nx):
        for b in range(ny):
            direct += p[a, b] * love_patch_deflection((i - a) * dx, (j - b) * dy, dx, dy, 1.0)
    np.testing.assert_allclose(u, direct, rtol=1e-10, atol=1e-12)


def test_periodic_love_matches_real_space_differences():
    """Deflection differences near a loaded pixel: periodic Love kernel vs Love's formula."""
    n = 128
    k, _ = influence_multiplier((n, n), 1.0, 1.0, 1.0, kernel="love")
    p = np.zeros((n, n))
    p[0, 0] = 1.0
    u = np.fft.irfft2(k * np.fft.rfft2(p), s=(n, n))
    exact = love_patch_deflection(np.array([0.0, 1.0, 3.0]), np.zeros(3), 1.0, 1.0, 1.0)
    assert u[0, 0] - u[1, 0] == pytest.approx(exact[0] - exact[1], rel=1e-3)
    assert u[0, 0] - u[3, 0] == pytest.approx(exact[0] - exact[2], rel=1e-3)


@given(w=st.floats(1e-4, 10.0), e_star=moduli, dx=sizes, ratio=st.floats(0.25, 4.0))
@settings(max_examples=50, deadline=None)
def test_critical_tension_properties(w, e_star, dx, ratio):
    dy = ratio * dx
    assert pohrt_popov_chi(dx, dy) == pytest.approx(pohrt_popov_chi(dy, dx), rel=1e-12)
    s = critical_tension(w, e_star, dx, dy)
    assert s > 0
    assert critical_tension(4 * w, e_star, dx, dy) == pytest.approx(2 * s, rel=1e-12)
    # eq:PohrtPopov_G at p = Sigma releases exactly w
    g = s**2 * pohrt_popov_chi(dx, dy) / (dx * dy * e_star)
    assert g == pytest.approx(w, rel=1e-10)


def test_critical_tension_square_value():
    assert pohrt_popov_chi(1.0, 1.0) == pytest.approx(0.473201, abs=1e-6)
    assert critical_tension(0.027, 1e6, 2e-6, 2e-6) == pytest.approx(
        math.sqrt(0.027 * 1e6 / (0.473201 * 2e-6)), rel=1e-6
    )
    assert critical_tension(0.0, 1e6, 1e-6, 1e-6) == 0.0
    with pytest.raises(ValueError, match="work_of_adhesion"):
        critical_tension(-1.0, 1e6, 1e-6, 1e-6)


arrays = st.integers(1, 300).flatmap(lambda n: st.tuples(st.just(n), st.integers(0, 2**31 - 1)))


def _state(n, seed):
    rng = np.random.default_rng(seed)
    u, h, t, r, p = (rng.standard_normal(n) for _ in range(5))
    c = (rng.random(n) < 0.4).astype(np.int8)
    p = np.where(c, np.abs(p), 0.0)
    t = np.where(c, t, 0.0)
    return u, h, c, t, r, p


@given(arrays, st.floats(-2, 2))
@settings(max_examples=60, deadline=None)
def test_fused_kernels_match_numpy(arr, offset):
    n, seed = arr
    u, h, c, t, r, p = _state(n, seed)
    m = c.astype(bool)
    w = u.copy()
    n_c, s1, s2 = kr.deflection_to_gap_stats(w, h, c, offset)
    np.testing.assert_allclose(w, u - h, rtol=1e-15, atol=1e-15)
    g = w - offset
    assert n_c == m.sum()
    assert s1 == pytest.approx(g[m].sum(), abs=1e-9)
    assert s2 == pytest.approx((g[m] ** 2).sum(), abs=1e-9)
    t2 = t.copy()
    sgt, pen, npen = kr.update_direction(w, c, t2, offset, 0.7)
    t_ref = np.where(m, g + 0.7 * t, 0.0)
    np.testing.assert_allclose(t2, t_ref, rtol=1e-14, atol=1e-14)
    assert sgt == pytest.approx((g[m] * t_ref[m]).sum(), abs=1e-9)
    assert pen == pytest.approx((np.minimum(g[~m], 0) ** 2).sum(), abs=1e-9)
    assert npen == int((g[~m] < 0).sum())
    # pressure step then gap step, with lower bound 0.1, against the numpy reference
    p2, w2, c2 = p.copy(), w.copy(), c.copy()
    tau = 0.3
    step = kr.step_pressure(p2, t2, w2, c2, tau, offset, 0.1, True, 2.0 * tau)
    gap = kr.gap_step(w2, r, c2, tau, offset)
    ref = reference_pressure_and_gap_step(p, t2, w, r, m, (tau, offset, 0.1, offset, True, 2 * tau))
    np.testing.assert_allclose(p2, ref["p"], rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(w2, ref["w"], rtol=1e-14, atol=1e-14)
    np.testing.assert_array_equal(c2.astype(bool), ref["c"])
    assert (step.n_left, step.n_entered, step.n_contact) == (ref["left"], ref["entered"], gap[0])
    assert step.pressure_sum == pytest.approx(ref["p"].sum(), abs=1e-9)
    assert step.pressure_sq == pytest.approx((ref["p"] ** 2).sum(), abs=1e-9)
    assert kr.dot(ref["p"], r) == pytest.approx(float(ref["p"] @ r), abs=1e-9)
    g2 = ref["w"] - offset
    assert gap.n_contact == ref["c"].sum()
    assert gap.gap_sum == pytest.approx(g2[ref["c"]].sum(), abs=1e-9)
    assert gap.gap_sq == pytest.approx((g2[ref["c"]] ** 2).sum(), abs=1e-9)
    # rescaling p rescales the deflection w + h
    p3, w3 = p2.copy(), w2.copy()
    kr.scale_with_stats(p3, w3, h, c2, 1.5, 0.0)
    np.testing.assert_allclose(p3, 1.5 * p2, rtol=1e-15)
    np.testing.assert_allclose(w3 + h, 1.5 * (w2 + h), rtol=1e-12, atol=1e-12)


def reference_pressure_and_gap_step(p, t, w, r, in_contact, step):
    """One Polonsky-Keer step with the Pohrt-Popov contact-set rule, in plain numpy.

    ``step`` = (tau, offset, lower, shift, allow_change, gain): p -= tau t, elements in contact
    leave where p < -lower (p -> 0), elements outside with gap g = w - offset < 0 enter with
    p = -gain g; then w -= tau r. The reference the split numba kernels must match.
    """
    tau, offset, lower, _shift, allow_change, gain = step
    g = w - offset
    p_try = p - tau * t
    leave = allow_change & in_contact & (p_try < -lower)
    enter = allow_change & ~in_contact & (g < 0)
    p_new = np.where(in_contact & ~leave, p_try, 0.0) + np.where(enter, -gain * g, 0.0)
    return {
        "p": p_new,
        "w": w - tau * r,
        "c": (in_contact & ~leave) | enter,
        "left": int(leave.sum()),
        "entered": int(enter.sum()),
    }


@pytest.mark.parametrize("allow_change", [True, False])
def test_split_pressure_and_gap_steps_match_the_numpy_reference(allow_change):
    """Both contact-set rules exercised on 1001 elements (not a multiple of the four lanes)."""
    rng = np.random.default_rng(3)
    n = 1001
    c = (rng.random(n) < 0.5).astype(np.int8)
    p = np.abs(rng.standard_normal(n)) * c
    t = rng.standard_normal(n) * c
    w, r = rng.standard_normal(n), rng.standard_normal(n)
    tau, offset, lower, shift, gain = 0.3, 0.1, 0.05, 0.02, 1.5
    ref = reference_pressure_and_gap_step(
        p, t, w, r, c.astype(bool), (tau, offset, lower, shift, allow_change, gain)
    )
    step = kr.step_pressure(p, t, w, c, tau, offset, lower, allow_change, gain)
    gap = kr.gap_step(w, r, c, tau, shift)
    np.testing.assert_array_equal(p, ref["p"])  # same operations in the same order: bit-equal
    np.testing.assert_array_equal(w, ref["w"])
    np.testing.assert_array_equal(c.astype(bool), ref["c"])
    assert (step.n_left, step.n_entered) == (ref["left"], ref["entered"])
    assert step.n_contact == gap.n_contact == ref["c"].sum()
    d = (ref["w"] - shift)[ref["c"]]
    assert gap.gap_sum == pytest.approx(d.sum(), rel=1e-12, abs=1e-12)
    assert gap.gap_sq == pytest.approx((d**2).sum(), rel=1e-12)
    if allow_change:
        assert step.n_left > 0 and step.n_entered > 0


def test_convolution_energy_is_parseval():
    rng = np.random.default_rng(3)
    for shape in [(16, 16), (15, 22), (9, 7)]:
        k = point_force_multiplier(*shape, 1.0, 1.0, 1.0)
        x = rng.standard_normal(shape)
        for backend in available_backends():
            conv = Convolution(k, shape, backend=backend)
            out = conv.empty()
            e = conv.with_energy(x, out)
            assert e == pytest.approx(float((x * out).sum()), rel=1e-12)


@pytest.mark.parametrize("backend", available_backends())
@pytest.mark.parametrize("shape", [(16, 16), (15, 22), (9, 7)])
def test_convolution_backends_agree_with_numpy(backend, shape):
    rng = np.random.default_rng(1)
    mult = rng.random((shape[0], shape[1] // 2 + 1))
    x = rng.standard_normal(shape)
    conv = Convolution(mult, shape, backend=backend, threads=2)
    ref = np.fft.irfft2(mult * np.fft.rfft2(x), s=shape)
    out = conv(x)
    np.testing.assert_allclose(out, ref, atol=1e-12)
    # aligned buffers and unaligned views give the same answer
    buf = conv.empty()
    buf[...] = x
    np.testing.assert_allclose(conv(buf, conv.empty()), ref, atol=1e-12)
    np.testing.assert_array_equal(buf, x)  # input preserved


def test_auto_backend_picks_an_available_one():
    conv = Convolution(np.ones((32, 17)), (32, 32), backend="auto")
    assert conv.backend in available_backends()
    with pytest.raises(ValueError, match="fft_backend"):
        Convolution(np.ones((32, 17)), (32, 32), backend="fftpack")


def test_fast_size_and_crop_warning():
    assert fast_size(5001) == 5000
    assert fast_size(1024) == 1024
    assert fast_size(1667) < 1667
    for n in (97, 1000, 5001):
        m = fast_size(n)
        k = m
        for f in (2, 3, 5, 7):
            while k % f == 0:
                k //= f
        assert k == 1 and m <= n
    h = np.zeros((5001, 13))
    with pytest.warns(UserWarning, match=r"5001 x 13 to 5000 x 12.*last 1 row.*last 1 column"):
        out = crop_to_fast_size(h)
    assert out.shape == (5000, 12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert crop_to_fast_size(np.zeros((64, 48))).shape == (64, 48)


def _iteration_kernels(n_threads: int, n: int, seed: int) -> list:
    """Every parallel kernel of an iteration once, on ``n_threads`` numba threads: outputs."""
    import numba

    u, h, c, t, r, p = _state(n, seed)
    w, tc, s = u.copy(), np.empty(n, dtype=np.float32), np.empty(n, dtype=np.float32)
    before = numba.get_num_threads()
    numba.set_num_threads(min(n_threads, numba.config.NUMBA_NUM_THREADS))
    try:
        out = [kr.deflection_to_gap_stats(w, h, c, 0.1)]
        out.append(kr.update_direction_into(w, c, t, tc, 0.1, 0.7))
        out.append(kr.residual_field(w, c, s, 0.1))
        out.append(kr.masked_sum(s, c))
        out.append(kr.update_direction_preconditioned_into(w, c, t, tc, s, 0.1, 0.01, 0.5))
        out.append(kr.step_pressure(p, t, w, c, 0.3, 0.1, 0.05, True, 0.2))
        out.append(kr.gap_step(w, r, c, 0.3, 0.1))
    finally:
        numba.set_num_threads(before)
    return [tuple(o) if isinstance(o, tuple) else o for o in out] + [w, t, tc, s, p, c]


def test_parallel_kernels_do_not_depend_on_the_thread_count():
    """The blocks' sums are added in block order: 1 and 2 threads give the same bits, on an
    array of several blocks and a ragged last one."""
    n = kr.PARALLEL_MIN + 2 * kr.CHUNK + 7
    one, two = _iteration_kernels(1, n, 4), _iteration_kernels(2, n, 4)
    for a, b in zip(one, two, strict=True):
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b)
        else:
            assert a == b


def test_parallel_kernels_match_numpy_across_blocks():
    """Across block boundaries the sums are those of the whole array (to round-off), the
    float32 copy of t is t rounded, and s is the contact-set residual rounded to float32."""
    n = kr.PARALLEL_MIN + kr.CHUNK + 3
    u, h, c, t, r, p = _state(n, 9)
    m = c.astype(bool)
    w = u.copy()
    n_c, s1, s2 = kr.deflection_to_gap_stats(w, h, c, 0.2)
    g = u - h - 0.2
    assert n_c == m.sum()
    assert s1 == pytest.approx(g[m].sum(), rel=1e-12, abs=1e-9)
    assert s2 == pytest.approx((g[m] ** 2).sum(), rel=1e-12)
    tc = np.empty(n, dtype=np.float32)
    t0 = t.copy()
    sgt, pen, npen = kr.update_direction_into(w, c, t, tc, 0.2, 0.5)
    np.testing.assert_array_equal(t, np.where(m, g + 0.5 * t0, 0.0))
    np.testing.assert_array_equal(tc, t.astype(np.float32))
    assert sgt == pytest.approx(float(g[m] @ t[m]), rel=1e-12)
    assert npen == int((g[~m] < 0).sum())
    s = np.empty(n, dtype=np.float32)
    kr.residual_field(w, c, s, 0.2)
    np.testing.assert_array_equal(s, np.where(m, g, 0.0).astype(np.float32))
    assert kr.masked_sum(s, c) == pytest.approx(float(s[m].astype(np.float64).sum()), rel=1e-12)


def test_small_arrays_take_the_serial_kernel_bit_for_bit():
    """Below PARALLEL_MIN the kernel is the serial one on the whole array (the same bits as
    before the blocks), and the blocks' sums differ from it only by round-off above."""
    for n in (kr.PARALLEL_MIN - 1, kr.PARALLEL_MIN + 5):
        u, h, c, t, r, p = _state(n, 2)
        w1, w2 = u.copy(), u.copy()
        got = kr.gap_step(w1, r, c, 0.3, 0.1)
        n_ref, _, _, sum_ref, sq_ref = kr._gap_step_block(0, n, (w2, r, c, 0.3, 0.1))
        np.testing.assert_array_equal(w1, w2)
        assert got.n_contact == n_ref
        if n < kr.PARALLEL_MIN:
            assert tuple(got) == (n_ref, sum_ref, sq_ref)
        else:
            assert got.gap_sq == pytest.approx(sq_ref, rel=1e-12)
