"""The read-and-level and resolution-scan stages: read and prepare the surface, then scan its
summit statistics over resolution.

The read-and-level stage (:func:`read_and_level`) gives a prepared :class:`topo.HeightMap` from
a file (any format :func:`topo.read_surface` reads) or from the seeded synthetic recipe, with
:func:`topo.prepare_surface`: crop, form removal (``detrend`` or ``form_order``), the outlier
rule and the missing-pixel policy of ``[surface]``; the job stores it, with the preparation
record, as a :class:`LevelledSurface`.
The resolution-scan stage (:func:`scan_resolutions`) runs :func:`topo.resolution_scan`: eta, R
and sigma_s of the map decimated with strides 1..K (Appendix A, Fig 12a-c) and the paper's fits
(:class:`ScanResult`).

A line profile as ``file`` (:mod:`asperity.pipelines.stages._profile`) is prepared as a
profile; the stage stores the isotropic map synthesised from its spectrum (realisation 0, what
the BEM and Persson's theory solve) and the prepared profile beside it, and the resolution scan
is the profile's Nayak scan (:func:`topo.profile_resolution_scan`, ``method`` "nayak-profile").
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from asperity import topo
from asperity.errors import InputError
from asperity.fields import array, document_fields, scalar, stacked, text
from asperity.pipelines.config import ConfigError, SurfaceConfig
from asperity.pipelines.engine.stage import Stage, StageContext
from asperity.pipelines.stages._profile import (
    PROFILE_METHOD,
    prepare_line_profile,
    profile_crop,
    require_nominal_area,
    synthesis_record,
    synthesised_map,
)
from asperity.pipelines.stages._pull_off import check_loads_above_pull_off
from asperity.topo import scan as topo_scan
from asperity.topo.heightmap import MapGeometry
from asperity.topo.io.limits import check_map_points

#: The scan's ``method`` for a map (summits counted on the map).
MAP_METHOD = "map-summits"
#: Fewest pixels per side kept by the coarsest resolution of the scan.
MIN_SCAN_PIXELS = 16


def file_sha256(path: str | Path, chunk: int = 1 << 20) -> str:
    """SHA-256 hex digest of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(chunk):
            digest.update(block)
    return digest.hexdigest()


#: The parameters behind each synthetic recipe, part of its hash: a change of a recipe's
#: constants recomputes the stored stages instead of reusing those of the old surface.
RECIPE_CONSTANTS: dict[str, object] = {
    "paper_like": topo.synthetic.PAPER_LIKE,
    "paper_surface": topo.synthetic.PAPER_SURFACE,
    "paper_spectrum": topo.synthetic.PAPER_SPECTRUM,
}


def input_sha256(config: SurfaceConfig) -> str:
    """Provenance hash of the input: the file's SHA-256, or that of the synthetic recipe (its
    configuration and the recipe's constants, :data:`RECIPE_CONSTANTS`)."""
    if config.file is not None:
        return file_sha256(config.file)
    recipe = config.synthetic
    constants = RECIPE_CONSTANTS[recipe.recipe]
    if dataclasses.is_dataclass(constants):  # as_dict: a recipe's own record, if it has one
        constants = getattr(constants, "as_dict", lambda: dataclasses.asdict(constants))()
    square = recipe.ny is None or recipe.ny == recipe.n  # hashed as before ny existed
    fields = {k: v for k, v in recipe.__dict__.items() if not (k == "ny" and square)}
    document = json.dumps({**fields, "constants": constants}, sort_keys=True)
    return hashlib.sha256(("synthetic:" + document).encode()).hexdigest()


def read_input(config: SurfaceConfig) -> topo.HeightMap | topo.LineProfile:
    """The raw input of the configuration: the file's map or line profile, or the synthetic
    recipe's map (heights in m)."""
    if config.file is not None:
        return topo.read_surface(
            config.file, channel=config.channel, pixel_size=config.pixel_size, unit=config.unit
        )
    recipe = config.synthetic
    ny = recipe.n if recipe.ny is None else recipe.ny
    check_map_points("[surface.synthetic]", "n x ny", recipe.n, ny)  # the files' memory rule
    generator = getattr(topo.synthetic, recipe.recipe)
    return generator(**recipe.generator_arguments())


def load_surface(config: SurfaceConfig) -> topo.HeightMap:
    """The raw surface of the configuration (file or synthetic recipe), heights in m; a line
    profile is refused here (the job's route for one is :func:`compute_surface`)."""
    surface = read_input(config)
    if not isinstance(surface, topo.HeightMap):
        raise ConfigError(
            f"surface.file: expected a 2D height map (summit statistics and the BEM are "
            f"2D), got a 1D line profile ({config.file})"
        )
    return surface


