"""``report.html``: one self-contained page (figures embedded) beside ``report.md``.

The page holds, in this order: the validity verdict (when the result has a verdict stage: its
wording, as in report.md and the terminal, then its reasons as a list, each with its severity
and code, coloured: red for invalid, amber for warnings; a verdict dataclass without reasons is
shown field by field), the few key numbers (:func:`~asperity.pipelines.report.text.
headline_numbers`), the per-load table, then the details: every key number with its
qualifications, the validity and convergence notes, the stage table and every figure, scaled
to the page's width (tables wider than the page scroll in their own box), embedded as a base64 PNG
(when PNG was written), else as inline SVG, else (PDF only) as a PNG drawn in memory. It needs
no other file and no network: mail it, or open it from a notebook.
"""

from __future__ import annotations

import base64
import dataclasses
import html
import io
import json
from pathlib import Path

import numpy as np

from asperity.atomic import write_text_atomic
from asperity.pipelines.report._run import Run
from asperity.pipelines.report.figures import draw_figure
from asperity.pipelines.report.friction_curves import friction_tests_html
from asperity.pipelines.report.numbers import PLUS_MINUS, plain_text
from asperity.pipelines.report.shear import shear_html
from asperity.pipelines.report.text import headline_numbers, key_numbers, load_table
from asperity.pipelines.stages.early_verdict import limit_lines
from asperity.pipelines.stages.verdict import Verdict

#: Attribute names under which a result may hold a verdict stage's result.
VERDICT_NAMES: tuple[str, ...] = ("verdict", "validity_verdict")


def find_verdict(result: object) -> Verdict | None:
    """The verdict stage's result when the result holds one (any dataclass), else None."""
    for name in VERDICT_NAMES:
        value = getattr(result, name, None)
        if value is not None and dataclasses.is_dataclass(value):
            return value
    for name, value in getattr(result, "extra", {}).items():
        if "verdict" in name and dataclasses.is_dataclass(value):
            return value
    return None


def _plain(value: object) -> str | None:
    """A verdict field as text; None for arrays and empty values (not shown)."""
    if value is None or isinstance(value, np.ndarray):
        return None
    if isinstance(value, list | tuple):
        return "; ".join(str(v) for v in value) if value else None
    if isinstance(value, dict):
        return json.dumps(value, default=str)
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def reasons_html(verdict: Verdict) -> str:
    """The verdict's wording and its reasons as a list with their severities, coloured."""
    from asperity.pipelines.stages.verdict import severity_label, verdict_wording

    word = str(verdict.verdict)
    items = "".join(
        f'<li class="reason severity-{html.escape(sev)}" data-severity="{html.escape(sev)}">'
        f"<b>{html.escape(severity_label(sev))}</b> (<code>{html.escape(code)}</code>): "
        f"{html.escape(plain_text(text))}</li>"
        for sev, code, text in zip(verdict.severities, verdict.codes, verdict.reasons, strict=True)
    )
    return (
        f'<section class="verdict" data-verdict="{html.escape(word)}"><h2>Validity verdict</h2>'
        f'<p class="verdict-word">{html.escape(verdict_wording(word))}</p>'
        + (f'<ul class="reasons">{items}</ul>' if items else "<p>Every check passed.</p>")
        + "</section>"
    )


def verdict_html(verdict: Verdict) -> str:
    """The verdict block: the reasons as a list (:func:`reasons_html`) when the verdict has
    them, else one row per non-array field, in declaration order."""
    if all(hasattr(verdict, name) for name in ("verdict", "reasons", "codes", "severities")):
        return reasons_html(verdict)
    rows = []
    for field in dataclasses.fields(verdict):
        text = _plain(getattr(verdict, field.name))
        if text is not None:
            rows.append([field.name.replace("_", " "), text])
    return (
        '<section class="verdict"><h2>Validity verdict</h2>'
        + table_html(["item", "value"], rows)
        + "</section>"
    )


def _cell(text: str) -> str:
    """A table cell's text escaped, each "value ± u" (or another package's "value +- u") as
    "value ± u" on one line (no-break spaces: a cell wraps between values, never inside one)."""
    escaped = html.escape(plain_text(text))
    for spelt in (" +- ", f" {PLUS_MINUS} "):
        escaped = escaped.replace(spelt, f"\u00a0{PLUS_MINUS}\u00a0")
    return escaped.replace("(+- ", f"({PLUS_MINUS}\u00a0").replace(
        f"({PLUS_MINUS} ", f"({PLUS_MINUS}\u00a0"
    )


