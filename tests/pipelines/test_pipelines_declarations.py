"""A stage declaration is the only description of a stage: what it reads keys it, what it does
not declare it cannot read, and the result types, numbers and titles follow from the list."""

from __future__ import annotations

import copy
import dataclasses
import typing

import numpy as np
import pytest

from asperity import statmodel
from asperity.pipelines import job, results
from asperity.pipelines.config import BemConfig
from asperity.pipelines.engine.parallel import SerialExecutor
from asperity.pipelines.engine.stage import DISABLED, Runner, StageContext, stage_label
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.engine.views import UndeclaredReadError
from asperity.pipelines.stages import STAGES, stage_number
from asperity.pipelines.stages import bem as bem_stage
from asperity.pipelines.stages.statistical_model import normal_contact_material
from asperity.pipelines.stages.surface import SCAN, SURFACE
from tests._helpers import python_stdout


def _plan(config, document):
    runner = Runner(
        store=ResultStore("unused.h5"),
        context=StageContext(config, {}, SerialExecutor()),
        config_document=document,
        version="1.0",
        root_attrs={},
    )
    runner.plan(STAGES)
    return runner.keys


def _downstream(stage):
    """The stage and every stage that reads it, directly or through another."""
    out = {stage.name}
    for later in STAGES:
        if any(s.name in out for s in later.inputs):
            out.add(later.name)
    return out


def _change(document, path):
    """Give the key at ``path`` (every key of it, for a section) a value it never had."""
    *parents, last = path.split(".")
    for part in parents:
        document = document[part]
    if isinstance(document[last], dict):
        document[last] = {name: {"changed": True} for name in document[last]}
    else:
        document[last] = {"changed": True}


DECLARED = [(stage, key) for stage in STAGES for key in stage.config]


@pytest.mark.parametrize(("stage", "key"), DECLARED, ids=[f"{s.name}:{k}" for s, k in DECLARED])
def test_changing_any_declared_key_recomputes_the_stage_and_what_reads_it(
    small, tmp_path, stage, key
):
    """Together with the views (a key not declared cannot be read), every key a stage reads
    enters its key: a stored result computed with another value is never reused."""
    config = small(tmp_path)
    before = _plan(config, config.key_document())
    document = copy.deepcopy(config.key_document())
    _change(document, key)
    after = _plan(config, document)
    changed = {name for name in before if before[name] != after[name]}
    disabled = {name for name, k in before.items() if k == DISABLED}  # profile stages on a map
    if stage.name in disabled:  # a switched-off stage's keys reach nothing (bem_shear)
        disabled |= _downstream(stage)
    assert _downstream(stage) - disabled <= changed
    readers = [s for s in STAGES if _reads(s, key)]
    assert changed <= set().union(*(_downstream(s) for s in readers))  # and nothing else


def _reads(stage, key):
    """The stage declares ``key``, its section or one of its keys."""
    return any(k == key or key.startswith(k + ".") or k.startswith(key + ".") for k in stage.config)


def test_compute_sees_only_its_declared_keys_inputs_and_measurements(small, tmp_path):
    config = small(tmp_path)
    probe = dataclasses.replace(
        STAGES[2],
        config=("material.E_star", "bem", "measured.normal_area"),
        inputs=(SURFACE,),
    )
    full = StageContext(config, {"surface": "S", "resolution_scan": "R"}, SerialExecutor())
    context = full.for_stage(probe)
    assert context.config.material.e_star == config.material.e_star
    assert context.config.bem.tol == config.bem.tol  # a whole section is declared
    assert context.result(SURFACE) == "S"
    assert context.measured.normal_area is None
    with pytest.raises(UndeclaredReadError, match=r"'work_of_adhesion' is not declared"):
        _ = context.config.material.work_of_adhesion
    with pytest.raises(UndeclaredReadError, match=r"\[loading\]"):
        _ = context.config.loading
    with pytest.raises(UndeclaredReadError, match="resolution_scan"):
        context.result(SCAN)
    with pytest.raises(UndeclaredReadError, match="shear_area"):
        _ = context.measured.shear_area


def test_a_declared_key_that_the_schema_does_not_have_is_refused(small, tmp_path):
    context = StageContext(small(tmp_path), {}, SerialExecutor())
    stage = dataclasses.replace(STAGES[2], config=("material.E_stare",))
    with pytest.raises(UndeclaredReadError, match="no key 'E_stare'"):
        _ = context.for_stage(stage).config.material


def test_bem_settings_are_the_fields_of_bem_config_and_the_declared_keys():
    """The ``[bem]`` keys are written once, as BemConfig's fields: the stage declares each
    (``enabled`` only switches it on); bem_reference takes the BemConfig itself."""
    fields = [f.name for f in dataclasses.fields(BemConfig) if f.name != "enabled"]
    assert list(bem_stage.SETTINGS) == fields
    assert {k for k in bem_stage.BEM.config if k.startswith("bem.")} == {
        f"bem.{name}" for name in fields
    }


