"""A non-Gaussian synthetic surface: spherical caps on caps, carried by a smooth wavy base.

The surface is a function of the physical position (m), sampled on the requested grid:

    z(x) = B(x) + G(x) + sum_k F_k(x),        B = A(x) (sigma_L L(x) + sigma_W W(x)),

* ``L`` and ``W`` are periodic Gaussian fields of unit variance, trigonometric sums over
  the wavevectors ``q = 2 pi (i / X, j / Y)`` of the ``X x Y`` domain: ``L`` with the
  spectrum ``C(q) = 1`` below the roll-off ``q_r = 2 pi / rolloff_wavelength`` and
  ``(q / q_r)^(-2(1 + H))`` above it, cut at ``2 pi / base_cutoff``; ``W`` (the waviness)
  with ``C(q) = 1`` below ``2 pi / waviness_wavelength`` and ``(q / q_w)^-8`` above, cut
  at the same wavenumber. Their coefficients are drawn in a fixed order from
  ``numpy.random.default_rng(seed)``, so ``B`` does not depend on the pixel size.
* ``A`` (the amplitude modulation, ``A = 1`` unless ``amplitude_modulation > 0``) is
  ``exp(s M(x)) / sqrt(<exp(2 s M)>)``, ``s = amplitude_modulation``, ``M`` a periodic
  Gaussian field of unit variance with ``C(q) = 1`` for ``0 < q <= 2 pi /
  modulation_wavelength`` and 0 above, the mean ``<.>`` taken on the reference grid (so the
  rms of ``B`` stays ``hypot(sigma_L, sigma_W)``). ``A`` varies over lengths longer than the
  roll-off: it leaves the base's spectrum where it is (no power is added at long wavelengths,
  unlike ``W``) and its summits where they are, but makes the base rougher in some regions and
  smoother in others (a modelling device, not a measured property). At a fixed rms it
  spreads the coarse summits' heights and flattens the mean summit (the mean radius is a mean
  of ``1 / kappa``, which the smoother regions raise): the combination a rolled-off Gaussian
  base cannot make (Xu et al. 2022, Fig 12, 260 um: R 1.18 mm and sigma_s 41.9 um with a
  roll-off near 600 um and an rms near 51 um, Section 5).
* ``F_k`` (level k = 0, 1, ...) is the upper envelope (the maximum) of spherical caps of
  base radius ``a_k = a_0 2^k`` (up to ``max_cap_radius``) and sphere radius
  ``rho_k = a_k / s_k`` (``s_0 = cap_slope``, ``s_k = coarse_cap_slope`` for k >= 1; the
  slope of a cap's rim is ``s_k / sqrt(1 - s_k^2)``), centred at Poisson points of density
  ``n_k = cap_density 2^(-k size_exponent)`` (1/m^2). Level k + 1 carries level k: the
  levels are added, a "protuberance on protuberance" structure.
* ``G`` (the coarse level, off unless ``coarse_cap_density > 0``) is the upper envelope of
  spherical caps of sphere radius ``rho_G = coarse_sphere_radius``, centred at Poisson points
  ``c_i`` of density ``coarse_cap_density``, each with its own apex height ``h_i`` drawn from
  ``N(coarse_height_mean, coarse_height_sd^2)`` (at most ``rho_G``) above a floor at 0:
  ``G(x) = max(0, max_i (h_i - rho_G + sqrt(rho_G^2 - |x - c_i|^2)))``. A cap meets the floor
  at its base radius ``a_i = sqrt(h_i (2 rho_G - h_i))``, so ``G`` is continuous, and one with
  ``h_i <= 0`` does not show. Every coarse summit is a cap apex of curvature ``1 / rho_G``;
  the creases between caps, and the floor, are valleys (no summit). With a mean well above
  the spread and dense caps the floor never shows and the caps bury one another (the replica
  of a shot-blasted mould): the visible cells are about ``sqrt(2 rho_G sd)`` wide whatever the
  density, and their apices' heights spread with ``h_i``. With a mean near 0 and few caps,
  they are isolated domes whose width grows with their height. ``G`` can stand in for the
  waviness ``W``: it spreads the coarse summits' heights without curving them beyond
  ``1 / rho_G``, over cells whose size sets the spectrum's knee (on its own, about 2.3 times
  the mean distance between its summits, measured).
* A cap of the levels ``F_k`` is kept with the probability
  ``Phi(((B(c) + G(c)) / sigma_B - threshold) / width)`` at its centre ``c`` (``Phi`` the
  normal distribution function, ``sigma_B = hypot(sigma_L, sigma_W)``, or with ``G`` the rms
  of ``B + G`` on the reference grid): the caps, and with them
  the small-scale summits, sit preferentially on the high parts of the base. ``B + G`` is
  read from the base sampled on a fixed reference grid (bilinear), so the choice does not
  depend on the output grid either.

The same ``seed`` and domain therefore give the same surface at any pixel size that
resolves the base (``pixel_size <= base_cutoff / 2``): a map made at ``k dx`` equals the
map made at ``dx`` decimated by k, up to rounding and the subtracted mean. The random draws
are made in a fixed order (base coefficients, then the modulation's coefficients if any, then
the coarse level's caps if any, then the levels ``F_k``), so a recipe without a modulation or a
coarse level gives the same heights, bit for bit, as before either existed. All lengths are
in metres.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numba
import numpy as np
import scipy.fft
import scipy.special

from asperity.errors import InputError

#: Pixel of the reference grid on which the base is read at the cap centres (m), at most.
REFERENCE_PIXEL = 25e-6
#: Rows of the map transformed and painted at once: the generator holds the heights (float64)
#: and a few blocks of this many rows, so a 17,500 x 10,000 map (the paper's whole 35 x 20 mm
#: interface at 2 um, 1.3 GiB of heights) peaks at about 1.6 GiB above the interpreter.
ROWS_PER_BLOCK = 512
#: Cap centres whose base height is interpolated at once (the whole interface has 4.9 million
#: caps of the smallest level: their interpolation's temporaries would be 0.4 GiB).
CAPS_PER_BLOCK = 2**18
#: Largest map side :func:`check_capped_size` accepts, pixels: the paper's 35 mm at 2 um.
MAX_PIXELS_PER_SIDE = 17500
#: Peak memory of :func:`capped_surface` per pixel, bytes: the float64 heights, the blocks and
#: the cap centres (about 1/30 as many as the pixels at 2 um) beside them; measured 9.8 bytes
#: a pixel above the interpreter on 8,750 x 5,000 at 2 um (before: about 18 bytes, with two
#: complex spectra and a full-size cap level: 3.1 GiB in all on 17,500 x 10,000).
GENERATOR_BYTES_PER_PIXEL = 10


@dataclass(frozen=True)
class CappedSurfaceRecipe:
    """Parameters of :func:`capped_surface` (SI units: m, 1/m^2).

    Attributes
    ----------
    base_rms : float
        ``sigma_L``, rms of the rolled-off Gaussian component L (m).
    waviness_rms : float
        ``sigma_W``, rms of the long-wave component W (m).
    rolloff_wavelength : float
        Roll-off wavelength of L (m).
    base_hurst : float
        Exponent H of L's power law above the roll-off, ``C ~ q^-2(1+H)``.
    base_cutoff : float
        Shortest wavelength of L and W (m).
    waviness_wavelength : float
        Wavelength below which W's spectrum falls as ``q^-8`` (m).
    cap_radius : float
        ``a_0``, base radius of the smallest caps (m).
    max_cap_radius : float
        Largest cap base radius (m): levels ``a_0 2^k <= max_cap_radius``.
    cap_slope : float
        ``s_0 = a_0 / rho_0`` of the smallest caps, in (0, 1).
    coarse_cap_slope : float
        ``s_k = a_k / rho_k`` of the larger levels, in (0, 1).
    cap_density : float
        ``n_0``, density of the smallest caps before thinning (1/m^2).
    size_exponent : float
        Density of level k: ``n_0 2^(-k size_exponent)``.
    threshold : float
        Height (in units of the base rms) around which caps start being kept.
    width : float
        Width of that transition (base rms units), > 0.
    coarse_cap_density : float
        Density of the coarse level's cap centres (1/m^2), >= 0; 0 (the default) leaves the
        coarse level ``G`` out, and the surface is the one of the other parameters alone.
    coarse_sphere_radius : float
        ``rho_G``, sphere radius of the coarse caps (m), > 0.
    coarse_height_mean : float
        Mean of the coarse caps' apex heights above the level's floor (m), finite.
    coarse_height_sd : float
        Standard deviation of the coarse caps' apex heights (m), >= 0.
    amplitude_modulation : float
        ``s``, standard deviation of ``log A`` (dimensionless), >= 0; 0 (the default) leaves
        the base unmodulated (``A = 1``).
    modulation_wavelength : float
        Shortest wavelength of the modulation field ``M`` (m), > 0.
    """

    base_rms: float
    waviness_rms: float
    rolloff_wavelength: float
    base_hurst: float
    base_cutoff: float
    waviness_wavelength: float
    cap_radius: float
    max_cap_radius: float
    cap_slope: float
    coarse_cap_slope: float
    cap_density: float
    size_exponent: float
    threshold: float
    width: float
    coarse_cap_density: float = 0.0
    coarse_sphere_radius: float = 1.2e-3
    coarse_height_mean: float = 0.0
    coarse_height_sd: float = 40e-6
    amplitude_modulation: float = 0.0
    modulation_wavelength: float = 3e-3

    def as_dict(self) -> dict:
        """The parameters as a plain dict; without the coarse level's when it is off
        (``coarse_cap_density == 0``) and without the modulation's when it is off
        (``amplitude_modulation == 0``), so a recipe without them is recorded and hashed as
        before they existed."""
        values = asdict(self)
        if self.coarse_cap_density == 0:
            for key in COARSE_FIELDS:
                del values[key]
        if self.amplitude_modulation == 0:
            for key in MODULATION_FIELDS:
                del values[key]
        return values


#: The coarse level's parameters in :class:`CappedSurfaceRecipe` (all with defaults).
COARSE_FIELDS = (
    "coarse_cap_density",
    "coarse_sphere_radius",
    "coarse_height_mean",
    "coarse_height_sd",
)
#: The amplitude modulation's parameters in :class:`CappedSurfaceRecipe` (with defaults).
MODULATION_FIELDS = ("amplitude_modulation", "modulation_wavelength")


def _check_recipe(recipe: CappedSurfaceRecipe, name: str) -> None:
    positive = (
        "base_rms",
        "rolloff_wavelength",
        "base_hurst",
        "base_cutoff",
        "waviness_wavelength",
        "cap_radius",
        "max_cap_radius",
        "width",
    )
    for key in positive:
        value = getattr(recipe, key)
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name}: {key} must be a finite value > 0, got {value!r}")
    for key in ("waviness_rms", "cap_density", "size_exponent"):
        value = getattr(recipe, key)
        if not (math.isfinite(value) and value >= 0):
            raise InputError(f"{name}: {key} must be a finite value >= 0, got {value!r}")
    for key in ("cap_slope", "coarse_cap_slope"):
        value = getattr(recipe, key)
        if not 0 < value < 1:
            raise InputError(
                f"{name}: {key} must be in (0, 1) (cap radius / sphere radius), got {value!r}"
            )
    if not math.isfinite(recipe.threshold):
        raise InputError(f"{name}: threshold must be finite, got {recipe.threshold!r}")
    for key in ("coarse_cap_density", "coarse_height_sd"):
        value = getattr(recipe, key)
        if not (math.isfinite(value) and value >= 0):
            raise InputError(f"{name}: {key} must be a finite value >= 0, got {value!r}")
    if not (math.isfinite(recipe.amplitude_modulation) and recipe.amplitude_modulation >= 0):
        raise InputError(
            f"{name}: amplitude_modulation must be a finite value >= 0 (the standard deviation "
            f"of log A), got {recipe.amplitude_modulation!r}"
        )
    if not (math.isfinite(recipe.modulation_wavelength) and recipe.modulation_wavelength > 0):
        raise InputError(
            f"{name}: modulation_wavelength must be a finite value > 0 m, "
            f"got {recipe.modulation_wavelength!r}"
        )
    if not (math.isfinite(recipe.coarse_sphere_radius) and recipe.coarse_sphere_radius > 0):
        raise InputError(
            f"{name}: coarse_sphere_radius must be a finite value > 0 m, "
            f"got {recipe.coarse_sphere_radius!r}"
        )
    if not math.isfinite(recipe.coarse_height_mean):
        raise InputError(
            f"{name}: coarse_height_mean must be finite (m), got {recipe.coarse_height_mean!r}"
        )


def _mode_grid(side_x: float, side_y: float, shortest: float):
    """Wavenumbers (rad/m) of the half plane of mode indices (i in -M..M, j in 0..N) down to
    the wavelength ``shortest`` (m): ``q``, the modes drawn, the weight of each (a j > 0 mode
    appears with its conjugate), ``M`` and ``N``."""
    m_x = int(side_x / shortest)
    m_y = int(side_y / shortest)
    i = np.arange(-m_x, m_x + 1)
    j = np.arange(0, m_y + 1)
    qx = 2 * math.pi * i[:, None] / side_x
    qy = 2 * math.pi * j[None, :] / side_y
    q = np.hypot(qx, qy)
    inside = (q > 0) & (q <= 2 * math.pi / shortest)
    lower = (j[None, :] == 0) & (i[:, None] < 0)  # conjugates of the i > 0, j = 0 modes
    weight = np.where(j[None, :] == 0, 1.0, 2.0)
    return q, inside & ~lower, weight, m_x, m_y


def _unit_field(grid, amplitude: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Coefficients of a unit-variance field with the mode amplitudes ``amplitude`` on
    ``grid`` (:func:`_mode_grid`); the j = 0 column is made Hermitian so that the
    trigonometric sum is real."""
    q, keep, weight, m_x, _ = grid
    noise = rng.standard_normal(q.shape + (2,))
    coef = np.where(keep, amplitude * (noise[..., 0] + 1j * noise[..., 1]), 0.0)
    coef[:m_x, 0] = np.conj(coef[:m_x:-1, 0])  # i < 0 from i > 0 on j = 0
    variance = float(np.sum(weight * np.abs(coef) ** 2))
    return coef / math.sqrt(variance) if variance > 0 else coef