def table_html(header: list[str], rows: list[list[str]]) -> str:
    """An HTML table of text cells (escaped; ``±`` kept on one line with its numbers)."""
    head = "".join(f"<th>{_cell(h)}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td>{_cell(str(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    # a wide table scrolls inside its own box instead of widening the page
    return (
        f'<div class="table"><table><thead><tr>{head}</tr></thead><tbody>{body}</tbody>'
        "</table></div>"
    )


def _png_bytes(result: Run, name: str) -> bytes:
    """Draw one figure into PNG bytes (when no PNG or SVG file was written)."""
    fig, _ = draw_figure(result, name)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    return buffer.getvalue()


def figure_html(result: Run, name: str, path: Path, caption: str) -> str:
    """One figure embedded with its caption: the PNG just written (base64), else the SVG
    just written (inline), else (PDF only) a PNG drawn in memory. ``path`` is the file of
    the first format written (PNG whenever PNG was requested), so a stale file of an earlier
    run is never embedded."""
    if path.suffix == ".svg":
        text = path.read_text(encoding="utf-8")
        body = text[text.index("<svg") :]
    else:
        data = path.read_bytes() if path.suffix == ".png" else _png_bytes(result, name)
        encoded = base64.b64encode(data).decode("ascii")
        body = f'<img alt="{html.escape(caption)}" src="data:image/png;base64,{encoded}">'
    return (
        f'<figure id="fig-{name}" data-figure="{name}">{body}'
        f"<figcaption>{html.escape(plain_text(caption))} Data: {html.escape(path.stem)}.csv"
        "</figcaption>"
        "</figure>"
    )


STYLE = (
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;"
    "text-align:left}th{background:#eee}div.table{max-width:100%;overflow-x:auto}"
    "figure{margin:2em 0}figure img,figure svg{display:block;max-width:100%;width:100%;"
    "height:auto}.key td:first-child{font-weight:bold}.verdict{border:2px solid #446;"
    "padding:0 1em;background:#f4f6ff}"
    ".warning{color:#a40}.verdict-word{font-size:1.3em;font-weight:bold}"
    ".verdict[data-verdict=invalid]{border-color:#b00000;background:#fff2f2}"
    ".verdict[data-verdict=invalid] .verdict-word{color:#b00000}"
    ".verdict[data-verdict=warnings]{border-color:#b35900;background:#fff8ee}"
    ".verdict[data-verdict=warnings] .verdict-word{color:#b35900}.severity-invalid{color:#b00000}"
    ".severity-warning{color:#b35900}"
)


def _notes(title: str, ok_text: str, notes: list[str]) -> str:
    if not notes:
        return f"<h2>{title}</h2><p>{html.escape(ok_text)}</p>"
    items = "".join(f'<li class="warning">{html.escape(plain_text(n))}</li>' for n in notes)
    return f"<h2>{title}</h2><ul>{items}</ul>"


def _wording(verdict: Verdict) -> str:
    from asperity.pipelines.stages.verdict import verdict_wording

    return verdict_wording(str(verdict.verdict))


def write_html(
    result: Run, out_dir: Path, figures: dict[str, Path], captions: dict[str, str]
) -> Path:
    """Write ``report.html`` in ``out_dir``; ``figures`` as returned by ``write_figures``."""
    status = {
        "stored": "stored (skipped)",
        "computed": "computed",
        "disabled": "disabled",
        "skipped": "not computed",
    }
    stage_rows = [
        [s.name, status.get(s.status, s.status), f"{s.seconds:.2f}"] for s in result.stages
    ]
    verdict = find_verdict(result)
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        "<title>asperity run report</title>",
        f"<style>{STYLE}</style></head><body><h1>asperity run report</h1>",
        verdict_html(verdict) if verdict is not None else "",
        _notes("Full-contact limit", "", limit_lines(verdict)) if limit_lines(verdict) else "",
        "<h2>Key numbers</h2>",
        table_html(["quantity", "value"], [list(r) for r in headline_numbers(result)]).replace(
            '<div class="table">', '<div class="table key">', 1
        ),
        "<h2>Per normal load</h2>",
        table_html(*load_table(result)),
        shear_html(result),
        friction_tests_html(result),
        "<h2>Details</h2>",
        table_html(["quantity", "value"], [list(r) for r in key_numbers(result)]),
        f"<h2>Validity</h2><p><b>{html.escape(_wording(verdict))}</b> (reasons at the top).</p>"
        if verdict is not None
        else _notes(
            "Validity",
            "The statistical model is within its assumptions.",
            result.statistical_model.validity,
        ),
        _notes("Convergence", "All solvers converged.", result.problems()),
        "<h2>Stages</h2>",
        table_html(["stage", "status", "seconds"], stage_rows),
        "<h2>Figures</h2>",
        *(figure_html(result, n, p, captions.get(n, n)) for n, p in figures.items()),
        "</body></html>",
    ]
    path = Path(out_dir) / "report.html"
    write_text_atomic(path, "\n".join(p for p in parts if p))
    return path
