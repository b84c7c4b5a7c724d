"""asperity.plotting and the no-forced-backend rule for every figure of the library."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from asperity.plotting import display_unit, layout_problems, new_figure, save_figure

# ----------------------------------------------------------------------------- SI prefixes


@pytest.mark.parametrize(
    "value, base, power, symbol, shown",
    [
        (12e-6, "m", 1, "\u00b5m", 12.0),  # a 12 um resolution, not 0.012 mm
        (1e-3, "m", 1, "mm", 1.0),  # the decade boundary goes up
        (999e-6, "m", 1, "\u00b5m", 999.0),
        (0.25e-9, "m", 1, "pm", 250.0),
        (3.1, "N", 1, "N", 3.1),
        (0.824, "N", 1, "mN", 824.0),
        (6.0e-6, "m", 2, "mm$^{2}$", 6.0),  # Fig. 4's real contact area
        (0.3e-6, "m", 2, "mm$^{2}$", 0.3),  # areas: one prefix spans six decades
        (652.1e6, "m", -2, "mm$^{-2}$", 652.1),  # the paper's eta = 652.1 mm^-2
        (0.13e6, "Pa", 1, "kPa", 130.0),
    ],
)
def test_display_unit_reads_like_the_paper(value, base, power, symbol, shown):
    unit = display_unit([0.0, -value / 2, value, np.nan], base, power)
    assert unit.symbol == symbol
    assert unit(value) == pytest.approx(shown, rel=1e-12)
    assert unit.label("length") == f"length ({symbol})"


def test_display_unit_without_data_is_the_si_unit():
    for values in ([], [0.0, 0.0], [np.nan, np.inf]):
        unit = display_unit(values, "m", 2)
        assert (unit.factor, unit.symbol) == (1.0, "m$^{2}$")
    with pytest.raises(ValueError, match="power"):
        display_unit([1.0], "m", 0)


@given(st.floats(min_value=1e-14, max_value=9.9e8), st.sampled_from([-2, -1, 1, 2, 3]))
def test_display_unit_brings_the_largest_value_near_32(value, power):
    """Within the prefixes' range the largest value is drawn in [1, 1000) (first powers), or
    in the six (nine) decades around 10**1.5 of a squared (cubed) unit."""
    si = value**power
    unit = display_unit([si, si / 7.0], "m", power)
    shown = math.log10(unit(si))
    half_width = 1.5 * abs(power)
    assert 1.5 - half_width - 1e-9 <= shown < 1.5 + half_width + 1e-9
    assert unit.factor == pytest.approx(10.0 ** round(math.log10(unit.factor)), rel=1e-12)


# ------------------------------------------------------------------ layout and file output


def test_layout_problems_finds_overlapping_and_clipped_text():
    fig = new_figure(4.0, 3.0)
    ax = fig.subplots()
    ax.set_xlabel("clean label (\u00b5m)")
    assert layout_problems(fig) == []
    ax.text(0.5, 0.5, "first", transform=ax.transAxes)
    ax.text(0.5, 0.5, "second", transform=ax.transAxes)
    fig.text(0.98, 0.5, "sticks out of the figure")
    problems = layout_problems(fig)
    assert "overlap: 'first' and 'second'" in problems
    assert "clipped: 'sticks out of the figure'" in problems
    assert len(problems) == 2


def test_save_figure_picks_the_format_from_the_suffix(tmp_path):
    fig = new_figure(3.0, 2.0)
    fig.subplots().plot([0, 1], [1, 0])
    magic = {".png": b"\x89PNG", ".svg": b"<?xml", ".pdf": b"%PDF"}
    for suffix, start in magic.items():
        path = save_figure(fig, tmp_path / f"f{suffix}", dpi=40)
        assert path.read_bytes().startswith(start)
    small = save_figure(fig, tmp_path / "low.png", dpi=40).stat().st_size
    assert save_figure(fig, tmp_path / "high.png", dpi=200).stat().st_size > small


# ----------------------------------------------------------------- no backend is forced

#: Modules the backend probe skips (none: every library module must leave the backend alone).
NOT_YET_CONVERTED: tuple[str, ...] = ()

_BACKEND_PROBE = """
import importlib, json, pkgutil, sys
import matplotlib
matplotlib.use("svg")  # the user's choice: a sentinel the library must not change
out, skip, mode = sys.argv[1], set(filter(None, sys.argv[2].split(","))), sys.argv[3]
imported = []
for name in ("asperity.topo", "asperity.bem", "asperity.statmodel", "asperity.pipelines"):
    package = importlib.import_module(name)
    for info in pkgutil.walk_packages(package.__path__, name + "."):
        if info.name not in skip and not info.name.rsplit(".", 1)[-1].startswith("__"):
            importlib.import_module(info.name)
            imported.append(info.name)