def _mode_coefficients(
    side_x: float, side_y: float, recipe: CappedSurfaceRecipe, rng: np.random.Generator
) -> tuple[np.ndarray, int, int]:
    """Complex coefficients of ``sigma_L L + sigma_W W`` on the half plane of mode indices.

    Unit-variance L and W scaled by their rms. Depends on the domain and the recipe only.
    """
    grid = _mode_grid(side_x, side_y, recipe.base_cutoff)
    q, m_x, m_y = grid[0], grid[3], grid[4]
    q_r = 2 * math.pi / recipe.rolloff_wavelength
    q_w = 2 * math.pi / recipe.waviness_wavelength
    base = _unit_field(
        grid, np.where(q < q_r, 1.0, (np.maximum(q, q_r) / q_r) ** -(1 + recipe.base_hurst)), rng
    )
    wave = _unit_field(grid, np.where(q < q_w, 1.0, (np.maximum(q, q_w) / q_w) ** -4.0), rng)
    return recipe.base_rms * base + recipe.waviness_rms * wave, m_x, m_y


def _modulation_coefficients(
    side_x: float, side_y: float, recipe: CappedSurfaceRecipe, rng: np.random.Generator
) -> tuple[np.ndarray, int, int]:
    """Coefficients of the modulation field ``M`` (unit variance, a flat spectrum down to
    ``modulation_wavelength``) on its own half plane of mode indices."""
    grid = _mode_grid(side_x, side_y, min(recipe.modulation_wavelength, side_x, side_y))
    flat = np.where(grid[0] <= 2 * math.pi / recipe.modulation_wavelength, 1.0, 0.0)
    return _unit_field(grid, flat, rng), grid[3], grid[4]


