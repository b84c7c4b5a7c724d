"""Moments ``int q^m C(q) dq`` of an isotropic power spectral density given at points.

Between two neighbouring points the spectrum is taken as the power law through them
(a straight line in log-log axes), so the quadrature is exact for piecewise power-law
spectra whose breakpoints are sample points (a plateau, a self-affine branch, a roll-off).
An interval with a zero end (beyond a hard cut-off) is interpolated linearly instead;
values below ``NOISE_FLOOR`` times the largest count as zero (the FFT round-off beyond a hard
cut-off, about 1e-32 of the peak, is not a spectrum to fit power laws through).
Units: q in rad/m, C in m^4 (Persson's normalisation, see :mod:`statmodel.persson`),
so ``int q^m C dq`` is in m^(3 - m).
"""

from __future__ import annotations

import numpy as np

from asperity.errors import InputError

__all__ = ["NOISE_FLOOR", "isotropic_moment", "validate_spectrum"]

#: PSD values below this fraction of the largest are taken as zero (12 decades in amplitude).
NOISE_FLOOR = 1e-24


def validate_spectrum(q: object, c: object, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(q, c)`` as float arrays after checking them, or raise :class:`InputError`.

    Parameters
    ----------
    q : array_like
        Wavenumbers (rad/m): finite, > 0, strictly increasing, at least two.
    c : array_like
        PSD values (m^4) at ``q``: finite and >= 0, same length as ``q``.
    where : str
        The caller's name, used in the error messages.

    Returns
    -------
    q, c : ndarray
        One-dimensional float64 copies.
    """
    q_arr = np.array(q, dtype=np.float64).ravel()
    c_arr = np.array(c, dtype=np.float64).ravel()
    if q_arr.size != c_arr.size:
        raise InputError(
            f"{where}: q and C must have the same length, got {q_arr.size} and {c_arr.size}"
        )
    if q_arr.size < 2:
        raise InputError(f"{where}: need at least two PSD points, got {q_arr.size}")
    if not np.all(np.isfinite(q_arr)) or np.any(q_arr <= 0):
        raise InputError(f"{where}: wavenumbers q must be finite and > 0 rad/m")
    if np.any(np.diff(q_arr) <= 0):
        raise InputError(f"{where}: wavenumbers q must be strictly increasing")
    if not np.all(np.isfinite(c_arr)) or np.any(c_arr < 0):
        bad = c_arr[~(np.isfinite(c_arr) & (c_arr >= 0))][0]
        raise InputError(f"{where}: PSD values C must be finite and >= 0 m^4, found {bad!r}")
    return q_arr, c_arr


def _power_law_pieces(qa, qb, ca, cb, a, b, power):
    """``int_a^b q^power C dq`` with C the power law through (qa, ca) and (qb, cb)."""
    slope = np.log(cb / ca) / np.log(qb / qa)  # C = ca (q / qa)^slope
    k = power + 1.0 + slope
    log_a, log_b = np.log(a / qa), np.log(b / qa)
    span = log_b - log_a
    safe_k = np.where(k == 0.0, 1.0, k)
    # (e^{k log_b} - e^{k log_a}) / k written so that k -> 0 gives log_b - log_a
    ratio = np.where(k == 0.0, span, np.expm1(k * span) / safe_k)
    return ca * qa ** (power + 1.0) * np.exp(k * log_a) * ratio


def _linear_pieces(qa, qb, ca, cb, a, b, power):
    """``int_a^b q^power C dq`` with C linear between (qa, ca) and (qb, cb)."""
    beta = (cb - ca) / (qb - qa)
    alpha = ca - beta * qa
    m1, m2 = power + 1.0, power + 2.0
    return alpha * (b**m1 - a**m1) / m1 + beta * (b**m2 - a**m2) / m2


def isotropic_moment(
    q: np.ndarray,
    c: np.ndarray,
    power: float,
    q_range: tuple[float, float] | None = None,
) -> float:
    """``int_{q_lo}^{q_hi} q^power C(q) dq`` of a spectrum sampled at ``q``.

    Parameters
    ----------
    q : ndarray
        Wavenumbers (rad/m), strictly increasing, > 0 (see :func:`validate_spectrum`).
    c : ndarray
        PSD (m^4) at ``q``, >= 0.
    power : float
        The exponent m (3 for Persson's G and the mean square slope, 1 for the mean square
        height, both times 2 pi for an isotropic surface).
    q_range : (float, float), optional
        Integration limits (rad/m) inside ``[q[0], q[-1]]``; default the whole sampled range.

    Returns
    -------
    float
        The moment in m^(3 - power) (m^2 for power 1, dimensionless for power 3).
    """
    q_lo, q_hi = (q[0], q[-1]) if q_range is None else q_range
    c = np.where(c < NOISE_FLOOR * np.max(c), 0.0, c)
    qa, qb, ca, cb = q[:-1], q[1:], c[:-1], c[1:]
    a = np.clip(qa, q_lo, q_hi)
    b = np.clip(qb, q_lo, q_hi)
    used = b > a
    qa, qb, ca, cb, a, b = (x[used] for x in (qa, qb, ca, cb, a, b))
    positive = (ca > 0) & (cb > 0)
    total = 0.0
    if np.any(positive):
        total += float(
            np.sum(
                _power_law_pieces(
                    qa[positive],
                    qb[positive],
                    ca[positive],
                    cb[positive],
                    a[positive],
                    b[positive],
                    power,
                )
            )
        )
    if np.any(~positive):
        zero = ~positive
        total += float(
            np.sum(_linear_pieces(qa[zero], qb[zero], ca[zero], cb[zero], a[zero], b[zero], power))
        )
    return total
