"""The whole job: the declared stages of :data:`STAGES` run in order, each stored in results.h5.

The stages are declared in their modules (:class:`~asperity.pipelines.engine.stage.Stage`):
what configuration keys and earlier stages each reads, and its typed result. A stage is skipped when
``results.h5`` already holds it with the same key (the hash of exactly what it reads, the keys
of its inputs and the package version) and its stored values pass their checksum: changing the
loads recomputes the BEM and everything after it, but not the surface or its resolution scan.
``force=True`` recomputes every stage. ``[bem] enabled = false`` skips the BEM; the measured
A_r(F_z) then alone chooses the effective resolution. When the adhesion regime judged before
the BEM makes the verdict invalid (``adhesion_full_contact``), the BEM and the model stages
are skipped and the verdict states the full-contact limit
(:mod:`asperity.pipelines.stages.early_verdict`); ``run.compute_all = true`` runs them anyway.

Python use::

    from asperity.pipelines import job, config
    result = job.run_job(config.load_preset("default"), "out")
    result.friction.static_friction      # N, one per load
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import asperity
from asperity.bem.progress import progress_line, solve_progress
from asperity.errors import InputError
from asperity.files import SpecialFileError
from asperity.h5 import UntrustedContentError
from asperity.pipelines.config import ConfigError, JobConfig
from asperity.pipelines.engine.interrupts import InterruptGuard, checkpoint
from asperity.pipelines.engine.outdir import (
    OutputLock,
    OutputWriteError,
    refuse_a_different_finished_job,
)
from asperity.pipelines.engine.parallel import Scheduler, make_executor
from asperity.pipelines.engine.stage import (
    DISABLED,
    R,
    Runner,
    Stage,
    StageContext,
    StageRun,
    hash_document,
    key_document,
    stage_label,
)
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.measured import Measurements, read_measurements
from asperity.pipelines.measured_friction import read_friction_files
from asperity.pipelines.results import StageResults, solver_problems
from asperity.pipelines.stages import STAGE_NAMES, STAGES
from asperity.pipelines.stages.early_verdict import SKIPPED_WHEN_KNOWN, known_invalid
from asperity.pipelines.stages.surface import input_sha256

__all__ = [
    "STAGES",
    "STAGE_NAMES",
    "JobResult",
    "run_job",
    "provenance",
    "progress_enabled",
    "solver_problems",
]


@dataclass(kw_only=True)
class JobResult(StageResults):
    """Everything the job produced (the same data as results.h5).

    Each stage's result is the field named by its group in results.h5
    (:class:`~asperity.pipelines.results.StageResults`): ``surface``, ``resolution_scan``,
    ``bem_reference``, ``statistical_model``, ``mode_mixity``, ``friction``, ``psd``,
    ``realisations``, ``verdict``, in the order of :data:`STAGES`. ``bem_reference`` is None
    when ``[bem] enabled = false``; ``verdict`` (:mod:`asperity.pipelines.stages.verdict`) says
    whether the report stands behind the numbers. ``problems()`` and ``converged`` say whether
    every solver converged.

    Attributes
    ----------
    config : JobConfig
        The configuration run.
    out_dir : Path
        The output folder.
    stages : list of StageRun
        How each stage went (computed, stored, disabled) and its seconds.
    total_seconds : float
        Wall time of the job, s.
    input_sha256 : str
        SHA-256 of the input map (or of the synthetic recipe).
    """

    config: JobConfig
    out_dir: Path
    stages: list[StageRun] = field(default_factory=list)
    total_seconds: float = 0.0
    input_sha256: str = ""


def provenance(config: JobConfig, input_hash: str) -> dict[str, str]:
    """The file-level attributes of results.h5: what this run was computed from."""
    return {
        "asperity_version": asperity.__version__,
        "config_toml": config.to_toml(),
        "config_source": config.source,
        "input_sha256": input_hash,
        "input": str(config.surface.file) if config.surface.file else "synthetic recipe",
        "conventions": "SI units; each group is a netCDF-4-style dataset (h5netcdf)",
    }


def run_job(
    config: JobConfig,
    out_dir: str | Path,
    *,
    force: bool = False,
    replace_run: bool = False,
    workers: int | None = None,
    scheduler: Scheduler = None,
    progress: bool = False,
    log: Callable[[str], None] | None = None,
) -> JobResult:
    """Run (or resume) the stages of :data:`STAGES` and write ``results.h5`` in ``out_dir``.

    Parameters
    ----------
    config : JobConfig
        The validated configuration.
    out_dir : path
        Output directory (created).
    force : bool
        Recompute every stage even when stored, and replace a finished run of another job.
    replace_run : bool
        Replace a finished run of another job in ``out_dir``, reusing the stored stages whose
        inputs it shares (the others are recomputed).
    workers : int, optional
        Worker processes for the sweeps (default: ``config.run.workers``).
    scheduler : str or distributed.Client, optional
        Run the sweeps on a dask.distributed cluster instead.
    progress : bool
        Show tqdm progress bars on stderr.
    log : callable, optional
        Receives one line per stage (e.g. ``print``).

    Returns
    -------
    JobResult
        Figures and the report are written separately by :func:`pipelines.report.write_report`.

    Raises
    ------
    pipelines.engine.outdir.OutputLockedError
        Another run holds ``out_dir`` (its lock file ``.asperity.lock``).
    pipelines.engine.outdir.DifferentJobError
        ``out_dir`` holds a finished run of another job (a configuration value its stages were
        computed with differs) and neither ``force`` nor ``replace_run``: nothing is written.
    pipelines.engine.outdir.OutputDirError, pipelines.engine.outdir.OutputWriteError
        ``out_dir`` cannot be written, or the disk is full: ``results.h5`` keeps what it held.
    KeyboardInterrupt
        Ctrl-C (SIGINT), always, even when it first landed in a finaliser that cannot raise
        (:mod:`pipelines.engine.interrupts`); ``results.h5`` keeps every stage written before.
    """
    t_job = time.perf_counter()
    out_dir = Path(out_dir)
    measured = _read_measured(config)  # a malformed CSV fails before any work
    input_hash = input_sha256(config.surface)
    workers = config.run.workers if workers is None else workers
    caller_log = log or (lambda line: None)

    def stage_log(line: str) -> None:  # a stage's line on its own line, above any solves bar
        progress_line(line, caller_log)

    with (
        InterruptGuard() as interrupts,  # a Ctrl-C swallowed in a finaliser is raised again
        OutputLock(out_dir, log=stage_log),  # one run per directory; stale temporaries removed
        make_executor(workers, scheduler=scheduler) as executor,
    ):
        runner = InterruptibleRunner(
            store=ResultStore(out_dir / "results.h5", set_aside=True),
            context=StageContext(config, {}, executor, progress, measured),
            config_document=config.key_document(),
            version=asperity.__version__,
            root_attrs=provenance(config, input_hash),
            force=force,
            log=stage_log,
        )
        if not (force or replace_run):  # a finished run of another job is never overwritten unasked
            runner.plan(STAGES)
            refuse_a_different_finished_job(
                out_dir,
                runner.store.stored(),
                runner.documents,
                (str(runner.store.root_attrs().get("config_source", "")), config.source),
            )
        try:
            run_stages(runner)  # each stage that solves shows its BEM solves (terminal only)
        except KeyboardInterrupt:
            interrupts.acknowledge()  # seen: the lock and the executor are released undisturbed
            raise
    return JobResult(
        config=config,
        out_dir=out_dir,
        **{stage.name: runner.context.results[stage.name] for stage in STAGES},
        stages=runner.runs,
        total_seconds=time.perf_counter() - t_job,
        input_sha256=input_hash,
    )


def _read_measured(config: JobConfig) -> Measurements:
    """The job's measured curves (``[measured]``: A_r(F_z), A_r(F_x), friction tests), in SI:
    a malformed CSV, or a curve at a load not configured, is an InputError naming it."""
    measured = read_measurements(
        config.measured, config.loading.nominal_area, config.loading.normal_loads
    )
    return replace(
        measured,
        friction_curves=read_friction_files(
            config.measured.friction_curves, config.loading.normal_loads
        ),
    )


@dataclass
class InterruptibleRunner(Runner):
    """The job's :class:`Runner`, with a safe point after each write of ``results.h5``: a
    Ctrl-C that a finaliser swallowed (:mod:`pipelines.engine.interrupts`) ends the run
    there, every finished stage written.

    It also stops where the verdict is known: when a preview run before the first stage of
    :data:`~asperity.pipelines.stages.early_verdict.SKIPPED_WHEN_KNOWN` (the adhesion regime,
    before the BEM) records an invalid reason, those stages are skipped (status "skipped",
    result None, their stored groups dropped) unless ``run.compute_all`` is true, and the
    verdict stage writes the early verdict with the full-contact limit.
    """

    stage_list: tuple[Stage, ...] = ()
    known_invalid: list[str] | None = None
    solves_note_shown: bool = False

    def run_all(self, stages: Sequence[Stage]) -> None:
        """:meth:`Runner.run_all`, the stages kept for re-keying after a skip."""
        self.stage_list = tuple(stages)
        super().run_all(stages)

    def run(self, stage: Stage[R]) -> R | None:
        """Skip ``stage`` when the verdict is known invalid before it, else run it."""
        skippable = stage.name in SKIPPED_WHEN_KNOWN and self.keys[stage.name] != DISABLED
        if skippable and not self.context.config.run.compute_all:
            if self.known_invalid is None:
                self.known_invalid = self._judge_before(stage)
            if self.known_invalid:
                self._skip(stage)
                return None
        return self._run_with_solves_bar(stage)

    def _run_with_solves_bar(self, stage: Stage[R]) -> R | None:
        """:meth:`Runner.run` with a bar of the stage's BEM solves (n/N, time left) from its
        first solve to its end, when progress is shown; :data:`SOLVES_NOTE` said once a job."""
        note = None if self.solves_note_shown else SOLVES_NOTE
        with solve_progress("BEM solves", enabled=self.context.progress, note=note) as bar:
            result = super().run(stage)
        self.solves_note_shown |= bar is not None and bar.shown
        return result

    def _judge_before(self, stage: Stage) -> list[str]:
        """Run the previews that precede ``stage`` or a disabled stage before it (the BEM's,
        with ``[bem] enabled = false``) and return the codes of their invalid reasons."""
        label = self.labels.get(stage.name, stage.title)
        codes: list[str] = []
        upto = self.stage_list[: self.stage_list.index(stage) + 1]
        for earlier in upto:
            for preview in self.previews.pop(earlier.name, ()):
                note = self.run_preview(preview, label)
                codes += known_invalid(None if note is None else note.record)
        return codes

    def _skip(self, stage: Stage) -> None:
        """Record ``stage`` as skipped and key the later stages without it."""
        label = self.labels.get(stage.name, stage.title)
        self.keys[stage.name], self.documents[stage.name] = DISABLED, ""
        why = f"the verdict is known invalid ({', '.join(self.known_invalid or [])})"
        self.runs.append(StageRun(stage.name, DISABLED, "skipped", 0.0, why))
        self.context.results[stage.name] = None
        self.log(f"{label}: skipped, {why}; run.compute_all = true computes it")
        later = self.stage_list[self.stage_list.index(stage) + 1 :]
        for other in later:
            if self.keys.get(other.name, DISABLED) != DISABLED:
                document = key_document(other, self.config_document, self.keys, self.version)
                self.keys[other.name] = hash_document(document)
                self.documents[other.name] = json.dumps(document, sort_keys=True, default=str)

    def flush(self) -> None:
        """Write the computed results held so far, then raise a Ctrl-C not yet seen."""
        super().flush()
        checkpoint()


#: Said once above the BEM solves bar: its force is the one solved on the map.
SOLVES_NOTE = (
    "F is the force solved on the map: the job's load scaled by A_map / A_n "
    "(the same A_r/A_n as on the nominal area)"
)


def run_stages(runner: Runner) -> None:
    """Run :data:`STAGES`; bad input met inside a stage names the stage and its config keys.

    A stage's functions see solver arguments (a load scaled to the map, a pixel grid); an
    :class:`InputError` about those is re-raised as a :class:`ConfigError` that says which
    stage met it and which configuration keys feed that stage, so the user knows what to edit.
    """
    try:
        runner.run_all(STAGES)
    except (ConfigError, OutputWriteError, SpecialFileError, UntrustedContentError):
        raise  # already name the key, or the output file (results.h5 a FIFO, hostile)
    except InputError as exc:
        stage = STAGES[min(len(runner.runs), len(STAGES) - 1)]
        keys = ", ".join(stage.config) or "none"
        raise ConfigError(
            f"stage {stage_label(stage, STAGES)} (configuration keys it reads: {keys}): {exc}"
        ) from exc


def progress_enabled() -> bool:
    """Progress bars only when stderr is a terminal."""
    return sys.stderr.isatty()
