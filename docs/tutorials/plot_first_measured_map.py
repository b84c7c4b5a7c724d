"""
Your first measured map
=======================

From an instrument file to the statistics of its asperities, to the main job's friction
prediction and its verdict, explaining every number on the way. The map is a real one: a
Zygo MetroPro interferometer file (``tests/data/metropro-1.dat`` in asperity's repository,
from the SurfaceTopography project's test files, MIT licence). Replace the path by your own
file: X3P, SUR, MetroPro DAT/DATX, PLu, OPD, Nanoscope, PicoView, Gwyddion, Dektak CSV, text,
NumPy and HDF5 maps are read the same way.

Everything is in SI units: heights and pixel sizes in m, areas in m², forces in N, moduli in
Pa, the work of adhesion in J/m². The printed lines convert to readable prefixes.
"""

from pathlib import Path

from asperity import topo

path = "tests/data/metropro-1.dat"  # in asperity's repository; put your own file here
# sphinx_gallery_start_ignore
path = str(Path.cwd().resolve().parents[1] / path)  # the build runs in docs/tutorials
# sphinx_gallery_end_ignore
raw = topo.read_surface(path)

# %%
# 1. What the file holds
# ----------------------
# A :class:`~asperity.topo.heightmap.HeightMap`: ``heights[i, j]`` in m, axis 0 along x (pixel
# size ``dx``), axis 1 along y (``dy``); pixels the instrument could not measure are NaN.
# ``provenance`` says what the reader found: the instrument, the channel read, how invalid
# pixels were marked.
import numpy as np

print(f"{raw.nx} x {raw.ny} pixels of {raw.dx * 1e6:.3f} x {raw.dy * 1e6:.3f} um")
print(f"map size {raw.nx * raw.dx * 1e3:.3f} x {raw.ny * raw.dy * 1e3:.3f} mm")
print(f"missing pixels: {np.isnan(raw.heights).sum()}")
print(f"height range {np.nanmin(raw.heights) * 1e9:.1f} .. {np.nanmax(raw.heights) * 1e9:.1f} nm")
print("instrument:", raw.provenance["instrument"], "| channel:", raw.provenance["channel"])

# %%
# A look at it. asperity's figures are plain :class:`matplotlib.figure.Figure` objects (no
# pyplot, your backend is left alone):
from asperity.plotting import new_figure


def height_image(heights, dx, dy, title):
    """A map in nm about its median, colours clipped to the 1..99th percentiles."""
    fig = new_figure(6.0, 4.0)
    ax = fig.subplots()
    h = (heights - np.nanmedian(heights)) * 1e9
    low, high = np.nanpercentile(h, [1, 99])
    extent = (0, heights.shape[0] * dx * 1e6, 0, heights.shape[1] * dy * 1e6)
    image = ax.imshow(h.T, origin="lower", extent=extent, vmin=low, vmax=high)
    ax.set(xlabel="x (µm)", ylabel="y (µm)", title=title)
    fig.colorbar(image, ax=ax, label="height about the median (nm)")
    return fig


fig_raw = height_image(raw.heights, raw.dx, raw.dy, "metropro-1.dat as read: a tilt dominates")

# %%
# 2. Preparation: remove the form, deal with outliers and holes
# --------------------------------------------------------------
# Roughness statistics need the roughness alone: :func:`asperity.topo.prepare_surface` removes
# a polynomial form (``form_order`` 1 is a plane), masks outliers (here heights more than
# 10 scaled MADs from the median) and fills missing pixels (``"interpolate"``: a harmonic fill,
# which the BEM needs). It returns the prepared surface and a *record* of what it did, with a
# warning wherever the choice matters.


def prepare(form_order):
    """Prepare the raw map with one form order and print what the record says."""
    options = topo.PreparationOptions(form_order=form_order, missing="interpolate")
    prepared = topo.prepare_surface(raw, options)
    rec = prepared.record
    print(f"form removed: rms {rec.form_rms * 1e9:.1f} nm")
    print(
        f"roughness left: rms {rec.roughness_rms * 1e9:.2f} nm (form / roughness "
        f"{rec.form_to_roughness:.1f})"
    )
    print(f"outliers masked: {rec.n_outliers}; missing pixels filled: {rec.n_filled}")
    for warning in rec.warnings:
        print("WARNING:", warning)
    return prepared


