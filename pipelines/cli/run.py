"""``asperity run``: the main job, from a surface to a calibrated friction prediction.

``asperity run [CONFIG.toml] [--out DIR] [--preset default|paper] [--force] [--replace]
[--compute-all] [--workers N] [--scheduler ADDRESS]``

Without a configuration the embedded ``default`` preset runs (the paper-like synthetic surface
on a reduced grid, about a minute). The configuration is validated before any heavy work; a
bad key exits 2 naming it. Exit status 1 when a solver did not converge (everything is still
written), else 3 when the validity verdict is "invalid" (:mod:`pipelines.stages.verdict`). A verdict
known invalid before the BEM (the full-contact regime) stops the job there, exit 3, unless
``--compute-all`` (``run.compute_all = true``) asks for every stage.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from asperity.errors import InputError
from asperity.files import require_output_dir
from asperity.pipelines.cli import batch, report
from asperity.pipelines.config import PRESETS, JobConfig, load_config, load_preset
from asperity.pipelines.engine.outdir import OutputLock, report_removed_on_failure, write_error
from asperity.quantities import quantity

if TYPE_CHECKING:  # imported when a job runs (the CLI starts without the solvers)
    from asperity.pipelines.job import JobResult


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``run`` sub-command to the asperity parser."""
    parser = subparsers.add_parser(
        "run",
        help="the main job: surface -> resolution -> BEM -> statistical model -> lambda -> "
        "friction",
        description="Run (or resume) the stages and write results.h5, the figures and "
        "report.md in --out. SI units throughout.",
    )
    parser.add_argument(
        "config",
        nargs="?",
        default=None,
        metavar="CONFIG.toml",
        help="job configuration (default: the embedded 'default' preset)",
    )
    parser.add_argument(
        "--out",
        default="asperity-out",
        metavar="DIR",
        help="output directory (default: asperity-out)",
    )
    parser.add_argument(
        "--preset",
        choices=PRESETS,
        default=None,
        help="run a shipped preset instead of CONFIG.toml",
    )
    parser.add_argument(
        "--force",
        action="store_true",
        help="recompute every stage even when results.h5 holds it; also needed to replace a "
        "finished run of a different job in --out (refused otherwise, exit 2)",
    )
    parser.add_argument(
        "--replace",
        action="store_true",
        help="replace a finished run of a different job in --out, reusing the stages it shares "
        "with this job (the others are recomputed)",
    )
    parser.add_argument(
        "--compute-all",
        action="store_true",
        help="compute every stage even when the verdict is known invalid before the BEM "
        "(run.compute_all = true; by default the job stops there and states the full-contact "
        "limit)",
    )
    parser.add_argument(
        "--workers",
        type=quantity("run.workers").option("--workers"),
        default=None,
        metavar="N",
        help="worker processes for the sweeps (default: run.workers, 1)",
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler address (needs the 'dask' extra)",
    )
    parser.add_argument(
        "--quiet",
        action="store_true",
        help="no progress bars (they show only on a terminal anyway); the summary is printed",
    )
    parser.set_defaults(func=handle_run)
    register_companions(subparsers)


def register_companions(subparsers: argparse._SubParsersAction) -> None:
    """Add ``report`` (redraw from results.h5) and ``batch`` (many maps, one job)."""
    report.register(subparsers)
    batch.register(subparsers)


def _log_line(line: str) -> None:
    print(line, file=sys.stderr)


def handle_run(args: argparse.Namespace) -> int:
    """Run the job; 0 ok, 1 a solver did not converge, 3 the verdict is invalid."""
    if args.config is not None and args.preset is not None:
        raise InputError("give either CONFIG.toml or --preset, not both")
    config = (
        load_config(args.config)
        if args.config is not None
        else load_preset(args.preset or "default")
    )
    if getattr(args, "compute_all", False):
        config = replace(config, run=replace(config.run, compute_all=True))
    require_output_dir(args.out, "--out", probe=False)  # "" would write into the current folder
    # The lock first (a second run on --out stops at once, before the heavy imports); held over
    # the job and the report.
    with OutputLock(args.out, log=_log_line):
        result = _run_and_report(args, config)
    # deferred: matplotlib and the stages' numerics, not for --help
    from asperity.pipelines.report import summary_text

    print(summary_text(result))
    from asperity.pipelines.stages.verdict import exit_status

    return int(exit_status(result.converged, result.verdict))


def _run_and_report(args: argparse.Namespace, config: JobConfig) -> JobResult:
    """The job and its report in ``args.out`` (the caller holds the directory's lock)."""
    # Heavy imports only after the configuration passed validation.
    from asperity.pipelines.engine.interrupts import interruptible
    from asperity.pipelines.job import progress_enabled, run_job
    from asperity.pipelines.report import write_report

    result = run_job(
        config,
        args.out,
        force=args.force,
        replace_run=args.replace,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=progress_enabled() and not args.quiet,
        log=_log_line,
    )
    try:  # a report that cannot finish removes what it wrote of itself
        with report_removed_on_failure(args.out), interruptible():
            write_report(result, args.out)  # no safe point in the drawing: Ctrl-C stops it
    except OSError as exc:  # a full disk while writing the figures: results.h5 is complete
        error = write_error(
            Path(args.out), exc, "results.h5 holds every stage; the unfinished report was removed"
        )
        if error is None:
            raise
        raise error from exc
    return result
