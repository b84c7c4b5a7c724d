"""Tangential loading of the rough contact up to full sliding (Sections 3.2 and 4).

At constant normal load F_z (load control) the separation d(delta_T) is solved at every tangential
displacement so that E:NewFormulation_Fy returns the imposed load; F_x and A_r then follow from
E:NewFormulation_Fx / E:NewFormulation_Ar with the composite limits E:delta_2 / E:delta_1:

    delta_2 = max(d_min - d + delta_JKR^loading, delta_PC^min(delta_T)),
    delta_1 = min(0, delta_2).

Asperities with delta >= delta_2 stick (Papangelo-Ciavarella law), those with
delta_1 <= delta < delta_2 slide (Hertz with shear strength tau0), the rest are out of contact.
Counts are expected numbers eta A_n int phi over each population. At delta_T = 0 and d = d_min the
formulation reduces to the preload (continuity, Section 3.2) and the same kernel evaluates both.

Derived quantities: the static friction (the peak of the continuous curve F_x(delta_T) over the
imposed range, refined between the grid points around the grid maximum by a bounded scalar
maximisation on the same model evaluation, to 1e-6 relative and better), the sliding friction
(the all-sliding limit tau0 * A_r^Hertz(d_s), with d_s the separation at which the
Greenwood-Williamson Hertz integral carries F_z, both in closed form: parabolic-cylinder function
D_{-5/2} for the load, the normal partial moment for the area) and the sliding displacement (the
delta_T at which the expected number of sticking asperities falls to one). SI units throughout.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.polynomial.hermite_e import hermegauss
from numpy.typing import ArrayLike
from scipy.optimize import brentq, minimize_scalar
from scipy.special import gamma, ndtr, pbdv

from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, text
from asperity.statmodel import integrals as _k
from asperity.statmodel.checks import StatmodelWarning, area_fraction_finding
from asperity.statmodel.options import ModelSetup, QuadratureOptions, setup_model
from asperity.statmodel.parameters import TABOR_JKR_LIMIT, Material, Roughness, finite_number
from asperity.statmodel.preloading import PreloadResult, pull_off_point, solve_preload
from asperity.validity import Finding, raise_findings


@document_fields
@dataclass(frozen=True)
class ShearCurve:
    """Response of the rough contact to a tangential displacement history (SI units).

    Each field declares its unit, its dimension (``step`` for the arrays) and a description
    (:mod:`asperity.fields`), from which the ``asperity friction`` outputs
    (:mod:`asperity.statmodel.results_io`) and the job's friction stage take theirs.

    Arrays (one entry per step): ``tangential_displacement`` delta_T (m), ``tangential_force``
    F_x (N), ``normal_force`` F_z (N), ``real_area`` A_r (m^2), ``n_contact``, ``n_stick``,
    ``n_slip`` (expected numbers of asperities), ``separation`` d (m), the stick/slip parts
    ``tangential_force_stick``/``_slip`` (N), ``normal_force_stick``/``_slip`` (N),
    ``real_area_stick``/``_slip`` (m^2), the integral limits ``delta_1``/``delta_2`` (m) and
    ``nit`` (normal-load evaluations per step). Scalars: ``tabor_parameter``,
    ``separation_preload`` d_min (m), ``static_friction`` (peak of the continuous F_x(delta_T) over
    the imposed range, N; see :func:`static_friction_peak`), ``static_displacement`` (delta_T at
    that peak, m), ``sliding_friction`` (all-sliding limit, N), ``sliding_separation`` (m),
    ``sliding_displacement`` (m; inf if never, e.g. lambda = 0), ``normal_load`` (imposed, N; NaN
    in fixed grip), ``pull_off_force`` (loading branch, N). Steps after a failed solve are NaN.

    Status, as scipy.optimize's results: ``success`` (bool), ``status`` (int, one of
    :data:`SHEAR_STATUS`: 0 every step solved and inside the model, 1 the preload separation
    solve did not converge, 2 a separation solve under shear failed, e.g. the load can no longer
    be carried, 3 every step solved but a number is outside what the model means: A_r/A_n above
    0.15 (A_r > A_n at worst) or a Tabor parameter below 5), ``message``; ``converged`` is True
    when every step was solved (status 0 or 3), whatever the validity.

    Validity: ``validity_codes`` and ``validity_notes``, one entry per finding (codes of
    :data:`asperity.validity.CODES`, shared with the job's verdict: ``area_fraction``,
    ``tabor``), each also raised as a :class:`~asperity.statmodel.checks.StatmodelWarning`.
    """

    tangential_displacement: np.ndarray = array("m", ("step",), "tangential displacement delta_T")
    tangential_force: np.ndarray = array("N", ("step",), "tangential force F_x")
    normal_force: np.ndarray = array("N", ("step",), "normal force F_z")
    real_area: np.ndarray = array("m^2", ("step",), "real contact area A_r")
    n_contact: np.ndarray = array("1", ("step",), "asperities in contact")
    n_stick: np.ndarray = array("1", ("step",), "sticking asperities")
    n_slip: np.ndarray = array("1", ("step",), "sliding asperities")
    separation: np.ndarray = array("m", ("step",), "separation d")
    tangential_force_stick: np.ndarray = array("N", ("step",), "F_x of sticking asperities")
    tangential_force_slip: np.ndarray = array("N", ("step",), "F_x of sliding asperities")
    normal_force_stick: np.ndarray = array("N", ("step",), "F_z of sticking asperities")
    normal_force_slip: np.ndarray = array("N", ("step",), "F_z of sliding asperities")
    real_area_stick: np.ndarray = array("m^2", ("step",), "A_r of sticking asperities")
    real_area_slip: np.ndarray = array("m^2", ("step",), "A_r of sliding asperities")
    delta_1: np.ndarray = array("m", ("step",), "limit delta_1 (E:delta_1)")
    delta_2: np.ndarray = array("m", ("step",), "limit delta_2 (E:delta_2)")
    nit: np.ndarray = array("1", ("step",), "normal-load evaluations per step")
    tabor_parameter: float = scalar("1", "Tabor parameter mu")
    separation_preload: float = scalar("m", "separation at the preload")
    static_friction: float = scalar("N", "static friction (peak F_x)")
    static_displacement: float = scalar("m", "delta_T at the static friction peak")
    sliding_friction: float = scalar("N", "sliding friction")
    sliding_separation: float = scalar("m", "separation at full sliding")
    sliding_displacement: float = scalar("m", "delta_T at full sliding")
    normal_load: float = scalar("N", "imposed normal load (NaN in fixed grip)")
    pull_off_force: float = scalar("N", "pull-off force")
    success: bool = scalar("1", "every step solved")
    status: int = scalar("1", "status code (SHEAR_STATUS)")
    message: str = text("solver message")
    validity_codes: tuple[str, ...] = text("validity finding codes", default_factory=tuple)
    validity_notes: tuple[str, ...] = text("validity finding messages", default_factory=tuple)

    @property
    def converged(self) -> bool:
        """Every step was solved (status 0, or 3: solved but outside the model's validity)."""
        return self.status in (0, OUTSIDE_MODEL)


#: ``ShearCurve.status`` codes and their meaning.
SHEAR_STATUS: dict[int, str] = {
    0: "converged: the preload and every step were solved",
    1: "the preload separation solve did not converge",
    2: "a separation solve under shear failed (the load cannot be carried, or no convergence)",
    3: "solved, but outside the model's validity (A_r/A_n above 0.15, or Tabor parameter < 5)",
}
#: The status of a curve solved at every step whose numbers the model cannot stand behind.
OUTSIDE_MODEL = 3

#: Most tangential-displacement steps of one curve: a curve needs a few hundred (the static
#: friction is refined between them); 1e5 steps take about 1 s and 30 MB.
MAX_STEPS = 100_000


def _check_displacements(tangential_displacement: ArrayLike) -> np.ndarray:
    dts = np.ascontiguousarray(np.atleast_1d(np.asarray(tangential_displacement, dtype=float)))
    if dts.ndim != 1 or dts.size == 0:
        raise InputError("tangential_displacement: expected a non-empty 1D array in m")
    if dts.size > MAX_STEPS:
        raise InputError(
            f"tangential_displacement: expected at most {MAX_STEPS} steps (a curve needs a few "
            f"hundred; the static friction is refined between them), got {dts.size}"
        )
    if not np.all(np.isfinite(dts)) or np.any(dts < 0.0):
        raise InputError("tangential_displacement: expected finite values >= 0 m")
    if np.any(np.diff(dts) < 0.0):
        raise InputError(
            "tangential_displacement: expected a non-decreasing history (monotonic loading, "
            "the formulation E:delta_2 assumes it)"
        )
    return dts


def _gw_load_moment(h: float) -> float:
    """E[(Z - h)_+^(3/2)] for a standard normal Z (dimensionless), h = d / sigma_s.

    Closed form Gamma(5/2) / sqrt(2 pi) exp(-h^2/4) D_{-5/2}(h) (parabolic-cylinder function) for
    h >= -8; below, where exp(-h^2/4) underflows against an overflowing D_{-5/2}, (Z - h)^(3/2) is
    smooth over the Gaussian's support and 80-node Gauss-Hermite quadrature is exact to
    round-off.
    """
    if h >= -8.0:
        d_val, _ = pbdv(-2.5, h)
        return float(gamma(2.5) / math.sqrt(2.0 * math.pi) * math.exp(-0.25 * h * h) * d_val)
    x, w = hermegauss(80)
    return float(np.sum(w * np.maximum(x - h, 0.0) ** 1.5) / math.sqrt(2.0 * math.pi))


def _hertz_sliding_load(setup: ModelSetup, separation: float) -> float:
    """Greenwood-Williamson Hertz load at separation d (m), closed form (N).

    eta A_n 4/3 E* sqrt(R) sigma^(3/2) E[(Z - h)_+^(3/2)], h = d/sigma (see _gw_load_moment).
    """
    sigma = setup.roughness.summit_height_rms
    return (
        setup.n_asperities
        * 4.0
        / 3.0
        * setup.material.e_star
        * math.sqrt(setup.roughness.summit_radius)
        * sigma**1.5
        * _gw_load_moment(separation / sigma)
    )


def _hertz_sliding_area(setup: ModelSetup, separation: float) -> float:
    """Greenwood-Williamson Hertz area eta A_n pi R sigma (pdf(h) - h Q(h)) at d = h sigma (m^2)."""
    sigma = setup.roughness.summit_height_rms
    h = separation / sigma
    pdf = math.exp(-0.5 * h * h) / math.sqrt(2.0 * math.pi)
    return float(
        setup.n_asperities * math.pi * setup.roughness.summit_radius * sigma * (pdf - h * ndtr(-h))
    )


def sliding_limit(setup: ModelSetup, normal_load: float) -> tuple[float, float, float]:
    """(sliding friction N, separation m, real area m^2) when every junction slides (closed form).

    With all junctions sliding the model is Greenwood-Williamson with Hertz asperities; the
    separation d_s solves F_GW(d_s) = F_z (Brent, xtol 1e-14 sigma_s) and the friction is
    tau0 * A_GW(d_s). A non-positive load cannot be carried by sliding junctions: (0, inf, 0).
    """
    if normal_load <= 0.0:
        return 0.0, math.inf, 0.0
    sigma = setup.roughness.summit_height_rms
    lo, hi = -1.0 * sigma, 1.0 * sigma
    while _hertz_sliding_load(setup, lo) < normal_load:
        lo -= 2.0 * (hi - lo)
    while _hertz_sliding_load(setup, hi) > normal_load:
        hi += 2.0 * (hi - lo)
    d_s = brentq(
        lambda d: _hertz_sliding_load(setup, d) - normal_load,
        lo,
        hi,
        xtol=1e-14 * sigma,
        rtol=1e-15,
        maxiter=500,
    )
    area = _hertz_sliding_area(setup, d_s)
    return setup.material.shear_strength * area, float(d_s), area


def _assemble(
    setup: ModelSetup,
    dts: np.ndarray,
    results: np.ndarray,
    separations: np.ndarray,
    nits: np.ndarray,
    **scalars: Any,
) -> ShearCurve:
    n = setup.n_asperities
    fz_stick = n * results[:, _k.FZ_STICK]
    fz_slip = n * results[:, _k.FZ_SLIP]
    fx_stick = n * results[:, _k.FX_STICK]
    fx_slip = n * results[:, _k.FX_SLIP]
    ar_stick = n * results[:, _k.AR_STICK]
    ar_slip = n * results[:, _k.AR_SLIP]
    n_stick = n * results[:, _k.N_STICK]
    n_slip = n * results[:, _k.N_SLIP]
    return ShearCurve(
        tangential_displacement=dts.copy(),
        tangential_force=fx_stick + fx_slip,
        normal_force=fz_stick + fz_slip,
        real_area=ar_stick + ar_slip,
        n_contact=n_stick + n_slip,
        n_stick=n_stick,
        n_slip=n_slip,
        separation=separations,
        tangential_force_stick=fx_stick,
        tangential_force_slip=fx_slip,
        normal_force_stick=fz_stick,
        normal_force_slip=fz_slip,
        real_area_stick=ar_stick,
        real_area_slip=ar_slip,
        delta_1=results[:, _k.DELTA_1].copy(),
        delta_2=results[:, _k.DELTA_2].copy(),
        nit=nits,
        tabor_parameter=setup.tabor_parameter,
        **scalars,
    )


def _load_control_state(
    setup: ModelSetup, prm: np.ndarray, delta_t: float, d_guess: float, target: float, ftol: float
) -> tuple[np.ndarray | None, float]:
    """Per-asperity integrals at delta_T (m) where F_z = ``target`` (N), and that separation (m).

    The separation solve starts from ``d_guess`` (m); a failed solve gives ``(None, d)``.
    """
    out = np.empty(_k.N_RESULTS)
    work = np.empty(6)
    sigma = setup.roughness.summit_height_rms
    d, _, ok = _k.solve_separation(
        d_guess,
        1e-6 * sigma,
        delta_t,
        target,
        ftol,
        1e-15 * sigma,
        setup.options.max_iter,
        prm,
        setup.gl_x,
        setup.gl_w,
        setup.panels,
        out,
        work,
    )
    return (out if ok else None), d


def _n_stick_load_control(
    setup: ModelSetup, prm: np.ndarray, delta_t: float, d_guess: float, target: float, ftol: float
) -> tuple[float, float]:
    out, d = _load_control_state(setup, prm, delta_t, d_guess, target, ftol)
    if out is None:
        return math.nan, d
    return setup.n_asperities * out[_k.N_STICK], d


def _tangential_force_at(
    setup: ModelSetup,
    prm: np.ndarray,
    dts: np.ndarray,
    separations: np.ndarray,
    target: float | None,
    ftol: float,
) -> Callable[[float], float]:
    """F_x(delta_T) (N) of the same model anywhere on the path, NaN where the solve fails.

    Load control (``target`` in N): the separation is solved afresh, starting from the computed
    separation of the grid step at or just below delta_T. Fixed grip (``target`` None): the
    separation is ``separations[0]`` throughout.
    """

    def fx_at(delta_t: float) -> float:
        out: np.ndarray | None
        if target is None:
            out = np.empty(_k.N_RESULTS)
            _k.asperity_integrals(
                separations[0], delta_t, prm, setup.gl_x, setup.gl_w, setup.panels, out
            )
        else:
            j = max(int(np.searchsorted(dts, delta_t, side="right")) - 1, 0)
            out, _ = _load_control_state(setup, prm, delta_t, separations[j], target, ftol)
            if out is None:
                return math.nan
        return float(setup.n_asperities * (out[_k.FX_STICK] + out[_k.FX_SLIP]))

    return fx_at


def static_friction_peak(
    fx_at: Callable[[float], float], dts: np.ndarray, fx: np.ndarray
) -> tuple[float, float]:
    """(static friction N, delta_T m at it): the peak of the continuous F_x(delta_T) on the path.

    The grid maximum F_x[i] brackets the peak in [delta_T[i-1], delta_T[i+1]] (F_x rises to the
    peak and falls after it). A bounded Brent maximisation of ``fx_at`` (the model evaluated
    afresh at any delta_T) over that bracket, to 1e-9 of its width, finds it whether it is a
    smooth maximum or a kink where junctions start to slide (golden-section steps converge on a
    kink or on the left limit of a drop alike); the larger of the grid maximum and the refined
    value is returned, so the result is never below the grid maximum. The refined value is
    within 1e-6 relative (in practice 1e-10) of the peak of a 100x finer grid (tested).
    ``(nan, nan)`` when no step was solved.
    """
    finite = np.flatnonzero(np.isfinite(fx))
    if finite.size == 0:
        return math.nan, math.nan
    i = int(finite[np.argmax(fx[finite])])
    best = (float(fx[i]), float(dts[i]))
    lo = float(dts[i - 1]) if i > 0 else float(dts[i])
    hi = float(dts[i + 1]) if i + 1 < dts.size and np.isfinite(fx[i + 1]) else float(dts[i])
    if not hi > lo:
        return best

    def negative_fx(delta_t: float) -> float:
        value = fx_at(delta_t)
        return -value if math.isfinite(value) else math.inf

    res = minimize_scalar(
        negative_fx,
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-9 * (hi - lo), "maxiter": 200},
    )
    if math.isfinite(res.fun) and -res.fun > best[0]:
        return float(-res.fun), float(res.x)
    return best


