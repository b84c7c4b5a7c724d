"""Greenwood-type rough contact with Maugis-Dugdale asperities: the BEM's own adhesion law.

The statistical model of Sections 2-3 with the JKR asperity (E:JKR_indent, E:JKR_load) replaced
by the Maugis-Dugdale sphere (:mod:`asperity.statmodel.maugis_dugdale`) at the range h_0 and
cohesive stress sigma_0 = w / h_0 of the Maugis-Dugdale BEM (``bem.solve_contact(...,
adhesion="maugis", adhesion_range=h_0)``: p = q - sigma_0 [gap <= h_0]). As E:Fy_Greenwood and
E:Ar_Greenwood, with Gaussian summit heights phi (standard deviation sigma_s), density eta,
common radius R and nominal area A_n, at the separation d between the flat and the mean summit
plane (approach delta = z - d of a summit at height z):

    F_z(d) = eta A_n int P_MD(delta) phi(d + delta) d delta,
    A_r(d) = eta A_n int pi a_MD^2(delta) phi(d + delta) d delta,

and the same law summed over an explicit list of summit heights (:func:`maugis_discrete_contact`).

The single asperity (Maugis 1992 in Johnson & Greenwood's notation, K = 4 E*/3; lengths in
l = (pi w R^2 / K)^(1/3), approaches in l^2 / R, forces in pi w R, Maugis parameter
lambda = 2 sigma_0 (R / (pi w K^2))^(1/3), so that h_0 = 2 / (pi lambda) in approach units):

* out of range, delta < -h_0: nothing.
* in range, out of contact (a = 0): the tension sigma_0 on the disc r < c where the gap is at
  most h_0, the sphere deformed by it (the centre lifted by 2 sigma_0 c / E*, the disc edge by
  4 sigma_0 c / (pi E*)). With C = c / l:

      Delta = C^2 / 2 - 8 lambda C / (3 pi) - 2 / (pi lambda),   P = -pi lambda C^2 / 2,

  valid while the apex gap -Delta - 4 lambda C / 3 is >= 0. Without the deformation terms this
  is the rigid-sphere Dugdale force F = -2 pi R sigma_0 (h_0 - s) at apex gap s; it joins the
  closed form's a -> 0 limit (m -> infinity with c = m a finite: (i) becomes
  pi lambda C^2 / 4 + 4 lambda^2 (pi / 2 - 1) C / 3 = 1, (ii) P = -pi lambda C^2 / 2,
  (iii) Delta = -4 lambda C / 3) exactly where the apex gap closes. This deformed form is what
  is used; the rigid-sphere force is weaker by the terms in lambda C: on the default job
  (lambda = 0.024) by 0.6 % at s = 0.1 h_0, 0.8 % at h_0 / 2, 6 % at 0.99 h_0.
* in contact (a > 0): the closed form (i)-(iii), parametrised by theta = arccos(1 / m) in
  (0, pi / 2] (theta = pi / 2 at first contact, theta -> 0 as a -> infinity), where (i) is a
  quadratic in c / l with coefficients smooth in theta, so every quantity and its derivative is
  explicit: no root is solved at the quadrature nodes.

The loading branch is the one the BEM follows, its attractive set only growing: along the path
(C from 0 to first contact, then a from 0 up) the state reached on approach is where Delta is at
its running maximum; where Delta(path) folds back the asperity jumps forward to the next state at
the same Delta (jump-in). On the DMT side (lambda 0.024 and 0.30 checked; the BEM's auto ranges
give 0.02-0.07 at the effective resolution) the only fold is at the edge of the range: at
Delta = -h_0 the tension disc jumps from c = 0 to C = 16 lambda / (3 pi), a force of
pi lambda (8 lambda / (3 pi))^2 times the DMT force -2 pi w R (3e-5 of it at lambda = 0.024);
towards the JKR side (lambda = 3 checked) the branch instead jumps from the edge of the range
straight into contact, onto the rising part of the closed form. The JKR model
(:mod:`asperity.statmodel.preloading`) uses Wu's jump-in distance (E:JKR_delta_min_loading)
instead: the two loading branches agree for lambda -> infinity except for asperities within a
few nm of first contact (on the default job's statistics the areas agree to 6e-5 at h_0 = 5 nm,
lambda = 61).

Quadrature: each monotone piece of the loading branch within |z| <= cutoff_sigma sigma_s is cut into
``panels`` panels of equal width in delta, their ends mapped to the path parameter (the contact
piece by Newton's method on Delta(theta), started from a cubic Hermite interpolant of a table of the
piece built once per asperity and kept inside its bracket), and each panel integrated by
Gauss-Legendre (``nodes``) in the path parameter (C out of contact, theta in contact; w = 0: the
Hertz radius a), where the integrand is smooth (no square-root end point at first contact or at a
fold). The defaults (16 panels of 16 nodes, cut-off 10 sigma_s) agree with scipy.integrate.quad of
an independent integrand to 1.2e-11 relative in F_z and A_r
(tests/statmodel/test_statmodel_maugis_rough.py).

Separation solve (cost): the law is solved at many separations in one evaluation
(:meth:`MaugisAsperity.gaussian_integrals_many`: every separation's panels together, the same
nodes and inverse as the one-separation form, so the two agree to round-off), and the march
down from the non-adhesive separation (step 0.02 sigma_s) skips the march points where F_z(d)
is known to be monotone (:mod:`asperity.statmodel.maugis_march`): F_z(d) = n int P(z - d)
phi(z) dz is monotone wherever the window |z| <= cutoff_sigma sigma_s of approaches holds no
turning point of P (a jump, a join of pieces or an extremum:
:meth:`MaugisAsperity.force_turning_points`), and there the root the full march would bracket
is the only root of the whole run. On a sticky map (plu-1, opd-1 with PDMS) the full march
took 3000-13000 steps per load, the solve now 10-15 evaluations, and the results agree with
the full march of the one-separation form to round-off (1e-13;
tests/statmodel/test_statmodel_maugis_march.py, benchmarks/statmodel_maugis_speed.py).

SI units throughout: m, Pa, N, J/m^2, m^2, 1/m^2.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from asperity.errors import InputError
from asperity.quantities import quantity
from asperity.statmodel.integrals import gauss_legendre
from asperity.statmodel.maugis_dugdale import MaugisScales, maugis_parameter
from asperity.statmodel.maugis_march import first_crossing
from asperity.statmodel.options import check_nominal_area
from asperity.statmodel.parameters import Roughness, checked_number, is_positive, tabor_parameter

__all__ = [
    "AsperityLawRegime",
    "MaugisAsperity",
    "MaugisRoughResult",
    "adhesion_regime",
    "asperity_law_regime",
    "maugis_discrete_contact",
    "maugis_rough_contact",
    "maugis_rough_state",
]

#: Path kinds: in range but out of contact (parameter C = c / l), in contact (theta).
NONCONTACT, CONTACT = 0, 1
#: Most steps of the contact-piece inverse (safeguarded Newton from a tabulated start; from
#: step NEWTON_STEPS on it bisects, interval pi/2 -> below the spacing of doubles).
NEWTON_STEPS, INVERSE_STEPS = 20, 120
#: Points of the per-piece table of Delta(theta) that starts and brackets the inverse.
TABLE_POINTS = 400
EPS = float(np.finfo(float).eps)
#: Relative Newton step after which the inverse stops (the next would be below EPS).
NEWTON_LAST = 1e-9
#: Maugis parameters bounding the DMT and JKR sides (Johnson & Greenwood 1997's map).
DMT_SIDE, JKR_SIDE = 0.1, 5.0

_SIN_SERIES = tuple((-1.0) ** k / math.factorial(2 * k + 1) for k in range(1, 9))


def _sin_minus_x(x: np.ndarray) -> np.ndarray:
    """sin x - x without cancellation for small x (series below 0.5)."""
    out = np.sin(x) - x
    small = x < 0.5
    if np.any(small):
        xs = x[small]
        x2 = xs * xs
        term = xs * x2
        acc = np.zeros_like(xs)
        for coef in _SIN_SERIES:
            acc += coef * term
            term = term * x2
        out[small] = acc
    return out


def _contact_radius(t: np.ndarray, lam: float) -> tuple[np.ndarray, ...]:
    """(sin theta, cos theta, q = c / l, dq/dtheta) on the closed form (i) (dimensionless);
    see :func:`_contact_path`."""
    sn, cs = np.sin(t), np.cos(t)
    g1 = 0.5 * _sin_minus_x(2.0 * t) + 2.0 * t * sn * sn
    g2 = t * sn - 2.0 * np.sin(0.5 * t) ** 2
    alpha = 0.5 * lam * g1
    beta = 4.0 * lam * lam * g2 / 3.0
    q = 2.0 / (beta + np.sqrt(beta * beta + 4.0 * alpha))
    d_alpha = lam * t * np.sin(2.0 * t)  # dg1/dtheta = 2 theta sin 2 theta
    d_beta = 4.0 * lam * lam * t * cs / 3.0  # dg2/dtheta = theta cos theta
    dq = -(d_alpha * q * q + d_beta * q) / (2.0 * alpha * q + beta)
    return sn, cs, q, dq


def _contact_path(theta: np.ndarray, lam: float) -> tuple[np.ndarray, ...]:
    """The closed form in theta = arccos(1/m): (q = c/l, A, P, Delta, dDelta/dtheta).

    With v = 1/m = cos theta, (i) times v^2 reads lambda g1 q^2 / 2 + 4 lambda^2 g2 q / 3 = 1,
    g1 = v^2 [s + (m^2 - 2) arctan s] = sin theta cos theta - theta cos 2 theta and
    g2 = v [s arctan s - m + 1] = theta sin theta + cos theta - 1; then A = q cos theta,
    P = q^3 cos^3 theta - lambda q^2 (sin theta cos theta + theta) (ii),
    Delta = q^2 cos^2 theta - 4 lambda q sin theta / 3 (iii). Dimensionless.
    """
    t = np.asarray(theta, dtype=float)
    sn, cs, q, dq = _contact_radius(t, lam)
    a = q * cs
    p = a**3 - lam * q * q * (sn * cs + t)
    delta = a * a - 4.0 * lam * q * sn / 3.0
    d_delta = (
        2.0 * q * dq * cs * cs - q * q * np.sin(2.0 * t) - 4.0 * lam * (dq * sn + q * cs) / 3.0
    )
    return q, a, p, delta, d_delta


def _contact_force_slope(theta: np.ndarray, lam: float) -> np.ndarray:
    """dP/dtheta on the closed form (dimensionless): from (ii), with a = q cos theta,
    dP/dtheta = 3 a^2 (q' cos theta - q sin theta)
    - 2 lambda [q q' (sin theta cos theta + theta) + q^2 cos^2 theta]."""
    t = np.asarray(theta, dtype=float)
    sn, cs, q, dq = _contact_radius(t, lam)
    a = q * cs
    return 3.0 * a * a * (dq * cs - q * sn) - 2.0 * lam * (q * dq * (sn * cs + t) + q * q * cs * cs)


def _piece_grid(p_a: float, p_b: float) -> np.ndarray:
    """theta strictly between p_a > p_b >= 0 (descending), refined geometrically towards both
    ends (down to 1e-9 of the piece) and uniform between: where dP/dtheta is sampled."""
    s = np.concatenate(
        [
            np.geomspace(1e-9, 1.0, TABLE_POINTS),
            1.0 - np.geomspace(1e-9, 1.0, TABLE_POINTS),
            np.linspace(0.0, 1.0, 2 * TABLE_POINTS),
        ]
    )
    s = np.unique(s[(s > 0.0) & (s < 1.0)])[::-1]
    return p_b + s * (p_a - p_b)


@dataclass(frozen=True)
class _Piece:
    """A monotone piece of the loading branch: kind, path parameter at its start and end (C
    ascending out of contact, theta descending in contact) and Delta there (increasing)."""

    kind: int
    start: float
    end: float
    delta_start: float
    delta_end: float


@dataclass(frozen=True)
class MaugisAsperity(MaugisScales):
    """The Maugis-Dugdale sphere on its loading branch (the branch the BEM follows on approach).

    Parameters
    ----------
    radius : float
        Summit radius R, m.
    e_star : float
        Reduced modulus E*, Pa.
    work : float
        Work of adhesion w, J/m^2 (> 0; w = 0 is Hertz, see :func:`maugis_rough_state`).
    adhesion_range : float
        Dugdale range h_0, m (sigma_0 = w / h_0).
    """

    radius: float
    e_star: float
    work: float
    adhesion_range: float

    def __post_init__(self) -> None:
        for name in ("radius", "e_star", "work", "adhesion_range"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value)):
                raise InputError(f"MaugisAsperity.{name}: expected a finite number, got {value!r}")
            if not value > 0:
                raise InputError(f"MaugisAsperity.{name}: expected > 0 (SI), got {value!r}")
        object.__setattr__(self, "_tables", {})
        object.__setattr__(self, "_pieces", self._build_pieces())

    # --- scales (lam, length_scale, force_scale: MaugisScales) ---------------------------
    @property
    def approach_scale(self) -> float:
        """l^2 / R (m), the unit of the approach delta."""
        return self.length_scale**2 / self.radius

    @property
    def pieces(self) -> tuple[_Piece, ...]:
        """Monotone pieces of the loading branch, contiguous in Delta from -h_0 to infinity."""
        return self._pieces  # type: ignore[attr-defined]

    @property
    def first_contact_approach(self) -> float:
        """delta (m) at which the loading branch enters contact (a > 0)."""
        for piece in self.pieces:
            if piece.kind == CONTACT:
                return piece.delta_start * self.approach_scale
        raise AssertionError("the loading branch ends in contact")  # pragma: no cover

    # --- the path -------------------------------------------------------------------------
    def _noncontact(self, c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(P, Delta, dDelta/dC) out of contact at C = c / l (dimensionless)."""
        lam = self.lam
        kappa = 8.0 * lam / (3.0 * math.pi)
        delta = 0.5 * c * c - kappa * c - 2.0 / (math.pi * lam)
        return -0.5 * math.pi * lam * c * c, delta, c - kappa

    def _build_pieces(self) -> tuple[_Piece, ...]:
        lam = self.lam
        q0 = float(_contact_path(np.array([0.5 * math.pi]), lam)[0][0])  # c / l at first contact
        kappa = 8.0 * lam / (3.0 * math.pi)
        monotone: list[tuple[int, float, float, float, float]] = []

        def nc_delta(c: float) -> float:
            return float(self._noncontact(np.array([c]))[1][0])

        if kappa < q0:  # out of contact: decreasing on [0, kappa], increasing on [kappa, q0]
            monotone.append((NONCONTACT, kappa, q0, nc_delta(kappa), nc_delta(q0)))
        # in contact: the extrema of Delta(theta) on a grid refined towards both ends
        grid = np.unique(
            np.concatenate(
                [0.5 * math.pi * np.geomspace(1e-9, 1.0, 900), np.linspace(0, 0.5 * math.pi, 901)]
            )
        )[1:][::-1]  # descending theta: along the path

        def slope(t: float) -> float:
            return float(_contact_path(np.array([t]), lam)[4][0])

        def delta_at(t: float) -> float:
            return float(_contact_path(np.array([t]), lam)[3][0])

        sl = _contact_path(grid, lam)[4]
        nodes = [float(grid[0])]
        for i in np.nonzero(np.sign(sl[1:]) != np.sign(sl[:-1]))[0]:
            nodes.append(brentq(slope, grid[i + 1], grid[i], xtol=1e-15, rtol=1e-15))
        nodes.append(0.0)
        for t_a, t_b in zip(nodes[:-1], nodes[1:], strict=True):
            mid = 0.5 * (t_a + t_b) if t_b > 0 else 0.5 * t_a
            if slope(mid) < 0.0:  # Delta grows as theta falls: a piece the approach can follow
                d_b = math.inf if t_b == 0.0 else delta_at(t_b)
                monotone.append((CONTACT, t_a, t_b, delta_at(t_a), d_b))
        # the loading branch: where Delta is at its running maximum, from the edge of the range
        running = -2.0 / (math.pi * lam)
        pieces = []
        for kind, p_a, p_b, d_a, d_b in monotone:
            if d_b <= running:
                continue
            if d_a < running:
                p_a = float(self._inverse(kind, p_a, p_b, np.array([running]))[0])
            # contiguous in Delta: a piece starts where the branch before it ends (the two
            # closed forms meet at first contact to round-off, which is what this absorbs)
            pieces.append(_Piece(kind, p_a, p_b, running, d_b))
            running = d_b
        return tuple(pieces)

    def _inverse(self, kind: int, p_a: float, p_b: float, delta: np.ndarray) -> np.ndarray:
        """The path parameter at Delta on the monotone piece from p_a to p_b.

        Out of contact the quadratic's root; in contact theta by Newton's method on Delta(theta)
        (dDelta/dtheta is explicit), started by cubic Hermite interpolation of theta(Delta) in a
        table of the piece and kept inside the table's bracket (a step that leaves it bisects
        instead); a Newton step below NEWTON_LAST theta is the last (its error is of order its
        square: below the spacing of doubles).
        """
        lam = self.lam
        delta = np.asarray(delta, dtype=float)
        if kind == NONCONTACT:
            kappa = 8.0 * lam / (3.0 * math.pi)
            disc = kappa * kappa + 2.0 * (delta + 2.0 / (math.pi * lam))
            return np.clip(kappa + np.sqrt(np.maximum(disc, 0.0)), p_a, p_b)
        t_tab, d_tab, m_tab = self._table(p_a, p_b)
        i = np.clip(np.searchsorted(d_tab, delta, side="right") - 1, 0, t_tab.size - 2)
        big, small = t_tab[i], t_tab[i + 1]  # Delta(big) <= delta < Delta(small)
        width = d_tab[i + 1] - d_tab[i]
        finite = np.isfinite(width)
        width = np.where(finite, width, 1.0)
        u = np.clip((delta - d_tab[i]) / width, 0.0, 1.0)
        u2, u3 = u * u, u * u * u
        t = (
            (2.0 * u3 - 3.0 * u2 + 1.0) * big
            + (u3 - 2.0 * u2 + u) * width * m_tab[i]
            + (3.0 * u2 - 2.0 * u3) * small
            + (u3 - u2) * width * m_tab[i + 1]
        )
        linear = big + u * (small - big)
        t = np.where(finite & (t >= small) & (t <= big), t, np.where(finite, linear, 0.5 * big))
        for step in range(INVERSE_STEPS):
            _, _, _, d_t, slope = _contact_path(t, lam)
            above = d_t >= delta
            small = np.where(above, t, small)
            big = np.where(above, big, t)
            change = (d_t - delta) / np.minimum(slope, -1e-200)  # slope < 0 on the piece
            newton = t - change
            inside = (newton >= small) & (newton <= big)
            done = inside & (np.abs(change) <= NEWTON_LAST * t) | (big - small <= EPS * t)
            if step >= NEWTON_STEPS:
                inside &= done
            t = np.where(inside, newton, 0.5 * (small + big))
            if np.all(done):
                break
        out = np.where(delta <= d_tab[0], p_a, t)
        return np.where(delta >= d_tab[-1], np.where(np.isfinite(d_tab[-1]), p_b, out), out)

    def _table(self, p_a: float, p_b: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """theta (descending from p_a to p_b), Delta there (increasing) and dtheta/dDelta on a
        contact piece: points refined towards both ends, Delta(p_b = 0) = infinity."""
        key = (p_a, p_b)
        tables = self._tables  # type: ignore[attr-defined]
        if key not in tables:
            s = np.concatenate(
                [
                    np.geomspace(1e-12, 1.0, TABLE_POINTS),
                    1.0 - np.geomspace(1e-12, 1.0, TABLE_POINTS),
                    np.linspace(0.0, 1.0, TABLE_POINTS),
                ]
            )
            s = np.unique(np.clip(s, 0.0, 1.0))[::-1]  # 1 -> 0: p_a -> p_b
            theta = p_b + s * (p_a - p_b)
            theta[0], theta[-1] = p_a, p_b
            inner = _contact_path(theta[1:-1], self.lam)[3] if theta.size > 2 else np.array([])
            d_a = float(_contact_path(np.array([p_a]), self.lam)[3][0])
            d_b = math.inf if p_b == 0.0 else float(_contact_path(np.array([p_b]), self.lam)[3][0])
            values = np.concatenate([[d_a], inner, [d_b]])
            slope = np.full(theta.shape, -math.inf)  # dDelta/dtheta, infinite at theta = 0
            slope[theta > 0.0] = _contact_path(theta[theta > 0.0], self.lam)[4]
            keep = np.concatenate([[True], values[1:] > np.maximum.accumulate(values)[:-1]])
            # dtheta/dDelta, bounded where the piece starts at a fold (dDelta/dtheta = 0)
            tables[key] = (theta[keep], values[keep], 1.0 / np.minimum(slope[keep], -1e-200))
        return tables[key]

    def _evaluate(self, kind: int, p: np.ndarray) -> tuple[np.ndarray, ...]:
        """(P, A, |dDelta/dp|, Delta) at path parameters p of one kind (dimensionless)."""
        if kind == NONCONTACT:
            force, delta, slope = self._noncontact(p)
            return force, np.zeros_like(p), np.abs(slope), delta
        _, a, force, delta, slope = _contact_path(p, self.lam)
        return force, a, np.abs(slope), delta

    # --- the law -------------------------------------------------------------------------
    def loading_state(self, approach: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """Force F (N) and contact radius a (m) on the loading branch at the approach delta (m).

        delta < -h_0: no force; -h_0 <= delta below first contact: the Dugdale tension on the
        deformed sphere out of contact (a = 0); above: the Maugis-Dugdale closed form.
        """
        delta = np.asarray(approach, dtype=float) / self.approach_scale
        force = np.zeros(delta.shape)
        radius = np.zeros(delta.shape)
        for piece in self.pieces:
            sel = (delta >= piece.delta_start) & (delta < piece.delta_end)
            if np.any(sel):
                p = self._inverse(piece.kind, piece.start, piece.end, delta[sel])
                f, a, _, _ = self._evaluate(piece.kind, p)
                force[sel], radius[sel] = f, a
        return force * self.force_scale, radius * self.length_scale

    def gaussian_integrals(
        self, separation: float, sigma: float, cutoff: float, gl: tuple, panels: int
    ) -> tuple[float, float]:
        """Per-asperity int P phi d delta (N) and int pi a^2 phi d delta (m^2) at d (m) for
        Gaussian summit heights of standard deviation sigma (m) cut at cutoff * sigma."""
        ds = self.approach_scale
        lo = (-cutoff * sigma - separation) / ds
        hi = (cutoff * sigma - separation) / ds
        gl_x, gl_w = gl
        fz = ar = 0.0
        for piece in self.pieces:
            a, b = max(piece.delta_start, lo), min(piece.delta_end, hi)
            if not b > a:
                continue
            edges = self._inverse(piece.kind, piece.start, piece.end, np.linspace(a, b, panels + 1))
            half = 0.5 * (edges[1:] - edges[:-1])
            p = (0.5 * (edges[1:] + edges[:-1]))[:, None] + half[:, None] * gl_x[None, :]
            force, rad, slope, delta = self._evaluate(piece.kind, p)
            z = separation + delta * ds
            weight = np.abs(half)[:, None] * gl_w[None, :] * slope * np.exp(-0.5 * (z / sigma) ** 2)
            fz += float((weight * force).sum())
            ar += float((weight * rad * rad).sum())
        norm = ds / (math.sqrt(2.0 * math.pi) * sigma)
        return fz * norm * self.force_scale, ar * norm * math.pi * self.length_scale**2

    def gaussian_integrals_many(
        self, separations: ArrayLike, sigma: float, cutoff: float, gl: tuple, panels: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`gaussian_integrals` at many separations d (m) in one evaluation: per-asperity
        int P phi d delta (N) and int pi a^2 phi d delta (m^2), one entry per separation.

        The same panels, nodes and inverse as the one-separation form (the panels of every
        separation solved together), so the two agree to round-off.
        """
        d = np.atleast_1d(np.asarray(separations, dtype=float)).ravel()
        ds = self.approach_scale
        lo, hi = (-cutoff * sigma - d) / ds, (cutoff * sigma - d) / ds
        fz, ar = np.zeros(d.size), np.zeros(d.size)
        for piece in self.pieces:
            a = np.maximum(piece.delta_start, lo)
            b = np.minimum(piece.delta_end, hi)
            on = np.nonzero(b > a)[0]
            if on.size:
                f_on, a_on = self._piece_integrals(piece, d[on], a[on], b[on], sigma, gl, panels)
                fz[on] += f_on
                ar[on] += a_on
        norm = ds / (math.sqrt(2.0 * math.pi) * sigma)
        return fz * norm * self.force_scale, ar * norm * math.pi * self.length_scale**2

    def _piece_integrals(self, piece, d, a, b, sigma, gl, panels) -> tuple[np.ndarray, ...]:
        """Gauss-Legendre sums of P phi |dDelta/dp| and A^2 phi |dDelta/dp| over one piece
        between Delta = a and b (arrays, one per separation d in m; dimensionless otherwise),
        in panels of equal width in Delta, as :meth:`gaussian_integrals`."""
        gl_x, gl_w = gl
        width = (b - a) / panels
        grid = a[:, None] + width[:, None] * np.arange(panels + 1)[None, :]
        grid[:, -1] = b
        edges = self._inverse(piece.kind, piece.start, piece.end, grid.ravel()).reshape(grid.shape)
        half = 0.5 * (edges[:, 1:] - edges[:, :-1])
        p = (0.5 * (edges[:, 1:] + edges[:, :-1]))[..., None] + half[..., None] * gl_x
        force, rad, slope, delta = self._evaluate(piece.kind, p)
        z = d[:, None, None] + delta * self.approach_scale
        weight = np.abs(half)[..., None] * gl_w * slope * np.exp(-0.5 * (z / sigma) ** 2)
        return (weight * force).sum(axis=(1, 2)), (weight * rad * rad).sum(axis=(1, 2))

    def force_turning_points(self) -> tuple[tuple[float, float], ...]:
        """Intervals of the approach delta (m) holding every point where the force P(delta) of
        the loading branch jumps, joins two pieces or has an extremum; between them it is
        smooth and monotone. A join is an interval of zero width; an extremum inside a contact
        piece is bracketed by two points of a grid in theta on which dP/dtheta changes sign."""
        ds = self.approach_scale
        out = [(piece.delta_start * ds, piece.delta_start * ds) for piece in self.pieces]
        for piece in self.pieces:
            if piece.kind != CONTACT:
                continue  # out of contact P = -pi lambda C^2 / 2 falls as C grows
            theta = _piece_grid(piece.start, piece.end)
            slope = _contact_force_slope(theta, self.lam)
            delta = _contact_path(theta, self.lam)[3]
            for i in np.nonzero(np.sign(slope[1:]) != np.sign(slope[:-1]))[0]:
                out.append((float(delta[i]) * ds, float(delta[i + 1]) * ds))
        return tuple(sorted(out))


def _hertz_integrals(
    radius: float, e_star: float, separation: float, sigma: float, cutoff: float, gl, panels
) -> tuple[float, float]:
    """w = 0 (Greenwood-Williamson): per-asperity int P_Hertz phi and int pi a^2 phi (N, m^2),
    over the Hertz radius a = sqrt(R delta) in panels of equal width in delta."""
    lo = max(0.0, -cutoff * sigma - separation)
    hi = cutoff * sigma - separation
    if not hi > lo:
        return 0.0, 0.0
    gl_x, gl_w = gl
    edges = np.sqrt(radius * np.linspace(lo, hi, panels + 1))
    half = 0.5 * (edges[1:] - edges[:-1])
    a = (0.5 * (edges[1:] + edges[:-1]))[:, None] + half[:, None] * gl_x[None, :]
    z = separation + a * a / radius
    weight = half[:, None] * gl_w[None, :] * (2.0 * a / radius) * np.exp(-0.5 * (z / sigma) ** 2)
    norm = 1.0 / (math.sqrt(2.0 * math.pi) * sigma)
    fz = float((weight * a**3).sum()) * 4.0 * e_star / (3.0 * radius) * norm
    return fz, float((weight * a * a).sum()) * math.pi * norm


@dataclass(frozen=True)
class MaugisRoughResult:
    """Rough contact under the Maugis-Dugdale law, one entry per imposed load.

    Attributes
    ----------
    normal_load : ndarray
        Imposed F_z, N.
    real_area : ndarray
        A_r, m^2 (NaN where the solve failed).
    separation : ndarray
        d, m: flat to mean summit plane (Gaussian form) or to the height origin (discrete form).
    normal_force : ndarray
        F_z carried at that separation, N.
    n_contact : ndarray
        Asperities in contact (expected number for the Gaussian form).
    n_attracted : ndarray
        Asperities within the range h_0 (in contact or attracted out of contact).
    maugis_parameter : float
        lambda of the summits (dimensionless; nan for w = 0).
    success : ndarray of bool
        Whether each load's separation solve converged.
    status : ndarray of int
        0 converged; 1 the Brent solve hit ``max_iter``; 2 the load was not reached (no bracket).
    message : tuple of str
        One message per load.
    nit : ndarray of int
        Force evaluations per load.
    """

    normal_load: np.ndarray
    real_area: np.ndarray
    separation: np.ndarray
    normal_force: np.ndarray
    n_contact: np.ndarray
    n_attracted: np.ndarray
    maugis_parameter: float
    success: np.ndarray
    status: np.ndarray
    message: tuple[str, ...]
    nit: np.ndarray


#: ``MaugisRoughResult.status`` codes.
STATUS: dict[int, str] = {
    0: "converged",
    1: "separation solve did not converge within max_iter",
    2: "load not reached: no separation carries it on the loading branch",
}


def _positive(name: str, value: object) -> float:
    return checked_number(
        value,
        is_positive,
        f"{name}: expected a positive number (SI), got {value!r}",
        f"{name}: expected a positive finite number (SI), got {value!r}",
    )


def _loads(normal_loads: ArrayLike) -> np.ndarray:
    loads = np.atleast_1d(np.asarray(normal_loads, dtype=float)).ravel()
    bad = ~(np.isfinite(loads) & (loads > 0))
    if loads.size == 0 or np.any(bad):
        raise InputError(
            "normal_loads: expected compressive loads > 0 N (the loading branch from the "
            f"non-adhesive state), got {np.asarray(normal_loads).tolist()!r}"
        )
    return loads


class _Law:
    """F_z(d), A_r(d) and the counts for one surface description (Gaussian or discrete)."""

    def __init__(self, radius, e_star, work, h0, heights=None, sigma=None, n_asp=1.0, knobs=None):
        self.radius, self.e_star, self.work, self.h0 = radius, e_star, work, h0
        self.heights, self.sigma, self.n_asp = heights, sigma, n_asp
        knobs = knobs or {}
        self.gl = gauss_legendre(int(knobs.get("nodes", 16)))
        self.panels = int(knobs.get("panels", 16))
        self.cutoff = float(knobs.get("cutoff_sigma", 10.0))
        self.asperity = MaugisAsperity(radius, e_star, work, h0) if work > 0 else None
        self._seen: dict[float, tuple[float, float, float, float]] = {}
        #: :meth:`monotone_separations`, kept once computed (a function of the law alone).
        self.monotone: list[tuple[float, float]] | None = None

    def state(self, d: float) -> tuple[float, float, float, float]:
        """(F_z N, A_r m^2, n_contact, n_attracted) at separation d (m), each separation
        evaluated once (the bracket ends and the root come back to the solver)."""
        d = float(d)
        if d not in self._seen:
            self._seen[d] = self._state(d) if self.heights is not None else self._batch([d])[0]
        return self._seen[d]

    def forces(self, separations: np.ndarray) -> np.ndarray:
        """F_z (N) at many separations (m) at once (Gaussian form), each kept for
        :meth:`state`."""
        d = np.asarray(separations, dtype=float)
        new = [float(x) for x in d if float(x) not in self._seen]
        if new:
            self._seen.update(zip(new, self._batch(new), strict=True))
        return np.array([self._seen[float(x)][0] for x in d])

    def _batch(self, separations: list[float]) -> list[tuple[float, float, float, float]]:
        """:meth:`state` of the Gaussian form at many separations (m), in one evaluation."""
        d = np.asarray(separations, dtype=float)
        if self.asperity is None:
            fa = [
                _hertz_integrals(
                    self.radius, self.e_star, x, self.sigma, self.cutoff, self.gl, self.panels
                )
                for x in d
            ]
            fz, ar = (np.array(col) for col in zip(*fa, strict=True))
            first = reach = 0.0
        else:
            quadrature = (self.sigma, self.cutoff, self.gl, self.panels)
            if d.size == 1:  # the one-separation form: the same sums, less overhead
                fz, ar = (
                    np.array([x]) for x in self.asperity.gaussian_integrals(d[0], *quadrature)
                )
            else:
                fz, ar = self.asperity.gaussian_integrals_many(d, *quadrature)
            first, reach = self.asperity.first_contact_approach, -self.h0
        root2s = math.sqrt(2.0) * self.sigma
        nc = [0.5 * math.erfc((x + first) / root2s) for x in d]
        na = [0.5 * math.erfc((x + reach) / root2s) for x in d]
        n = self.n_asp
        return [
            (n * float(f), n * float(a), n * c, n * t)
            for f, a, c, t in zip(fz, ar, nc, na, strict=True)
        ]

    def _state(self, d: float) -> tuple[float, float, float, float]:
        """:meth:`state` of the discrete form: the law summed over the summit heights."""
        approach = self.heights - d
        if self.asperity is None:
            a = np.sqrt(self.radius * np.maximum(approach, 0.0))
            f = 4.0 * self.e_star * a**3 / (3.0 * self.radius)
        else:
            f, a = self.asperity.loading_state(approach)
        first = 0.0 if self.asperity is None else self.asperity.first_contact_approach
        reach = 0.0 if self.asperity is None else -self.h0
        return (
            float(np.sum(f)),
            float(np.sum(math.pi * a * a)),
            float(np.count_nonzero(approach > first)),
            float(np.count_nonzero(approach >= reach)),
        )

    def span(self) -> tuple[float, float]:
        """(d_low, d_high) (m): below d_low every summit is pressed well in, above d_high none
        is within reach."""
        if self.heights is not None:
            top, bottom = float(np.max(self.heights)), float(np.min(self.heights))
            return bottom - 1e3 * (top - bottom + self.radius), top + self.h0
        return -self.cutoff * self.sigma - 1e3 * self.sigma, self.cutoff * self.sigma + self.h0

    def step(self) -> float:
        """Marching step (m) of the bracket search: small against every feature of F_z(d)."""
        if self.heights is not None:
            gaps = np.diff(np.unique(self.heights))
            return min(self.h0, float(np.min(gaps)) if gaps.size else self.h0) / 16.0
        return 0.02 * self.sigma

    def monotone_separations(self) -> list[tuple[float, float]]:
        """Intervals of d (m) on which F_z(d) is monotone (Gaussian form with w > 0).

        F_z(d) = n int P(z - d) phi(z) dz over |z| <= cutoff sigma: where that window of
        approaches holds no turning point of P (:meth:`MaugisAsperity.force_turning_points`),
        dF_z/dd = -n int P'(z - d) phi(z) dz has one sign. Each turning point's window of d is
        widened by two march steps; the intervals are what lies between.
        """
        reach = self.cutoff * self.sigma + 2.0 * self.step()
        zones = sorted(
            (-hi - reach, -lo + reach) for lo, hi in self.asperity.force_turning_points()
        )
        merged: list[list[float]] = []
        for lo, hi in zones:
            if merged and lo <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], hi)
            else:
                merged.append([lo, hi])
        edges = [-math.inf] + [x for zone in merged for x in zone] + [math.inf]
        return [(edges[k], edges[k + 1]) for k in range(0, len(edges), 2)]


