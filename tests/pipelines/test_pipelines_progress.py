"""A job's progress on a terminal (issue 39): the BEM solves bar counts n/N with the time
left, each stage line stands on a line of its own (never glued to a bar's text), and the
word that the force shown is scaled to the map is said once."""

from __future__ import annotations

import re
import sys

from asperity.pipelines.job import SOLVES_NOTE, run_job

#: A tqdm bar's count and its time left: "7/9 [00:01<00:00".
_COUNT = re.compile(r"\| *(\d+)/(\d+) \[\d\d:\d\d<[\d:?]+")
#: A stage's line as the job logs it: "3 BEM reference: 1.80 s", "8 ...: disabled".
_STAGE = re.compile(r"\d+ [A-Za-z][^:]*: (\d+\.\d\d s|disabled|stored, skipped)")


def _tiny(small, base_dir):
    data = small.data()
    data["surface"]["synthetic"].update(n=32, pixel_size=80e-6)
    data["surface"]["max_stride"] = 2
    data["bem"]["max_stride"] = 1
    data["loading"]["normal_loads"] = [1.0, 3.0]
    return small(base_dir, data=data)


def test_solves_bar_counts_n_of_n_on_its_own_line(small, tmp_path, capsys):
    """A small job run with progress shown: its stderr (bars and stage lines together, as on a
    terminal) holds "BEM solves" frames with n/N, n never above N, the last frame n = N; every
    stage line is a piece of its own between carriage returns and newlines."""
    config = _tiny(small, tmp_path)
    run_job(config, tmp_path / "out", progress=True, log=lambda line: print(line, file=sys.stderr))
    err = capsys.readouterr().err
    pieces = [p.strip() for p in re.split(r"[\r\n]+", err) if p.strip()]
    frames = [p for p in pieces if p.startswith("BEM solves:") and _COUNT.search(p)]
    assert frames, err[:2000]
    counts = [tuple(map(int, _COUNT.search(f).groups())) for f in frames]
    assert all(0 <= n <= total for n, total in counts)
    assert counts[-1][0] == counts[-1][1] > 1
    stage_lines = [p for p in pieces if _STAGE.search(p)]
    assert any(p.startswith("3 BEM reference:") for p in stage_lines), pieces
    for line in stage_lines:  # alone: no bar text before or after it on its line
        assert _STAGE.fullmatch(line.replace("\x1b[A", "")), line
    assert err.count(SOLVES_NOTE) == 1
    assert "scaled by A_map / A_n" in SOLVES_NOTE
