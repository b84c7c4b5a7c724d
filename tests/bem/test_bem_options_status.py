"""Solver options (bounded at validation, with the reason), the status vocabulary and the stall
diagnosis."""

from __future__ import annotations

import numpy as np
import pytest

from asperity.bem import BemInputError, SolverOptions, SolverStatus, solve_contact
from asperity.bem.normal.diagnosis import stall_causes
from asperity.bem.options import resolve_options
from asperity.errors import InputError


@pytest.mark.parametrize(
    "knob, value, words",
    [
        ("tol", 1e300, "a number in [1e-14, 0.01] ("),
        ("tol", 1e-20, "round-off"),
        ("tol", float("nan"), "tol"),
        ("max_iter", 10**9, "an integer in [1, 1000000] ("),
        ("max_iter", 0, "max_iter"),
        ("stall_window", 2.5, "integer"),
        ("refresh", -1, "refresh"),
        ("threads", 0, "threads"),
        ("kernel", "hertz", "'point', 'love'"),
        ("fft_backend", "fftw3", "'auto'"),
        ("precondition", "yes", "True or False"),
    ],
)
def test_every_knob_is_bounded_with_a_reason(knob, value, words):
    with pytest.raises(InputError, match="solve_contact") as info:
        SolverOptions(**{knob: value})
    assert words in str(info.value) and isinstance(info.value, BemInputError)
    with pytest.raises(InputError), pytest.warns(DeprecationWarning, match=knob):
        solve_contact(np.zeros((4, 4)), 1.0, 1.0, 1.0, normal_force=1.0, **{knob: value})


def test_the_keyword_form_of_0_3_warns_naming_the_field_and_gives_the_same_solve(rough):
    """``solve_contact(tol=...)`` (documented in 0.3) still works for one version: a
    DeprecationWarning names the SolverOptions field, and the solve is the options object's."""
    h = rough(32, seed=5)
    opts = SolverOptions(tol=1e-10, precondition=False, refresh=20)
    a = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.05, options=opts)
    fields = r"SolverOptions\(tol=1e-10, precondition=False, refresh=20\)"
    with pytest.warns(DeprecationWarning, match=fields):
        b = solve_contact(
            h, 1.0, 1.0, 1.0, mean_pressure=0.05, tol=1e-10, precondition=False, refresh=20
        )
    assert a.nit == b.nit and np.array_equal(a.pressure, b.pressure)
    # a keyword overrides the options object
    assert resolve_options(opts, tol=1e-6).tol == 1e-6 and resolve_options(opts).refresh == 20
    with pytest.raises(InputError, match="SolverOptions"):
        solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.05, options={"tol": 1e-6})
    with pytest.raises(TypeError, match="tolerance"):
        solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.05, tolerance=1e-6)


def test_bad_arguments_raise_input_errors_not_bare_value_errors():
    cases = [
        dict(heights=np.zeros((1, 4)), normal_force=1.0),
        dict(heights=np.zeros((4, 4)), normal_force=-1.0),
        dict(heights=np.zeros((4, 4)), normal_force=1.0, separation=0.1),
        dict(heights=np.zeros((4, 4)), normal_force=1.0, periodic="no"),
        dict(heights=np.zeros((4, 4)), normal_force=1.0, initial=np.ones((3, 3))),
    ]
    for case in cases:
        heights = case.pop("heights")
        with pytest.raises(InputError):
            solve_contact(heights, 1.0, 1.0, 1.0, **case)


def test_status_codes_are_documented_integers(rough):
    h = rough(32, seed=1)
    ok = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.04)
    capped = solve_contact(h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(max_iter=2))
    assert (ok.status, capped.status) == (SolverStatus.CONVERGED, SolverStatus.ITERATION_CAP)
    assert ok.success and ok.converged and not capped.success
    assert [s.value for s in SolverStatus] == [0, 1, 2, 3, 4]


def test_a_stall_names_the_precision_floor(rough):
    """Heights 1e3 rms above their datum: the residual floors near 1e-12, tol 1e-14 stalls and
    the message says that tol is below the attainable precision."""
    h = rough(64, seed=1) + 1e3
    res = solve_contact(
        h, 1.0, 1.0, 1.0, mean_pressure=0.04, options=SolverOptions(tol=1e-14, stall_window=20)
    )
    assert res.status == SolverStatus.STALLED
    assert "tolerance_below_precision" in res.extra["stall_causes"]
    assert "below the attainable precision" in res.message and "subtract the mean" in res.message


def test_stall_causes_detect_outliers_and_full_contact(rough):
    from asperity.bem.normal.problem import set_up_problem

    h = rough(64, seed=2)
    spiked = h.copy()
    spiked[10, 20] += 40 * h.std()  # one pixel far outside the height distribution
    opts = SolverOptions()
    for heights, fraction, expected in (
        (spiked, 0.1, ["outlier_pixels"]),
        (h, 0.95, ["near_full_contact"]),
        (h, 0.1, []),
    ):
        problem = set_up_problem(heights, 1.0, 1.0, 1.0, {"normal_force": 1.0}, 0.0, True, opts)
        codes = [code for code, _ in stall_causes(problem, fraction, 1e-15, 1e-8)]
        assert codes == expected