def _bracket(law: _Law, target: float, d0: float, d_low: float) -> tuple[float, float, int]:
    """(lower, upper, evaluations): the march step below d0 (m) where F_z first reaches the
    load (N), lower = upper = d0 when it already does there, NaN when never above d_low.

    Gaussian form: :func:`maugis_march.first_crossing`, the march points batched and the
    interior of the runs where F_z is monotone skipped (the same bracketed root as the full
    march). Discrete form: the march one point at a time.
    """
    h = law.step()
    if law.heights is None and law.asperity is not None:
        if law.monotone is None:
            law.monotone = law.monotone_separations()
        found = first_crossing(lambda d: law.forces(d) - target, d0, h, d_low, law.monotone)
        return found.lower, found.upper, found.evaluations
    upper, f_upper = d0, law.state(d0)[0] - target
    nit = 1
    while f_upper < 0.0 and nit < 100000:
        lower = upper - h
        f_lower = law.state(lower)[0] - target
        nit += 1
        if f_lower >= 0.0:
            return lower, upper, nit
        upper, f_upper = lower, f_lower
        if lower < d_low:
            break
    if f_upper >= 0.0:
        return upper, upper, nit
    return math.nan, math.nan, nit


def _solve_one(law: _Law, hertz: _Law, target: float, d_low: float, d_high: float, max_iter):
    """(d, F_z, A_r, n_contact, n_attracted, status, nit) of one load (N): from the
    non-adhesive separation d0 (m) at that load, the first d below it where F_z reaches it."""
    nan = math.nan
    if hertz.state(d_low)[0] < target:
        return (nan, nan, nan, nan, nan, 2, 0)
    d0 = brentq(lambda d, t=target: hertz.state(d)[0] - t, d_low, d_high, xtol=1e-15)
    lower, upper, nit = _bracket(law, target, d0, d_low)
    if math.isnan(lower):
        return (nan, nan, nan, nan, nan, 2, nit)
    d, ok = lower, True
    if lower < upper:
        d, info = brentq(
            lambda x, t=target: law.state(x)[0] - t,
            lower,
            upper,
            xtol=1e-15 * max(1.0, abs(d0)),
            rtol=1e-15,
            maxiter=max_iter,
            full_output=True,
            disp=False,
        )
        nit += info.function_calls
        ok = info.converged
    return (d, *law.state(d), 0 if ok else 1, nit)


