"""The friction tests' part of the report (stage ``friction_tests``): the markdown and HTML
section with the measured-against-predicted table, one figure per test (F_x against the drive,
measured and predicted through the loading system's spring, the stick-slip jump marked) and the
friction coefficient mu(F_z) with the measured points.

Everything here reads the stored results (:class:`~asperity.pipelines.stages.friction_curves.
FrictionTestComparison` and the friction stage), so ``asperity report`` redraws it from
``results.h5``; each figure's data is written beside it as CSV. The spring's stiffness is stated
wherever the prediction is shown. Nothing is shown when the stage did not run.
"""

from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING

import numpy as np

from asperity import statmodel
from asperity.pipelines.report.figure_output import FigureTable
from asperity.pipelines.report.numbers import format_number, format_quantity, plain_text, text_unit
from asperity.pipelines.stages import stage_number
from asperity.pipelines.stages.friction_curves import FrictionTestComparison, stacked_field
from asperity.pipelines.stages.verdict import mark
from asperity.plotting import DisplayUnit, display_unit, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from asperity.pipelines.report._run import Run

__all__ = [
    "FRICTION_TEST_CAPTIONS",
    "FRICTION_TEST_FIGURES",
    "MAX_TEST_FIGURES",
    "draw_friction_coefficient",
    "draw_friction_test",
    "friction_tests_html",
    "friction_tests_section",
    "spring_text",
]

#: Tests drawn one figure each (the rest are in the table, results.h5 and the mu(F_z) figure).
MAX_TEST_FIGURES = 12


def _tests(result: Run) -> FrictionTestComparison | None:
    return getattr(result, "friction_tests", None)


def _required(result: Run) -> FrictionTestComparison:
    """The stage's result of a run that has it (the section and figures are drawn only then)."""
    tests = _tests(result)
    if tests is None:
        raise ValueError("the run has no friction_tests stage result")
    return tests


def spring_text(k: float) -> str:
    """The loading system as the report states it: its stiffness, or a rigid drive."""
    if math.isinf(k):
        return "rigid drive (no loading.drive_stiffness): drive = delta_T"
    return f"loading system k = {k:.4g} N/m (loading.drive_stiffness): drive = delta_T + F_x / k"


def _pm(value: float, u: float, unit: DisplayUnit) -> str:
    """``value +- u`` in the column's display unit (SI in: N or m); the unit is in the header."""
    if not math.isfinite(value):
        return "not reached"
    return format_number(float(unit(value)), float(unit(u)) if math.isfinite(u) else math.nan)


def _jump_text(tests: FrictionTestComparison, i: int) -> str:
    if not tests.predicted_stick_slip[i]:
        return "none (the drive holds the contact)"
    return (
        f"drop {format_quantity(tests.predicted_jump_force_drop[i], 'N')} at drive "
        f"{format_quantity(tests.predicted_jump_drive[i], 'm')}"
    )


#: The table's compared quantities: (column name, field stem, SI base unit).
_COMPARED = (
    ("F_s", "static_friction", "N"),
    ("drive at peak", "static_drive", "m"),
    ("F_d", "sliding_friction", "N"),
)


def friction_tests_table(result: Run) -> tuple[list[str], list[list[str]]]:
    """Per test: F_s, the drive at the peak and F_d, measured and predicted (+- one sigma,
    each column in one unit, named in its header), and the predicted stick-slip jump;
    predicted cells marked when the verdict is invalid."""
    tests, verdict = _required(result), getattr(result, "verdict", None)
    load_unit = text_unit(tests.normal_load, "N")
    header, units = [f"F_z ({load_unit.text})"], {}
    for label, stem, base in _COMPARED:
        values = np.concatenate(
            [getattr(tests, f"{kind}_{stem}") for kind in ("measured", "predicted")]
        )
        units[stem] = text_unit(values, base)
        header += [
            f"{label} measured ({units[stem].text})",
            f"{label} predicted ({units[stem].text})",
        ]
    header.append("stick-slip predicted")
    rows = []
    for i, load in enumerate(tests.normal_load):
        row = [format_number(float(load_unit(load)))]
        for _, stem, _ in _COMPARED:
            for kind in ("measured", "predicted"):
                cell = _pm(
                    getattr(tests, f"{kind}_{stem}")[i],
                    getattr(tests, f"{kind}_{stem}_uncertainty")[i],
                    units[stem],
                )
                row.append(mark(cell, verdict) if kind == "predicted" else cell)
        rows.append([*row, mark(_jump_text(tests, i), verdict)])
    return header, rows


