"""Batch mode: every height map through the same job, one folder each, one summary across maps.

``run_batch("job.toml", ["maps/*.x3p"], "batch-out")`` runs :func:`pipelines.job.run_job` and
:func:`pipelines.report.write_report` once per map, with ``[surface] file`` replaced by the map
(every other key of the job as written), in ``batch-out/<map stem>/``. Each folder is an
ordinary, resumable run: running the batch again skips the stored stages, and a folder whose
run is finished and identical (results.h5 holds the same stage keys after the run as before,
its report there) is taken as it is, its figures not redrawn. Maps run one per task: in
this process, in ``workers`` processes, or one per task on a dask.distributed cluster. A map
that fails (an unreadable file, loads below its pull-off force, any error) is recorded with
its message and does not stop the others.

Outputs: ``summary.csv`` (one row per map: effective resolution, eta, R, sigma_s, lambda, and
at each load A_r/A_n, static and sliding friction, the verdict when the job has one; then a
``mean`` and a ``std`` row over the maps that succeeded; SI units in the headers) and
``summary.png`` (those quantities against the map, mean +- one standard deviation shaded).
"""

from __future__ import annotations

import glob
import sys
import traceback
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path

from asperity.errors import InputError
from asperity.pipelines.batch.summary import (
    MapRecord,
    write_summary_csv,
    write_summary_figure,
)
from asperity.pipelines.batch.summary import summary_values as _summary_values
from asperity.pipelines.config import Document, JobConfig, config_from_dict
from asperity.pipelines.engine.outdir import report_removed_on_failure
from asperity.pipelines.engine.parallel import Scheduler, make_executor
from asperity.pipelines.engine.store import ResultStore
from asperity.pipelines.job import JobResult, run_job
from asperity.pipelines.report import write_report

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

#: Characters that make a MAP argument a glob pattern.
GLOB_CHARS = "*?["


def expand_maps(patterns: Sequence[str]) -> list[Path]:
    """The map files named by ``patterns`` (globs expanded, sorted; duplicates dropped).

    Raises
    ------
    InputError
        A pattern that matches no file, or a named file that does not exist.
    """
    maps: list[Path] = []
    for pattern in patterns:
        if any(c in pattern for c in GLOB_CHARS):
            found = sorted(Path(p) for p in glob.glob(pattern, recursive=True) if Path(p).is_file())
            if not found:
                raise InputError(f"MAP {pattern!r}: expected a glob matching files, got none")
        else:
            found = [Path(pattern)]
            if not found[0].is_file():
                raise InputError(f"MAP {pattern}: file not found")
        maps += [p for p in found if p.resolve() not in {m.resolve() for m in maps}]
    if not maps:
        raise InputError("MAP: expected at least one height-map file")
    return maps


def read_job(path: str | Path) -> tuple[Document, Path]:
    """The job file's TOML data and its folder (relative names are taken from there)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_bytes().decode("utf-8"))
    except FileNotFoundError as exc:
        raise InputError(f"{path}: job file not found") from exc
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"{path}: cannot read the job: {exc}") from exc
    return data, path.resolve().parent


def map_config(data: Document, base_dir: Path, source: str, map_path: Path) -> JobConfig:
    """The job with ``[surface] file`` set to ``map_path`` (any synthetic recipe dropped)."""
    table = data.get("surface", {})
    if not isinstance(table, dict):
        raise InputError(f"{source}: [surface] expected a table, found {type(table).__name__}")
    surface = {k: v for k, v in table.items() if k != "synthetic"}
    surface["file"] = str(Path(map_path).resolve())
    return config_from_dict(
        {**data, "surface": surface}, source=f"{source} [{map_path}]", base_dir=base_dir
    )


def map_folders(maps: Sequence[Path], out_dir: Path) -> list[Path]:
    """One output folder per map: its stem, numbered when two maps share a stem."""
    stems = [m.stem for m in maps]
    return [out_dir / (s if stems.count(s) == 1 else f"{s}-{i + 1}") for i, s in enumerate(stems)]


def summary_values(result: JobResult) -> dict[str, float | str]:
    """The summary numbers of one run (:func:`pipelines.batch.summary.summary_values`)."""
    return _summary_values(result)


def _map_status(result: JobResult) -> str:
    """A finished run's status: "not converged" first, then "invalid" (the verdict), else "ok"."""
    if not result.converged:
        return "not converged"
    verdict = getattr(result, "verdict", None)
    return "invalid" if getattr(verdict, "verdict", None) == "invalid" else "ok"


def _invalid_reasons(result: JobResult) -> list[str]:
    """The verdict's reasons of severity "invalid" (none for a valid run or no verdict)."""
    verdict = getattr(result, "verdict", None)
    if verdict is None:
        return []
    pairs = zip(verdict.severities, verdict.reasons, strict=True)
    return [reason for severity, reason in pairs if severity == "invalid"]