def _solve_loads(law: _Law, loads: np.ndarray, max_iter: int, lam: float) -> MaugisRoughResult:
    """Separation of each load on the branch the BEM follows: from the non-adhesive (w = 0)
    separation at that load, the first d below it (largest) where F_z(d) reaches the load."""
    hertz = _Law(law.radius, law.e_star, 0.0, law.h0, law.heights, law.sigma, law.n_asp)
    hertz.gl, hertz.panels, hertz.cutoff = law.gl, law.panels, law.cutoff
    d_low, d_high = law.span()
    rows = [_solve_one(law, hertz, target, d_low, d_high, max_iter) for target in loads]
    sep, fz, ar, nc, na, status, nit = (np.array(col) for col in zip(*rows, strict=True))
    status = status.astype(int)
    return MaugisRoughResult(
        normal_load=loads,
        real_area=ar,
        separation=sep,
        normal_force=fz,
        n_contact=nc,
        n_attracted=na,
        maugis_parameter=lam,
        success=status == 0,
        status=status,
        message=tuple(STATUS[int(s)] for s in status),
        nit=nit.astype(int),
    )


def _material(e_star: float, work: float, h0: float) -> tuple[float, float, float]:
    e_star = quantity("material.E_star").check(e_star, "e_star")
    work = quantity("material.work_of_adhesion").check(work, "work_of_adhesion")
    h0 = _positive("adhesion_range", h0)
    return e_star, work, h0


