"""A stage of the job, declared once as data: what it reads, what it returns, how it is keyed.

A :class:`Stage` names its HDF5 group, the configuration keys and the earlier stages it reads,
its result dataclass (fields with units and dims, :mod:`asperity.fields`) and the function that
computes it. From that one declaration :class:`Runner` keys, stores, reuses and checks the
stage, and its result is the field of :class:`~asperity.pipelines.results.StageResults`
(``JobResult``, ``Results``) named by its group (a test holds the two lists together); nothing
else lists its fields or its dependencies. A stage's number is its place in
:data:`asperity.pipelines.stages.STAGES`. Example (the one docs/DEVELOPING.md walks through)::

    ROUGHNESS = Stage(
        name="roughness",              # its group in results.h5
        title="roughness parameters",  # the log says "<number> roughness parameters"
        result=RoughnessParameters,    # fields declared with asperity.fields
        config=("surface.max_stride",),
        inputs=(SURFACE,),
        compute=compute_roughness,     # (StageContext) -> RoughnessParameters
    )

The key of a stage is the SHA-256 of one JSON document holding exactly the configuration
values it declares (a whole section, ``"bem"``, or one key, ``"material.E_star"``; files named
by those keys enter by their SHA-256), the keys of its input stages and the package version
(:data:`asperity.__version__`), so that a result of an older solver is recomputed, never
relabelled. A disabled stage (``enabled(config)`` false) has no result (None) and its key is
"disabled"; a disabled input enters no key (its result, None, does not depend on its keys).

``compute`` sees only what it declares (:mod:`~asperity.pipelines.engine.views`): its
configuration keys, its input stages and the measured curves named by its ``measured.*`` keys;
reading anything else raises :class:`~asperity.pipelines.engine.views.UndeclaredReadError`,
so a key read but not declared cannot silently reuse a result stored with another value.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar, cast

from asperity.fields import field_specs
from asperity.pipelines.config import JOB_SCHEMA, Document, JobConfig, TomlValue
from asperity.pipelines.engine.interrupts import checkpoint
from asperity.pipelines.engine.store import ResultStore, StoredStageError
from asperity.pipelines.engine.views import ConfigView, DeclaredView, UndeclaredReadError
from asperity.pipelines.measured import Measurements

R = TypeVar("R")
T = TypeVar("T")

#: The key of a stage that ``enabled(config)`` switched off.
DISABLED = "disabled"


def _always(config: JobConfig) -> bool:
    return True


@dataclass
class StageContext:
    """What a stage's ``compute`` gets: the configuration, its inputs and where to run.

    Attributes
    ----------
    config : JobConfig or ConfigView
        The validated job configuration; for ``compute``, a view of the keys it declares.
    results : dict
        Results of the stages run so far, by name (None for a disabled stage).
    executor : Executor
        Runs independent sweeps (serial, worker processes or dask).
    progress : bool
        Show progress bars.
    measured : Measurements or DeclaredView
        The measured curves, read before any stage ran; for ``compute``, only those its
        ``measured.*`` keys declare.
    inputs : tuple of str or None
        The stages ``result`` may give (None: any stage run so far).
    """

    config: JobConfig | ConfigView
    results: dict[str, Any]
    executor: Executor
    progress: bool = False
    measured: Measurements | DeclaredView = field(default_factory=Measurements)
    inputs: tuple[str, ...] | None = None

    def result(self, stage: Stage[T]) -> T:
        """The result of an input stage (None when it was disabled).

        Raises
        ------
        UndeclaredReadError
            ``stage`` is not among the declared inputs of the stage being computed.
        """
        if self.inputs is not None and stage.name not in self.inputs:
            raise UndeclaredReadError(
                f"stage result {stage.name!r} is not a declared input (inputs: "
                f"{', '.join(self.inputs) or 'none'})"
            )
        return self.results[stage.name]

    def for_stage(self, stage: Stage | Preview) -> StageContext:
        """The context ``stage.compute`` (or a preview's ``run``) sees: its declared keys,
        inputs and measurements."""
        measured_keys = {k.split(".", 1)[1]: k for k in stage.config if k.startswith("measured.")}
        measured: Measurements | DeclaredView = self.measured
        if "measured" not in stage.config:
            where = f"stage {stage.name!r}, measured curves"
            measured = DeclaredView(self.measured, measured_keys, where)
        return StageContext(
            config=ConfigView(self.config, stage.config, stage.name, JOB_SCHEMA.sections),
            results=self.results,
            executor=self.executor,
            progress=self.progress,
            measured=measured,
            inputs=tuple(s.name for s in stage.inputs),
        )


@dataclass(frozen=True)
class PreviewNote:
    """What a :class:`Preview` found: lines for the log and a record for ``results.h5``.

    Attributes
    ----------
    lines : list of str
        Logged before the stage the preview precedes.
    record : dict
        JSON-ready; stored as the file attribute ``preview_<name>`` of ``results.h5`` (JSON
        text) at once, before that stage runs.
    """

    lines: list[str]
    record: dict[str, Any]


@dataclass(frozen=True)
class Preview:
    """A cheap part of a later stage's judgement, made and said before an expensive stage.

    E.g. the verdict's adhesion regime (a second, from the map) before the BEM stage
    (minutes): the user learns at once what the BEM's numbers will mean, and the job still
    runs every stage asked for. Declared on the later stage (``Stage.preview``); it reads only
    what it declares, as a stage does.

    Attributes
    ----------
    name : str
        Its name: the file attribute ``preview_<name>`` holds its record.
    before : str
        The group name of the stage it runs before (each time that stage is computed or
        taken from the store; not when that stage is disabled).
    config : tuple of str
        Configuration keys it reads.
    inputs : tuple of Stage
        Earlier stages it reads (all before ``before``).
    run : callable
        ``run(context) -> PreviewNote | None`` (None: nothing to say).
    """

    name: str
    before: str
    config: tuple[str, ...]
    inputs: tuple[Stage, ...]
    run: Callable[[StageContext], PreviewNote | None]


@dataclass(frozen=True)
class Stage(Generic[R]):
    """One stage of the job, declared as data.

    Attributes
    ----------
    name : str
        HDF5 group name in ``results.h5``.
    title : str
        How the log and the report call it ("BEM reference"; the number comes from the
        stage's place in the job's list, :func:`stage_label`).
    result : type
        The result dataclass (every field declared with :mod:`asperity.fields`).
    config : tuple of str
        Configuration keys it reads: a section ("bem") or one key ("material.E_star").
    inputs : tuple of Stage
        Earlier stages it reads.
    compute : callable
        ``compute(context) -> result``; ``context`` holds only the declared keys and inputs.
    enabled : callable
        ``enabled(config) -> bool``; a disabled stage is skipped and its result is None.
    check : callable or None
        ``check(context, result)``, run after the stage is computed *or* taken from the store
        (e.g. the loads checked against the pull-off force after the resolution scan).
    attribute : str or None
        A deprecated second name of the stage on ``JobResult`` and ``Results`` (asperity 0.3's
        ``run.bem`` for ``run.bem_reference``), answered with a ``DeprecationWarning``; None
        for a stage that only has its group name (every new stage).
    preview : Preview or None
        A part of this stage's judgement made early, before an earlier stage runs.
    """

    name: str
    title: str
    result: type[R]
    config: tuple[str, ...]
    inputs: tuple[Stage, ...]
    compute: Callable[[StageContext], R]
    enabled: Callable[[JobConfig], bool] = _always
    check: Callable[[StageContext, R], None] | None = None
    attribute: str | None = None
    preview: Preview | None = None

    def __post_init__(self) -> None:
        field_specs(self.result)  # a faulty result declaration fails at import


@dataclass
class StageRun:
    """How one stage went.

    Attributes
    ----------
    name : str
        Stage (group) name.
    key : str
        Its key ("disabled" when switched off).
    status : str
        "computed", "stored" (taken from results.h5) or "disabled".
    seconds : float
        Wall time of the computation, s (the stored one when reused).
    note : str
        Why a stored result was not reused, when it was not.
    """

    name: str
    key: str
    status: str
    seconds: float
    note: str = ""

    @property
    def cached(self) -> bool:
        """Taken from the store."""
        return self.status == "stored"


def stage_label(stage: Stage, stages: Sequence[Stage]) -> str:
    """ "<number> <title>", numbered from 1 by the stage's place in ``stages``."""
    return f"{list(stages).index(stage) + 1} {stage.title}"


def config_value(document: Mapping[str, TomlValue], path: str) -> TomlValue:
    """The value at a dotted path of the configuration document ("material.E_star")."""
    first, *rest = path.split(".")
    value = document[first]
    for part in rest:
        if not isinstance(value, dict):
            raise KeyError(path)
        value = value[part]
    return value


def key_document(
    stage: Stage,
    config_document: Mapping[str, TomlValue],
    input_keys: Mapping[str, str],
    version: str,
) -> Document:
    """Everything a stage's result depends on, as one JSON-ready document."""
    return {
        "stage": stage.name,
        "asperity_version": version,
        "config": {path: config_value(config_document, path) for path in stage.config},
        # a disabled input enters no key: a stage reading an optional stage (bem_shear) keeps
        # the key it had before that stage existed while the stage is off
        "inputs": {
            s.name: input_keys[s.name] for s in stage.inputs if input_keys[s.name] != DISABLED
        },
    }


def hash_document(document: Mapping[str, TomlValue]) -> str:
    """SHA-256 of a JSON document (keys sorted)."""
    text = json.dumps(document, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass
class Runner:
    """Runs declared stages in order against one :class:`ResultStore`.

    Results computed before the last stage that has a ``check`` are held in memory and
    written once that check passed, so a configuration refused by a check (loads below the
    pull-off force) changes nothing on disk. Every write carries the file's provenance and
    drops the stored stages this configuration would not reuse, so the provenance always
    describes the stages beside it.

    Attributes
    ----------
    store : ResultStore
        ``results.h5``.
    context : StageContext
        Passed to every stage.
    config_document : dict
        The configuration as plain data, files replaced by their SHA-256 (what keys hash).
    version : str
        Package version entering every key.
    root_attrs : dict
        File provenance written with each stage.
    force : bool
        Recompute stages even when stored.
    log : callable
        Receives one line per stage.
    """

    store: ResultStore
    context: StageContext
    config_document: Document
    version: str
    root_attrs: dict[str, str]
    force: bool = False
    log: Callable[[str], None] = print
    keys: dict[str, str] = field(default_factory=dict)
    documents: dict[str, str] = field(default_factory=dict)
    runs: list[StageRun] = field(default_factory=list)
    pending: list[tuple[Stage, object, float]] = field(default_factory=list)
    labels: dict[str, str] = field(default_factory=dict)
    previews: dict[str, list[Preview]] = field(default_factory=dict)

    def plan(self, stages: Sequence[Stage]) -> None:
        """Key every stage before any runs (keys depend on the configuration alone), and
        gather the previews by the stage they precede."""
        self.labels = {stage.name: stage_label(stage, stages) for stage in stages}
        self.previews = {}
        config = self.job_config()
        for stage in stages:
            if stage.preview is not None and stage.enabled(config):
                self.previews.setdefault(stage.preview.before, []).append(stage.preview)
        for stage in stages:
            if not stage.enabled(config):
                self.keys[stage.name], self.documents[stage.name] = DISABLED, ""
                continue
            document = key_document(stage, self.config_document, self.keys, self.version)
            self.keys[stage.name] = hash_document(document)
            self.documents[stage.name] = json.dumps(document, sort_keys=True, default=str)

    def job_config(self) -> JobConfig:
        """The whole validated configuration: the runner's own context holds it (each stage's
        ``compute`` sees a :class:`ConfigView` of it, built by :meth:`StageContext.for_stage`)."""
        return cast(JobConfig, self.context.config)

    def run_all(self, stages: Sequence[Stage]) -> None:
        """Plan, then run every stage in order; write what was computed."""
        self.plan(stages)
        last_check = max((i for i, s in enumerate(stages) if s.check is not None), default=-1)
        for i, stage in enumerate(stages):
            self.run(stage)
            if i >= last_check:
                self.flush()
        self.flush()
        stale = self.stale()
        if stale or self.store.root_attrs().get("config_toml") != self.root_attrs["config_toml"]:
            self.store.write(root_attrs=self.root_attrs, drop=stale)

    def stale(self) -> list[str]:
        """Stored groups that this configuration would not reuse."""
        stored = self.store.stored()
        return [name for name in stored if self.keys.get(name) != stored[name].key]

    def reuse(self, stage: Stage[R], key: str) -> tuple[R | None, float, str]:
        """The stored result when it has this key and passes its checksum."""
        stored = self.store.stored().get(stage.name)
        if self.force or stored is None or stored.key != key:
            return None, 0.0, ""
        try:
            return self.store.read(stage.name, stage.result), stored.seconds, ""
        except StoredStageError as exc:
            return None, 0.0, f"stored result not reused: {exc}"

    def run(self, stage: Stage[R]) -> R | None:
        """Compute, or take from the store, one stage (its write waits for :meth:`flush`).

        A Ctrl-C requested meanwhile stops the run here, before the stage (a safe point:
        :mod:`~asperity.pipelines.engine.interrupts`).
        """
        checkpoint()
        key, label = self.keys[stage.name], self.labels.get(stage.name, stage.title)
        if key == DISABLED:
            self.runs.append(StageRun(stage.name, key, "disabled", 0.0))
            self.context.results[stage.name] = None
            self.log(f"{label}: disabled")
            return None
        for preview in self.previews.get(stage.name, ()):
            self.run_preview(preview, label)
        reused = self.reuse(stage, key)  # unpacked apart: mypy would infer R from the targets
        stored, seconds, note = reused
        if stored is not None:
            result = stored
            self.runs.append(StageRun(stage.name, key, "stored", seconds))
            self.log(f"{label}: stored, skipped")
        else:
            if note:
                self.log(f"{label}: {note}")
            t0 = time.perf_counter()
            result = stage.compute(self.context.for_stage(stage))
            seconds = time.perf_counter() - t0
            self.pending.append((stage, result, seconds))
            self.runs.append(StageRun(stage.name, key, "computed", seconds, note))
            self.log(f"{label}: {seconds:.2f} s")
        self.context.results[stage.name] = result
        if stage.check is not None:
            stage.check(self.context, result)
        return result

    def run_preview(self, preview: Preview, before: str) -> PreviewNote | None:
        """Run ``preview`` before the stage labelled ``before``: log its lines, and store its
        record as the file attribute ``preview_<name>`` (JSON) in ``results.h5``: at once when
        every result computed so far is written (an interrupted run keeps it), else with them
        once the checks that hold them back passed."""
        note = preview.run(self.context.for_stage(preview))
        if note is None:
            return None
        for line in note.lines:
            self.log(f"before {before}: {line}")
        record = {"before": preview.before, **note.record}
        self.root_attrs[f"preview_{preview.name}"] = json.dumps(record, default=str)
        if not self.pending:
            self.store.write(root_attrs=self.root_attrs, drop=self.stale())
        return note

    def flush(self) -> None:
        """Write the computed results held so far, each in one atomic write."""
        while self.pending:
            stage, result, seconds = self.pending.pop(0)
            self.store.write(
                stage.name,
                result,
                key=self.keys[stage.name],
                key_inputs=self.documents[stage.name],
                seconds=seconds,
                root_attrs=self.root_attrs,
                drop=[name for name in self.stale() if name != stage.name],
            )
            checkpoint()  # the stage is stored: a Ctrl-C stops the run here
