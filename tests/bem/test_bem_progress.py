"""A long BEM stage shows its solves as they finish, only when asked (a terminal)."""

from __future__ import annotations

import math

import numpy as np

from asperity import bem


def _wavy(n: int = 16) -> np.ndarray:
    x = np.arange(n) / n
    return np.repeat((1e-6 * np.cos(2 * math.pi * x))[:, None], n, axis=1)


def test_solves_are_counted_inside_the_block_and_nothing_outside(capsys):
    heights = _wavy()
    bem.solve_contact(heights, 1e-6, 1e-6, 1e6, mean_pressure=1e4)
    assert capsys.readouterr().err == ""  # the library prints nothing by itself
    with bem.solve_progress("BEM solves", total=2):
        for p in (1e4, 2e4):
            bem.solve_contact(heights, 1e-6, 1e-6, 1e6, mean_pressure=p)
    err = capsys.readouterr().err
    assert "BEM solves" in err and "2/2" in err and "A_r/A_n" in err
    with bem.solve_progress(enabled=False):
        bem.solve_contact(heights, 1e-6, 1e-6, 1e6, mean_pressure=1e4)
    assert capsys.readouterr().err == ""
