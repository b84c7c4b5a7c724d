"""
Fig. 1: one adhesive asperity sheared in fixed grip
===================================================

A sphere of radius :math:`R` pressed to an indentation :math:`\\delta` against a flat, then
displaced tangentially by :math:`\\delta_T` at fixed :math:`\\delta`. Papangelo and
Ciavarella's model (its indentation, normal and tangential load under shear, Eqs. 6-8,
``E:PC_indent`` .. ``E:PC_T``) couples the tangential loading to the
adhesive crack through the mode-mixity parameter :math:`\\lambda`: the contact shrinks as
:math:`\\delta_T` grows, until it reaches a fold (the unstable boundary: the fold radius at
fixed indentation, Eq. 9, ``E:PC_a_min_1``)
where the asperity jumps to sliding or out of contact.

The parameters are the paper's Fig. 1 caption (a smooth PDMS sphere on glass): work of
adhesion :math:`w` = 27 mJ/m², :math:`R` = 9.42 mm, :math:`E^*` = 2.133 MPa,
:math:`\\lambda` = 0.0023. Every quantity is in SI units (m, N, m², J/m²); the figure picks
readable prefixes.
"""

import numpy as np

from asperity.statmodel import (
    jkr_pull_off_force_fixed_grip,
    pc_contact_radius,
    pc_max_tangential_displacement,
    tabor_parameter,
)

R, W, E_STAR, LAMBDA = 9.42e-3, 0.027, 2.133e6, 0.0023

# %%
# The numbers behind the figure
# -----------------------------
# The Tabor parameter :math:`\mu` tells whether JKR (large :math:`\mu`, soft and adhesive) is
# the right single-asperity law; the paper's model needs :math:`\mu \gtrsim 5`. For one
# indentation, the largest tangential displacement the asperity can stick to, and how much of
# its contact area it has lost at the fold:
mu = tabor_parameter(R, W, E_STAR)
delta = 0.02e-3  # m
dt_fold = pc_max_tangential_displacement(delta, R, W, E_STAR, LAMBDA)
a0 = pc_contact_radius(delta, 0.0, R, W, E_STAR, LAMBDA)
a_fold = pc_contact_radius(delta, 0.999 * dt_fold, R, W, E_STAR, LAMBDA)
print(f"Tabor parameter mu = {mu:.0f}")
print(f"JKR pull-off force in fixed grip = {jkr_pull_off_force_fixed_grip(R, W) * 1e3:.3f} mN")
print(f"delta = {delta * 1e3:g} mm: sticks up to delta_T = {dt_fold * 1e6:.2f} um")
print(f"contact radius {a0 * 1e3:.3f} mm at rest, {a_fold * 1e3:.3f} mm near the fold")
print(f"area lost before the jump: {100 * (1 - (a_fold / a0) ** 2):.0f} %")
assert np.isfinite(dt_fold) and a_fold < a0

# %%
# The figure
# ----------
# :func:`asperity.statmodel.figures.figure_1` draws the paper's four panels for five
# indentations and writes the plotted data (SI units) into an HDF5 group; here the file is kept
# in memory. ``asperity figures --out DIR`` writes the same figure as a PNG.
import h5py

from asperity.statmodel import figures

with h5py.File("fig1.h5", "w", driver="core", backing_store=False) as h5:
    fig = figures.figure_1(h5)
