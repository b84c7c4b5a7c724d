"""Reopening a run: asperity.open_results, `asperity report` (no solver runs) and report.html."""

from __future__ import annotations

import dataclasses
import shutil
from html.parser import HTMLParser

import numpy as np
import pytest

import asperity
from asperity.errors import InputError
from asperity.fields import checksum
from asperity.pipelines.cli import main
from asperity.pipelines.job import STAGES
from asperity.pipelines.report import FIGURES, key_numbers, load_table, write_report
from asperity.pipelines.report.friction_curves import FRICTION_TEST_FIGURES
from asperity.pipelines.report.html import find_verdict, write_html
from asperity.pipelines.report.numbers import plain_text
from asperity.pipelines.results import ALIASES
from tests._helpers import area_to_peak, sampled_area_curves, shear_area_model


def test_open_results_gives_back_every_stage(small_run):
    """Each stored stage reads back equal (same checksum) to what the job returned."""
    _, out, result = small_run
    run = asperity.open_results(out)
    for stage in STAGES:
        stored, computed = getattr(run, stage.name), getattr(result, stage.name)
        if computed is None:  # disabled in this job (the line-profile realisations)
            assert stored is None, stage.name
            continue
        assert checksum(stored) == checksum(computed), stage.name
        assert isinstance(stored, stage.result), stage.name
    assert [s.name for s in run.stages] == [s.name for s in result.stages if s.status != "disabled"]
    assert run.input_sha256 == result.input_sha256
    assert run.problems() == result.problems()
    assert "[material]" in run.config_toml


def test_old_stage_names_warn_and_answer(small_run):
    """asperity 0.3's second names (run.scan, run.bem, run.resolution) still answer, warning."""
    _, out, result = small_run
    run = asperity.open_results(out)
    for alias, group in ALIASES.items():
        for value in (run, result):
            with pytest.warns(DeprecationWarning, match=f"use .{group}.*removed in asperity"):
                assert getattr(value, alias) is getattr(value, group)
    assert set(ALIASES) == {"scan", "bem", "resolution"}


def test_to_xarray_has_units_and_dims(small_run):
    pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    _, out, result = small_run
    datasets = asperity.open_results(out / "results.h5").to_xarray()
    friction = datasets["friction"]
    assert friction["static_friction"].attrs["units"] == "N"
    assert friction["static_friction"].dims == ("normal_load",)
    np.testing.assert_array_equal(friction["static_friction"], result.friction.static_friction)
    tree = asperity.open_results(out).to_datatree()
    assert set(tree.children) == set(datasets)


def test_open_results_refuses_what_is_not_a_run(tmp_path):
    """A missing file or a non-HDF5 file: InputError naming it, and the file left in place."""
    with pytest.raises(InputError, match="not found"):
        asperity.open_results(tmp_path)
    bogus = tmp_path / "results.h5"
    bogus.write_text("not hdf5")
    with pytest.raises(InputError, match="not an HDF5 file"):
        asperity.open_results(bogus)
    assert bogus.read_text() == "not hdf5"


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_report_command_redraws_without_solving(small_run, tmp_path, monkeypatch, capsys):
    """`asperity report OUT --formats png --dpi 40` from results.h5 alone: no solver runs."""
    _, out, _ = small_run
    shutil.copy(out / "results.h5", tmp_path / "results.h5")

    def refuse(*args, **kwargs):
        raise AssertionError("a solver ran during `asperity report`")

    from asperity import bem, statmodel
    from asperity.pipelines import job

    monkeypatch.setattr(bem, "solve_contact", refuse, raising=False)
    monkeypatch.setattr(statmodel, "shear_curve", refuse, raising=False)
    monkeypatch.setattr(job, "run_job", refuse)
    assert main(["report", str(tmp_path), "--formats", "png", "--dpi", "40"]) == 0
    for stem, _, _ in FIGURES.values():
        absent = ("lambda_fit", "lambda_residuals", "fig4_bem_shear", "fig13_bem_shear")
        if stem not in absent and stem not in FRICTION_TEST_FIGURES:  # stems are the names
            for suffix in (".png", ".csv"):
                assert (tmp_path / stem).with_suffix(suffix).exists(), stem + suffix
    assert (tmp_path / "report.md").exists() and (tmp_path / "report.html").exists()
    assert main(["report", str(tmp_path), "--formats", "gif"]) == 2
    assert "--formats: expected" in capsys.readouterr().err