def preparation_options(config: SurfaceConfig) -> topo.PreparationOptions:
    """The :class:`topo.PreparationOptions` of ``[surface]``: crop, form, outliers, missing.

    ``form_order`` wins over ``detrend`` when given; ``detrend`` names the order otherwise
    (none, mean 0, plane 1, quadratic 2).
    """
    crop = None
    if config.crop is not None:
        x0, x1, y0, y1 = config.crop
        crop = topo.CropWindow((x0, x1), (y0, y1), "px")
    order = (
        config.form_order
        if config.form_order is not None
        else topo.PreparationOptions.order_of(config.detrend)
    )
    return topo.PreparationOptions(
        crop=crop,
        missing=config.missing,
        outliers=topo.OutlierRule(config.outliers, config.outlier_threshold, config.outlier_action),
        form_order=order,
    )


def prepare(config: SurfaceConfig, surface: topo.HeightMap | None = None) -> topo.PreparedSurface:
    """Read (or generate) the surface and prepare it (:func:`topo.prepare_surface`).

    ``surface``, when given, is the map already read from ``config`` (heights in m).

    Raises
    ------
    ConfigError
        Naming the ``surface.*`` key: a crop outside the map, missing pixels with
        ``missing = "refuse"``, too few valid pixels for the form.
    """
    surface = load_surface(config) if surface is None else surface
    try:
        return topo.prepare_surface(surface, preparation_options(config))
    except InputError as exc:
        key = "surface.crop" if config.crop is not None and "window" in str(exc) else None
        key = key or ("surface.missing" if config.missing == "refuse" else "surface")
        raise ConfigError(f"{key}: {exc}") from exc


def read_and_level(config: SurfaceConfig) -> topo.HeightMap:
    """The read-and-level stage: read (or generate) the surface and prepare it as ``[surface]``
    says.

    Parameters
    ----------
    config : SurfaceConfig
        ``file`` or ``synthetic`` recipe, crop, form (``detrend`` / ``form_order``), outlier
        rule and missing-pixel policy.

    Returns
    -------
    topo.HeightMap
        Heights in m (axis 0 is x), prepared; ``provenance["preparation"]`` holds the record.
    """
    return prepare(config).surface


