"""asperity.pipelines: the main job, from a measured surface to a calibrated friction prediction.

Layout: :mod:`~asperity.pipelines.job` runs the stages of :mod:`~asperity.pipelines.stages`
(one module per stage) on the engine of :mod:`~asperity.pipelines.engine` (stage declaration
and runner, HDF5 store, output-folder lock, parallel sweeps); :mod:`~asperity.pipelines.results`
reopens a run, :mod:`~asperity.pipelines.report` writes the figures and reports,
:mod:`~asperity.pipelines.cli` the ``asperity`` command, :mod:`~asperity.pipelines.batch` many
maps at once; :mod:`~asperity.pipelines.config` and :mod:`~asperity.pipelines.measured` read
the job's inputs. The flat module names of asperity 0.2 (``surface_stage``, ``bem_stage``,
``store``, ...) still import (:mod:`asperity.pipelines._moved`).
"""

from typing import Any

from asperity import __version__
from asperity.pipelines import _moved

_moved.install()

__all__ = ["__version__"]


def __getattr__(name: str) -> Any:
    # ``asperity.pipelines.surface_stage`` and the other old flat names, imported when first used
    return _moved.moved_module(name)
