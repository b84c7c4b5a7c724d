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
def _blocks(size):  # pragma: no cover - compiled
    return max(1, (size + CHUNK - 1) // CHUNK)  # one (empty) block for an empty array


@njit(inline="always")
def _fsum(a):  # pragma: no cover - compiled
    total = a[0] * 0
    for k in range(a.size):
        total += a[k]
    return total


@njit(inline="always")
def _lane_sums(elem, lo, hi, args):  # pragma: no cover - compiled
    """The sums over lo <= i < hi of ``elem(i, args) = (k1, k2, k3, x, y)`` (three counts, two
    values; an element kernel also writes its arrays at i): the counts exactly, x and y each in
    four interleaved lanes (the blocks of four from ``lo``, the tail in lane 0) added as
    (l0 + l1) + (l2 + l3). The one reduction of the module's kernels (inlined: the slots a
    kernel leaves at 0 are dead code)."""
    n1 = n2 = n3 = 0
    x0 = x1 = x2 = x3 = 0.0
    y0 = y1 = y2 = y3 = 0.0
    m4 = hi - (hi - lo) % 4
    for i in range(lo, m4, 4):
        a1, a2, a3, ax, ay = elem(i, args)
        b1, b2, b3, bx, by = elem(i + 1, args)
        c1, c2, c3, cx, cy = elem(i + 2, args)
        d1, d2, d3, dx, dy = elem(i + 3, args)
        n1 += a1 + b1 + c1 + d1
        n2 += a2 + b2 + c2 + d2
        n3 += a3 + b3 + c3 + d3
        x0 += ax
        x1 += bx
        x2 += cx
        x3 += dx
        y0 += ay
        y1 += by
        y2 += cy
        y3 += dy
    for i in range(m4, hi):
        a1, a2, a3, ax, ay = elem(i, args)
        n1 += a1
        n2 += a2
        n3 += a3
        x0 += ax
        y0 += ay
    return n1, n2, n3, (x0 + x1) + (x2 + x3), (y0 + y1) + (y2 + y3)


@njit(inline="always")
def _dot_elem(i, args):  # pragma: no cover - compiled
    a, b = args
    return 0, 0, 0, a[i] * b[i], 0.0


@njit(cache=True, fastmath=False)
def dot(a, b):  # pragma: no cover - compiled
    """sum(a * b) in the module's fixed four-lane order."""
    return _lane_sums(_dot_elem, 0, a.size, (a, b))[3]


@njit(inline="always")
def _block_sums(block, size, args):  # pragma: no cover - compiled
    """The sums of ``block(lo, hi, args)`` (a serial kernel: :func:`_lane_sums` of one element
    kernel over lo <= i < hi) over the whole array (``size`` elements): in one call below
    :data:`PARALLEL_MIN`, else over blocks of :data:`CHUNK` in parallel (``prange``, in the
    caller's parallel region), the blocks' sums added in block order. The element kernels
    run only inside the serial ``block``: inlined into a parallel function, numba 0.68 drops
    some of their array writes."""
    if size < PARALLEL_MIN:
        return block(0, size, args)
    nb = _blocks(size)
    n1 = np.zeros(nb, dtype=np.int64)
    n2 = np.zeros(nb, dtype=np.int64)
    n3 = np.zeros(nb, dtype=np.int64)
    sx = np.zeros(nb)
    sy = np.zeros(nb)
    for k in prange(nb):
        lo, hi = k * CHUNK, min((k + 1) * CHUNK, size)
        n1[k], n2[k], n3[k], sx[k], sy[k] = block(lo, hi, args)
    return _fsum(n1), _fsum(n2), _fsum(n3), _fsum(sx), _fsum(sy)


@njit(inline="always")
def _contact_moments(ci, g, shift):  # pragma: no cover - compiled
    """The slots of a gap-statistics element: (c, 0, 0, d, d^2), d = g - shift on the contact
    set (c = 1), 0 outside."""
    d = (g - shift) * (1.0 if ci else 0.0)
    return ci, 0, 0, d, d * d


@njit(inline="always")
def _gap_elem(i, args):  # pragma: no cover - compiled
    w, h, c, shift = args
    g = w[i] - h[i]
    w[i] = g
    return _contact_moments(c[i], g, shift)


@njit(cache=True, fastmath=False)
def _gap_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_gap_elem, lo, hi, args)


