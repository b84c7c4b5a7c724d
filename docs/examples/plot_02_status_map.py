"""
Fig. 2: stick, slide or out of contact: the status map of one asperity
======================================================================

Made dimensionless with :math:`\\xi = (E^* R / w)^{1/3}`
(:math:`\\tilde\\delta = \\xi^2 \\delta / R`, :math:`\\tilde\\delta_T = 2 \\xi^2 \\delta_T / (3R)`),
the state of a sheared adhesive asperity depends only on its indentation
:math:`\\tilde\\delta`, its tangential displacement :math:`\\tilde\\delta_T` and
:math:`\\lambda`. Below the unstable boundary
:math:`\\tilde\\delta_{\\min}^{PC}(\\tilde\\delta_T)` the Papangelo-Ciavarella solution no longer
exists: an asperity pressed in (:math:`\\tilde\\delta > 0`) slides with the Hertz contact and a
constant shear strength :math:`\\tau_0` (the Hertz laws of a sliding junction, Eq. 14,
``E:Hertz_theory``); one held in tension
(:math:`\\tilde\\delta < 0`) leaves the contact. This map is what the statistical model
integrates over the summit heights.

Parameters of the paper's Fig. 2: as Fig. 1 (:math:`w` = 27 mJ/m², :math:`R` = 9.42 mm,
:math:`E^*` = 2.133 MPa, :math:`\\lambda` = 0.0023) and :math:`\\tau_0` = 0.43 MPa.
"""

from asperity.statmodel import OUT_OF_CONTACT, SLIDE, STICK, asperity_status
from asperity.statmodel.status_map import from_dimensionless

LAMBDA = 0.0023

# %%
# Where does an asperity stand?
# -----------------------------
# :func:`asperity.statmodel.asperity_status` answers for any (dimensionless) state; the two
# paths of panels (b-d) start in contact and end sliding (:math:`\tilde\delta = 3`) or out of
# contact (:math:`\tilde\delta = -0.5`):
names = {OUT_OF_CONTACT: "out of contact", STICK: "stick", SLIDE: "slide"}
for delta_tilde in (3.0, -0.5):
    path = [int(asperity_status(delta_tilde, dt, LAMBDA)) for dt in (0.0, 20.0, 90.0)]
    print(f"delta~ = {delta_tilde:+g}: " + " -> ".join(names[s] for s in path))
delta, _ = from_dimensionless(3.0, 0.0, 9.42e-3, 0.027, 2.133e6)
print(f"delta~ = 3 is an indentation of {float(delta) * 1e9:.0f} nm for the PDMS sphere")
assert asperity_status(3.0, 90.0, LAMBDA) == SLIDE
assert asperity_status(-0.5, 90.0, LAMBDA) == OUT_OF_CONTACT
assert float(delta) > 0

# %%
# The figure
# ----------
# Panel (a) is the map, (b-d) the contact area, normal and tangential load along the two paths
# (:func:`asperity.statmodel.figures.figure_2`).
import h5py

from asperity.statmodel import figures

with h5py.File("fig2.h5", "w", driver="core", backing_store=False) as h5:
    fig = figures.figure_2(h5)
