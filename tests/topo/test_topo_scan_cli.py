"""Resolution scan (Fig 12a-c), the HeightMap contract and the command-line contract."""

from __future__ import annotations

import json
import math

import h5py
import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.cli import main
from asperity.topo.cli import STATS_KEYS

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data"


@pytest.fixture(scope="module")
def surface():
    return topo.synthetic.paper_like(n=400, pixel_size=10e-6, seed=5)


def test_scan_rows_are_summit_statistics_and_fits_follow_the_paper(surface):
    scan = topo.resolution_scan(surface, 20)
    np.testing.assert_array_equal(scan.stride, np.arange(1, 21))
    np.testing.assert_allclose(scan.resolution, scan.stride * 10e-6)
    for k in (1, 7, 20):
        row = topo.summit_statistics(surface, stride=k)
        assert scan.n_summits[k - 1] == row.n_summits
        assert scan.summit_radius[k - 1] == row.summit_radius
    # the paper's trends: R grows with resolution, eta falls as a power law, sigma_s ~ const
    assert scan.radius_slope > 0
    assert -2.5 < scan.density_exponent < -0.5
    assert scan.height_rms_relative_spread < 0.3
    fitted = scan.density_prefactor * scan.resolution**scan.density_exponent
    assert np.median(np.abs(np.log(fitted / scan.asperity_density))) < 0.3
    with pytest.raises(ValueError, match="max_stride"):
        topo.resolution_scan(surface, 500)


def test_scan_fits_recover_exact_trends():
    # spikes on a lattice: decimation by k keeps the spikes whose indices divide by k
    from asperity.topo.scan import resolution_scan

    heights = np.zeros((240, 240))
    spikes = np.random.default_rng(0).uniform(1e-6, 2e-6, size=(20, 20))
    heights[::12, ::12] = spikes
    scan = resolution_scan(topo.HeightMap(heights, 1e-6, 1e-6, periodic=True), 4)
    # strides 1, 2, 3, 4 all keep every spike (12 is divisible by all): N and sigma_s constant
    assert list(scan.n_summits) == [400] * 4
    assert scan.density_exponent == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(scan.summit_height_rms, np.std(spikes), rtol=1e-12)
    assert scan.height_rms_relative_spread == pytest.approx(0.0, abs=1e-12)
    # R of a spike is (k dx)^2 / (2 z): R(k) = k^2 R(1), and the linear fit rises
    np.testing.assert_allclose(
        scan.summit_radius, np.arange(1, 5) ** 2 * np.mean(1e-12 / (2 * spikes))
    )
    assert scan.radius_slope > 0


def test_heightmap_contract():
    h = np.zeros((4, 3), dtype=np.float32)
    h[1, 1] = np.nan
    m = topo.HeightMap(h, 1e-6, 2e-6)
    assert m.heights.dtype == np.float64 and not m.heights.flags.writeable
    assert (m.nx, m.ny, m.lx, m.ly) == (4, 3, 4e-6, 6e-6)
    assert m.nominal_area == pytest.approx(24e-12) and m.n_missing == 1
    for bad in ({"dx": 0.0}, {"dx": float("nan")}, {"dy": -1.0}):
        with pytest.raises(ValueError, match="pixel size"):
            topo.HeightMap(h, **{"dx": 1e-6, "dy": 1e-6, **bad})
    with pytest.raises(ValueError, match="2D"):
        topo.HeightMap(np.zeros(5), 1e-6, 1e-6)
    with pytest.raises(TypeError, match="float64"):
        topo.HeightMap(np.zeros((2, 2), dtype=complex), 1e-6, 1e-6)
    with pytest.raises(AttributeError):
        m.dx = 3.0


def run_cli(capsys, *args):
    status = main([str(a) for a in args])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_stats_json_contract(capsys, tmp_path, surface):
    path = topo.write_hdf5(surface, tmp_path / "s.h5")
    status, out, _ = run_cli(capsys, "stats", path, "--json", "--stride", "3", "--detrend", "mean")
    assert status == 0
    record = json.loads(out)
    assert tuple(record)[: len(STATS_KEYS)] == STATS_KEYS  # documented keys first, in order
    assert {"nominal_area", "grid_area", "preparation"} <= set(record)
    stats = topo.summit_statistics(topo.level(surface, "mean"), stride=3)
    assert record["nx"] == 134 and record["dx"] == pytest.approx(30e-6)
    assert record["n_summits"] == stats.n_summits
    assert record["asperity_density"] == pytest.approx(stats.asperity_density)
    assert record["summit_radius"] == pytest.approx(stats.summit_radius)
    assert record["summit_height_rms"] == pytest.approx(stats.summit_height_rms)
    assert record["rms_height"] == pytest.approx(50e-6, rel=0.05)


def test_stats_on_real_file_and_first_axis_convention(capsys):
    status, out, _ = run_cli(capsys, "stats", DATA / "metropro-1.dat", "--json")
    record = json.loads(out)
    assert status == 0 and (record["nx"], record["ny"]) == (640, 480)
    assert record["dx"] == pytest.approx(0.0007028812979115173 / 640)