def _lam(radius: float, e_star: float, work: float, h0: float) -> float:
    return maugis_parameter(work / h0, radius, work, e_star) if work > 0 else math.nan


def _knobs(knobs: dict) -> dict:
    allowed = {"nodes", "panels", "cutoff_sigma", "max_iter"}
    unknown = sorted(set(knobs) - allowed)
    if unknown:
        raise InputError(f"unknown accuracy knob(s) {unknown}; expected some of {sorted(allowed)}")
    for name, (lo, hi) in {"nodes": (1, 128), "panels": (1, 256), "max_iter": (1, 10000)}.items():
        if name in knobs and not (lo <= int(knobs[name]) <= hi and knobs[name] == int(knobs[name])):
            raise InputError(f"{name}: expected an integer in [{lo}, {hi}], got {knobs[name]!r}")
    if "cutoff_sigma" in knobs:
        quantity("accuracy.cutoff_sigma").check(knobs["cutoff_sigma"], "cutoff_sigma")
    return knobs


def maugis_rough_state(
    roughness: Roughness,
    e_star: float,
    work_of_adhesion: float,
    adhesion_range: float,
    nominal_area: float,
    separation: ArrayLike,
    **knobs: float,
) -> tuple[np.ndarray, np.ndarray]:
    """F_z (N) and A_r (m^2) at the separations d (m), E:Fy_Greenwood / E:Ar_Greenwood with the
    Maugis-Dugdale loading branch (attraction out of contact within h_0 included).

    Parameters as :func:`maugis_rough_contact`; ``separation`` in m (array or scalar).
    """
    law = _gaussian_law(
        roughness, e_star, work_of_adhesion, adhesion_range, nominal_area, _knobs(knobs)
    )
    d = np.asarray(separation, dtype=float)
    if law.asperity is not None:
        law.forces(d.ravel())  # every separation in one evaluation
    out = np.array([law.state(float(x))[:2] for x in d.ravel()]).reshape(d.shape + (2,))
    return out[..., 0], out[..., 1]


