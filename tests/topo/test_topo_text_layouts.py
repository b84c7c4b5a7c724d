"""Text layouts: an x z stylus profile is a LineProfile, a Gwyddion text export carries its
pixel size and axes, an unknown header is an unsupported format."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity import topo
from asperity.errors import InputError
from asperity.topo.errors import NumberFormatError, UnsupportedContentError

RNG = np.random.default_rng(18)


def write_xz(path, x, z, fmt="%.6f"):
    np.savetxt(path, np.column_stack([x, z]), fmt=fmt, delimiter="\t")
    return path


def test_two_column_stylus_export_is_a_profile_with_its_own_step(tmp_path):
    # like SurfaceTopography's xy-4.txt: 10001 positions printed to 1e-6, a rounded step
    step = 9.95613e-5
    x = step * np.arange(10001)
    z = 1e-6 * np.sin(2 * np.pi * x / 0.05) + 3.6e-3
    profile = topo.read_surface(write_xz(tmp_path / "xz.txt", x, z), unit="m")
    assert isinstance(profile, topo.LineProfile)
    assert profile.nx == 10001
    assert profile.dx == pytest.approx(step, rel=1e-6)
    np.testing.assert_allclose(profile.heights, z, atol=5e-7)  # printed to 1e-6
    assert profile.provenance["format"] == "xz-profile-text"


def test_two_column_profile_refuses_a_pixel_size_instead_of_becoming_a_map(tmp_path):
    path = write_xz(tmp_path / "xz.txt", 1e-6 * np.arange(20), RNG.normal(size=20) * 1e-7)
    with pytest.raises(InputError, match=r"x z profile.*leave pixel_size"):
        topo.read_surface(path, pixel_size=1e-6)


def test_profile_with_a_missing_height_counts_it(tmp_path):
    z = RNG.normal(size=12) * 1e-7
    z[3] = np.nan
    profile = topo.read_surface(
        write_xz(tmp_path / "holes.txt", 1e-6 * np.arange(12), z, "%.9g"), unit="m"
    )
    assert profile.n_missing == 1 == profile.provenance["missing_pixels"]


def test_non_uniform_profile_is_refused_never_interpolated(tmp_path):
    x = np.array([0, 1, 2, 3, 4, 4.5, 5, 6, 7, 8, 9]) * 1e-6
    path = write_xz(tmp_path / "uneven.txt", x, np.zeros_like(x), "%.9g")
    with pytest.raises(UnsupportedContentError, match=r"x column: is not uniformly sampled"):
        topo.read_surface(path)


GWYDDION = """# Channel: Topography
# Width: 12 µm
# Height: 3 nm
# Value units: nm
1 2 3 4
5 6 7 8
9 10 11 12
"""


@pytest.mark.parametrize("language", ["english", "german"])
def test_gwyddion_text_export_gives_pixel_sizes_axes_and_units(tmp_path, language):
    text = GWYDDION
    if language == "german":
        text = text.replace("Channel", "Kanal").replace("Width", "Breite")
        text = text.replace("# Height", "# Höhe")
    path = tmp_path / "export.txt"
    path.write_text(text, encoding="utf-8")
    surface = topo.read_surface(path)
    assert isinstance(surface, topo.HeightMap)
    # 4 columns along x (Width 12 um), 3 rows along y (Height 3 nm)
    assert (surface.nx, surface.ny) == (4, 3)
    assert surface.dx == pytest.approx(3e-6) and surface.dy == pytest.approx(1e-9)
    assert surface.lx == pytest.approx(12e-6) and surface.ly == pytest.approx(3e-9)
    # the first file row is the line y = 0, running along x
    np.testing.assert_allclose(surface.heights[:, 0], [1e-9, 2e-9, 3e-9, 4e-9])
    assert surface.provenance["channel"] == "Topography"
    with pytest.raises(InputError, match="Gwyddion header"):
        topo.read_surface(path, pixel_size=1e-6)


def test_gwyddion_export_of_a_non_length_channel_is_refused(tmp_path):
    path = tmp_path / "phase.txt"
    path.write_text(GWYDDION.replace("# Value units: nm", "# Value units: deg"))
    with pytest.raises(UnsupportedContentError, match=r"# Value units: is 'deg'"):
        topo.read_surface(path)


@pytest.mark.parametrize(
    "header", ["µm µm", "X_(microns),y1", "h=650 w=650", "This is not a topography file."]
)
def test_unknown_header_is_an_unsupported_format_not_a_number_error(tmp_path, header):
    path = tmp_path / "other.txt"
    path.write_text(f"{header}\n1 2\n3 4\n", encoding="utf-8")
    with pytest.raises(UnsupportedContentError, match=r"line 1: .*unsupported format") as info:
        topo.read_surface(path, pixel_size=1e-6)
    assert "asperity[formats]" in str(info.value)


def test_a_bad_number_on_the_first_line_is_still_a_number_error(tmp_path):
    path = tmp_path / "comma.txt"
    path.write_text("1,5 2,5\n3,5 4,5\n")
    with pytest.raises(NumberFormatError, match="decimal comma"):
        topo.read_surface(path, pixel_size=1e-6)


finite = st.floats(min_value=-1e-3, max_value=1e-3, allow_nan=False, allow_subnormal=False)


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(
    heights=st.lists(finite, min_size=8, max_size=40),
    step=st.floats(min_value=1e-9, max_value=1e-3),
    origin=st.floats(min_value=-1e-2, max_value=1e-2),
)
def test_any_uniform_xz_profile_reads_back_its_heights_and_step(
    tmp_path_factory, heights, step, origin
):
    x = origin + step * np.arange(len(heights))
    path = tmp_path_factory.mktemp("xz") / "profile.txt"
    path.write_text("".join(f"{float(a)!r} {b!r}\n" for a, b in zip(x, heights, strict=True)))
    profile = topo.read_surface(path, unit="m")
    assert isinstance(profile, topo.LineProfile)
    np.testing.assert_array_equal(profile.heights, heights)
    assert profile.dx == pytest.approx(step, rel=1e-6)


@settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck))
@given(columns=st.lists(st.tuples(finite, finite), min_size=8, max_size=30))
def test_any_two_column_text_is_a_profile_a_matrix_or_a_typed_error(tmp_path_factory, columns):
    path = tmp_path_factory.mktemp("xz") / "two.txt"
    path.write_text("".join(f"{a!r}\t{b!r}\n" for a, b in columns))
    try:
        surface = topo.read_surface(path, unit="m")
    except InputError as exc:  # TopographyFileError included
        assert str(path) in str(exc) and "\n" not in str(exc)
        return
    assert isinstance(surface, topo.LineProfile)  # two columns are never a map
    assert surface.nx == len(columns)
