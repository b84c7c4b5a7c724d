"""Progress of BEM solves on a terminal: one tqdm line that counts the solves as they finish.

A long BEM stage (a 5000^2 map, a grid check, a range search) runs many solves of
:func:`bem.solve_contact`, each seconds to minutes long. Inside :func:`solve_progress` every
solve that finishes advances one bar on stderr, showing ``n/N`` (the solves done against the
solves planned so far), tqdm's estimate of the time left, the elapsed time and rate, and the
last solve's iterations, force and contact fraction. ``N`` is what the solvers announced with
:func:`expect_solves` before solving (the grid check's strides, the load chains, the
refinement levels) plus ``total`` given to the block; an adaptive solve nobody announced (a
step of the range search) raises ``N`` with ``n``, so ``n`` never exceeds ``N``. The bar
appears at the first solve, not when the block opens (a job opens one per stage), and a
``note`` given to the block is printed once on its own line above it (e.g. that the force
shown is the load scaled to the map); :attr:`SolveBar.shown` says whether it was. The bar is
removed when the block ends. :func:`progress_line` prints a line (a stage's log) on its own
line above the bar, never on the bar's. Outside the block (the default) nothing is shown: the
library prints nothing unless its caller asks. The block is bound to the running context
(:mod:`contextvars`), so concurrent callers do not share a bar; solves in worker processes are
not counted (their own stage bars count them), nor announced.
"""

from __future__ import annotations

import contextlib
import contextvars
import sys
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from asperity.bem.result import ContactResult

__all__ = ["SolveBar", "expect_solves", "progress_line", "solve_finished", "solve_progress"]

_BAR: contextvars.ContextVar = contextvars.ContextVar("asperity_bem_progress", default=None)


class SolveBar:
    """The bar of one :func:`solve_progress` block, made at its first solve (so an open block
    shows nothing until then); ``shown`` is True once it appeared (its note printed)."""

    def __init__(self, desc: str, total: int | None, note: str | None) -> None:
        self.desc, self.note = desc, note
        self.expected = int(total or 0)
        self.bar: Any = None
        self.shown = False

    def expect(self, solves: int) -> None:
        """Add ``solves`` to the solves planned (``N``)."""
        self.expected += max(0, int(solves))
        if self.bar is not None:
            self.bar.total = self.expected

    def advance(self) -> Any:
        """Count one finished solve (an unannounced one is planned as it finishes); the bar."""
        bar = self.get()
        self.expected = max(self.expected, bar.n + 1)
        bar.total = self.expected
        bar.update(1)
        return bar

    def get(self) -> Any:
        """The tqdm bar, made (and the note printed) on first use."""
        if self.bar is None:
            from tqdm import tqdm  # deferred: the library imports nothing for a bar not shown

            if self.note:
                tqdm.write(f"{self.desc}: {self.note}", file=sys.stderr)
            self.bar = tqdm(
                total=max(self.expected, 1), desc=self.desc, unit=" solves", leave=False,
                dynamic_ncols=True, file=sys.stderr, delay=1e-9,
            )  # fmt: skip
            self.shown = True
        return self.bar

    def close(self) -> None:
        """Remove the bar from the terminal (it was a progress line, not a result)."""
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def solve_progress(
    desc: str = "BEM solves",
    *,
    enabled: bool = True,
    total: int | None = None,
    note: str | None = None,
) -> Iterator[SolveBar | None]:
    """Show a tqdm bar (stderr) that counts the BEM solves finished inside the block.

    Parameters
    ----------
    desc : str
        The bar's label.
    enabled : bool
        False: no bar (e.g. stderr is not a terminal, or the user asked for quiet output).
    total : int, optional
        Solves expected besides those the solvers announce (:func:`expect_solves`).
    note : str, optional
        Printed once, on its own line, when the bar first appears (``"<desc>: <note>"``).

    Yields
    ------
    SolveBar or None
        The block's bar (None when not ``enabled``): ``.shown`` says whether it appeared.
    """
    if not enabled:
        yield None
        return
    lazy = SolveBar(desc, total, note)
    token = _BAR.set(lazy)
    try:
        yield lazy
    finally:
        _BAR.reset(token)
        lazy.close()


def expect_solves(solves: int) -> None:
    """Announce ``solves`` more :func:`bem.solve_contact` calls to the bar of the enclosing
    :func:`solve_progress` (its ``N``); nothing outside a block."""
    lazy = _BAR.get()
    if lazy is not None:
        lazy.expect(solves)


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
    """Advance the bar of the enclosing :func:`solve_progress`, if any, by one solve (an
    unannounced solve raises ``N`` with it)."""
    lazy = _BAR.get()
    if lazy is None:
        return
    bar = lazy.advance()
    bar.set_postfix_str(
        f"{result.nit} it, F = {result.normal_force:.3g} N, "
        f"A_r/A_n = {result.contact_fraction:.3g}",
        refresh=False,
    )
    bar.refresh()  # a solve takes seconds: show each one (tqdm would wait for its interval)