def run_one_map(
    data: Document, base_dir: str, source: str, map_path: str, folder: str, force: bool
) -> MapRecord:
    """Run (or resume) the job on one map; never raises: failures come back as a record.

    Returns
    -------
    dict
        ``map``, ``folder``, ``status`` ("ok", "not converged", "invalid" or "failed"),
        ``message`` and,
        unless failed, ``values`` (:func:`summary_values`).
    """
    record: MapRecord = {"map": map_path, "folder": folder, "status": "failed"}
    try:
        config = map_config(data, Path(base_dir), source, Path(map_path))
        before = _stored_keys(folder)
        result = run_job(config, folder, force=force, workers=1)
        if not _finished_report_in(folder, before):
            with report_removed_on_failure(folder):  # never half a report
                write_report(result, folder)
        record["status"] = _map_status(result)
        record["message"] = "; ".join([*_invalid_reasons(result), *result.problems()][:3])
        record["values"] = summary_values(result)
        record["computed"] = [s.name for s in result.stages if s.status == "computed"]
    except Exception as exc:  # noqa: BLE001 (one map's failure must not stop the batch)
        kind = "bad input" if isinstance(exc, InputError) else type(exc).__name__
        record["message"] = f"{kind}: {' '.join(str(exc).split())}"
        record["traceback"] = traceback.format_exc(limit=5)
    return record


def _stored_keys(folder: str | Path) -> dict[str, str]:
    """The stage keys stored in ``folder``'s results.h5 ({} when none can be read)."""
    path = Path(folder) / "results.h5"
    if not path.is_file():
        return {}
    try:
        return {name: info.key for name, info in ResultStore(path).stored().items()}
    except InputError:  # unreadable or hostile: run_job sets it aside and recomputes
        return {}


def _finished_report_in(folder: str | Path, before: dict[str, str]) -> bool:
    """Whether ``folder`` already holds this run's report: results.h5 holds, after the run,
    exactly the stages with exactly the keys it held before (the same job, the same
    asperity, the same inputs: the same numbers and verdict), and report.md and report.html
    are there. A finished identical run in the folder is then reused whole, its figures not
    redrawn (``asperity report DIR`` redraws them)."""
    folder = Path(folder)
    same = bool(before) and "verdict" in before and _stored_keys(folder) == before
    return same and (folder / "report.md").is_file() and (folder / "report.html").is_file()


@dataclass
class BatchResult:
    """What a batch produced.

    Attributes
    ----------
    records : list of dict
        One per map, in the order of the maps (:func:`run_one_map`).
    summary_csv, summary_figure : Path
        ``summary.csv`` and ``summary.png``.
    """

    records: list[MapRecord]
    summary_csv: Path
    summary_figure: Path | None = None
    failed: list[str] = field(default_factory=list)

    @property
    def status(self) -> int:
        """Exit status: 2 some map failed (bad input) or raised, else 1 some map did not
        converge, else 3 some map's verdict is invalid, else 0."""
        states = {r["status"] for r in self.records}
        for state, status in (("failed", 2), ("not converged", 1), ("invalid", 3)):
            if state in states:
                return status
        return 0


def run_batch(
    job_path: str | Path,
    patterns: Sequence[str],
    out_dir: str | Path,
    *,
    workers: int = 1,
    scheduler: Scheduler = None,
    force: bool = False,
    log: Callable[[str], None] | None = None,
) -> BatchResult:
    """Run the job of ``job_path`` on every map of ``patterns``; write the summary.

    Parameters
    ----------
    job_path : path
        The job TOML; its ``[surface] file`` (or recipe) is replaced by each map.
    patterns : sequence of str
        Map files or glob patterns.
    out_dir : path
        Output folder: one sub-folder per map, ``summary.csv``, ``summary.png``.
    workers : int
        Maps run at once in worker processes (1: one after the other here).
    scheduler : str or distributed.Client, optional
        Run one map per task on this dask.distributed cluster instead.
    force : bool
        Recompute every stage of every map.
    log : callable, optional
        Receives one line per finished map.

    Raises
    ------
    InputError
        A bad job file or key, or a map pattern matching nothing: before any map runs.
    """
    log = log or (lambda line: None)
    data, base_dir = read_job(job_path)
    maps = expand_maps(patterns)
    map_config(data, base_dir, str(job_path), maps[0])  # a bad job key stops here, exit 2
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    folders = map_folders(maps, out_dir)
    args = [
        (data, str(base_dir), str(job_path), str(m), str(f), force)
        for m, f in zip(maps, folders, strict=True)
    ]
    with make_executor(workers, scheduler=scheduler) as executor:
        futures = []
        for a in args:
            future = executor.submit(run_one_map, *a)
            future.add_done_callback(_log_when_done(log, a[3]))
            futures.append(future)
        records = [_record(future, a) for a, future in zip(args, futures, strict=True)]
    csv_path = write_summary_csv(records, out_dir / "summary.csv")
    figure = write_summary_figure(records, out_dir / "summary.png")
    failed = [r["map"] for r in records if r["status"] == "failed"]
    return BatchResult(records, csv_path, figure, failed)


def _record(future: Future[MapRecord], args: tuple) -> MapRecord:
    """A map's record; a lost worker (the task itself raised) is a failed map."""
    try:
        return future.result()
    except Exception as exc:  # noqa: BLE001 (a worker lost: the map failed)
        return {"map": args[3], "folder": args[4], "status": "failed", "message": str(exc)}


def _log_when_done(
    log: Callable[[str], None], map_path: str
) -> Callable[[Future[MapRecord]], None]:
    """The callback that logs :func:`_log_line` for ``map_path`` once its run finishes."""

    def logged(done: Future[MapRecord]) -> None:
        log(_log_line(done, map_path))

    return logged


def _log_line(future: Future[MapRecord], map_path: str) -> str:
    """One line as a map finishes (completion order)."""
    record = _record(future, (None, None, None, map_path, ""))
    reason = f" ({record['message']})" if record.get("message") else ""
    return f"{map_path}: {record['status']}{reason}"