def _sliding_displacement(
    setup: ModelSetup,
    prm: np.ndarray,
    dts: np.ndarray,
    n_stick: np.ndarray,
    separations: np.ndarray,
    target: float | None,
    ftol: float,
) -> float:
    """delta_T (m) at which the expected number of sticking asperities falls to 1.

    Bracketed on the computed curve (extended by doubling delta_T when needed), refined by Brent
    (rtol 1e-10). inf when it never happens (lambda = 0), 0 when fewer than one sticks at the
    first step, NaN when the separation solve fails before it.
    """
    mat = setup.material
    if mat.mode_mixity == 0.0:
        return math.inf  # pure JKR: no shear-induced instability, junctions never slide
    if mat.work_of_adhesion == 0.0:
        return 0.0  # no adhesion: every junction slides as soon as delta_T > 0
    if n_stick[0] < 1.0:
        return float(dts[0])
    count = _stick_counter(setup, prm, separations, target, ftol)
    below = np.flatnonzero(n_stick < 1.0)
    if below.size:
        i = int(below[0])
        lo, hi, d_lo = float(dts[i - 1]), float(dts[i]), float(separations[i - 1])
    else:
        finite = np.flatnonzero(np.isfinite(separations))
        if finite.size == 0:
            return math.nan
        j = int(finite[-1])
        lo, d_lo = float(dts[j]), float(separations[j])
        hi = max(2.0 * lo, setup.roughness.summit_height_rms * 1e-3)
        for _ in range(80):
            n_hi, d_hi = count(hi, d_lo)
            if not math.isfinite(n_hi):
                return math.nan
            if n_hi < 1.0:
                break
            lo, d_lo, hi = hi, d_hi, 2.0 * hi
        else:
            return math.inf
    return _one_sticking_root(count, lo, hi, d_lo)


