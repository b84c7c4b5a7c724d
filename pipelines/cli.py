"""The ``asperity`` command line: a thin shell over the package's functions.

Each package contributes its own sub-commands through a ``register(subparsers)``
function in its ``cli`` module; this module only assembles them and turns
user-facing errors into a one-line message and a non-zero exit status.

Exit status: 0 success, 1 a solver did not converge (the result is still
written), 2 bad input (file, key or value), 130 interrupted.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from asperity.pipelines import __version__

#: Modules that provide ``register(subparsers)``; each adds its sub-commands.
COMMAND_MODULES: tuple[str, ...] = (
    "asperity.topo.cli",  # stats, scan, synth
    "asperity.bem.cli",  # bem
    "asperity.statmodel.cli",  # friction, figures
    "asperity.pipelines.run_cli",  # run
)


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every package's sub-commands."""
    parser = argparse.ArgumentParser(
        prog="asperity",
        description="Adhesive friction of rough elastic contacts (SI units throughout).",
    )
    parser.add_argument("--version", action="version", version=f"asperity {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMAND_MODULES:
        module = importlib.import_module(name)
        module.register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``asperity`` command; returns the process exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "func", None) is None:
        parser.print_help()
        return 2
    try:
        status = args.func(args)
    except KeyboardInterrupt:
        print("asperity: interrupted; finished stages are kept", file=sys.stderr)
        return 130
    except (ValueError, OSError) as exc:
        print(f"asperity {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return int(status or 0)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
