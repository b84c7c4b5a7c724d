"""The job configuration: a TOML file read, checked and resolved before any heavy work.

Every value is in SI units (m, Pa, N, J/m^2). A configuration names either a surface file
(any format :func:`topo.read_surface` reads) or a seeded synthetic recipe, the material, the
loads, the solver tolerances and, optionally, measured curves to calibrate against.

The schema (:data:`JOB_SCHEMA`) is built with :mod:`asperity.schema`, the mechanism the
``asperity friction`` parameter file uses too, and shares its ``[material]`` table
(:func:`statmodel.config.material_section`, building a :class:`statmodel.Material`; ``E_star``
and ``e_star`` both accepted). Validation happens in :func:`load_config` and
:func:`config_from_dict` within milliseconds and loads no numerical library: an unknown key,
a missing file, a value outside its bounds (each bound states its reason, e.g. the memory that
``loading.steps`` implies) raises :class:`ConfigError` as one line
``job.toml: material.E_star: expected a number in [100, 1e+13] Pa (...), got -2133000.0``.
The check that the loads are above the statistical model's pull-off force needs the surface
statistics; it runs right after the resolution scan (stage 2), before the BEM, and names
``loading.normal_loads``.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, TypeAlias

from asperity.length_units import UNIT_HELP, UNIT_SPELLINGS, length_unit_in_metres
from asperity.quantities import quantity
from asperity.schema import (
    Choice,
    ConfigError,
    Context,
    ExistingFile,
    Flag,
    Integer,
    Invalid,
    Key,
    Kind,
    ListOf,
    OrAuto,
    Schema,
    Section,
    Text,
    dump_toml,
    read_toml,
)
from asperity.statmodel.config import material_section
from asperity.statmodel.measured_curves import FIT_SOURCES
from asperity.statmodel.parameters import Material

#: A value of parsed TOML (or of the JSON key documents built from it): the configuration as
#: data, before validation or after :meth:`JobConfig.to_dict`.
TomlValue: TypeAlias = str | int | float | bool | None | list["TomlValue"] | dict[str, "TomlValue"]
#: A TOML table or JSON object: ``{name: value}``.
Document: TypeAlias = dict[str, TomlValue]

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["ConfigError", "JobConfig", "config_from_dict", "dump_toml", "load_config"]

#: Names of the shipped presets (``pipelines/presets/<name>.toml``).
PRESETS: tuple[str, ...] = ("default", "paper", "paper-two-step", "shear", "nominal")

DETREND_METHODS: tuple[str, ...] = ("none", "mean", "plane", "quadratic")
SYNTHETIC_RECIPES: tuple[str, ...] = ("paper_like", "paper_surface", "paper_spectrum")
#: ``surface.missing``: what a contact solve can use (a complete map).
MISSING_POLICIES: tuple[str, ...] = ("refuse", "fill-lowest", "interpolate")
#: ``surface.outliers``.
OUTLIER_RULES: tuple[str, ...] = ("mad", "percentile", "none")
#: ``fit.mode`` (the first is the default).
FIT_MODES: tuple[str, ...] = ("shape", "absolute")
#: Where lambda is fitted (``[fit] source``): measured A_r(F_x) curves (``measured.shear_area``),
#: measured friction tests F_x(drive) (``measured.friction_curves``), or both jointly.


@dataclass(frozen=True)
class JobMaterial(Material):
    """:class:`statmodel.Material` with the job's optional hardness (``[material] hardness``).

    Attributes
    ----------
    hardness : float or None
        Indentation hardness H of the rough solid, Pa (None: not given; the plasticity checks
        of the verdict, :mod:`asperity.statmodel.plausibility`, then do not run).
    """

    hardness: float | None = None

    def __post_init__(self) -> None:
        checked = Material(  # the statistical model's own bounds, converted to float
            self.e_star,
            self.work_of_adhesion,
            self.mode_mixity,
            self.shear_strength,
            self.equilibrium_distance,
        )
        for name in ("e_star", "work_of_adhesion", "mode_mixity", "shear_strength"):
            object.__setattr__(self, name, getattr(checked, name))
        object.__setattr__(self, "equilibrium_distance", checked.equilibrium_distance)
        if self.hardness is not None:
            value = quantity("material.hardness").check(self.hardness, "material.hardness")
            object.__setattr__(self, "hardness", value)


def job_material_section(defaults: Material) -> Section:
    """The job's ``[material]`` table: the statistical model's keys and ``hardness`` (Pa)."""
    section = material_section(defaults)
    hardness = Key("hardness", quantity("material.hardness").kind, None)
    return dataclasses.replace(section, build=JobMaterial, keys=(*section.keys, hardness))


#: The material of the paper's Figs 5 and 13 (used for absent ``[material]`` keys).
DEFAULT_MATERIAL = Material(
    e_star=2.133e6,
    work_of_adhesion=0.040,
    mode_mixity=0.03,
    shear_strength=0.13e6,
    equilibrium_distance=0.2e-9,
)


@dataclass(frozen=True)
class SyntheticRecipe:
    """A seeded recipe for a synthetic surface (``topo.synthetic.<recipe>``).

    Attributes
    ----------
    recipe : str
        Generator name: ``"paper_like"`` (:func:`topo.synthetic.paper_like`, the default job)
        ``"paper_spectrum"`` (:func:`topo.synthetic.paper_spectrum`, the paper presets'
        Gaussian stand-in) or ``"paper_surface"`` (:func:`topo.synthetic.paper_surface`, the
        capped recipe built to follow the paper's summit table).
    n : int
        Pixels per side (along x, axis 0, when ``ny`` is given).
    pixel_size : float
        Pixel size, m.
    seed : int
        Random seed: the same recipe always gives the same surface.
    ny : int or None
        Pixels along y (axis 1) of a non-square map, not for ``"paper_like"`` (the ``nominal``
        preset: 17,500 x 10,000, the paper's whole 35 x 20 mm interface at 2 um); None: ``n``.
    """

    recipe: str = "paper_like"
    n: int = 500
    pixel_size: float = 20e-6
    seed: int = 0
    ny: int | None = None

    def generator_arguments(self) -> dict[str, Any]:
        """The keywords of ``topo.synthetic.<recipe>`` (``ny`` only when given)."""
        kw: dict[str, Any] = {"n": self.n, "pixel_size": self.pixel_size, "seed": self.seed}
        if self.ny is not None:
            kw["ny"] = self.ny
        return kw


@dataclass(frozen=True)
class SurfaceConfig:
    """Where the surface comes from and how it is prepared (stages 1-2).

    Attributes
    ----------
    file : Path or None
        Surface file (any format :func:`topo.read_surface` reads); None for a synthetic recipe.
    channel : str or None
        Channel of a multi-channel file; None picks the height channel.
    pixel_size : float or None
        Pixel size, m, for formats that do not store one (.npy, plain text).
    unit : str or None
        Length unit of a plain-text file's numbers ("m", "mm", "um", "nm"): text states none
        and is refused without it (:func:`topo.read_surface`); None for every other format.
    synthetic : SyntheticRecipe or None
        The recipe used when ``file`` is None.
    detrend : str
        Levelling before any analysis: "none", "mean", "plane" or "quadratic".
    max_stride : int
        Resolution scan over strides 1..max_stride (the paper's decimation, Fig 12a-c).
    crop : tuple of int or None
        ``(x0, x1, y0, y1)``: pixel window kept (half-open, axis 0 then axis 1); None: all.
    missing : str
        Missing pixels (measured holes and masked outliers): "refuse", "fill-lowest" or
        "interpolate" (harmonic fill). The BEM needs a complete map.
    outliers : str
        Outlier rule on the levelled heights: "mad" (|h - median| > k x 1.4826 MAD),
        "percentile" (below the p-th or above the (100 - p)-th percentile) or "none".
    outlier_threshold : float
        k of the MAD rule or p (percent) of the percentile rule.
    outlier_action : str
        "mask" (the outliers become missing pixels) or "clip" (set to the rule's bounds).
    form_order : int or None
        Polynomial order of the form removed (0 mean, 1 plane, 2 quadratic, ... 8); None
        uses ``detrend``.
    profile_synthesis_n : int
        For a line profile as ``file``: pixels per side of the isotropic maps synthesised
        from its spectrum (pixel size: the profile's sampling interval, m).
    profile_seed : int
        For a line profile: the seed of the first synthesised map (the BEM's); realisation
        ``i`` uses ``profile_seed + i``.
    profile_realisations : int
        For a line profile with the BEM: maps synthesised and solved at the job's loads (the
        first is the BEM stage's; the spread of A_r over all of them is reported).
    """

    file: Path | None = None
    channel: str | None = None
    pixel_size: float | None = None
    unit: str | None = None
    synthetic: SyntheticRecipe | None = None
    detrend: str = "plane"
    max_stride: int = 20
    crop: tuple[int, int, int, int] | None = None
    missing: str = "interpolate"
    outliers: str = "mad"
    outlier_threshold: float = 10.0
    outlier_action: str = "mask"
    form_order: int | None = None
    profile_synthesis_n: int = 512
    profile_seed: int = 0
    profile_realisations: int = 3


@dataclass(frozen=True)
class LoadingConfig:
    """Loads and the shear path.

    Attributes
    ----------
    nominal_area : float
        Nominal contact area A_n of the experiment, m^2 (the BEM load is scaled to the map area).
    normal_loads : tuple of float
        Imposed normal loads F_z, N.
    max_tangential_displacement : float or None
        Largest delta_T, m; None ("auto") extends the path until full sliding.
    steps : int
        Number of delta_T steps (first one delta_T = 0).
    drive_stiffness : float or None
        Stiffness k of the tangential loading system in series with the contact, N/m (the
        paper's wire: 9200 N/m); None (absent): a rigid drive. The model's F_x(delta_T) is
        compared with measured friction tests at drive = delta_T + F_x / k
        (:mod:`asperity.statmodel.drive`).
    """

    nominal_area: float = 700e-6
    normal_loads: tuple[float, ...] = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)
    max_tangential_displacement: float | None = None
    steps: int = 201
    drive_stiffness: float | None = None


@dataclass(frozen=True)
class BemConfig:
    """The BEM reference (stage 3): the ``[bem]`` table, written once.

    Its fields but ``enabled`` are the settings of
    :func:`asperity.pipelines.stages.bem.bem_reference` (which takes this object) and the keys
    the stage declares (:data:`asperity.pipelines.stages.bem.SETTINGS` is derived from them).

    Attributes
    ----------
    tol : float
        Solver tolerance of every BEM solve (:class:`bem.SolverOptions` ``tol``).
    max_iter : int or None
        Iteration cap (None: the solver's default).
    area_tolerance : float
        Relative real-area change allowed between a grid and the next finer one; the coarsest
        grid whose area agrees with its refinement within this is used ("model no more than a
        scene needs").
    max_stride : int
        Coarsest decimation of the map tried by the refinement check.
    adhesive : bool
        Also run the adhesive solves (law ``adhesion``).
    enabled : bool
        Run the BEM at all; false needs a measured A_r(F_z) (``measured.normal_area``), which
        then alone chooses the effective resolution.
    boundary : str
        ``"periodic"`` (the map is one period of the interface, as the paper's Appendix B) or
        ``"free"`` (a finite specimen); see :mod:`asperity.bem.reference.grid_refinement`.
    coarsen : bool
        Let the sweeps use a coarser grid than the map when its area is within
        ``area_tolerance`` of the finest grid solved (false: the map's own resolution).
    adhesion : str
        The adhesive BEM's law: ``"maugis"`` (Maugis-Dugdale, attraction outside the contact:
        adhesive on loading, like the statistical model; default) or ``"pohrt-popov"`` (the
        paper's Appendix B criterion, whose loading branch carries no adhesion).
    adhesion_range : float or None
        Maugis-Dugdale range h_0, m; None ("auto" in the job file): the shortest range whose
        cohesive zone the grid resolves (:mod:`asperity.bem.reference.adhesion_range`).
    max_refinement : int
        The discretisation error: the check load is solved again on the grid used
        Fourier-interpolated by 2 and 4 (same roughness,
        :mod:`asperity.bem.reference.interpolated_refinement`), up to this factor (1: no estimate).
    refinement_pixels : int
        Largest grid of a refinement solve, pixels (a level beyond it is left out; when even
        the x2 grid of the whole map is larger, a centred window is refined).
    """

    tol: float = 1e-6
    max_iter: int | None = None
    area_tolerance: float = 0.05
    max_stride: int = 4
    adhesive: bool = True
    enabled: bool = True
    boundary: str = "periodic"
    coarsen: bool = True
    adhesion: str = "maugis"
    adhesion_range: float | None = None
    max_refinement: int = 4
    refinement_pixels: int = 2048 * 2048


def bem_settings(settings: BemConfig | None, caller: str, keywords: Mapping[str, Any]) -> BemConfig:
    """``settings`` (default ``BemConfig()``) with settings given the 0.3 way, as keywords of
    ``caller`` (e.g. ``bem_reference(..., max_stride=2)``): they warn once
    (``DeprecationWarning`` naming the fields; removed in asperity 0.5) and replace their
    fields. A keyword that is not a setting is a TypeError, as for any function."""
    settings = BemConfig() if settings is None else settings
    if not keywords:
        return settings
    known = {f.name for f in dataclasses.fields(BemConfig)} - {"enabled"}
    unknown = sorted(set(keywords) - known)
    if unknown:
        raise TypeError(f"{caller}() got an unexpected keyword argument {unknown[0]!r}")
    given = ", ".join(f"{name}=..." for name in keywords)
    fields = ", ".join(f"{name}={value!r}" for name, value in keywords.items())
    warnings.warn(
        f"{caller}({given}) is deprecated since asperity 0.4 and will be removed in 0.5: "
        f"pass settings=BemConfig({fields})",
        DeprecationWarning,
        stacklevel=3,
    )
    return dataclasses.replace(settings, **keywords)


#: ``bem_shear.law``: chi_T of the mixed-mode edge law (:class:`asperity.bem.MixedModeLaw`
#: ``tangential_energy``): "pc", the paper's K_II (chi_T = chi), or "cerruti", the energy of the
#: Cerruti patch (chi_T = 1.5 chi; docs/bem_shear.md).
SHEAR_LAWS: tuple[str, ...] = ("pc", "cerruti")


#: ``bem_shear.preload``: the state before shear (:class:`BemShearConfig`).
SHEAR_PRELOADS = ("reference", "pohrt-popov")


@dataclass(frozen=True)
class BemShearConfig:
    """The shear BEM stage (``[bem_shear]``, :mod:`asperity.pipelines.stages.bem_shear`).

    Absent from a job file, the section is None on :class:`JobConfig` and the stage is off.

    Attributes
    ----------
    enabled : bool
        Run the stage (default false: minutes on the default surface, docs/job.md).
    loads : tuple of float or None
        Experiment loads F_z (N) sheared, each one of ``loading.normal_loads``; None ("auto"):
        all of them.
    stride : int or None
        The map decimated by this stride is the grid of the shear solves; None ("auto", the
        default): the BEM reference's stride (``bem`` stage), so that the shear is judged on
        the grid the model was calibrated against.
    grid_check : bool
        Solve on coarser grids too (``check_grids`` of them): the discretisation error;
        false is ``check_grids = 0``.
    check_grids : int
        Coarser grids solved with ``grid_check`` (strides x 2, x 4, x 8): with two, the grid
        error is Richardson's with the observed order (Roache's grid convergence index); with
        one, first order and a safety factor 3.
    preload : str
        The state before shear: ``"reference"`` (default) the BEM reference's adhesive solve at
        F_z on the grid (its law: the Maugis-Dugdale loading branch at its range h_0, or
        Pohrt-Popov's loading branch), settled under the mixed-mode law, so that
        A_r(F_x = 0) is the reference's; ``"pohrt-popov"`` the Pohrt-Popov overload-unload
        preload (the unloading branch; path-dependent on coarse grids).
    steps : int
        delta_T values per curve up to its planned end, the first at 0.
    path_extension : float
        While a junction still sticks at the planned end, the path goes on with the same step
        up to this multiple of it (1: it stops there); beyond it, a warning.
    max_displacement : float or None
        Last delta_T, m; None ("auto"): :data:`~asperity.pipelines.stages.bem_shear.PATH_FACTOR`
        times the model's sliding displacement at that load.
    law : str
        chi_T of the paper's mixed-mode law (:data:`SHEAR_LAWS`); lambda and tau_0 are the
        job's.
    tol : float
        Tolerance of the conjugate-gradient solves (:class:`asperity.bem.ShearOptions`).
    """

    enabled: bool = False
    loads: tuple[float, ...] | None = None
    stride: int | None = None
    grid_check: bool = True
    steps: int = 40
    max_displacement: float | None = None
    law: str = "pc"
    tol: float = 1e-6
    check_grids: int = 2
    preload: str = "reference"
    path_extension: float = 3.0

    @property
    def coarser_grids(self) -> int:
        """Coarser grids solved: ``check_grids``, none without ``grid_check``."""
        return self.check_grids if self.grid_check else 0


@dataclass(frozen=True)
class StatmodelConfig:
    """Accuracy of the statistical model (stages 4-6).

    Attributes
    ----------
    area_tolerance : float
        Relative change of A_r and F_x allowed between a quadrature setting and the next finer
        one; the coarsest passing setting is used.
    """

    area_tolerance: float = 1e-4


@dataclass(frozen=True)
class ShearCurveFile:
    """One measured A_r(F_x) file (columns ``tangential_force`` (N), ``real_area`` (m^2)).

    ``normal_load`` is None for a long file with its own ``normal_load`` column.
    """

    file: Path
    normal_load: float | None = None


@dataclass(frozen=True)
class MeasuredConfig:
    """Optional measurements to calibrate against (CSV, SI, with a header).

    Attributes
    ----------
    normal_area : Path or None
        A_r(F_z): columns ``normal_load`` (N), ``real_area`` (m^2).
    shear_area : tuple of ShearCurveFile
        A_r(F_x) curves: one file per normal load, or one long file with a ``normal_load`` column.
    friction_curves : tuple of ShearCurveFile
        Friction tests F_x(drive): columns ``drive_displacement`` (m), ``tangential_force`` (N)
        (and ``normal_load``, N, in a long file); files given as ``shear_area``
        (:mod:`asperity.pipelines.measured_friction`).
    """

    normal_area: Path | None = None
    shear_area: tuple[ShearCurveFile, ...] = ()
    friction_curves: tuple[ShearCurveFile, ...] = ()


@dataclass(frozen=True)
class FitConfig:
    """The lambda fit (stage 5).

    Attributes
    ----------
    mode_mixity_bounds : tuple of float
        Search interval for lambda.
    mode : str
        "shape" (default: A_r/A_r(F_x=0), the paper's shape of the area reduction; a measured
        level offset does not bias lambda) or "absolute" (A_r itself).
    trim_after_first_peak : bool
        Cut each measured curve after its first static peak of F_x (the stick-slip tail).
    source : str
        What lambda is fitted to (:data:`FIT_SOURCES`): "area" (default: the A_r(F_x) curves,
        ``measured.shear_area``), "friction" (the friction tests F_x(drive),
        ``measured.friction_curves``, through ``loading.drive_stiffness``) or "joint" (both,
        each weighted by its own residual variance); see
        :mod:`asperity.statmodel.lambda_fit_friction`.
    """

    mode_mixity_bounds: tuple[float, float] = (1e-4, 1.0)
    mode: str = "shape"
    trim_after_first_peak: bool = True
    source: str = "area"


@dataclass(frozen=True)
class RunConfig:
    """Execution: ``workers`` processes for the sweeps (1 = in this process); ``compute_all``
    computes every stage even when the verdict is known invalid before the BEM (by default
    the job stops there: :mod:`asperity.pipelines.stages.early_verdict`)."""

    workers: int = 1
    compute_all: bool = False


#: Figure formats ``[report] formats`` accepts (matplotlib writers without extra packages).
FIGURE_FORMATS: tuple[str, ...] = ("png", "svg", "pdf")


@dataclass(frozen=True)
class ReportConfig:
    """Figures: ``formats`` written (each figure in each), ``dpi`` of raster output (PNG)."""

    formats: tuple[str, ...] = ("png",)
    dpi: int = 150


@dataclass(frozen=True)
class JobConfig:
    """The whole resolved configuration of ``asperity run``."""

    surface: SurfaceConfig
    material: Material
    loading: LoadingConfig
    bem: BemConfig
    statmodel: StatmodelConfig
    measured: MeasuredConfig
    fit: FitConfig
    run: RunConfig
    report: ReportConfig = ReportConfig()
    #: None when the job file has no ``[bem_shear]`` table (the stage is then off).
    bem_shear: BemShearConfig | None = None
    source: str = "<dict>"
    #: The ``section.key`` names the file gave (the rest are defaults): a line profile has no
    #: area, so its job must give ``loading.nominal_area`` itself.
    given_keys: frozenset[str] = field(default_factory=frozenset, compare=False)

    def sections(self) -> dict[str, object]:
        """The built sections by table name."""
        return {section.name: getattr(self, section.name) for section in JOB_SCHEMA.sections}

    def to_dict(self) -> Document:
        """The resolved configuration as TOML data (documented spellings, paths as strings)."""
        return JOB_SCHEMA.plain(self.sections())

    def to_toml(self) -> str:
        """The resolved configuration as TOML text (defaults filled in, paths absolute)."""
        return dump_toml(self.to_dict())

    def key_document(self) -> Document:
        """Every key as plain data, files by path and SHA-256: what the stage keys hash, so
        a changed file recomputes the stages that read it."""
        return JOB_SCHEMA.document(self.sections())


@dataclass(frozen=True)
class ShearFiles(Kind):
    """``measured.shear_area``: one long file, or a list of ``{normal_load, file}`` tables."""

    def convert(self, value: object, context: Context) -> tuple[ShearCurveFile, ...]:
        if isinstance(value, str):
            return (ShearCurveFile(ExistingFile().convert(value, context)),)
        if not isinstance(value, list):
            raise Invalid('a file name or a list of {normal_load = N, file = "curve.csv"} tables')
        return tuple(self._item(i, item, context) for i, item in enumerate(value))

    @staticmethod
    def _item(i: int, item: object, context: Context) -> ShearCurveFile:
        if not isinstance(item, Mapping) or set(item) != {"normal_load", "file"}:
            raise Invalid('a table {normal_load = N, file = "curve.csv"}', f"[{i}]", item)
        try:  # the load first, then the file (the error names the first bad one)
            load = LOAD.convert(item["normal_load"], context)
        except Invalid as exc:
            raise Invalid(exc.expected, f"[{i}].normal_load", item["normal_load"]) from None
        try:
            file = ExistingFile().convert(item["file"], context)
        except Invalid as exc:
            raise Invalid(exc.expected, f"[{i}].file", item["file"]) from None
        return ShearCurveFile(file, load)

    def plain(self, value: tuple[ShearCurveFile, ...]) -> TomlValue:
        if not value:
            return None
        if len(value) == 1 and value[0].normal_load is None:
            return str(value[0].file)
        return [{"normal_load": c.normal_load, "file": str(c.file)} for c in value]

    def document(self, value: tuple[ShearCurveFile, ...]) -> TomlValue:
        return [[c.normal_load, ExistingFile().document(c.file)] for c in value]


@dataclass(frozen=True)
class CropPixels(Kind):
    """``surface.crop``: ``[x0, x1, y0, y1]``, half-open pixel ranges along axis 0 and 1."""

    def convert(self, value: object, context: Context) -> tuple[int, ...]:
        pixels = ListOf(Integer(0, 10**7, why="a pixel index"), 4, 4).convert(value, context)
        if not (pixels[0] < pixels[1] and pixels[2] < pixels[3]):
            raise Invalid("[x0, x1, y0, y1] with x0 < x1 and y0 < y1 (pixels)", "", value)
        return pixels

    def plain(self, value: tuple[int, ...] | None) -> TomlValue:
        return None if value is None else list(value)

    def document(self, value: tuple[int, ...] | None) -> TomlValue:
        return self.plain(value)


#: One normal load, N.
LOAD = quantity("loading.normal_load").kind
#: A pixel size, m.
PIXEL = quantity("surface.pixel_size").kind


def _bounded(key: str, default: float | int | None) -> Key:
    """The key ``table.name`` of ``key``, bounded by its entry of the shared quantities."""
    return Key(key.rsplit(".", 1)[1], quantity(key).kind, default)


def _one_surface_source(values: dict[str, Any]) -> None:
    if (values["file"] is None) == (values["synthetic"] is None):
        raise Invalid("exactly one of surface.file and a [surface.synthetic] recipe", "file")


def _percentile_below_half(values: dict[str, Any]) -> None:
    if values["outliers"] == "percentile" and not values["outlier_threshold"] < 50:
        raise Invalid(
            "a percentile p < 50 with outliers = 'percentile'",
            "outlier_threshold",
            values["outlier_threshold"],
        )


def _surface_checks(values: dict[str, Any]) -> None:
    _one_surface_source(values)
    _percentile_below_half(values)


def _ordered_bounds(values: dict[str, Any]) -> None:
    low, high = values["mode_mixity_bounds"]
    if not low < high:
        raise Invalid("[low, high] with 0 < low < high <= 1", "mode_mixity_bounds", [low, high])


#: The length-unit spellings ``[surface] unit`` accepts for a plain-text file: those of the
#: command line's ``--unit`` (one table, :data:`asperity.topo.io.units.UNIT_SPELLINGS`; long
#: names also in any case and plural).
TEXT_UNITS = tuple(spelling for group in UNIT_SPELLINGS.values() for spelling in group)


@dataclass(frozen=True)
class LengthUnit(Kind):
    """A length unit, spelt as on the command line (:data:`TEXT_UNITS`, long names in any
    case, singular or plural); kept as written, the reader converts it to metres."""

    def convert(self, value: Any, context: Context) -> str:
        if not isinstance(value, str) or length_unit_in_metres(value) is None:
            raise Invalid(f"a length unit: {UNIT_HELP}")
        return value


def _rectangular_recipe(values: dict[str, Any]) -> None:
    if values["ny"] is not None and values["recipe"] == "paper_like":
        raise Invalid("ny only with recipe = 'paper_surface' or 'paper_spectrum'", "ny")


SYNTHETIC = Section(
    "surface.synthetic",
    SyntheticRecipe,
    (
        Key("recipe", Choice(SYNTHETIC_RECIPES), "paper_like"),
        _bounded("surface.synthetic.n", SyntheticRecipe.n),
        Key("pixel_size", PIXEL, SyntheticRecipe.pixel_size),
        _bounded("surface.synthetic.seed", 0),
        _bounded("surface.synthetic.ny", None),
    ),
    check=_rectangular_recipe,
)

JOB_SCHEMA = Schema(
    (
        Section(
            "surface",
            SurfaceConfig,
            (
                Key("file", ExistingFile(), None),
                Key("channel", Text(), None),
                Key("pixel_size", PIXEL, None),
                Key("unit", LengthUnit(), None),
                Key("synthetic", SYNTHETIC, None),
                Key("detrend", Choice(DETREND_METHODS), "plane"),
                _bounded("surface.max_stride", SurfaceConfig.max_stride),
                Key(
                    "crop",
                    CropPixels(),
                    None,
                ),
                Key("missing", Choice(MISSING_POLICIES), SurfaceConfig.missing),
                Key("outliers", Choice(OUTLIER_RULES), SurfaceConfig.outliers),
                _bounded("surface.outlier_threshold", SurfaceConfig.outlier_threshold),
                Key("outlier_action", Choice(("mask", "clip")), SurfaceConfig.outlier_action),
                _bounded("surface.form_order", None),
                _bounded("surface.profile_synthesis_n", SurfaceConfig.profile_synthesis_n),
                _bounded("surface.profile_seed", SurfaceConfig.profile_seed),
                _bounded("surface.profile_realisations", SurfaceConfig.profile_realisations),
            ),
            required=True,
            check=_surface_checks,
        ),
        job_material_section(DEFAULT_MATERIAL),
        Section(
            "loading",
            LoadingConfig,
            (
                _bounded("loading.nominal_area", LoadingConfig.nominal_area),
                Key(
                    "normal_loads",
                    ListOf(LOAD, 1, 100, why="each load is a BEM solve and a shear curve"),
                    LoadingConfig.normal_loads,
                ),
                Key(
                    "max_tangential_displacement",
                    OrAuto(quantity("loading.max_tangential_displacement").kind),
                    None,
                ),
                _bounded("loading.steps", LoadingConfig.steps),
                _bounded("loading.drive_stiffness", None),
            ),
        ),
        Section(
            "bem",
            BemConfig,
            (
                _bounded("bem.tol", BemConfig.tol),
                _bounded("bem.max_iter", None),
                _bounded("bem.area_tolerance", BemConfig.area_tolerance),
                _bounded("bem.max_stride", BemConfig.max_stride),
                Key("adhesive", Flag(), BemConfig.adhesive),
                Key("enabled", Flag(), BemConfig.enabled),
                Key("boundary", Choice(("periodic", "free")), BemConfig.boundary),
                Key("coarsen", Flag(), BemConfig.coarsen),
                Key("adhesion", Choice(("maugis", "pohrt-popov")), BemConfig.adhesion),
                Key("adhesion_range", OrAuto(quantity("bem.adhesion_range").kind), None),
                _bounded("bem.max_refinement", BemConfig.max_refinement),
                _bounded("bem.refinement_pixels", BemConfig.refinement_pixels),
            ),
        ),
        Section(
            "bem_shear",
            BemShearConfig,
            (
                Key("enabled", Flag(), BemShearConfig.enabled),
                Key(
                    "loads",
                    OrAuto(ListOf(LOAD, 1, 100, why="each load is a shear curve")),
                    None,
                ),
                Key("stride", OrAuto(quantity("bem_shear.stride").kind), None),
                Key("grid_check", Flag(), BemShearConfig.grid_check),
                _bounded("bem_shear.check_grids", BemShearConfig.check_grids),
                Key("preload", Choice(SHEAR_PRELOADS), BemShearConfig.preload),
                _bounded("bem_shear.steps", BemShearConfig.steps),
                _bounded("bem_shear.path_extension", BemShearConfig.path_extension),
                Key(
                    "max_displacement",
                    OrAuto(quantity("bem_shear.max_displacement").kind),
                    None,
                ),
                Key("law", Choice(SHEAR_LAWS), BemShearConfig.law),
                _bounded("bem_shear.tol", BemShearConfig.tol),
            ),
        ),
        Section(
            "statmodel",
            StatmodelConfig,
            (_bounded("statmodel.area_tolerance", StatmodelConfig.area_tolerance),),
        ),
        Section(
            "measured",
            MeasuredConfig,
            (
                Key("normal_area", ExistingFile(), None),
                Key("shear_area", ShearFiles(), ()),
                Key("friction_curves", ShearFiles(), ()),
            ),
        ),
        Section(
            "fit",
            FitConfig,
            (
                Key(
                    "mode_mixity_bounds",
                    ListOf(quantity("fit.mode_mixity_bounds").kind, 2, 2),
                    FitConfig.mode_mixity_bounds,
                ),
                Key("mode", Choice(FIT_MODES), FitConfig.mode),
                Key("trim_after_first_peak", Flag(), FitConfig.trim_after_first_peak),
                Key("source", Choice(FIT_SOURCES), FitConfig.source),
            ),
            check=_ordered_bounds,
        ),
        Section(
            "run",
            RunConfig,
            (
                _bounded("run.workers", RunConfig.workers),
                Key("compute_all", Flag(), RunConfig.compute_all),
            ),
        ),
        Section(
            "report",
            ReportConfig,
            (
                Key(
                    "formats",
                    ListOf(Choice(FIGURE_FORMATS), 1, len(FIGURE_FORMATS)),
                    ReportConfig.formats,
                ),
                _bounded("report.dpi", ReportConfig.dpi),
            ),
        ),
    )
)


# --------------------------------------------------------------------------------------------
# reading
# --------------------------------------------------------------------------------------------


def preset_text(name: str) -> str:
    """The TOML text of a shipped preset (``"default"`` or ``"paper"``)."""
    if name not in PRESETS:
        raise ConfigError(f"--preset: expected one of {', '.join(PRESETS)}, got {name!r}")
    return resources.files("asperity.pipelines.presets").joinpath(f"{name}.toml").read_text("utf-8")


def load_preset(name: str) -> JobConfig:
    """The resolved configuration of a shipped preset."""
    data = tomllib.loads(preset_text(name))
    presets = Path(str(resources.files("asperity.pipelines.presets")))  # its measured CSV files
    return config_from_dict(data, source=f"preset {name}", base_dir=presets)


def load_config(path: str | Path) -> JobConfig:
    """Read and validate a TOML job configuration.

    Relative file names inside it are resolved against the file's directory.

    Raises
    ------
    ConfigError
        Unreadable file or TOML, unknown or missing key, wrong type, value out of bounds,
        missing file.
    """
    path = Path(path)
    data = read_toml(path, "configuration")
    return config_from_dict(data, source=str(path), base_dir=path.resolve().parent)


def config_from_dict(
    data: Mapping[str, TomlValue], *, source: str = "<dict>", base_dir: str | Path = "."
) -> JobConfig:
    """Validate plain TOML data into a :class:`JobConfig` (defaults fill missing keys).

    Parameters
    ----------
    data : mapping
        The parsed TOML tables.
    source : str
        Name used in error messages (the file name).
    base_dir : path
        Directory against which relative file names are resolved.

    Raises
    ------
    ConfigError
        ``source: section.key: expected ..., got ...``.
    """
    sections = JOB_SCHEMA.read(data, source=source, base_dir=base_dir)
    if not sections["bem"].enabled and sections["measured"].normal_area is None:
        raise Context(source).fail(
            "bem.enabled",
            "true unless measured.normal_area gives a measured A_r(F_z) to calibrate against",
            False,
        )
    _compressive_loads_for_the_bem(sections, source)
    _fit_source_has_its_curves(sections, source)
    if "bem_shear" not in data:  # the optional stage's table absent: the stage is off
        sections["bem_shear"] = None
    else:
        _shear_loads_among_the_job_loads(sections, source)
    return JobConfig(**sections, source=source, given_keys=given_keys(data))


def _fit_source_has_its_curves(sections: Mapping[str, Any], source: str) -> None:
    """``fit.source`` "friction" needs ``measured.friction_curves``; "joint" needs them and
    ``measured.shear_area`` (the curves lambda is fitted to must be given)."""
    fit, measured = sections["fit"].source, sections["measured"]
    needs = {"friction": ("friction_curves",), "joint": ("friction_curves", "shear_area")}
    for key in needs.get(fit, ()):
        if not getattr(measured, key):
            raise Context(source).fail(
                "fit.source",
                f"'area' unless measured.{key} gives the curves lambda is fitted to "
                f"(source {fit!r} fits "
                + ("the friction tests" if fit == "friction" else "both measurements")
                + ")",
                fit,
            )


def _compressive_loads_for_the_bem(sections: Mapping[str, Any], source: str) -> None:
    """Loads <= 0 N are refused when the BEM runs: its non-adhesive reference sweep (the
    Polonsky-Keer solver under load control) has no contact to solve at a tensile or zero
    load. The user's own value is quoted, before any stage runs."""
    if not sections["bem"].enabled:
        return  # the statistical model alone: loads above its pull-off force (after stage 2)
    loads = sections["loading"].normal_loads
    tensile = [f for f in loads if not f > 0]
    if tensile:
        raise Context(source).fail(
            "loading.normal_loads",
            "loads > 0 N while bem.enabled = true (the non-adhesive BEM reference solves "
            "compressive loads only; set bem.enabled = false with a measured A_r(F_z) to "
            "predict at tensile loads above the pull-off force)",
            tensile[0],
        )


def _shear_loads_among_the_job_loads(sections: Mapping[str, Any], source: str) -> None:
    """``bem_shear.loads`` must be loads of ``loading.normal_loads`` (the model's shear curves
    it is compared with are computed there), and > 0 N (the preload is compressive)."""
    shear, loads = sections["bem_shear"], sections["loading"].normal_loads
    for value in shear.loads or ():
        if not any(math.isclose(value, f, rel_tol=1e-9) for f in loads):
            raise Context(source).fail(
                "bem_shear.loads",
                "loads among loading.normal_loads ("
                + ", ".join(f"{f:g}" for f in loads)
                + " N: the model's shear curves are computed there)",
                value,
            )
    if shear.enabled:
        tensile = [f for f in (shear.loads or loads) if not f > 0]
        if tensile:
            raise Context(source).fail(
                "bem_shear.loads",
                "loads > 0 N (the shear BEM holds a compressive preload)",
                tensile[0],
            )


def given_keys(data: Mapping[str, TomlValue]) -> frozenset[str]:
    """The ``section.key`` names present in parsed TOML data (top-level tables only)."""
    return frozenset(
        f"{section}.{key}"
        for section, table in data.items()
        if isinstance(table, Mapping)
        for key in table
    )