def _stick_counter(
    setup: ModelSetup,
    prm: np.ndarray,
    separations: np.ndarray,
    target: float | None,
    ftol: float,
) -> Callable[[float, float], tuple[float, float]]:
    """count(delta_T m, d_guess m) -> (expected number of sticking asperities, separation m).

    Load control (``target`` in N): the separation is solved from ``d_guess`` (NaN count when
    the solve fails). Fixed grip (``target`` None): the separation is ``separations[0]``.
    """

    def count(dt: float, d_guess: float) -> tuple[float, float]:
        if target is None:
            out = np.empty(_k.N_RESULTS)
            _k.asperity_integrals(
                separations[0], dt, prm, setup.gl_x, setup.gl_w, setup.panels, out
            )
            return setup.n_asperities * out[_k.N_STICK], separations[0]
        return _n_stick_load_control(setup, prm, dt, d_guess, target, ftol)

    return count


def _one_sticking_root(
    count: Callable[[float, float], tuple[float, float]], lo: float, hi: float, d_lo: float
) -> float:
    """delta_T (m) in [lo, hi] where ``count`` falls to one sticking asperity (Brent, rtol 1e-10).

    Each evaluation starts its separation solve from the last finite separation (m), the first
    from ``d_lo``; NaN when Brent fails (no sign change, or a failed solve).
    """
    state = {"d": d_lo}

    def f(dt: float) -> float:
        n_dt, d_dt = count(dt, state["d"])
        if math.isfinite(d_dt):
            state["d"] = d_dt
        return n_dt - 1.0

    try:
        return float(brentq(f, lo, hi, rtol=1e-10, xtol=1e-300, maxiter=200))
    except (ValueError, RuntimeError):
        return math.nan


