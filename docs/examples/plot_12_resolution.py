"""
Fig. 12: the statistics depend on the resolution; the BEM picks the one to use
==============================================================================

Summit statistics of a self-affine surface are not properties of the surface alone: the finer
the pixel, the more (and sharper) summits one finds. The paper (Section 5, Fig. 12) decimates
the measured map ("one out of two, three, four ... points"), computes :math:`\\eta`,
:math:`R` and :math:`\\sigma_s` at each resolution (a-c), runs the statistical model with each
set, and keeps the *effective resolution* at which the model's real contact area
:math:`A_r(F_z)` best matches a reference: a boundary-element (BEM) solution of the full map
(d), or the user's measured :math:`A_r(F_z)`.

This is what the main job, ``asperity run``, does first. Here it runs on the embedded default:
a paper-like synthetic surface (10 mm square, 1000 x 1000 pixels of 10 µm, seeded), the
material of the paper's Fig. 13 and the six normal loads of Sahli et al. It takes about a
minute.
"""

import tempfile
from pathlib import Path

from asperity.pipelines import config
from asperity.pipelines.job import run_job

out = Path(tempfile.gettempdir()) / "asperity-docs-default-job"
job = config.load_preset("default")
result = run_job(job, out, force=True)  # force: recompute even if `out` holds a finished run

# %%
# The job's summary
# -----------------
# The same lines as the terminal summary of ``asperity run``. At the top, the **verdict**:
# whether the model can stand behind these numbers, each reason with its number and its
# threshold. Then the key numbers: the effective resolution and the summit statistics there,
# the Tabor parameter, the mode-mixity parameter :math:`\lambda`, and per normal load the
# real contact area from the BEM, the model and Persson's theory, and the static and sliding
# friction.
from asperity.pipelines.report import summary_text

print(summary_text(result))

# %%
# Reading the effective resolution
# --------------------------------
# ``result.statistical_model`` holds the misfit at every stride. Against the BEM, the model
# compared with it carries the BEM's own adhesion law: the Maugis-Dugdale statistical model at
# the BEM's range :math:`h_0` (``real_area_bem_law``), since the grid-resolved range puts the
# BEM on the DMT side while the JKR model that makes the predictions is far on the JKR side.
# The stride of least misfit is one of the decimated grids; between strides, the job locates
# the optimum on a continuous resolution axis with a one-sigma interval (widened by the BEM's
# own band), and that one resolution, ``choice.effective_resolution``, with the statistics of
# the map resampled there (``choice.roughness``), is the one used and shown everywhere (SI
# units: m, 1/m^2).
choice = result.statistical_model
stride_resolution = choice.resolution[choice.effective_index]
print(
    f"stride of least misfit: {choice.effective_stride} "
    f"({stride_resolution * 1e6:.0f} um, misfit {choice.misfit_bem.min():.3f}), "
    f"chosen against {choice.basis} with the model under the BEM's law: {choice.bem_law}"
)
low, high = choice.optimum_interval
print(
    f"effective resolution: {choice.effective_resolution * 1e6:.1f} um "
    f"(interval {low * 1e6:.1f}..{high * 1e6:.1f} um), misfit {choice.optimum_misfit:.3f}"
)
rough = choice.roughness
print(
    f"eta = {rough.asperity_density * 1e-6:.1f} 1/mm^2, R = {rough.summit_radius * 1e6:.1f} um, "
    f"sigma_s = {rough.summit_height_rms * 1e6:.2f} um"
)
gain = choice.effective_real_area_bem_law / choice.effective_real_area_non_adhesive - 1
bem = result.bem_reference
bem_gain = bem.contact_fraction_adhesive / bem.contact_fraction - 1
print(
    f"adhesive gain over GW: model {gain.min():.2%}..{gain.max():.2%}, "
    f"BEM {bem_gain.min():.2%}..{bem_gain.max():.2%}"
)
print(choice.adhesion_statement)
assert result.verdict is not None and result.verdict.verdict in ("valid", "warnings", "invalid")

# %%
# The figure
# ----------
# :func:`asperity.pipelines.report.draw_resolution` draws Fig. 12: (a-c) :math:`R`,
# :math:`\eta` and :math:`\sigma_s` against the resolution with the paper's fits, the
# effective resolution marked, and (d) :math:`A_r/A_n` against :math:`F_z`: the non-adhesive
# BEM with Greenwood-Williamson, the Maugis-Dugdale BEM with the Maugis-Dugdale model (the
# like-for-like pairs), the JKR model that makes the predictions, with its band, and Persson's
# theory. It returns the figure and the table of its data (written as CSV beside the PNG by
# ``asperity run``).
from asperity.pipelines.report import draw_resolution

fig, table = draw_resolution(result)
