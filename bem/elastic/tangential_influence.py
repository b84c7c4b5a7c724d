"""Tangential (Cerruti) influence of the elastic half-space: u_x from a traction q_x.

A rigid flat against an elastic half-space (E, nu; E* = E / (1 - nu^2)). Cerruti's surface
solution for a point force Q along x at the origin (Johnson 1985, eq. 3.86a, z = 0):

    u_x = Q (1 + nu) / (pi E rho) [(1 - nu) + nu x^2 / rho^2],
    u_y = Q (1 + nu) / (pi E rho) nu x y / rho^2,
    u_z = -Q (1 + nu)(1 - 2 nu) / (2 pi E) x / rho^2.

Scope, stated once for the whole shear package:

* Only nu = 1/2 (incompressible: elastomers, the paper's case, and E:PC_indent..E:PC_T assume it)
  is accepted. Then the Dundurs constant beta of the pair (rigid flat, incompressible body)
  vanishes, the u_z term above is zero and the normal and tangential problems are exactly
  uncoupled: a normal pressure gives no u_x and a tangential traction no u_z. For other nu the
  coupling ``(1 - 2 nu)`` would have to be solved for; the functions here refuse nu != 1/2
  (:func:`check_poisson`).
* With nu = 1/2 the point-force compliance is ``u_x = Q / (pi E*) (1/rho + x^2/rho^3)``: a
  Boussinesq term plus an anisotropic one. Its Fourier transform (2D, FT of 1/rho = 2 pi/q,
  of x_i x_j / rho^3 = 2 pi (delta_ij / q - q_i q_j / q^3)) is the multiplier

      K_xx(q) = (2 / (E* |q|)) (1 + q_y^2 / |q|^2) = (2 / (E* |q|)) (2 - q_x^2 / |q|^2).

* The shear solvers of this package load along x only: q_y = 0 and the stick condition acts on
  u_x. The cross term u_y = Q/(pi E*) x y / rho^3 (nu = 1/2) is not enforced, as in
  Cattaneo-Mindlin's solution (Johnson 1985, section 7.2), where it vanishes in the stick zone of
  a circular contact anyway.

Two operators, as :mod:`asperity.bem.elastic.influence` for the normal problem (compliances in m/Pa
in the
DFT sense, ``u_x = irfft2(K * rfft2(q))``):

``periodic``
    The point-force multiplier K_xx sampled on the DFT wavevectors, zero at q = 0 (the mean
    tangential surface displacement is the reference, as the mean deflection in the normal case).
``free`` (non-periodic)
    The exact u_x of a uniform x-traction on a dx x dy rectangle, at the pixel-centre offsets,
    laid out with wrap-around on the zero-padded doubled grid (Hockney): tractions confined to the
    original block give the free-space displacements there, without periodic images.
    The patch integral: ``iint dA / rho`` is Love's (``x asinh(y/|x|) + y asinh(x/|y|)``) and
    ``iint x^2/rho^3 dA`` has the antiderivative ``y asinh(x/|y|)`` (its mixed derivative is
    ``1/rho - y^2/rho^3 = x^2/rho^3``), so

        u_x = (1 / (pi E*)) [F(x + a, y + b) - F(x + a, y - b) - F(x - a, y + b) + F(x - a, y - b)],
        F(x, y) = x asinh(y/|x|) + 2 y asinh(x/|y|),   a = dx/2, b = dy/2.

The energy factor chi_T of the mixed-mode criterion (:func:`tangential_chi`) is half the element
average of this patch displacement (E* = 1); see its docstring for the derivation.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.bem.elastic.influence import love_patch_deflection
from asperity.bem.elastic.pohrt_popov import pohrt_popov_chi
from asperity.bem.errors import BemInputError

__all__ = [
    "cerruti_patch_displacement",
    "check_poisson",
    "padded_cerruti_multiplier",
    "periodic_cerruti_multiplier",
    "tangential_chi",
    "tangential_multiplier",
]


def check_poisson(poisson_ratio: float) -> None:
    """Refuse any Poisson ratio but 1/2: only there are normal and tangential problems uncoupled.

    Raises
    ------
    BemInputError
        When ``poisson_ratio != 0.5``; the message names the neglected coupling.
    """
    if poisson_ratio != 0.5:
        raise BemInputError(
            "poisson_ratio: the shear solver needs nu = 0.5 (incompressible body against a rigid "
            "flat, Dundurs beta = 0: normal and tangential problems uncoupled), got "
            f"{poisson_ratio}; for nu != 0.5 the coupling u_z ~ (1 - 2 nu) q_x is not modelled"
        )


def _check(nx: int, ny: int, dx: float, dy: float, e_star: float) -> None:
    if nx < 1 or ny < 1:
        raise BemInputError(f"tangential kernel: grid must be at least 1 x 1, got {nx} x {ny}")
    for name, val in (("dx", dx), ("dy", dy), ("e_star", e_star)):
        if not (np.isfinite(val) and val > 0):
            raise BemInputError(
                f"tangential kernel: {name} must be a positive finite number, got {val}"
            )


def periodic_cerruti_multiplier(
    nx: int, ny: int, dx: float, dy: float, e_star: float
) -> np.ndarray:
    """Periodic point-force multiplier ``(2 / (E* q)) (1 + q_y^2 / q^2)`` (m/Pa), 0 at q = 0.

    Parameters
    ----------
    nx, ny : int
        Grid size (pixels) along x (axis 0) and y (axis 1).
    dx, dy, e_star : float
        Pixel sizes (m) and the reduced modulus E* (Pa), nu = 1/2.

    Returns
    -------
    ndarray, shape (nx, ny // 2 + 1)
        Multiplier for ``rfft2`` spectra of x-tractions (Pa) giving u_x (m).
    """
    _check(nx, ny, dx, dy, e_star)
    qx = 2.0 * np.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2.0 * np.pi * np.fft.rfftfreq(ny, d=dy)
    qy2 = np.broadcast_to(qy[None, :] ** 2, (nx, qy.size))
    q2 = qx[:, None] ** 2 + qy2
    out = np.zeros_like(q2)
    pos = q2 > 0
    out[pos] = 2.0 / (e_star * np.sqrt(q2[pos])) * (1.0 + qy2[pos] / q2[pos])
    return out


def _asinh_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """``asinh(num / |den|)``, 0 where den = 0."""
    aden = np.abs(den)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(aden > 0, np.arcsinh(num / np.where(aden > 0, aden, 1.0)), 0.0)


def _extra_antiderivative(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Antiderivative ``y asinh(x/|y|)`` of x^2/rho^3 (0 on y = 0, its limit)."""
    return y * _asinh_ratio(x, y)


def cerruti_patch_displacement(
    x: np.ndarray, y: np.ndarray, dx: float, dy: float, e_star: float
) -> np.ndarray:
    """u_x (m) at ``(x, y)`` (m) under a unit x-traction (1 Pa) on ``|x| <= dx/2, |y| <= dy/2``.

    nu = 1/2: ``u_x = 1/(pi E*) iint (1/rho + x^2/rho^3) dA`` (module docstring). At the centre of
    a square patch ``u_x = 1.5 x 1.1222 dx / E*`` (the anisotropic term is half the Love term
    there, by the x <-> y symmetry of the square).

    Parameters
    ----------
    x, y : array_like
        Field points (m) relative to the patch centre.
    dx, dy : float
        Patch sides (m) along x and y.
    e_star : float
        Reduced modulus E* (Pa).
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    a, b = 0.5 * dx, 0.5 * dy
    f = _extra_antiderivative
    extra = f(x + a, y + b) - f(x + a, y - b) - f(x - a, y + b) + f(x - a, y - b)
    return love_patch_deflection(x, y, dx, dy, e_star) + extra / (np.pi * e_star)


def padded_cerruti_multiplier(nx: int, ny: int, dx: float, dy: float, e_star: float) -> np.ndarray:
    """Multiplier (m/Pa) on the doubled grid ``(2 nx, 2 ny)`` for a free (non-periodic) domain.

    Returns
    -------
    ndarray, shape (2 nx, ny + 1)
        ``rfft2`` multiplier of the wrap-around layout of the patch displacements at offsets
        ``-(n-1) .. (n-1)`` pixels: exact free-space u_x on the original block.
    """
    _check(nx, ny, dx, dy, e_star)
    mx, my = 2 * nx, 2 * ny
    ox = np.where(np.arange(mx) < nx, np.arange(mx), np.arange(mx) - mx) * dx
    oy = np.where(np.arange(my) < ny, np.arange(my), np.arange(my) - my) * dy
    coeff = cerruti_patch_displacement(ox[:, None], oy[None, :], dx, dy, e_star)
    return np.fft.rfft2(coeff).real.copy()


def tangential_multiplier(
    shape: tuple[int, int], dx: float, dy: float, e_star: float, *, periodic: bool = True
) -> tuple[np.ndarray, tuple[int, int]]:
    """The u_x-from-q_x multiplier (m/Pa) and its FFT grid: ``shape`` when periodic, doubled
    when free (same layout as :func:`asperity.bem.elastic.influence.influence_multiplier`)."""
    nx, ny = int(shape[0]), int(shape[1])
    if periodic:
        return periodic_cerruti_multiplier(nx, ny, dx, dy, e_star), (nx, ny)
    return padded_cerruti_multiplier(nx, ny, dx, dy, e_star), (2 * nx, 2 * ny)


def tangential_chi(dx: float, dy: float) -> float:
    """Tangential analogue chi_T (m^3) of Pohrt-Popov's chi: ``q^2 chi_T / E*`` is the energy (J)
    released by removing a uniform x-traction q from one dx x dy element (nu = 1/2).

    Derivation. The energy stored by a traction q on an element S is ``(q/2) iint_S u_x dA``, with
    u_x the patch displacement above; for E* = 1 and q = 1 it is

        chi_T = 1/(2 pi) iint_S iint_S (1/rho + s^2/rho^3) dA dA',   s = x - x', rho = |r - r'|.

    The first part is Pohrt-Popov's chi (``1/(2 pi) iint iint 1/rho``). For the second, with
    s in (-dx, dx), t in (-dy, dy) and the overlap weight (dx - |s|)(dy - |t|) of two copies of S,

        I_x = 4 int_0^dx int_0^dy s^2 (s^2 + t^2)^(-3/2) (dx - s)(dy - t) dt ds.

    The inner integral is ``sqrt(s^2 + dy^2) - s`` (by ``int s^2 (s^2+t^2)^(-3/2) dt =
    t/sqrt(s^2+t^2)`` and ``int s^2 t (s^2+t^2)^(-3/2) dt = -s^2/sqrt(s^2+t^2)``); the outer one
    (``int sqrt(s^2+b^2) ds = s D/2 + b^2/2 asinh(s/b)``, ``int s sqrt(s^2+b^2) ds = D^3/3``) gives

        I_x = 2/3 (dx^2 D - dx^3) + 4/3 (dy^3 - dy^2 D) + 2 dx dy^2 asinh(dx/dy),
        D = sqrt(dx^2 + dy^2),   chi_T = chi + I_x / (2 pi).

    Checks: I_x + I_y (dx <-> dy) equals 2 pi chi (the x^2 + y^2 terms add to 1/rho); for a square
    element ``chi_T = 1.5 chi = 0.709802 dx^3``. ``tests/bem/test_bem_shear_kernels.py`` checks it
    against the element-averaged FFT patch displacement of a subdivided element.

    Parameters
    ----------
    dx, dy : float
        Element sides (m) along x (the traction direction) and y.

    Returns
    -------
    float
        chi_T (m^3).
    """
    chi = pohrt_popov_chi(dx, dy)  # validates dx, dy
    d = math.hypot(dx, dy)
    i_x = (
        2.0 / 3.0 * (dx * dx * d - dx**3)
        + 4.0 / 3.0 * (dy**3 - dy * dy * d)
        + 2.0 * dx * dy * dy * math.asinh(dx / dy)
    )
    return chi + i_x / (2.0 * math.pi)
