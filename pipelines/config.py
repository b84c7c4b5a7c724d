"""The job configuration: a TOML file read, checked and resolved before any heavy work.

Every value is in SI units (m, Pa, N, J/m^2). A configuration names either a surface file
(any format :func:`topo.read_surface` reads) or a seeded synthetic recipe, the material, the
loads, the solver tolerances and, optionally, measured curves to calibrate against.

Validation happens in :func:`load_config` and :func:`config_from_dict` within milliseconds: an
unknown key, a missing file, a negative modulus or a malformed table raises :class:`ConfigError`
naming the key (``material.E_star``) and what was expected. The check that the loads are above
the statistical model's pull-off force needs the surface statistics; it runs right after the
resolution scan (stage 2), before the BEM, and names ``loading.normal_loads``.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import math
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from asperity.errors import InputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

#: Names of the shipped presets (``pipelines/presets/<name>.toml``).
PRESETS: tuple[str, ...] = ("default", "paper")

DETREND_METHODS: tuple[str, ...] = ("none", "mean", "plane", "quadratic")
SYNTHETIC_RECIPES: tuple[str, ...] = ("paper_like",)


class ConfigError(InputError):
    """A configuration value is wrong; the message names the file and the key."""


@dataclass(frozen=True)
class SyntheticRecipe:
    """A seeded recipe for a synthetic surface (``topo.synthetic.<recipe>``).

    Attributes
    ----------
    recipe : str
        Generator name, ``"paper_like"`` (:func:`topo.synthetic.paper_like`).
    n : int
        Pixels per side.
    pixel_size : float
        Pixel size, m.
    seed : int
        Random seed: the same recipe always gives the same surface.
    """

    recipe: str = "paper_like"
    n: int = 500
    pixel_size: float = 20e-6
    seed: int = 0


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
    synthetic : SyntheticRecipe or None
        The recipe used when ``file`` is None.
    detrend : str
        Levelling before any analysis: "none", "mean", "plane" or "quadratic".
    max_stride : int
        Resolution scan over strides 1..max_stride (the paper's decimation, Fig 12a-c).
    """

    file: Path | None = None
    channel: str | None = None
    pixel_size: float | None = None
    synthetic: SyntheticRecipe | None = None
    detrend: str = "plane"
    max_stride: int = 20