def _gaussian_law(roughness, e_star, work, h0, nominal_area, knobs) -> _Law:
    if not isinstance(roughness, Roughness):
        raise InputError(
            f"roughness: expected a statmodel.Roughness, got {type(roughness).__name__}"
        )
    e_star, work, h0 = _material(e_star, work, h0)
    area = check_nominal_area(roughness, nominal_area)
    return _Law(
        roughness.summit_radius,
        e_star,
        work,
        h0,
        sigma=roughness.summit_height_rms,
        n_asp=roughness.asperity_density * area,
        knobs=knobs,
    )


def maugis_rough_contact(
    roughness: Roughness,
    e_star: float,
    work_of_adhesion: float,
    adhesion_range: float,
    nominal_area: float,
    normal_loads: ArrayLike,
    **knobs: float,
) -> MaugisRoughResult:
    """Real contact area of Gaussian summits with Maugis-Dugdale asperities at given loads.

    The statistical model under the BEM's adhesion law (range h_0, sigma_0 = w / h_0): each
    summit follows the Maugis-Dugdale loading branch (see the module docstring), the attraction
    of summits within h_0 but out of contact counted in F_z; E:Fy_Greenwood and E:Ar_Greenwood
    with that law. Each load is carried at the largest separation below the non-adhesive one
    where F_z(d) reaches it: the state reached by letting the attraction act from the
    non-adhesive state, as the BEM does.

    Parameters
    ----------
    roughness : Roughness
        eta (1/m^2), R (m), sigma_s (m).
    e_star : float
        E*, Pa.
    work_of_adhesion : float
        w, J/m^2 (0: Greenwood-Williamson with Hertz asperities).
    adhesion_range : float
        h_0, m (> 0).
    nominal_area : float
        A_n, m^2.
    normal_loads : float or array
        Compressive loads F_z > 0, N.
    **knobs
        ``nodes`` (16), ``panels`` (16, per monotone piece of the branch), ``cutoff_sigma``
        (10), ``max_iter`` (200).

    Returns
    -------
    MaugisRoughResult
    """
    knobs = _knobs(knobs)
    law = _gaussian_law(roughness, e_star, work_of_adhesion, adhesion_range, nominal_area, knobs)
    return _solve_loads(
        law,
        _loads(normal_loads),
        int(knobs.get("max_iter", 200)),
        _lam(law.radius, law.e_star, law.work, law.h0),
    )


