"""Deprecated (asperity 0.2's path): import :mod:`asperity.pipelines.stages.bem`.

``import asperity.pipelines.bem_stage`` warns (DeprecationWarning) and gives the public names of
the module at its new path, the same objects. Removed in asperity 0.5.
"""

import warnings

# public in 0.2 in the stage module; since 0.4 in asperity.bem.reference.load_sweeps
from asperity.bem.reference.load_sweeps import check_load_index, load_chains  # noqa: F401
from asperity.pipelines.stages.bem import *  # noqa: F403

warnings.warn(
    "asperity.pipelines.bem_stage is deprecated and will be removed in asperity 0.5: "
    "import asperity.pipelines.stages.bem instead",
    DeprecationWarning,
    stacklevel=2,
)
