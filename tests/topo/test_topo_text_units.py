"""Plain text states no length unit: asperity refuses it unless the unit is stated."""

from __future__ import annotations

import numpy as np
import pytest

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.cli import main
from asperity.topo.errors import TopographyFileError
from asperity.topo.io.units import UNIT_SPELLINGS


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


@pytest.mark.parametrize(
    "spelling",
    [s for group in UNIT_SPELLINGS.values() for s in group] + ["Microns", "MicroMeters"],
)
def test_every_spelling_of_the_table_is_read_alike_by_the_job_file_and_the_reader(
    tmp_path, spelling
):
    """One table (topo.io.units.UNIT_SPELLINGS): what --unit accepts, [surface] unit accepts."""
    from asperity.pipelines.config import config_from_dict
    from asperity.topo.io.units import length_unit_in_metres

    metres = length_unit_in_metres(spelling)
    path = tmp_path / "xy.txt"
    x = 1e-6 / metres * np.arange(40)  # a 1 um step and sub-um heights, in the file's unit
    np.savetxt(path, np.column_stack([x, 1e-7 / metres * np.sin(np.arange(40))]))
    job = config_from_dict({"surface": {"file": str(path), "unit": spelling}}, source="job.toml")
    profile = topo.read_surface(path, unit=job.surface.unit)
    assert profile.dx == pytest.approx(1e-6, rel=1e-9)


def test_job_file_refuses_a_non_length_unit_listing_the_spellings(tmp_path):
    from asperity.pipelines.config import ConfigError, config_from_dict

    path = tmp_path / "xy.txt"
    _profile(path)
    with pytest.raises(ConfigError) as caught:
        config_from_dict({"surface": {"file": str(path), "unit": "V"}}, source="job.toml")
    text = str(caught.value)
    assert "unit" in text and "micron" in text and "V" in text
