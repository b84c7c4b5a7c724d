"""Writing a report figure: every requested format, and the data behind it as one tidy CSV.

Each figure of :mod:`pipelines.report` is drawn together with a :class:`FigureTable`: one row
per plotted point, a ``panel`` and a ``series`` column, then one column per quantity with its
SI unit in the header (``"normal load F_z (N)"``). The values are the SI values of
``results.h5``, not the prefixed display values, so a CSV can be checked against the file and
re-plotted in any unit. :func:`publish` writes the figure in each format of
:class:`FigureOptions` and the CSV beside it (same stem, ``.csv``).

A table's ``header`` lines are written first, each after ``# `` (the run's verdict and its
first reason, :func:`asperity.pipelines.report.verdict_marks.csv_header`): read such a file
with ``pandas.read_csv(path, comment="#")`` or :func:`read_figure_csv`, which skip them.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from asperity.atomic import open_atomic
from asperity.plotting import DEFAULT_DPI, save_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Formats a figure can be written in (matplotlib's own writers).
FORMATS: tuple[str, ...] = ("png", "svg", "pdf")


@dataclass(frozen=True)
class FigureOptions:
    """How figures are written.

    Attributes
    ----------
    formats : tuple of str
        Any of "png", "svg", "pdf"; each figure is written once per format.
    dpi : int
        Dots per inch of PNG output (vector formats ignore it).
    """

    formats: tuple[str, ...] = ("png",)
    dpi: int = DEFAULT_DPI

    def __post_init__(self) -> None:
        from asperity.errors import InputError

        unknown = [f for f in self.formats if f not in FORMATS]
        if unknown or not self.formats:
            raise InputError(
                f"formats: expected one or more of {', '.join(FORMATS)}, got "
                f"{', '.join(self.formats) or 'none'}"
            )
        if not 30 <= int(self.dpi) <= 2400:
            raise InputError(f"dpi: expected an integer in [30, 2400], got {self.dpi}")
        object.__setattr__(self, "formats", tuple(dict.fromkeys(self.formats)))


class FigureTable:
    """The tidy data behind one figure: rows of (panel, series, quantity columns...)."""

    def __init__(self) -> None:
        self.rows: list[dict[str, object]] = []
        self.columns: list[str] = ["panel", "series"]
        self.header: list[str] = []  # comment lines written first, after "# "

    def add(self, panel: str, series: str, columns: Mapping[str, ArrayLike]) -> None:
        """Add one plotted series: columns named ``"quantity (SI unit)"``, equal lengths
        (a single value is repeated)."""
        arrays = {
            name: np.ravel(np.asarray(values, dtype=float)) for name, values in columns.items()
        }
        n = max(a.size for a in arrays.values())
        for name in arrays:
            if name not in self.columns:
                self.columns.append(name)
        for i in range(n):
            row: dict[str, object] = {"panel": panel, "series": series}
            for name, a in arrays.items():
                row[name] = a[i] if a.size == n else a[0]
            self.rows.append(row)

    def series(self, panel: str, series: str, column: str) -> np.ndarray:
        """The values of one column of one series (NaN where the row has none)."""
        return np.array(
            [
                row.get(column, np.nan)
                for row in self.rows
                if row["panel"] == panel and row["series"] == series
            ],
            dtype=float,
        )

    def write_csv(self, path: Path) -> Path:
        """Write the header comments, then the table (empty cells where a row has no such
        quantity), atomically."""
        with open_atomic(path, "w", newline="", encoding="utf-8") as handle:
            for line in self.header:
                handle.write(f"# {' '.join(line.split())}\n")
            writer = csv.writer(handle)
            writer.writerow(self.columns)
            for row in self.rows:
                writer.writerow([_cell(row.get(name, "")) for name in self.columns])
        return path


def _cell(value: object) -> str:
    if isinstance(value, float | np.floating):
        return "" if np.isnan(value) else repr(float(value))
    return str(value)


def read_figure_csv(path: str | Path) -> list[dict[str, str]]:
    """Rows of a figure CSV as dicts of strings (for checks and notebooks); the ``#`` header
    lines are skipped (:func:`read_csv_header` reads them)."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def read_csv_header(path: str | Path) -> list[str]:
    """The ``#`` comment lines heading a CSV, without the ``# ``."""
    lines = []
    with open(path, encoding="utf-8") as handle:
        for line in handle:
            if not line.startswith("#"):
                break
            lines.append(line[1:].strip())
    return lines


def publish(
    fig: Figure, table: FigureTable, path: Path, options: FigureOptions | None = None
) -> Path:
    """Write ``fig`` at ``path`` (format from its suffix), in every format of ``options``
    (same stem), and ``table`` as ``<stem>.csv``; returns ``path``."""
    options = options or FigureOptions()
    path = Path(path)
    formats = dict.fromkeys([path.suffix.lstrip(".").lower(), *options.formats])
    for fmt in formats:
        save_figure(fig, path.with_suffix(f".{fmt}"), dpi=options.dpi)
    table.write_csv(path.with_suffix(".csv"))
    return path
