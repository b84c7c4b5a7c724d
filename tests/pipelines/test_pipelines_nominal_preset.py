"""The ``nominal`` preset (the paper's whole 35 x 20 mm interface at 2 um) loads and validates;
it is never run here (hours on 2 cores: benchmarks/bem_nominal.py)."""

from __future__ import annotations

import pytest

from asperity.bem import resolving_range
from asperity.pipelines.config import ConfigError, config_from_dict, load_preset, preset_text
from asperity.pipelines.stages.surface import RECIPE_CONSTANTS, input_sha256, read_input
from asperity.topo.errors import OverBudgetError
from asperity.topo.io.limits import MEMORY_BUDGET_ENV
from asperity.topo.synthetic import PAPER_SURFACE_WAVY

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


def test_the_nominal_preset_maps_the_whole_nominal_contact_at_2_um():
    cfg = load_preset("nominal")
    s = cfg.surface.synthetic
    assert (s.recipe, s.n, s.ny, s.pixel_size) == ("paper_surface", 17500, 10000, 2e-6)
    # the map is the experiment's whole nominal area, 35 x 20 mm, not a window of it
    assert s.n * s.ny * s.pixel_size**2 == pytest.approx(cfg.loading.nominal_area, rel=1e-12)
    assert cfg.loading.normal_loads == (0.56, 2.08)
    # the map's own grid only, and the given range is the rule's: a 3-pixel zone at 2 um
    assert (cfg.bem.max_stride, cfg.bem.coarsen, cfg.bem.max_refinement) == (1, False, 1)
    expected = resolving_range(cfg.material.work_of_adhesion, cfg.material.e_star, 2e-6)
    assert cfg.bem.adhesion_range == pytest.approx(expected, rel=1e-3)
    again = config_from_dict(tomllib.loads(cfg.to_toml()), source=cfg.source)
    assert again == cfg


def test_the_memory_rule_refuses_it_under_16_gib_and_names_the_budget(monkeypatch):
    """Judged from the recipe before any pixel is generated (175 M points x 128 B + 0.5 GiB =
    21.4 GiB): refused under the default 16 GiB, accepted under 24 GiB."""
    surface = load_preset("nominal").surface
    monkeypatch.delenv(MEMORY_BUDGET_ENV, raising=False)
    with pytest.raises(OverBudgetError) as info:
        read_input(surface)
    assert "17500 x 10000" in str(info.value) and MEMORY_BUDGET_ENV in str(info.value)
    monkeypatch.setenv(MEMORY_BUDGET_ENV, "21GiB")
    with pytest.raises(OverBudgetError):
        read_input(surface)


def test_ny_is_refused_for_the_square_recipe():
    data = tomllib.loads(preset_text("default"))
    data["surface"]["synthetic"]["ny"] = 600
    with pytest.raises(ConfigError, match=r"surface\.synthetic\.ny"):
        config_from_dict(data)


def test_a_square_recipe_keeps_its_input_hash(monkeypatch):
    """``ny`` absent or equal to ``n`` is the same square map with the hash it had before ``ny``
    existed, so its stored stages stay valid; a different ``ny`` is another surface. Pinned:
    the paper preset on seed 1 with asperity 0.4.2's recipe, and with 0.4.1's recipe
    (``PAPER_SURFACE_WAVY``) the hash 0.4.1 gave, as the code hashed it before ``ny`` and the
    recipe's optional fields (coarse level, modulation) existed. The paper preset's stand-in is
    now the Gaussian ``paper_spectrum``; the capped recipe, named, keeps its 0.4.2 hash."""
    data = tomllib.loads(preset_text("paper"))
    data["surface"]["synthetic"]["recipe"] = "paper_surface"
    square = config_from_dict(data).surface
    data["surface"]["synthetic"]["ny"] = data["surface"]["synthetic"]["n"]
    explicit = config_from_dict(data).surface
    data["surface"]["synthetic"]["ny"] = 5000
    other = config_from_dict(data).surface
    assert (
        input_sha256(square)
        == input_sha256(explicit)
        == ("27b0cc431024e9d54c6159aa8ecf821630c1bb57cb243a0fcd3940078b9976d0")
    )
    monkeypatch.setitem(RECIPE_CONSTANTS, "paper_surface", PAPER_SURFACE_WAVY)
    assert input_sha256(square) == (
        "ba7faecefa00a7cc66944c64cad2a78b811f8fda358c913a1ca7e58748969e80"
    )
    assert input_sha256(other) != input_sha256(square)
