"""Plotting helpers shared by every asperity figure: no backend is ever forced.

Every figure of the library is a :class:`matplotlib.figure.Figure` built with
:func:`new_figure` and written with :func:`save_figure`; neither touches ``matplotlib.pyplot``
nor ``matplotlib.use``, so importing or calling asperity in a notebook leaves the user's
backend as it was. Axis units are chosen from the data with :func:`display_unit` (SI prefixes:
a 10 um map is drawn in um, not in "mm x 1e-2"); an axis whose data span a decade or more is
logarithmic with plain-number ticks (:func:`spans_decades`, :func:`log_axis`,
:func:`auto_log_scale`, :func:`plain_log_ticks`). This is the one module of shared styling:
the figures of ``topo``, ``statmodel`` and the pipeline's report (``pipelines.report.figures``)
use it.
:func:`layout_problems` lists overlapping or clipped text of a drawn figure (used by the tests).

This module imports matplotlib only inside its functions, so importing it is cheap.
"""

from __future__ import annotations

import contextlib
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from asperity.atomic import atomic_output

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.axis import Axis
    from matplotlib.figure import Figure

#: Resolution of raster output (PNG), dots per inch.
DEFAULT_DPI = 150

#: SI prefixes by power of ten (engineering steps only: no centi, no deci).
SI_PREFIXES: dict[int, str] = {
    -15: "f",
    -12: "p",
    -9: "n",
    -6: "\u00b5",
    -3: "m",
    0: "",
    3: "k",
    6: "M",
    9: "G",
}

#: The display value of the largest datum is kept nearest to 10**1.5 (~32) on a log scale:
#: for a unit to the first power that means 1 <= value < 1000.
_TARGET_LOG10 = 1.5
_TIE_BREAK = 1e-9

#: Digits and minus as Unicode superscripts (the plain-text unit of :class:`DisplayUnit`).
_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


@dataclass(frozen=True)
class DisplayUnit:
    """An SI-prefixed unit to draw data in.

    Attributes
    ----------
    factor : float
        Multiply values in the SI unit by this to get values in the display unit
        (e.g. 1e6 to draw metres in micrometres).
    symbol : str
        The unit as matplotlib text, e.g. ``"µm"``, ``"mm$^{2}$"``, ``"mm$^{-2}$"``, ``"mN"``.
    """

    factor: float
    symbol: str

    def label(self, quantity: str) -> str:
        """Axis label ``"quantity (unit)"``; ``quantity`` may hold mathtext."""
        return f"{quantity} ({self.symbol})" if self.symbol else quantity

    def __call__(self, values: ArrayLike) -> np.ndarray:
        """The values (SI unit) in the display unit."""
        return np.asarray(values, dtype=float) * self.factor

    @property
    def text(self) -> str:
        """The unit as plain text for tables and reports: ``"µm"``, ``"mm²"``, ``"mm⁻²"``."""
        return re.sub(
            r"\$\^\{(-?\d+)\}\$", lambda m: m.group(1).translate(_SUPERSCRIPTS), self.symbol
        )


def _unit_symbol(prefix: str, base: str, power: int) -> str:
    if power == 1:
        return f"{prefix}{base}"
    return f"{prefix}{base}$^{{{power}}}$"


def display_unit(values: ArrayLike, base: str, power: int = 1) -> DisplayUnit:
    """Choose the SI prefix of ``base**power`` that draws ``values`` with readable numbers.

    The prefix applies to the base unit before the power (areas in mm^2, densities in mm^-2,
    as in the paper). The largest finite magnitude is brought nearest to 10**1.5 on a log
    scale, so lengths and forces read 1 to 999 (0.0120 mm becomes 12.0 um; 3.1e-3 N becomes
    3.1 mN) and areas 0.03 to 3e4 of their unit.

    Parameters
    ----------
    values : array_like
        The data in the SI unit ``base**power`` (e.g. m, N, m^2, 1/m^2).
    base : str
        The SI base unit symbol, e.g. ``"m"``, ``"N"``, ``"Pa"``.
    power : int
        Its power: 1 for lengths and forces, 2 for areas, -2 for densities per area.

    Returns
    -------
    DisplayUnit
        The factor and the symbol; the plain SI unit when no value is finite and non-zero.
    """
    if power == 0:
        raise ValueError("display_unit: power must be non-zero (a dimensionless value has no unit)")
    magnitudes = np.abs(np.asarray(values, dtype=float)).ravel()
    magnitudes = magnitudes[np.isfinite(magnitudes) & (magnitudes > 0)]
    if magnitudes.size == 0:
        return DisplayUnit(1.0, _unit_symbol("", base, power))
    largest = math.log10(float(magnitudes.max()))
    # the tiny shift breaks ties upwards: 1e-3 m is 1 mm, not 1000 um
    exponent = min(SI_PREFIXES, key=lambda e: abs(largest - e * power - _TARGET_LOG10 + _TIE_BREAK))
    symbol = _unit_symbol(SI_PREFIXES[exponent], base, power)
    return DisplayUnit(10.0 ** (-exponent * power), symbol)


