"""The documentation builds with warnings as errors, every gallery example and tutorial executed.

Slow (two to three minutes on 2 cores: the main job runs in the Fig. 12 example and in the
tutorial). Skipped, with the reason, where the ``docs`` extra is not installed.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The import names of the ``docs`` extra's packages.
DOCS_TOOLS = (
    "sphinx",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery",
    "furo",
    "sphinx-mathjax-offline",
)
#: Gallery scripts (docs/examples) and tutorials (docs/tutorials): each must draw a figure.
EXAMPLES = sorted(
    path.stem
    for folder in ("examples", "tutorials")
    for path in (ROOT / "docs" / folder).glob("plot_*.py")
)


def _missing_tools() -> list[str]:
    return [name for name in DOCS_TOOLS if importlib.util.find_spec(name) is None]


@pytest.mark.slow
def test_docs_build_with_warnings_as_errors(tmp_path_factory: pytest.TempPathFactory) -> None:
    missing = _missing_tools()
    if missing:
        pytest.skip(
            f"the docs extra is not installed (no {', '.join(missing)}): "
            'python -m pip install -e ".[docs]"'
        )
    # kept for tests/test_docs_offline_maths.py, which checks this same site (no second build)
    tmp_path = tmp_path_factory.getbasetemp() / "docs_build"
    html = tmp_path / "html"
    command = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-E", "-q", "-b", "html"]
    # run every example even where sphinx-gallery's cache says it is unchanged
    command += ["-D", "sphinx_gallery_conf.run_stale_examples=1"]
    command += ["-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(html)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=1200, cwd=ROOT)
    assert done.returncode == 0, f"sphinx -W failed:\n{done.stderr[-6000:]}"

    # the guides, the API reference of every package and the namespace's modules
    pages = ["index", "job", "performance", "topo", "bem", "statmodel", "pipelines", "paper"]
    pages += ["DEVELOPING"]
    pages += [f"api/generated/asperity.{name}" for name in ("topo", "bem", "statmodel")]
    pages += [f"api/generated/asperity.{name}" for name in ("pipelines", "errors", "plotting")]
    for page in pages:
        assert (html / f"{page}.html").is_file(), page
    # every example ran and drew at least one figure (the paper's Figs 1, 2, 4, 5, 12, 13)
    assert len(EXAMPLES) >= 7
    for stem in EXAMPLES:
        assert (html / "_images" / f"sphx_glr_{stem}_001.png").is_file(), stem
    # an API page carries a numpy-style section rendered as such, with its units
    shear = (html / "api/generated/asperity.statmodel.shear.html").read_text("utf-8")
    assert "shear_curve" in shear and "Parameters" in shear

    # maths render offline: MathJax is in the build, and no page loads anything from a CDN
    assert (html / "_static" / "mathjax" / "tex-chtml.js").is_file()
    for page in html.rglob("*.html"):
        text = page.read_text("utf-8")
        assert "https://cdn" not in text and "mathjax@" not in text, page
    index = (html / "index.html").read_text("utf-8")
    assert "fig13_area_vs_force.png" in index  # the index is its own page, not the README
    assert (html / "_static" / "fig13_area_vs_force.png").is_file()