class _Page(HTMLParser):
    """Collects figure ids, embedded images and the visible text of report.html."""

    def __init__(self) -> None:
        super().__init__()
        self.figures: list[str] = []
        self.images = 0
        self.svgs = 0
        self.text: list[str] = []
        self.verdict = False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "figure":
            self.figures.append(attrs["data-figure"])
        if tag == "img" and attrs.get("src", "").startswith("data:image/png;base64,"):
            self.images += 1
        if tag == "svg":
            self.svgs += 1
        if tag == "section" and attrs.get("class") == "verdict":
            self.verdict = True

    def handle_data(self, data):
        self.text.append(data)


def _parse(path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def test_html_report_holds_every_figure_and_number(small_run):
    _, out, result = small_run
    page = _parse(out / "report.html")
    absent = (
        "lambda_fit",
        "lambda_residuals",
        "bem_shear_force",
        "bem_shear_area",
        *FRICTION_TEST_FIGURES,  # no friction tests in the small job
    )
    expected = [n for n in FIGURES if n not in absent]
    assert sorted(page.figures) == sorted(expected)
    assert page.images + page.svgs == len(expected)
    text = " ".join(page.text)

    def shown(cell: str) -> str:  # report.html writes "value ± u" on one line (no-break)
        return cell.replace(" ± ", "\u00a0±\u00a0").replace("(± ", "(±\u00a0")

    assert "+-" not in text
    for quantity, value in key_numbers(result):
        assert shown(quantity) in text and shown(value) in text, quantity
    header, rows = load_table(result)
    assert all(shown(h) in text for h in header)
    assert all(shown(c) in text for row in rows for c in row)
    assert all(stage.name in text for stage in STAGES)
    assert page.verdict  # the verdict stage's block is on the page, with its reasons
    # as written on the page: in words, micro spelt µm (report.numbers.plain_text)
    assert all(plain_text(reason) in text for reason in result.verdict.reasons)


@dataclasses.dataclass
class _Verdict:
    verdict: str
    reasons: list


def test_html_report_shows_a_verdict_stage_generically(small_run, tmp_path):
    """Any verdict dataclass on the result (before or after a verdict stage exists) is shown."""
    _, _, result = small_run
    verdict = _Verdict("invalid", ["Tabor parameter 12 > 5: JKR limit"])
    with_verdict = dataclasses.replace(result, out_dir=tmp_path)
    with_verdict.verdict = verdict
    assert find_verdict(with_verdict) is verdict
    write_html(with_verdict, tmp_path, {}, {})
    page = _parse(tmp_path / "report.html")
    assert page.verdict
    assert "Tabor parameter 12 > 5: JKR limit" in " ".join(page.text)


def test_model_values_are_stored_beside_the_measured_points(tmp_path):
    """Curves the model made at lambda = 0.1: at the fitted lambda the stored model values at
    the measured points reproduce them, and they read back from results.h5 beside them."""
    from asperity import statmodel
    from asperity.pipelines.engine.store import ResultStore
    from asperity.pipelines.stages.friction import ModeMixityChoice, calibrate_mode_mixity

    material = statmodel.Material(
        e_star=2.133e6, work_of_adhesion=0.04, mode_mixity=0.03, shear_strength=0.13e6
    )
    roughness = statmodel.Roughness(6e6, 0.3e-3, 40e-6)
    a_n = 700e-6
    peaks = area_to_peak(shear_area_model(material, roughness, a_n, 81), 0.1, (1.0, 3.0))
    curves = sampled_area_curves(peaks, (1.0, 3.0), 8, 0.9)
    choice = calibrate_mode_mixity(material, roughness, a_n, curves, steps=81)
    np.testing.assert_allclose(
        choice.model_real_area_at_measured, choice.measured_real_area, rtol=1e-3
    )
    store = ResultStore(tmp_path / "results.h5")
    store.write("mode_mixity", choice, key="k", key_inputs="{}", seconds=0.0, root_attrs={})
    back = store.read("mode_mixity", ModeMixityChoice)
    np.testing.assert_array_equal(
        back.model_real_area_at_measured, choice.model_real_area_at_measured
    )


@pytest.mark.slow
def test_html_embeds_svg_or_a_drawn_png_without_png_files(small_run, tmp_path):
    """SVG only: the figures are inline SVG; PDF only: PNGs drawn in memory (no stale files)."""
    from asperity.pipelines.report.figure_output import FigureOptions

    _, _, result = small_run
    absent = (
        "lambda_fit",
        "lambda_residuals",
        "bem_shear_force",
        "bem_shear_area",
        *FRICTION_TEST_FIGURES,  # no friction tests in the small job
    )
    expected = len([n for n in FIGURES if n not in absent])
    write_report(result, tmp_path, FigureOptions(("svg",)))
    page = _parse(tmp_path / "report.html")
    assert (page.svgs, page.images) == (expected, 0)
    write_report(result, tmp_path, FigureOptions(("pdf",)))
    page = _parse(tmp_path / "report.html")
    assert (page.svgs, page.images) == (0, expected)
