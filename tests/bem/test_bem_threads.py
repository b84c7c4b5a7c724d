"""Solves running at the same time in threads of one process give the serial answers.

The FFT operators own work buffers; a cache shared between threads once let two concurrent
solves overwrite each other's spectra (contact fractions of 0.0 or 0.75 instead of 0.13).
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from asperity import bem


def _rough_surface(n: int, seed: int) -> np.ndarray:
    """A smooth periodic random surface (m): filtered white noise, rms 1 um."""
    rng = np.random.default_rng(seed)
    spectrum = np.fft.rfft2(rng.standard_normal((n, n)))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.rfftfreq(n), indexing="ij"))
    spectrum *= np.where(q > 0, 1.0, 0.0) / (1.0 + (q * 32.0) ** 2)
    h = np.fft.irfft2(spectrum, s=(n, n))
    return h * (1e-6 / h.std())


# the largest load flattens this map (full contact, a BemWarning); thread safety is the subject
@pytest.mark.filterwarnings("ignore::asperity.bem.normal.validity.BemWarning")
def test_concurrent_solves_in_threads_match_serial_solves() -> None:
    h = _rough_surface(128, seed=3)
    dx = 1e-6
    loads = [1e-3, 2e-2, 5e-3, 1e-2]
    serial = [
        bem.solve_contact(
            h, dx, dx, 1000000.0, normal_force=f, options=bem.SolverOptions(tol=1e-8)
        ).contact_fraction
        for f in loads
    ]
    assert len(set(serial)) == len(loads)  # the loads really give different answers
    for _ in range(3):
        results: list[float | None] = [None] * len(loads)
        barrier = threading.Barrier(len(loads))

        def solve(i: int, barrier=barrier, results=results) -> None:
            barrier.wait()
            res = bem.solve_contact(
                h, dx, dx, 1000000.0, normal_force=loads[i], options=bem.SolverOptions(tol=1e-8)
            )
            assert res.converged
            results[i] = res.contact_fraction

        threads = [threading.Thread(target=solve, args=(i,)) for i in range(len(loads))]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert results == serial
