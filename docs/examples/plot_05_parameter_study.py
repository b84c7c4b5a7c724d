"""
Fig. 5: what sets the static friction peak
==========================================

The shear curve of Fig. 4 for four values of each parameter in turn: the work of adhesion
:math:`w`, the mode-mixity parameter :math:`\\lambda` and the shear strength :math:`\\tau_0`
(panels a-c, real contact area against tangential force), and the normal load :math:`F_z`
(panel d, the tangential force relative to its sliding value, with the relative height of the
static peak in the inset). Other parameters as in Fig. 4.

A larger :math:`\\lambda` couples shear and adhesion more strongly: the contact area falls
sooner and the peak is reached earlier. A larger normal load brings the peak closer to the
sliding value.
"""

import numpy as np

from asperity.statmodel import Material, Roughness, shear_curve

roughness = Roughness(asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3)
base = {"e_star": 2.133e6, "work_of_adhesion": 0.040, "shear_strength": 0.13e6}
displacement = np.linspace(0.0, 30e-6, 301)  # m

# %%
# The peak against lambda
# -----------------------
# One line per :math:`\lambda`: static and sliding friction (N) and where the peak is.
for lam in (0.05, 0.2, 0.3, 0.9):
    c = shear_curve(Material(mode_mixity=lam, **base), roughness, 700e-6, 3.1, displacement)
    assert c.success, c.message
    print(
        f"lambda = {lam:4.2f}: static {c.static_friction:.3f} N at "
        f"{c.static_displacement * 1e6:5.2f} um, sliding {c.sliding_friction:.3f} N"
    )

# %%
# The figure
# ----------
# :func:`asperity.statmodel.figures.figure_5` computes the 17 curves of the paper's figure,
# each run until full sliding (about two seconds).
import h5py

from asperity.statmodel import figures

with h5py.File("fig5.h5", "w", driver="core", backing_store=False) as h5:
    fig = figures.figure_5(h5)
