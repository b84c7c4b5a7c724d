"""Plain text states no length unit: asperity refuses it unless the unit is stated."""

from __future__ import annotations

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.cli import main
from asperity.topo.errors import TopographyFileError


def _profile(path, step=0.5, n=40):
    x = step * np.arange(n)
    z = np.sin(x)  # in the file's unit
    np.savetxt(path, np.column_stack([x, z]))
    return x, z


def test_unitless_profile_is_refused_naming_the_file_and_how(tmp_path):
    path = tmp_path / "xy.txt"
    _profile(path)
    with pytest.raises(TopographyFileError) as caught:
        topo.read_surface(path)
    text = str(caught.value)
    assert str(path) in text and "unit" in text and "--unit" in text and "[surface]" in text


def test_stated_unit_scales_heights_and_positions(tmp_path):
    path = tmp_path / "xy.txt"
    x, z = _profile(path)
    um = topo.read_surface(path, unit="um")
    mm = topo.read_surface(path, unit="mm")
    assert um.dx == pytest.approx(0.5e-6) and mm.dx == pytest.approx(0.5e-3)
    np.testing.assert_allclose(um.heights, z * 1e-6, rtol=1e-12)
    np.testing.assert_allclose(mm.heights, z * 1e-3, rtol=1e-12)
    # the rms height follows the unit: 1000x between mm and um
    assert np.std(mm.heights) / np.std(um.heights) == pytest.approx(1e3)


def test_xyz_and_matrix_need_a_unit_and_refuse_a_non_length(tmp_path):
    x, y = np.meshgrid(np.arange(6) * 2.0, np.arange(5) * 3.0, indexing="ij")
    z = np.random.default_rng(0).normal(size=x.shape)
    path = tmp_path / "map.xyz"
    np.savetxt(path, np.column_stack([x.ravel(), y.ravel(), z.ravel()]))
    with pytest.raises(TopographyFileError, match="unit"):
        topo.read_surface(path)
    surface = topo.read_surface(path, unit="nm")
    assert (surface.dx, surface.dy) == pytest.approx((2e-9, 3e-9))
    with pytest.raises(InputError, match="length unit"):
        topo.read_surface(path, unit="V")
    matrix = tmp_path / "m.txt"
    np.savetxt(matrix, z)
    with pytest.raises(TopographyFileError, match="unit"):
        topo.read_surface(matrix, pixel_size=1e-6)


def test_unit_is_refused_for_a_file_that_states_its_own(tmp_path):
    np.save(tmp_path / "h.npy", np.zeros((4, 4)))
    with pytest.raises(InputError, match="leave unit"):
        topo.read_surface(tmp_path / "h.npy", pixel_size=1e-6, unit="um")


def test_cli_refuses_then_reads_with_unit(tmp_path, capsys):
    path = tmp_path / "xy.txt"
    _profile(path, n=64)
    assert main(["stats", str(path)]) == 2
    assert "--unit" in capsys.readouterr().err
    assert main(["stats", str(path), "--unit", "um", "--json"]) != 2  # read, whatever its verdict
    assert '"dx": 5e-07' in capsys.readouterr().out
