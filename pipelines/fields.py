"""Deprecated (asperity 0.2's path): import :mod:`asperity.fields`.

``import asperity.pipelines.fields`` warns (DeprecationWarning) and gives the public names of
the module at its new path, the same objects. Removed in asperity 0.5.
"""

import warnings

from asperity.fields import *  # noqa: F403

warnings.warn(
    "asperity.pipelines.fields is deprecated and will be removed in asperity 0.5: "
    "import asperity.fields instead",
    DeprecationWarning,
    stacklevel=2,
)