def maugis_discrete_contact(
    summit_heights: ArrayLike,
    summit_radius: float,
    e_star: float,
    work_of_adhesion: float,
    adhesion_range: float,
    normal_loads: ArrayLike,
    *,
    max_iter: int = 200,
) -> MaugisRoughResult:
    """The same law summed over explicit summit heights (no interaction between summits).

    F_z(d) = sum_i P_MD(z_i - d), A_r(d) = sum_i pi a_MD(z_i - d)^2: the exact answer for
    identical, non-interacting spherical caps (paraboloids of radius R) at heights z_i.

    Parameters
    ----------
    summit_heights : array
        z_i, m (any origin; ``separation`` of the result is measured from it).
    summit_radius : float
        R, m.
    e_star, work_of_adhesion, adhesion_range : float
        E* (Pa), w (J/m^2, 0: Hertz), h_0 (m).
    normal_loads : float or array
        Compressive loads > 0, N.
    max_iter : int
        Most Brent iterations per load.

    Returns
    -------
    MaugisRoughResult
        ``n_contact`` and ``n_attracted`` are counts of summits.
    """
    z = np.atleast_1d(np.asarray(summit_heights, dtype=float)).ravel()
    if z.size == 0 or not np.all(np.isfinite(z)):
        raise InputError(f"summit_heights: expected finite heights in m, got {summit_heights!r}")
    radius = quantity("roughness.summit_radius").check(summit_radius, "summit_radius")
    e_star, work, h0 = _material(e_star, work_of_adhesion, adhesion_range)
    law = _Law(radius, e_star, work, h0, heights=z)
    _knobs({"max_iter": max_iter})
    return _solve_loads(law, _loads(normal_loads), int(max_iter), _lam(radius, e_star, work, h0))


