"""Polonsky-Keer on any array library: the periodic non-adhesive solve on a GPU (CuPy) or NumPy.

The same problem as :func:`asperity.bem.solve_contact` with its defaults (periodic domain, the
point-force kernel ``2/(E*|q|)``, no adhesion, load control, preconditioned conjugate
gradients), written once against an array namespace ``xp``: ``numpy`` (tests, any machine) or
``cupy`` (an NVIDIA GPU, the optional path past the CPU's memory and speed; CuPy is never a
dependency of asperity). It is a second, deliberately plain implementation of eqs.
E:BEM_eq1..E:BEM_eq4 (Polonsky & Keer 1999, with the stiffness preconditioner of Vollebregt
2014), not the CPU solver's fused numba kernels: the tests hold it to that solver on the same
maps.

One iteration, on the contact set Omega_c (p > 0):

1. gap statistics: w = u - h, its mean on Omega_c (the rigid-body term of E:BEM_eq1), the
   residual g = w - mean;
2. direction: z = K^-1 g on Omega_c (stiffness E*|q|/2, one convolution), made mean-free on
   Omega_c; t = z + beta t (beta = 0 after the contact set changed);
3. step: r = K t (one convolution), tau = sum g t / sum r t, p -= tau t; elements at or below
   zero leave (p = 0), elements outside with g < 0 enter with p = 0 (the contact set is an
   explicit mask, as the CPU solver's);
4. load: p scaled to the imposed mean pressure (E:BEM_eq4); u follows linearly (u -= tau r,
   then the same scale) unless the contact set changed, when u = K p is recomputed.

The convergence residual is :func:`asperity.bem.solve_contact`'s (``tol``): the rms violation of
g = 0 in contact and g >= 0 outside, times the pixel stiffness E*/sqrt(dx dy), over the rms
pressure. Memory on the device: about 8 float64 map-sized arrays (64 B per element) plus the
FFT's half spectrum and the library's plan workspace.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any, TypeAlias

import numpy as np

from asperity.bem.errors import BemInputError
from asperity.bem.result import ContactResult, SolverStatus

__all__ = ["array_module", "solve_periodic_array"]

#: Recompute u = K p from scratch every this many iterations (bounds the round-off drift of the
#: linear update u -= tau r).
REFRESH = 50

#: An array of the chosen library: a ``numpy.ndarray`` or a ``cupy.ndarray`` (CuPy ships no
#: type information, so the type checker sees Any).
DeviceArray: TypeAlias = Any


def array_module(name: str) -> ModuleType:
    """The array namespace called ``name``: ``"numpy"`` or ``"cupy"`` (imported on demand).

    Raises
    ------
    BemInputError
        An unknown name, or ``"cupy"`` when CuPy or a GPU is not available (the message says
        which).
    """
    if name == "numpy":
        return np
    if name != "cupy":
        raise BemInputError(f"array library: expected 'numpy' or 'cupy', got {name!r}")
    try:
        import cupy  # deferred: optional, never a dependency of asperity
    except ImportError as exc:
        raise BemInputError(
            f"array library 'cupy': CuPy is not installed ({exc}); the GPU path is optional, "
            "use 'numpy' or asperity.bem.solve_contact"
        ) from None
    try:
        cupy.cuda.runtime.getDeviceCount()
    except Exception as exc:  # noqa: BLE001 - CUDA reports a missing driver/device in many types
        raise BemInputError(f"array library 'cupy': no usable GPU ({exc})") from None
    return cupy


def _to_host(xp: ModuleType, a: DeviceArray) -> np.ndarray:
    """A device array copied to a NumPy array (a no-op for NumPy)."""
    return a if xp is np else xp.asnumpy(a)


def _multipliers(xp: ModuleType, shape: tuple[int, int], dx: float, dy: float, e_star: float):
    """The rfft2 compliance 2/(E*|q|) (m/Pa, zero at q = 0) and stiffness E*|q|/2 (Pa/m)."""
    nx, ny = shape
    qx = 2.0 * np.pi * xp.fft.fftfreq(nx, d=dx)
    qy = 2.0 * np.pi * xp.fft.rfftfreq(ny, d=dy)
    q = xp.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
    stiffness = 0.5 * e_star * q
    compliance = xp.zeros_like(q)
    nonzero = q > 0
    compliance[nonzero] = 2.0 / (e_star * q[nonzero])
    return compliance, stiffness


def _check_input(heights: np.ndarray, dx: float, dy: float, e_star: float, load: float) -> None:
    """Refuse what the solve cannot mean (names the argument, the expected and the found)."""
    if np.ndim(heights) != 2 or min(np.shape(heights)) < 2:
        raise BemInputError(f"heights: expected a 2-D map of at least 2x2, got {np.shape(heights)}")
    for name, value in (("dx", dx), ("dy", dy), ("e_star", e_star), ("normal_force", load)):
        if not (np.isfinite(value) and value > 0):
            raise BemInputError(f"{name}: expected a finite value > 0, got {value!r}")


@dataclass
class _ArrayState:
    """The iteration's state: pressure p (Pa), deflection u (m), search direction t, contact
    mask, the previous ``s . z`` (conjugacy), whether conjugacy is on and whether the contact
    set changed in the last step."""

    p: DeviceArray
    u: DeviceArray
    t: DeviceArray
    mask: DeviceArray
    previous: float = 1.0
    beta_on: bool = False
    changed: bool = True


@dataclass
class _ArrayIteration:
    """Polonsky-Keer on an array library ``mod``: heights h (m), the compliance and stiffness
    multipliers in Fourier space, the total load as ``mean pressure x pixels`` (Pa)."""

    mod: ModuleType
    h: DeviceArray
    compliance: DeviceArray
    stiffness: DeviceArray
    total: float
    convolutions: int = 0

    def convolve(self, field, multiplier):
        """One real-FFT convolution (counted)."""
        self.convolutions += 1
        shape = self.h.shape
        return self.mod.fft.irfft2(multiplier * self.mod.fft.rfft2(field), s=shape)

    def start(self, mean_pressure: float) -> _ArrayState:
        """The uniform pressure (Pa) and its deflection."""
        p = self.mod.full(self.h.shape, mean_pressure, dtype=self.mod.float64)
        return _ArrayState(p, self.convolve(p, self.compliance), self.mod.zeros_like(p), p > 0)

    def gap(self, state: _ArrayState):
        """The gap g = u - h less its mean on the contact (m)."""
        w = state.u - self.h
        return w - float((w * state.mask).sum()) / int(state.mask.sum())

    def step(self, state: _ArrayState, g, nit: int) -> None:
        """One constrained conjugate-gradient step: direction, step length, projection on
        p >= 0, the contact set's update and the load's rescaling (E:BEM_eq2..E:BEM_eq4)."""
        mod, mask = self.mod, state.mask
        n_contact = int(mask.sum())
        s = mod.where(mask, g, 0.0)
        z = self.convolve(s, self.stiffness)
        z = mod.where(mask, z - float((z * mask).sum()) / n_contact, 0.0)
        current = float((s * z).sum())
        beta = current / state.previous if state.beta_on else 0.0
        state.t = mod.where(mask, z + beta * state.t, 0.0)
        state.previous = current
        r = self.convolve(state.t, self.compliance)
        r_mean = float((r * mask).sum()) / n_contact
        tau = float((s * state.t).sum()) / float((state.t * (r - r_mean)).sum())
        state.p -= tau * state.t
        entered = (~mask) & (g < 0)
        left = mask & (state.p <= 0)
        state.changed = bool(left.any()) or bool(entered.any())
        mod.maximum(state.p, 0.0, out=state.p)
        state.mask = (mask & ~left) | entered
        scale = self.total / float(state.p.sum())
        state.p *= scale
        if state.changed or nit % REFRESH == REFRESH - 1:
            state.u = self.convolve(state.p, self.compliance)
        else:
            state.u = (state.u - tau * r) * scale
        state.beta_on = not state.changed


def solve_periodic_array(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    normal_force: float,
    *,
    xp: str = "numpy",
    tol: float = 1e-6,
    max_iter: int = 1000,
) -> ContactResult:
    """Periodic non-adhesive contact under a normal force, on NumPy or a GPU (E:BEM_eq1..4).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Surface heights h (m), larger = closer to the flat; axis 0 is x. Finite.
    dx, dy : float
        Pixel sizes (m).
    e_star : float
        Reduced modulus E* (Pa).
    normal_force : float
        Total compressive force F_z (N), > 0.
    xp : {"numpy", "cupy"}
        Array library the iteration runs on. The result's arrays are NumPy arrays either way.
    tol : float
        Convergence threshold on the residual (as :class:`asperity.bem.SolverOptions.tol`).
    max_iter : int
        Iteration cap.

    Returns
    -------
    ContactResult
        As :func:`asperity.bem.solve_contact`'s (``branch="unique"``); ``extra`` holds
        ``array_library``, ``convolutions`` and ``device`` (the GPU's name with CuPy).
    """
    _check_input(heights, dx, dy, e_star, normal_force)
    mod = array_module(xp)
    start = time.perf_counter()
    h = mod.asarray(heights, dtype=mod.float64)
    if not bool(mod.isfinite(h).all()):
        raise BemInputError("heights: expected finite values, found NaN or inf")
    shape = h.shape
    compliance, stiffness = _multipliers(mod, shape, dx, dy, e_star)
    n_total = shape[0] * shape[1]
    mean_pressure = normal_force / (n_total * dx * dy)
    run = _ArrayIteration(mod, h, compliance, stiffness, mean_pressure * n_total)
    state = run.start(mean_pressure)
    pixel_stiffness = e_star / np.sqrt(dx * dy)
    history: list[float] = []
    status = SolverStatus.ITERATION_CAP
    for nit in range(max_iter + 1):
        g = run.gap(state)
        residual = _residual(mod, g, state.mask, state.p) * pixel_stiffness
        history.append(residual)
        if residual < tol and not state.changed:
            status = SolverStatus.CONVERGED
            break
        if nit == max_iter:
            break
        run.step(state, g, nit)
    return _result(
        mod, h, state.p, state.u, state.mask, history, status, start, dx, dy, run.convolutions
    )


def _residual(mod: ModuleType, g, mask, p) -> float:
    """sqrt(sum_c g^2 + sum_outside min(g, 0)^2) / sqrt(sum p^2) (m/Pa): the residual's core."""
    violation = mod.where(mask, g, mod.minimum(g, 0.0))
    return float(mod.sqrt((violation * violation).sum() / (p * p).sum()))


def _result(mod, h, p, u, mask, history, status, start, dx, dy, convolutions) -> ContactResult:
    """The ContactResult of the final state, its arrays copied to the host."""
    w = u - h
    d = -float((w * mask).sum()) / max(int(mask.sum()), 1)
    gap = w + d
    n_total = h.shape[0] * h.shape[1]
    n_contact = int(mask.sum())
    force = float(p.sum()) * dx * dy
    device = ""
    if mod is not np:
        device = str(mod.cuda.runtime.getDeviceProperties(0)["name"].decode())
    message = (
        f"converged: residual {history[-1]:.3g} below tol"
        if status == SolverStatus.CONVERGED
        else f"iteration cap reached: residual {history[-1]:.3g}"
    )
    return ContactResult(
        pressure=_to_host(mod, p),
        gap=_to_host(mod, gap),
        contact_mask=_to_host(mod, mask),
        real_area=n_contact * dx * dy,
        contact_fraction=n_contact / n_total,
        normal_force=force,
        mean_pressure=force / (n_total * dx * dy),
        mean_gap=float(gap.mean()),
        separation=d,
        nit=len(history) - 1,
        residual_history=np.asarray(history),
        status=int(status),
        message=message,
        seconds=time.perf_counter() - start,
        dx=dx,
        dy=dy,
        residual=history[-1],
        extra={
            "array_library": mod.__name__,
            "convolutions": convolutions,
            "device": device,
        },
    )