def shear_curve(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    normal_load: float,
    tangential_displacement: ArrayLike,
    **accuracy_knobs: float,
) -> ShearCurve:
    """Tangential loading at constant normal load, from the preload to full sliding.

    Preload on Greenwood's loading branch (E:Fy_Greenwood) to d_min, then for every delta_T the
    separation d with F_z(d, delta_T) = ``normal_load`` (E:NewFormulation_Fy), and F_x, A_r from
    E:NewFormulation_Fx / E:NewFormulation_Ar with the limits E:delta_2 / E:delta_1.

    Parameters
    ----------
    material, roughness : Material, Roughness
        Interface and summit statistics (SI).
    nominal_area : float
        A_n, m^2 (eta A_n >= 1).
    normal_load : float
        Imposed F_z, N (compressive positive); must not be below the loading-branch pull-off
        force :func:`statmodel.pull_off_force` (else ``InputError`` naming it in N).
    tangential_displacement : array_like
        Non-decreasing delta_T history, m (start with 0 to include the preload state).
    **accuracy_knobs
        ``nodes``, ``panels``, ``cutoff_sigma``, ``load_rtol``, ``max_iter``
        (see :mod:`statmodel.options`).

    Returns
    -------
    ShearCurve
        ``success`` False with ``status`` 1 if the preload solve failed, 2 (and later steps NaN)
        if a separation solve under shear failed, e.g. when the load can no longer be carried
        (pull-off under shear); see :data:`SHEAR_STATUS`.
    """
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    dts = _check_displacements(tangential_displacement)
    pull = pull_off_point(setup)
    pre = solve_preload(setup, normal_load, pull)
    target = float(normal_load)
    ftol = setup.options.load_rtol * max(abs(target), abs(pull[0]))
    prm = setup.with_preload_separation(pre.separation)
    results, separations, nits, n_ok = _march_load_control(setup, prm, dts, pre, target, ftol)
    status, message = _load_control_status(pre, n_ok, dts, target)
    f_slide, d_slide, _ = sliding_limit(setup, target)
    curve = _assemble(
        setup,
        dts,
        results,
        separations,
        nits,
        **_friction_measures(setup, prm, dts, results, separations, target, ftol),
        separation_preload=pre.separation,
        sliding_friction=f_slide,
        sliding_separation=d_slide,
        normal_load=target,
        pull_off_force=pull[0],
        success=status == 0,
        status=status,
        message=message,
    )
    return _with_validity(curve, setup)


