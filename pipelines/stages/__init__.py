"""The stages of the job, one module each, and their order (:data:`STAGES`).

=====  ======================  ====================================================
 no.   group in results.h5     module
=====  ======================  ====================================================
 1     surface                 :mod:`~asperity.pipelines.stages.surface`
 2     resolution_scan         :mod:`~asperity.pipelines.stages.surface`
 3     bem_reference           :mod:`~asperity.pipelines.stages.bem`
 4     statistical_model       :mod:`~asperity.pipelines.stages.statistical_model`
 5     mode_mixity             :mod:`~asperity.pipelines.stages.friction`
 6     friction                :mod:`~asperity.pipelines.stages.friction`
 7     psd                     :mod:`~asperity.pipelines.stages.psd`
 8     realisations            :mod:`~asperity.pipelines.stages.realisations`
 9     bem_shear               :mod:`~asperity.pipelines.stages.bem_shear`
 10    friction_tests          :mod:`~asperity.pipelines.stages.friction_curves`
 11    verdict                 :mod:`~asperity.pipelines.stages.verdict`
=====  ======================  ====================================================

(a test holds this table to :data:`STAGES`.) Each module declares its stages with
:class:`~asperity.pipelines.engine.stage.Stage`; a stage's number is its place in
:data:`STAGES`; the declaration API is :mod:`asperity.pipelines.engine.stage`'s.
"""

from asperity.pipelines.engine.stage import Stage
from asperity.pipelines.stages.bem import BEM
from asperity.pipelines.stages.bem_shear import BEM_SHEAR
from asperity.pipelines.stages.friction import FRICTION, MODE_MIXITY
from asperity.pipelines.stages.friction_curves import FRICTION_CURVES
from asperity.pipelines.stages.psd import PSD
from asperity.pipelines.stages.realisations import REALISATIONS
from asperity.pipelines.stages.statistical_model import STATISTICAL_MODEL
from asperity.pipelines.stages.surface import SCAN, SURFACE
from asperity.pipelines.stages.verdict import VERDICT

#: The stages of the job, in the order they run; a stage's number is its place here, from 1.
STAGES: tuple[Stage, ...] = (
    SURFACE,
    SCAN,
    BEM,
    STATISTICAL_MODEL,
    MODE_MIXITY,
    FRICTION,
    PSD,
    REALISATIONS,
    BEM_SHEAR,
    FRICTION_CURVES,
    VERDICT,
)
#: Their group names in results.h5.
STAGE_NAMES: tuple[str, ...] = tuple(stage.name for stage in STAGES)


def stage_number(name: str) -> int:
    """The number of the stage with group or attribute ``name`` (1 for "surface")."""
    for i, stage in enumerate(STAGES, start=1):
        if name in (stage.name, stage.attribute):
            return i
    raise KeyError(f"no stage named {name!r} (stages: {', '.join(STAGE_NAMES)})")


__all__ = ["STAGES", "STAGE_NAMES", "stage_number"]
