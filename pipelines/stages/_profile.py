"""A line profile as the job's input: telling a profile file from a map file, preparing the
profile, and the isotropic maps synthesised from its spectrum.

A stylus profile is one line of a surface. The job takes it as ``[surface] file`` under
Nayak's random-process theory (an isotropic Gaussian surface assumed; :mod:`asperity.topo`,
"Line profiles"): the resolution scan is the profile's (:func:`topo.profile_resolution_scan`),
and the maps the BEM and Persson's theory need are synthesised from the profile's spectrum
with random phases (:func:`topo.synthesise_from_profile`): ``surface.profile_synthesis_n``
pixels per side at the profile's sampling interval, realisation ``i`` seeded with
``surface.profile_seed + i``. A profile has no area: its job must give the experiment's
nominal area ``loading.nominal_area`` (m^2) itself (:func:`require_nominal_area`).
Lengths and heights in m.
"""

from __future__ import annotations

import functools
from pathlib import Path

from asperity import topo
from asperity.errors import InputError
from asperity.pipelines.config import ConfigError, JobConfig, SurfaceConfig

#: What the job calls the route of a line profile (the scan's ``method``).
PROFILE_METHOD = "nayak-profile"


@functools.lru_cache(maxsize=32)
def _file_is_profile(
    path: str,
    size: int,
    mtime_ns: int,
    channel: str | None,
    pixel_size: float | None,
    unit: str | None = None,
) -> bool:
    """Whether the file reads as a :class:`topo.LineProfile` (keyed by its size and mtime)."""
    surface = topo.read_surface(path, channel=channel, pixel_size=pixel_size, unit=unit)
    return isinstance(surface, topo.LineProfile)


def input_is_profile(config: SurfaceConfig) -> bool:
    """Whether ``[surface] file`` is a line profile (False for a synthetic recipe).

    The file is read once per size and modification time (cached); a file that cannot be
    read counts as no profile here, and the read-and-level stage reports why.
    """
    if config.file is None:
        return False
    path = Path(config.file)
    try:
        stat = path.stat()
        return _file_is_profile(
            str(path),
            stat.st_size,
            stat.st_mtime_ns,
            config.channel,
            config.pixel_size,
            config.unit,
        )
    except (InputError, OSError):
        return False


def profile_crop(config: SurfaceConfig) -> topo.CropWindow | None:
    """The crop of a profile: ``[x0, x1, 0, 1]`` keeps points x0..x1-1 (a profile has one row).

    Raises
    ------
    ConfigError
        A crop whose y range is not ``0, 1``.
    """
    if config.crop is None:
        return None
    x0, x1, y0, y1 = config.crop
    if (y0, y1) != (0, 1):
        raise ConfigError(
            f"surface.crop: expected [x0, x1, 0, 1] for a line profile (one row), "
            f"got {list(config.crop)}"
        )
    return topo.CropWindow((x0, x1), (None, None), "px")


def prepare_line_profile(
    profile: topo.LineProfile, config: SurfaceConfig, options: topo.PreparationOptions
) -> tuple[topo.LineProfile, dict]:
    """Prepare a profile as ``[surface]`` says (:func:`topo.prepare_profile`): ``options`` are
    the map's (form, outliers, missing) with the profile's crop (:func:`profile_crop`).

    Returns
    -------
    LineProfile, dict
        The prepared, complete profile (m) and its preparation record.

    Raises
    ------
    ConfigError
        Naming the ``surface.*`` key: a crop outside the profile, missing points with
        ``missing = "refuse"``, too few valid points for the form.
    """
    try:
        prepared, record = topo.prepare_profile(profile, options)
    except InputError as exc:
        key = "surface.crop" if config.crop is not None and "crop" in str(exc) else None
        key = key or ("surface.missing" if config.missing == "refuse" else "surface")
        raise ConfigError(f"{key}: {exc}") from exc
    return prepared, record


def synthesised_map(profile: topo.LineProfile, config: SurfaceConfig, index: int) -> topo.HeightMap:
    """Realisation ``index`` (seed ``profile_seed + index``) of the isotropic map synthesised
    from the profile's spectrum: ``profile_synthesis_n`` pixels per side, pixel ``profile.dx``
    (m), periodic."""
    seed = int(config.profile_seed) + int(index)
    return topo.synthesise_from_profile(profile, n=config.profile_synthesis_n, seed=seed)


def synthesis_record(
    profile: topo.LineProfile, config: SurfaceConfig
) -> dict[str, str | int | float]:
    """What the synthesised maps are, for the provenance and the report (SI units)."""
    n = int(config.profile_synthesis_n)
    return {
        "method": "isotropic, random phases, 2D PSD by Abel inversion of the profile's PSD",
        "profile_points": int(profile.nx),
        "profile_dx": float(profile.dx),
        "profile_length": float(profile.lx),
        "n": n,
        "pixel_size": float(profile.dx),
        "map_size": float(n * profile.dx),
        "seed": int(config.profile_seed),
        "longest_wavelength_kept": float(min(n, profile.nx) * profile.dx),
    }


def require_nominal_area(config: JobConfig) -> None:
    """A line profile has no area: refuse a job that does not give ``loading.nominal_area``.

    Raises
    ------
    ConfigError
        ``job.toml: loading.nominal_area: expected ..., got no value``.
    """
    if "loading.nominal_area" in config.given_keys:
        return
    raise ConfigError(
        f"{config.source}: loading.nominal_area: expected the experiment's nominal contact "
        "area A_n in m^2, given in the job: a line profile has no area (the default "
        f"{config.loading.nominal_area:g} m^2 is the paper's specimen, not yours), got none"
    )
