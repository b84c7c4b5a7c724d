"""Compiled kernels of the statistical model: the asperity integrals and the separation solve.

The integrals E:Fy_Greenwood / E:Ar_Greenwood (preload) and E:NewFormulation_Fy/Fx/Ar (shear, with
the limits E:delta_2 and E:delta_1) are evaluated with the contact radius ``a`` as the integration
variable instead of the indentation ``delta``:

* stick population (delta >= delta_2, PC law): with u = sqrt(k^2 a - c) (k^2 = 2 pi w/E*,
  c = 4/9 lambda delta_T^2), E:PC_indent is explicit, a = (u^2 + c)/k^2 and
  delta(u) = a^2/R - u, so int P(delta) phi(d + delta) d delta = int P(u) phi(d + delta(u))
  delta'(u) du with delta'(u) = 4 a u / (R k^2) - 1 and P = 4 E* a^3/(3R) - 2 E* a u (E:PC_P).
  The integrand is a polynomial in u times a Gaussian: the square-root singularity of a(delta) at
  the fold delta_PC^min (a simple zero of delta'(u)) and the branch point of the PC law at
  k^2 a = c are both removed, so Gauss-Legendre converges spectrally, and no root is solved at
  the nodes: only the two end points a(delta_2) and a(delta_hi) are roots. (w = 0: Hertz in a.)
* slip population (delta_1 <= delta <= delta_2, Hertz law, only when delta_2 > 0): a = sqrt(R delta)
  removes the delta^(3/2) end-point singularity at delta = 0.

Each range is cut where the Gaussian summit-height density phi(z) is negligible, |z| <= cutoff *
sigma_s (z = d + delta), split into ``panels`` equal panels in ``a`` and integrated by
Gauss-Legendre with ``nodes`` nodes per panel. The expected numbers of sticking / slipping
asperities are closed forms (complementary error functions). All per-asperity values are returned
without the factor eta * A_n (applied by the caller).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from asperity.errors import InputError
from asperity.statmodel.papangelo_ciavarella import (
    coupling_term,
    pc_fold_indentation,
    pc_fold_radius_kernel,
    pc_radius_from_fold,
)

# Layout of the per-asperity result vector filled by :func:`asperity_integrals`.
FZ_STICK, FZ_SLIP, FX_STICK, FX_SLIP, AR_STICK, AR_SLIP, N_STICK, N_SLIP, DELTA_1, DELTA_2 = range(
    10
)
N_RESULTS = 10

# Layout of the parameter vector ``prm``.
P_D_PRELOAD, P_R, P_E, P_W, P_LAM, P_TAU, P_SIGMA, P_DELTA_LOAD, P_N_ASP, P_CUTOFF = range(10)
N_PARAMS = 10


def gauss_legendre(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1] (numpy.polynomial.legendre.leggauss)."""
    if nodes < 1:
        raise InputError(f"nodes: expected a positive number of Gauss-Legendre nodes, got {nodes}")
    x, w = np.polynomial.legendre.leggauss(int(nodes))
    return np.ascontiguousarray(x), np.ascontiguousarray(w)


@njit(cache=True)
def asperity_integrals(d, delta_t, prm, gl_x, gl_w, n_panels, out):
    """Fill ``out`` with the per-asperity integrals at separation d (m) and delta_T (m).

    ``prm[P_D_PRELOAD]`` is the preload separation d_min (m); NaN selects the preload stage itself
    (lower limit delta_JKR^loading, i.e. d_min = d). Units of ``out``: N (forces), m^2 (areas),
    dimensionless (expected fraction of asperities), m (delta_1, delta_2).
    """
    sigma = prm[P_SIGMA]
    k2, c, a_f, delta_f, delta_1, delta_2 = _limits(d, delta_t, prm)
    lo = -prm[P_CUTOFF] * sigma - d
    hi = prm[P_CUTOFF] * sigma - d
    for j in range(N_RESULTS):
        out[j] = 0.0
    if delta_2 < hi:
        _stick_population(
            d, delta_t, prm, k2, c, a_f, delta_f, delta_2, lo, hi, gl_x, gl_w, n_panels, out
        )
    if delta_2 > 0.0:
        _slip_population(d, prm, delta_2, lo, hi, gl_x, gl_w, n_panels, out)
    root2s = math.sqrt(2.0) * sigma
    n_stick = 0.0 if math.isinf(delta_2) else 0.5 * math.erfc((d + delta_2) / root2s)
    n_all = 0.5 * math.erfc((d + delta_1) / root2s)
    out[N_STICK] = n_stick
    out[N_SLIP] = max(n_all - n_stick, 0.0)
    out[DELTA_1] = delta_1
    out[DELTA_2] = delta_2