@njit(inline="always")
def _stats_elem(i, args):  # pragma: no cover - compiled
    w, c, shift = args
    return _contact_moments(c[i], w[i], shift)


@njit(cache=True, fastmath=False)
def gap_stats(w, c, shift):  # pragma: no cover - compiled
    """The statistics of :func:`deflection_to_gap_stats` of a ``w`` that already holds the
    gap (nothing is written): n, sum(g - shift) and sum((g - shift)^2) over the contact set,
    summed in the same order (bit-identical)."""
    n, _, _, s1, s2 = _lane_sums(_stats_elem, 0, w.size, (w, c, shift))
    return GapStats(n, s1, s2)


@njit(inline="always")
def _direction_elem(i, args):  # pragma: no cover - compiled
    w, c, t, tc, offset, beta = args
    g = w[i] - offset
    m = 1.0 if c[i] else 0.0
    ti = m * (g + beta * t[i])
    t[i] = ti
    tc[i] = ti
    q = min(g, 0.0) * (1.0 - m)
    return 1 if q < 0.0 else 0, 0, 0, g * ti, q * q


@njit(cache=True, fastmath=False)
def _direction_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_direction_elem, lo, hi, args)


@njit(inline="always")
def _residual_elem(i, args):  # pragma: no cover - compiled
    w, c, s, offset = args
    g = w[i] - offset
    m = 1.0 if c[i] else 0.0
    s[i] = m * g
    q = min(g, 0.0) * (1.0 - m)
    return 1 if q < 0.0 else 0, 0, 0, q * q, 0.0


@njit(cache=True, fastmath=False)
def _residual_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_residual_elem, lo, hi, args)


@njit(inline="always")
def _masked_elem(i, args):  # pragma: no cover - compiled
    z, c = args
    return 0, 0, 0, z[i] * (1.0 if c[i] else 0.0), 0.0


@njit(cache=True, fastmath=False)
def _masked_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_masked_elem, lo, hi, args)


@njit(inline="always")
def _pc_direction_elem(i, args):  # pragma: no cover - compiled
    w, c, t, tc, z, offset, zbar, beta = args
    m = 1.0 if c[i] else 0.0
    ti = m * ((z[i] - zbar) + beta * t[i])
    t[i] = ti
    tc[i] = ti
    return 0, 0, 0, (w[i] - offset) * ti, 0.0


@njit(cache=True, fastmath=False)
def _pc_direction_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_pc_direction_elem, lo, hi, args)


@njit(inline="always")
def _scale_elem(i, args):  # pragma: no cover - compiled
    p, w, h, c, alpha, shift = args
    p[i] *= alpha
    hi = h[i]
    wi = alpha * (w[i] + hi) - hi
    w[i] = wi
    return _contact_moments(c[i], wi, shift)


@njit(cache=True, fastmath=False)
def scale_with_stats(p, w, h, c, alpha, shift):  # pragma: no cover - compiled
    """p *= alpha and the gap w = u - h follows (u = K p is linear in p); returns the
    contact-set gap statistics after."""
    n, _, _, s1, s2 = _lane_sums(_scale_elem, 0, w.size, (p, w, h, c, alpha, shift))
    return GapStats(n, s1, s2)


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
def _step_elem(i, args):  # pragma: no cover - compiled
    p, t, w, c, tau, offset, lower, allow_change, gain = args
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
    return 1 if leave else 0, 1 if enter else 0, cn, pi, pi * pi


@njit(cache=True, fastmath=False)
def _step_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_step_elem, lo, hi, args)