def new_figure(width: float, height: float) -> Figure:
    """A blank figure of ``width`` x ``height`` inches with matplotlib's constrained layout.

    The layout engine places titles, labels and legends so that they neither overlap nor get
    clipped. The figure is not registered with pyplot: it needs no closing and shows in a
    notebook only when the user displays it.
    """
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height), layout="constrained")


#: Data spanning at least this ratio are drawn on a log axis.
LOG_SPAN = 10.0


def spans_decades(values: ArrayLike) -> bool:
    """Positive finite data whose largest and smallest differ by :data:`LOG_SPAN` or more."""
    v = np.asarray(values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    return v.size > 1 and bool(np.all(v > 0)) and v.max() >= LOG_SPAN * v.min()


def log_axis(ax: Axes, which: str, values: ArrayLike | None = None) -> None:
    """A log axis (``which`` "x" or "y") labelled at 1, 2, 5 x 10^k (1 x 10^k beyond 3 decades
    of ``values``) in plain numbers; no minor tick labels (they overprint)."""
    getattr(ax, f"set_{which}scale")("log")
    v = np.asarray(values if values is not None else [1.0, 1e6], dtype=float).ravel()
    v = v[np.isfinite(v) & (v > 0)]
    decades = np.log10(v.max() / v.min()) if v.size else 6.0
    plain_log_ticks(getattr(ax, f"{which}axis"), (1.0, 2.0, 5.0) if decades < 3 else (1.0,))


def plain_log_ticks(axis: Axis, subs: tuple[float, ...] = (1.0, 2.0, 5.0)) -> None:
    """Major ticks of a log ``axis`` at ``subs`` x 10^k, written as plain numbers (0.002, 50,
    1e+06); no minor tick labels (they overprint)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    axis.set_major_locator(LogLocator(base=10, subs=subs))
    axis.set_major_formatter(FuncFormatter(_tick_text))
    axis.set_minor_formatter(NullFormatter())


def _tick_text(value: float, _position: float | None) -> str:
    """A log-axis tick as a short number (0.002, 50, 1e+06)."""
    return f"{value:g}"


def auto_log_scale(ax: Axes, x: ArrayLike, y: ArrayLike) -> None:
    """Log axes (:func:`log_axis`) where the plotted data ``x``, ``y`` span decades."""
    if spans_decades(x):
        log_axis(ax, "x", x)
    if spans_decades(y):
        log_axis(ax, "y", y)


#: Characters per inch of figure width of a 9 pt stamp line (a safe under-estimate).
_STAMP_CHARS_PER_INCH = 13


def stamp(fig: Figure, text: str, *, color: str = "#b00000", fontsize: float = 9) -> Figure:
    """Put ``text`` at the top of ``fig``, above any title it has, so that it travels with
    every copy of the picture (a PNG pasted into a slide keeps it).

    The text becomes the first lines of the figure's suptitle (placed by the constrained
    layout, so it never overlaps the axes), wrapped at word boundaries to the figure's width
    and never cut: every word of ``text`` is drawn. An existing suptitle follows on its own
    line.

    Parameters
    ----------
    fig : Figure
        The drawn figure (from :func:`new_figure`).
    text : str
        One sentence, e.g. a verdict and its first reason.
    color : str
        Colour of the stamp (matplotlib colour).
    fontsize : float
        Font size of the stamp, points.

    Returns
    -------
    Figure
        ``fig``, stamped.
    """
    import textwrap

    width = max(20, int(fig.get_figwidth() * _STAMP_CHARS_PER_INCH * 9 / fontsize))
    lines = textwrap.wrap(text, width, break_long_words=False, break_on_hyphens=False)
    existing = fig.get_suptitle()
    fig.suptitle(
        "\n".join([*lines, existing] if existing else lines), color=color, fontsize=fontsize
    )
    return fig


def legend_below(ax: Axes, *, gap: float = 0.55, **kwargs: object) -> object:
    """The legend of ``ax`` outside it, centred under its x-axis label, so that it hides no
    point, curve or tick; the constrained layout makes room for it.

    Parameters
    ----------
    ax : Axes
        The axes whose labelled artists are listed.
    gap : float
        Distance from the axes' bottom edge to the legend's top, inches (clears the tick labels
        and the axis label).
    **kwargs
        Passed to :meth:`matplotlib.axes.Axes.legend` (``fontsize``, ``ncols``, ...).

    Returns
    -------
    matplotlib.legend.Legend
        The legend drawn.
    """
    from matplotlib.transforms import ScaledTranslation

    fig = ax.get_figure()
    assert fig is not None, "the axes belong to a figure"
    shift = ScaledTranslation(0.0, -gap, fig.dpi_scale_trans)
    kwargs.setdefault("fontsize", 8)
    return ax.legend(
        loc="upper center", bbox_to_anchor=(0.5, 0.0), bbox_transform=ax.transAxes + shift, **kwargs
    )


def save_figure(fig: Figure, path: str | Path, *, dpi: int = DEFAULT_DPI) -> Path:
    """Write ``fig`` to ``path``; the suffix picks the format (``.png``, ``.svg``, ``.pdf``).

    Parameters
    ----------
    fig : Figure
        The figure (from :func:`new_figure`).
    path : str or Path
        The output file; its folder must exist. Written atomically
        (:func:`asperity.atomic.atomic_output`).
    dpi : int
        Resolution of raster formats, dots per inch.

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"  # named: the temporary's suffix is .tmp
    with atomic_output(path) as tmp:  # the old figure or the new one, never a truncated file
        fig.savefig(tmp, dpi=dpi, format=fmt)
    return path