def _notes(result: Run) -> list[str]:
    tests, lam = _required(result), result.mode_mixity
    if lam is None:
        raise ValueError("the run has no lambda stage result")
    source = getattr(lam, "fit_source", None) or "area"
    fitted = (
        "fitted to the "
        + {
            "area": "A_r(F_x) curves",
            "friction": "friction tests",
            "joint": "A_r(F_x) curves and friction tests jointly",
        }[source]
    )
    used = fitted if lam.fitted else "configured, not fitted"
    notes = [
        f"Prediction at lambda = {tests.mode_mixity:.4g} ({used}); "
        f"{spring_text(tests.drive_stiffness)}.",
        "Drive measured from each test's first point (start a test where the loading system "
        "begins to carry the force).",
        f"Uncertainties: {tests.uncertainty_message}.",
    ]
    friction_lambda, interval = lam.friction_mode_mixity, lam.friction_interval
    if friction_lambda is not None and interval is not None:
        low, high = interval
        notes.append(
            f"lambda from the friction tests alone: {friction_lambda:.4g} (one-sigma interval "
            f"{low:.4g}..{high:.4g}, {lam.friction_n_points} points, rms residual "
            f"{lam.friction_residual_rms:.3g} of each test's largest F_x)"
            + (" **on a bound of the search interval**" if lam.friction_at_bound else "")
            + "."
        )
    comparison = getattr(lam, "lambda_sources_comparison", None)
    if comparison:
        flag = "**Warning (lambda_sources_disagree):** " if lam.lambda_sources_disagree else ""
        notes.append(f"{flag}{comparison}.")
    notes += _bem_notes(tests)
    if tests.normal_load.size > MAX_TEST_FIGURES:
        notes.append(
            f"Figures drawn for the first {MAX_TEST_FIGURES} tests; every test is in the table, "
            "the mu(F_z) figure and results.h5 (group friction_tests)."
        )
    return notes


def _bem_notes(tests: FrictionTestComparison) -> list[str]:
    """One line per test with the shear BEM's curve through the spring (none without it)."""
    drive, slips, drop = tests.bem_static_drive, tests.bem_stick_slip, tests.bem_jump_force_drop
    if drive is None or slips is None or drop is None:
        return []
    notes = []
    for i, load in enumerate(tests.normal_load):
        if math.isfinite(drive[i]):
            jump = (
                f"a stick-slip drop of {format_quantity(drop[i], 'N')}"
                if slips[i] == 1
                else "no stick-slip jump"
            )
            notes.append(
                f"Shear BEM at {format_quantity(load, 'N')} through the same spring: peak at "
                f"drive {format_quantity(drive[i], 'm')}, {jump}."
            )
    return notes


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def friction_tests_section(result: Run) -> list[str]:
    """The report.md section of the friction tests (empty when the stage did not run)."""
    if _tests(result) is None:
        return []
    header, rows = friction_tests_table(result)
    return [
        f"## Friction tests against the model (stage {stage_number('friction_tests')})",
        "",
        _md_table(header, rows),
        "",
        *(f"- {note}" for note in _notes(result)),
        "",
    ]


def friction_tests_html(result: Run) -> str:
    """The report.html section of the friction tests ("" when the stage did not run)."""
    if _tests(result) is None:
        return ""
    header, rows = friction_tests_table(result)
    head = "".join(f"<th>{html.escape(plain_text(h))}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(plain_text(c))}</td>" for c in row) + "</tr>"
        for row in rows
    )
    items = "".join(
        f"<li>{html.escape(plain_text(n.replace('**', '')))}</li>" for n in _notes(result)
    )
    return (
        f'<h2 id="friction-tests">Friction tests against the model (stage '
        f'{stage_number("friction_tests")})</h2><div class="table"><table><thead><tr>{head}'
        f"</tr></thead><tbody>{body}</tbody></table></div><ul>{items}</ul>"
    )


def _model(tests: FrictionTestComparison, i: int, prefix: str = "model") -> statmodel.DriveCurve:
    """Test ``i``'s stored model (or, ``prefix`` "bem", shear BEM) curve as a DriveCurve again
    (delta_T = drive - F_x / k)."""
    drive, force = getattr(tests, f"{prefix}_drive")[i], getattr(tests, f"{prefix}_force")[i]
    keep = np.isfinite(drive) & np.isfinite(force)
    drive, force = drive[keep], force[keep]
    k = tests.drive_stiffness
    dts = drive - force / k if math.isfinite(k) else drive
    return statmodel.map_to_drive(dts, force, k)


def _unstable_segments(model: statmodel.DriveCurve) -> np.ndarray:
    """The model's F_x with its stable points blanked (NaN): the part a drive cannot hold."""
    unstable = ~model.stable
    shown = unstable | np.concatenate([unstable[1:], [False]])
    return np.where(shown, model.tangential_force, np.nan)