def usable_max_stride(surface: topo.HeightMap, max_stride: int) -> int:
    """``max_stride`` capped so the coarsest decimated map keeps MIN_SCAN_PIXELS per side."""
    return max(1, min(int(max_stride), min(surface.nx, surface.ny) // MIN_SCAN_PIXELS))


def scan_resolutions(surface: topo.HeightMap, max_stride: int) -> topo.ResolutionScan:
    """The resolution-scan stage: summit statistics at strides 1..max_stride
    (:func:`topo.resolution_scan`).

    ``max_stride`` is capped by :func:`usable_max_stride`.

    Returns
    -------
    topo.ResolutionScan
        ``stride``, ``resolution`` (m), ``n_summits``, ``asperity_density`` (1/m^2),
        ``summit_radius`` (m), ``summit_height_rms`` (m) and the fits.
    """
    return topo.resolution_scan(surface, usable_max_stride(surface, max_stride))


@document_fields
@dataclass
class LevelledSurface(MapGeometry):
    """Stage-1 result: the levelled height map (SI).

    Attributes
    ----------
    x, y : ndarray
        Pixel positions, m.
    heights : ndarray, shape (nx, ny)
        Levelled heights, m (NaN: missing pixel).
    dx, dy : float
        Pixel sizes, m.
    periodic : bool
        The map is one period of a periodic surface.
    n_missing : int
        Missing pixels.
    rms_height : float
        Root mean square of the valid heights about their mean, m.
    provenance : dict
        Where the map came from (reader, file, levelling).
    preparation : dict or None
        The :class:`topo.PreparationRecord` (crop, levelling, form-to-roughness ratio,
        missing fraction and policy, outliers changed, dx and dy, warnings), SI units.
    filled : ndarray of bool or None
        Pixels whose height the missing-pixel policy filled (measured holes and masked
        outliers); the resolution scan leaves them out, so eta is per measured area.
    profile_heights : ndarray or None
        For a line profile as input: the prepared profile, m (the map above is then the
        isotropic map synthesised from its spectrum; ``provenance["profile_synthesis"]``
        says how).
    profile_dx : float or None
        Sampling interval of that profile, m.
    """

    x: np.ndarray = array("m", ("x",), "position along x")
    y: np.ndarray = array("m", ("y",), "position along y")
    heights: np.ndarray = array("m", ("x", "y"), "levelled height")
    dx: float = scalar("m", "pixel size along x")
    dy: float = scalar("m", "pixel size along y")
    periodic: bool = scalar("1", "the map is one period of a periodic surface")
    n_missing: int = scalar("1", "missing pixels")
    rms_height: float = scalar("m", "rms of the valid heights")
    provenance: dict[str, object] = text("reader, file and levelling (JSON)")
    preparation: dict[str, object] | None = text("surface preparation record (JSON)", optional=True)
    filled: np.ndarray | None = array(
        "1", ("x", "y"), "height filled by the missing-pixel policy, not measured", optional=True
    )
    profile_heights: np.ndarray | None = array(
        "m", ("profile_x",), "prepared heights of the input line profile", optional=True
    )
    profile_dx: float | None = scalar(
        "m", "sampling interval of the input line profile", optional=True
    )

    @classmethod
    def from_prepared(cls, prepared: topo.PreparedSurface) -> LevelledSurface:
        """Wrap a :class:`topo.PreparedSurface`, keeping which pixels were filled."""
        stored = cls.from_height_map(prepared.surface)
        if prepared.filled_mask.any():
            stored.filled = np.asarray(prepared.filled_mask, dtype=bool)
        return stored

    @classmethod
    def from_profile(
        cls, profile: topo.LineProfile, record: dict, surface: topo.HeightMap, synthesis: dict
    ) -> LevelledSurface:
        """Wrap a prepared line profile (m), its preparation record, the map synthesised from
        it (realisation 0, m) and the record of that synthesis."""
        stored = cls.from_height_map(surface)
        stored.provenance = json.loads(
            json.dumps(
                {**surface.provenance, "input": profile.provenance, "profile_synthesis": synthesis},
                default=str,
            )
        )
        stored.preparation = json.loads(json.dumps(record, default=str))
        stored.profile_heights = np.asarray(profile.heights, dtype=float)
        stored.profile_dx = float(profile.dx)
        return stored

    def line_profile(self) -> topo.LineProfile | None:
        """The input line profile (m), or None when the input was a map."""
        if self.profile_heights is None or self.profile_dx is None:
            return None
        source = self.provenance.get("input") or {}
        return topo.LineProfile(self.profile_heights, self.profile_dx, dict(source))

    def scanned_height_map(self) -> topo.HeightMap | None:
        """The map the resolution scan analysed (:meth:`measured_height_map`), which a
        statistic between strides may resample; None for a line profile, whose scan is
        Nayak's on the profile (the synthesised map's summits are another statistic, of a map
        without the profile's longest wavelengths)."""
        return None if self.profile_heights is not None else self.measured_height_map()

    def measured_height_map(self) -> topo.HeightMap:
        """The map with filled pixels missing again (NaN): what summit statistics count."""
        surface = self.height_map()
        if self.filled is None or not np.any(self.filled):
            return surface
        return surface.with_heights(np.where(self.filled, np.nan, self.heights))

    @classmethod
    def from_height_map(cls, surface: topo.HeightMap) -> LevelledSurface:
        """Wrap a levelled :class:`topo.HeightMap` (heights in m)."""
        valid = surface.heights[~np.isnan(surface.heights)]
        return cls(
            x=np.arange(surface.nx) * surface.dx,
            y=np.arange(surface.ny) * surface.dy,
            heights=np.asarray(surface.heights, dtype=float),
            dx=float(surface.dx),
            dy=float(surface.dy),
            periodic=bool(surface.periodic),
            n_missing=int(surface.n_missing),
            rms_height=float(np.sqrt(np.mean((valid - valid.mean()) ** 2))),
            provenance=json.loads(json.dumps(surface.provenance, default=str)),
            preparation=json.loads(json.dumps(surface.provenance.get("preparation"), default=str)),
        )

    def height_map(self) -> topo.HeightMap:
        """The map as a :class:`topo.HeightMap` (heights in m)."""
        return topo.HeightMap(
            self.heights, dx=self.dx, dy=self.dy, periodic=self.periodic, provenance=self.provenance
        )


#: The fields of :class:`topo.ResolutionScan` the resolution-scan stage stores.
SCAN_FIELDS = (*topo_scan.ARRAY_FIELDS, *topo_scan.FIT_FIELDS[:4])  # arrays, R and eta fits


@document_fields
@dataclass
@stacked(topo.ResolutionScan, SCAN_FIELDS, None)
class ScanResult:
    """Stage-2 result: summit statistics per decimation stride and the paper's fits (SI).

    The fields of :class:`topo.ResolutionScan` the job uses (:data:`SCAN_FIELDS`, declared
    there, taken over by :func:`asperity.fields.stacked`): R = radius_intercept +
    radius_slope * resolution, eta = density_prefactor * resolution**density_exponent.
    """

    fit_units: str = text("how the fits read")
    method: str | None = text(
        f"{MAP_METHOD!r} (the map's summits) or {PROFILE_METHOD!r} (Nayak's theory on the line "
        "profile; n_summits counts its peaks)",
        optional=True,
    )

    @classmethod
    def from_scan(cls, scan: topo.ResolutionScan) -> ScanResult:
        """Keep the arrays and fits of a :class:`topo.ResolutionScan`."""
        return cls(
            stride=np.asarray(scan.stride),
            resolution=np.asarray(scan.resolution, dtype=float),
            n_summits=np.asarray(scan.n_summits),
            asperity_density=np.asarray(scan.asperity_density, dtype=float),
            summit_radius=np.asarray(scan.summit_radius, dtype=float),
            summit_height_rms=np.asarray(scan.summit_height_rms, dtype=float),
            radius_slope=float(scan.radius_slope),
            radius_intercept=float(scan.radius_intercept),
            density_exponent=float(scan.density_exponent),
            density_prefactor=float(scan.density_prefactor),
            fit_units="R = radius_intercept (m) + radius_slope (m/m) * resolution; "
            "eta = density_prefactor * resolution**density_exponent (SI)",
            method=getattr(scan, "method", MAP_METHOD),
        )


def compute_surface(context: StageContext) -> LevelledSurface:
    """The job's read-and-level stage: :func:`prepare` on ``[surface]``; for a line profile,
    the prepared profile and the map synthesised from it (:func:`profile_surface`)."""
    config = context.config.surface
    raw = read_input(config)
    if isinstance(raw, topo.LineProfile):
        return profile_surface(raw, config)
    return LevelledSurface.from_prepared(prepare(config, raw))


def profile_surface(profile: topo.LineProfile, config: SurfaceConfig) -> LevelledSurface:
    """A line profile prepared as ``[surface]`` says, with realisation 0 of the isotropic map
    synthesised from its spectrum (``profile_synthesis_n`` pixels, seed ``profile_seed``)."""
    options = dataclasses.replace(preparation_options(config), crop=profile_crop(config))
    prepared, record = prepare_line_profile(profile, config, options)
    surface = synthesised_map(prepared, config, 0)
    synthesis = synthesis_record(prepared, config)
    return LevelledSurface.from_profile(prepared, record, surface, synthesis)


def check_profile_input(context: StageContext, surface: LevelledSurface) -> None:
    """After the read-and-level stage: a line profile's job must give its nominal area."""
    if surface.profile_heights is not None:
        require_nominal_area(context.config)


def compute_scan(context: StageContext) -> ScanResult:
    """The job's resolution-scan stage: :func:`scan_resolutions` up to ``surface.max_stride``,
    over the measured pixels only (filled ones are missing again: eta per measured area); for
    a line profile, its Nayak scan (:func:`scan_profile`)."""
    stored = context.result(SURFACE)
    profile = stored.line_profile()
    if profile is not None:
        return ScanResult.from_scan(scan_profile(profile, context.config.surface.max_stride))
    surface = stored.measured_height_map()
    return ScanResult.from_scan(scan_resolutions(surface, context.config.surface.max_stride))


def scan_profile(profile: topo.LineProfile, max_stride: int) -> topo.ResolutionScan:
    """Nayak's eta, R, sigma_s of a line profile at strides 1..``max_stride``
    (:func:`topo.profile_resolution_scan`), capped so the coarsest profile keeps
    MIN_SCAN_PIXELS points (and at least 3)."""
    usable = max(1, min(int(max_stride), profile.nx // MIN_SCAN_PIXELS, (profile.nx - 1) // 2))
    return topo.profile_resolution_scan(profile, usable)


def check_scan_loads(context: StageContext, scan: ScanResult) -> None:
    """After the resolution-scan stage: every load must exceed the statistical model's pull-off
    force."""
    config = context.config
    check_loads_above_pull_off(
        config.material,
        scan,
        config.loading.nominal_area,
        config.loading.normal_loads,
    )


SURFACE = Stage(
    name="surface",
    title="read and level",
    result=LevelledSurface,
    config=(
        "surface.file",
        "surface.channel",
        "surface.pixel_size",
        "surface.unit",
        "surface.synthetic",
        "surface.detrend",
        "surface.crop",
        "surface.missing",
        "surface.outliers",
        "surface.outlier_threshold",
        "surface.outlier_action",
        "surface.form_order",
        "surface.profile_synthesis_n",
        "surface.profile_seed",
    ),
    inputs=(),
    compute=compute_surface,
    check=check_profile_input,
)

SCAN = Stage(
    name="resolution_scan",
    title="resolution scan",
    attribute="scan",
    result=ScanResult,
    config=("surface.max_stride",),
    inputs=(SURFACE,),
    compute=compute_scan,
    check=check_scan_loads,
)