def test_cli_refusals(capsys, tmp_path):
    status, _, err = run_cli(capsys, "stats", DATA / "dektak-1.csv", "--neighbours", "8")
    assert status == 0  # a profile: Nayak's theory (tests/topo/test_topo_profile_*.py)
    np.save(tmp_path / "m.npy", np.zeros((8, 8)))
    status, _, err = run_cli(capsys, "stats", tmp_path / "m.npy")
    assert status == 2 and "--pixel-size" in err
    status, out, _ = run_cli(capsys, "stats", tmp_path / "m.npy", "--pixel-size", "1e-6", "--json")
    assert status == 0 and json.loads(out)["n_summits"] == 0
    assert json.loads(out)["summit_radius"] is None  # NaN is written as null
    cut = tmp_path / "cut.sur"
    cut.write_bytes((DATA / "sur-3.sur").read_bytes()[:5000])
    status, _, err = run_cli(capsys, "stats", cut)
    assert status == 2 and "cut.sur" in err


def test_scan_and_synth_commands(capsys, tmp_path):
    out_file = tmp_path / "synth.h5"
    status, out, _ = run_cli(
        capsys, "synth", "--n", 200, "--pixel-size", 20e-6, "--seed", 3, "--out", out_file
    )
    assert status == 0 and out_file.exists()
    surface = topo.read_surface(out_file)
    assert surface.periodic and surface.heights.shape == (200, 200)
    scan_file = tmp_path / "scan.h5"
    status, out, _ = run_cli(
        capsys, "scan", out_file, "--max-stride", 8, "--out", scan_file, "--json"
    )
    assert status == 0
    data = json.loads(out)
    assert data["stride"] == list(range(1, 9)) and math.isfinite(data["density_exponent"])
    with h5py.File(scan_file) as handle:
        np.testing.assert_allclose(handle["summit_radius"][()], data["summit_radius"])
        assert handle["resolution"].attrs["units"] == "m"
    assert scan_file.with_suffix(".png").stat().st_size > 10_000
    npy = tmp_path / "synth.npy"
    assert run_cli(capsys, "synth", "--n", 64, "--pixel-size", 1e-5, "--out", npy)[0] == 0
    assert np.load(npy).shape == (64, 64)


def test_resolution_scan_figure_units_follow_the_data(surface):
    """Fig 12(a-c) of a 10 um map: resolution in um, eta in mm^-2 (the paper's units), the
    plotted points are the scan's own, and no text overlaps or is clipped."""
    from asperity.plotting import layout_problems, new_figure

    scan = topo.resolution_scan(surface, 12)
    fig = topo.draw_resolution_scan(new_figure(13, 4), scan, title="paper-like map")
    ax_r, ax_eta, ax_sigma = fig.get_axes()
    assert all(ax.get_xlabel() == "resolution $\\Delta$ (\u00b5m)" for ax in fig.get_axes())
    assert ax_eta.get_ylabel().endswith("(mm$^{-2}$)") and ax_eta.get_yscale() == "log"
    np.testing.assert_allclose(ax_r.lines[0].get_xdata(), np.arange(1, 13) * 10.0)
    eta = ax_eta.lines[0].get_ydata()
    np.testing.assert_allclose(eta, scan.asperity_density * 1e-6)
    r_unit = ax_r.get_ylabel().rsplit("(", 1)[-1].rstrip(")")
    factor = {"\u00b5m": 1e6, "mm": 1e3}[r_unit]
    np.testing.assert_allclose(ax_r.lines[0].get_ydata(), scan.summit_radius * factor)
    assert layout_problems(fig) == []


def stats_json(capsys, *args):
    status, out, err = run_cli(capsys, "stats", *args, "--json")
    assert status == 0, err
    return json.loads(out), err


def test_stats_preparation_options_on_real_files(capsys):
    metropro = DATA / "metropro-1.dat"
    record, _ = stats_json(capsys, metropro)
    preparation = record["preparation"]
    assert preparation["levelling"] == "plane" and preparation["missing_policy"] == "keep"
    assert 1 <= preparation["n_outliers"] <= 20 and record["n_missing"] == preparation["n_outliers"]
    untouched, _ = stats_json(capsys, metropro, "--outliers", "none")
    assert untouched["preparation"]["n_outliers"] == 0 and untouched["n_missing"] == 0
    by_name, err = stats_json(capsys, metropro, "--detrend", "quadratic")
    by_order, _ = stats_json(capsys, metropro, "--form-order", "2")
    assert by_name == by_order and by_name["preparation"]["form_order"] == 2
    assert "warning: the removed form (quadratic" in err
    cropped, _ = stats_json(capsys, metropro, "--crop", "100:400,:300", "--missing", "interpolate")
    assert (cropped["nx"], cropped["ny"], cropped["n_missing"]) == (300, 300, 0)
    assert cropped["preparation"]["crop"] == [100, 400, 0, 300]
    status, _, err = run_cli(capsys, "stats", DATA / "opd-1.opd", "--missing", "refuse")
    assert status == 2 and "opd-1.opd" in err and "'refuse'" in err
    for bad in (["--outliers", "mad:x"], ["--crop", "0:9999,:"], ["--crop-m", "a:b,:"]):
        status, _, err = run_cli(capsys, "stats", metropro, *bad)
        assert status == 2 and ("--outliers" in err or "crop" in err)
    status, _, err = run_cli(capsys, "stats", metropro, "--detrend", "mean", "--form-order", "2")
    assert status == 2 and "not allowed with argument" in err and len(err.splitlines()) == 1


def test_scan_json_carries_the_preparation_and_the_valid_area(capsys):
    status, out, _ = run_cli(capsys, "scan", DATA / "sur-3.sur", "--max-stride", 3, "--json")
    data = json.loads(out)
    assert status == 0 and data["preparation"]["missing_fraction"] > 0.88
    assert any("missing" in w for w in data["preparation"]["warnings"])
    density = np.array(data["n_summits"]) / np.array(data["nominal_area"])
    np.testing.assert_allclose(data["asperity_density"], density)
