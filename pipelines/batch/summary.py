"""The across-maps summary of a batch: ``summary.csv`` and ``summary.png``.

``summary.csv``: one row per map (``map``, ``folder``, ``status``, ``message``, then the
numbers of :func:`pipelines.batch.summary_values`, SI units in the headers), then a ``mean``
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
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from asperity.atomic import open_atomic
from asperity.plotting import display_unit, log_axis, new_figure, save_figure, spans_decades, stamp

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: Text columns among the values (no mean or std).
TEXT_COLUMNS = ("verdict", "validity")


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
        if name in TEXT_COLUMNS:
            continue
        v = column_values(sound, name)
        v = v[np.isfinite(v)]
        mean[name] = float(v.mean()) if v.size else np.nan
        spread[name] = float(v.std(ddof=1)) if v.size > 1 else np.nan
    left_out = sum("values" in r for r in records) - len(sound)
    note = f"; {left_out} invalid or unconverged map(s) left out" if left_out else ""
    mean["message"] = spread["message"] = f"over {len(sound)} maps with status ok{note}"
    return mean, spread


def _cell(value: object) -> str:
    if isinstance(value, float):
        return "" if not np.isfinite(value) else repr(value)
    return "" if value is None else str(value)


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
    rows = [{**{k: r.get(k, "") for k in LEAD_COLUMNS}, **r.get("values", {})} for r in records]
    rows += list(_statistics(records, columns))
    with open_atomic(path, "w", newline="", encoding="utf-8") as handle:
        for line in summary_header(records):
            handle.write(f"# {' '.join(line.split())}\n")
        writer = csv.writer(handle)
        writer.writerow([*LEAD_COLUMNS, *columns])
        for row in rows:
            writer.writerow([_cell(row.get(name, "")) for name in (*LEAD_COLUMNS, *columns)])
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
        m = unit(good.mean())
        ax.axhline(m, color="k", lw=1)
        if good.size > 1:
            s = unit(good.std(ddof=1))
            low = m - s if m - s > 0 or not spans_decades(good) else unit(good.min()) / 2
            ax.axhspan(low, m + s, color="0.85", zorder=0)
    if spans_decades(good):
        log_axis(ax, "y", unit(good))
    ax.set_xlabel("map")
    ax.set_ylabel(unit.label(name.rsplit(" (", 1)[0]), fontsize=8)
    ax.set_xticks(index)


def _per_load_panel(ax: Axes, records: list[MapRecord], prefix: str, base: str) -> None:
    """A per-load quantity against F_z, one line per map."""
    columns = [c for c in numeric_columns(records) if c.startswith(prefix)]
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
