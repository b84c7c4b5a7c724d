"""Helpers shared by several test files (a test file imports no other test file).

Import as ``from tests._helpers import ...``. Fixtures stay in the ``conftest.py`` of their
folder; what a fixture hands out may be defined here.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from asperity import bem, statmodel
from asperity.bem.reference_solutions import MaugisDugdale

# --------------------------------------------------------------------------------------------
# bem: geometries
# --------------------------------------------------------------------------------------------


#: hypothesis strategies of the kernels' property tests: pixel sizes (m) and moduli E* (Pa).
def pixel_size_strategy():
    """Pixel sizes from 0.1 um to 1 cm (m)."""
    from hypothesis import strategies as st

    return st.floats(min_value=1e-7, max_value=1e-2, allow_nan=False)


def modulus_strategy():
    """Reduced moduli E* from 1 kPa to 1 TPa (Pa)."""
    from hypothesis import strategies as st

    return st.floats(min_value=1e3, max_value=1e12, allow_nan=False)


def mirrored_patch_values(patch, dx: float, dy: float, e_star: float) -> np.ndarray:
    """A uniform-patch solution ``patch(x, y, dx, dy, e_star)`` (x, y in m) at three points
    (0.3, 1.7 and 4 pixels), asserted even in x and in y (to 1e-12); returns its values there."""
    pts = np.array([0.3, 1.7, 4.0]) * dx
    u = patch(pts, pts[::-1], dx, dy, e_star)
    assert np.allclose(u, patch(-pts, pts[::-1], dx, dy, e_star), rtol=1e-12)
    assert np.allclose(u, patch(pts, -pts[::-1], dx, dy, e_star), rtol=1e-12)
    return u


def sphere_heights(n: int, box: float, radius: float) -> tuple[np.ndarray, float]:
    """Parabolic sphere cap h = -r^2 / (2 R) (m), apex at the grid centre; returns (h, dx)."""
    dx = box / n
    x = (np.arange(n) - n / 2 + 0.5) * dx
    return -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius), dx


def random_surface(n: int, seed: int = 0, hurst: float = 0.8, cutoff: float = 8.0) -> np.ndarray:
    """Periodic self-affine heights (rms slope 1, pixel size 1) for solver tests."""
    rng = np.random.default_rng(seed)
    qx = 2 * np.pi * np.fft.fftfreq(n)
    qy = 2 * np.pi * np.fft.rfftfreq(n)
    q = np.hypot(qx[:, None], qy[None, :])
    band = (q > 0) & (q <= 2 * np.pi / cutoff)
    amp = np.where(band, np.where(q > 0, q, 1.0) ** (-(1 + hurst)), 0.0)
    spec = amp * (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape))
    h = np.fft.irfft2(spec, s=(n, n))
    gx, gy = np.gradient(h)
    return (h - h.mean()) / np.sqrt(np.mean(gx**2 + gy**2))


# --------------------------------------------------------------------------------------------
# bem: the ``asperity bem --json`` contract
# --------------------------------------------------------------------------------------------

#: The keys of one ``asperity bem --json`` entry, in order.
BEM_JSON_KEYS = [
    "contact_fraction",
    "real_area",
    "normal_force",
    "mean_gap",
    "iterations",
    "converged",
    "seconds",
    "status",
    "branch",
]

# --------------------------------------------------------------------------------------------
# bem: the Maugis-Dugdale sphere (test_bem_maugis.py, test_bem_maugis_sphere.py)
# --------------------------------------------------------------------------------------------

MAUGIS_RADIUS, MAUGIS_E_STAR, MAUGIS_WORK = 1e-2, 1e6, 0.05  # m, Pa, J/m^2


def maugis_sphere_case(lam: float, per_radius: float, n: int):
    """The closed form at Maugis parameter ``lam`` and a paraboloid (apex on a grid node)
    with ``per_radius`` pixels per contact radius at the load pi w R.

    Returns (MaugisDugdale, heights m, dx m, keyword arguments of ``bem.solve_contact``).
    """
    k = 4 * MAUGIS_E_STAR / 3
    sigma0 = lam / 2 * (math.pi * MAUGIS_WORK * k**2 / MAUGIS_RADIUS) ** (1 / 3)
    md = MaugisDugdale(MAUGIS_RADIUS, MAUGIS_E_STAR, MAUGIS_WORK, MAUGIS_WORK / sigma0)
    dx = md.contact_radius(md.force_scale) / per_radius
    x = (np.arange(n) - n // 2) * dx
    h = -(x[:, None] ** 2 + x[None, :] ** 2) / (2 * MAUGIS_RADIUS)
    kw = dict(
        work_of_adhesion=MAUGIS_WORK,
        adhesion="maugis",
        adhesion_range=md.adhesion_range,
        periodic=False,
    )
    return md, h, dx, kw


def equivalent_radius(res) -> float:
    """sqrt(A / pi) (m) of a contact result's real area A (m^2)."""
    return math.sqrt(res.real_area / math.pi)