import h5py
from asperity import topo
from asperity.plotting import save_figure
from asperity.pipelines.cli import main
from asperity.statmodel.figures import FIGURES
status = None
if mode == "cli":
    status = main(["figures", "--out", out])
else:  # draw every paper figure, save one of them in two formats
    with h5py.File(out + "/data.h5", "w") as h5:
        figures = {name: draw(h5) for name, draw in FIGURES.items()}
    save_figure(figures["fig4_shear_curve"], out + "/fig4.png", dpi=30)
    save_figure(figures["fig4_shear_curve"], out + "/fig4.pdf")
scan = topo.resolution_scan(topo.synthetic.paper_like(n=96, pixel_size=10e-6, seed=1), 6)
topo.plot_resolution_scan(scan, out + "/scan.svg", title="probe")
print(json.dumps({
    "status": status,
    "backend": matplotlib.get_backend(),
    "rc_backend": matplotlib.rcParams["backend"],
    "pyplot": "matplotlib.pyplot" in sys.modules,
    "imported": imported,
}))
"""


def _probe(out: Path, mode: str) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", _BACKEND_PROBE, str(out), ",".join(NOT_YET_CONVERTED), mode],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.splitlines()[-1])
    assert report["backend"] == report["rc_backend"] == "svg"
    assert report["pyplot"] is False
    assert {"asperity.statmodel.figures", "asperity.topo.scan", "asperity.bem.cli"} <= set(
        report["imported"]
    )
    assert (out / "scan.svg").read_bytes().startswith(b"<?xml")
    return report


@pytest.mark.slow
def test_library_never_forces_a_backend_nor_imports_pyplot(tmp_path):
    """Importing every module and drawing every figure leaves a notebook's backend alone.

    A fresh interpreter chooses the "svg" backend first, imports every module of the four
    packages, draws Figs. 1, 2, 4, 5 and a resolution scan and saves some as PNG, PDF and SVG;
    the backend must still be "svg" and ``matplotlib.pyplot`` never imported.
    """
    _probe(tmp_path, "draw")
    assert (tmp_path / "fig4.png").read_bytes().startswith(b"\x89PNG")
    assert (tmp_path / "fig4.pdf").read_bytes().startswith(b"%PDF")


@pytest.mark.slow
def test_figures_command_writes_pngs_and_data_and_keeps_the_backend(tmp_path):
    """``asperity figures`` in a fresh interpreter (backend "svg"): four PNGs and the HDF5
    data with units on every dataset; the backend is untouched."""
    assert _probe(tmp_path, "cli")["status"] == 0
    assert sorted(p.name for p in tmp_path.glob("*.png")) == [
        "fig1_pc_single_asperity.png",
        "fig2_status_map.png",
        "fig4_shear_curve.png",
        "fig5_parameter_study.png",
    ]
    with h5py.File(tmp_path / "statmodel_figures.h5") as fh:
        assert {"fig1", "fig2", "fig4", "fig5"} <= set(fh)
        names = []
        fh.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        assert all("units" in fh[n].attrs for n in names)
        np.testing.assert_allclose(fh["fig4/normal_force"][()], 3.1, rtol=1e-9)
