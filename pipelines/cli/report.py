"""``asperity report OUT_DIR [--formats png,svg,pdf] [--dpi N]``: redraw a run's figures and report.

Reads ``OUT_DIR/results.h5`` (:func:`asperity.open_results`) and writes every figure (each
format, with its CSV), ``report.md`` and ``report.html`` again, without recomputing anything:
no solver runs. Formats and dpi default to the run's ``[report]`` section (stored in the
file's resolved configuration), else PNG at 150 dpi. Exit status 0, or 2 when the folder
holds no complete run, another run holds its lock, or it cannot be written (read-only, full).
Every file is written atomically; temporaries left by a killed run are removed first.
"""

from __future__ import annotations

import argparse
import sys

from asperity.errors import InputError
from asperity.pipelines.engine.outdir import OutputLock
from asperity.quantities import quantity

#: Stages a report needs (attributes of :class:`pipelines.results.Results`).
REQUIRED = ("surface", "resolution_scan", "statistical_model", "mode_mixity", "friction")


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``report`` sub-command."""
    parser = subparsers.add_parser(
        "report",
        help="redraw a run's figures, report.md and report.html from results.h5 (no solving)",
        description="Redraw every figure (each format, with its data as CSV), report.md and "
        "report.html from OUT_DIR/results.h5 without recomputing.",
    )
    parser.add_argument("out_dir", metavar="OUT_DIR", help="a run's output folder")
    parser.add_argument(
        "--formats",
        default=None,
        metavar="LIST",
        help="comma-separated figure formats among png, svg, pdf (default: the run's "
        "[report] formats, else png)",
    )
    parser.add_argument(
        "--dpi",
        type=quantity("report.dpi").option("--dpi"),
        default=None,
        metavar="N",
        help="PNG resolution (default: 150)",
    )
    parser.set_defaults(func=handle_report)


def stored_report_section(config_toml: str) -> dict:
    """The ``[report]`` table of a run's stored configuration ({} when absent)."""
    import tomllib

    try:
        return dict(tomllib.loads(config_toml).get("report", {}))
    except tomllib.TOMLDecodeError:
        return {}


def handle_report(args: argparse.Namespace) -> int:
    """Redraw the report of ``args.out_dir``; 0 on success."""
    # deferred: matplotlib and h5py, only for the command, not for --help
    from asperity.pipelines.report import write_report
    from asperity.pipelines.report.figure_output import FigureOptions
    from asperity.pipelines.results import open_results

    results = open_results(args.out_dir)
    missing = [name for name in REQUIRED if getattr(results, name) is None]
    if missing:
        raise InputError(
            f"{results.path}: expected a finished run, but stages {', '.join(missing)} are not "
            "stored (run `asperity run` first)"
        )
    stored = stored_report_section(results.config_toml)
    formats = (
        tuple(f.strip().lower() for f in args.formats.split(",") if f.strip())
        if args.formats is not None
        else tuple(stored.get("formats", ("png",)))
    )
    dpi = args.dpi if args.dpi is not None else int(stored.get("dpi", 150))
    try:
        options = FigureOptions(formats, dpi)
    except InputError as exc:
        raise InputError(f"--{exc}") from None
    # The folder's lock: no run writes there meanwhile, and temporaries of a killed run are removed.
    with OutputLock(
        results.out_dir, log=lambda line: print(line, file=sys.stderr), option="OUT_DIR"
    ):
        report = write_report(results, results.out_dir, options)
    print(f"{report}, {report.with_suffix('.html')} and the figures ({', '.join(options.formats)})")
    return 0
