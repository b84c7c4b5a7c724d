"""``asperity batch JOB.toml MAP [MAP ...] [--out DIR] [--workers N] [--scheduler ADDRESS]
[--force]``.

Every map (globs allowed: quote them, or let the shell expand them) through the same job, each
in its own folder of ``--out`` (resumable), then ``summary.csv`` and ``summary.png`` across the
maps (:mod:`pipelines.batch`). Exit status: 0 every map ok, 1 some map did not converge, 2 a
bad job or map argument (before any map runs) or some map failed (named in summary.csv and on
stderr; the other maps still ran). A MAP named outright that is a directory, a FIFO, a device or
a socket is refused on its own line (``REFUSED MAP: ...``) and the other maps run; the batch
then exits 2 (the summary lists the maps that ran).
"""

from __future__ import annotations

import argparse
import sys

from asperity.errors import InputError, error_line
from asperity.files import describe_kind, require_output_dir
from asperity.quantities import quantity
from asperity.schema import read_toml


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``batch`` sub-command."""
    parser = subparsers.add_parser(
        "batch",
        help="run one job on many height maps; summary.csv and summary.png across them",
        description="Run JOB.toml on every MAP (its [surface] file replaced by the map), each in "
        "its own folder of --out, resumable; then summary.csv (one row per map, mean and std "
        "rows) and summary.png. A failing map is reported and does not stop the others.",
    )
    parser.add_argument("job", metavar="JOB.toml", help="the job configuration")
    parser.add_argument("maps", nargs="+", metavar="MAP", help="height-map files or glob patterns")
    parser.add_argument(
        "--out", default="asperity-batch", metavar="DIR", help="output folder (asperity-batch)"
    )
    parser.add_argument(
        "--workers",
        type=quantity("run.workers").option("--workers"),
        default=1,
        metavar="N",
        help="maps run at once locally (1)",
    )
    parser.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="dask.distributed scheduler: one map per task (needs the 'dask' extra)",
    )
    parser.add_argument("--force", action="store_true", help="recompute every stage")
    parser.set_defaults(func=handle_batch)


def handle_batch(args: argparse.Namespace) -> int:
    """Run the batch; the exit status of :attr:`pipelines.batch.BatchResult.status`."""
    # deferred: the job's numerical stages and matplotlib, only for the command
    from asperity.pipelines.batch import run_batch

    require_output_dir(args.out, "--out")  # an unwritable folder stops before any map runs
    read_toml(args.job, "job")  # a FIFO, an oversized or too deeply nested file: exit 2 now
    maps, refused = [], []
    for pattern in args.maps:
        kind = describe_kind(pattern) if not any(c in pattern for c in "*?[") else None
        if kind is not None and kind != "a regular file":
            refused.append(f"  REFUSED {pattern}: is {kind}, expected a height-map file")
        else:
            maps.append(pattern)
    for line in refused:
        print(error_line("  ", line.strip()), file=sys.stderr)
    if not maps:
        raise InputError(f"MAP: none of the {len(args.maps)} entries is a height-map file")
    result = run_batch(
        args.job,
        maps,
        args.out,
        workers=args.workers,
        scheduler=args.scheduler,
        force=args.force,
        log=lambda line: print(error_line("", line), file=sys.stderr),
    )
    ok = sum(r["status"] == "ok" for r in result.records)
    print(f"{ok} / {len(result.records)} maps ok; summary: {result.summary_csv}")
    for record in result.records:
        if record["status"] in ("failed", "invalid", "not converged"):
            state = record["status"].upper()
            line = error_line(f"  {state} ", f"{record['map']}: {record['message']}")
            print(line, file=sys.stderr)
    return 2 if refused else result.status  # a refused map counts as a failed one
