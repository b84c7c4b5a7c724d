"""Sub-commands of the topo package (being written)."""

import argparse


def register(subparsers: "argparse._SubParsersAction") -> None:
    """Add this package's sub-commands to the asperity parser."""
