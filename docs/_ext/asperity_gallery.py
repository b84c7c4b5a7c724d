"""sphinx-gallery helpers for asperity's examples: a scraper for plain Figure objects.

asperity never touches ``matplotlib.pyplot`` (its figures are :class:`matplotlib.figure.Figure`
objects made by :func:`asperity.plotting.new_figure`), so sphinx-gallery's default scraper, which
walks pyplot's figure list, sees none of them. :func:`asperity_figure_scraper` instead looks
for Figure objects in the example's namespace after each code block: a variable holding a
Figure, or a tuple, list or dict holding some (``fig, table = draw_resolution(run)``). Each
Figure is drawn once, in the block that first made it visible. The names are referred to as
strings in ``conf.py`` (``"asperity_gallery.asperity_figure_scraper"``) so that Sphinx can
cache the configuration.
"""

from __future__ import annotations

from pathlib import PurePosixPath
from typing import Any

from sphinx_gallery.scrapers import figure_rst, matplotlib_scraper

#: ids of the Figures already written for the example being executed.
_SEEN: set[int] = set()
#: Keeps those Figures alive so that their ids are not reused within one example.
_KEPT: list[Any] = []


def _figures_in(value: Any, depth: int = 0) -> list[Any]:
    """The Figures held by ``value`` (itself, or inside containers up to two levels deep)."""
    from matplotlib.figure import Figure

    if isinstance(value, Figure):
        return [value]
    if depth >= 2:
        return []
    if isinstance(value, dict):
        items = list(value.values())
    elif isinstance(value, list | tuple):
        items = list(value)
    else:
        return []
    return [fig for item in items for fig in _figures_in(item, depth + 1)]


def _new_figures(namespace: dict[str, Any]) -> list[Any]:
    """Figures of ``namespace`` not yet written, in the order their names were bound."""
    found = []
    for name, value in namespace.items():
        if name.startswith("__"):
            continue
        for fig in _figures_in(value):
            if id(fig) not in _SEEN:
                _SEEN.add(id(fig))
                _KEPT.append(fig)
                found.append(fig)
    return found


def asperity_figure_scraper(block: Any, block_vars: dict[str, Any], gallery_conf: Any) -> str:
    """Write the example's new Figure objects as PNGs and return the reST that shows them.

    pyplot figures, if an example makes any, are handed to sphinx-gallery's own scraper.
    """
    paths = []
    for fig, path in zip(
        _new_figures(block_vars["example_globals"]),
        block_vars["image_path_iterator"],
        strict=False,
    ):
        fig.savefig(path, dpi=100)
        paths.append(PurePosixPath(path))
    rst = figure_rst(paths, gallery_conf["src_dir"]) if paths else ""
    return rst + matplotlib_scraper(block, block_vars, gallery_conf)


def reset_figures(gallery_conf: Any, fname: str) -> None:
    """Forget the previous example's Figures (called before each example)."""
    _SEEN.clear()
    _KEPT.clear()