def draw_friction_test(result: Run, i: int) -> tuple[Figure, FigureTable]:
    """Test ``i``: measured F_x against the drive, the model's drive-controlled path (the jump
    drawn as a vertical drop, marked), its unstable quasi-static branch dotted, and the
    measured and predicted static peaks with their one-sigma bars."""
    tests = _required(result)
    model = _model(tests, i)
    pick = tests.point_test == i
    drive_m, force_m = tests.point_drive[pick], tests.point_force[pick]
    path_d, path_f = model.followed_path()
    end = max(float(np.nanmax(drive_m)), float(tests.measured_static_drive[i]))
    if path_d[-1] < 1.05 * end:  # beyond the model's path its last force holds (full sliding)
        path_d, path_f = np.append(path_d, 1.05 * end), np.append(path_f, path_f[-1])
    du = display_unit([end], "m")
    fu = display_unit([np.nanmax(force_m), np.nanmax(path_f)], "N")
    fig = new_figure(7, 4.5)
    ax = fig.subplots()
    ax.plot(du(drive_m), fu(force_m), ".", color="0.45", ms=3, label="measured")
    _draw_model_paths(ax, model, (path_d, path_f), 1.05 * end, du, fu)
    _draw_static_peaks(ax, tests, i, du, fu)
    table = FigureTable()
    x_col, y_col = "drive displacement (m)", "tangential force F_x (N)"
    if tests.bem_drive is not None and np.isfinite(tests.bem_drive[i]).sum() >= 2:
        bem_d, bem_f = _model(tests, i, "bem").followed_path()
        keep = bem_d <= 1.05 * end
        ax.plot(du(bem_d[keep]), fu(bem_f[keep]), "-", color="C4", lw=1,
                label="shear BEM, drive-controlled")  # fmt: skip
        table.add("all", "shear BEM drive-controlled", {x_col: bem_d, y_col: bem_f})
    table.add("all", "measured", {x_col: drive_m, y_col: force_m})
    table.add("all", "model drive-controlled", {x_col: path_d, y_col: path_f})
    table.add(
        "all",
        "model quasi-static",
        {x_col: model.drive_displacement, y_col: model.tangential_force},
    )
    _annotate_jump(ax, model, du, fu)
    _finish_test_axes(ax, tests, i, 1.05 * end, du, fu)
    return fig, table


def _draw_model_paths(ax, model, path: tuple[np.ndarray, np.ndarray], end: float, du, fu) -> None:
    """The model's drive-controlled path (solid) and its unstable branch (dotted) up to
    ``end`` (m of drive)."""
    path_d, path_f = path
    inside = path_d <= end
    ax.plot(du(path_d[inside]), fu(path_f[inside]), "-", color="C0", lw=1.6,
            label="model, drive-controlled")  # fmt: skip
    shown = model.drive_displacement <= end
    ax.plot(
        du(model.drive_displacement[shown]),
        fu(_unstable_segments(model)[shown]),
        ":",
        color="C3",
        lw=1.2,
        label="model, unstable branch" if model.stick_slip else None,
    )


def _draw_static_peaks(ax, tests, i: int, du, fu) -> None:
    """The measured and the predicted static peak of test ``i`` with their one-sigma bars."""
    ax.errorbar(
        du(tests.measured_static_drive[i]),
        fu(tests.measured_static_friction[i]),
        xerr=du(tests.measured_static_drive_uncertainty[i]),
        yerr=fu(tests.measured_static_friction_uncertainty[i]),
        fmt="s",
        color="k",
        ms=5,
        capsize=3,
        label="measured peak",
    )
    ax.errorbar(
        du(tests.predicted_static_drive[i]),
        fu(tests.predicted_static_friction[i]),
        xerr=du(np.nan_to_num(tests.predicted_static_drive_uncertainty[i])),
        yerr=fu(np.nan_to_num(tests.predicted_static_friction_uncertainty[i])),
        fmt="D",
        color="C2",
        ms=5,
        capsize=3,
        label="predicted peak",
    )


def _annotate_jump(ax, model, du, fu) -> None:
    """The first stick-slip jump's force drop, beside it (none without a jump)."""
    if not model.jumps:
        return
    jump = model.jumps[0]
    ax.annotate(
        f"stick-slip: drop {format_quantity(jump.force_drop, 'N')}",
        (du(jump.drive_displacement), fu(0.5 * (jump.force_before + jump.force_after))),
        xytext=(8, 0),
        textcoords="offset points",
        fontsize=8,
        color="C3",
    )


