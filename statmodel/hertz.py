"""Hertz theory of a single asperity (E:Hertz_theory): :mod:`asperity.single_asperity.hertz`.

The single-asperity closed forms are the ground both :mod:`asperity.bem` (its reference
solutions) and :mod:`asperity.statmodel` stand on, so that the BEM that checks the model does not
import it; this module keeps the statistical model's name for them (asperity 0.4).
"""

from asperity.single_asperity.hertz import *  # noqa: F403
from asperity.single_asperity.hertz import __all__ as __all__
