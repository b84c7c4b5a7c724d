"""The seam limit of the BEM's boundary check, re-exported for :mod:`asperity.pipelines.report.bem`.

The grid check lives in :mod:`asperity.bem.grid_refinement`; import from there.
"""

from asperity.bem.grid_refinement import EDGE_MISMATCH_LIMIT

__all__ = ["EDGE_MISMATCH_LIMIT"]
