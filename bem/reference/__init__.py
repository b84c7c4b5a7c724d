"""The BEM reference of the job: load chains on decimated grids, grid refinement and extrapolation,
the adhesion range, the discretisation uncertainty.

The public names are those of :mod:`asperity.bem` (its ``__init__.pyi``).
"""
