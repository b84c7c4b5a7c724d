"""Persson's theory against our boundary-element method on periodic self-affine surfaces.

Non-adhesive contact, E* = 1 MPa, H = 0.8, rms height 1 um, pixel 1 um on the finest grid.
Loads are chosen so that the BEM contact fraction is about 1, 2, 5, 10 and 20 %
(``p = f E* h'_rms / 2``, i.e. the BEM's kappa ~ 2); at each, the table gives the BEM
fraction, Persson's ``erf`` fraction (:func:`asperity.statmodel.persson_real_area`, the map's
own PSD up to its Nyquist wavenumber), their ratio and the BEM's
``kappa = (A_r/A_n) E* h'_rms / p`` (Persson: sqrt(8/pi) = 1.60 at small load).

* refinement: one physical surface (1024 um square, roll-off 256 um, cut-off 32 um) on
  256^2, 512^2 and 1024^2 grids (cut-off over 8, 16, 32 pixels; the coarser grids are
  Fourier-truncated copies of the finest, so the surface is the same);
* broad band: 1024^2 grid, roll-off 256 um, cut-off 8 um (8 pixels): 32x between roll-off
  and cut-off.

Run: ``flock /tmp/asperity-bench.lock python benchmarks/statmodel_persson_vs_bem.py [SEED ...]``
(default seeds 1 2 3; a few minutes on two cores).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from asperity.bem import load_sweep
from asperity.statmodel import KAPPA_PERSSON, persson_real_area
from asperity.topo import fourier_resample
from asperity.topo.synthetic import self_affine

E_STAR = 1e6  # Pa
PIXEL = 1e-6  # m, finest grid
N_FINE = 1024
TARGETS = np.array([0.01, 0.02, 0.05, 0.1, 0.2])


def _compare(surface):
    """BEM fractions, Persson fractions, BEM kappa and the seconds of the BEM sweep."""
    area = surface.nominal_area
    slope = persson_real_area(surface, E_STAR, [1.0], area).rms_slope
    pressure = TARGETS * E_STAR * slope / 2
    start = time.perf_counter()
    bem = load_sweep(surface.heights, surface.dx, surface.dy, E_STAR, list(pressure * area))
    seconds = time.perf_counter() - start
    if not all(r.converged for r in bem):
        raise RuntimeError("a BEM solve did not converge: " + bem[-1].message)
    bem_fraction = np.array([r.contact_fraction for r in bem])
    persson = persson_real_area(surface, E_STAR, pressure * area, area).contact_fraction
    return bem_fraction, persson, bem_fraction * E_STAR * slope / pressure, seconds


def _cases(seed: int):
    """(label, surface) pairs of the refinement series and the broad-band surface."""
    fine = self_affine(
        N_FINE,
        PIXEL,
        rms_height=1e-6,
        rolloff_wavelength=256e-6,
        hurst=0.8,
        short_cutoff=32e-6,
        seed=seed,
    )
    for factor in (4, 2, 1):
        surface = fourier_resample(fine, factor) if factor > 1 else fine
        yield f"{surface.nx}^2 cut-off {32 // factor} px", surface
    broad = self_affine(
        N_FINE,
        PIXEL,
        rms_height=1e-6,
        rolloff_wavelength=256e-6,
        hurst=0.8,
        short_cutoff=8e-6,
        seed=seed,
    )
    yield f"{N_FINE}^2 broad, cut-off 8 px", broad


def main(seeds: list[int]) -> None:
    print(f"Persson's kappa = sqrt(8/pi) = {KAPPA_PERSSON:.3f}; E* = {E_STAR:.0e} Pa, H = 0.8\n")
    print("| surface | seed | BEM A_r/A_n | Persson A_r/A_n | Persson/BEM | BEM kappa | BEM s |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    summary: dict[str, list[np.ndarray]] = {}
    for seed in seeds:
        for label, surface in _cases(seed):
            bem, persson, kappa, seconds = _compare(surface)
            summary.setdefault(label, []).append(persson / bem)
            for k in range(TARGETS.size):
                print(
                    f"| {label} | {seed} | {bem[k]:.4f} | {persson[k]:.4f} | "
                    f"{persson[k] / bem[k]:.3f} | {kappa[k]:.2f} | {seconds:.1f} |"
                )
    print("\nPersson/BEM per target BEM contact fraction: mean over the seeds (min-max):\n")
    print("| surface | " + " | ".join(f"{100 * t:g} %" for t in TARGETS) + " |")
    print("|---|" + "---:|" * TARGETS.size)
    for label, ratios in summary.items():
        stack = np.array(ratios)
        cells = " | ".join(
            f"{m:.3f} ({lo:.2f}-{hi:.2f})"
            for m, lo, hi in zip(stack.mean(0), stack.min(0), stack.max(0), strict=True)
        )
        print(f"| {label} | {cells} |")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [1, 2, 3])
