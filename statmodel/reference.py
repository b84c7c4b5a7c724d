"""Converged reference of the statistical model by tight adaptive quadrature (tests, benchmarks).

Independent of the fast kernels in everything but the equations:

* integration variable: the indentation itself, delta = delta_PC^min + s^2 for the stick
  population (removes the square-root behaviour of a(delta) at the fold) and delta = s^2 for the
  Hertz slip population (removes the delta^(3/2) end point), instead of the fast path's u variable;
* quadrature: ``scipy.integrate.quad`` (adaptive Gauss-Kronrod, QUADPACK) with epsabs = 0,
  epsrel = 1e-13, limit = 500, one call per quantity, summit heights cut at |z| = 12 sigma_s;
* asperity laws: a(delta) from ``scipy.optimize.brentq`` on E:PC_indent in [a'_min, a_up]
  (xtol 1e-300, rtol 8.9e-16) with a'_min from brentq on the cubic E:Instable_boundary;
  P from E:PC_P as written (square-root form);
* separation: brentq (rtol 8.9e-16) on F_z(d) - F_z imposed, bracketed by its own scan.

It is slow (about 0.1-0.5 s per state); use it on a handful of steps.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import IntegrationWarning, quad
from scipy.optimize import brentq
from scipy.special import ndtr

from asperity.statmodel.parameters import Material, Roughness, material_tabor_parameter

EPSREL = 1e-13
LIMIT = 500
CUTOFF_SIGMA = 12.0
_RTOL = 8.9e-16


@dataclass(frozen=True)
class ReferenceState:
    """Reference integrals at one (d, delta_T): forces N, areas m^2, counts, limits m."""

    separation: float
    normal_force_stick: float
    normal_force_slip: float
    tangential_force_stick: float
    tangential_force_slip: float
    real_area_stick: float
    real_area_slip: float
    n_stick: float
    n_slip: float
    delta_1: float
    delta_2: float

    @property
    def normal_force(self) -> float:
        """F_z, N."""
        return self.normal_force_stick + self.normal_force_slip

    @property
    def tangential_force(self) -> float:
        """F_x, N."""
        return self.tangential_force_stick + self.tangential_force_slip

    @property
    def real_area(self) -> float:
        """A_r, m^2."""
        return self.real_area_stick + self.real_area_slip

    @property
    def n_contact(self) -> float:
        """Expected number of contacting asperities."""
        return self.n_stick + self.n_slip


class ReferenceModel:
    """Reference evaluation of the model for one material / roughness / nominal area."""

    def __init__(self, material: Material, roughness: Roughness, nominal_area: float) -> None:
        self.m = material
        self.r = roughness
        self.n_asp = roughness.asperity_density * nominal_area
        self.tabor = material_tabor_parameter(material, roughness, warn=False)
        # Wu's fit E:JKR_delta_min_loading, written out here (no shared code with the fast path)
        mu, eps = self.tabor, material.equilibrium_distance
        self.delta_load = (
            -2.641 * mu ** (3.0 / 7.0) * math.exp(-0.5 / math.sqrt(mu)) * eps if mu > 0 else 0.0
        )
        self.k2 = 2.0 * math.pi * material.work_of_adhesion / material.e_star

    # --- single asperity -------------------------------------------------------------------
    def fold(self, delta_t: float) -> tuple[float, float]:
        """(a'_min, delta_PC^min) in m by brentq on E:Instable_boundary; (inf, inf) if none."""
        R, k2 = self.r.summit_radius, self.k2
        c = 4.0 / 9.0 * self.m.mode_mixity * delta_t**2
        if k2 == 0.0:
            return (0.0, 0.0) if c == 0.0 else (math.inf, math.inf)
        q = (k2 * R / 4.0) ** 2
        lo = c / k2
        hi = lo + 2.0 * (q / k2) ** (1.0 / 3.0)
        a = brentq(lambda x: k2 * x**3 - c * x**2 - q, lo, hi, xtol=1e-300, rtol=_RTOL, maxiter=500)
        return a, a * a / R - math.sqrt(max(k2 * a - c, 0.0))

    def radius(self, delta: float, delta_t: float, fold: tuple[float, float]) -> float:
        """Stable root of E:PC_indent (m) by brentq."""
        R, k2 = self.r.summit_radius, self.k2
        c = 4.0 / 9.0 * self.m.mode_mixity * delta_t**2
        a_f, d_f = fold
        if delta <= d_f:
            return a_f

        def g(a: float) -> float:
            return a * a / R - math.sqrt(max(k2 * a - c, 0.0)) - delta

        hi = max(2.0 * a_f, math.sqrt(R * abs(delta)), 1e-300)
        while g(hi) <= 0.0:
            hi *= 2.0
        return brentq(g, a_f, hi, xtol=1e-300, rtol=_RTOL, maxiter=500)

    # --- integrals ---------------------------------------------------------------------------
    def state(self, d: float, delta_t: float, d_preload: float | None) -> ReferenceState:
        """Reference integrals at separation d (m) and delta_T (m); d_preload None = preload.

        E:NewFormulation_Fy/Fx/Ar with the limits E:delta_2 / E:delta_1 (E:Fy_Greenwood /
        E:Ar_Greenwood at the preload), summit heights cut at |z| = 12 sigma_s.
        """
        sigma = self.r.summit_height_rms
        fold = self.fold(delta_t)
        delta_1, delta_2 = self._limits(d, fold[1], d_preload)
        lo, hi = -CUTOFF_SIGMA * sigma - d, CUTOFF_SIGMA * sigma - d
        fz_st, fx_st, ar_st = self._stick_integrals(d, delta_t, fold, delta_2, lo, hi)
        fz_sl, fx_sl, ar_sl = self._slip_integrals(d, delta_2, lo, hi)
        n_stick = 0.0 if math.isinf(delta_2) else float(ndtr(-(d + delta_2) / sigma))
        n_all = float(ndtr(-(d + delta_1) / sigma))
        n = self.n_asp
        return ReferenceState(
            separation=d,
            normal_force_stick=n * fz_st,
            normal_force_slip=n * fz_sl,
            tangential_force_stick=n * fx_st,
            tangential_force_slip=n * fx_sl,
            real_area_stick=n * ar_st,
            real_area_slip=n * ar_sl,
            n_stick=n * n_stick,
            n_slip=n * max(n_all - n_stick, 0.0),
            delta_1=delta_1,
            delta_2=delta_2,
        )

    def _limits(self, d: float, delta_fold: float, d_preload: float | None) -> tuple[float, float]:
        """(delta_1, delta_2) in m at separation d (m), E:delta_1 / E:delta_2.

        delta_2 = max(d_min - d + delta_JKR^loading, delta_PC^min) with ``delta_fold`` =
        delta_PC^min (m); at the preload (``d_preload`` None) the history term is
        delta_JKR^loading alone. delta_1 = min(0, delta_2).
        """
        hist = self.delta_load if d_preload is None else d_preload - d + self.delta_load
        delta_2 = max(hist, delta_fold)
        return min(0.0, delta_2), delta_2

    def _density(self, z: float) -> float:
        """Gaussian summit-height density phi(z), 1/m, at height z (m)."""
        sigma = self.r.summit_height_rms
        norm = 1.0 / (math.sqrt(2.0 * math.pi) * sigma)
        return norm * math.exp(-0.5 * (z / sigma) ** 2)

    def _stick_integrals(
        self,
        d: float,
        delta_t: float,
        fold: tuple[float, float],
        delta_2: float,
        lo: float,
        hi: float,
    ) -> tuple[float, float, float]:
        """Per-asperity (F_z N, F_x N, A_r m^2) of the sticking population (E:PC_P, E:PC_T).

        Indentations delta in [max(delta_2, lo), hi] (m), written delta = delta_PC^min + s^2.
        """
        if not delta_2 < hi:
            return 0.0, 0.0, 0.0
        R, E = self.r.summit_radius, self.m.e_star
        lam, w = self.m.mode_mixity, self.m.work_of_adhesion
        phi = self._density
        d_f = fold[1]
        s0 = math.sqrt(max(max(delta_2, lo) - d_f, 0.0))
        s1 = math.sqrt(hi - d_f)
        cache: dict[float, float] = {}

        def a_of(s: float) -> float:
            if s not in cache:
                cache[s] = self.radius(d_f + s * s, delta_t, fold)
            return cache[s]

        def load(s: float) -> float:
            a = a_of(s)
            p = 4.0 * E * a**3 / (3.0 * R) - math.sqrt(
                max(
                    8.0 * math.pi * E * a**3 * w - 16.0 / 9.0 * lam * E**2 * a**2 * delta_t**2,
                    0.0,
                )
            )
            return p * phi(d + d_f + s * s) * 2.0 * s

        def tang(s: float) -> float:
            return 4.0 / 3.0 * E * a_of(s) * delta_t * phi(d + d_f + s * s) * 2.0 * s

        def area(s: float) -> float:
            return math.pi * a_of(s) ** 2 * phi(d + d_f + s * s) * 2.0 * s

        fz, fx, ar = (_integrate(f, s0, s1) for f in (load, tang, area))
        return fz, fx, ar

    def _slip_integrals(
        self, d: float, delta_2: float, lo: float, hi: float
    ) -> tuple[float, float, float]:
        """Per-asperity (F_z N, F_x N, A_r m^2) of the sliding population (E:Hertz_theory, tau0).

        Indentations delta in [max(0, lo), min(delta_2, hi)] (m), written delta = s^2.
        """
        if not delta_2 > 0.0:
            return 0.0, 0.0, 0.0
        d0, d1 = max(0.0, lo), min(delta_2, hi)
        if not d1 > d0:
            return 0.0, 0.0, 0.0
        R, E, phi = self.r.summit_radius, self.m.e_star, self._density
        s0, s1 = math.sqrt(d0), math.sqrt(d1)
        fz = _integrate(
            lambda s: 4.0 / 3.0 * E * math.sqrt(R) * s**3 * phi(d + s * s) * 2.0 * s, s0, s1
        )
        ar = _integrate(lambda s: math.pi * R * s * s * phi(d + s * s) * 2.0 * s, s0, s1)
        return fz, self.m.shear_strength * ar, ar

    # --- separations -------------------------------------------------------------------------
    def preload_separation(self, normal_load: float) -> float:
        """d_min (m) carrying ``normal_load`` (N) on the stable preload branch (brentq).

        Scans d downwards from 10 sigma_s (steps of sigma_s/4, doubling below -6 sigma_s) for the
        first place where F_z(d) - load turns from <= 0 to > 0, then refines with brentq.
        """
        sigma = self.r.summit_height_rms

        def f(x: float) -> float:
            return self.state(x, 0.0, None).normal_force - normal_load

        d_prev, f_prev = 10.0 * sigma, f(10.0 * sigma)
        step = 0.25 * sigma
        for _ in range(400):
            d = d_prev - step
            fd = f(d)
            if f_prev <= 0.0 < fd:
                return brentq(f, d, d_prev, xtol=1e-300, rtol=_RTOL, maxiter=500)
            d_prev, f_prev = d, fd
            if d < -6.0 * sigma:
                step *= 2.0
        raise ValueError(f"reference: no preload separation for {normal_load} N")

    def separation(
        self, normal_load: float, delta_t: float, d_preload: float, d_guess: float
    ) -> float:
        """d (m) with F_z(d, delta_T) = normal_load (N) after a preload at d_preload (brentq)."""
        sigma = self.r.summit_height_rms

        def f(x: float) -> float:
            return self.state(x, delta_t, d_preload).normal_force - normal_load

        f0 = f(d_guess)
        if f0 == 0.0:
            return d_guess
        step = 1e-4 * sigma * (1.0 if f0 > 0.0 else -1.0)
        a, fa = d_guess, f0
        for _ in range(200):
            b = a + step
            fb = f(b)
            if (fb > 0.0) != (fa > 0.0):
                lo, hi = (a, b) if a < b else (b, a)
                return brentq(f, lo, hi, xtol=1e-300, rtol=_RTOL, maxiter=500)
            a, fa = b, fb
            step *= 2.0
        raise ValueError(f"reference: no separation for {normal_load} N at delta_T = {delta_t}")

    def shear_states(
        self, normal_load: float, tangential_displacement: np.ndarray
    ) -> tuple[float, list[ReferenceState]]:
        """(d_min, states) of the load-controlled shear path at the given delta_T values (m)."""
        d_pre = self.preload_separation(normal_load)
        states = []
        d = d_pre
        for dt in np.asarray(tangential_displacement, dtype=float):
            d = self.separation(normal_load, float(dt), d_pre, d)
            states.append(self.state(d, float(dt), d_pre))
        return d_pre, states


def _integrate(f: Callable[[float], float], s0: float, s1: float) -> float:
    """int_s0^s1 f(s) ds by ``scipy.integrate.quad`` (epsabs 0, epsrel :data:`EPSREL`).

    QUADPACK may report that round-off stops it short of epsrel = 1e-13: the result is then
    accurate to round-off (~1e-13), far below the 1e-6 the fast path is held to.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IntegrationWarning)
        val, _ = quad(f, s0, s1, epsabs=0.0, epsrel=EPSREL, limit=LIMIT)
    return val
