"""statmodel: the single-asperity adhesive friction laws and the statistical rough-contact model.

Xu, Scheibert, Gadegaard and Mulvihill's model (the paper's Sections 2-4): JKR (E:JKR_indent,
E:JKR_load), Papangelo-Ciavarella under shear (E:PC_indent..E:PC_T), Hertz sliding
(E:Hertz_theory), the status map (Fig. 2a), Greenwood's preload (E:Fy_Greenwood, E:Ar_Greenwood)
and the tangential loading up to full sliding (E:NewFormulation_Fy/Fx/Ar). SI units throughout.

Typical use::

    from statmodel import Material, Roughness, shear_curve
    mat = Material(e_star=2.133e6, work_of_adhesion=0.040, mode_mixity=0.2, shear_strength=0.13e6)
    rough = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
    curve = shear_curve(mat, rough, 700e-6, 3.1, numpy.linspace(0.0, 14e-6, 281))
    curve.static_friction, curve.sliding_friction  # N
"""

from statmodel.hertz import hertz_contact_radius, hertz_normal_load, hertz_sliding_tangential_load
from statmodel.jkr import (
    jkr_contact_radius,
    jkr_jump_in_distance,
    jkr_jump_off_distance,
    jkr_normal_load,
    jkr_pull_off_force_fixed_grip,
    jkr_pull_off_force_load_control,
)
from statmodel.options import QuadratureOptions
from statmodel.papangelo_ciavarella import (
    pc_contact_radius,
    pc_fold_radius,
    pc_max_tangential_displacement,
    pc_min_indentation,
    pc_normal_load,
    pc_tangential_load,
)
from statmodel.parameters import Material, Roughness, TaborWarning, tabor_parameter
from statmodel.preload import PreloadResult, preload, pull_off_force, real_area_at_loads
from statmodel.shear import ShearCurve, shear_curve, shear_curve_fixed_separation
from statmodel.status_map import (
    OUT_OF_CONTACT,
    SLIDE,
    STICK,
    asperity_status,
    dimensionless_unstable_boundary,
)

__all__ = [
    "OUT_OF_CONTACT",
    "SLIDE",
    "STICK",
    "Material",
    "PreloadResult",
    "QuadratureOptions",
    "Roughness",
    "ShearCurve",
    "TaborWarning",
    "asperity_status",
    "dimensionless_unstable_boundary",
    "hertz_contact_radius",
    "hertz_normal_load",
    "hertz_sliding_tangential_load",
    "jkr_contact_radius",
    "jkr_jump_in_distance",
    "jkr_jump_off_distance",
    "jkr_normal_load",
    "jkr_pull_off_force_fixed_grip",
    "jkr_pull_off_force_load_control",
    "pc_contact_radius",
    "pc_fold_radius",
    "pc_max_tangential_displacement",
    "pc_min_indentation",
    "pc_normal_load",
    "pc_tangential_load",
    "preload",
    "pull_off_force",
    "real_area_at_loads",
    "shear_curve",
    "shear_curve_fixed_separation",
    "tabor_parameter",
]
