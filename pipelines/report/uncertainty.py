"""Error bars wherever a predicted number is shown: ``value ± u`` text and the uncertainties
the figures draw as bands and error bars (drawn in :mod:`~asperity.pipelines.report.figures`;
docs/pipelines.md, "Uncertainties").

Where the numbers come from (all SI, stored in results.h5):

* BEM A_r/A_n: ``bem_reference.contact_fraction_uncertainty`` (Richardson extrapolation of the
  grid check, Roache's grid convergence index; the adhesion-range part in quadrature when
  given);
* the effective resolution: ``statistical_model.optimum_resolution`` and ``optimum_interval``;
* the model's A_r, static and sliding friction, sliding displacement:
  ``friction.*_uncertainty`` (:func:`statmodel.uncertainty.propagate_to_predictions`).

An uncertainty that is a lower bound (an interval open on a side) is written ``± >u``; one
that is not known ``± ?``: never a bare number that looks exact.
"""

from __future__ import annotations

import math

import numpy as np

from asperity.pipelines.report._run import Run
from asperity.pipelines.report.numbers import format_number
from asperity.pipelines.stages.bem import BemReference
from asperity.pipelines.stages.friction import FrictionPrediction
from asperity.pipelines.stages.statistical_model import ResolutionChoice


def plus_minus(value: float, u: float | None, scale: float = 1.0, lower_bound: bool = False) -> str:
    """``"value ± u"`` in the display unit ``scale`` (e.g. 1e6 for µm) with the digits u
    supports (:func:`~asperity.pipelines.report.numbers.format_number`: u to 2 significant
    digits, the value to the same decimal place; 4 significant digits without u); ``± ?``
    when u is not known, ``± >u`` (rounded down) when it is a lower bound."""
    v = float(value) * scale
    if u is None or not math.isfinite(v):
        return format_number(v)
    return format_number(v, float(u) * scale, lower_bound=lower_bound)


def _at(values: np.ndarray | None, i: int) -> float | None:
    return None if values is None else float(np.asarray(values)[i])


def bem_cells(bem: BemReference, i: int) -> tuple[str, str]:
    """The non-adhesive and adhesive BEM A_r/A_n of load ``i`` with their uncertainties."""
    if bem is None:
        return "-", "-"
    u = getattr(bem, "contact_fraction_uncertainty", None)
    plain = plus_minus(bem.contact_fraction[i], None if u is None else u[0, i])
    adh = bem.contact_fraction_adhesive
    if adh is None:
        return plain, "-"
    return plain, plus_minus(adh[i], None if u is None else u[-1, i])


def model_cells(result: Run, i: int, force: float = 1.0, length: float = 1e6) -> list[str]:
    """The model's A_r/A_n, static and sliding friction and sliding displacement of load ``i``,
    each ``+- u`` when the friction stage estimated it; forces times ``force`` (1: N) and the
    displacement times ``length`` (1e6: µm), the display units of their columns."""
    fr, res = result.friction, result.statistical_model
    a_n = fr.nominal_area
    low = bool(getattr(fr, "uncertainty_lower_bound", False))
    area = getattr(fr, "model_real_area", None)
    if area is None:
        area_text = format_number(res.real_area[res.index, i] / a_n)
    else:
        area_text = plus_minus(area[i], _at(fr.model_real_area_uncertainty, i), 1 / a_n, low)
    return [
        area_text,
        plus_minus(fr.static_friction[i], _at(fr.static_friction_uncertainty, i), force, low),
        plus_minus(fr.sliding_friction[i], _at(fr.sliding_friction_uncertainty, i), force, low),
        plus_minus(
            fr.sliding_displacement[i], _at(fr.sliding_displacement_uncertainty, i), length, low
        ),
    ]


def resolution_text(res: ResolutionChoice) -> str:
    """The effective resolution row: the located optimum with its interval (um), and the
    stride of least misfit."""
    at_stride = float(res.resolution[res.effective_index])
    stride = f"stride of least misfit {res.effective_stride}: {at_stride * 1e6:.4g} um"
    if getattr(res, "optimum_resolution", None) is None:
        return f"{res.effective_resolution * 1e6:.4g} um (stride {res.effective_stride})"
    low, high = np.asarray(res.optimum_interval, dtype=float) * 1e6
    flags = (("fine", res.optimum_open_finer), ("coarse", res.optimum_open_coarser))
    sides = [side for side, is_open in flags if is_open]
    interval = f"interval {low:.4g}..{high:.4g} um" if math.isfinite(low) else "no interval"
    if sides:
        interval += f", open on the {' and '.join(sides)} side"
    shift = getattr(res, "optimum_reference_shift", None)
    if shift is not None:
        misfit_low, misfit_high = np.asarray(res.optimum_misfit_interval, dtype=float) * 1e6
        interval += (
            f": the misfit's {misfit_low:.4g}..{misfit_high:.4g} um united with the optima "
            f"against the BEM reference times (1 -/+ u), {shift[0] * 1e6:.4g} and "
            f"{shift[1] * 1e6:.4g} um"
        )
    if getattr(res, "optimum_kept_sample", None):
        stride += "; a measured resolution fitted better than the parabola's vertex"
    return f"{res.effective_resolution * 1e6:.4g} um ({interval}; {stride})"


def misfit_text(res: ResolutionChoice) -> str:
    """The least misfit: located between strides, and at the stride of least misfit."""
    at_stride = f"{res.misfit[res.index]:.3g} at stride {res.effective_stride}"
    if getattr(res, "optimum_misfit", None) is None:
        return f"{at_stride} (rms ln ratio)"
    return f"{res.optimum_misfit:.3g} between strides ({at_stride}; rms ln ratio)"


def uncertainty_rows(result: Run) -> list[tuple[str, str]]:
    """Key-number rows saying what the ± u of the load table are and what limits them."""
    fr = result.friction
    message = getattr(fr, "uncertainty_message", None)
    if message is None:
        return []
    return [
        (
            "error bars (± u)",
            f"model, one sigma: {message}; BEM: grid convergence index of the grid used "
            "refined by Fourier interpolation (Richardson extrapolation, about 95 %)",
        )
    ]


def bem_error_bars(bem: BemReference) -> list[np.ndarray | None]:
    """Per BEM mode (non-adhesive, adhesive), its A_r/A_n uncertainty per load (None unknown)."""
    u = getattr(bem, "contact_fraction_uncertainty", None)
    modes = 1 if bem.contact_fraction_adhesive is None else 2
    return [None if u is None else np.asarray(u[m], dtype=float) for m in range(modes)]


def friction_error_bars(fr: FrictionPrediction) -> dict[str, np.ndarray | None]:
    """Static and sliding friction uncertainties (N) per load, None when not estimated."""
    return {
        "static (peak)": getattr(fr, "static_friction_uncertainty", None),
        "sliding": getattr(fr, "sliding_friction_uncertainty", None),
    }
