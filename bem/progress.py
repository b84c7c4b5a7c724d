"""Progress of BEM solves on a terminal: one tqdm line that counts the solves as they finish.

A long BEM stage (a 5000^2 map, a grid check, a range search) runs many solves of
:func:`bem.solve_contact`, each seconds to minutes long. Inside :func:`solve_progress` every
solve that finishes advances one bar on stderr, showing the solves done (``n/N`` with tqdm's
estimate of the time left when ``total`` is known, else the count), the elapsed time and rate,
and the last solve's iterations, force and contact fraction. The bar appears at the first
solve, not when the block opens (a job opens it before its first stage), and a ``note`` given
to the block is printed once on its own line above it (e.g. that the force shown is the load
scaled to the map). :func:`progress_line` prints a line (a stage's log) on its own line above
the bar, never on the bar's. Outside the block (the default) nothing is shown: the library
prints nothing unless its caller asks. The block is bound to the running context
(:mod:`contextvars`), so concurrent callers do not share a bar; solves in worker processes are
not counted (their own stage bars count them).
"""

from __future__ import annotations

import contextlib
import contextvars
import sys
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from asperity.bem.result import ContactResult

__all__ = ["progress_line", "solve_finished", "solve_progress"]

_BAR: contextvars.ContextVar = contextvars.ContextVar("asperity_bem_progress", default=None)


class _LazyBar:
    """A tqdm bar made at the first solve (so an open block shows nothing until then)."""

    def __init__(self, desc: str, total: int | None, note: str | None) -> None:
        self.desc, self.total, self.note = desc, total, note
        self.bar = None

    def get(self):
        if self.bar is None:
            from tqdm import tqdm  # deferred: the library imports nothing for a bar not shown

            if self.note:
                tqdm.write(f"{self.desc}: {self.note}", file=sys.stderr)
            self.bar = tqdm(
                total=self.total, desc=self.desc, unit=" solves", leave=False,
                dynamic_ncols=True, file=sys.stderr,
            )  # fmt: skip
        return self.bar

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def solve_progress(
    desc: str = "BEM solves",
    *,
    enabled: bool = True,
    total: int | None = None,
    note: str | None = None,
) -> Iterator[None]:
    """Show a tqdm bar (stderr) that counts the BEM solves finished inside the block.

    Parameters
    ----------
    desc : str
        The bar's label.
    enabled : bool
        False: no bar (e.g. stderr is not a terminal, or the user asked for quiet output).
    total : int, optional
        The number of solves expected, when known: the bar then shows ``n/N`` and tqdm's
        estimate of the time left.
    note : str, optional
        Printed once, on its own line, when the bar first appears (``"<desc>: <note>"``).
    """
    if not enabled:
        yield
        return
    lazy = _LazyBar(desc, total, note)
    token = _BAR.set(lazy)
    try:
        yield
    finally:
        _BAR.reset(token)
        lazy.close()


def _to_stderr(line: str) -> None:
    print(line, file=sys.stderr)


def progress_line(line: str, write: Callable[[str], None] = _to_stderr) -> None:
    """``write(line)`` (default: print to stderr) on its own line: with the bar of an enclosing
    :func:`solve_progress` shown, the bar is cleared first and redrawn below the line."""
    lazy = _BAR.get()
    if lazy is None or lazy.bar is None:
        write(line)
        return
    from tqdm import tqdm

    with tqdm.external_write_mode(file=sys.stderr):
        write(line)


def solve_finished(result: ContactResult) -> None:
    """Advance the bar of the enclosing :func:`solve_progress`, if any, by one solve."""
    lazy = _BAR.get()
    if lazy is None:
        return
    bar = lazy.get()
    bar.set_postfix_str(
        f"{result.nit} it, F = {result.normal_force:.3g} N, "
        f"A_r/A_n = {result.contact_fraction:.3g}",
        refresh=False,
    )
    bar.update(1)
    bar.refresh()  # a solve takes seconds: show each one (tqdm would wait for its interval)
