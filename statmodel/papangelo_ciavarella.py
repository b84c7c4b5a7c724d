"""Papangelo-Ciavarella: a JKR asperity under shear (E:PC_indent, E:PC_P, E:PC_T,
E:max_disp_PC): :mod:`asperity.single_asperity.papangelo_ciavarella`.

The single-asperity closed forms are the ground both :mod:`asperity.bem` (its reference
solutions) and :mod:`asperity.statmodel` stand on, so that the BEM that checks the model does not
import it; this module keeps the statistical model's name for them (asperity 0.4).
"""

from asperity.single_asperity.papangelo_ciavarella import *  # noqa: F403
from asperity.single_asperity.papangelo_ciavarella import __all__ as __all__
