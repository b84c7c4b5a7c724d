"""The job's engine: what every stage runs on, whatever it computes.

- :mod:`~asperity.pipelines.engine.stage`: the declaration of a stage (:class:`Stage`), the
  configuration view a stage sees, and the :class:`Runner` that keys, reuses and stores stages;
- :mod:`~asperity.pipelines.engine.store`: ``results.h5``, one group per stage, atomic writes;
- :mod:`~asperity.pipelines.engine.outdir`: the output folder's lock and write errors;
- :mod:`~asperity.pipelines.engine.parallel`: serial, process and dask executors for sweeps.
"""
