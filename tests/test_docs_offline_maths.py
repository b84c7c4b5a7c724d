"""The HTML documentation typesets its maths offline: MathJax comes from the built tree itself.

Two levels of check, on a built site (``python -m sphinx -b html docs OUT``):

* **Without a browser** (:func:`offline_problems`, cheap): every page that holds maths loads a
  MathJax script, every script, stylesheet, image or frame a page loads resolves to a file inside
  the built tree (never a CDN, never a path that leaves the tree). It runs wherever the docs are
  built (the slow suite builds them once, in ``tests/test_docs_build.py``). Fast tests below check
  on small made-up trees that it catches each fault.
* **In a headless browser with no network** (:func:`check_pages_in_browser`, slow): each page with
  maths, plus the guides and an API page, is opened from ``file://`` with every http(s) request
  aborted and recorded; once MathJax's start-up has typeset the page, the page must hold one
  ``mjx-container`` per maths element and no MathJax error, no raw ``\\(``, ``\\[`` or ``$$`` may
  be left in its visible prose, MathJax's fonts must have loaded from the tree, and no request may
  have been attempted off the machine.

The browser check needs Playwright's Python package and a Chromium. Neither is a dependency of
asperity and CI has neither, so there the test is skipped with the reason. To run it::

    python -m venv /work/venv-browser && /work/venv-browser/bin/pip install playwright
    apt-get install chromium             # Playwright's own browser download needs the network
    PYTHONPATH=/work/venv-browser/lib/python3.11/site-packages \\
        python -m pytest -m slow tests/test_docs_offline_maths.py

The browser is found as ``$ASPERITY_CHROMIUM``, else ``chromium``, ``chromium-browser`` or
``google-chrome`` on the PATH, else Playwright's own. The built site is
``$ASPERITY_DOCS_HTML`` when set (a tree you built), else the tree that
``tests/test_docs_build.py`` built earlier in the same pytest session, else it is built here
(two to four minutes on 2 cores).
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Where ``tests/test_docs_build.py`` builds the site, relative to pytest's session directory.
SESSION_BUILD = Path("docs_build") / "html"
#: The guides and API pages opened in the browser whether or not they hold maths: a page without
#: maths must not try the network either.
ALWAYS_OPENED = ("index", "bem", "statmodel", "paper", "api/generated/asperity.statmodel.shear")
#: The two pages whose screenshots are kept (when a folder for them is given).
SCREENSHOT_PAGES = ("auto_examples/plot_02_status_map", "auto_tutorials/plot_first_measured_map")
#: Text that is TeX left untypeset when it appears in a page's visible prose.
RAW_TEX = ("\\(", "\\)", "\\[", "\\]", "$$")
#: Tags whose ``src``/``href`` the browser fetches when the page loads (links it does not).
LOADED = {"script": "src", "img": "src", "iframe": "src", "source": "src", "link": "href"}


# ------------------------------------------------------------------------------------------------
# the check without a browser
# ------------------------------------------------------------------------------------------------


@dataclass
class PageScan:
    """What one HTML page loads and how much maths it holds (read by :class:`_Scanner`)."""

    maths: int = 0  # elements of class "math": Sphinx's inline spans and display divs
    mathjax_scripts: list[str] = field(default_factory=list)
    loaded: list[str] = field(default_factory=list)  # every URL fetched at load time


class _Scanner(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.scan = PageScan()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = {name: value or "" for name, value in attrs}
        if "math" in values.get("class", "").split() and tag in ("span", "div"):
            self.scan.maths += 1
        attribute = LOADED.get(tag)
        if attribute is None or not values.get(attribute):
            return
        if tag == "link" and not {"stylesheet", "preload", "icon", "modulepreload"} & set(
            values.get("rel", "").split()
        ):
            return  # rel="next", "canonical": a link, not a load
        url = values[attribute]
        self.scan.loaded.append(url)
        if tag == "script" and "mathjax" in url.lower():
            self.scan.mathjax_scripts.append(url)


def scan_page(path: Path) -> PageScan:
    """Read one built page: its maths elements, its MathJax scripts, everything it loads."""
    scanner = _Scanner()
    scanner.feed(path.read_text("utf-8"))
    scanner.close()
    return scanner.scan


def _resolve_inside(url: str, page: Path, html: Path) -> str | None:
    """Why ``url``, loaded by ``page``, is not a file inside the tree ``html`` (None if it is)."""
    parts = urlsplit(url)
    if parts.scheme in ("http", "https") or url.startswith("//"):
        return f"loads {url} from the network"
    if parts.scheme == "data":
        return None  # inline: nothing is fetched
    if parts.scheme not in ("", "file"):
        return f"loads {url} (scheme {parts.scheme!r})"
    path = Path(unquote(parts.path))
    target = (path if path.is_absolute() else page.parent / path).resolve()
    if not target.is_relative_to(html.resolve()):
        return f"loads {url}, which resolves outside the built tree ({target})"
    if not target.is_file():
        return f"loads {url}, which is not in the built tree ({target} missing)"
    return None


def offline_problems(html: Path) -> list[str]:
    """Every reason a page of the built site ``html`` would not read offline, or need the network.

    A page with maths must load MathJax; every script, stylesheet, image and frame of every page
    must be a file inside ``html``. One line per fault, naming the page.
    """
    problems = []
    for page in sorted(html.rglob("*.html")):
        name = page.relative_to(html).as_posix()
        scan = scan_page(page)
        if scan.maths and not scan.mathjax_scripts:
            problems.append(f"{name}: {scan.maths} maths elements and no MathJax script")
        for url in scan.loaded:
            reason = _resolve_inside(url, page, html)
            if reason:
                problems.append(f"{name}: {reason}")
    return problems


def _write(path: Path, body: str, head: str = "") -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"<html><head>{head}</head><body>{body}</body></html>", "utf-8")


MATHS = '<p>Area <span class="math notranslate nohighlight">\\(A_r/A_n\\)</span></p>'


def test_offline_check_accepts_mathjax_from_the_tree_at_any_depth(tmp_path: Path) -> None:
    (tmp_path / "_static/mathjax").mkdir(parents=True)
    (tmp_path / "_static/mathjax/tex-chtml.js").write_text("// MathJax", "utf-8")
    (tmp_path / "_static/furo.css").write_text("", "utf-8")
    script = '<script defer src="{}_static/mathjax/tex-chtml.js"></script>'
    css = '<link rel="stylesheet" href="{}_static/furo.css"><link rel="next" href="https://x.org">'
    _write(tmp_path / "index.html", MATHS, script.format("") + css.format(""))
    _write(tmp_path / "api/generated/m.html", MATHS, script.format("../../") + css.format("../../"))
    _write(tmp_path / "plain.html", '<a href="https://example.org">a link is not a load</a>')
    assert offline_problems(tmp_path) == []
    assert scan_page(tmp_path / "api/generated/m.html").maths == 1


@pytest.mark.parametrize(
    ("src", "expected"),
    [
        ("https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-chtml.js", "from the network"),
        ("//cdn.example.org/mathjax/tex-chtml.js", "from the network"),
        ("_static/mathjax/tex-chtml.js", "not in the built tree"),  # the copy never ran
        ("../outside/mathjax/tex-chtml.js", "outside the built tree"),
    ],
)
def test_offline_check_names_a_mathjax_script_that_would_not_load(
    tmp_path: Path, src: str, expected: str
) -> None:
    (tmp_path / "outside/mathjax").mkdir(parents=True)
    (tmp_path / "outside/mathjax/tex-chtml.js").write_text("// MathJax", "utf-8")
    html = tmp_path / "html"
    _write(html / "bem.html", MATHS, f'<script defer src="{src}"></script>')
    problems = offline_problems(html)
    assert len(problems) == 1 and problems[0].startswith("bem.html: ") and expected in problems[0]


def test_offline_check_names_a_page_with_maths_and_no_mathjax(tmp_path: Path) -> None:
    _write(tmp_path / "paper.html", MATHS + MATHS.replace("span", "div"))
    assert offline_problems(tmp_path) == ["paper.html: 2 maths elements and no MathJax script"]


# ------------------------------------------------------------------------------------------------
# the built site
# ------------------------------------------------------------------------------------------------


def _docs_tools_missing() -> list[str]:
    names = ("sphinx", "numpydoc", "myst_parser", "sphinx_gallery", "furo")
    names += ("sphinx-mathjax-offline",)
    return [name for name in names if importlib.util.find_spec(name) is None]


@pytest.fixture(scope="module")
def docs_html(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The built site: ``$ASPERITY_DOCS_HTML``, this session's build by test_docs_build, or new."""
    given = os.environ.get("ASPERITY_DOCS_HTML")
    if given:
        html = Path(given)
        if not (html / "index.html").is_file():
            pytest.fail(f"ASPERITY_DOCS_HTML={given}: expected a built site, found no index.html")
        return html
    session = tmp_path_factory.getbasetemp() / SESSION_BUILD
    if (session / "index.html").is_file():
        return session
    missing = _docs_tools_missing()
    if missing:
        pytest.skip(f"the docs extra is not installed (no {', '.join(missing)})")
    out = tmp_path_factory.mktemp("docs_offline")
    command = [sys.executable, "-m", "sphinx", "-q", "-b", "html", "-d", str(out / "doctrees")]
    command += [str(ROOT / "docs"), str(out / "html")]
    done = subprocess.run(command, capture_output=True, text=True, timeout=1200, cwd=ROOT)
    assert done.returncode == 0, f"sphinx failed:\n{done.stderr[-6000:]}"
    return out / "html"


