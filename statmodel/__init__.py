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

import lazy_loader

# The public names are the imports in __init__.pyi (also what type checkers read); each is
# imported on first use, so that `asperity --help` and light sub-commands load no numba kernel.
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
