"""The contact driven through a spring: F_x against the drive's displacement, stick-slip.

A friction test imposes the displacement of a drive (a motor), not the interfacial tangential
displacement delta_T: the drive reaches the contact through the loading system, a spring of
stiffness k (N/m) in series with it. The spring carries the tangential force F_x, so

    drive = delta_T + F_x(delta_T) / k,

with F_x(delta_T) the model's tangential force (E:NewFormulation_Fx, :func:`statmodel.shear_curve`
at the curve's normal load). A rigid drive (k = inf) imposes delta_T itself.

Stability: at a fixed drive the equilibrium is stable where d drive / d delta_T > 0, i.e. where
dF_x/d delta_T > -k. Where F_x falls after the static peak more steeply than -k the drive can
no longer hold the contact: at the drive position D* where d drive / d delta_T reaches 0 the
contact jumps, at that same drive (the drive does not move during the fast slip), to the next
stable point of the curve with drive = D*: a stick-slip event, with a force drop
F_x(before) - F_x(after). When the curve ends in full sliding (every junction slides, F_x the
all-sliding friction tau0 A_r^Hertz, constant in delta_T) the curve is continued at that force
beyond its end, so a jump that lands beyond the computed path is still located, in closed form:
delta_T(after) = D* - F_d / k.

The paper's rig (Sahli et al., loaded through a 9200 N/m wire) is in this regime: the model's
F_x falls by up to 5e4 N/m after its peak, and its sliding displacement (about 25 um) is the
interface's share of the measured one (about 1 mm), the rest being the wire's F_x / k
(Section 4). SI units throughout: m, N, N/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar
from asperity.statmodel.shear import ShearCurve


@document_fields
@dataclass(frozen=True)
class StickSlipJump:
    """One stick-slip jump of the contact driven through a spring (SI units).

    The drive stays at ``drive_displacement`` during the jump; the interface slips from
    ``tangential_displacement_before`` to ``tangential_displacement_after`` and F_x drops from
    ``force_before`` to ``force_after``.
    """

    drive_displacement: float = scalar("m", "drive position D* of the jump")
    tangential_displacement_before: float = scalar("m", "delta_T where the contact lets go")
    tangential_displacement_after: float = scalar("m", "delta_T where it is held again")
    force_before: float = scalar("N", "F_x just before the jump")
    force_after: float = scalar("N", "F_x just after the jump")

    @property
    def force_drop(self) -> float:
        """F_x(before) - F_x(after), N (positive)."""
        return self.force_before - self.force_after


@document_fields
@dataclass(frozen=True)
class DriveCurve:
    """A shear curve seen from the drive: drive = delta_T + F_x / k (SI units).

    Arrays (one entry per point of the model curve, continued at the sliding friction when a
    jump lands beyond it): ``tangential_displacement`` delta_T (m), ``tangential_force`` F_x
    (N), ``drive_displacement`` (m) and ``stable`` (d drive / d delta_T > 0 on the segment
    ending at the point; the first point is stable). ``jumps`` lists the stick-slip jumps a
    drive moving forward meets, in order (empty: none, e.g. a rigid drive).
    """

    drive_stiffness: float = scalar("N/m", "stiffness k of the loading system (inf: rigid)")
    tangential_displacement: np.ndarray = array("m", ("point",), "interfacial delta_T")
    tangential_force: np.ndarray = array("N", ("point",), "tangential force F_x")
    drive_displacement: np.ndarray = array("m", ("point",), "drive = delta_T + F_x / k")
    stable: np.ndarray = array("1", ("point",), "stable under drive control")
    static_friction: float = scalar("N", "static friction F_s (peak F_x)")
    static_displacement: float = scalar("m", "delta_T at the peak")
    static_drive_displacement: float = scalar("m", "drive at the peak: delta_s + F_s / k")
    sliding_friction: float = scalar("N", "sliding friction F_d (NaN: unknown)")
    jumps: tuple[StickSlipJump, ...] = field(default_factory=tuple)

    @property
    def stick_slip(self) -> bool:
        """At least one stick-slip jump is predicted."""
        return bool(self.jumps)

    def followed_path(self) -> tuple[np.ndarray, np.ndarray]:
        """(drive m, F_x N) a forward-moving drive follows: stable branches joined by jumps.

        The drive is non-decreasing; at each jump it holds two points (the force before and
        after it), so a line plot draws the drop as a vertical segment.
        """
        dts, fx, drive = (
            self.tangential_displacement,
            self.tangential_force,
            self.drive_displacement,
        )
        pieces_d, pieces_f = [], []
        pick = dts >= dts[0]
        for jump in self.jumps:
            pick &= dts <= jump.tangential_displacement_before
            pieces_d += [drive[pick], [jump.drive_displacement]]
            pieces_f += [fx[pick], [jump.force_after]]
            pick = dts > jump.tangential_displacement_after
        pieces_d.append(drive[pick])
        pieces_f.append(fx[pick])
        return np.concatenate(pieces_d), np.concatenate(pieces_f)

    def force_at_drive(self, drive_displacement: ArrayLike) -> np.ndarray:
        """F_x (N) a forward-moving drive measures at the given drive positions (m).

        Linear between the points of :meth:`followed_path`; at or past a jump's drive the force
        after the jump; beyond the curve's end the last force (the sliding friction when the
        curve ends in full sliding).
        """
        drive, force = self.followed_path()
        x = np.asarray(drive_displacement, dtype=float)
        out = np.interp(x, drive, force)
        for jump in self.jumps:
            out = np.where(x == jump.drive_displacement, jump.force_after, out)
        return out


def _check_stiffness(drive_stiffness: float) -> float:
    try:
        k = float(drive_stiffness)
    except (TypeError, ValueError):
        raise InputError(
            f"drive_stiffness: expected a number in N/m (inf: rigid), got {drive_stiffness!r}"
        ) from None
    if math.isnan(k) or k <= 0.0:
        raise InputError(
            f"drive_stiffness: expected a stiffness > 0 N/m (inf: a rigid drive), got {k!r}"
        )
    return k


def _finite_prefix(
    tangential_displacement: ArrayLike, tangential_force: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """The points (m, N) up to the first non-finite one (a shear curve is NaN after a failed
    step); refused when fewer than two remain or delta_T decreases."""
    dts = np.asarray(tangential_displacement, dtype=float).ravel()
    fx = np.asarray(tangential_force, dtype=float).ravel()
    if dts.shape != fx.shape:
        raise InputError(
            f"tangential_displacement and tangential_force: expected equal lengths, got "
            f"{dts.size} and {fx.size}"
        )
    bad = np.flatnonzero(~(np.isfinite(dts) & np.isfinite(fx)))
    end = int(bad[0]) if bad.size else dts.size
    if end < 2:
        raise InputError("tangential curve: expected at least two finite points (m, N)")
    dts, fx = dts[:end], fx[:end]
    if np.any(np.diff(dts) <= 0.0):
        raise InputError("tangential_displacement: expected an increasing delta_T in m")
    return dts, fx


def _extend_to_sliding(
    dts: np.ndarray, fx: np.ndarray, k: float, sliding_friction: float
) -> tuple[np.ndarray, np.ndarray]:
    """The curve continued at F_x = F_d (N) beyond its end, far enough in delta_T (m) that its
    drive passes the largest drive of the computed part (every jump then lands on it)."""
    if not math.isfinite(sliding_friction) or math.isinf(k):
        return dts, fx
    reach = float(np.max(dts + fx / k)) - sliding_friction / k
    span = float(dts[-1] - dts[0])
    end = max(reach, float(dts[-1])) + 0.05 * span
    return np.append(dts, end), np.append(fx, sliding_friction)


def _landing(dts: np.ndarray, drive: np.ndarray, start: int, level: float) -> tuple[int, float]:
    """First index j > start with drive[j] >= level and the delta_T (m) of drive = level on
    segment j-1..j (linear); (-1, nan) when the drive never gets back to ``level``."""
    above = np.flatnonzero(drive[start + 1 :] >= level)
    if not above.size:
        return -1, math.nan
    j = start + 1 + int(above[0])
    d0, d1 = drive[j - 1], drive[j]
    t = 1.0 if d1 == d0 else (level - d0) / (d1 - d0)
    return j, float(dts[j - 1] + t * (dts[j] - dts[j - 1]))


def _find_jumps(dts: np.ndarray, fx: np.ndarray, drive: np.ndarray) -> list[StickSlipJump]:
    """The jumps a forward-moving drive meets: at each local maximum of the drive along the
    curve (the onset of d drive / d delta_T < 0), at equal drive to the next point of the curve
    with that drive. A jump that never lands (the curve does not reach that drive again) is
    left out: without a continuation the landing is unknown."""
    jumps: list[StickSlipJump] = []
    i = 0
    while True:
        falling = np.flatnonzero(np.diff(drive[i:]) < 0.0)
        if not falling.size:
            return jumps
        top = i + int(falling[0])
        j, dt_after = _landing(dts, drive, top, float(drive[top]))
        if j < 0:
            return jumps
        f_after = float(np.interp(dt_after, dts[j - 1 : j + 1], fx[j - 1 : j + 1]))
        jumps.append(
            StickSlipJump(float(drive[top]), float(dts[top]), dt_after, float(fx[top]), f_after)
        )
        i = j


def map_to_drive(
    tangential_displacement: ArrayLike,
    tangential_force: ArrayLike,
    drive_stiffness: float,
    *,
    sliding_friction: float = math.nan,
    static_friction: float | None = None,
    static_displacement: float | None = None,
) -> DriveCurve:
    """Map a tangential curve F_x(delta_T) to the drive, drive = delta_T + F_x / k; find the
    stick-slip jumps where dF_x/d delta_T < -k.

    Parameters
    ----------
    tangential_displacement : array_like
        Increasing interfacial delta_T, m (the curve is used up to its first non-finite point).
    tangential_force : array_like
        F_x at those delta_T, N (E:NewFormulation_Fx).
    drive_stiffness : float
        k of the loading system in series with the contact, N/m; ``inf`` for a rigid drive.
    sliding_friction : float, optional
        F_d, N, when the curve ends in full sliding: the curve is continued at F_d beyond its
        end (a jump may land there). NaN (default): no continuation.
    static_friction, static_displacement : float, optional
        The refined static peak (N, m) of the continuous curve
        (:func:`statmodel.shear.static_friction_peak`); default: the largest point.

    Returns
    -------
    DriveCurve
        With ``static_drive_displacement`` = delta_s + F_s / k and the jumps, each at the drive
        D* where d drive / d delta_T first turns negative (the grid point of the largest drive
        before the fall), landing by linear interpolation on the curve.
    """
    k = _check_stiffness(drive_stiffness)
    dts, fx = _finite_prefix(tangential_displacement, tangential_force)
    peak = int(np.argmax(fx))
    f_s = float(fx[peak]) if static_friction is None else float(static_friction)
    d_s = float(dts[peak]) if static_displacement is None else float(static_displacement)
    dts, fx = _extend_to_sliding(dts, fx, k, float(sliding_friction))
    drive = dts + fx / k if math.isfinite(k) else dts.copy()
    stable = np.concatenate([[True], np.diff(drive) > 0.0])
    return DriveCurve(
        drive_stiffness=k,
        tangential_displacement=dts,
        tangential_force=fx,
        drive_displacement=drive,
        stable=stable,
        static_friction=f_s,
        static_displacement=d_s,
        static_drive_displacement=d_s + (f_s / k if math.isfinite(k) else 0.0),
        sliding_friction=float(sliding_friction),
        jumps=tuple(_find_jumps(dts, fx, drive)),
    )


def drive_curve(curve: ShearCurve, drive_stiffness: float) -> DriveCurve:
    """A model shear curve (:func:`statmodel.shear_curve`) seen from a drive of stiffness k (N/m).

    The curve's refined static peak is kept; when its path reaches the model's sliding
    displacement (every junction slides: F_x = tau0 A_r^Hertz, the all-sliding limit) it is
    continued at its sliding friction beyond its end, so that a jump landing beyond the path
    is located (see :func:`map_to_drive`).
    """
    dts = np.asarray(curve.tangential_displacement, dtype=float)
    ends_sliding = math.isfinite(curve.sliding_displacement) and (
        curve.sliding_displacement <= dts[-1]
    )
    return map_to_drive(
        dts,
        curve.tangential_force,
        drive_stiffness,
        sliding_friction=float(curve.sliding_friction) if ends_sliding else math.nan,
        static_friction=float(curve.static_friction),
        static_displacement=float(curve.static_displacement),
    )