@pytest.mark.slow
def test_every_built_page_reads_offline(docs_html: Path) -> None:
    assert offline_problems(docs_html) == []
    # the gallery and the tutorial write maths: the check saw them
    assert scan_page(docs_html / f"{SCREENSHOT_PAGES[0]}.html").maths > 0


# ------------------------------------------------------------------------------------------------
# the browser
# ------------------------------------------------------------------------------------------------

CHROMIUM_FLAGS = [
    "--no-sandbox",  # root on the CI and developer machines
    "--disable-gpu",
    "--disable-background-networking",  # no update, sync or safe-browsing traffic of its own
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
]

_WAIT_FOR_MATHJAX = """async (limit) => {
    const start = Date.now();
    while (!(window.MathJax && MathJax.startup && MathJax.startup.promise)) {
        if (Date.now() - start > limit) return `MathJax did not start within ${limit} ms`;
        await new Promise((r) => setTimeout(r, 50));
    }
    await MathJax.startup.promise;
    await document.fonts.ready;
    return null;
}"""

_MEASURE = """() => {
    const prose = document.body.cloneNode(true);
    prose.querySelectorAll("pre, code, script, style, .highlight, mjx-container")
        .forEach((e) => e.remove());
    const maths = [...document.querySelectorAll("span.math, div.math")];
    return {
        maths: maths.length,
        typeset: maths.filter((e) => e.querySelector("mjx-container")).length,
        containers: document.querySelectorAll("mjx-container").length,
        errors: [...document.querySelectorAll("mjx-merror")].map((e) => e.textContent),
        prose: prose.innerText,
        fonts: [...document.fonts].filter((f) => f.family.includes("MJX"))
            .map((f) => [f.family, f.status]),
        // a code block wider than its box must scroll, never be clipped or spill over
        cut: [...document.querySelectorAll("pre")].filter((e) => e.scrollWidth > e.clientWidth + 1
            && !["auto", "scroll"].includes(getComputedStyle(e).overflowX)).length,
        wide: [...document.querySelectorAll("pre")]
            .filter((e) => e.scrollWidth > e.clientWidth + 1).length,
    };
}"""


