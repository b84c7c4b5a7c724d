"""Stages 1 and 2: read and level the surface, then scan its summit statistics over resolution.

Stage 1 (:func:`read_and_level`) gives a levelled :class:`topo.HeightMap` from a file (any
format :func:`topo.read_surface` reads) or from the seeded synthetic recipe.
Stage 2 (:func:`scan_resolutions`) runs :func:`topo.resolution_scan`: eta, R and sigma_s of the
map decimated with strides 1..K (Appendix A, Fig 12a-c) and the paper's fits.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import numpy as np

from asperity import topo
from asperity.pipelines.config import SurfaceConfig
from asperity.pipelines.store import StageRecord, Variable

#: Fewest pixels per side kept by the coarsest resolution of the scan.
MIN_SCAN_PIXELS = 16


def file_sha256(path: str | Path, chunk: int = 1 << 20) -> str:
    """SHA-256 hex digest of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while block := handle.read(chunk):
            digest.update(block)
    return digest.hexdigest()


def input_sha256(config: SurfaceConfig) -> str:
    """Provenance hash of the input: the file's SHA-256, or that of the synthetic recipe."""
    if config.file is not None:
        return file_sha256(config.file)
    recipe = json.dumps(config.synthetic.__dict__, sort_keys=True)
    return hashlib.sha256(("synthetic:" + recipe).encode()).hexdigest()


def load_surface(config: SurfaceConfig) -> topo.HeightMap:
    """The raw surface of the configuration (file or synthetic recipe), heights in m."""
    if config.file is not None:
        surface = topo.read_surface(
            config.file, channel=config.channel, pixel_size=config.pixel_size
        )
        if not isinstance(surface, topo.HeightMap):
            raise ValueError(
                f"{config.file}: surface.file is a 1D line profile; the job needs "
                "a 2D height map (summit statistics and the BEM are 2D)"
            )
        return surface
    recipe = config.synthetic
    generator = getattr(topo.synthetic, recipe.recipe)
    return generator(n=recipe.n, pixel_size=recipe.pixel_size, seed=recipe.seed)


def read_and_level(config: SurfaceConfig) -> topo.HeightMap:
    """Stage 1: read (or generate) the surface and level it with ``config.detrend``.

    Parameters
    ----------
    config : SurfaceConfig
        ``file`` or ``synthetic`` recipe, and the levelling method.

    Returns
    -------
    topo.HeightMap
        Heights in m (axis 0 is x), levelled.
    """
    return topo.level(load_surface(config), method=config.detrend)


def surface_record(surface: topo.HeightMap) -> StageRecord:
    """Stage-1 record: the levelled heights on x/y coordinates (m)."""
    valid = surface.heights[~np.isnan(surface.heights)]
    return StageRecord(
        coords={
            "x": Variable(np.arange(surface.nx) * surface.dx, "m", ("x",), "position along x"),
            "y": Variable(np.arange(surface.ny) * surface.dy, "m", ("y",), "position along y"),
        },
        variables={"heights": Variable(surface.heights, "m", ("x", "y"), "levelled height")},
        attrs={
            "dx": surface.dx,
            "dy": surface.dy,
            "periodic": surface.periodic,
            "nx": surface.nx,
            "ny": surface.ny,
            "n_missing": surface.n_missing,
            "rms_height": float(np.sqrt(np.mean((valid - valid.mean()) ** 2))),
            "provenance": json.dumps(surface.provenance, default=str),
        },
    )


def surface_from_record(record: StageRecord) -> topo.HeightMap:
    """Rebuild the stage-1 height map from its stored record."""
    a = record.attrs
    try:
        provenance = json.loads(a.get("provenance", "{}"))
    except json.JSONDecodeError:
        provenance = {}
    return topo.HeightMap(
        record.variables["heights"].data,
        dx=float(a["dx"]),
        dy=float(a["dy"]),
        periodic=bool(a["periodic"]),
        provenance=provenance,
    )


def usable_max_stride(surface: topo.HeightMap, max_stride: int) -> int:
    """``max_stride`` capped so the coarsest decimated map keeps MIN_SCAN_PIXELS per side."""
    return max(1, min(int(max_stride), min(surface.nx, surface.ny) // MIN_SCAN_PIXELS))


def scan_resolutions(surface: topo.HeightMap, max_stride: int) -> Any:
    """Stage 2: summit statistics at strides 1..max_stride (:func:`topo.resolution_scan`).

    ``max_stride`` is capped by :func:`usable_max_stride`.

    Returns
    -------
    topo.ResolutionScan
        ``stride``, ``resolution`` (m), ``n_summits``, ``asperity_density`` (1/m^2),
        ``summit_radius`` (m), ``summit_height_rms`` (m) and the fits.
    """
    return topo.resolution_scan(surface, usable_max_stride(surface, max_stride))


SCAN_FIELDS = {
    "resolution": ("m", "pixel size of the decimated map"),
    "n_summits": ("1", "number of summits (4 nearest neighbours)"),
    "asperity_density": ("1/m^2", "asperity density eta"),
    "summit_radius": ("m", "mean summit radius R"),
    "summit_height_rms": ("m", "rms summit height sigma_s"),
}
SCAN_FITS = ("radius_slope", "radius_intercept", "density_exponent", "density_prefactor")


def scan_record(scan: Any) -> StageRecord:
    """Stage-2 record: the scan arrays over ``stride`` and the fits as attributes."""
    record = StageRecord(
        coords={"stride": Variable(np.asarray(scan.stride), "1", ("stride",), "decimation stride")}
    )
    for name, (units, long_name) in SCAN_FIELDS.items():
        record.variables[name] = Variable(
            np.asarray(getattr(scan, name)), units, ("stride",), long_name
        )
    for name in SCAN_FITS:
        record.attrs[name] = float(getattr(scan, name))
    record.attrs["fit_units"] = (
        "R = radius_intercept (m) + radius_slope (m/m) * resolution; "
        "eta = density_prefactor * resolution**density_exponent (SI)"
    )
    return record


class StoredScan:
    """A resolution scan read back from the store, with the fields of topo.ResolutionScan."""

    def __init__(self, record: StageRecord):
        self.stride = np.asarray(record.coords["stride"].data)
        for name in SCAN_FIELDS:
            setattr(self, name, np.asarray(record.variables[name].data))
        for name in SCAN_FITS:
            setattr(self, name, float(record.attrs[name]))
