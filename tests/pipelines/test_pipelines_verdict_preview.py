"""The adhesion regime is judged from the map before the BEM runs (issue 24, section 5): the
engine's previews (a later stage's cheap judgement, said and stored before an expensive stage),
and the verdict's preview of the regime on real maps."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import h5py

from asperity.fields import document_fields, scalar
from asperity.pipelines.config import config_from_dict
from asperity.pipelines.engine.parallel import SerialExecutor
from asperity.pipelines.engine.stage import Preview, PreviewNote, Runner, Stage, StageContext
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.stages.surface import SURFACE, LevelledSurface, prepare
from asperity.pipelines.stages.verdict import PREVIEW_ATTRIBUTE, VERDICT

DATA = Path(__file__).resolve().parents[1] / "data"


@document_fields
@dataclass
class Number:
    """A toy stage result.

    Attributes
    ----------
    value : float
        A number.
    """

    value: float = scalar("1", "a number")


def _toy_stages(log: list[str], store_path: Path, expensive_enabled: bool = True):
    """cheap -> expensive -> judge, the judge previewing before the expensive stage."""

    def expensive(context: StageContext) -> Number:
        # the preview was said and stored before this stage began
        log.append("expensive computing")
        with h5py.File(store_path, "r") as f:
            log.append(f"stored before: {'preview_early' in f.attrs}")
        return Number(2.0)

    cheap = Stage("cheap", "cheap", Number, ("material.E_star",), (), lambda c: Number(1.0))
    costly = Stage(
        "costly",
        "costly",
        Number,
        (),
        (cheap,),
        expensive,
        enabled=lambda config: expensive_enabled,
    )

    def early(context: StageContext) -> PreviewNote:
        value = context.result(cheap).value
        return PreviewNote([f"judged early: {value:g}"], {"value": value})

    judge = Stage(
        "judge",
        "judge",
        Number,
        (),
        (cheap, costly),
        lambda c: Number(3.0),
        preview=Preview("early", "costly", ("material.E_star",), (cheap,), early),
    )
    return [cheap, costly, judge]


def _runner(small, tmp_path, log):
    config = small(tmp_path)
    return Runner(
        store=ResultStore(tmp_path / "results.h5"),
        context=StageContext(config, {}, SerialExecutor()),
        config_document=config.key_document(),
        version="test",
        root_attrs={"config_toml": config.to_toml()},
        log=log.append,
    )


def test_a_preview_is_said_and_stored_before_the_stage_it_precedes(small, tmp_path):
    log: list[str] = []
    runner = _runner(small, tmp_path, log)
    runner.run_all(_toy_stages(log, tmp_path / "results.h5"))
    assert log[:4] == [
        "1 cheap: " + log[0].split(": ")[1],
        "before 2 costly: judged early: 1",
        "expensive computing",
        "stored before: True",
    ]
    with h5py.File(tmp_path / "results.h5", "r") as f:
        assert json.loads(f.attrs["preview_early"]) == {"before": "costly", "value": 1.0}
    # taken from the store, the stage is still preceded by its preview
    log.clear()
    _runner(small, tmp_path, log).run_all(_toy_stages(log, tmp_path / "results.h5"))
    assert log[1:3] == ["before 2 costly: judged early: 1", "2 costly: stored, skipped"]


def test_no_preview_before_a_disabled_stage(small, tmp_path):
    log: list[str] = []
    runner = _runner(small, tmp_path, log)
    runner.run_all(_toy_stages(log, tmp_path / "results.h5", expensive_enabled=False))
    assert not any("judged early" in line for line in log)
    assert "2 costly: disabled" in log


def _context(material: dict, crop: list[int]) -> StageContext:
    config = config_from_dict(
        {"surface": {"file": str(DATA / "x3p-2.x3p"), "crop": crop}, "material": material}
    )
    surface = LevelledSurface.from_prepared(prepare(config.surface))
    context = StageContext(config, {SURFACE.name: surface}, SerialExecutor())
    return context.for_stage(VERDICT.preview)  # only what the preview declares


def test_the_verdict_previews_the_regime_before_the_bem():
    assert VERDICT.preview.before == "bem_reference"
    assert PREVIEW_ATTRIBUTE == f"preview_{VERDICT.preview.name}"
    crop = [0, 128, 0, 128]
    full = VERDICT.preview.run(_context({"E_star": 2.133e6}, crop))  # PDMS: full contact
    (line,) = full.lines
    assert "FULL CONTACT" in line and "decided by its range h_0" in line
    assert "are skipped" in line and "run.compute_all = true" in line
    assert full.record["codes"] == ["adhesion_full_contact"]
    assert full.record["severities"] == ["invalid"] and full.record["adhesion_energy_ratio"] < 1
    glassy = VERDICT.preview.run(_context({"E_star": 3.5e9}, crop))
    assert "partial contact" in glassy.lines[0] and glassy.record["codes"] == []
    assert glassy.record["adhesion_energy_ratio"] > 1
    silent = VERDICT.preview.run(_context({"work_of_adhesion": 0.0}, crop))  # no adhesion
    assert silent.lines == [] and silent.record["codes"] == []