plane = prepare(form_order=1)

# %%
# The warning says that a plane leaves a curvature behind which a quadratic would remove:
# that curvature is the part's shape (or the interferometer's reference), not roughness.
# Following it:
prepared = prepare(form_order=2)
surface = prepared.surface
fig_prepared = height_image(surface.heights, surface.dx, surface.dy, "after the quadratic form")

# %%
# The roughness is now a few nanometres, 20 times smaller than the form that was removed: the
# remaining warning is right that the statistics depend on that choice. Keep it in mind when
# the verdict comes. Against a 3 nm roughness the outlier rule (10 scaled MADs) now catches a
# few dozen isolated pixels (dust, or phase-unwrapping errors); they are masked and filled like
# the holes.
#
# 3. Asperity statistics
# ----------------------
# The statistical model describes the surface by three numbers (paper, Appendix A): the
# asperity density :math:`\eta` (summits per m²; a summit is a pixel higher than its four
# neighbours), their mean radius of curvature :math:`R` (m) and the rms height of the summits
# :math:`\sigma_s` (m).
stats = topo.summit_statistics(surface)
print(f"{stats.n_summits} summits")
print(f"eta     = {stats.asperity_density * 1e-6:.4g} per mm^2")
print(f"R       = {stats.summit_radius * 1e3:.4g} mm")
print(f"sigma_s = {stats.summit_height_rms * 1e9:.3g} nm")

# %%
# These numbers depend on the pixel size: decimating the map ("one point in k", Fig. 12 of the
# paper) finds fewer, blunter summits. The resolution scan repeats the statistics for strides
# 1..8 and fits the paper's laws: :math:`R` linear in the resolution, :math:`\eta` a power law.
scan = topo.resolution_scan(surface, 8)
for k, res, eta, r in zip(
    scan.stride, scan.resolution, scan.asperity_density, scan.summit_radius, strict=True
):
    print(f"stride {k}: {res * 1e6:5.2f} um  eta {eta * 1e-6:9.4g}/mm^2  R {r * 1e3:7.4g} mm")
print(
    f"fits: R = {scan.radius_slope:.4g} x resolution + {scan.radius_intercept * 1e3:.4g} mm; "
    f"eta ~ resolution^{scan.density_exponent:.3g}"
)
fig_scan = topo.draw_resolution_scan(new_figure(12.0, 3.8), scan, title="metropro-1.dat")

# %%
# 4. The main job
# ---------------
# ``asperity run job.toml`` (or :func:`asperity.pipelines.job.run_job`) does all of the above
# and the rest: a boundary-element (BEM) solution of the contact of the prepared map with a
# smooth rigid flat at each normal load, the choice of the *effective resolution* at which the
# statistical model matches the BEM's real contact area, then the shear curves up to full
# sliding, Persson's theory as an independent check, and a verdict. The job file says which
# surface, which material and which loads. A stiff polymer (effective modulus
# :math:`E^*` = 10 GPa) against the map's counterpart, loads of 20 to 100 mN on the map's
# area. A measured map is a patch of a larger surface whose opposite edges do not meet, so
# the BEM solves it with free boundaries (``boundary = "free"``; ``"periodic"``, the default,
# suits synthetic periodic maps and warns when a map's edges jump):
import tempfile

from asperity.pipelines.config import load_config
from asperity.pipelines.job import run_job
from asperity.pipelines.report import draw_resolution, summary_text, write_report

job_toml = f"""
[surface]
file = "{Path(path).resolve().as_posix()}"
form_order = 2            # the quadratic form, as chosen above
missing = "interpolate"   # the BEM needs every pixel
max_stride = 8            # resolution scan over strides 1..8

[bem]
boundary = "free"         # a measured patch is not periodic: its opposite edges do not meet

[material]
E_star = 10e9                  # Pa
work_of_adhesion = 0.040       # J/m^2
mode_mixity = 0.03             # lambda
shear_strength = 0.13e6        # tau0, Pa
equilibrium_distance = 0.2e-9  # m

[loading]
nominal_area = {surface.nx * surface.dx * surface.ny * surface.dy:.6g}   # m^2: the map's area
normal_loads = [0.02, 0.05, 0.1]                                # N
"""
work = Path(tempfile.mkdtemp(prefix="asperity-tutorial-"))
(work / "job.toml").write_text(job_toml)
job = load_config(work / "job.toml")  # a wrong key or value fails here, naming it
result = run_job(job, work / "out")
write_report(result, work / "out")  # report.md, report.html and the figures with their CSVs
print(summary_text(result))

