"""The public contact solve: :func:`solve_contact` checks its arguments and dispatches.

One route for every adhesive law: the arguments become a validated
:class:`~asperity.bem.normal.problem.ContactProblem`, which the Polonsky-Keer solver
(:mod:`asperity.bem.normal.polonsky_keer`: non-adhesive or Pohrt-Popov) or the Maugis-Dugdale
attractive-set iteration (:mod:`asperity.bem.normal.maugis`, itself built on the Polonsky-Keer
solve)
solves. This module imports both; neither imports it, so there is no import cycle.

How the solver iterates travels in one :class:`~asperity.bem.options.SolverOptions`; the
keyword form of asperity 0.3 (``tol=``, ``max_iter=``, ...) is accepted with a
``DeprecationWarning`` until 0.5 (:func:`options_with_deprecated_knobs`).
"""

from __future__ import annotations

import dataclasses
import time
import warnings

import numpy as np

from asperity.bem.normal.maugis import check_adhesion, solve_maugis_problem
from asperity.bem.normal.polonsky_keer import solve_problem
from asperity.bem.normal.problem import set_up_problem
from asperity.bem.normal.validity import BemWarning, contact_findings
from asperity.bem.options import SolverOptions, resolve_options
from asperity.bem.progress import solve_finished
from asperity.bem.result import ContactResult
from asperity.validity import raise_findings

__all__ = ["KNOBS", "options_with_deprecated_knobs", "solve_contact"]

#: The fields of :class:`SolverOptions`: the knobs that 0.3 also took as keywords.
KNOBS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(SolverOptions))


def options_with_deprecated_knobs(
    options: SolverOptions | None, knobs: dict[str, object]
) -> SolverOptions:
    """``options`` with the knobs given the 0.3 way, as keywords of :func:`solve_contact`.

    Knobs given warn once (a ``DeprecationWarning`` naming each :class:`SolverOptions` field)
    and, when not None, replace their fields, as in 0.3. A keyword that is not a knob is a
    TypeError, as for any function.
    """
    unknown = sorted(set(knobs) - set(KNOBS))
    if unknown:
        raise TypeError(f"solve_contact() got an unexpected keyword argument {unknown[0]!r}")
    if knobs:
        given = ", ".join(f"{name}=..." for name in knobs)
        fields = ", ".join(f"{name}={value!r}" for name, value in knobs.items())
        warnings.warn(
            f"solve_contact({given}) is deprecated since asperity 0.4 and will be removed in "
            f"0.5: pass options=bem.SolverOptions({fields})",
            DeprecationWarning,
            stacklevel=3,
        )
    return resolve_options(options, **knobs)