def retract_to_pull_off(h, dx, kw, md, steps: int = 24) -> tuple[float, list]:
    """Displacement-controlled unloading from zero approach: the most tensile force (N)."""
    res = bem.solve_contact(h, dx, dx, MAUGIS_E_STAR, separation=0.0, **kw)
    branch = [res]
    for d in np.linspace(0.0, 1.5 * md.approach_scale, steps + 1)[1:]:
        res = bem.solve_contact(h, dx, dx, MAUGIS_E_STAR, separation=float(d), initial=res, **kw)
        branch.append(res)
        if res.real_area == 0:
            break
    return bem.pull_off_force(branch), branch


# --------------------------------------------------------------------------------------------
# statmodel: the paper's material and roughness laws (resolution and prediction uncertainty)
# --------------------------------------------------------------------------------------------

#: The Fig. 4 case: lambda = 0.2, no equilibrium distance given (SI units), its roughness
#: (eta in m^-2, R and sigma_s in m), A_n (m^2) and F_z (N).
FIG4_MATERIAL = statmodel.Material(
    e_star=2.133e6, work_of_adhesion=0.040, mode_mixity=0.2, shear_strength=0.13e6
)
FIG4_ROUGHNESS = statmodel.Roughness(
    asperity_density=652.1e6, summit_radius=0.041e-3, summit_height_rms=0.032e-3
)
FIG4_AREA, FIG4_LOAD = 700e-6, 3.1
#: The paper's PDMS-on-glass material (SI units): Fig. 4's with the fitted lambda = 0.03
#: (Section 5) and z_0 = 0.2 nm.
PAPER_MATERIAL = dataclasses.replace(FIG4_MATERIAL, mode_mixity=0.03, equilibrium_distance=0.2e-9)
#: The paper's nominal contact area, m^2.
PAPER_NOMINAL_AREA = 700e-6


def paper_roughness(resolution: float) -> statmodel.Roughness:
    """The paper's Fig 12 laws at a resolution (m): eta = 652.1 mm^-2 (Delta/2 um)^-1.12,
    R = 0.041 mm + 4.4 (Delta - 2 um), sigma_s = 0.032 mm."""
    return statmodel.Roughness(
        652.1e6 * (resolution / 2e-6) ** -1.12, 0.041e-3 + 4.4 * (resolution - 2e-6), 0.032e-3
    )


# --------------------------------------------------------------------------------------------
# One adhesive paraboloid cap under the mixed-mode shear curve (tests/bem/test_bem_shear_*.py):
# R = 1, E* = 1, w = 1e-6 (xi = 100), indented 3 R / xi^2, on a free grid of 3.5 JKR radii.
# --------------------------------------------------------------------------------------------
SHEAR_CAP_R, SHEAR_CAP_E_STAR, SHEAR_CAP_W = 1.0, 1.0, 1e-6
SHEAR_CAP_DELTA = 3.0 * SHEAR_CAP_R / 100**2


def stepped_tangential_path(contact, bound, dx: float, e_star: float, steps, **kw) -> list:
    """solve_tangential at each delta_T of ``steps`` (m) on a square-pixel grid (``dx`` m,
    E* Pa, slip threshold ``bound`` Pa), each step started from the last one's slip and
    tractions (asperity 0.4.0's per-step curve); ``kw`` go to every solve."""
    from asperity.bem.shear.stick_slip import solve_tangential

    prev, path = None, []
    for value in steps:
        slip = None if prev is None else prev.slip
        prev = solve_tangential(
            contact, bound, dx, dx, e_star, float(value), slip=slip, initial=prev, **kw
        )
        path.append(prev)
    return path


def shear_cap_load() -> float:
    """The JKR load (fixed grip) of the cap at its indentation, in the units above."""
    from asperity.statmodel.jkr import jkr_normal_load

    r, w, e = SHEAR_CAP_R, SHEAR_CAP_W, SHEAR_CAP_E_STAR
    return float(jkr_normal_load(SHEAR_CAP_DELTA, r, w, e))


def shear_cap(n_per: int = 8) -> tuple[np.ndarray, float]:
    """The cap's heights on a free grid of 3.5 JKR radii, ``n_per`` elements per radius, and
    the element size."""
    from asperity.statmodel.jkr import jkr_contact_radius

    r, w, e = SHEAR_CAP_R, SHEAR_CAP_W, SHEAR_CAP_E_STAR
    dx = float(jkr_contact_radius(SHEAR_CAP_DELTA, r, w, e)) / n_per
    n = int(3.5 * n_per) + 2
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x, indexing="ij")
    return -(xx**2 + yy**2) / (2 * r), dx


