"""asperity.pipelines: the main job, from a measured surface to a calibrated friction prediction."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("asperity")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"