# The steps of asperity_integrals below are inlined into it (numba inline="always"): as
# separate compiled calls they made a shear curve about 3.5 % slower.


@njit(cache=True, inline="always")
def _limits(d, delta_t, prm):
    """(k^2, c, a'_min, delta_PC^min, delta_1, delta_2) at separation d (m) and delta_T (m).

    k^2 = 2 pi w / E* (m), c = 4/9 lambda delta_T^2 (m^2), the fold of the PC law (m), and the
    integral limits E:delta_2 = max(d_min - d + delta_JKR^loading, delta_PC^min), E:delta_1 =
    min(0, delta_2) in m (d_min = d at the preload, ``prm[P_D_PRELOAD]`` NaN).
    """
    R = prm[P_R]
    E = prm[P_E]
    w = prm[P_W]
    k2 = 2.0 * math.pi * w / E
    c = coupling_term(delta_t, prm[P_LAM])
    a_f = pc_fold_radius_kernel(delta_t, R, w, E, prm[P_LAM])
    delta_f = pc_fold_indentation(a_f, k2, c, R)
    if math.isnan(prm[P_D_PRELOAD]):
        hist = prm[P_DELTA_LOAD]
    else:
        hist = prm[P_D_PRELOAD] - d + prm[P_DELTA_LOAD]
    delta_2 = max(hist, delta_f)  # E:delta_2
    delta_1 = min(0.0, delta_2)  # E:delta_1
    return k2, c, a_f, delta_f, delta_1, delta_2


@njit(cache=True, inline="always")
def _stick_population(
    d, delta_t, prm, k2, c, a_f, delta_f, delta_2, lo, hi, gl_x, gl_w, n_panels, out
):
    """Fill ``out`` with F_z (N), F_x (N), A_r (m^2) of the sticking asperities.

    PC law (E:PC_indent, E:PC_P, E:PC_T) over delta in [max(delta_2, lo), hi] (m), integrated
    over u (w > 0) or a (w = 0).
    """
    R = prm[P_R]
    E = prm[P_E]
    sigma = prm[P_SIGMA]
    a_lo = pc_radius_from_fold(max(delta_2, lo), k2, c, R, a_f, delta_f)
    a_hi = pc_radius_from_fold(hi, k2, c, R, a_f, delta_f)
    inv2s2 = 0.5 / (sigma * sigma)
    if k2 > 0.0:
        fz, fx, ar, width = _stick_sums_pc(d, a_lo, a_hi, k2, c, R, E, inv2s2, gl_x, gl_w, n_panels)
    else:
        fz, fx, ar, width = _stick_sums_hertz(d, a_lo, a_hi, R, E, inv2s2, gl_x, gl_w, n_panels)
    scale = 0.5 * width * (1.0 / (math.sqrt(2.0 * math.pi) * sigma))
    out[FZ_STICK] = fz * scale
    out[FX_STICK] = fx * scale * (4.0 / 3.0 * E * abs(delta_t))
    out[AR_STICK] = ar * scale * math.pi


@njit(cache=True, inline="always")
def _stick_sums_pc(d, a_lo, a_hi, k2, c, R, E, inv2s2, gl_x, gl_w, n_panels):
    """Gauss-Legendre sums over u = sqrt(k^2 a - c) of the PC law (E:PC_indent, E:PC_P).

    a = (u^2 + c)/k^2, delta = a^2/R - u, d delta = (4 a u/(R k^2) - 1) du. Returns the sums
    of P, a and a^2 times the Gaussian (without its normalisation) and the panel width in u.
    """
    u_lo = math.sqrt(max(k2 * a_lo - c, 0.0))
    u_hi = math.sqrt(max(k2 * a_hi - c, 0.0))
    width = (u_hi - u_lo) / n_panels
    fz = 0.0
    fx = 0.0
    ar = 0.0
    for p in range(n_panels):
        mid = u_lo + (p + 0.5) * width
        for i in range(gl_x.shape[0]):
            u = mid + 0.5 * width * gl_x[i]
            a = (u * u + c) / k2
            dd = 4.0 * a * u / (R * k2) - 1.0
            z = d + a * a / R - u
            f = gl_w[i] * dd * math.exp(-z * z * inv2s2)
            fz += f * (4.0 * E * a * a * a / (3.0 * R) - 2.0 * E * a * u)
            fx += f * a
            ar += f * a * a
    return fz, fx, ar, width