def shear_cap_curve(**kw):
    """The cap's mixed-mode shear curve (lambda 0.2, tau_0 1e-3 E*) in load control at its JKR
    load, over delta_T = 0..2e-3 in 8 steps; ``kw`` go to ``mixed_mode_shear_curve``."""
    from asperity.bem.shear.mixed_mode import MixedModeLaw
    from asperity.bem.shear.rough_mixed_mode import mixed_mode_shear_curve

    h, dx = shear_cap()
    return mixed_mode_shear_curve(
        h,
        dx,
        dx,
        SHEAR_CAP_E_STAR,
        shear_cap_load(),
        np.linspace(0.0, 2e-3, 9),
        MixedModeLaw(SHEAR_CAP_W, 0.2),
        shear_strength=1e-3 * SHEAR_CAP_E_STAR,
        periodic=False,
        **kw,
    )


# --------------------------------------------------------------------------------------------
# statmodel: the model's A_r(F_x) up to the peak, sampled as measured curves (lambda fits)
# --------------------------------------------------------------------------------------------


def shear_area_model(material, roughness, nominal_area: float, steps: int):
    """``model(lam, f_z) -> (F_x (N), A_r (m^2))``: the statistical model's shear path for
    these parameters (``nominal_area`` in m^2), no displacement cap, default quadrature."""
    from asperity.statmodel.shear_path import model_shear_area

    return functools.partial(
        model_shear_area,
        material=material,
        roughness=roughness,
        nominal_area=nominal_area,
        max_tangential_displacement=None,
        steps=steps,
        knobs={},
    )


def area_to_peak(model, lam: float, loads) -> list[tuple[np.ndarray, np.ndarray]]:
    """(F_x, A_r) of ``model`` at mode mixity ``lam`` up to its peak force, per load (N)."""
    from asperity.statmodel.lambda_fit import area_up_to_peak

    return [area_up_to_peak(*model(lam, f)) for f in loads]


def sampled_area_curves(peaks, loads, points: int, fraction: float, noise=0.0, rng=None):
    """A ShearAreaCurve per load (N) and curve of ``peaks`` (:func:`area_to_peak`): ``points``
    forces from 0 to ``fraction`` of the peak, the model's area there, times 1 + N(0, noise)
    drawn from ``rng`` in load order when ``noise`` (relative)."""
    from asperity.pipelines.measured import ShearAreaCurve
    from asperity.statmodel.lambda_fit import interpolate_area

    curves = []
    for f, (fx, ar) in zip(loads, peaks, strict=True):
        picks = np.linspace(0.0, fraction * fx[-1], points)
        area = interpolate_area(fx, ar, picks)
        if noise:
            area = area * (1 + rng.normal(0, noise, picks.size))
        curves.append(ShearAreaCurve(f, picks, area))
    return curves


# --------------------------------------------------------------------------------------------
# pipelines: the small job (a 2.56 mm, 64 x 64 patch of the paper-like surface)
# --------------------------------------------------------------------------------------------


def small_data(**loading) -> dict:
    """TOML data of the small job: three loads, 41 shear steps, a few seconds in all."""
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover
        import tomli as tomllib
    from asperity.pipelines.config import preset_text

    data = tomllib.loads(preset_text("default"))
    data["surface"]["synthetic"].update(n=64, pixel_size=40e-6, seed=3)
    data["surface"]["max_stride"] = 4
    data["bem"]["max_stride"] = 2
    data["loading"].update({"normal_loads": [1.0, 2.0, 3.0], "steps": 41, **loading})
    return data


def adhesive_in_tension_toml(steps: int) -> str:
    """The ``asperity-statmodel friction`` TOML of a smooth adhesive contact held in tension
    (F_z = -1 N; E* 1 MPa, w 0.05 J/m^2, sigma_s 30 nm), ``steps`` shear steps: shear peels
    the junctions until the tensile load can no longer be carried (exit status 1)."""
    return f"""
[material]
E_star = 1e6
work_of_adhesion = 0.05
mode_mixity = 0.2
shear_strength = 1e5
[roughness]
asperity_density = 1e9
summit_radius = 1e-4
summit_height_rms = 3e-8
[loading]
normal_load = -1.0
nominal_area = 1e-4
max_tangential_displacement = 50e-6
steps = {steps}
"""


def planned_keys(config, version: str = "1.0") -> dict:
    """The stage keys a runner plans for ``config`` at package ``version`` (no stage runs)."""
    from asperity.pipelines.engine.parallel import SerialExecutor
    from asperity.pipelines.engine.stage import Runner, StageContext
    from asperity.pipelines.engine.store import ResultStore
    from asperity.pipelines.job import STAGES

    runner = Runner(
        store=ResultStore("unused.h5"),
        context=StageContext(config, {}, SerialExecutor()),
        config_document=config.key_document(),
        version=version,
        root_attrs={},
    )
    runner.plan(STAGES)
    return runner.keys


def python_stdout(code: str) -> str:
    """The stripped standard output of ``code`` run in a fresh Python process (fails on an
    error): what a statement imports, seen from a clean interpreter."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return out.stdout.strip()


def copied_run(out_dir, to):
    """A copy of a finished run's folder ``out_dir`` at ``to`` (its path): a run to alter."""
    import shutil

    shutil.copytree(out_dir, to)
    return to