def solve_contact(
    heights: np.ndarray,
    dx: float,
    dy: float,
    e_star: float,
    *,
    normal_force: float | None = None,
    mean_pressure: float | None = None,
    separation: float | None = None,
    work_of_adhesion: float = 0.0,
    initial: ContactResult | np.ndarray | None = None,
    periodic: bool = True,
    adhesion: str = "pohrt-popov",
    adhesion_range: float | None = None,
    options: SolverOptions | None = None,
    **deprecated_knobs: object,
) -> ContactResult:
    """Normal contact of an elastic half-space with a rigid flat (E:BEM_eq1..E:BEM_eq4).

    Parameters
    ----------
    heights : ndarray (nx, ny)
        Surface heights h (m), larger = closer to the flat; axis 0 is x. No NaN.
    dx, dy : float
        Pixel sizes (m) along x and y.
    e_star : float
        Reduced modulus E* = E / (1 - nu^2) (Pa).
    normal_force, mean_pressure, separation : float, optional
        Exactly one: the total force F_z (N) or F_z / nominal area (Pa), load control; or the
        rigid-body distance d of eq. E:BEM_eq1 (m), displacement control. For a periodic
        domain d must exceed the mean height (the mean deflection is zero); for a non-periodic
        one d is the approach relative to the far field.
    work_of_adhesion : float
        w (J/m^2). When > 0, elements in contact carry tension down to the Pohrt-Popov
        critical tension Sigma (eq:max_sigma) and delaminate below it. The state then depends
        on the path (``branch`` of the result). A tensile force needs ``initial`` = a state on
        the unloading branch.
    initial : ContactResult or ndarray, optional
        Warm start: a previous result (its pressure and contact set) or a pressure field (Pa).
    periodic : bool
        Periodic domain (default) or finite specimen (zero-padded doubled grid).
    adhesion : {"pohrt-popov", "maugis"}
        How ``work_of_adhesion`` acts: the paper's Pohrt-Popov criterion (default, Appendix
        B), or the Maugis-Dugdale cohesive law, a tension w / adhesion_range wherever the gap
        is within ``adhesion_range`` (:mod:`asperity.bem.normal.maugis`; loading with jump-in from
        scratch, unloading from ``initial``; a force <= 0 is allowed).
    adhesion_range : float, optional
        The Maugis-Dugdale range h_0 (m), required with ``adhesion="maugis"`` only.
    options : SolverOptions, optional
        How the solver iterates: tol, max_iter, precondition, stall_window, refresh, kernel,
        fft_backend, threads, coarse_start, precision (default ``SolverOptions()``).
    **deprecated_knobs
        A knob of :class:`SolverOptions` given as a keyword (``tol=1e-10``), the form of
        asperity 0.3: still accepted, with a ``DeprecationWarning`` naming the field, and
        overriding ``options``; removed in asperity 0.5. Any other keyword is a TypeError.

    Returns
    -------
    ContactResult
        Pressure (Pa), gap (m), contact mask, areas (m^2), force (N), ``status`` (0 converged,
        1 iteration cap, 2 stalled, 3 contact lost, 4 load not carried), ``success``,
        ``message``, ``nit``. Non-convergence is reported, never raised. Its validity is in
        ``extra["validity_codes"]`` and ``extra["validity_notes"]``
        (:mod:`asperity.bem.normal.validity`:
        ``bem_full_contact``, ``bem_cohesive_zone``); a full contact is also raised as a
        :class:`~asperity.bem.normal.validity.BemWarning`.

    Raises
    ------
    asperity.bem.errors.BemInputError
        (an :class:`asperity.errors.InputError`) naming the argument: heights not a real 2D
        array of at least 2 x 2 finite values; dx, dy, e_star not positive finite; not exactly
        one finite load; a force <= 0 without adhesion; a periodic separation <= mean(h);
        work_of_adhesion not finite >= 0; an option out of its bounds (:class:`SolverOptions`);
        an ``initial`` of the wrong shape or with non-finite values.
    """
    started = time.perf_counter()
    opts = options_with_deprecated_knobs(options, deprecated_knobs)
    loads: dict[str, object] = {
        "normal_force": normal_force,
        "mean_pressure": mean_pressure,
        "separation": separation,
    }
    law = check_adhesion(adhesion, work_of_adhesion, adhesion_range)
    problem = set_up_problem(heights, dx, dy, e_star, loads, work_of_adhesion, periodic, opts)
    if law is not None:
        result = solve_maugis_problem(problem, law, initial, opts)
    else:
        result = solve_problem(problem, initial, opts, started)
    return with_validity(result, float(e_star))


def with_validity(result: ContactResult, e_star: float) -> ContactResult:
    """``result`` with its validity findings (:func:`asperity.bem.normal.validity.contact_findings`)
    in ``extra["validity_codes"]`` / ``extra["validity_notes"]``; full contact is also raised
    as a :class:`~asperity.bem.normal.validity.BemWarning` (code ``bem_full_contact``). The solver's
    ``status`` is left as it is: it says whether the solve converged."""
    solve_finished(result)  # the bar of an enclosing bem.progress.solve_progress, if any
    findings = contact_findings(result, e_star)
    result.extra["validity_codes"] = [f.code for f in findings]
    result.extra["validity_notes"] = [f.message for f in findings]
    raise_findings([f for f in findings if f.code == "bem_full_contact"], BemWarning, stacklevel=4)
    return result
