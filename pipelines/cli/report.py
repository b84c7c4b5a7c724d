"""``asperity report OUT_DIR [--formats png,svg,pdf] [--dpi N]``: redraw a run's figures and report.

Reads ``OUT_DIR/results.h5`` (:func:`asperity.open_results`) and writes every figure (each
format, with its CSV), ``report.md`` and ``report.html`` again, without recomputing anything:
no solver runs. Formats and dpi default to the run's ``[report]`` section (stored in the
file's resolved configuration), else PNG at 150 dpi. Every file is written atomically;
temporaries left by a killed run are removed first.

``results.h5`` is untrusted input (a run folder may come from someone else): it is read only
if it is a regular file that refers to nothing outside itself and declares no more data than
it holds (:class:`asperity.pipelines.engine.store.ResultStore`); otherwise exit 2 names the
object. A report never shows numbers without their verdict: a file without a stored
``verdict`` stage is refused.

Exit status: the one ``asperity run`` gave for the stored run: 0, 1 when a stored solve did
not converge, 3 when the stored verdict is invalid (the report is written in every case, and
marked); 2 when the folder holds no complete run (the verdict included), an unsafe or damaged
``results.h5``, another run holds its lock, or it cannot be written (read-only, full).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import cast

from asperity.errors import InputError
from asperity.files import describe_kind, require_regular_file
from asperity.pipelines.engine.outdir import OutputLock, report_removed_on_failure
from asperity.quantities import quantity
from asperity.schema import clip

#: Stages a report needs (attributes of :class:`pipelines.results.Results`); the verdict
#: among them: no number is shown without it.
REQUIRED = ("surface", "resolution_scan", "statistical_model", "mode_mixity", "friction", "verdict")
#: The stages a run stopped where its verdict was known stores (stages.early_verdict).
EARLY_REQUIRED = ("surface", "resolution_scan", "verdict")


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
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover - exercised on Python 3.10 only
        import tomli as tomllib

    try:
        section = tomllib.loads(config_toml).get("report", {})
    except (tomllib.TOMLDecodeError, RecursionError):  # damaged, or nested past the stack
        return {}
    return dict(section) if isinstance(section, dict) else {}


def handle_report(args: argparse.Namespace) -> int:
    """Redraw the report of ``args.out_dir``; the stored run's exit status (module docstring)."""
    # deferred: matplotlib and h5py, only for the command, not for --help
    from asperity.pipelines.engine.interrupts import interruptible
    from asperity.pipelines.report import write_report
    from asperity.pipelines.report.figure_output import FigureOptions
    from asperity.pipelines.results import open_results
    from asperity.pipelines.stages.verdict import Verdict, exit_status, verdict_wording

    named = Path(args.out_dir)
    path = named / "results.h5" if named.is_dir() else named
    if describe_kind(path) is not None:  # a FIFO would be "not found" below, or block
        require_regular_file(path, "OUT_DIR")
    results = open_results(args.out_dir)
    early = getattr(results.verdict, "full_contact_real_area", None) is not None
    required = EARLY_REQUIRED if early else REQUIRED  # stopped where the verdict was known
    missing = [name for name in required if getattr(results, name) is None]
    if missing:
        raise InputError(
            f"{results.path}: expected a finished run, but stages {', '.join(missing)} are not "
            "stored (run `asperity run` first)"
        )
    stored = stored_report_section(results.config_toml)
    try:
        formats = (
            tuple(f.strip().lower() for f in args.formats.split(",") if f.strip())
            if args.formats is not None
            else tuple(str(f) for f in stored.get("formats", ("png",)))
        )
        dpi = args.dpi if args.dpi is not None else int(stored.get("dpi", 150))
        options = FigureOptions(formats, dpi)
    except InputError as exc:
        raise InputError(f"--{exc}") from None
    except (TypeError, ValueError) as exc:  # the stored [report] section is damaged
        raise InputError(
            f"{results.path}: the stored configuration's [report] section is not valid "
            f"({clip(str(exc))}); give --formats and --dpi"
        ) from None
    # The folder's lock: no run writes there meanwhile, and temporaries of a killed run are removed.
    with OutputLock(
        results.out_dir, log=lambda line: print(line, file=sys.stderr), option="OUT_DIR"
    ):
        # no safe point in the drawing: a Ctrl-C stops it at once; a report that cannot
        # finish removes what it wrote of itself
        with report_removed_on_failure(results.out_dir), interruptible():
            report = write_report(results, results.out_dir, options)
    print(f"{report}, {report.with_suffix('.html')} and the figures ({', '.join(options.formats)})")
    verdict = cast(Verdict, results.verdict)  # among the required stages: stored
    print(verdict_wording(verdict))
    return int(exit_status(results.converged, verdict))