@dataclass
class BrowserPage:
    """What the browser saw on one page, once MathJax was done."""

    name: str
    maths: int
    typeset: int  # maths elements holding an mjx-container
    containers: int
    errors: list[str]
    raw_tex: list[str]  # the RAW_TEX strings found in the visible prose
    font_failures: list[str]
    fonts_loaded: int  # MathJax's fonts that loaded (from the tree's _static/mathjax)
    code_blocks_cut: int  # code blocks wider than their box that do not scroll
    code_blocks_scrolling: int  # code blocks wider than their box, scrolling
    started: str | None  # why MathJax did not start (None: it did, or the page has no maths)


@dataclass
class BrowserReport:
    pages: list[BrowserPage]
    requested: list[str]  # every request the pages made (files of the tree, mostly)
    blocked: list[str]  # those that would have left the machine (all aborted)
    screenshots: list[Path]


def find_chromium() -> str | None:
    """The Chromium to drive: ``$ASPERITY_CHROMIUM``, one on the PATH, else None."""
    given = os.environ.get("ASPERITY_CHROMIUM")
    if given:
        return given
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def check_pages_in_browser(
    html: Path,
    pages: list[str],
    screenshots: Path | None = None,
    executable: str | None = None,
    start_limit: float = 15.0,
) -> BrowserReport:
    """Open each page (``name`` without ``.html``) of ``html`` from ``file://``, the network cut.

    Every http(s), ws(s) request is aborted and recorded; the browser is also told it is offline.
    On a page with maths, MathJax must have started within ``start_limit`` seconds. Screenshots
    of :data:`SCREENSHOT_PAGES` (the viewport at the first maths) go to ``screenshots`` when it
    is given.
    """
    from playwright.sync_api import sync_playwright  # deferred: not a dependency (see above)

    local = ("file", "data", "blob", "about")
    requested: list[str] = []  # every request the pages made, local or not
    results: list[BrowserPage] = []
    shots: list[Path] = []

    def route(request_route) -> None:
        url = request_route.request.url
        if urlsplit(url).scheme in local:
            request_route.continue_()
        else:
            request_route.abort("internetdisconnected")

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=executable, args=CHROMIUM_FLAGS)
        context = browser.new_context(viewport={"width": 1280, "height": 860})
        context.set_offline(True)
        context.route("**/*", route)
        context.on("request", lambda request: requested.append(request.url))
        context.on("websocket", lambda socket: requested.append(socket.url))
        for name in pages:
            page = context.new_page()
            page.goto((html / f"{name}.html").resolve().as_uri(), wait_until="load")
            started = None
            if page.evaluate("() => document.querySelectorAll('span.math, div.math').length"):
                started = page.evaluate(_WAIT_FOR_MATHJAX, round(start_limit * 1000))
            seen = page.evaluate(_MEASURE)
            results.append(
                BrowserPage(
                    name=name,
                    maths=seen["maths"],
                    typeset=seen["typeset"],
                    containers=seen["containers"],
                    errors=seen["errors"],
                    raw_tex=[tex for tex in RAW_TEX if tex in seen["prose"]],
                    font_failures=[family for family, status in seen["fonts"] if status == "error"],
                    fonts_loaded=sum(status == "loaded" for _, status in seen["fonts"]),
                    code_blocks_cut=seen["cut"],
                    code_blocks_scrolling=seen["wide"] - seen["cut"],
                    started=started,
                )
            )
            if screenshots is not None and name in SCREENSHOT_PAGES:
                first = page.locator("span.math, div.math").first
                if first.count():
                    first.scroll_into_view_if_needed()
                    page.evaluate("() => window.scrollBy(0, -200)")
                path = screenshots / f"{name.replace('/', '__')}.png"
                page.screenshot(path=str(path))
                shots.append(path)
            page.close()
        context.close()
        browser.close()
    blocked = [url for url in requested if urlsplit(url).scheme not in local]
    return BrowserReport(pages=results, requested=requested, blocked=blocked, screenshots=shots)


