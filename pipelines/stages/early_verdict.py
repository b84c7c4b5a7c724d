"""A verdict known before the expensive stages, given there: the full-contact limit.

The verdict's preview (:func:`~asperity.pipelines.stages.verdict.preview_adhesion_regime`)
judges the adhesion regime from the levelled map before the BEM. When it finds a reason that
makes every later number invalid (``adhesion_full_contact``: the elastic energy to flatten the
map, U_el/(A0 w), below 1, Persson-Tosatti), the BEM reference and the statistical model cannot
change the verdict: the job (:mod:`asperity.pipelines.job`) skips the stages of
:data:`SKIPPED_WHEN_KNOWN` and the verdict stage writes the early verdict
(:func:`asperity.pipelines.stages.verdict.early_verdict`, from this module's pieces), with what
the regime does predict:

* the real area A_r -> A_n at every load (a closed interface), and
* the sliding friction it implies, F_d -> tau_0 A_n: the paper's sliding junctions carry the
  uniform shear strength tau_0 over their area (E:Hertz_theory, T = pi a^2 tau_0; the model's
  sliding friction is tau_0 A_r, paper Section 3), and A_r = A_n when the interface is closed.
  The static peak above it needs the asperity model and is not predicted.

The limit is tested against the measured A_r/A_n when the job has measured curves
(:func:`full_contact_test`): a measured fraction far below 1 (under
:data:`CONTRADICTED_FRACTION`) contradicts the regime, a warning ``full_contact_contradicted``
naming what to check. ``run.compute_all = true`` (``asperity run --compute-all``) computes
every stage anyway; the verdict is then the full one, with the same invalid reason.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

#: The stages skipped when the verdict is known before the BEM: none can change it.
SKIPPED_WHEN_KNOWN: tuple[str, ...] = (
    "bem_reference",
    "statistical_model",
    "mode_mixity",
    "friction",
    "psd",
    "realisations",
    "bem_shear",
)
#: Measured A_r/A_n below which the measurement contradicts the full-contact limit (A_r/A_n -> 1).
CONTRADICTED_FRACTION = 0.5


def known_invalid(record: Mapping[str, object] | None) -> list[str]:
    """The codes of a preview record's invalid reasons (its ``codes`` and ``severities``):
    when not empty, the verdict is known to be invalid before the stages it precedes."""
    if not record:
        return []
    codes = list(record.get("codes") or [])
    severities = list(record.get("severities") or [])
    return [c for c, s in zip(codes, severities, strict=False) if s == "invalid"]


def full_contact_limit(nominal_area: float, shear_strength: float) -> tuple[float, float]:
    """(A_r, F_d) of a closed interface: A_r = A_n (m^2) and F_d = tau_0 A_n (N), tau_0 in Pa
    (E:Hertz_theory's T = pi a^2 tau_0 summed over the whole nominal area)."""
    return float(nominal_area), float(shear_strength) * float(nominal_area)


def measured_fractions(measured: object, nominal_area: float) -> np.ndarray:
    """Every measured A_r/A_n of the job: the A_r(F_z) points and each A_r(F_x) curve's
    first point (at rest, F_x ~ 0)."""
    values: list[float] = []
    normal = getattr(measured, "normal_area", None)
    if normal is not None:
        values += list(np.asarray(normal.real_area, dtype=float))
    for curve in getattr(measured, "shear_area", ()) or ():
        area = np.asarray(curve.real_area, dtype=float)
        if area.size:
            values.append(float(area[np.argmin(np.abs(curve.tangential_force))]))
    return np.asarray(values, dtype=float) / float(nominal_area)


def full_contact_test(fractions: np.ndarray) -> tuple[str, list[tuple[str, str, str]]]:
    """The limit A_r/A_n -> 1 against the measured fractions: its sentence, and a warning
    ``full_contact_contradicted`` (code, severity, text) when the largest measured fraction is
    below :data:`CONTRADICTED_FRACTION`."""
    if not fractions.size:
        return "no measured A_r/A_n to test it against (measured.normal_area, shear_area)", []
    top = float(np.max(fractions))
    if top >= CONTRADICTED_FRACTION:
        return f"the measured A_r/A_n reaches {top:.3g}: consistent with the limit 1", []
    sentence = (
        f"the measured A_r/A_n reaches only {top:.3g} < {CONTRADICTED_FRACTION:g}: the "
        "measurement contradicts the full-contact regime"
    )
    why = (
        f"{sentence} predicted from the map; check the material (E*, w: a stiffer solid or a "
        "smaller w gives partial contact), the map's finest scales (a coarser or filtered "
        "map stores less elastic energy) and the measured areas' units"
    )
    return sentence, [("full_contact_contradicted", "warning", why)]


def limit_lines(verdict: object) -> list[str]:
    """The full-contact limit in words, one line per statement (terminal and reports); empty
    unless the verdict was known early."""
    if getattr(verdict, "full_contact_real_area", None) is None:
        return []
    loads = ", ".join(f"{f:g}" for f in np.atleast_1d(verdict.full_contact_normal_load))
    area, sliding = verdict.full_contact_real_area, verdict.full_contact_sliding_friction
    return [
        "Full-contact limit (what this regime predicts; not the asperity model's numbers): "
        f"A_r -> A_n = {area:.4g} m^2 (A_r/A_n -> 1) at every load ({loads} N); sliding "
        f"friction F_d -> tau_0 A_n = {sliding:.4g} N, the same at every load; the static "
        "peak above it is not predicted.",
        f"Test of the limit: {verdict.full_contact_test}.",
        "Not computed (the verdict was known before them): "
        + ", ".join(verdict.stages_skipped or [])
        + "; run.compute_all = true (asperity run --compute-all) computes every stage.",
    ]
