"""What the report reads: a job's result or a reopened ``results.h5`` (the same stage fields).

Shared by the report's text (:mod:`~asperity.pipelines.report.text`) and figures
(:mod:`~asperity.pipelines.report.figures`).
"""

from __future__ import annotations

from typing import TypeAlias

import numpy as np

from asperity.pipelines.job import JobResult
from asperity.pipelines.results import Results, StageResults

#: A run the report is written from: the job's result, or a run reopened from results.h5.
Run: TypeAlias = JobResult | Results


def persson_fraction(result: StageResults) -> np.ndarray | None:
    """Persson's non-adhesive A_r/A_n (1) at the job's loads, None without the PSD stage."""
    psd = result.psd
    if psd is None:
        return None
    return np.asarray(psd.persson_real_area) / result.statistical_model.nominal_area