def pages_to_open(html: Path) -> list[str]:
    """Every page with maths, and :data:`ALWAYS_OPENED`."""
    with_maths = [
        page.relative_to(html).with_suffix("").as_posix()
        for page in sorted(html.rglob("*.html"))
        if "_static" not in page.parts and "_modules" not in page.parts and scan_page(page).maths
    ]
    return list(dict.fromkeys([*with_maths, *ALWAYS_OPENED]))


needs_playwright = pytest.mark.skipif(
    importlib.util.find_spec("playwright") is None,
    reason="no headless browser: Playwright's Python package is not importable (it is no "
    "dependency of asperity and CI has none; see this module's docstring to run it)",
)


@pytest.fixture
def chromium() -> str | None:
    """The Chromium executable, None for Playwright's own; skips where there is none."""
    executable = find_chromium()
    if executable is None and not os.environ.get("PLAYWRIGHT_BROWSERS_PATH"):
        pytest.skip("no Chromium: none on the PATH and $ASPERITY_CHROMIUM unset")
    return executable


@pytest.mark.slow
@needs_playwright
def test_browser_check_sees_untypeset_maths_and_requests_off_the_machine(
    tmp_path: Path, chromium: str | None
) -> None:
    """The check itself, on three made-up pages: it passes a page whose MathJax is in the tree,
    and names the page whose MathJax file is missing and the one that asks a CDN."""
    spec = importlib.util.find_spec("sphinx-mathjax-offline")
    if spec is None or spec.origin is None:
        pytest.skip("no MathJax bundle: sphinx-mathjax-offline (the docs extra) is not installed")
    (tmp_path / "_static").mkdir()
    (tmp_path / "_static/mathjax").symlink_to(Path(spec.origin).parent / "static" / "mathjax")
    cdn = "https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-chtml.js"
    for name, src in [
        ("good", "_static/mathjax/tex-chtml.js"),
        ("missing", "_static/mathjax-gone/tex-chtml.js"),
        ("cdn", cdn),
    ]:
        _write(tmp_path / f"{name}.html", MATHS, f'<script defer src="{src}"></script>')
    report = check_pages_in_browser(tmp_path, ["good", "missing", "cdn"], None, chromium, 3.0)

    good, missing, from_cdn = report.pages
    assert (good.maths, good.typeset, good.containers, good.raw_tex) == (1, 1, 1, [])
    assert good.started is None and good.errors == [] and good.fonts_loaded >= 2
    for page in (missing, from_cdn):
        assert page.typeset == 0 and page.raw_tex == ["\\(", "\\)"], page
        assert page.started == "MathJax did not start within 3000 ms"
    assert report.blocked == [cdn]
    assert all(url.startswith("file://") for url in report.requested if url != cdn)


@pytest.mark.slow
@needs_playwright
def test_maths_typeset_in_a_browser_with_no_network(
    docs_html: Path, tmp_path: Path, chromium: str | None
) -> None:
    executable = chromium
    pages = pages_to_open(docs_html)
    assert len(pages) > len(ALWAYS_OPENED)  # the gallery's and tutorial's maths were found
    report = check_pages_in_browser(docs_html, pages, tmp_path, executable)

    assert report.blocked == [], "requests tried to leave the machine"
    with_maths = [page for page in report.pages if page.maths]
    assert len(with_maths) >= 3
    for page in report.pages:
        assert page.started is None, f"{page.name}: {page.started}"
        assert page.typeset == page.maths == page.containers, page
        assert page.errors == [] and page.font_failures == [], page
        assert page.code_blocks_cut == 0, page
        if page.maths:  # typeset in MathJax's own fonts, not in a fallback
            assert page.fonts_loaded >= 2, page
        assert page.raw_tex == [], f"{page.name}: untypeset TeX {page.raw_tex} in the prose"
    assert [path.stat().st_size > 10_000 for path in report.screenshots] == [True, True]