@njit(cache=True, inline="always")
def _stick_sums_hertz(d, a_lo, a_hi, R, E, inv2s2, gl_x, gl_w, n_panels):
    """Gauss-Legendre sums over a of the stick population when w = 0 (then c = 0).

    Hertz, delta = a^2/R, d delta = 2a/R da. Returns the sums of P, a and a^2 times the
    Gaussian (without its normalisation) and the panel width in a (m).
    """
    width = (a_hi - a_lo) / n_panels
    fz = 0.0
    fx = 0.0
    ar = 0.0
    for p in range(n_panels):
        mid = a_lo + (p + 0.5) * width
        for i in range(gl_x.shape[0]):
            a = mid + 0.5 * width * gl_x[i]
            z = d + a * a / R
            f = gl_w[i] * (2.0 * a / R) * math.exp(-z * z * inv2s2)
            fz += f * (4.0 * E * a * a * a / (3.0 * R))
            fx += f * a
            ar += f * a * a
    return fz, fx, ar, width


@njit(cache=True, inline="always")
def _slip_population(d, prm, delta_2, lo, hi, gl_x, gl_w, n_panels, out):
    """Fill ``out`` with F_z (N), F_x = tau0 A_r (N), A_r (m^2) of the sliding asperities.

    Hertz law over delta in [max(0, lo), min(delta_2, hi)] (m), integrated over
    a = sqrt(R delta) (removes the delta^(3/2) end point at delta = 0).
    """
    R = prm[P_R]
    sigma = prm[P_SIGMA]
    d_lo = max(0.0, lo)
    d_hi = min(delta_2, hi)
    if not d_hi > d_lo:
        return
    a_lo = math.sqrt(R * d_lo)
    a_hi = math.sqrt(R * d_hi)
    width = (a_hi - a_lo) / n_panels
    inv2s2 = 0.5 / (sigma * sigma)
    fz = 0.0
    ar = 0.0
    for p in range(n_panels):
        mid = a_lo + (p + 0.5) * width
        for i in range(gl_x.shape[0]):
            a = mid + 0.5 * width * gl_x[i]
            z = d + a * a / R
            f = gl_w[i] * (2.0 * a / R) * math.exp(-z * z * inv2s2)
            fz += f * a * a * a
            ar += f * a * a
    scale = 0.5 * width * (1.0 / (math.sqrt(2.0 * math.pi) * sigma))
    out[FZ_SLIP] = fz * scale * (4.0 * prm[P_E] / (3.0 * R))
    out[AR_SLIP] = ar * scale * math.pi
    out[FX_SLIP] = out[AR_SLIP] * prm[P_TAU]


@njit(cache=True)
def _residual(d, delta_t, target, prm, gl_x, gl_w, n_panels, out):
    asperity_integrals(d, delta_t, prm, gl_x, gl_w, n_panels, out)
    return prm[P_N_ASP] * (out[FZ_STICK] + out[FZ_SLIP]) - target


@njit(cache=True)
def _bracket(d0, h, delta_t, target, ftol, prm, gl_x, gl_w, n_panels, out, result):
    """March from d0 (geometric steps, first h) towards the root of F_z(d) - target.

    result <- (d_a, f_a, d_b, f_b, status, n_evaluations); status 1: |f(d0)| <= ftol already,
    2: bracket found, 0: failed (no sign change: the load cannot be carried).
    """
    f0 = _residual(d0, delta_t, target, prm, gl_x, gl_w, n_panels, out)
    nev = 1
    result[0] = d0
    result[1] = f0
    result[2] = d0
    result[3] = f0
    result[4] = 0.0
    if abs(f0) <= ftol:
        result[4] = 1.0
        result[5] = nev
        return
    direction = 1.0 if f0 > 0.0 else -1.0  # too much compression -> open the gap
    d_limit = 2.0 * prm[P_CUTOFF] * prm[P_SIGMA] + abs(d0)
    for _ in range(200):
        d1 = d0 + direction * h
        f1 = _residual(d1, delta_t, target, prm, gl_x, gl_w, n_panels, out)
        nev += 1
        if (f1 <= 0.0) == (f0 > 0.0) or f1 == 0.0:
            result[0] = d0
            result[1] = f0
            result[2] = d1
            result[3] = f1
            result[4] = 2.0
            result[5] = nev
            return
        d0 = d1
        f0 = f1
        h *= 2.0
        if direction > 0.0 and d1 > d_limit:
            break  # beyond the cut-off no asperity touches: the load cannot be reached
    result[5] = nev


