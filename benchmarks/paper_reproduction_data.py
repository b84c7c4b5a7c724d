"""The paper's Fig 12d and Fig 13 curves made by asperity's own statistical model: a REPRODUCTION.

These are *not* measurements. Sahli et al.'s experimental A_r(F_z) and A_r(F_x) are not
published as data, so the ``paper-two-step`` preset (``asperity run --preset paper-two-step``)
calibrates against what the paper says they are matched by: the statistical model at the
paper's effective resolution of 260 um (Fig 13 caption: R = 1.180 mm, eta = 2.25 mm^-2,
sigma_s = 0.0419 mm) with lambda = 0.03 (Section 5), the material of Figs 5 and 13
(E* = 2.133 MPa, w = 0.040 J/m^2, tau_0 = 0.13 MPa, epsilon = 0.2 nm) and A_n = 700 mm^2.
The job, given these curves as "measured" input, must then recover 260 um and lambda = 0.03:
the paper's two-step procedure (Section 5) run backwards on a known truth.

Writes two CSV files (the ``[measured]`` format of pipelines.measured; units in the headers):

* ``paper_two_step_normal_area.csv``: ``normal_load [N]``, ``real_area [mm^2]`` at the six
  loads 0.56..3.12 N (Fig 12d's test points), the model with the JKR asperity law
  (E:Fy_Greenwood, E:JKR_load) at zero tangential displacement;
* ``paper_two_step_shear_area.csv``: ``normal_load [N]``, ``tangential_force [N]``,
  ``real_area [mm^2]``, one block per load in acquisition order (growing tangential
  displacement): :func:`statmodel.shear_curve` (the PC law, E:PC_indent) on a uniform path up to
  the static peak of F_x and on until F_x has fallen by :data:`BEYOND_PEAK` of its peak (the
  start of the model's post-peak drop, where Fig 13's hooks begin; the job's
  ``fit.trim_after_first_peak`` cuts there).

Usage (seconds; no lock needed)::

    .venv/bin/python benchmarks/paper_reproduction_data.py [--out pipelines/presets]

``--summarise RESULTS.h5`` instead reads a finished ``paper-two-step`` job and writes the small
stored result the gallery page reads (``--json``, default
``pipelines/presets/paper_two_step_result.json``): the scan's statistics and misfit, the
located effective resolution and its interval with the summit statistics there, the fitted
lambda and its interval, and lambda refitted (the job's own fit,
:func:`pipelines.stages.friction.calibrate_mode_mixity`) at the summit statistics of the
interval's two ends and at the paper's own 260 um statistics (step 2 alone: must give 0.03).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from asperity import statmodel

#: The paper's roughness at its effective resolution, 260 um (Fig 13 caption), SI.
PAPER_ROUGHNESS_260UM = statmodel.Roughness(
    asperity_density=2.25e6, summit_radius=1.180e-3, summit_height_rms=0.0419e-3
)
#: The material of Figs 5 and 13 with the paper's fitted lambda (Section 5), SI.
PAPER_MATERIAL = statmodel.Material(
    e_star=2.133e6,
    work_of_adhesion=0.040,
    mode_mixity=0.03,
    shear_strength=0.13e6,
    equilibrium_distance=0.2e-9,
)
#: A_n, m^2 (35 x 20 mm^2).
NOMINAL_AREA = 700e-6
#: The six normal loads of Sahli et al., N.
NORMAL_LOADS = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)
#: Points per shear curve written up to the static peak.
POINTS_TO_PEAK = 30
#: The written curve continues past the static peak until F_x has fallen by this fraction of it.
BEYOND_PEAK = 0.05
#: Steps of the fine shear path the written points are read from.
FINE_STEPS = 2001

HEADER_NOTE = (
    "# REPRODUCTION, not an experiment: made by asperity's statistical model "
    "(benchmarks/paper_reproduction_data.py)\n"
    "# at the paper's 260 um statistics R = 1.180 mm, eta = 2.25 mm^-2, sigma_s = 0.0419 mm "
    "(Xu et al. 2022, Fig 13 caption),\n"
    "# E* = 2.133 MPa, w = 0.040 J/m^2, lambda = 0.03, tau_0 = 0.13 MPa, epsilon = 0.2 nm, "
    "A_n = 700 mm^2.\n"
)


def normal_area_curve() -> np.ndarray:
    """A_r (m^2) at :data:`NORMAL_LOADS` at rest (the model of Fig 12d at 260 um)."""
    return np.asarray(
        statmodel.real_area_at_loads(
            PAPER_MATERIAL, PAPER_ROUGHNESS_260UM, NOMINAL_AREA, np.asarray(NORMAL_LOADS)
        ),
        dtype=float,
    )


def shear_area_curve(normal_load: float) -> tuple[np.ndarray, np.ndarray]:
    """F_x (N) and A_r (m^2) of the Fig 13 curve at ``normal_load`` (N), acquisition order.

    A first curve on a generous path gives the static displacement; the written curve has
    :data:`POINTS_TO_PEAK` uniform steps of tangential displacement up to it, then the same
    step on until F_x has dropped by :data:`BEYOND_PEAK` of the peak.
    """
    guess = statmodel.shear_curve(
        PAPER_MATERIAL,
        PAPER_ROUGHNESS_260UM,
        NOMINAL_AREA,
        normal_load,
        np.linspace(0.0, 2e-3, FINE_STEPS),
    )
    d_static = float(guess.static_displacement)
    d_slide = float(guess.sliding_displacement)
    if not (math.isfinite(d_static) and d_static > 0):
        raise RuntimeError(f"no static peak at F_z = {normal_load} N: {guess.message}")
    step = d_static / POINTS_TO_PEAK
    end = max(d_slide, d_static) * 1.5
    path = np.arange(0.0, end + step, step)
    curve = statmodel.shear_curve(
        PAPER_MATERIAL, PAPER_ROUGHNESS_260UM, NOMINAL_AREA, normal_load, path
    )
    fx, ar = np.asarray(curve.tangential_force), np.asarray(curve.real_area)
    peak = int(np.argmax(fx))
    after = np.nonzero(fx[peak:] < (1 - BEYOND_PEAK) * fx[peak])[0]
    stop = peak + (int(after[0]) if after.size else fx.size - 1 - peak)
    return fx[: stop + 1], ar[: stop + 1]


def write(out: Path) -> tuple[Path, Path]:
    """Write both CSV files into ``out``; return their paths."""
    out.mkdir(parents=True, exist_ok=True)
    normal = out / "paper_two_step_normal_area.csv"
    shear = out / "paper_two_step_shear_area.csv"
    areas = normal_area_curve()
    lines = [HEADER_NOTE, "# Fig 12d's six loads, zero tangential displacement\n"]
    lines.append("normal_load [N],real_area [mm^2]\n")
    lines += [f"{f:.2f},{a * 1e6:.8g}\n" for f, a in zip(NORMAL_LOADS, areas, strict=True)]
    normal.write_text("".join(lines), encoding="utf-8")
    lines = [HEADER_NOTE, "# Fig 13: A_r(F_x) per load, to the static peak and a little beyond\n"]
    lines.append("normal_load [N],tangential_force [N],real_area [mm^2]\n")
    for load in NORMAL_LOADS:
        fx, ar = shear_area_curve(load)
        lines += [f"{load:.2f},{x:.8g},{a * 1e6:.8g}\n" for x, a in zip(fx, ar, strict=True)]
    shear.write_text("".join(lines), encoding="utf-8")
    return normal, shear


def _lambda_at(roughness: statmodel.Roughness, shear_csv: Path) -> dict[str, float]:
    """Lambda and its one-sigma interval fitted to the shear CSV at ``roughness`` (SI)."""
    from asperity.pipelines.measured import read_shear_area
    from asperity.pipelines.stages.friction import calibrate_mode_mixity

    curves = read_shear_area(shear_csv, nominal_area=NOMINAL_AREA)
    choice = calibrate_mode_mixity(
        PAPER_MATERIAL, roughness, NOMINAL_AREA, curves, knobs={"nodes": 8, "panels": 4}
    )
    return {
        "mode_mixity": float(choice.mode_mixity),
        "interval_low": float(choice.interval_low),
        "interval_high": float(choice.interval_high),
    }


def summarise(results: Path, shear_csv: Path) -> dict:
    """The stored result of a finished ``paper-two-step`` job (SI units, plain lists)."""
    import h5py

    with h5py.File(results, "r") as f:
        scan, sm, mm = f["resolution_scan"], f["statistical_model"], f["mode_mixity"]
        ends = [
            statmodel.Roughness(
                float(sm["interval_asperity_density"][i]),
                float(sm["interval_summit_radius"][i]),
                float(sm["interval_summit_height_rms"][i]),
            )
            for i in range(2)
        ]
        surface = f["surface"]
        provenance = json.loads(surface.attrs["provenance"])
        out = {
            "map": {
                "shape": list(surface["heights"].shape),
                "pixel_size": float(surface.attrs["dx"]),
                "seed": provenance.get("seed"),
                "generator": provenance.get("generator"),
            },
            "note": HEADER_NOTE.replace("# ", "").replace("\n", " ").strip(),
            "scan": {
                "resolution": scan["resolution"][:].tolist(),
                "asperity_density": scan["asperity_density"][:].tolist(),
                "summit_radius": scan["summit_radius"][:].tolist(),
                "summit_height_rms": scan["summit_height_rms"][:].tolist(),
                "misfit": sm["misfit_measured"][:].tolist(),
            },
            "sampled_resolution": sm["sampled_resolution"][:].tolist(),
            "sampled_misfit": sm["sampled_misfit"][:].tolist(),
            "effective_resolution": float(sm.attrs["optimum_resolution"]),
            "interval": [float(v) for v in sm["optimum_interval"][:]],
            "interval_open": bool(
                sm.attrs["optimum_open_finer"] or sm.attrs["optimum_open_coarser"]
            ),
            "misfit": float(sm.attrs["optimum_misfit"]),
            "roughness": [
                float(sm.attrs["optimum_asperity_density"]),
                float(sm.attrs["optimum_summit_radius"]),
                float(sm.attrs["optimum_summit_height_rms"]),
            ],
            "interval_roughness": [
                [r.asperity_density, r.summit_radius, r.summit_height_rms] for r in ends
            ],
            "mode_mixity": float(mm.attrs["mode_mixity"]),
            "mode_mixity_interval": [
                float(mm.attrs["interval_low"]),
                float(mm.attrs["interval_high"]),
            ],
        }
    out["mode_mixity_at_interval_ends"] = [_lambda_at(r, shear_csv) for r in ends]
    at = int(np.argmin(np.abs(np.asarray(out["scan"]["resolution"]) - 260e-6)))
    surface_260 = statmodel.Roughness(
        *(out["scan"][k][at] for k in ("asperity_density", "summit_radius", "summit_height_rms"))
    )
    out["surface_at_260um"] = {
        "resolution": out["scan"]["resolution"][at],
        "roughness": [
            surface_260.asperity_density,
            surface_260.summit_radius,
            surface_260.summit_height_rms,
        ],
        "misfit": out["scan"]["misfit"][at],
        **_lambda_at(surface_260, shear_csv),
    }
    out["mode_mixity_at_paper_statistics"] = _lambda_at(PAPER_ROUGHNESS_260UM, shear_csv)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("pipelines/presets"))
    parser.add_argument("--summarise", type=Path, default=None, metavar="RESULTS.h5")
    parser.add_argument(
        "--json", type=Path, default=Path("pipelines/presets/paper_two_step_result.json")
    )
    args = parser.parse_args()
    if args.summarise is not None:
        summary = summarise(args.summarise, args.out / "paper_two_step_shear_area.csv")
        args.json.write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
        print(json.dumps({k: v for k, v in summary.items() if k not in ("scan",)}, indent=1))
        return
    normal, shear = write(args.out)
    areas = normal_area_curve()
    for load, area in zip(NORMAL_LOADS, areas, strict=True):
        fraction = area / NOMINAL_AREA
        print(f"F_z = {load:.2f} N: A_r = {area * 1e6:.4f} mm^2, A_r/A_n = {fraction:.5f}")
    print(f"wrote {normal} and {shear}")


if __name__ == "__main__":
    main()
