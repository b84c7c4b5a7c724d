"""The report's text: ``report.md`` (key numbers, the per-load table, the sections, captions)
and the one-screen terminal summary; ``report.html`` (:mod:`~asperity.pipelines.report.html`)
shows the same tables. Values are SI in ``results.h5`` and written here in the units named in
each row (um, mm, N).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from asperity import topo
from asperity.pipelines.report._run import Run, persson_fraction
from asperity.pipelines.report.bem import bem_section
from asperity.pipelines.report.early import (
    early_key_numbers,
    early_load_table,
    early_markdown,
    is_early,
)
from asperity.pipelines.report.friction_curves import (
    FRICTION_TEST_CAPTIONS,
    friction_tests_section,
)
from asperity.pipelines.report.measured import shape_scale_key_numbers
from asperity.pipelines.report.numbers import (
    format_number,
    format_quantity,
    format_uncertainty,
    plain_text,
    text_unit,
)
from asperity.pipelines.report.profile import (
    profile_key_numbers,
    profile_section,
)
from asperity.pipelines.report.shear import SHEAR_CAPTIONS, shear_key_numbers, shear_section
from asperity.pipelines.report.static_peak import MeasuredPeak, measured_peaks
from asperity.pipelines.report.uncertainty import (
    bem_cells,
    misfit_text,
    model_cells,
    plus_minus,
    resolution_text,
    uncertainty_rows,
)
from asperity.pipelines.report.verdict_marks import mark_adhesive_bem
from asperity.pipelines.stages import stage_number
from asperity.pipelines.stages.bem import BemReference
from asperity.pipelines.stages.early_verdict import limit_lines
from asperity.pipelines.stages.surface import LevelledSurface
from asperity.pipelines.stages.verdict import (
    Verdict,
    mark,
    verdict_lines,
    verdict_markdown,
    verdict_wording,
)
from asperity.plotting import DisplayUnit


def _grid_error_text(bem: BemReference) -> str:
    """The grid used: its discretisation error from the interpolated refinement where it was
    measured; else against the finest grid solved (the finest grid's own error then unknown)."""
    relative = getattr(bem, "discretisation_relative_uncertainty", None)
    if relative is not None and np.all(np.isfinite(relative)):
        return (
            f"discretisation error {format_uncertainty(float(np.max(relative)), percent=True)} "
            "(the grid used against its "
            "Fourier-interpolated refinement, at the check load)"
        )
    if bem.stride <= int(np.min(bem.check_stride)):
        return "the finest grid solved (its own error is not known)"
    return f"A_r {bem.grid_error:.2%} from the finest grid solved"


def _range_resolution_text(bem: BemReference) -> str:
    """Whether the h_0 / 2 solve resolved its cohesive zone (else the range part is a lower
    bound)."""
    note = getattr(bem, "range_sensitivity_note", None) or ""
    if getattr(bem, "range_sensitivity_resolved", None):
        return f"h_0 / 2 with its cohesive zone resolved{': ' + note if note else ''}"
    return (
        "a lower bound: at h_0 / 2 the cohesive zone spans fewer elements than the rule asks"
        f"{': ' + note if note else ''}"
    )


def pixel_size_text(surface: LevelledSurface) -> str:
    """``"10 µm pixels"``, or ``"127.7 x 314.6 nm pixels (dx x dy)"`` when dy differs."""
    if np.isclose(surface.dx, surface.dy, rtol=1e-9, atol=0.0):
        return f"{format_quantity(surface.dx, 'm')} pixels"
    unit = text_unit([surface.dx, surface.dy], "m")
    dx, dy = (format_number(unit(d)) for d in (surface.dx, surface.dy))
    return f"{dx} x {dy} {unit.text} pixels (dx x dy)"


#: Key-number rows the verdict judges (marked under an invalid one: :func:`mark`).
JUDGED_KEYS: tuple[str, ...] = (
    "effective resolution",
    "summit",
    "asperity",
    "rms summit",
    "Tabor",
    "misfit",
    "mode mixity lambda",  # fitted, or configured with what a decade of it does to F_s
    "shear BEM, model over BEM",
)


def key_numbers(result: Run) -> list[tuple[str, str]]:
    """(quantity, value with unit) rows of the report's headline table (the full-contact
    limit's when the job stopped where its verdict was known: :mod:`.early`): the surface and
    the statistics at the effective resolution, lambda, the BEM, the PSD, the error bars, the
    profiles and the quadrature, each number with the digits its uncertainty supports
    (:mod:`~asperity.pipelines.report.numbers`); the rows the verdict judges marked by it."""
    if is_early(result):
        return early_key_numbers(result, pixel_size_text(result.surface))
    fr = result.friction
    rows = roughness_key_numbers(result) + [mode_mixity_key_number(result)]
    rows += shape_scale_key_numbers(result)
    rows += bem_key_numbers(result)
    rows += psd_key_numbers(result)
    rows += uncertainty_rows(result)
    rows += profile_key_numbers(result)
    rows += shear_key_numbers(result)
    rows += [
        ("statmodel quadrature", fr.quadrature_reason),
        ("shear curves converged", f"{int(np.sum(fr.converged))} / {fr.converged.size}"),
    ]
    verdict = getattr(result, "verdict", None)
    rows = [(k, mark(v, verdict) if k.startswith(JUDGED_KEYS) else v) for k, v in rows]
    return [(plain_text(k), plain_text(v)) for k, v in rows]


def roughness_key_numbers(result: Run) -> list[tuple[str, str]]:
    """The surface, the effective resolution, the summit statistics (R, m; eta, 1/m^2;
    sigma_s, m) and the Tabor parameter at it, and the misfit there."""
    res = result.statistical_model
    r = res.roughness
    return [
        (
            "surface",
            f"{result.surface.nx} x {result.surface.ny} px, {pixel_size_text(result.surface)}",
        ),
        ("effective resolution", f"{resolution_text(res)}; chosen against {res.basis}"),
        ("summit radius R", format_quantity(r.summit_radius, "m")),
        ("asperity density eta", format_quantity(r.asperity_density, "m", power=-2)),
        ("rms summit height sigma_s", format_quantity(r.summit_height_rms, "m")),
        ("Tabor parameter mu", format_number(res.tabor_parameter)),
        ("misfit at effective resolution", misfit_text(res)),
    ]


def mode_mixity_key_number(result: Run) -> tuple[str, str]:
    """lambda fitted (with its u, residual and points; the interval united with the
    roughness's shift where computed), or configured (:func:`assumed_lambda_text`)."""
    lam = result.mode_mixity
    if not lam.fitted:
        return ("mode mixity lambda (configured)", assumed_lambda_text(result))
    shift = getattr(lam, "mode_mixity_roughness_shift", None)
    united = (
        ""
        if shift is None
        else f"; interval {format_number(lam.interval_low)}..{format_number(lam.interval_high)}"
        ": the profile's united with lambda fitted at the resolution interval's ends "
        f"({format_number(shift[0])}, {format_number(shift[1])})"
    )
    return (
        "mode mixity lambda (fitted)",
        f"{format_number(lam.mode_mixity, lam.mode_mixity_std)} "
        f"(rms relative residual {lam.residual_rms:.3g}, {lam.n_points} points{united})",
    )


def bem_key_numbers(result: Run) -> list[tuple[str, str]]:
    """The BEM's grid (stride, pixel m, its discretisation error, boundary), its solves
    converged and its adhesive law's rows (:func:`adhesion_key_numbers`); one row when the
    BEM was not run."""
    bem = result.bem_reference
    if bem is None:
        return [("BEM", "not run ([bem] enabled = false): calibrated on the measurement")]
    rows = [
        (
            "BEM grid",
            f"stride {bem.stride} ({format_quantity(bem.dx, 'm')}), {_grid_error_text(bem)}; "
            f"{bem.boundary} boundary",
        ),
        ("BEM solves converged", f"{int(np.sum(bem.converged))} / {bem.converged.size}"),
    ]
    return rows + adhesion_key_numbers(result)


#: Key numbers shown first (report.html's "Key numbers"), shortened to their value.
HEADLINE_KEYS: tuple[str, ...] = (
    "surface",
    "summit radius R",
    "asperity density eta",
    "rms summit height sigma_s",
    "Tabor parameter mu",
)


def headline_numbers(result: Run) -> list[tuple[str, str]]:
    """The few numbers a reader wants first, each short (the full rows, with how each was
    found, are :func:`key_numbers`): the surface, the effective resolution and its interval,
    R, eta, sigma_s, the Tabor parameter, lambda, and at the lightest and heaviest loads the
    friction coefficient mu_s = F_s/F_z and the area drop A_r(peak)/A_r(0) (Fig 13)."""
    if is_early(result):
        return early_key_numbers(result, pixel_size_text(result.surface))
    rows = dict(key_numbers(result))
    verdict = getattr(result, "verdict", None)
    res, lam, fr = result.statistical_model, result.mode_mixity, result.friction
    where = format_quantity(res.effective_resolution, "m")
    interval = getattr(res, "optimum_interval", None)
    if interval is not None and np.all(np.isfinite(interval)):
        unit = text_unit(interval, "m")
        finer, coarser = (format_number(unit(end)) for end in interval)
        where += f" (interval {finer}..{coarser} {unit.text})"
    out = [("surface", rows["surface"]), ("effective resolution", mark(where, verdict))]
    out += [(k, rows[k]) for k in HEADLINE_KEYS[1:] if k in rows]
    if lam.fitted:
        out.append(
            (
                "mode mixity lambda",
                mark(format_number(lam.mode_mixity, lam.mode_mixity_std), verdict),
            )
        )
    else:
        assumed = f"{format_number(lam.mode_mixity)} (assumed, not fitted)"
        out.append(("mode mixity lambda", mark(assumed, verdict)))
    low = bool(getattr(fr, "uncertainty_lower_bound", False))
    mu_u = fr.static_friction_coefficient_uncertainty
    ends = list(dict.fromkeys([int(np.argmin(fr.normal_load)), int(np.argmax(fr.normal_load))]))
    load = text_unit(fr.normal_load, "N")
    at = {i: f"at {format_number(load(fr.normal_load[i]))} {load.text}" for i in ends}
    mu = [
        f"{plus_minus(fr.static_friction_coefficient[i], _at(mu_u, i), 1.0, low)} {at[i]}"
        for i in ends
    ]
    drop = [f"{format_number(fr.real_area_drop[i])} {at[i]}" for i in ends]
    out += [
        ("friction coefficient mu_s = F_s/F_z", mark("; ".join(mu), verdict)),
        ("area drop A_r(static peak)/A_r(0)", mark("; ".join(drop), verdict)),
    ]
    return [(plain_text(k), plain_text(v)) for k, v in out]


def assumed_lambda_text(result: Run) -> str:
    """The configured lambda, said to be assumed, and what a decade of it does to the static
    friction at the lightest and heaviest loads (the friction stage's
    ``static_friction_mode_mixity_decade``), each number in the form the load table writes it
    (the configured lambda's F_s with its u: :func:`decade_forces`)."""
    lam, fr = result.mode_mixity, result.friction
    text = (
        f"{format_number(lam.mode_mixity)}, assumed: no measured A_r(F_x) curves, so lambda is "
        "not fitted, carries no uncertainty and the error bars leave it out"
    )
    if getattr(fr, "static_friction_mode_mixity_decade", None) is None:
        return text
    low, high = fr.mode_mixity_decade
    force = text_unit([fr.static_friction, fr.sliding_friction], "N")
    ends = [int(np.argmin(fr.normal_load)), int(np.argmax(fr.normal_load))]
    moves = "; ".join(
        f"F_s({format_quantity(fr.normal_load[i], 'N')}) = "
        f"{' / '.join(decade_forces(result, i, force))} {force.text}"
        for i in dict.fromkeys(ends)
    )
    lambdas = " / ".join(format_number(v) for v in (low, lam.mode_mixity, high))
    return f"{text}; a decade of lambda ({lambdas}): {moves}"


def decade_forces(result: Run, i: int, force: DisplayUnit) -> tuple[str, str, str]:
    """Load ``i``'s static friction at lambda / sqrt(10), at the configured lambda (with its
    u, as the load table's "static F_s" cell) and at lambda x sqrt(10), in ``force``'s unit;
    the decade's ends carry no u of their own (4 significant digits)."""
    fr = result.friction
    decade = fr.static_friction_mode_mixity_decade
    low = bool(getattr(fr, "uncertainty_lower_bound", False))
    u = _at(getattr(fr, "static_friction_uncertainty", None), i)
    configured = plus_minus(fr.static_friction[i], u, force.factor, low)  # = model_cells'
    return format_number(force(decade[0, i])), configured, format_number(force(decade[1, i]))


def adhesion_key_numbers(result: Run) -> list[tuple[str, str]]:
    """Rows of the adhesive BEM's law and range, the non-adhesive pair's resolution, and the
    adhesion regime (Persson-Tosatti, Pastewka-Robbins, Tabor); empty where not run."""
    bem, res = result.bem_reference, result.statistical_model
    rows = []
    law = getattr(bem, "adhesion", None)
    if law == "maugis":
        rows.append(("BEM adhesion", f"Maugis-Dugdale (adhesive on loading); {bem.range_rule}"))
        spread = bem.range_sensitivity
        rows.append(
            (
                "BEM range uncertainty",
                f"A_r/A_n {format_uncertainty(bem.area_range_uncertainty)} (half spread over "
                "h_0/2, h_0, "
                f"2 h_0: {spread[0]:.4g}, {spread[1]:.4g}, {spread[2]:.4g} at "
                f"{bem.check_load:.4g} N; {_range_resolution_text(bem)})",
            )
        )
    elif law == "pohrt-popov":
        rows.append(("BEM adhesion", "Pohrt-Popov (Appendix B): no adhesion on loading"))
    rows += bem_law_key_numbers(res, bem)
    index = getattr(res, "effective_index_non_adhesive", None)
    if index is not None:
        rows.append(
            (
                "effective resolution, non-adhesive pair",
                f"{format_quantity(res.resolution[index], 'm')} (w=0 model against the "
                "non-adhesive "
                f"BEM, misfit {res.misfit_bem_non_adhesive[index]:.3g}; not used: the "
                "adhesive pair chooses)",
            )
        )
    rows += gain_key_numbers(result)
    return rows + regime_key_numbers(getattr(result, "verdict", None))


def _gain_text(gain: np.ndarray) -> str:
    """Relative gains (1) as ``+a .. +b %`` over the loads."""
    gain = np.asarray(gain, dtype=float) * 100
    if not np.isfinite(gain).any():
        return "?"
    low, high = float(np.nanmin(gain)), float(np.nanmax(gain))
    return f"{low:+.3g} %" if np.isclose(low, high, rtol=0.05) else f"{low:+.3g} .. {high:+.3g} %"


def adhesive_gains(result: Run) -> dict[str, np.ndarray] | None:
    """The adhesive gains over the non-adhesive partner per load (1) at the effective
    resolution: the BEM's (adhesive / non-adhesive - 1), the model's under the BEM's law
    (Maugis-Dugdale / Greenwood-Williamson - 1) and the JKR model's (JKR / GW - 1); None
    without the pairs."""
    res, bem, fr = result.statistical_model, result.bem_reference, result.friction
    plain = getattr(res, "effective_real_area_non_adhesive", None)
    if bem is None or plain is None or bem.contact_fraction_adhesive is None:
        return None
    jkr = getattr(fr, "model_real_area", None)
    if jkr is None:
        jkr = getattr(res, "optimum_real_area", None)
    out = {
        "bem": np.asarray(bem.contact_fraction_adhesive) / np.asarray(bem.contact_fraction) - 1,
        "model": np.asarray(res.effective_real_area_bem_law) / plain - 1,
    }
    if jkr is not None:
        out["jkr"] = np.asarray(jkr) / plain - 1
    return out


def bem_law_key_numbers(res: object, bem: BemReference | None) -> list[tuple[str, str]]:
    """Rows of the like-for-like calibration: the model's law paired with the BEM, the
    adhesive gains at the effective resolution, the BEM's Maugis parameter beside the JKR
    model's Tabor parameter and what follows (empty without a BEM)."""
    law = getattr(res, "bem_law", None)
    if law is None:
        return []
    if law == "maugis-dugdale":
        h0 = res.bem_law_adhesion_range
        pair = (
            f"Maugis-Dugdale statistical model at the BEM's h_0 = {format_quantity(h0, 'm')} "
            "(sigma_0 = "
            "w / h_0) against the Maugis-Dugdale BEM; Greenwood-Williamson against the "
            "non-adhesive BEM; the JKR/PC model makes the predictions at that resolution"
        )
    else:
        pair = (
            "Greenwood-Williamson (w = 0) against the BEM (its loading branch carries no "
            "adhesion); the JKR/PC model makes the predictions at that resolution"
        )
    rows = [("calibration pair (like for like)", pair)]
    return rows


def gain_key_numbers(result: Run) -> list[tuple[str, str]]:
    """The adhesive gains at the effective resolution and the regime statement."""
    res = result.statistical_model
    rows = []
    gains = adhesive_gains(result)
    if gains is not None:
        text = (
            f"BEM {_gain_text(gains['bem'])}; model under the BEM's law "
            f"{_gain_text(gains['model'])}"
        )
        if "jkr" in gains:
            text += f"; JKR model (predictions) {_gain_text(gains['jkr'])}"
        rows.append(("adhesive gain over non-adhesive at the effective resolution", text))
    lam = getattr(res, "maugis_parameter", None)
    if lam is not None:
        rows.append(
            (
                "BEM Maugis parameter / model Tabor parameter",
                f"lambda = {format_number(lam)} / mu = {format_number(res.tabor_parameter)} at R = "
                f"{format_quantity(res.summit_radius, 'm')}: {res.adhesion_statement}",
            )
        )
    return rows


def regime_key_numbers(verdict: Verdict) -> list[tuple[str, str]]:
    """The adhesion regime's row (empty without one): U_el/(A0 w) and S_PR as the verdict's
    preview line before the BEM writes them (3 significant digits), the Tabor parameter as
    its key row (4)."""
    ratio = getattr(verdict, "adhesion_energy_ratio", None)
    if ratio is None:
        return []
    full = "full contact expected" if ratio < 1 else "partial contact"
    return [
        (
            "adhesion regime",
            f"U_el/(A0 w) = {ratio:.3g} ({full}; Persson-Tosatti, threshold 1); "
            f"stickiness S_PR = {verdict.stickiness:.3g} (Pastewka-Robbins, sticky below 1); "
            f"Tabor mu = {format_number(verdict.regime_tabor_parameter)}",  # as its key row
        )
    ]


def hurst_text(slope_hurst: float) -> str:
    """The PSD slope's H = -exponent/2 - 1, called a Hurst exponent only inside (0, 1)."""
    if not math.isfinite(slope_hurst) or 0 < slope_hurst < 1:
        return f"{slope_hurst:.3g}"
    estimate = topo.hurst_from_psd_exponent(-2.0 * (slope_hurst + 1.0), warn=False)
    return f"none: {estimate.validity_notes[0]}"


def slope_hurst(psd: object) -> float:
    """The PSD fit's ``-psd_fit_exponent/2 - 1``, whatever its range (``psd.hurst_exponent``
    is NaN outside (0, 1); a results.h5 of asperity <= 0.4.2 holds it there unflagged)."""
    return float(-float(psd.psd_fit_exponent) / 2 - 1)


def psd_key_numbers(result: Run) -> list[tuple[str, str]]:
    """Rows of the PSD stage (empty when the result has none)."""
    psd = getattr(result, "psd", None)
    if psd is None:
        return []
    return [
        ("PSD roll-off wavelength", format_quantity(psd.rolloff_wavelength, "m")),
        ("Hurst exponent H (PSD above roll-off)", hurst_text(slope_hurst(psd))),
        (
            "effective Nyquist wavelength 2x",
            format_quantity(psd.effective_nyquist_wavelength, "m"),
        ),
        ("rms slope h' (Persson)", format_number(psd.persson_rms_slope)),
    ]


def load_table(result: Run) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the per-load table: F_z; the BEM's A_r/A_n; the model's A_r/A_n at
    F_x = 0, static friction F_s, mu_s = F_s/F_z, A_r/A_n at the static peak and the area drop
    A_r(peak)/A_r(0) (:mod:`~asperity.pipelines.report.static_peak`), sliding friction and
    displacement; with measured A_r(F_x) curves their F_s, A_r/A_n at the peak and drop;
    Persson's A_r/A_n and the like-for-like partners. Forces and lengths in the unit named in
    each header (N unless the column's values call for a prefix), every number with the digits
    its uncertainty supports. A job stopped where its verdict was known: the full-contact
    limit's table (:func:`.early.early_load_table`)."""
    if is_early(result):
        return early_load_table(result)
    fr, bem = result.friction, result.bem_reference
    verdict = getattr(result, "verdict", None)
    low = bool(getattr(fr, "uncertainty_lower_bound", False))
    a_n = fr.nominal_area
    load_unit = text_unit(fr.normal_load, "N")
    force = text_unit([fr.static_friction, fr.sliding_friction], "N")
    length = text_unit(fr.sliding_displacement, "m")
    measured = measured_peaks(result)
    header = [
        f"F_z ({load_unit.text})",
        "A_r/A_n BEM",
        "A_r/A_n BEM adh.",
        "A_r/A_n model",
        f"static F_s ({force.text})",
        "mu_s = F_s/F_z",
        "A_r/A_n at static peak",
        "A_r drop peak/0",
        f"sliding F_x ({force.text})",
        f"delta_T slide ({length.text})",
    ]
    if measured:
        header += [
            f"measured F_s ({force.text})",
            "measured A_r/A_n at peak",
            "measured A_r drop",
        ]
    persson = persson_fraction(result)
    if persson is not None:
        header.append("A_r/A_n Persson")
    mu_u = fr.static_friction_coefficient_uncertainty
    rows = []
    for i, f in enumerate(fr.normal_load):
        area, static, sliding, slide = model_cells(result, i, force.factor, length.factor)
        peak = [
            plus_minus(fr.static_friction_coefficient[i], _at(mu_u, i), 1.0, low),
            format_number(fr.static_peak_real_area[i] / a_n),
            format_number(fr.real_area_drop[i]),
        ]
        model = [mark(c, verdict) for c in (area, static, *peak, sliding, slide)]
        adh = bem_cells(bem, i)
        row = [format_number(load_unit(f)), adh[0], mark_adhesive_bem(adh[1], verdict), *model]
        if measured:
            row += measured_cells(measured.get(i), force, a_n)
        if persson is not None:
            row.append(format_number(persson[i]))
        rows.append(row)
    header, rows = decade_column(result, *non_adhesive_column(result, header, rows))
    return [plain_text(h) for h in header], [[plain_text(c) for c in row] for row in rows]


def _at(values: np.ndarray | None, i: int) -> float | None:
    return None if values is None else float(np.asarray(values)[i])


def measured_cells(peak: MeasuredPeak | None, force: DisplayUnit, a_n: float) -> list[str]:
    """The measured curve's F_s (``>= F`` when the curve ends on its largest F_x), A_r/A_n at
    it and the drop +- u from the stick branch's fit; "-" without a curve at that load."""
    if peak is None:
        return ["-", "-", "-"]
    fs = format_number(force(peak.static_friction))
    return [
        f">= {fs}" if peak.ends_rising else fs,
        format_number(peak.peak_real_area / a_n),
        plus_minus(peak.real_area_drop, _finite_or_none(peak.real_area_drop_uncertainty)),
    ]


def _finite_or_none(value: float) -> float | None:
    return float(value) if math.isfinite(value) else None


def decade_column(
    result: Run, header: list[str], rows: list[list[str]]
) -> tuple[list[str], list[list[str]]]:
    """With an assumed lambda, the static friction at lambda / sqrt(10) and x sqrt(10) per load
    (what a decade of the unfitted lambda does; not an error bar)."""
    fr = result.friction
    decade = getattr(fr, "static_friction_mode_mixity_decade", None)
    if decade is None:
        return header, rows
    low, high = fr.mode_mixity_decade
    force = text_unit([fr.static_friction, fr.sliding_friction], "N")
    name = (
        f"static F_s at lambda {format_number(low)} .. {format_number(high)} "
        f"({force.text}, lambda assumed)"
    )
    verdict = getattr(result, "verdict", None)
    cells = []
    for i in range(decade.shape[1]):
        at_low, _, at_high = decade_forces(result, i, force)
        cells.append(mark(f"{at_low} .. {at_high}", verdict))
    return [*header, name], [[*row, cell] for row, cell in zip(rows, cells, strict=True)]


def non_adhesive_column(
    result: Run, header: list[str], rows: list[list[str]]
) -> tuple[list[str], list[list[str]]]:
    """The load table with the like-for-like partners at the effective resolution appended:
    Greenwood-Williamson (w = 0; partner of "A_r/A_n BEM") and, with a Maugis-Dugdale BEM,
    the Maugis-Dugdale model (partner of "A_r/A_n BEM adh."); "A_r/A_n model" is the JKR
    model that makes the predictions. Without them (a run stored before), the w = 0 model at
    the non-adhesive pair's least-misfit stride."""
    res = result.statistical_model
    verdict = getattr(result, "verdict", None)
    columns: list[tuple[str, np.ndarray]] = []
    plain = getattr(res, "effective_real_area_non_adhesive", None)
    at = f"{res.effective_resolution * 1e6:.4g} um"
    if plain is not None:
        columns.append((f"A_r/A_n model w=0 (GW, {at})", plain / res.nominal_area))
        if getattr(res, "bem_law", None) == "maugis-dugdale":
            md = res.effective_real_area_bem_law / res.nominal_area
            columns.append((f"A_r/A_n model MD (BEM's law, {at})", md))
    else:
        index = getattr(res, "effective_index_non_adhesive", None)
        if index is None or res.real_area_non_adhesive is None:
            return header, rows
        fraction = res.real_area_non_adhesive[index] / res.nominal_area
        columns.append((f"A_r/A_n model w=0 ({res.resolution[index] * 1e6:.3g} um)", fraction))
    header = [*header, *(name for name, _ in columns)]
    rows = [
        [*row, *(mark(f"{values[i]:.4g}", verdict) for _, values in columns)]
        for i, row in enumerate(rows)
    ]
    return header, rows


def surface_section(result: Run) -> list[str]:
    """The report's "Surface" section: how the map was prepared, with its warnings."""
    surface = result.surface
    record = getattr(surface, "preparation", None) or {}
    rows = [
        ["grid", f"{surface.nx} x {surface.ny} px"],
        [
            "pixel size dx, dy",
            f"{format_quantity(surface.dx, 'm')}, {format_quantity(surface.dy, 'm')}",
        ],
    ]
    if record:
        ratio = record.get("form_to_roughness")
        rows += [
            ["crop", crop_text(record.get("crop"))],
            ["levelling (form removed)", str(record.get("levelling"))],
            ["form-to-roughness rms ratio", "-" if ratio is None else f"{ratio:.3g}"],
            [
                "missing pixels",
                f"{record['n_missing']} ({100 * record['missing_fraction']:.3g} %), policy "
                f"{record['missing_policy']}; {record['n_filled']} filled",
            ],
            [
                "outliers changed",
                f"{record['n_outliers']} ({100 * record['outlier_fraction']:.3g} % of the valid "
                f"pixels, {record['outlier_action']}): {record['outlier_rule']}",
            ],
            ["rms roughness after preparation", format_quantity(record["roughness_rms"], "m")],
        ]
    rows = [[key, value.replace("|", "\\|")] for key, value in rows]  # a pipe ends a cell
    lines = ["## Surface", "", _md_table(["step", "value"], rows), ""]
    warnings = record.get("warnings") or []
    lines += [f"- **Warning:** {w}" for w in warnings]
    return [*lines, ""] if warnings else lines


def crop_text(crop: object) -> str:
    """The crop window ``[x0, x1, y0, y1]`` (pixels) in words; "none" without one."""
    if not crop:
        return "none"
    if isinstance(crop, list | tuple) and len(crop) == 4:
        x0, x1, y0, y1 = crop
        return f"pixels x {x0}..{x1}, y {y0}..{y1}"
    return str(crop)


def _md_table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _source(result: Run) -> str:
    """Where the configuration came from (a job's config, or a reopened file's record)."""
    config = getattr(result, "config", None)
    return config.source if config is not None else getattr(result, "source", "results.h5")


#: Figure name -> caption in report.md and report.html.
CAPTIONS: dict[str, str] = {
    "surface": f"Stage {stage_number('surface')}: levelled surface.",
    "resolution": "Fig 12: summit statistics against resolution (a-c) and A_r/A_n against "
    "F_z (d). Persson's theory (dash-dot) is non-adhesive: a lower bound.",
    "misfit": f"Stage {stage_number('statistical_model')}: misfit of the statistical model "
    "against resolution.",
    "bem_grid": f"Stage {stage_number('bem_reference')}: BEM grid refinement (A_r/A_n and its "
    "error against the finest grid solved) and contact at the largest load.",
    "lambda_fit": f"Stage {stage_number('mode_mixity')}: lambda fit.",
    "lambda_residuals": f"Stage {stage_number('mode_mixity')}: measured minus fitted A_r at each "
    "load (the points fitted: trimmed after the first static peak, repeated points merged).",
    "shear": "Fig 4: shear response at the heaviest load, with stick and slip parts.",
    "area_vs_force": "Fig 13: A_r/A_n against F_x (dashed: model; dotted: constant shear "
    "strength).",
    "friction_vs_load": "Static and sliding friction against normal load.",
    "psd": f"Stage {stage_number('psd')}: radially averaged PSD with the roll-off, the power-law "
    "(Hurst) fit and "
    "the Nyquist wavenumbers of the map and of the effective resolution.",
    **SHEAR_CAPTIONS,
    **FRICTION_TEST_CAPTIONS,
}


def refusals_section(result: Run) -> list[str]:
    """Markdown lines listing the resolutions where the statistical model gave no value."""
    messages = list(getattr(result.statistical_model, "messages", None) or [])
    if not messages:
        return []
    return [
        "## Statistical model refusals",
        "",
        "No value at these resolutions (NaN in `results.h5`, group `statistical_model`):",
        "",
        *(f"- {m}" for m in messages),
        "",
    ]


def summary_text(result: Run) -> str:
    """The one-screen terminal summary."""
    lines = ["asperity run: summary", ""]
    if getattr(result, "verdict", None) is not None:
        lines += [*verdict_lines(result.verdict), ""]
    limit = limit_lines(getattr(result, "verdict", None))
    lines += [*(f"  {line}" for line in limit), *([""] if limit else [])]
    width = max(len(k) for k, _ in key_numbers(result))
    for key, value in key_numbers(result):
        lines.append(f"  {key:<{width}}  {value}")
    header, rows = load_table(result)
    widths = [max(len(h), *(len(r[j]) for r in rows)) for j, h in enumerate(header)]
    lines += ["", "  " + "  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True))]
    for row in rows:
        lines.append("  " + "  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)))
    computed = sum(s.seconds for s in result.stages if not s.cached)
    cached = [s.name for s in result.stages if s.cached]
    lines += [
        "",
        f"  stages computed in {computed:.1f} s"
        + (f"; stored stages skipped: {', '.join(cached)}" if cached else "")
        + f"; total {result.total_seconds:.1f} s",
    ]
    if getattr(result, "verdict", None) is None:
        lines += [f"  WARNING: {note}" for note in result.statistical_model.validity]
    for note in [] if result.bem_reference is None else result.bem_reference.warnings:
        lines.append(f"  WARNING: {note}")
    problems = result.problems()
    if problems:
        lines.append("  NOT CONVERGED:")
        lines += [f"    {p}" for p in problems[:8]]
    lines = [plain_text(line) for line in lines]  # the outputs' paths below stay as they are
    out = result.out_dir
    lines.append(
        f"  outputs: {out / 'results.h5'}, {out / 'report.md'}, {out / 'report.html'} and the "
        f"figures in {out} (each with its data as CSV)"
    )
    return "\n".join(lines)


#: How a stage's status reads in the report's stage table.
STAGE_STATUS_WORDS = {
    "stored": "stored (skipped)",
    "computed": "computed",
    "disabled": "disabled",
    "skipped": "not computed",
}


def _stage_rows(result: Run) -> list[list[str]]:
    """The stage table's rows: name, status in words (with its note), seconds."""
    return [
        [
            s.name,
            STAGE_STATUS_WORDS.get(s.status, s.status) + (f" ({s.note})" if s.note else ""),
            f"{s.seconds:.2f}",
        ]
        for s in result.stages
    ]


def report_markdown(result: Run, figures: dict[str, Path]) -> str:
    """The text of ``report.md``: verdict, key numbers, per-load table, sections, stage table
    and the figures ``figures`` ({name: written file}) with their captions."""
    header, rows = load_table(result)
    stage_rows = _stage_rows(result)
    problems = result.problems()
    verdict = getattr(result, "verdict", None)
    text = [
        "# asperity run report",
        "",
        *([] if verdict is None else verdict_markdown(verdict)),
        f"Configuration: `{_source(result)}`; input SHA-256 `{result.input_sha256[:16]}...`;"
        " all data in `results.h5` (SI units).",
        "",
        "## Key numbers",
        "",
        _md_table(["quantity", "value"], [list(r) for r in key_numbers(result)]),
        "",
        "## Per normal load",
        "",
        _md_table(header, rows),
        "",
        *early_markdown(result),
        *surface_section(result),
        *profile_section(result),
        *bem_section(result),
        *(plain_text(line) for line in shear_section(result)),
        *(plain_text(line) for line in friction_tests_section(result)),
        "## Validity",
        "",
        f"**{verdict_wording(verdict)}** (reasons at the top)."
        if verdict is not None
        else "The statistical model is within its assumptions."
        if not result.statistical_model.validity
        else "\n".join(f"- **Warning:** {note}" for note in result.statistical_model.validity),
        "",
        *refusals_section(result),
        "## Convergence",
        "",
        "All solvers converged."
        if not problems
        else "**Not converged:**\n\n" + "\n".join(f"- {p}" for p in problems),
        "",
        "## Stages",
        "",
        _md_table(["stage", "status", "seconds"], stage_rows),
        "",
        "## Figures",
        "",
    ]
    for name, path in figures.items():
        text += [f"![{CAPTIONS[name]}]({path.name})", "", f"*{CAPTIONS[name]}*", ""]
    # every line in words and one spelling of micro; the configuration's path as it is
    return "\n".join(t if t.startswith("Configuration:") else plain_text(t) for t in text)
