"""Report rows of the measured A_r(F_x) curves: the shape fit's scale factor per curve.

In mode ``shape`` the lambda fit compares each measured curve with the model curve at the
curve's own load times a free factor c (:mod:`asperity.statmodel.lambda_fit`); the
verdict's ``shape_scale`` reason judges c (:func:`asperity.pipelines.stages.verdict.
check_shape_scale`). The row shows every c beside its load so that a reader sees the level
the fit absorbed.
"""

from __future__ import annotations

import numpy as np

from asperity.pipelines.report._run import Run


def shape_scale_key_numbers(result: Run) -> list[tuple[str, str]]:
    """The row ``shape-fit scale factor c``: c (dimensionless) at each curve's F_z (N).

    Empty when lambda was not fitted, was fitted in mode ``absolute`` (c = 1), or the stored
    result predates the field.
    """
    lam = result.mode_mixity
    scales = getattr(lam, "shape_scale", None)
    if not lam.fitted or scales is None or lam.fit_mode == "absolute":
        return []
    loads = np.asarray(lam.shape_scale_normal_load, dtype=float)
    cells = ", ".join(
        f"{c:.3g} at {f:.4g} N" for c, f in zip(np.asarray(scales, float), loads, strict=True)
    )
    return [("shape-fit scale factor c (measured / model)", cells)]