@dataclass(frozen=True)
class MaterialConfig:
    """Material and interface parameters (``statmodel.Material``), SI units.

    Attributes
    ----------
    E_star : float
        Effective elastic modulus E*, Pa.
    work_of_adhesion : float
        w, J/m^2.
    mode_mixity : float
        lambda in [0, 1]; the starting value of the fit when measured shear curves are given.
    shear_strength : float
        tau0, Pa (sliding junctions, E:Hertz_theory).
    equilibrium_distance : float
        epsilon, m (Tabor parameter).
    """

    E_star: float = 2.133e6
    work_of_adhesion: float = 0.040
    mode_mixity: float = 0.03
    shear_strength: float = 0.13e6
    equilibrium_distance: float = 0.2e-9

    @property
    def e_star(self) -> float:
        """E*, Pa (the spelling of :class:`statmodel.Material`)."""
        return self.E_star

    def to_material(self, mode_mixity: float | None = None) -> Any:
        """The :class:`statmodel.Material` of this table, optionally with another lambda."""
        from asperity.statmodel.parameters import Material

        return Material(
            e_star=self.E_star,
            work_of_adhesion=self.work_of_adhesion,
            mode_mixity=self.mode_mixity if mode_mixity is None else mode_mixity,
            shear_strength=self.shear_strength,
            equilibrium_distance=self.equilibrium_distance,
        )


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
    """

    nominal_area: float = 700e-6
    normal_loads: tuple[float, ...] = (0.56, 1.06, 1.58, 2.08, 2.57, 3.12)
    max_tangential_displacement: float | None = None
    steps: int = 201


@dataclass(frozen=True)
class BemConfig:
    """The BEM reference (stage 3).

    Attributes
    ----------
    tol : float
        Solver tolerance passed to :func:`bem.load_sweep`.
    max_iter : int or None
        Iteration cap (None: the solver's default).
    area_tolerance : float
        Relative real-area change allowed between a grid and the next finer one; the coarsest
        grid whose area agrees with its refinement within this is used ("model no more than a
        scene needs").
    max_stride : int
        Coarsest decimation of the map tried by the refinement check.
    adhesive : bool
        Also run the Pohrt-Popov adhesive sweep.
    enabled : bool
        Run the BEM at all; false needs a measured A_r(F_z) (``measured.normal_area``), which
        then alone chooses the effective resolution.
    """

    tol: float = 1e-6
    max_iter: int | None = None
    area_tolerance: float = 0.05
    max_stride: int = 4
    adhesive: bool = True
    enabled: bool = True


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
    """

    normal_area: Path | None = None
    shear_area: tuple[ShearCurveFile, ...] = ()


@dataclass(frozen=True)
class FitConfig:
    """The lambda fit (stage 5).

    Attributes
    ----------
    mode_mixity_bounds : tuple of float
        Search interval for lambda.
    """

    mode_mixity_bounds: tuple[float, float] = (1e-4, 1.0)


@dataclass(frozen=True)
class RunConfig:
    """Execution: ``workers`` processes for the sweeps (1 = in this process)."""

    workers: int = 1


@dataclass(frozen=True)
class JobConfig:
    """The whole resolved configuration of ``asperity run``."""

    surface: SurfaceConfig
    material: MaterialConfig
    loading: LoadingConfig
    bem: BemConfig
    statmodel: StatmodelConfig
    measured: MeasuredConfig
    fit: FitConfig
    run: RunConfig
    source: str = "<dict>"

    def to_dict(self) -> dict[str, Any]:
        """The resolved configuration as plain TOML-like data (paths as strings)."""
        return _plain(dataclasses.asdict(self))

    def to_toml(self) -> str:
        """The resolved configuration as TOML text (defaults filled in, paths absolute)."""
        data = self.to_dict()
        data.pop("source", None)
        data["measured"]["shear_area"] = [
            item["file"] if item["normal_load"] is None else item
            for item in data["measured"]["shear_area"]
        ]
        if len(data["measured"]["shear_area"]) == 1 and isinstance(
            data["measured"]["shear_area"][0], str
        ):
            data["measured"]["shear_area"] = data["measured"]["shear_area"][0]
        elif not data["measured"]["shear_area"]:
            del data["measured"]["shear_area"]
        return dump_toml(data)

    def key_document(self) -> dict[str, Any]:
        """The configuration as plain data with every file replaced by its path and SHA-256:
        what stage keys hash, so a changed file recomputes the stages that read it."""
        return _with_file_hashes(dataclasses.asdict(self))


def _file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(1 << 20):
            digest.update(block)
    return digest.hexdigest()


def _with_file_hashes(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _with_file_hashes(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_with_file_hashes(v) for v in value]
    if isinstance(value, Path):
        return {"path": str(value), "sha256": _file_sha256(value)}
    return value


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):  # a JSON string is a TOML basic string, once DEL is escaped
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return (
            "{"
            + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items() if v is not None)
            + "}"
        )
    raise TypeError(f"cannot write {value!r} as TOML")


def dump_toml(data: Mapping[str, Any], prefix: str = "") -> str:
    """Write nested plain data (tables, lists, str, numbers, bool; None omitted) as TOML."""
    lines: list[str] = []
    tables: list[tuple[str, Mapping[str, Any]]] = []
    for key, value in data.items():
        if value is None:
            continue
        if isinstance(value, Mapping):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {_toml_value(value)}")
    text = "\n".join(lines) + ("\n" if lines else "")
    for key, table in tables:
        name = f"{prefix}{key}"
        text += f"\n[{name}]\n" + dump_toml(table, prefix=name + ".")
    return text


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    return value


# --------------------------------------------------------------------------------------------
# reading
# --------------------------------------------------------------------------------------------


def preset_text(name: str) -> str:
    """The TOML text of a shipped preset (``"default"`` or ``"paper"``)."""
    if name not in PRESETS:
        raise ConfigError(f"unknown preset {name!r}; expected one of {', '.join(PRESETS)}")
    return resources.files("asperity.pipelines.presets").joinpath(f"{name}.toml").read_text("utf-8")


def load_preset(name: str) -> JobConfig:
    """The resolved configuration of a shipped preset."""
    data = tomllib.loads(preset_text(name))
    return config_from_dict(data, source=f"preset {name}", base_dir=Path.cwd())


def load_config(path: str | Path) -> JobConfig:
    """Read and validate a TOML job configuration.

    Relative file names inside it are resolved against the file's directory.

    Raises
    ------
    ConfigError
        Unreadable TOML, unknown or missing key, wrong type or value, missing file.
    """
    path = Path(path)
    try:
        text = path.read_text("utf-8")
    except FileNotFoundError as exc:
        raise ConfigError(f"{path}: configuration file not found") from exc
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from exc
    return config_from_dict(data, source=str(path), base_dir=path.resolve().parent)


class _Section:
    """Typed access to one TOML table that reports unknown and wrongly typed keys by name."""

    def __init__(self, data: Any, name: str, source: str):
        if not isinstance(data, Mapping):
            raise ConfigError(f"{source}: [{name}] must be a table")
        self.data = dict(data)
        self.name = name
        self.source = source
        self.used: set[str] = set()

    def key(self, key: str) -> str:
        return f"{self.name}.{key}"

    def fail(self, key: str, expected: str, value: Any = None) -> ConfigError:
        got = "" if value is None else f", got {value!r}"
        return ConfigError(f"{self.source}: {self.key(key)}: expected {expected}{got}")

    def get(self, key: str, default: Any) -> Any:
        self.used.add(key)
        return self.data.get(key, default)

    def number(
        self,
        key: str,
        default: float | None,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        allow_none: bool = False,
    ) -> float | None:
        value = self.get(key, default)
        if value is None and allow_none:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(key, "a number", value)
        value = float(value)
        if not math.isfinite(value):
            raise self.fail(key, "a finite number", value)
        if positive and value <= 0:
            raise self.fail(key, "a positive number", value)
        if nonnegative and value < 0:
            raise self.fail(key, "a non-negative number", value)
        return value

    def integer(
        self, key: str, default: int | None, *, minimum: int = 1, allow_none: bool = False
    ) -> int | None:
        value = self.get(key, default)
        if value is None and allow_none:
            return None
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(key, "an integer", value)
        if value < minimum:
            raise self.fail(key, f"an integer >= {minimum}", value)
        return int(value)

    def choice(self, key: str, default: str, choices: tuple[str, ...]) -> str:
        value = self.get(key, default)
        if value not in choices:
            raise self.fail(key, "one of " + ", ".join(repr(c) for c in choices), value)
        return value

    def boolean(self, key: str, default: bool) -> bool:
        value = self.get(key, default)
        if not isinstance(value, bool):
            raise self.fail(key, "true or false", value)
        return value

    def finish(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise ConfigError(
                f"{self.source}: unknown key {self.key(unknown[0])!r}"
                f" (known keys in [{self.name}]: {', '.join(sorted(self.used))})"
            )


def _existing_file(section: _Section, key: str, value: Any, base_dir: Path) -> Path:
    if not isinstance(value, str) or not value:
        raise section.fail(key, "a file name", value)
    path = Path(value).expanduser()
    if not path.is_absolute():
        path = base_dir / path
    if not path.is_file():
        raise ConfigError(f"{section.source}: {section.key(key)}: file not found: {path}")
    return path


def config_from_dict(
    data: Mapping[str, Any], *, source: str = "<dict>", base_dir: str | Path = "."
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
    """
    base_dir = Path(base_dir)
    data = copy.deepcopy(dict(data))
    top = _Section(data, "config", source)
    tables = {}
    for name in ("surface", "material", "loading", "bem", "statmodel", "measured", "fit", "run"):
        tables[name] = _Section(top.get(name, {}), name, source)
    unknown = sorted(set(data) - top.used)
    if unknown:
        raise ConfigError(
            f"{source}: unknown table or key {unknown[0]!r} (known: {', '.join(sorted(top.used))})"
        )

    surface = _surface(tables["surface"], base_dir)
    m = tables["material"]
    material = MaterialConfig(
        E_star=m.number("E_star", MaterialConfig.E_star, positive=True),
        work_of_adhesion=m.number(
            "work_of_adhesion", MaterialConfig.work_of_adhesion, nonnegative=True
        ),
        mode_mixity=m.number("mode_mixity", MaterialConfig.mode_mixity, nonnegative=True),
        shear_strength=m.number("shear_strength", MaterialConfig.shear_strength, nonnegative=True),
        equilibrium_distance=m.number(
            "equilibrium_distance", MaterialConfig.equilibrium_distance, positive=True
        ),
    )
    if material.mode_mixity > 1:
        raise m.fail("mode_mixity", "a number in [0, 1]", material.mode_mixity)
    m.finish()

    ld = tables["loading"]
    loads_raw = ld.get("normal_loads", list(LoadingConfig.normal_loads))
    if (
        not isinstance(loads_raw, list)
        or not loads_raw
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in loads_raw)
    ):
        raise ld.fail("normal_loads", "a non-empty list of numbers (N)", loads_raw)
    loads = tuple(float(v) for v in loads_raw)
    if not all(math.isfinite(v) for v in loads):
        raise ld.fail("normal_loads", "finite numbers", loads_raw)
    max_dt = ld.get("max_tangential_displacement", "auto")
    if max_dt == "auto":
        max_dt = None
    else:
        max_dt = ld.number("max_tangential_displacement", None, positive=True)
    loading = LoadingConfig(
        nominal_area=ld.number("nominal_area", LoadingConfig.nominal_area, positive=True),
        normal_loads=loads,
        max_tangential_displacement=max_dt,
        steps=ld.integer("steps", LoadingConfig.steps, minimum=3),
    )
    ld.finish()

    b = tables["bem"]
    bem = BemConfig(
        tol=b.number("tol", BemConfig.tol, positive=True),
        max_iter=b.integer("max_iter", None, allow_none=True),
        area_tolerance=b.number("area_tolerance", BemConfig.area_tolerance, positive=True),
        max_stride=b.integer("max_stride", BemConfig.max_stride),
        adhesive=b.boolean("adhesive", BemConfig.adhesive),
        enabled=b.boolean("enabled", BemConfig.enabled),
    )
    b.finish()

    s = tables["statmodel"]
    statmodel_cfg = StatmodelConfig(
        area_tolerance=s.number("area_tolerance", StatmodelConfig.area_tolerance, positive=True),
    )
    s.finish()

    measured = _measured(tables["measured"], base_dir)
    if not bem.enabled and measured.normal_area is None:
        raise ConfigError(
            f"{source}: bem.enabled: expected true unless measured.normal_area gives a measured "
            "A_r(F_z) to calibrate against, got false without it"
        )

    f = tables["fit"]
    bounds = f.get("mode_mixity_bounds", list(FitConfig.mode_mixity_bounds))
    if (
        not isinstance(bounds, list)
        or len(bounds) != 2
        or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in bounds)
        or not 0 < bounds[0] < bounds[1] <= 1
    ):
        raise f.fail("mode_mixity_bounds", "[low, high] with 0 < low < high <= 1", bounds)
    fit = FitConfig(mode_mixity_bounds=(float(bounds[0]), float(bounds[1])))
    f.finish()

    r = tables["run"]
    run = RunConfig(workers=r.integer("workers", RunConfig.workers))
    r.finish()

    return JobConfig(
        surface=surface,
        material=material,
        loading=loading,
        bem=bem,
        statmodel=statmodel_cfg,
        measured=measured,
        fit=fit,
        run=run,
        source=source,
    )


def _surface(s: _Section, base_dir: Path) -> SurfaceConfig:
    file_value = s.get("file", None)
    synthetic_value = s.get("synthetic", None)
    if file_value is not None and synthetic_value is not None:
        raise ConfigError(
            f"{s.source}: [surface] gives both surface.file and "
            "[surface.synthetic]; expected exactly one"
        )
    if file_value is None and synthetic_value is None:
        raise ConfigError(
            f"{s.source}: [surface] needs surface.file or a [surface.synthetic] recipe"
        )
    file = None if file_value is None else _existing_file(s, "file", file_value, base_dir)
    synthetic = None
    if synthetic_value is not None:
        t = _Section(synthetic_value, "surface.synthetic", s.source)
        synthetic = SyntheticRecipe(
            recipe=t.choice("recipe", "paper_like", SYNTHETIC_RECIPES),
            n=t.integer("n", SyntheticRecipe.n, minimum=8),
            pixel_size=t.number("pixel_size", SyntheticRecipe.pixel_size, positive=True),
            seed=t.integer("seed", 0, minimum=0),
        )
        t.finish()
    channel = s.get("channel", None)
    if channel is not None and not isinstance(channel, str):
        raise s.fail("channel", "a channel name", channel)
    result = SurfaceConfig(
        file=file,
        channel=channel,
        pixel_size=s.number("pixel_size", None, positive=True, allow_none=True),
        synthetic=synthetic,
        detrend=s.choice("detrend", "plane", DETREND_METHODS),
        max_stride=s.integer("max_stride", SurfaceConfig.max_stride),
    )
    s.finish()
    return result


def _measured(s: _Section, base_dir: Path) -> MeasuredConfig:
    normal = s.get("normal_area", None)
    normal_path = None if normal is None else _existing_file(s, "normal_area", normal, base_dir)
    shear = s.get("shear_area", None)
    curves: list[ShearCurveFile] = []
    if shear is None:
        pass
    elif isinstance(shear, str):
        curves.append(ShearCurveFile(_existing_file(s, "shear_area", shear, base_dir)))
    elif isinstance(shear, list):
        for i, item in enumerate(shear):
            key = f"shear_area[{i}]"
            if not isinstance(item, Mapping) or set(item) != {"normal_load", "file"}:
                raise s.fail(key, 'a table {normal_load = N, file = "curve.csv"}', item)
            load = item["normal_load"]
            if isinstance(load, bool) or not isinstance(load, (int, float)):
                raise s.fail(key + ".normal_load", "a number (N)", load)
            curves.append(
                ShearCurveFile(
                    _existing_file(s, key + ".file", item["file"], base_dir), float(load)
                )
            )
    else:
        raise s.fail("shear_area", "a file name or a list of {normal_load, file} tables", shear)
    s.finish()
    return MeasuredConfig(normal_area=normal_path, shear_area=tuple(curves))
