"""The verdict wherever a number goes: a stamp on every figure, a header on every CSV, and
lines at the verdict's thresholds on the figures that show those quantities.

A figure of an *invalid* run carries the verdict and its first reason, whole, as the first
lines of its title (:func:`stamp_verdict`, in red), so a PNG pasted into a slide keeps it; a
run *valid, with warnings* keeps its figures plain. Every figure CSV starts with ``#`` comment lines
(:func:`csv_header`): the verdict, its first reason and where the others are. The words are
those of :func:`asperity.pipelines.stages.verdict.verdict_wording`, as in the terminal,
report.md and report.html. The verdict is the last stage of the job and is stored in
``results.h5``, so ``asperity report DIR`` redraws the same stamps.

:func:`threshold_lines` draws the verdict's limits (A_r/A_n 0.10 warning and 0.15 invalid,
misfit 0.2 and 0.7) as horizontal lines where they fall inside the axis, and names in the
axis title those that lie outside it (the axis is not stretched to show them, which would
squash the data). :func:`separate_bem_markers` keeps the non-adhesive BEM points visible
beside the adhesive ones where the two coincide.

:func:`mark_adhesive_bem` marks the cells of the adhesive BEM column of the load table
(report.md, report.html, the terminal summary) ``range-decided: <value>`` when the verdict
holds the ``bem_adhesive_range`` reason: in the full-contact regime, or where that column's
A_r/A_n reaches ~1, its values are set by the Maugis-Dugdale range h_0 (grid-sized with
``"auto"``), not by the physics of the rough contact.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from asperity.pipelines.report.numbers import plain_text
from asperity.pipelines.stages.verdict import (
    MAX_AREA_FRACTION,
    MAX_MISFIT,
    RANGE_DECIDED_REASON,
    WARN_AREA_FRACTION,
    WARN_MISFIT,
    Verdict,
    first_reason,
    verdict_wording,
)
from asperity.plotting import stamp

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Colour of each verdict's stamp and of each severity's threshold line.
COLOURS: dict[str, str] = {"invalid": "#b00000", "warnings": "#b35900", "warning": "#b35900"}

#: (value, severity) of the A_r/A_n limits of the verdict (the ``area_fraction`` reason).
AREA_FRACTION_THRESHOLDS: tuple[tuple[float, str], ...] = (
    (WARN_AREA_FRACTION, "warning"),
    (MAX_AREA_FRACTION, "invalid"),
)
#: (value, severity) of the misfit limits of the verdict (the ``misfit`` reason).
MISFIT_THRESHOLDS: tuple[tuple[float, str], ...] = (
    (WARN_MISFIT, "warning"),
    (MAX_MISFIT, "invalid"),
)


#: The prefix of an adhesive BEM cell whose value the range decides (``bem_adhesive_range``).
RANGE_DECIDED_MARK = "range-decided"


def mark_adhesive_bem(value: str, verdict: Verdict | None) -> str:
    """An adhesive BEM cell of the load table: ``range-decided: <value>`` when the verdict
    holds the ``bem_adhesive_range`` reason, else the value ("-" and "" stay as they are)."""
    codes = getattr(verdict, "codes", None) or []
    if RANGE_DECIDED_REASON not in codes or value in ("-", ""):
        return value
    return f"{RANGE_DECIDED_MARK}: {value}"


def stamp_verdict(fig: Figure, verdict: Verdict | None) -> Figure:
    """Stamp ``fig`` with the verdict and its first reason, whole (wrapped, never cut), when
    the verdict is *invalid*; a run *valid, with warnings* keeps its figures plain (the
    warnings head report.md, report.html and every CSV)."""
    if verdict is None or verdict.verdict != "invalid":
        return fig
    text = verdict_wording(verdict)
    if verdict.reasons:
        text += f". First reason: {first_reason(verdict)}"  # "INVALID (code): ..." once
        more = len(verdict.reasons) - 1
        if more:
            text += f" (+{more} more reason{'s' if more > 1 else ''} in report.md)"
    return stamp(fig, plain_text(text), color=COLOURS["invalid"])


#: Legend entries that state a model number (the effective resolution, the fitted lambda):
#: marked ``invalid:`` on an invalid run, as in the tables.
MODEL_LABELS: tuple[str, ...] = ("effective,", "fit ", "located ", "stride of least misfit")


def mark_model_labels(fig: Figure, verdict: Verdict | None) -> Figure:
    """Prefix ``invalid: `` to the legend entries of :data:`MODEL_LABELS` when the verdict
    is invalid (a figure's legend never states a plain model number on an invalid run)."""
    if getattr(verdict, "verdict", None) != "invalid":
        return fig
    for ax in fig.axes:
        legend = ax.get_legend()
        for entry in [] if legend is None else legend.get_texts():
            if entry.get_text().startswith(MODEL_LABELS):
                entry.set_text(f"invalid: {entry.get_text()}")
    return fig


def csv_header(verdict: Verdict | None) -> list[str]:
    """Comment lines (without the leading ``#``) heading a figure's CSV; none without a
    verdict stage."""
    if verdict is None:
        return []
    lines = [verdict_wording(verdict)]
    if verdict.reasons:
        lines.append(f"first reason: {first_reason(verdict)}")
        lines.append(
            f"{len(verdict.reasons)} reason(s) in all: report.md, report.html and results.h5 "
            "(group verdict)"
        )
    return lines


def threshold_lines(
    ax: Axes, quantity: str, thresholds: Sequence[tuple[float, str]]
) -> list[float]:
    """Horizontal lines at the verdict's thresholds inside the y-axis; the others named in
    the axis title. Call after the data and the axis limits are set, before the legend.

    Parameters
    ----------
    ax : Axes
        The axes, its y-axis showing ``quantity`` in its own unit (A_r/A_n, misfit: both 1).
    quantity : str
        The quantity's name in the labels, e.g. ``"A_r/A_n"``.
    thresholds : sequence of (float, str)
        (value, severity "warning" or "invalid").

    Returns
    -------
    list of float
        The values drawn as lines.
    """
    low, high = sorted(ax.get_ylim())
    drawn: list[float] = []
    outside: dict[str, list[str]] = {"above": [], "below": []}
    for value, severity in thresholds:
        word = "INVALID" if severity == "invalid" else "warning"
        if low <= value <= high:
            ax.axhline(
                value,
                color=COLOURS[severity],
                ls=(0, (5, 3)),
                lw=0.9,
                zorder=1,
                label=f"{quantity} {value:g}: {word} (verdict)",
            )
            drawn.append(value)
        else:
            outside["above" if value > high else "below"].append(f"{value:g} ({word})")
    parts = [f"{' and '.join(v)} {side}" for side, v in outside.items() if v]
    if parts:
        note = f"verdict limits of {quantity}: {'; '.join(parts)} the axis"
        title = ax.get_title()
        ax.set_title(f"{title} {note}" if title else note, fontsize=8)
    return drawn


#: Marker styles of the BEM modes where both are drawn: the non-adhesive open, larger and on
#: top, the adhesive filled and small inside it.
BEM_MARKERS: dict[str, dict[str, str | float]] = {
    "plain": {"marker": "o", "markerfacecolor": "none", "markersize": 8, "zorder": 3},
    "adhesive": {"marker": "s", "markersize": 4, "zorder": 2.5},
}


def separate_bem_markers(
    ax: Axes, labels: tuple[str, str] = ("BEM, non-adhesive", "BEM, adhesive")
) -> None:
    """Restyle the two BEM series of ``ax`` (plain lines, or error bars) by their labels
    (non-adhesive, adhesive) with :data:`BEM_MARKERS`, so neither hides the other."""
    lines = {line.get_label(): line for line in ax.get_lines()}
    for container in getattr(ax, "containers", []):
        if container.get_label() in labels and getattr(container, "lines", None):
            lines[container.get_label()] = container.lines[0]
    for label, style in zip(labels, BEM_MARKERS.values(), strict=True):
        if label in lines:
            lines[label].set(**style)
