"""
Fig. 13: the real contact area falls under shear
================================================

Fig. 13 of the paper compares the real contact area under increasing tangential force with
Sahli et al.'s measurements: :math:`A_r/A_n` drops from its preload value to its sliding value
as the asperities are sheared; how fast it drops is set by the mode-mixity parameter
:math:`\\lambda`, which the job fits to measured :math:`A_r(F_x)` curves when they are given
(``[measured]`` in the job file) and otherwise takes from the configuration (here the paper's
fit, :math:`\\lambda` = 0.03). The dashed line is the constant-shear-strength prediction
:math:`F_x = \\tau_0 A_r`.

The previous example ran the main job on the embedded default into a folder; running the same
configuration on the same folder again reuses every stored stage (their checksums and keys
still hold), so this takes a second. A finished run is also reopened without recomputing
anything by :func:`asperity.open_results`, as here.
"""

import tempfile
from pathlib import Path

import asperity
from asperity.pipelines import config
from asperity.pipelines.job import run_job

out = Path(tempfile.gettempdir()) / "asperity-docs-default-job"
result = run_job(config.load_preset("default"), out)  # resumes: nothing left to compute
print("stages reused:", ", ".join(s.name for s in result.stages if s.cached))

run = asperity.open_results(out)  # the typed stage results stored in out/results.h5

# %%
# Static and sliding friction, per normal load
# --------------------------------------------
# ``run.friction`` holds one shear curve per normal load (arrays of shape
# ``(normal_load, step)``); ``static_friction`` is the peak of :math:`F_x`,
# ``sliding_friction`` the all-sliding value (N).
friction = run.friction
print(f"lambda = {friction.mode_mixity:g}, tau0 = {friction.shear_strength * 1e-6:g} MPa")
fraction = friction.real_area / friction.nominal_area  # A_r/A_n, (normal_load, step)
for k, f_z in enumerate(friction.normal_load):
    print(
        f"F_z = {f_z:4.2f} N: static {friction.static_friction[k]:.3f} N, "
        f"sliding {friction.sliding_friction[k]:.3f} N, "
        f"A_r/A_n {100 * fraction[k, 0]:.3f} % -> {100 * fraction[k, -1]:.3f} %"
    )
print("verdict:", run.verdict.verdict)
assert (friction.static_friction >= friction.sliding_friction).all()

# %%
# The figure
# ----------
# :func:`asperity.pipelines.report.draw_area_vs_force` draws Fig. 13 from the reopened run.
from asperity.pipelines.report import draw_area_vs_force

fig, table = draw_area_vs_force(run)
