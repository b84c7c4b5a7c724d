"""asperity.pipelines: the main job, from a measured surface to a calibrated friction prediction.

Layout: :mod:`~asperity.pipelines.job` runs the stages of :mod:`~asperity.pipelines.stages`
(one module per stage) on the engine of :mod:`~asperity.pipelines.engine` (stage declaration
and runner, HDF5 store, output-folder lock, parallel sweeps); :mod:`~asperity.pipelines.results`
reopens a run, :mod:`~asperity.pipelines.report` writes the figures and reports,
:mod:`~asperity.pipelines.cli` the ``asperity`` command, :mod:`~asperity.pipelines.batch` many
maps at once; :mod:`~asperity.pipelines.config` and :mod:`~asperity.pipelines.measured` read
the job's inputs. The module paths that asperity 0.2's documentation named
(``asperity.pipelines.surface_stage``, ``bem_stage``, ``resolution_stage``, ``friction_stage``,
``psd_stage``, ``fitting``, ``fields``, ``verdict``) still import, with a DeprecationWarning
naming the new path, until asperity 0.5.
"""

from asperity import __version__

__all__ = ["__version__"]
