"""The single-asperity closed forms: the ground :mod:`asperity.bem` and :mod:`asperity.statmodel`
both stand on (paper, Section 2; SI units: m, Pa, J/m^2, N).

* :mod:`~asperity.single_asperity.hertz`: Hertz (E:Hertz_theory), a non-adhesive or sliding
  asperity;
* :mod:`~asperity.single_asperity.jkr`: JKR in fixed grip (E:JKR_indent, E:JKR_load), jump-off
  (E:JKR_delta_min_unloading), pull-off;
* :mod:`~asperity.single_asperity.papangelo_ciavarella`: a JKR asperity under shear
  (E:PC_indent, E:PC_P, E:PC_T, E:max_disp_PC);
* :mod:`~asperity.single_asperity.maugis_dugdale`: the Maugis-Dugdale sphere (Maugis 1992);
* :mod:`~asperity.single_asperity.newton`: the scalar Newton solver their numba kernels share.

The BEM's reference solutions (:mod:`asperity.bem.reference_solutions`) and the statistical
model (:mod:`asperity.statmodel`, which keeps its 0.4 module names for these laws) both import
from here, so the BEM that checks the model does not import the model.
"""
