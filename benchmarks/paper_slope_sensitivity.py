"""The paper case's verdict against the surface's rms slope: BEM / model at 2 um over h'.

The paper preset's verdict compares the BEM's real area on the 2 um map with the statistical
model at 2 um (Fig 12d). Under a small load the BEM's area follows the map's rms slope
(Persson: ``A_r/A_n = kappa p / (E* h'_rms)``, kappa = sqrt(8/pi)), while the model at 2 um
follows the 2 um summit statistics. This script measures the ratio on Gaussian surfaces with
the paper's rms (51 um) and roll-off (600 um) whose slope is set by where the power law
(H = 0.8) is cut: from 600 um (a plateau alone, h' = q_r h_rms / sqrt(2) = 0.378, the least any
surface with that rms and roll-off has) to 20 um (the presets' stand-in,
``topo.synthetic.paper_spectrum``); and on two plateaus rolled off at longer wavelengths (lower
slopes than the paper's spectrum allows), for the paper's table read as a Gaussian surface
(h' 0.25-0.33).

Per surface, one non-adhesive BEM solve at F_z = 2.08 N scaled to the map (the nominal pressure
of the paper's 2.08 N on 700 mm^2: 2971 Pa), E* = 2.133 MPa, on an N x N map of 2 um pixels
(default 1500: a 3 mm square; roll-off 600 um is 5 wavelengths of it), beside the JKR model
(w = 0.040 J/m^2, epsilon = 0.2 nm) at the map's own 2 um summit statistics and at the paper's
(eta 652.1 mm^-2, R 0.041 mm, sigma_s 0.032 mm), and Persson's small-load estimate. SI units.

Run: ``python benchmarks/paper_slope_sensitivity.py [--n 1500] [--seed 1]`` (about a minute
on two cores at n = 1500).
"""

from __future__ import annotations

import argparse
import math
import time

from asperity import statmodel, topo
from asperity.bem import load_sweep
from asperity.topo.synthetic import self_affine

E_STAR, WORK, EPSILON = 2.133e6, 0.040, 0.2e-9  # Pa, J/m^2, m (the paper's Figs 5 and 13)
PRESSURE = 2.08 / 700e-6  # Pa: the paper's 2.08 N on its 700 mm^2 nominal area
PIXEL = 2e-6  # m (the default; --pixel)
RMS = 51e-6  # m
PAPER_2UM = statmodel.Roughness(652.1e6, 0.041e-3, 0.032e-3)
#: (label, roll-off wavelength m, short cut-off m): H = 0.8 between them.
CASES = (
    ("roll-off 1.2 mm, plateau only", 1.2e-3, 1.2e-3),
    ("roll-off 900 um, plateau only", 900e-6, 900e-6),
    ("roll-off 600 um, plateau only (the bound)", 600e-6, 600e-6),
    ("roll-off 600 um, cut 200 um", 600e-6, 200e-6),
    ("roll-off 600 um, cut 100 um", 600e-6, 100e-6),
    ("roll-off 600 um, cut 50 um", 600e-6, 50e-6),
    ("roll-off 600 um, cut 20 um (the stand-in)", 600e-6, 20e-6),
)


def _jkr_fraction(roughness: statmodel.Roughness, area: float) -> float:
    material = statmodel.Material(E_STAR, WORK, 0.03, 0.13e6, EPSILON)
    (area_at_load,) = statmodel.real_area_at_loads(material, roughness, area, [PRESSURE * area])
    return float(area_at_load) / area


def row(label: str, rolloff: float, cutoff: float, n: int, seed: int, pixel: float) -> dict:
    """One surface: its slope and summit statistics, the BEM, the models (fractions)."""
    surface = self_affine(
        n,
        pixel,
        rms_height=RMS,
        rolloff_wavelength=rolloff,
        hurst=0.8,
        short_cutoff=cutoff,
        seed=seed,
    )
    area = surface.nominal_area
    slope = topo.rms_slope(surface)
    stats = topo.summit_statistics(surface)
    own = statmodel.Roughness(stats.asperity_density, stats.summit_radius, stats.summit_height_rms)
    start = time.perf_counter()
    (bem,) = load_sweep(surface.heights, pixel, pixel, E_STAR, [PRESSURE * area])
    seconds = time.perf_counter() - start
    if not bem.converged:
        raise RuntimeError(f"{label}: the BEM did not converge: {bem.message}")
    return {
        "label": label,
        "slope": slope,
        "eta": stats.asperity_density,
        "R": stats.summit_radius,
        "sigma_s": stats.summit_height_rms,
        "bem": bem.contact_fraction,
        "persson": statmodel.KAPPA_PERSSON * PRESSURE / (E_STAR * slope),
        "jkr_own": _jkr_fraction(own, area),
        "jkr_paper": _jkr_fraction(PAPER_2UM, area),
        "seconds": seconds,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1500, help="pixels per side (2 um pixels)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--pixel", type=float, default=PIXEL, help="pixel size, m (2e-6)")
    parser.add_argument(
        "--plateaus", action="store_true", help="only the plateau-only surfaces (smooth)"
    )
    args = parser.parse_args()
    cases = [c for c in CASES if c[1] == c[2]] if args.plateaus else CASES
    print(
        f"{args.n} x {args.n} at {args.pixel * 1e6:g} um ({args.n * args.pixel * 1e3:.1f} mm), "
        f"seed {args.seed}, "
        f"F_z 2.08 N on 700 mm^2 ({PRESSURE:.0f} Pa); A_r/A_n in %; bound "
        f"{2 * math.pi / 600e-6 * RMS / math.sqrt(2):.3f}"
    )
    print(
        "| surface (H = 0.8, rms 51 um) | h'_rms "
        "| eta (mm^-2), R (mm), sigma_s (mm) at the pixel | BEM | Persson "
        "| JKR model, own statistics | JKR model, paper's 2 um | BEM / own model "
        "| BEM / paper's model | BEM s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, rolloff, cutoff in cases:
        r = row(label, rolloff, cutoff, args.n, args.seed, args.pixel)
        print(
            f"| {r['label']} | {r['slope']:.3f} | {r['eta'] * 1e-6:.0f}, {r['R'] * 1e3:.4f}, "
            f"{r['sigma_s'] * 1e3:.4f} | {100 * r['bem']:.3f} | {100 * r['persson']:.3f} | "
            f"{100 * r['jkr_own']:.3f} | {100 * r['jkr_paper']:.3f} | "
            f"{r['bem'] / r['jkr_own']:.2f} | {r['bem'] / r['jkr_paper']:.2f} | "
            f"{r['seconds']:.0f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