# %%
# 5. The early verdict
# --------------------
# The verdict is the first thing to read, and here it came before the BEM. The regime check
# compares the elastic energy of flattening these few nanometres of roughness with the
# work of adhesion: for this smooth map and this adhesive pair, adhesion wins and pulls the
# surfaces into *full contact* (``adhesion_full_contact``). The independent-asperity model
# then does not apply at all, so the job stops there: it states the full-contact limit
# (:math:`A_r \to A_n` at every load, sliding friction :math:`\to \tau_0 A_n`), skips the
# BEM, statistical-model, :math:`\lambda`, friction and PSD stages (their results are
# ``None``) and ``asperity run`` exits with status 3.
from asperity.errors import ExitStatus
from asperity.pipelines.stages.early_verdict import limit_lines

verdict = result.verdict
print("verdict:", verdict.verdict)
for severity, code, reason in zip(verdict.severities, verdict.codes, verdict.reasons, strict=True):
    print(f"[{severity}] {code}: {reason[:110]}...")
for line in limit_lines(verdict):  # the full-contact-limit statement of the report
    print(line)
if not result.converged:  # a solver that did not converge takes precedence
    status = ExitStatus.NOT_CONVERGED
else:
    status = ExitStatus.INVALID_RESULT if verdict.invalid else ExitStatus.OK
print(f"exit status of `asperity run`: {int(status)} ({status.name})")
print("written:", ", ".join(sorted(p.name for p in (work / "out").iterdir() if p.name[0] != ".")))

# %%
# 6. Computing the model anyway, to see why it fails
# --------------------------------------------------
# ``[run] compute_all = true`` in the job file (``asperity run --compute-all``) runs every
# stage despite the early verdict. The numbers it prints are **invalid**, and the report marks
# them ``invalid:``: the statistical model assumes separate asperities, and in full contact
# there are none. It shows the failure: the BEM finds a few per cent of real contact, while the
# model, fed with this map's summits (a few nanometres high, millimetres in radius, adhesive),
# puts several times the nominal area in contact, at every resolution of the scan.
(work / "job_all.toml").write_text(job_toml + "\n[run]\ncompute_all = true\n")
result_all = run_job(load_config(work / "job_all.toml"), work / "out_all")
print(summary_text(result_all))

# %%
# Reading that summary: **effective resolution** is the stride whose statistics fit the BEM
# best (**R**, **eta**, **sigma_s** at that stride; **Tabor parameter mu** says whether the JKR
# law of adhesive asperities holds, it needs :math:`\mu \gtrsim 5`); **misfit** is the rms of
# :math:`\ln(A_{model}/A_{BEM})` over the loads (0.2 good, 0.7 the limit); ``+- u`` is each
# number's error bar. The job's Fig. 12 shows the failure: (a-c) the statistics against the
# resolution, (d) the model's :math:`A_r/A_n` far above the BEM's and Persson's at every load.
fig_job = draw_resolution(result_all)[0]

# %%
# What next? The verdict's reasons point at the model's assumptions: a rougher
# surface (or a softer, less adhesive pair) keeps the asperities apart and the model within
# its validity, as the embedded default surface does (see the gallery's Fig. 12 and 13
# examples). With measured :math:`A_r(F_z)` and :math:`A_r(F_x)` curves (``[measured]`` in the
# job file) the job calibrates against your measurements instead of the BEM and fits
# :math:`\lambda`; the pipelines guide lists every key.

# sphinx_gallery_start_ignore
# The documentation build keeps no copy of the run (the figures are already on this page).
import shutil

shutil.rmtree(work)
# sphinx_gallery_end_ignore
