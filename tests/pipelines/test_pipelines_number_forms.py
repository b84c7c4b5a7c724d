"""One form per quantity (issue 39): a value with its uncertainty is written with the digits
the uncertainty supports, and in the same form in the terminal summary, report.md,
report.html and a batch's summary.csv."""

from __future__ import annotations

import csv
import html

from asperity.pipelines.batch.summary import summary_values, write_summary_csv
from asperity.pipelines.report.numbers import PLUS_MINUS, format_number
from asperity.pipelines.report.text import key_numbers, load_table, summary_text


def _summary_rows(path):
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(line for line in handle if not line.startswith("#")))


def test_static_friction_reads_the_same_in_terminal_md_html_and_csv(small_run, tmp_path):
    """The small job's F_s at each load (N, its unit in every output): the load table's cell
    is format_number(F_s, u) ("0.545 ± 0.042"), found as it is in the terminal summary and
    report.md, in report.html with no-break spaces around "±" (never "+-"), and in
    summary.csv's written column; the numeric columns keep full precision."""
    _, out, result = small_run
    fr = result.friction
    header, rows = load_table(result)
    static = header.index("static F_s (N)")
    terminal = summary_text(result)
    markdown = (out / "report.md").read_text(encoding="utf-8")
    page = (out / "report.html").read_text(encoding="utf-8")
    record = {"map": "a", "folder": "a", "status": "ok", "message": "", "values": {}}
    record["values"] = summary_values(result)
    (csv_row, *_) = _summary_rows(write_summary_csv([record], tmp_path / "summary.csv"))
    assert "+-" not in page
    for i, load in enumerate(fr.normal_load):
        form = format_number(fr.static_friction[i], fr.static_friction_uncertainty[i])
        assert PLUS_MINUS in form and rows[i][static].endswith(form), (rows[i][static], form)
        assert form in terminal and form in markdown
        assert html.escape(form).replace(f" {PLUS_MINUS} ", f"\u00a0{PLUS_MINUS}\u00a0") in page
        at = f"at F_z={load:.6g} N"
        assert csv_row[f"static friction {at} written (N)"] == form
        assert float(csv_row[f"static friction {at} (N)"]) == fr.static_friction[i]


def test_the_assumed_lambda_row_writes_f_s_as_the_load_table_does(small_run):
    """The key row of an assumed lambda says F_s at its lightest load in the table's form,
    its decade's ends to 4 significant digits as in the decade column."""
    _, _, result = small_run
    fr = result.friction
    assert fr.static_friction_mode_mixity_decade is not None  # the small job assumes lambda
    row = dict(key_numbers(result))["mode mixity lambda (configured)"]
    header, rows = load_table(result)
    i = int(fr.normal_load.argmin())
    cell = rows[i][header.index("static F_s (N)")]
    ends = rows[i][-1].split(" .. ")
    assert f"{ends[0].split(': ')[-1]} / {cell.split(': ')[-1]} / {ends[1]}" in row, row