def test_result_types_and_numbers_follow_from_the_stage_list():
    names = [s.name for s in STAGES]
    hints = typing.get_type_hints(results.StageResults)
    assert [f.name for f in dataclasses.fields(results.StageResults)] == names
    for stage in STAGES:  # each field typed by the stage's result, None where absent
        assert hints[stage.name] == stage.result | None, stage.name
    for cls in (job.JobResult, results.Results):
        assert [f.name for f in dataclasses.fields(cls)][: len(STAGES)] == names
    assert results.ALIASES == {s.attribute: s.name for s in STAGES if s.attribute}
    for number, stage in enumerate(STAGES, start=1):
        assert stage_number(stage.name) == stage_number(stage.attribute or stage.name) == number
        assert stage_label(stage, STAGES) == f"{number} {stage.title}"
        assert not stage.title[0].isdigit()  # the number is never written by hand


def test_the_stage_table_of_the_stages_package_is_the_stage_list():
    import asperity.pipelines.stages as package

    rows = [line.split() for line in package.__doc__.splitlines() if line[:3].strip().isdigit()]
    table = [(int(row[0]), row[1], row[2]) for row in rows]
    assert table == [
        (i, s.name, f":mod:`~{s.compute.__module__}`") for i, s in enumerate(STAGES, start=1)
    ]


def test_the_normal_contact_model_does_not_read_lambda_or_tau0():
    """The statistical-model stage keys on E*, w and epsilon only: its areas and pull-off
    forces are the same whatever the shear-only properties are."""
    rough = statmodel.Roughness(asperity_density=2e8, summit_radius=1e-4, summit_height_rms=2e-6)
    loads = np.array([0.5, 1.0, 2.0])
    base = dict(e_star=2.133e6, work_of_adhesion=0.04, equilibrium_distance=0.2e-9)
    values = []
    for mode_mixity, shear_strength in [(0.0, 0.0), (0.03, 1.3e5), (1.0, 1e9)]:
        material = statmodel.Material(
            **base, mode_mixity=mode_mixity, shear_strength=shear_strength
        )
        area = statmodel.real_area_at_loads(material, rough, 7e-4, loads)
        values.append((*np.asarray(area), statmodel.pull_off_force(material, rough, 7e-4)))
    assert values[0] == values[1] == values[2]
    configured = statmodel.Material(**base, mode_mixity=0.3, shear_strength=1e5)
    used = normal_contact_material(configured)
    assert (used.e_star, used.work_of_adhesion, used.equilibrium_distance) == tuple(base.values())


def test_the_stage_table_of_docs_pipelines_is_the_stage_list():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "pipelines.md").read_text()
    section = text.split("## The stages, and the same from Python", 1)[1].split("```", 1)[0]
    rows = [
        [cell.strip() for cell in line.strip("|").split("|")]
        for line in section.splitlines()
        if line.startswith("| ") and line.split("|")[1].strip().isdigit()
    ]
    assert [(int(r[0]), r[-1].strip("`")) for r in rows] == [
        (i, s.name) for i, s in enumerate(STAGES, start=1)
    ]


def _result_types():
    from asperity.statmodel import ShearCurve
    from asperity.topo import HeightMap
    from asperity.topo.scan import ResolutionScan

    return [HeightMap, ResolutionScan, ShearCurve, *(s.result for s in STAGES)]


@pytest.mark.parametrize("cls", _result_types(), ids=lambda c: c.__name__)
def test_every_stored_field_is_described_once_and_in_the_docstring(cls):
    from asperity.fields import undocumented_fields

    assert undocumented_fields(cls) == []


def test_the_friction_outputs_take_their_units_from_the_shear_curve_declaration():
    from asperity.fields import field_specs
    from asperity.statmodel import ShearCurve
    from asperity.statmodel.results_io import ARRAY_UNITS, SCALAR_UNITS

    curve = {s.name: s for s in field_specs(ShearCurve)}
    stage = {s.name: s for s in field_specs(STAGES[5].result)}
    for name, units in {**ARRAY_UNITS, **SCALAR_UNITS}.items():
        assert curve[name].units == units
        if name != "normal_load":
            assert (stage[name].units, stage[name].long_name) == (units, curve[name].long_name)
            assert stage[name].dims == ("normal_load", *curve[name].dims)


def test_results_module_does_not_import_the_job():
    """results.py needs no job.py (job.py imports results.py only): no import cycle between
    them, so a reopened run reads without loading the job runner."""
    code = (
        "import pathlib, sys, asperity.pipelines.results as r; "
        "assert r.Results(path=pathlib.Path('results.h5')).problems() == []; "
        "print('asperity.pipelines.job' in sys.modules)"
    )
    assert python_stdout(code) == "False"
