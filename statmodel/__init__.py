"""statmodel: the single-asperity adhesive friction laws and the statistical rough-contact model.

Xu, Scheibert, Gadegaard and Mulvihill's model (the paper's Sections 2-4): JKR (E:JKR_indent,
E:JKR_load), Papangelo-Ciavarella under shear (E:PC_indent..E:PC_T), Hertz sliding
(E:Hertz_theory), the status map (Fig. 2a), Greenwood's preload (E:Fy_Greenwood, E:Ar_Greenwood)
and the tangential loading up to full sliding (E:NewFormulation_Fy/Fx/Ar). SI units throughout.

Typical use::

    from asperity.statmodel import Material, Roughness, shear_curve
    mat = Material(e_star=2.133e6, work_of_adhesion=0.040, mode_mixity=0.2, shear_strength=0.13e6)
    rough = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
    curve = shear_curve(mat, rough, 700e-6, 3.1, numpy.linspace(0.0, 14e-6, 281))
    curve.static_friction, curve.sliding_friction  # N
"""

from __future__ import annotations

import importlib
from typing import Any

# Public names and the module that defines each; imported on first use so that
# `asperity --help` and light sub-commands do not load numba kernels they never call.
_EXPORTS: dict[str, str] = {
    "AdhesionRegime": "asperity.statmodel.regimes",
    "FULL_CONTACT_MEANING": "asperity.statmodel.regimes",
    "FULL_CONTACT_REASON": "asperity.statmodel.regimes",
    "FlatteningEnergy": "asperity.statmodel.regimes",
    "adhesion_regime": "asperity.statmodel.regimes",
    "flattening_energy": "asperity.statmodel.regimes",
    "full_contact_check": "asperity.statmodel.regimes",
    "pastewka_robbins_range_ratio": "asperity.statmodel.regimes",
    "pastewka_robbins_stickiness": "asperity.statmodel.regimes",
    "Check": "asperity.statmodel.checks",
    "contact_pressure_check": "asperity.statmodel.plausibility",
    "junction_shear_check": "asperity.statmodel.plausibility",
    "plasticity_index": "asperity.statmodel.plausibility",
    "plasticity_index_check": "asperity.statmodel.plausibility",
    "static_to_sliding_check": "asperity.statmodel.plausibility",
    "hertz_contact_radius": "asperity.statmodel.hertz",
    "hertz_normal_load": "asperity.statmodel.hertz",
    "hertz_sliding_tangential_load": "asperity.statmodel.hertz",
    "jkr_contact_radius": "asperity.statmodel.jkr",
    "jkr_jump_in_distance": "asperity.statmodel.jkr",
    "jkr_jump_off_distance": "asperity.statmodel.jkr",
    "jkr_normal_load": "asperity.statmodel.jkr",
    "jkr_pull_off_force_fixed_grip": "asperity.statmodel.jkr",
    "jkr_pull_off_force_load_control": "asperity.statmodel.jkr",
    "draw_shear_curve": "asperity.statmodel.figures",
    "QuadratureOptions": "asperity.statmodel.options",
    "pc_contact_radius": "asperity.statmodel.papangelo_ciavarella",
    "pc_fold_radius": "asperity.statmodel.papangelo_ciavarella",
    "pc_max_tangential_displacement": "asperity.statmodel.papangelo_ciavarella",
    "pc_min_indentation": "asperity.statmodel.papangelo_ciavarella",
    "pc_normal_load": "asperity.statmodel.papangelo_ciavarella",
    "pc_tangential_load": "asperity.statmodel.papangelo_ciavarella",
    "KAPPA_PERSSON": "asperity.statmodel.persson",
    "PerssonResult": "asperity.statmodel.persson",
    "persson_contact_fraction": "asperity.statmodel.persson",
    "persson_psd": "asperity.statmodel.persson",
    "persson_real_area": "asperity.statmodel.persson",
    "persson_small_load_fraction": "asperity.statmodel.persson",
    "psd_rms_slope": "asperity.statmodel.persson",
    "Material": "asperity.statmodel.parameters",
    "Roughness": "asperity.statmodel.parameters",
    "TaborWarning": "asperity.statmodel.parameters",
    "tabor_parameter": "asperity.statmodel.parameters",
    "PreloadResult": "asperity.statmodel.preloading",
    "preload": "asperity.statmodel.preloading",
    "pull_off_force": "asperity.statmodel.preloading",
    "real_area_at_loads": "asperity.statmodel.preloading",
    "unloading_pull_off_force": "asperity.statmodel.preloading",
    "ShearCurve": "asperity.statmodel.shear",
    "shear_curve": "asperity.statmodel.shear",
    "shear_curve_fixed_separation": "asperity.statmodel.shear",
    "OUT_OF_CONTACT": "asperity.statmodel.status_map",
    "SLIDE": "asperity.statmodel.status_map",
    "STICK": "asperity.statmodel.status_map",
    "asperity_status": "asperity.statmodel.status_map",
    "dimensionless_unstable_boundary": "asperity.statmodel.status_map",
    "EffectiveResolution": "asperity.statmodel.effective_resolution",
    "locate_least_misfit": "asperity.statmodel.effective_resolution",
    "roughness_at_resolution": "asperity.statmodel.effective_resolution",
    "PredictionUncertainty": "asperity.statmodel.uncertainty",
    "propagate_to_predictions": "asperity.statmodel.uncertainty",
}

__all__ = [
    "FULL_CONTACT_MEANING",
    "FULL_CONTACT_REASON",
    "KAPPA_PERSSON",
    "OUT_OF_CONTACT",
    "SLIDE",
    "STICK",
    "AdhesionRegime",
    "Check",
    "FlatteningEnergy",
    "Material",
    "PerssonResult",
    "PreloadResult",
    "QuadratureOptions",
    "Roughness",
    "ShearCurve",
    "TaborWarning",
    "adhesion_regime",
    "asperity_status",
    "contact_pressure_check",
    "dimensionless_unstable_boundary",
    "draw_shear_curve",
    "flattening_energy",
    "full_contact_check",
    "hertz_contact_radius",
    "hertz_normal_load",
    "hertz_sliding_tangential_load",
    "jkr_contact_radius",
    "jkr_jump_in_distance",
    "jkr_jump_off_distance",
    "jkr_normal_load",
    "jkr_pull_off_force_fixed_grip",
    "jkr_pull_off_force_load_control",
    "junction_shear_check",
    "pastewka_robbins_range_ratio",
    "pastewka_robbins_stickiness",
    "pc_contact_radius",
    "pc_fold_radius",
    "pc_max_tangential_displacement",
    "pc_min_indentation",
    "pc_normal_load",
    "pc_tangential_load",
    "persson_contact_fraction",
    "persson_psd",
    "persson_real_area",
    "persson_small_load_fraction",
    "plasticity_index",
    "plasticity_index_check",
    "preload",
    "psd_rms_slope",
    "pull_off_force",
    "real_area_at_loads",
    "shear_curve",
    "shear_curve_fixed_separation",
    "static_to_sliding_check",
    "tabor_parameter",
    "unloading_pull_off_force",
    "EffectiveResolution",
    "locate_least_misfit",
    "roughness_at_resolution",
    "PredictionUncertainty",
    "propagate_to_predictions",
]


def __getattr__(name: str) -> Any:
    module_name = _EXPORTS.get(name)
    if module_name is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = importlib.import_module(module_name)
    value = module if module_name == f"{__name__}.{name}" else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