def _drawn_texts(fig: Figure) -> tuple[list, object]:
    """Lay out ``fig`` (Agg metrics, nothing rasterised); return the texts drawn and the renderer.

    Only texts the figure actually draws are returned (tick labels outside the view limits
    exist as artists but are not drawn).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    renderer = FigureCanvasAgg(fig).get_renderer()
    drawn: list = []

    def record_text(gc, x, y, s, prop, angle, ismath=False, mtext=None) -> None:  # noqa: ANN001
        if mtext is not None and s.strip() and all(mtext is not t for t in drawn):
            drawn.append(mtext)

    # matplotlib's own way to run a draw for sizes only (as in savefig); optional API
    no_drawing = getattr(renderer, "_draw_disabled", contextlib.nullcontext)
    with no_drawing():
        renderer.draw_text = record_text
        fig.draw(renderer)
    return drawn, renderer


def _overlap(a, b) -> bool:  # noqa: ANN001
    """Two display boxes intersect by more than one pixel each way."""
    return min(a.x1, b.x1) - max(a.x0, b.x0) > 1 and min(a.y1, b.y1) - max(a.y0, b.y0) > 1


def layout_problems(fig: Figure) -> list[str]:
    """Texts of a figure that overlap each other or stick out of the figure, once drawn.

    Checks every text the renderer draws: titles, axis labels, tick labels, legend entries,
    annotations. Two texts overlap when their boxes intersect by more than one pixel each way;
    a text is clipped when its box leaves the figure by more than one pixel.

    Parameters
    ----------
    fig : Figure
        The figure to check; it is drawn here with the Agg renderer (the backend is not
        changed).

    Returns
    -------
    list of str
        One line per problem, e.g. ``"overlap: 'F_x (N)' and '0.8'"``; empty when the layout
        is clean.
    """
    texts, renderer = _drawn_texts(fig)
    page = fig.bbox.padded(1.0)
    boxes = [(text.get_text(), text.get_window_extent(renderer)) for text in texts]
    problems = [
        f"clipped: {name!r}"
        for name, box in boxes
        if box.x0 < page.x0 or box.y0 < page.y0 or box.x1 > page.x1 or box.y1 > page.y1
    ]
    for i, (first, a) in enumerate(boxes):
        problems += [
            f"overlap: {first!r} and {second!r}" for second, b in boxes[i + 1 :] if _overlap(a, b)
        ]
    return problems