@njit(cache=True)
def _brent(a, b, fa, fb, delta_t, target, ftol, xtol, max_iter, prm, gl_x, gl_w, n_panels, out):
    """Brent-Dekker root of F_z(d) - target in the bracket [a, b]; returns (d, nit, converged)."""
    eps = 2.220446049250313e-16
    c = a
    fc = fa
    e = b - a
    step = e
    for it in range(1, max_iter + 1):
        if (fb > 0.0) == (fc > 0.0) and fb != 0.0:
            c = a
            fc = fa
            e = b - a
            step = e
        if abs(fc) < abs(fb):
            a = b
            b = c
            c = a
            fa = fb
            fb = fc
            fc = fa
        tol1 = 2.0 * eps * abs(b) + 0.5 * xtol
        xm = 0.5 * (c - b)
        if abs(xm) <= tol1 or abs(fb) <= ftol:
            return b, it, True
        if abs(e) >= tol1 and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p = 2.0 * xm * s
                q = 1.0 - s
            else:
                q = fa / fc
                r = fb / fc
                p = s * (2.0 * xm * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * xm * q - abs(tol1 * q), abs(e * q)):
                e = step
                step = p / q
            else:
                step = xm
                e = step
        else:
            step = xm
            e = step
        a = b
        fa = fb
        if abs(step) > tol1:
            b += step
        else:
            b += tol1 if xm > 0.0 else -tol1
        fb = _residual(b, delta_t, target, prm, gl_x, gl_w, n_panels, out)
    return b, max_iter, False


@njit(cache=True)
def solve_separation(
    d0, h, delta_t, target, ftol, xtol, max_iter, prm, gl_x, gl_w, n_panels, out, work
):
    """Separation d (m) carrying the normal load ``target`` (N) at delta_T, starting from d0.

    Returns (d, nit, converged); ``out`` holds the integrals at the returned d.
    """
    _bracket(d0, h, delta_t, target, ftol, prm, gl_x, gl_w, n_panels, out, work)
    nev = int(work[5])
    if work[4] == 1.0:
        asperity_integrals(work[0], delta_t, prm, gl_x, gl_w, n_panels, out)
        return work[0], nev, True
    if work[4] == 0.0:
        asperity_integrals(work[0], delta_t, prm, gl_x, gl_w, n_panels, out)
        return math.nan, nev, False
    if work[3] == 0.0:
        asperity_integrals(work[2], delta_t, prm, gl_x, gl_w, n_panels, out)
        return work[2], nev, True
    d, nit, ok = _brent(
        work[0],
        work[2],
        work[1],
        work[3],
        delta_t,
        target,
        ftol,
        xtol,
        max_iter,
        prm,
        gl_x,
        gl_w,
        n_panels,
        out,
    )
    asperity_integrals(d, delta_t, prm, gl_x, gl_w, n_panels, out)
    return d, nev + nit + 1, ok


@njit(cache=True)
def shear_path(
    delta_ts,
    target,
    d_start,
    ftol,
    xtol,
    max_iter,
    prm,
    gl_x,
    gl_w,
    n_panels,
    results,
    separations,
    nits,
):
    """Load-controlled shear path: for each delta_T solve d with F_z(d, delta_T) = target.

    Warm start: each step starts from the previous separation with a first bracketing step of
    1.5 times the previous separation increment. Fills ``results[i, :]`` (per-asperity integrals),
    ``separations[i]`` (m) and ``nits[i]`` (function evaluations); returns the number of
    converged steps (the path stops at the first failure, the rest stays NaN).
    """
    out = np.empty(N_RESULTS)
    work = np.empty(6)
    d = d_start
    h_min = 1.0e-8 * prm[P_SIGMA]
    h = h_min
    for i in range(delta_ts.shape[0]):
        d_new, nit, ok = solve_separation(
            d, h, delta_ts[i], target, ftol, xtol, max_iter, prm, gl_x, gl_w, n_panels, out, work
        )
        nits[i] = nit
        if not ok:
            return i
        for j in range(N_RESULTS):
            results[i, j] = out[j]
        separations[i] = d_new
        h = max(1.5 * abs(d_new - d), h_min)
        d = d_new
    return delta_ts.shape[0]


@njit(cache=True)
def fixed_separation_path(delta_ts, d, prm, gl_x, gl_w, n_panels, results):
    """Fixed-grip shear at constant separation d (m): fills ``results[i, :]`` for each delta_T."""
    out = np.empty(N_RESULTS)
    for i in range(delta_ts.shape[0]):
        asperity_integrals(d, delta_ts[i], prm, gl_x, gl_w, n_panels, out)
        for j in range(N_RESULTS):
            results[i, j] = out[j]
