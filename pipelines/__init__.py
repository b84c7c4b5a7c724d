"""asperity.pipelines: the main job, from a measured surface to a calibrated friction prediction."""

from asperity import __version__

__all__ = ["__version__"]
