"""
Fig. 4: a rough adhesive contact sheared up to full sliding
===========================================================

The statistical model (Sections 3-4 of the paper): asperities with a Gaussian height
distribution (rms summit height :math:`\\sigma_s`), all of radius :math:`R`, with
:math:`\\eta` summits per unit area, are first pressed to the normal load :math:`F_z`
(Greenwood's preload with JKR asperities: the preload normal force, Eq. 15,
``E:Fy_Greenwood``), then sheared at constant :math:`F_z` (the normal force, tangential force
and real contact area under shear, Eqs. 17-19: ``E:NewFormulation_Fy``,
``E:NewFormulation_Fx``, ``E:NewFormulation_Ar``). Each
asperity sticks (Papangelo-Ciavarella) until the status map sends it sliding or out of
contact; the tangential force :math:`F_x` peaks (static friction), then settles on the
all-sliding value (sliding friction) once every asperity slides.

Parameters of the paper's Fig. 4: :math:`w` = 40 mJ/m², :math:`\\lambda` = 0.2,
:math:`\\tau_0` = 0.13 MPa, :math:`E^*` = 2.133 MPa, :math:`F_z` = 3.1 N,
:math:`A_n` = 700 mm², :math:`\\eta` = 652.1 mm⁻², :math:`\\sigma_s` = 0.032 mm,
:math:`R` = 0.041 mm.
"""

import numpy as np

from asperity.statmodel import Material, Roughness, shear_curve

material = Material(
    e_star=2.133e6,  # Pa
    work_of_adhesion=0.040,  # J/m^2
    mode_mixity=0.2,  # lambda
    shear_strength=0.13e6,  # tau0, Pa
)
roughness = Roughness(
    asperity_density=652.1e6,  # 1/m^2
    summit_radius=0.041e-3,  # m
    summit_height_rms=0.032e-3,  # m
)
displacement = np.linspace(0.0, 14e-6, 281)  # delta_T, m
curve = shear_curve(material, roughness, 700e-6, 3.1, displacement)

# %%
# What the curve says
# -------------------
# The result reads like a ``scipy.optimize`` result: check ``success`` before using the
# numbers. The normal force stays at the imposed 3.1 N along the whole curve (the model solves
# for the separation at every step), and the real contact area drops as the asperities slide.
print(curve.message, "| success:", curve.success)
print(f"Tabor parameter mu = {curve.tabor_parameter:.0f}")
print(f"F_z along the curve: {curve.normal_force.min():.6f} .. {curve.normal_force.max():.6f} N")
print(
    f"static friction  = {curve.static_friction:.3f} N at {curve.static_displacement * 1e6:.2f} um"
)
print(f"sliding friction = {curve.sliding_friction:.3f} N (every asperity sliding)")
print(
    f"A_r/A_n: {100 * curve.real_area[0] / 700e-6:.2f} % at rest, "
    f"{100 * curve.real_area[-1] / 700e-6:.2f} % at {displacement[-1] * 1e6:g} um"
)
assert curve.success
assert np.allclose(curve.normal_force, 3.1, rtol=1e-9)
assert curve.static_friction > curve.sliding_friction

# %%
# The figure
# ----------
# :func:`asperity.statmodel.draw_shear_curve` draws any
# :class:`~asperity.statmodel.shear.ShearCurve` in the paper's four panels (the main job's
# report uses it too): forces, numbers of asperities, real area and tangential force, each with
# its stick (dotted) and slip (dashed) parts.
from asperity.plotting import new_figure
from asperity.statmodel import draw_shear_curve

fig = draw_shear_curve(new_figure(10.0, 8.0), curve, title="Fig. 4 (the paper's parameters)")