def _row_blocks(coef: np.ndarray, m_x: int, m_y: int, nx: int, ny: int):
    """The trigonometric sum with coefficients ``coef`` on an ``nx x ny`` periodic grid, as
    ``(start, stop, rows)`` blocks of at most :data:`ROWS_PER_BLOCK` rows.

    The inverse transform is done in the two passes of ``scipy.fft.irfft2`` (complex along x,
    then complex-to-real along y) with the same scaling, so the heights are bit-identical to
    ``irfft2`` of the zero-padded half spectrum times ``nx ny``; but the x pass runs on the
    ``m_y + 1`` non-zero columns only and the y pass on blocks of rows, so the memory is
    O(nx m_y + ny) beside the caller's, instead of two full complex spectra.
    """
    if nx <= 2 * m_x or ny // 2 <= m_y:
        raise InputError(
            f"capped_surface: a {nx} x {ny} grid does not resolve the base (needs more than "
            f"{2 * m_x} x {2 * m_y} pixels: a pixel at most half the base cut-off wavelength)"
        )
    columns = np.zeros((nx, m_y + 1), dtype=np.complex128)
    columns[np.arange(-m_x, m_x + 1) % nx] = coef
    columns = scipy.fft.ifft(columns, axis=0, norm="forward", overwrite_x=True)
    # irfft2's factor 1 / (nx ny), which pocketfft rounds from long double, then times nx ny
    scale = float(np.float64(np.longdouble(1) / np.longdouble(nx * ny)))
    block = np.zeros((min(ROWS_PER_BLOCK, nx), ny // 2 + 1), dtype=np.complex128)
    for start in range(0, nx, ROWS_PER_BLOCK):
        stop = min(start + ROWS_PER_BLOCK, nx)
        part = block[: stop - start]
        part[:, : m_y + 1] = columns[start:stop]
        rows = scipy.fft.irfft(part, n=ny, axis=1, norm="forward")
        rows *= scale
        rows *= nx * ny
        yield start, stop, rows


def _sample_base(coef: np.ndarray, m_x: int, m_y: int, nx: int, ny: int) -> np.ndarray:
    """The trigonometric sum with coefficients ``coef`` on an ``nx x ny`` periodic grid
    (:func:`_row_blocks`): the memory is the heights (8 bytes a pixel, float64) and the
    blocks beside them."""
    heights = np.empty((nx, ny), dtype=np.float64)
    for start, stop, rows in _row_blocks(coef, m_x, m_y, nx, ny):
        heights[start:stop] = rows
    return heights


def _modulation_norm(coef: np.ndarray, m_x: int, m_y: int, ref_nx: int, ref_ny: int, s: float):
    """``sqrt(<exp(2 s M)>)`` on the reference grid: the factor that keeps the rms of ``B``."""
    total = 0.0
    for _, _, rows in _row_blocks(coef, m_x, m_y, ref_nx, ref_ny):
        total += float(np.sum(np.exp(2 * s * rows)))
    return math.sqrt(total / (ref_nx * ref_ny))


def _modulate(heights: np.ndarray, modulation, s: float, norm: float) -> None:
    """Multiply ``heights`` in place by ``A = exp(s M) / norm``, a block of rows at a time."""
    coef, m_x, m_y = modulation
    nx, ny = heights.shape
    for start, stop, rows in _row_blocks(coef, m_x, m_y, nx, ny):
        rows *= s
        np.exp(rows, out=rows)
        rows /= norm
        heights[start:stop] *= rows


@numba.njit(cache=True)
def _paint_caps(level, row0, nx, dx, dy, cx, cy, radius, sphere, base):
    """Raise ``level`` to the upper envelope of spherical caps: cap k centred at (cx[k], cy[k])
    (m), of sphere radius ``sphere[k]``, painted out to the distance ``radius[k]`` (m) from
    its centre, its height there ``base[k] + sqrt(sphere[k]^2 - r^2)`` (m). ``level[r]`` is
    row ``row0 + r`` of the periodic grid of ``nx`` rows (pixel (i, j) at (i dx, j dy)).
    A small-cap level has ``base = -sqrt(sphere^2 - radius^2)`` (each cap meets 0 at its
    rim); the coarse level ``base = apex - sphere`` (module docstring)."""
    rows, ny = level.shape
    last = row0 + rows - 1
    for k in range(cx.size):
        s2 = sphere[k] * sphere[k]
        r2max = radius[k] * radius[k]
        i0 = int(math.ceil((cx[k] - radius[k]) / dx))
        i1 = int(math.floor((cx[k] + radius[k]) / dx))
        j0 = int(math.ceil((cy[k] - radius[k]) / dy))
        j1 = int(math.floor((cy[k] + radius[k]) / dy))
        # the periods m whose rows row0 + m nx .. last + m nx meet the cap's rows i0 .. i1
        m0 = -((last - i0) // nx)
        m1 = (i1 - row0) // nx
        for m in range(m0, m1 + 1):
            lo = max(i0, row0 + m * nx)
            hi = min(i1, last + m * nx)
            for i in range(lo, hi + 1):
                ddx = i * dx - cx[k]
                ii = i - m * nx - row0
                for j in range(j0, j1 + 1):
                    ddy = j * dy - cy[k]
                    r2 = ddx * ddx + ddy * ddy
                    if r2 < r2max:
                        value = base[k] + math.sqrt(s2 - r2)
                        jj = j % ny
                        if value > level[ii, jj]:
                            level[ii, jj] = value


def _coarse_caps(
    side_x: float, side_y: float, recipe: CappedSurfaceRecipe, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The coarse level's visible caps: centres (m), apex heights above the floor 0 (m) and
    base radii (m), drawn (centres, then heights) from ``rng``; depends on the domain and the
    recipe only. A cap whose apex is not above 0 does not show and is dropped."""
    count = int(rng.poisson(recipe.coarse_cap_density * side_x * side_y))
    cx = rng.random(count) * side_x
    cy = rng.random(count) * side_y
    apex = recipe.coarse_height_mean + recipe.coarse_height_sd * rng.standard_normal(count)
    rho = recipe.coarse_sphere_radius
    apex = np.minimum(apex, rho)  # a cap at most a hemisphere
    shows = apex > 0
    cx, cy, apex = cx[shows], cy[shows], apex[shows]
    radius = np.sqrt(apex * (2 * rho - apex))  # where the sphere meets the floor 0
    return cx, cy, apex, radius


def _add_coarse_level(heights: np.ndarray, dx: float, dy: float, caps, recipe) -> None:
    """Add the coarse level ``G`` (module docstring) to ``heights`` by blocks of rows."""
    cx, cy, apex, radius = caps
    nx = heights.shape[0]
    sphere = np.broadcast_to(recipe.coarse_sphere_radius, cx.shape)
    level = np.empty((min(ROWS_PER_BLOCK, nx), heights.shape[1]), dtype=np.float64)
    for start in range(0, nx, ROWS_PER_BLOCK):
        part = level[: min(ROWS_PER_BLOCK, nx - start)]
        part.fill(0.0)
        _paint_caps(part, start, nx, dx, dy, cx, cy, radius, sphere, apex - sphere)
        heights[start : start + part.shape[0]] += part


def _bilinear(grid: np.ndarray, pixel_x: float, pixel_y: float, x: np.ndarray, y: np.ndarray):
    """Periodic bilinear interpolation of ``grid`` (pixel (i, j) at (i px, j py)) at (x, y)."""
    nx, ny = grid.shape
    fx = x / pixel_x
    fy = y / pixel_y
    i0 = np.floor(fx).astype(np.int64)
    j0 = np.floor(fy).astype(np.int64)
    tx = fx - i0
    ty = fy - j0
    i0 %= nx
    j0 %= ny
    i1 = (i0 + 1) % nx
    j1 = (j0 + 1) % ny
    return (
        grid[i0, j0] * (1 - tx) * (1 - ty)
        + grid[i1, j0] * tx * (1 - ty)
        + grid[i0, j1] * (1 - tx) * ty
        + grid[i1, j1] * tx * ty
    )


def check_capped_size(nx: int, ny: int, name: str = "n") -> None:
    """Refuse, before any allocation, a map larger than :data:`MAX_PIXELS_PER_SIDE` a side.

    The generator holds the heights and blocks of :data:`ROWS_PER_BLOCK` rows
    (:data:`GENERATOR_BYTES_PER_PIXEL` bytes a pixel), so the side limit is the largest map
    in use (the paper's whole interface, 17,500 x 10,000 at 2 um: 1.3 GiB of heights), not the
    generator's memory; the job's memory rule (:func:`asperity.topo.io.limits.check_map_points`)
    judges what the solver will need.

    Raises
    ------
    InputError
        Naming ``name``, the limit and the memory the map would take.
    """
    side = max(nx, ny)
    if side > MAX_PIXELS_PER_SIDE:
        need = GENERATOR_BYTES_PER_PIXEL * float(nx) * float(ny) / 2**30
        raise InputError(
            f"{name}: expected at most {MAX_PIXELS_PER_SIDE} pixels per side (generating "
            f"{nx} x {ny} pixels needs about {need:.3g} GiB of memory, "
            f"{GENERATOR_BYTES_PER_PIXEL} bytes a pixel), got {side}"
        )


def capped_surface(
    nx: int, ny: int, dx: float, dy: float, recipe: CappedSurfaceRecipe, seed: int
) -> np.ndarray:
    """Heights (m) of the caps-on-caps surface on an ``nx x ny`` periodic grid (see module).

    Parameters
    ----------
    nx, ny : int
        Pixels along x and y.
    dx, dy : float
        Pixel sizes (m); the domain is ``nx dx`` by ``ny dy``.
    recipe : CappedSurfaceRecipe
        The parameters (SI units).
    seed : int
        Seed of ``numpy.random.default_rng``.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights in m, mean subtracted.

    Raises
    ------
    InputError
        A parameter out of range, or a grid too coarse to resolve the base.
    """
    _check_recipe(recipe, "capped_surface")
    side_x, side_y = nx * dx, ny * dy
    rng = np.random.default_rng(seed)
    coef, m_x, m_y = _mode_coefficients(side_x, side_y, recipe, rng)
    heights = _sample_base(coef, m_x, m_y, nx, ny)
    ref_nx = max(2 * m_x + 1, math.ceil(side_x / REFERENCE_PIXEL))
    ref_ny = max(2 * m_y + 2, math.ceil(side_y / REFERENCE_PIXEL))
    reference = _sample_base(coef, m_x, m_y, ref_nx, ref_ny)
    if recipe.amplitude_modulation > 0:
        s = recipe.amplitude_modulation
        modulation = _modulation_coefficients(side_x, side_y, recipe, rng)
        norm = _modulation_norm(*modulation, ref_nx, ref_ny, s)
        _modulate(heights, modulation, s, norm)
        _modulate(reference, modulation, s, norm)
    base_sigma = math.hypot(recipe.base_rms, recipe.waviness_rms)
    if recipe.coarse_cap_density > 0:
        caps = _coarse_caps(side_x, side_y, recipe, rng)
        _add_coarse_level(heights, dx, dy, caps, recipe)
        _add_coarse_level(reference, side_x / ref_nx, side_y / ref_ny, caps, recipe)
        base_sigma = float(np.std(reference))  # of B + G, on the reference grid: any dx
    level = np.empty((min(ROWS_PER_BLOCK, nx), ny), dtype=np.float64)
    radius = recipe.cap_radius
    k = 0
    while radius <= recipe.max_cap_radius * (1 + 1e-12):
        density = recipe.cap_density * 2.0 ** (-k * recipe.size_exponent)
        count = int(rng.poisson(density * side_x * side_y))
        cx = rng.random(count) * side_x
        cy = rng.random(count) * side_y
        draw = rng.random(count)
        slope = recipe.cap_slope if k == 0 else recipe.coarse_cap_slope
        keep = np.empty(count, dtype=bool)
        for start in range(0, count, CAPS_PER_BLOCK):  # the interpolation's temporaries bounded
            part = slice(start, start + CAPS_PER_BLOCK)
            base_at = _bilinear(reference, side_x / ref_nx, side_y / ref_ny, cx[part], cy[part])
            chance = scipy.special.ndtr((base_at / base_sigma - recipe.threshold) / recipe.width)
            keep[part] = draw[part] < chance
        kept_x, kept_y = cx[keep], cy[keep]
        # one radius, sphere and base per level: read-only broadcasts, no per-cap memory
        sphere = radius / slope
        each = (
            np.broadcast_to(radius, kept_x.shape),
            np.broadcast_to(sphere, kept_x.shape),
            np.broadcast_to(-math.sqrt(sphere * sphere - radius * radius), kept_x.shape),
        )  # each cap meets 0 at its rim
        for start in range(0, nx, ROWS_PER_BLOCK):  # a block of rows at a time: no full level
            rows = level[: min(ROWS_PER_BLOCK, nx - start)]
            rows.fill(0.0)
            _paint_caps(rows, start, nx, dx, dy, kept_x, kept_y, *each)
            heights[start : start + rows.shape[0]] += rows
        radius *= 2.0
        k += 1
    heights -= heights.mean()
    return heights
