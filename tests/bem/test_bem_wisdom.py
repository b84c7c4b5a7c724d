"""FFTW wisdom is cached on disk as raw bytes (an .npz read with allow_pickle=False) and reused."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyfftw")

PLAN = (
    "import numpy as np; from asperity.bem.elastic.fft_backend import Convolution; "
    "c = Convolution(np.ones((96, 49)), (96, 96), backend='pyfftw', threads=1); "
    "import pyfftw; print(sum(len(w) for w in pyfftw.export_wisdom()))"
)


def _run(cache: Path, code: str) -> str:
    env = dict(os.environ, ASPERITY_CACHE_DIR=str(cache))
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True
    )
    return done.stdout.strip()


@pytest.mark.slow  # two fresh interpreters (numba and pyFFTW imports): 4-10 s
def test_wisdom_is_stored_without_pickle_and_loaded_by_a_second_process(tmp_path: Path) -> None:
    _run(tmp_path, PLAN)
    files = list(tmp_path.glob("fftw_wisdom_*.npz"))
    assert len(files) == 1
    with np.load(files[0], allow_pickle=False) as stored:  # raw bytes, no objects
        assert all(stored[name].dtype == np.uint8 for name in stored.files)
        stored_bytes = sum(stored[name].size for name in stored.files)
    assert stored_bytes > 0
    # a second process imports the wisdom before planning: it knows at least what was stored
    loaded = _run(
        tmp_path,
        "import pyfftw; from asperity.bem.elastic import fft_backend; fft_backend._load_wisdom(); "
        "print(sum(len(w) for w in pyfftw.export_wisdom()))",
    )
    assert int(loaded) >= stored_bytes - 3  # export appends a terminator per precision


def test_a_corrupt_wisdom_file_is_ignored(tmp_path: Path, monkeypatch) -> None:
    """In this process: loading a corrupt cache file neither raises nor imports anything, and a
    plan made afterwards still works (and saves wisdom that can be read back)."""
    import pyfftw

    from asperity.bem.elastic import fft_backend
    from asperity.bem.elastic.fft_backend import Convolution

    monkeypatch.setenv("ASPERITY_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(fft_backend, "_WISDOM_LOADED", False)
    corrupt = tmp_path / f"fftw_wisdom_{pyfftw.__version__}.npz"
    corrupt.write_bytes(b"not an npz file")
    fft_backend._load_wisdom()  # ignored, no exception
    conv = Convolution(np.ones((40, 21)), (40, 40), backend="pyfftw", threads=1)
    x = np.zeros((40, 40))
    x[3, 4] = 1.0
    y = conv.empty()
    conv(x, y)
    np.testing.assert_allclose(y, x, atol=1e-12)  # multiplier 1 everywhere: the identity
