"""The across-maps summary of a batch: ``summary.csv`` and ``summary.png``.

``summary.csv``: one row per map (``map``, ``folder``, ``status``, ``message``, then the
numbers of :func:`summary_values`, SI units in the headers, each predicted quantity with its
``<quantity> uncertainty (unit)`` column (full precision) and its ``<quantity> written (unit)``
column (text: the value and its uncertainty as the report writes them, ``0.300 ± 0.024``),
and the ``verdict`` column; every number of a map whose
verdict is invalid is written ``invalid: 4389.5``, text that no spreadsheet reads as a
number), then a ``mean``
and a ``std`` row (sample standard deviation, ddof = 1) over the maps whose result the
verdict stands behind (status "ok"): an invalid or unconverged map is listed but never
averaged in. The file opens with ``#`` comment lines (:func:`summary_header`): how many maps
are ok, invalid, not converged or failed, and each such map with its first reason (read it
with ``pandas.read_csv(path, comment="#")``). ``summary.png``: each quantity against the map
number, with the mean (line) and mean +- std (band) over the maps with status "ok", as in the
CSV; invalid and unconverged maps drawn as red crosses, and the figure stamped with their
number when there are any.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from asperity.atomic import open_atomic
from asperity.plotting import display_unit, log_axis, new_figure, save_figure, spans_decades, stamp

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from asperity.pipelines.job import JobResult
    from asperity.pipelines.stages.friction import FrictionPrediction

#: Text columns among the values (no mean or std).
TEXT_COLUMNS = ("verdict", "validity")
#: The word that heads each number of an invalid map in summary.csv ("invalid: 4389.5"): text
#: a spreadsheet cannot read as a number (docs/pipelines.md).
INVALID_MARK = "invalid"


def _at(values: object, i: int) -> float:
    """Element ``i`` of an optional per-load array (NaN when absent)."""
    return float("nan") if values is None else float(np.asarray(values, dtype=float)[i])


#: Ends the name of a column of text: a quantity written with its uncertainty, as the
#: terminal summary, report.md and report.html write it ("static friction at F_z=1 N written
#: (N)": "0.300 ± 0.024").
WRITTEN = " written ("


def is_text_column(name: str) -> bool:
    """A column of text (no mean or std): :data:`TEXT_COLUMNS` and the written forms."""
    return name in TEXT_COLUMNS or WRITTEN in name


def _stacked(friction: FrictionPrediction, name: str, i: int) -> float:
    """Load ``i`` of a per-load field that :func:`asperity.fields.stacked` adds to the friction
    result from :class:`asperity.statmodel.ShearCurve` (set at import: unseen by a type
    checker)."""
    return float(getattr(friction, name)[i])


def _with_uncertainty(
    values: dict[str, float | str],
    name: str,
    value: float,
    uncertainty: float,
    lower_bound: bool = False,
) -> None:
    """``values[name] = value`` (SI, full precision) and, beside it,
    ``values[<name> uncertainty (<unit>)]`` and ``values[<name> written (<unit>)]``: the value
    with its uncertainty in the digits the uncertainty supports, in the column's unit
    (:func:`asperity.pipelines.report.numbers.format_number`; ``± ?`` where u is unknown)."""
    from asperity.pipelines.report.numbers import format_number  # matplotlib-free, report's

    quantity, _, unit = name.rpartition(" (")
    values[name] = float(value)
    values[f"{quantity} uncertainty ({unit}"] = float(uncertainty)
    values[f"{quantity}{WRITTEN}{unit}"] = format_number(
        float(value), float(uncertainty), lower_bound=lower_bound
    )


def verdict_text(result: object) -> str:
    """The run's verdict word ("valid", "warnings", "invalid"; "" without a verdict), found
    as report.html finds it (:func:`asperity.pipelines.report.html.find_verdict`)."""
    from asperity.pipelines.report.html import find_verdict  # matplotlib: only when summarised

    verdict = find_verdict(result)
    if verdict is None:
        return ""
    for name in ("verdict", "status", "summary"):
        value = getattr(verdict, name, None)
        if isinstance(value, str | int | bool):
            return str(value)
    return ""


def summary_values(result: JobResult) -> dict[str, float | str]:
    """The summary numbers of one run (SI; column names carry the units), each predicted
    quantity followed by its ``<quantity> uncertainty (unit)`` column (NaN where the model could not
    estimate it), then ``verdict`` and ``validity``. A run stopped where its verdict was known
    (:mod:`asperity.pipelines.stages.early_verdict`) has no model numbers: only its verdict."""
    verdict = getattr(result, "verdict", None)
    res, fr, lam = result.statistical_model, result.friction, result.mode_mixity
    if res is None or fr is None or lam is None:
        reasons = "; ".join(getattr(verdict, "reasons", []) or [])
        return {"verdict": verdict_text(result), "validity": reasons}
    interval = getattr(res, "optimum_interval", None)
    resolution_u = (
        float(np.ptp(interval)) / 2
        if interval is not None and np.all(np.isfinite(interval))
        else float("nan")
    )
    values: dict[str, float | str] = {}
    _with_uncertainty(values, "effective resolution (m)", res.effective_resolution, resolution_u)
    values["asperity density eta (1/m^2)"] = float(res.asperity_density)
    values["summit radius R (m)"] = float(res.summit_radius)
    values["rms summit height sigma_s (m)"] = float(res.summit_height_rms)
    lam_u = lam.mode_mixity_std if lam.mode_mixity_std is not None else float("nan")
    _with_uncertainty(values, "mode mixity lambda (1)", lam.mode_mixity, lam_u)
    low = bool(getattr(fr, "uncertainty_lower_bound", False))
    for i, load in enumerate(fr.normal_load):
        at = f"at F_z={load:.6g} N"
        area_u = _at(fr.model_real_area_uncertainty, i) / res.nominal_area
        area = float(res.real_area[res.index, i] / res.nominal_area)
        _with_uncertainty(values, f"A_r/A_n {at} (1)", area, area_u, low)
        static_u = _at(fr.static_friction_uncertainty, i)
        static = _stacked(fr, "static_friction", i)
        _with_uncertainty(values, f"static friction {at} (N)", static, static_u, low)
        sliding_u = _at(fr.sliding_friction_uncertainty, i)
        sliding = _stacked(fr, "sliding_friction", i)
        _with_uncertainty(values, f"sliding friction {at} (N)", sliding, sliding_u, low)
    values["verdict"] = verdict_text(result)
    values["validity"] = "; ".join(res.validity) or "within the model's assumptions"
    return values


class MapRecord(TypedDict, total=False):
    """One map's record in a batch (:func:`asperity.pipelines.batch.run_one_map`).

    ``map`` and ``folder`` are paths as text; ``status`` is "ok", "not converged", "invalid" or
    "failed"; ``message`` says why; ``values`` holds the summary numbers (SI, the column names
    carry the units) and the verdict and validity text; ``computed`` names the stages computed
    (not taken from results.h5); ``traceback`` is kept for a failed map.
    """

    map: str
    folder: str
    status: str
    message: str
    values: dict[str, float | str]
    computed: list[str]
    traceback: str


#: Columns before the numbers.
LEAD_COLUMNS = ("map", "folder", "status", "message")


def numeric_columns(records: list[MapRecord]) -> list[str]:
    """Every value column of the finished runs, in first-seen order (numbers, then the
    :data:`TEXT_COLUMNS` where present)."""
    columns: dict[str, None] = {}
    for record in records:
        for name in record.get("values", {}):
            columns.setdefault(name, None)
    return list(columns)


def column_values(records: list[MapRecord], name: str) -> np.ndarray:
    """One column over the finished runs (NaN where a run lacks it)."""
    return np.array(
        [float(r["values"].get(name, np.nan)) for r in records if "values" in r], dtype=float
    )


def _statistics(
    records: list[MapRecord], columns: list[str]
) -> tuple[dict[str, str | float], dict[str, str | float]]:
    mean: dict[str, str | float] = {"map": "mean"}
    spread: dict[str, str | float] = {"map": "std"}
    sound = [r for r in records if r["status"] == "ok"]
    for name in columns:
        if is_text_column(name):
            continue
        v = column_values(sound, name)
        v = v[np.isfinite(v)]
        mean[name] = float(v.mean()) if v.size else np.nan
        spread[name] = float(v.std(ddof=1)) if v.size > 1 else np.nan
    left_out = sum("values" in r for r in records) - len(sound)
    note = f"; {left_out} invalid or unconverged map(s) left out" if left_out else ""
    mean["message"] = spread["message"] = f"over {len(sound)} maps with status ok{note}"
    return mean, spread


def _cell(value: object, invalid: bool = False, written: bool = False) -> str:
    """A CSV cell: a number as ``repr`` ("" for NaN), marked ``invalid: <number>`` on a map
    whose verdict is invalid (never a bare number a spreadsheet would average); a ``written``
    value (text) marked the same way."""
    if isinstance(value, float | int) and not isinstance(value, bool):
        if not np.isfinite(value):
            return ""
        return f"{INVALID_MARK}: {value!r}" if invalid else repr(float(value))
    text = "" if value is None else str(value)
    return f"{INVALID_MARK}: {text}" if invalid and written and text else text


#: Map statuses the summary counts, in the order its header names them.
STATUSES: tuple[str, ...] = ("ok", "invalid", "not converged", "failed")


def summary_header(records: list[MapRecord]) -> list[str]:
    """Comment lines (without ``# ``) heading summary.csv: the count per status and each map
    that is not ok with its status and first reason."""
    counts = {s: sum(r.get("status") == s for r in records) for s in STATUSES}
    lines = [
        f"asperity batch summary of {len(records)} map(s): "
        + ", ".join(f"{n} {'INVALID' if s == 'invalid' else s}" for s, n in counts.items() if n)
    ]
    flagged = [r for r in records if r.get("status") != "ok"]
    if flagged:
        lines.append("maps not ok are listed but left out of the mean and std rows:")
    for r in flagged:
        status = "INVALID" if r["status"] == "invalid" else r["status"]
        first = str(r.get("message", "")).split("; ")[0]
        lines.append(f"{Path(str(r['map'])).name}: {status}" + (f": {first}" if first else ""))
    return lines


def write_summary_csv(records: list[MapRecord], path: Path) -> Path:
    """The :func:`summary_header` comments, one row per map, then the mean and std rows."""
    columns = numeric_columns(records)
    rows: list[Mapping[str, object]] = [
        {**{k: r.get(k, "") for k in LEAD_COLUMNS}, **r.get("values", {})} for r in records
    ]
    rows += list(_statistics(records, columns))
    with open_atomic(path, "w", newline="", encoding="utf-8") as handle:
        for line in summary_header(records):
            handle.write(f"# {' '.join(line.split())}\n")
        writer = csv.writer(handle)
        writer.writerow([*LEAD_COLUMNS, *columns])
        for row in rows:
            invalid = row.get("status") == "invalid"  # the mean and std rows have no status
            writer.writerow(
                [
                    _cell(row.get(name, ""), invalid, WRITTEN in name)
                    for name in (*LEAD_COLUMNS, *columns)
                ]
            )
    return path


def _panel(ax: Axes, records: list[MapRecord], name: str, base: str, power: int) -> None:
    """One quantity against the map number: points, mean line, mean +- std band."""
    values = column_values(records, name)
    unit = display_unit(values, base, power)
    index = np.arange(1, values.size + 1)
    sound = np.array([r["status"] == "ok" for r in records if "values" in r], dtype=bool)
    ax.plot(index[sound], unit(values[sound]), "o")
    if not sound.all():
        ax.plot(index[~sound], unit(values[~sound]), "x", color="#b00000", label="not ok")
    good = values[sound & np.isfinite(values)]
    if good.size:
        m = float(unit(good.mean()))
        ax.axhline(m, color="k", lw=1)
        if good.size > 1:
            s = float(unit(good.std(ddof=1)))
            low = m - s if m - s > 0 or not spans_decades(good) else float(unit(good.min())) / 2
            ax.axhspan(low, m + s, color="0.85", zorder=0)
    if spans_decades(good):
        log_axis(ax, "y", unit(good))
    ax.set_xlabel("map")
    ax.set_ylabel(unit.label(name.rsplit(" (", 1)[0]), fontsize=8)
    ax.set_xticks(index)


def _per_load_panel(ax: Axes, records: list[MapRecord], prefix: str, base: str) -> None:
    """A per-load quantity against F_z, one line per map."""
    columns = [
        c
        for c in numeric_columns(records)
        if c.startswith(prefix) and "uncertainty" not in c and not is_text_column(c)
    ]
    loads = np.array([float(c.split("F_z=")[1].split(" N")[0]) for c in columns])
    table = np.array([column_values(records, c) for c in columns]).T  # (map, load)
    fu = display_unit(loads, "N")
    yu = display_unit(table, base) if base else None
    for row in table:
        ax.plot(fu(loads), row if yu is None else yu(row), "o-", lw=1, ms=3)
    if spans_decades(table):
        log_axis(ax, "y", table if yu is None else yu(table))
    label = prefix.strip()
    ax.set_xlabel(fu.label("normal load $F_z$"))
    ax.set_ylabel(yu.label(label) if yu is not None else label, fontsize=8)


def write_summary_figure(records: list[MapRecord], path: Path) -> Path | None:
    """Write the summary figure (None when no map finished)."""
    if not any("values" in r for r in records):
        return None
    return save_figure(draw_summary_figure(records), path)


def draw_summary_figure(records: list[MapRecord]) -> Figure:
    """Every summary quantity against the map (top) and against F_z per map (bottom)."""
    fig = new_figure(12, 7)
    axes = fig.subplots(2, 4)
    scalars = [
        ("effective resolution (m)", "m", 1),
        ("summit radius R (m)", "m", 1),
        ("asperity density eta (1/m^2)", "m", -2),
        ("rms summit height sigma_s (m)", "m", 1),
    ]
    for ax, (name, base, power) in zip(axes[0], scalars, strict=True):
        _panel(ax, records, name, base, power)
    _per_load_panel(axes[1, 0], records, "A_r/A_n", "")
    _per_load_panel(axes[1, 1], records, "static friction", "N")
    _per_load_panel(axes[1, 2], records, "sliding friction", "N")
    values = column_values(records, "mode mixity lambda (1)")
    axes[1, 3].plot(np.arange(1, values.size + 1), values, "o")
    axes[1, 3].set_xlabel("map")
    axes[1, 3].set_ylabel("mode mixity $\\lambda$", fontsize=8)
    axes[1, 3].set_xticks(np.arange(1, values.size + 1))
    names = [Path(r["map"]).name for r in records if "values" in r]
    fig.suptitle(
        f"{len(names)} maps (numbered as in summary.csv): mean (line) +- std (band) over the "
        "maps with status ok",
        fontsize=10,
    )
    finished = [r for r in records if "values" in r]
    flagged = [str(i + 1) for i, r in enumerate(finished) if r["status"] != "ok"]
    if flagged:
        which = ", ".join(flagged)
        stamp(
            fig,
            f"{len(flagged)} of {len(names)} maps not ok (invalid verdict or not converged: "
            f"map {which}; red crosses, left out of the mean and std; reasons in summary.csv)",
        )
    return fig
