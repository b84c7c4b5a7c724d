"""Fused numba kernels of the Polonsky-Keer iteration (flat float64 arrays, int8 contact mask).

Each kernel is one pass over the arrays, written as four interleaved lanes with separate partial
sums and without data-dependent branches in the common path: the loop-carried floating-point
sums then no longer serialise on the add latency and LLVM can pack the lanes into SIMD
registers, all without fastmath (the summation order is fixed, results are deterministic).
Measured at 1024^2: 5.1 ms -> 1.1 ms for the direction update.

The array ``w`` holds the gap u - h without the rigid-body term (m), ``p`` the pressure (Pa),
``t`` the conjugate direction, ``r = K t`` its deflection, ``c`` the contact set (1 = in
contact). Kernels that return several sums return them as named tuples.

The kernels of an iteration (issue 36, section 1: the pointwise work) run, on arrays of
:data:`PARALLEL_MIN` elements or more, in parallel over fixed blocks of :data:`CHUNK` elements
(numba ``prange``, on the threads the caller allows: the solver runs them on its FFT operator's
threads, :func:`asperity.bem.normal.iteration.iterate`); smaller arrays take the serial kernel
on the whole array. Each block is the serial four-lane kernel above on a slice; the blocks'
partial sums are added in block order, so the result does not depend on the number of threads
(the same bits on 1 or 16 cores). One thread costs about what the serial kernel did (0.85
against 0.84 ms for the gap step at 1024^2); on the shared 2-core machine a second thread gave
0.9-1.3x (the kernels are bound by memory bandwidth, and the other core was busy); many cores
were not measured. The ``*_into`` variants also write t into a second array (the
single-precision transform's own float32 input: no cast pass), and the kernels take float32
``s``, ``z`` and ``r`` as the transforms leave them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, prange

__all__ = [
    "CHUNK",
    "PARALLEL_MIN",
    "DirectionUpdate",
    "GapStats",
    "ResidualField",
    "PressureStep",
    "deflection_to_gap_stats",
    "dot",
    "gap_stats",
    "gap_step",
    "masked_sum",
    "residual_field",
    "scale_with_stats",
    "shift_on_contact",
    "step_pressure",
    "update_direction",
    "update_direction_into",
    "update_direction_preconditioned",
    "update_direction_preconditioned_into",
]


#: Elements per parallel block (2^15: 256 KiB of float64). The blocks' partial sums are added
#: in block order, so the result does not depend on the thread count.
CHUNK = 1 << 15
#: Below this many elements (512^2) a kernel runs serially on the whole array (as before the
#: blocks: the same bits): a parallel region's start and its wait for a second thread on a busy
#: core cost more than such a pass (at 256^2 on the shared 2-core machine, 2 threads: mean 0.71
#: ms against 0.18 ms for the gap step).
PARALLEL_MIN = 1 << 18


class GapStats(NamedTuple):
    """Gap statistics over the contact set: element count, sum of (g - shift) (m) and sum of
    (g - shift)^2 (m^2)."""

    n_contact: int
    gap_sum: float
    gap_sq: float


class DirectionUpdate(NamedTuple):
    """Result of :func:`update_direction`: sum over the contact set of g t (m^2), the squared
    penetration outside it (m^2) and the number of penetrating elements."""

    sum_gt: float
    penetration_sq: float
    n_penetrating: int


class ResidualField(NamedTuple):
    """Result of :func:`residual_field`: squared penetration outside the contact set (m^2) and
    the number of penetrating elements."""

    penetration_sq: float
    n_penetrating: int


class PressureStep(NamedTuple):
    """Result of :func:`step_pressure`: elements that left / entered the contact set, sum p and
    sum p^2 (Pa, Pa^2) after the step, and the contact-set size."""

    n_left: int
    n_entered: int
    pressure_sum: float
    pressure_sq: float
    n_contact: int


@njit(inline="always")
def _gap_elem(w, h, c, i, shift):  # pragma: no cover - compiled
    g = w[i] - h[i]
    w[i] = g
    ci = c[i]
    d = (g - shift) * (1.0 if ci else 0.0)
    return ci, d, d * d


@njit(cache=True, fastmath=False)
def _deflection_to_gap_stats_block(w, h, c, shift):  # pragma: no cover - compiled
    """w -= h in place (deflection -> gap without the rigid-body term); returns n, sum(g - shift)
    and sum((g - shift)^2) over the contact set."""
    n = 0
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        k0, x0, y0 = _gap_elem(w, h, c, i, shift)
        k1, x1, y1 = _gap_elem(w, h, c, i + 1, shift)
        k2, x2, y2 = _gap_elem(w, h, c, i + 2, shift)
        k3, x3, y3 = _gap_elem(w, h, c, i + 3, shift)
        n += k0 + k1 + k2 + k3
        a0 += x0
        a1 += x1
        a2 += x2
        a3 += x3
        b0 += y0
        b1 += y1
        b2 += y2
        b3 += y3
    for i in range(m4, size):
        k0, x0, y0 = _gap_elem(w, h, c, i, shift)
        n += k0
        a0 += x0
        b0 += y0
    return GapStats(n, (a0 + a1) + (a2 + a3), (b0 + b1) + (b2 + b3))


@njit(inline="always")
def _stats_elem(w, c, i, shift):  # pragma: no cover - compiled
    ci = c[i]
    d = (w[i] - shift) * (1.0 if ci else 0.0)
    return ci, d, d * d


@njit(cache=True, fastmath=False)
def gap_stats(w, c, shift):  # pragma: no cover - compiled
    """The statistics of :func:`deflection_to_gap_stats` of a ``w`` that already holds the
    gap (nothing is written): n, sum(g - shift) and sum((g - shift)^2) over the contact set,
    summed in the same order (bit-identical)."""
    n = 0
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        k0, x0, y0 = _stats_elem(w, c, i, shift)
        k1, x1, y1 = _stats_elem(w, c, i + 1, shift)
        k2, x2, y2 = _stats_elem(w, c, i + 2, shift)
        k3, x3, y3 = _stats_elem(w, c, i + 3, shift)
        n += k0 + k1 + k2 + k3
        a0 += x0
        a1 += x1
        a2 += x2
        a3 += x3
        b0 += y0
        b1 += y1
        b2 += y2
        b3 += y3
    for i in range(m4, size):
        k0, x0, y0 = _stats_elem(w, c, i, shift)
        n += k0
        a0 += x0
        b0 += y0
    return GapStats(n, (a0 + a1) + (a2 + a3), (b0 + b1) + (b2 + b3))


@njit(inline="always")
def _direction_elem(w, c, t, tc, i, offset, beta):  # pragma: no cover - compiled
    g = w[i] - offset
    m = 1.0 if c[i] else 0.0
    ti = m * (g + beta * t[i])
    t[i] = ti
    tc[i] = ti
    q = min(g, 0.0) * (1.0 - m)
    return g * ti, q * q, 1 if q < 0.0 else 0


@njit(cache=True, fastmath=False)
def _update_direction_block(w, c, t, tc, offset, beta):  # pragma: no cover - compiled
    """t = g + beta t on the contact set (0 outside), g = w - offset.

    Returns sum_c g t, the squared penetration outside the set and its pixel count.
    """
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    npen = 0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        x0, y0, k0 = _direction_elem(w, c, t, tc, i, offset, beta)
        x1, y1, k1 = _direction_elem(w, c, t, tc, i + 1, offset, beta)
        x2, y2, k2 = _direction_elem(w, c, t, tc, i + 2, offset, beta)
        x3, y3, k3 = _direction_elem(w, c, t, tc, i + 3, offset, beta)
        a0 += x0
        a1 += x1
        a2 += x2
        a3 += x3
        b0 += y0
        b1 += y1
        b2 += y2
        b3 += y3
        npen += k0 + k1 + k2 + k3
    for i in range(m4, size):
        x0, y0, k0 = _direction_elem(w, c, t, tc, i, offset, beta)
        a0 += x0
        b0 += y0
        npen += k0
    return DirectionUpdate((a0 + a1) + (a2 + a3), (b0 + b1) + (b2 + b3), npen)


@njit(inline="always")
def _residual_elem(w, c, s, i, offset):  # pragma: no cover - compiled
    g = w[i] - offset
    m = 1.0 if c[i] else 0.0
    s[i] = m * g
    q = min(g, 0.0) * (1.0 - m)
    return q * q, 1 if q < 0.0 else 0


@njit(cache=True, fastmath=False)
def _residual_field_block(w, c, s, offset):  # pragma: no cover - compiled
    """s = g on the contact set, 0 outside (g = w - offset), the input of the preconditioner;
    returns the squared penetration outside the set and its pixel count."""
    b0 = b1 = b2 = b3 = 0.0
    npen = 0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        y0, k0 = _residual_elem(w, c, s, i, offset)
        y1, k1 = _residual_elem(w, c, s, i + 1, offset)
        y2, k2 = _residual_elem(w, c, s, i + 2, offset)
        y3, k3 = _residual_elem(w, c, s, i + 3, offset)
        b0 += y0
        b1 += y1
        b2 += y2
        b3 += y3
        npen += k0 + k1 + k2 + k3
    for i in range(m4, size):
        y0, k0 = _residual_elem(w, c, s, i, offset)
        b0 += y0
        npen += k0
    return ResidualField((b0 + b1) + (b2 + b3), npen)


@njit(cache=True, fastmath=False)
def _masked_sum_block(z, c):  # pragma: no cover - compiled
    """Sum of z over the contact set."""
    s0 = s1 = s2 = s3 = 0.0
    size = z.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        s0 += z[i] * (1.0 if c[i] else 0.0)
        s1 += z[i + 1] * (1.0 if c[i + 1] else 0.0)
        s2 += z[i + 2] * (1.0 if c[i + 2] else 0.0)
        s3 += z[i + 3] * (1.0 if c[i + 3] else 0.0)
    for i in range(m4, size):
        s0 += z[i] * (1.0 if c[i] else 0.0)
    return (s0 + s1) + (s2 + s3)


@njit(inline="always")
def _pc_direction_elem(w, c, t, tc, z, i, offset, zbar, beta):  # pragma: no cover - compiled
    m = 1.0 if c[i] else 0.0
    ti = m * ((z[i] - zbar) + beta * t[i])
    t[i] = ti
    tc[i] = ti
    return (w[i] - offset) * ti


@njit(cache=True, fastmath=False)
def _update_direction_preconditioned_block(w, c, t, tc, z, offset, zbar, beta):  # pragma: no cover
    """t = (z - zbar) + beta t on the contact set, 0 outside, z the preconditioned gap;
    returns sum_c g t with g = w - offset."""
    a0 = a1 = a2 = a3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        a0 += _pc_direction_elem(w, c, t, tc, z, i, offset, zbar, beta)
        a1 += _pc_direction_elem(w, c, t, tc, z, i + 1, offset, zbar, beta)
        a2 += _pc_direction_elem(w, c, t, tc, z, i + 2, offset, zbar, beta)
        a3 += _pc_direction_elem(w, c, t, tc, z, i + 3, offset, zbar, beta)
    for i in range(m4, size):
        a0 += _pc_direction_elem(w, c, t, tc, z, i, offset, zbar, beta)
    return (a0 + a1) + (a2 + a3)


@njit(cache=True, fastmath=False)
def dot(a, b):  # pragma: no cover - compiled
    s0 = s1 = s2 = s3 = 0.0
    size = a.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        s0 += a[i] * b[i]
        s1 += a[i + 1] * b[i + 1]
        s2 += a[i + 2] * b[i + 2]
        s3 += a[i + 3] * b[i + 3]
    for i in range(m4, size):
        s0 += a[i] * b[i]
    return (s0 + s1) + (s2 + s3)


@njit(inline="always")
def _scale_elem(p, w, h, c, i, alpha, shift):  # pragma: no cover - compiled
    p[i] *= alpha
    hi = h[i]
    wi = alpha * (w[i] + hi) - hi
    w[i] = wi
    ci = c[i]
    d = (wi - shift) * (1.0 if ci else 0.0)
    return ci, d


@njit(cache=True, fastmath=False)
def scale_with_stats(p, w, h, c, alpha, shift):  # pragma: no cover - compiled
    """p *= alpha and the gap w = u - h follows (u = K p is linear in p); returns the
    contact-set gap statistics after."""
    n = 0
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        k0, d0 = _scale_elem(p, w, h, c, i, alpha, shift)
        k1, d1 = _scale_elem(p, w, h, c, i + 1, alpha, shift)
        k2, d2 = _scale_elem(p, w, h, c, i + 2, alpha, shift)
        k3, d3 = _scale_elem(p, w, h, c, i + 3, alpha, shift)
        n += k0 + k1 + k2 + k3
        a0 += d0
        a1 += d1
        a2 += d2
        a3 += d3
        b0 += d0 * d0
        b1 += d1 * d1
        b2 += d2 * d2
        b3 += d3 * d3
    for i in range(m4, size):
        k0, d0 = _scale_elem(p, w, h, c, i, alpha, shift)
        n += k0
        a0 += d0
        b0 += d0 * d0
    return GapStats(n, (a0 + a1) + (a2 + a3), (b0 + b1) + (b2 + b3))


@njit(cache=True, fastmath=False)
def shift_on_contact(p, c, delta):  # pragma: no cover - compiled
    """p += delta on the contact set (elements pushed below -Sigma delaminate at the next
    change-allowed step); returns the new sum of p."""
    s = 0.0
    for i in range(p.size):
        if c[i]:
            p[i] += delta
        s += p[i]
    return s


@njit(inline="always")
def _step_elem(p, t, w, c, i, step):  # pragma: no cover - compiled
    tau, offset, lower, allow_change, gain = step
    ci = c[i]
    pi = p[i] - tau * t[i]  # t = 0 and p = 0 outside the contact set
    g = w[i] - offset
    leave = allow_change and ci != 0 and pi < -lower
    enter = allow_change and ci == 0 and g < 0.0
    pi = 0.0 if leave else pi
    pi = -gain * g if enter else pi
    cn = 0 if leave else ci
    cn = 1 if enter else cn
    c[i] = cn
    p[i] = pi
    return 1 if leave else 0, 1 if enter else 0, pi, cn


@njit(cache=True, fastmath=False)
def _step_pressure_block(p, t, w, c, tau, offset, lower, allow_change, gain):  # pragma: no cover
    """The pressure and contact-set update of a Polonsky-Keer step, without the gap.

    p -= tau t; when ``allow_change`` elements leave where p < -lower and enter (p = -gain g)
    where the gap g = w - offset < 0. Returns a :class:`PressureStep`; the gap follows with
    :func:`gap_step` once r = K t is known, or from a fresh u = K p."""
    step = (tau, offset, lower, allow_change, gain)
    left = 0
    entered = 0
    n = 0
    ps0 = ps1 = ps2 = ps3 = 0.0
    pq0 = pq1 = pq2 = pq3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        l0, e0, p0, k0 = _step_elem(p, t, w, c, i, step)
        l1, e1, p1, k1 = _step_elem(p, t, w, c, i + 1, step)
        l2, e2, p2, k2 = _step_elem(p, t, w, c, i + 2, step)
        l3, e3, p3, k3 = _step_elem(p, t, w, c, i + 3, step)
        left += l0 + l1 + l2 + l3
        entered += e0 + e1 + e2 + e3
        n += k0 + k1 + k2 + k3
        ps0 += p0
        ps1 += p1
        ps2 += p2
        ps3 += p3
        pq0 += p0 * p0
        pq1 += p1 * p1
        pq2 += p2 * p2
        pq3 += p3 * p3
    for i in range(m4, size):
        l0, e0, p0, k0 = _step_elem(p, t, w, c, i, step)
        left += l0
        entered += e0
        n += k0
        ps0 += p0
        pq0 += p0 * p0
    return PressureStep(left, entered, (ps0 + ps1) + (ps2 + ps3), (pq0 + pq1) + (pq2 + pq3), n)


@njit(inline="always")
def _gap_step_elem(w, r, c, i, tau, shift):  # pragma: no cover - compiled
    wi = w[i] - tau * r[i]
    w[i] = wi
    ci = c[i]
    d = (wi - shift) * (1.0 if ci else 0.0)
    return ci, d


@njit(cache=True, fastmath=False)
def _gap_step_block(w, r, c, tau, shift):  # pragma: no cover - compiled
    """The gap update of a Polonsky-Keer step (after :func:`step_pressure`): w -= tau r.

    Returns the contact-set gap statistics about ``shift`` (a :class:`GapStats`)."""
    n = 0
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    size = w.size
    m4 = size - size % 4
    for i in range(0, m4, 4):
        k0, d0 = _gap_step_elem(w, r, c, i, tau, shift)
        k1, d1 = _gap_step_elem(w, r, c, i + 1, tau, shift)
        k2, d2 = _gap_step_elem(w, r, c, i + 2, tau, shift)
        k3, d3 = _gap_step_elem(w, r, c, i + 3, tau, shift)
        n += k0 + k1 + k2 + k3
        a0 += d0
        a1 += d1
        a2 += d2
        a3 += d3
        b0 += d0 * d0
        b1 += d1 * d1
        b2 += d2 * d2
        b3 += d3 * d3
    for i in range(m4, size):
        k0, d0 = _gap_step_elem(w, r, c, i, tau, shift)
        n += k0
        a0 += d0
        b0 += d0 * d0
    return GapStats(n, (a0 + a1) + (a2 + a3), (b0 + b1) + (b2 + b3))


@njit(inline="always")
def _blocks(size):  # pragma: no cover - compiled
    return max(1, (size + CHUNK - 1) // CHUNK)  # one (empty) block for an empty array


@njit(inline="always")
def _fsum(a):  # pragma: no cover - compiled
    total = a[0] * 0
    for k in range(a.size):
        total += a[k]
    return total


@njit(cache=True, fastmath=False, parallel=True)
def deflection_to_gap_stats(w, h, c, shift):  # pragma: no cover - compiled
    """w -= h in place (deflection -> gap without the rigid-body term); returns n, sum(g - shift)
    and sum((g - shift)^2) over the contact set (a :class:`GapStats`), in parallel blocks."""
    if w.size < PARALLEL_MIN:
        return _deflection_to_gap_stats_block(w, h, c, shift)
    nb = _blocks(w.size)
    n = np.zeros(nb, dtype=np.int64)
    s1 = np.zeros(nb)
    s2 = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        n[k], s1[k], s2[k] = _deflection_to_gap_stats_block(w[lo:hi], h[lo:hi], c[lo:hi], shift)
    return GapStats(_fsum(n), _fsum(s1), _fsum(s2))


@njit(cache=True, fastmath=False)
def update_direction(w, c, t, offset, beta):  # pragma: no cover - compiled
    """t = g + beta t on the contact set (0 outside), g = w - offset, in parallel blocks.

    Returns sum_c g t, the squared penetration outside the set and its pixel count.
    """
    return update_direction_into(w, c, t, t, offset, beta)


@njit(cache=True, fastmath=False, parallel=True)
def update_direction_into(w, c, t, tc, offset, beta):  # pragma: no cover - compiled
    """:func:`update_direction` that also writes t into ``tc`` (the float32 input of the
    single-precision transform of t: no cast pass; ``tc`` may be ``t`` itself)."""
    if w.size < PARALLEL_MIN:
        return _update_direction_block(w, c, t, tc, offset, beta)
    nb = _blocks(w.size)
    s1 = np.zeros(nb)
    s2 = np.zeros(nb)
    n = np.zeros(nb, dtype=np.int64)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        s1[k], s2[k], n[k] = _update_direction_block(
            w[lo:hi], c[lo:hi], t[lo:hi], tc[lo:hi], offset, beta
        )
    return DirectionUpdate(_fsum(s1), _fsum(s2), _fsum(n))


@njit(cache=True, fastmath=False, parallel=True)
def residual_field(w, c, s, offset):  # pragma: no cover - compiled
    """s = g on the contact set, 0 outside (g = w - offset), the input of the preconditioner;
    returns the squared penetration outside the set and its pixel count (parallel blocks)."""
    if w.size < PARALLEL_MIN:
        return _residual_field_block(w, c, s, offset)
    nb = _blocks(w.size)
    s2 = np.zeros(nb)
    n = np.zeros(nb, dtype=np.int64)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        s2[k], n[k] = _residual_field_block(w[lo:hi], c[lo:hi], s[lo:hi], offset)
    return ResidualField(_fsum(s2), _fsum(n))


@njit(cache=True, fastmath=False, parallel=True)
def masked_sum(z, c):  # pragma: no cover - compiled
    """Sum of z over the contact set (parallel blocks)."""
    if z.size < PARALLEL_MIN:
        return _masked_sum_block(z, c)
    nb = _blocks(z.size)
    s = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, z.size)
        s[k] = _masked_sum_block(z[lo:hi], c[lo:hi])
    return _fsum(s)


@njit(cache=True, fastmath=False)
def update_direction_preconditioned(w, c, t, z, offset, zbar, beta):  # pragma: no cover
    """t = (z - zbar) + beta t on the contact set, 0 outside, z the preconditioned gap;
    returns sum_c g t with g = w - offset (parallel blocks)."""
    return update_direction_preconditioned_into(w, c, t, t, z, offset, zbar, beta)


@njit(cache=True, fastmath=False, parallel=True)
def update_direction_preconditioned_into(w, c, t, tc, z, offset, zbar, beta):  # pragma: no cover
    """:func:`update_direction_preconditioned` that also writes t into ``tc`` (the float32
    input of the single-precision transform of t; ``tc`` may be ``t`` itself)."""
    if w.size < PARALLEL_MIN:
        return _update_direction_preconditioned_block(w, c, t, tc, z, offset, zbar, beta)
    nb = _blocks(w.size)
    s = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        s[k] = _update_direction_preconditioned_block(
            w[lo:hi], c[lo:hi], t[lo:hi], tc[lo:hi], z[lo:hi], offset, zbar, beta
        )
    return _fsum(s)


@njit(cache=True, fastmath=False, parallel=True)
def step_pressure(p, t, w, c, tau, offset, lower, allow_change, gain):  # pragma: no cover
    """The pressure and contact-set update of a Polonsky-Keer step, without the gap.

    p -= tau t; when ``allow_change`` elements leave where p < -lower and enter (p = -gain g)
    where the gap g = w - offset < 0. Returns a :class:`PressureStep`; the gap follows with
    :func:`gap_step` once r = K t is known, or from a fresh u = K p. Parallel blocks."""
    if w.size < PARALLEL_MIN:
        return _step_pressure_block(p, t, w, c, tau, offset, lower, allow_change, gain)
    nb = _blocks(w.size)
    nl = np.zeros(nb, dtype=np.int64)
    ne = np.zeros(nb, dtype=np.int64)
    nc = np.zeros(nb, dtype=np.int64)
    s1 = np.zeros(nb)
    s2 = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        nl[k], ne[k], s1[k], s2[k], nc[k] = _step_pressure_block(
            p[lo:hi], t[lo:hi], w[lo:hi], c[lo:hi], tau, offset, lower, allow_change, gain
        )
    return PressureStep(_fsum(nl), _fsum(ne), _fsum(s1), _fsum(s2), _fsum(nc))


@njit(cache=True, fastmath=False, parallel=True)
def gap_step(w, r, c, tau, shift):  # pragma: no cover - compiled
    """The gap update of a Polonsky-Keer step (after :func:`step_pressure`): w -= tau r.

    Returns the contact-set gap statistics about ``shift`` (a :class:`GapStats`); parallel
    blocks."""
    if w.size < PARALLEL_MIN:
        return _gap_step_block(w, r, c, tau, shift)
    nb = _blocks(w.size)
    n = np.zeros(nb, dtype=np.int64)
    s1 = np.zeros(nb)
    s2 = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, w.size)
        n[k], s1[k], s2[k] = _gap_step_block(w[lo:hi], r[lo:hi], c[lo:hi], tau, shift)
    return GapStats(_fsum(n), _fsum(s1), _fsum(s2))