def curve_findings(curve: ShearCurve, setup: ModelSetup) -> list[Finding]:
    """The validity findings of a solved curve: its largest A_r/A_n (``area_fraction``) and
    its Tabor parameter (``tabor``, adhesive interfaces only); see :mod:`asperity.validity`."""
    findings = []
    area = np.asarray(curve.real_area, dtype=float)
    area = area[np.isfinite(area)]
    if area.size:
        found = area_fraction_finding(float(area.max()) / setup.nominal_area)
        if found is not None:
            findings.append(found)
    mu = float(curve.tabor_parameter)
    if setup.material.work_of_adhesion > 0.0 and mu < TABOR_JKR_LIMIT:
        findings.append(
            Finding(
                "tabor",
                "invalid",
                f"Tabor parameter mu = {mu:.3g} < {TABOR_JKR_LIMIT:g}: the JKR asperity laws "
                "(E:JKR_indent, E:PC_indent) hold for mu > 5 (paper, Section 2)",
                mu,
                TABOR_JKR_LIMIT,
            )
        )
    return findings


def _with_validity(curve: ShearCurve, setup: ModelSetup) -> ShearCurve:
    """``curve`` with its findings recorded (status 3 when one is invalid and every step was
    solved) and raised as :class:`StatmodelWarning` (the Tabor finding is raised by
    :func:`setup_model` already, as a :class:`TaborWarning`)."""
    findings = curve_findings(curve, setup)
    if not findings:
        return curve
    raise_findings([f for f in findings if f.code != "tabor"], StatmodelWarning, stacklevel=4)
    status, success, message = curve.status, curve.success, curve.message
    invalid = [f for f in findings if f.level == "invalid"]
    if status == 0 and invalid:
        status, success = OUTSIDE_MODEL, False
        message = f"solved, but outside the model: {invalid[0].message}"
    return dataclasses.replace(
        curve,
        status=status,
        success=success,
        message=message,
        validity_codes=tuple(f.code for f in findings),
        validity_notes=tuple(f.message for f in findings),
    )


