"""Deprecated (asperity 0.2's path): import :mod:`asperity.statmodel.lambda_fit`.

``import asperity.pipelines.fitting`` warns (DeprecationWarning) and gives the public names of
the module at its new path, the same objects. Removed in asperity 0.5.
"""

import warnings

from asperity.statmodel.lambda_fit import *  # noqa: F403

warnings.warn(
    "asperity.pipelines.fitting is deprecated and will be removed in asperity 0.5: "
    "import asperity.statmodel.lambda_fit instead",
    DeprecationWarning,
    stacklevel=2,
)
