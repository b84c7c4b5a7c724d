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


def test_bar_waits_for_the_first_solve_and_says_its_note_once(capsys):
    heights = _wavy()
    with bem.solve_progress("BEM solves", note="F is the force on the map"):
        bem.progress.progress_line("1 read and level: 0.1 s")
        before = capsys.readouterr().err
        for p in (1e4, 2e4):
            bem.solve_contact(heights, 1e-6, 1e-6, 1e6, mean_pressure=p)
        bem.progress.progress_line("3 BEM reference: 0.2 s")
    err = capsys.readouterr().err
    assert before == "1 read and level: 0.1 s\n"  # no bar before a solve: the line is alone
    assert err.count("F is the force on the map") == 1
    # the stage line stands on a line of its own, not glued to the bar's text
    assert "\n3 BEM reference: 0.2 s\n" in err.replace("\r", "\n")
    assert "2/2" in err  # each unannounced solve is planned as it finishes: n/N, n <= N
