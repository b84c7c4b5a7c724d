"""Progress of BEM solves on a terminal: one tqdm line that counts the solves as they finish.

A long BEM stage (a 5000^2 map, a grid check, a range search) runs many solves of
:func:`bem.solve_contact`, each seconds to minutes long. Inside :func:`solve_progress` every
solve that finishes advances one bar on stderr, showing the solves done (of ``total`` when
known, with tqdm's estimate of the time left), the elapsed time and rate, and the last solve's
iterations, load and contact fraction. Outside the block (the default) nothing is shown: the
library prints nothing unless its caller asks. The block is bound to the running context
(:mod:`contextvars`), so concurrent callers do not share a bar; solves in worker processes are
not counted (their own stage bars count them).
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Iterator
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from asperity.bem.result import ContactResult

__all__ = ["solve_finished", "solve_progress"]

_BAR: contextvars.ContextVar = contextvars.ContextVar("asperity_bem_progress", default=None)


@contextlib.contextmanager
def solve_progress(
    desc: str = "BEM solves", *, enabled: bool = True, total: int | None = None
) -> Iterator[None]:
    """Show a tqdm bar (stderr) that counts the BEM solves finished inside the block.

    Parameters
    ----------
    desc : str
        The bar's label.
    enabled : bool
        False: no bar (e.g. stderr is not a terminal, or the user asked for quiet output).
    total : int, optional
        The number of solves expected, when known: tqdm then estimates the time left.
    """
    if not enabled:
        yield
        return
    from tqdm import tqdm  # deferred: the library imports nothing for a bar it does not show

    bar = tqdm(total=total, desc=desc, unit="solve", leave=False, dynamic_ncols=True)
    token = _BAR.set(bar)
    try:
        yield
    finally:
        _BAR.reset(token)
        bar.close()


def solve_finished(result: ContactResult) -> None:
    """Advance the bar of the enclosing :func:`solve_progress`, if any, by one solve."""
    bar = _BAR.get()
    if bar is None:
        return
    bar.set_postfix_str(
        f"{result.nit} it, F = {result.normal_force:.3g} N, "
        f"A_r/A_n = {result.contact_fraction:.3g}",
        refresh=False,
    )
    bar.update(1)
    bar.refresh()  # a solve takes seconds: show each one (tqdm would wait for its interval)