def _march_load_control(
    setup: ModelSetup,
    prm: np.ndarray,
    dts: np.ndarray,
    pre: PreloadResult,
    target: float,
    ftol: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The march over delta_T (m) at the normal load ``target`` (N), from the preload state.

    Returns the per-asperity integrals (one row per step, layout of :mod:`statmodel.integrals`),
    the separations (m), the normal-load evaluations per step and the number of solved steps;
    rows from the first failed step on (all of them after a failed preload) stay NaN.
    """
    m = dts.size
    results = np.full((m, _k.N_RESULTS), np.nan)
    separations = np.full(m, np.nan)
    nits = np.zeros(m, dtype=np.int64)
    if not pre.success:
        return results, separations, nits, 0
    n_ok = _k.shear_path(
        dts,
        target,
        pre.separation,
        ftol,
        1e-15 * setup.roughness.summit_height_rms,
        setup.options.max_iter,
        prm,
        setup.gl_x,
        setup.gl_w,
        setup.panels,
        results,
        separations,
        nits,
    )
    return results, separations, nits, n_ok


def _load_control_status(
    pre: PreloadResult, n_ok: int, dts: np.ndarray, target: float
) -> tuple[int, str]:
    """(status, message) of a load-controlled curve (codes of :data:`SHEAR_STATUS`)."""
    if not pre.success:
        return 1, pre.message
    if n_ok == dts.size:
        return 0, "converged"
    return 2, (
        f"separation solve failed at step {n_ok} (delta_T = {dts[n_ok]:.6g} m): the normal "
        f"load {target:.6g} N cannot be carried (pull-off under shear) or the solver did "
        "not converge"
    )


def _friction_measures(
    setup: ModelSetup,
    prm: np.ndarray,
    dts: np.ndarray,
    results: np.ndarray,
    separations: np.ndarray,
    target: float | None,
    ftol: float,
) -> dict[str, float]:
    """The static friction (N) and its delta_T (m), and the sliding displacement (m).

    ``target`` is the imposed normal load (N) in load control, None in fixed grip; see
    :func:`static_friction_peak` and :func:`_sliding_displacement`.
    """
    n_stick = setup.n_asperities * results[:, _k.N_STICK]
    slide_dt = _sliding_displacement(setup, prm, dts, n_stick, separations, target, ftol)
    fx = setup.n_asperities * (results[:, _k.FX_STICK] + results[:, _k.FX_SLIP])
    fx_at = _tangential_force_at(setup, prm, dts, separations, target, ftol)
    static, static_dt = static_friction_peak(fx_at, dts, fx)
    return {
        "sliding_displacement": slide_dt,
        "static_friction": static,
        "static_displacement": static_dt,
    }


def shear_curve_fixed_separation(
    material: Material,
    roughness: Roughness,
    nominal_area: float,
    separation: float,
    tangential_displacement: ArrayLike,
    **accuracy_knobs: float,
) -> ShearCurve:
    """Tangential loading in fixed grip: the separation stays at ``separation`` (m) throughout.

    The contact is pre-loaded to d_min = ``separation`` (lower limit delta_JKR^loading), then
    sheared at constant d; F_z varies (E:NewFormulation_Fy). The sliding friction is the
    all-sliding limit at that separation, tau0 * A_GW(d) (closed form); ``normal_load`` is NaN.
    """
    setup = setup_model(
        material, roughness, nominal_area, QuadratureOptions.from_knobs(**accuracy_knobs)
    )
    dts = _check_displacements(tangential_displacement)
    d = finite_number(separation, "separation", "m", "separation")
    prm = setup.with_preload_separation(d)
    results = np.empty((dts.size, _k.N_RESULTS))
    _k.fixed_separation_path(dts, d, prm, setup.gl_x, setup.gl_w, setup.panels, results)
    separations = np.full(dts.size, d)
    area = _hertz_sliding_area(setup, d)
    curve = _assemble(
        setup,
        dts,
        results,
        separations,
        np.zeros(dts.size, dtype=np.int64),
        **_friction_measures(setup, prm, dts, results, separations, None, 0.0),
        separation_preload=d,
        sliding_friction=material.shear_strength * area,
        sliding_separation=d,
        normal_load=math.nan,
        pull_off_force=math.nan,
        success=True,
        status=0,
        message="fixed grip: no solve needed",
    )
    return _with_validity(curve, setup)