@njit(inline="always")
def _gap_step_elem(i, args):  # pragma: no cover - compiled
    w, r, c, tau, shift = args
    wi = w[i] - tau * r[i]
    w[i] = wi
    return _contact_moments(c[i], wi, shift)


@njit(cache=True, fastmath=False)
def _gap_step_block(lo, hi, args):  # pragma: no cover - compiled
    return _lane_sums(_gap_step_elem, lo, hi, args)


@njit(cache=True, fastmath=False, parallel=True)
def deflection_to_gap_stats(w, h, c, shift):  # pragma: no cover - compiled
    """w -= h in place (deflection -> gap without the rigid-body term); returns n, sum(g - shift)
    and sum((g - shift)^2) over the contact set (a :class:`GapStats`), in parallel blocks."""
    n, _, _, s1, s2 = _block_sums(_gap_block, w.size, (w, h, c, shift))
    return GapStats(n, s1, s2)


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
    n, _, _, s1, s2 = _block_sums(_direction_block, w.size, (w, c, t, tc, offset, beta))
    return DirectionUpdate(s1, s2, n)


@njit(cache=True, fastmath=False, parallel=True)
def residual_field(w, c, s, offset):  # pragma: no cover - compiled
    """s = g on the contact set, 0 outside (g = w - offset), the input of the preconditioner;
    returns the squared penetration outside the set and its pixel count (parallel blocks)."""
    n, _, _, s2, _ = _block_sums(_residual_block, w.size, (w, c, s, offset))
    return ResidualField(s2, n)


@njit(cache=True, fastmath=False, parallel=True)
def masked_sum(z, c):  # pragma: no cover - compiled
    """Sum of z over the contact set (parallel blocks)."""
    return _block_sums(_masked_block, z.size, (z, c))[3]


@njit(cache=True, fastmath=False)
def update_direction_preconditioned(w, c, t, z, offset, zbar, beta):  # pragma: no cover
    """t = (z - zbar) + beta t on the contact set, 0 outside, z the preconditioned gap;
    returns sum_c g t with g = w - offset (parallel blocks)."""
    return update_direction_preconditioned_into(w, c, t, t, z, offset, zbar, beta)


@njit(cache=True, fastmath=False, parallel=True)
def update_direction_preconditioned_into(w, c, t, tc, z, offset, zbar, beta):  # pragma: no cover
    """:func:`update_direction_preconditioned` that also writes t into ``tc`` (the float32
    input of the single-precision transform of t; ``tc`` may be ``t`` itself)."""
    args = (w, c, t, tc, z, offset, zbar, beta)
    return _block_sums(_pc_direction_block, w.size, args)[3]


@njit(cache=True, fastmath=False, parallel=True)
def step_pressure(p, t, w, c, tau, offset, lower, allow_change, gain):  # pragma: no cover
    """The pressure and contact-set update of a Polonsky-Keer step, without the gap.

    p -= tau t; when ``allow_change`` elements leave where p < -lower and enter (p = -gain g)
    where the gap g = w - offset < 0. Returns a :class:`PressureStep`; the gap follows with
    :func:`gap_step` once r = K t is known, or from a fresh u = K p. Parallel blocks."""
    args = (p, t, w, c, tau, offset, lower, allow_change, gain)
    left, entered, n, s1, s2 = _block_sums(_step_block, w.size, args)
    return PressureStep(left, entered, s1, s2, n)


@njit(cache=True, fastmath=False, parallel=True)
def gap_step(w, r, c, tau, shift):  # pragma: no cover - compiled
    """The gap update of a Polonsky-Keer step (after :func:`step_pressure`): w -= tau r.

    Returns the contact-set gap statistics about ``shift`` (a :class:`GapStats`); parallel
    blocks."""
    n, _, _, s1, s2 = _block_sums(_gap_step_block, w.size, (w, r, c, tau, shift))
    return GapStats(n, s1, s2)
