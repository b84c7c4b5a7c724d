"""The seam limit for :mod:`~asperity.pipelines.report.bem`; it lives in bem.grid_refinement."""

from asperity.bem.grid_refinement import EDGE_MISMATCH_LIMIT as EDGE_MISMATCH_LIMIT
