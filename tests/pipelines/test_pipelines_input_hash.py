"""The input hash of a synthetic surface covers the recipe's constants, not only its name."""

from __future__ import annotations

import dataclasses

import pytest

from asperity import topo
from asperity.pipelines.config import SYNTHETIC_RECIPES, SurfaceConfig, SyntheticRecipe
from asperity.pipelines.stages import surface as surface_stage


@pytest.mark.parametrize("recipe", ["paper_like", "paper_surface"])
def test_changing_a_recipe_constant_changes_the_input_hash(recipe, monkeypatch):
    """A resumed run must not reuse stages computed on a surface made with other constants."""
    config = SurfaceConfig(synthetic=SyntheticRecipe(recipe=recipe, n=64, pixel_size=1e-5, seed=0))
    before = surface_stage.input_sha256(config)
    assert surface_stage.input_sha256(config) == before  # deterministic
    constants = surface_stage.RECIPE_CONSTANTS[recipe]
    if dataclasses.is_dataclass(constants):
        changed = dataclasses.replace(constants, cap_density=constants.cap_density * 1.01)
    else:
        changed = {**constants, "rms_height": constants["rms_height"] * 1.01}
    monkeypatch.setitem(surface_stage.RECIPE_CONSTANTS, recipe, changed)
    assert surface_stage.input_sha256(config) != before


def test_every_recipe_has_its_constants_hashed():
    assert set(SYNTHETIC_RECIPES) == set(surface_stage.RECIPE_CONSTANTS)
    assert surface_stage.RECIPE_CONSTANTS["paper_like"] is topo.synthetic.PAPER_LIKE