def _finish_test_axes(ax, tests, i: int, end: float, du, fu) -> None:
    """Limits, labels with units, the load, spring and lambda in the title, the legend."""
    ax.set_xlim(0, float(du(end)))
    ax.set_ylim(0, None)
    ax.set_xlabel(du.label("drive displacement"))
    ax.set_ylabel(fu.label("tangential force $F_x$"))
    k = tests.drive_stiffness
    spring = "rigid drive" if math.isinf(k) else f"$k$ = {k:.4g} N/m"
    ax.set_title(
        f"$F_z$ = {tests.normal_load[i]:.4g} N, {spring}, $\\lambda$ = {tests.mode_mixity:.3g}",
        fontsize=10,
    )
    ax.legend(fontsize=7, loc="lower right")


def draw_friction_coefficient(result: Run) -> tuple[Figure, FigureTable]:
    """mu(F_z): the model's static and sliding friction coefficients at the configured loads
    (F_s / F_z with its bars, F_d / F_z) and the measured tests' points with theirs."""
    tests, fr = _required(result), result.friction
    if fr is None:
        raise ValueError("the run has no friction stage result")
    load = np.asarray(fr.normal_load, dtype=np.float64)
    fig = new_figure(6.5, 4.5)
    ax = fig.subplots()
    mu_s = stacked_field(fr, "static_friction") / load
    mu_u = fr.static_friction_coefficient_uncertainty
    ax.errorbar(
        load,
        mu_s,
        yerr=None if mu_u is None else np.nan_to_num(mu_u),
        fmt="-o",
        color="C0",
        ms=4,
        capsize=3,
        label="model $\\mu_s = F_s/F_z$",
    )
    mu_d = stacked_field(fr, "sliding_friction") / load
    ax.plot(load, mu_d, "--o", color="C1", ms=4, mfc="none", label="model $\\mu_d = F_d/F_z$")
    fz = tests.normal_load
    ax.errorbar(
        fz,
        tests.measured_static_friction / fz,
        yerr=tests.measured_static_friction_uncertainty / fz,
        fmt="s",
        color="k",
        capsize=3,
        label="measured $F_s/F_z$",
    )
    ax.errorbar(
        fz,
        tests.measured_sliding_friction / fz,
        yerr=tests.measured_sliding_friction_uncertainty / fz,
        fmt="s",
        color="k",
        mfc="none",
        capsize=3,
        label="measured $F_d/F_z$",
    )
    ax.set_xlabel("normal load $F_z$ (N)")
    ax.set_ylabel("friction coefficient $\\mu$ (1)")
    ax.set_ylim(0, None)
    k = tests.drive_stiffness
    spring = "rigid drive" if math.isinf(k) else f"$k$ = {k:.4g} N/m"
    ax.set_title(f"{spring}, $\\lambda$ = {tests.mode_mixity:.3g}", fontsize=10)
    ax.legend(fontsize=7)
    table = FigureTable()
    table.add("all", "model", {"F_z (N)": load, "mu_s (1)": mu_s, "mu_d (1)": mu_d})
    table.add(
        "all",
        "measured",
        {
            "F_z (N)": fz,
            "mu_s (1)": tests.measured_static_friction / fz,
            "mu_d (1)": tests.measured_sliding_friction / fz,
        },
    )
    return fig, table


def _test_drawer(i: int):
    def draw(result: Run) -> tuple[Figure, FigureTable]:
        return draw_friction_test(result, i)

    return draw


def _has_test(i: int):
    def present(result: Run) -> bool:
        tests = _tests(result)
        return tests is not None and tests.normal_load.size > i

    return present


#: The friction tests' figures: name -> (file stem, drawing function, whether the run has it),
#: the form of :data:`asperity.pipelines.report.figures.FIGURES`; one per test (up to
#: :data:`MAX_TEST_FIGURES`) and the friction coefficient.
FRICTION_TEST_FIGURES = {
    **{
        f"friction_test_{i + 1}": (f"friction_test_{i + 1}", _test_drawer(i), _has_test(i))
        for i in range(MAX_TEST_FIGURES)
    },
    "friction_coefficient": ("friction_coefficient", draw_friction_coefficient, _has_test(0)),
}

#: Their captions (the form of :data:`asperity.pipelines.report.text.CAPTIONS`).
FRICTION_TEST_CAPTIONS: dict[str, str] = {
    **{
        f"friction_test_{i + 1}": f"Stage {stage_number('friction_tests')}: friction test "
        f"{i + 1}, measured F_x against the drive (dots) and the model through the loading "
        "system's spring (its k in the title; solid: the path a forward drive follows, with the "
        "stick-slip drop; dotted: the branch it cannot hold), the measured and predicted peaks "
        "± one sigma."
        for i in range(MAX_TEST_FIGURES)
    },
    "friction_coefficient": f"Stage {stage_number('friction_tests')}: friction coefficient "
    "against normal load, the model's mu_s = F_s/F_z (± one sigma) and mu_d = F_d/F_z, with "
    "the measured tests' points.",
}