@dataclass(frozen=True)
class AsperityLawRegime:
    """The regime of the two asperity laws at one summit radius: where the BEM's
    Maugis-Dugdale law and the model's JKR law lie on Johnson & Greenwood's map (not the rough
    contact's adhesion regime, :class:`asperity.statmodel.regimes.AdhesionRegime`).

    Attributes
    ----------
    maugis_parameter : float
        lambda of the BEM's Maugis-Dugdale law (range h_0) at the summit radius.
    tabor_parameter : float
        mu of the statistical model's JKR law (equilibrium distance epsilon).
    cohesive_stress : float
        sigma_0 = w / h_0, Pa.
    statement : str
        What follows for the comparison and the predictions (one sentence).
    """

    maugis_parameter: float
    tabor_parameter: float
    cohesive_stress: float
    statement: str


def _side(lam: float) -> str:
    if lam < DMT_SIDE:
        return "DMT side"
    if lam > JKR_SIDE:
        return "JKR side"
    return "transition"


def asperity_law_regime(
    summit_radius: float,
    e_star: float,
    work_of_adhesion: float,
    adhesion_range: float,
    equilibrium_distance: float = 0.2e-9,
) -> AsperityLawRegime:
    """The BEM's Maugis parameter at a summit radius beside the model's Tabor parameter.

    lambda = 2 sigma_0 (R / (pi w K^2))^(1/3), K = 4 E*/3, sigma_0 = w / h_0 (the BEM's law);
    mu = (R w^2 / (E*^2 epsilon^3))^(1/3) (the JKR model's, paper Section 2). SI units.
    Johnson & Greenwood's map: DMT side for lambda < 0.1, JKR side above 5 (1.16 mu ~ lambda
    for a Lennard-Jones range).
    """
    radius = quantity("roughness.summit_radius").check(summit_radius, "summit_radius")
    e_star, work, h0 = _material(e_star, work_of_adhesion, adhesion_range)
    if not work > 0:
        raise InputError("work_of_adhesion: expected > 0 J/m^2 for an adhesion regime, got 0")
    lam = maugis_parameter(work / h0, radius, work, e_star)
    mu = tabor_parameter(radius, work, e_star, equilibrium_distance, warn=False)
    asp = MaugisAsperity(radius, e_star, work, h0)
    dmt = 2.0 * asp.force_scale
    statement = (
        f"At R = {radius:.4g} m the BEM's Maugis-Dugdale law (h_0 = {h0:.3g} m) has lambda = "
        f"{lam:.3g} ({_side(lam)}) while the JKR model has Tabor mu = {mu:.4g} "
        f"({_side(1.16 * mu)}): the adhesive BEM can only show the area gain of its own law, "
        "the like-for-like partner is the Maugis-Dugdale model at the same h_0, and the JKR "
        "model's larger adhesive gain (a short-range law the grid cannot resolve) is a "
        "prediction that no BEM at this range checks"
        if _side(lam) != _side(1.16 * mu)
        else f"At R = {radius:.4g} m the BEM's law has lambda = {lam:.3g} and the JKR model "
        f"mu = {mu:.4g}, both on the {_side(lam)}: the JKR model and the BEM share the regime "
        f"(pull-off per summit {dmt:.3g} N at most)"
    )
    return AsperityLawRegime(lam, mu, work / h0, statement)


def adhesion_regime(*args: Any, **kwargs: Any) -> AsperityLawRegime:
    """Deprecated name of :func:`asperity_law_regime` (asperity 0.4; removed in 0.6): one
    ``adhesion_regime`` per meaning, :func:`asperity.statmodel.regimes.adhesion_regime`."""
    warnings.warn(
        "asperity.statmodel.maugis_rough.adhesion_regime is now asperity_law_regime "
        "(statmodel.adhesion_regime is the rough contact's regime)",
        DeprecationWarning,
        stacklevel=2,
    )
    return asperity_law_regime(*args, **kwargs)
