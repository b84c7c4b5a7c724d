"""The whole job: six stages run in order, each stored in ``results.h5`` as it finishes.

A stage is skipped when ``results.h5`` already holds it with the same key: a SHA-256 of the
configuration parts it depends on and of the keys of the stages it uses, so changing the loads
recomputes the BEM and everything after it, but not the surface or its resolution scan.
``force=True`` recomputes every stage.

Python use::

    from asperity.pipelines import job, config
    result = job.run_job(config.load_preset("default"), "out")
    result.friction.scalars["static_friction"]      # N, one per load
"""

from __future__ import annotations

import hashlib
import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from asperity.pipelines import __version__
from asperity.pipelines.bem_stage import BemReference, bem_from_record, bem_record, bem_reference
from asperity.pipelines.config import JobConfig
from asperity.pipelines.friction_stage import (
    FrictionPrediction,
    ModeMixityChoice,
    calibrate_mode_mixity,
    friction_from_record,
    friction_prediction,
    friction_record,
    lambda_from_record,
    lambda_record,
)
from asperity.pipelines.measured import ShearAreaCurve, read_normal_area, read_shear_area
from asperity.pipelines.parallel import make_executor
from asperity.pipelines.resolution_stage import (
    ResolutionChoice,
    check_loads_above_pull_off,
    material_from_config,
    resolution_from_record,
    resolution_record,
    statistical_model_scan,
)
from asperity.pipelines.store import ResultStore, StageRecord
from asperity.pipelines.surface_stage import (
    StoredScan,
    file_sha256,
    input_sha256,
    read_and_level,
    scan_record,
    scan_resolutions,
    surface_from_record,
    surface_record,
)

#: Stage group names in results.h5, in order.
STAGES: tuple[str, ...] = (
    "surface",
    "resolution_scan",
    "bem_reference",
    "statistical_model",
    "mode_mixity",
    "friction",
)
STAGE_TITLES: dict[str, str] = {
    "surface": "1 read and level",
    "resolution_scan": "2 resolution scan",
    "bem_reference": "3 BEM reference",
    "statistical_model": "4 statistical model / resolution",
    "mode_mixity": "5 lambda",
    "friction": "6 friction prediction",
}


@dataclass
class StageRun:
    """How one stage went: computed or taken from the store, and its wall time (s)."""

    name: str
    key: str
    cached: bool
    seconds: float


@dataclass
class JobResult:
    """Everything the job produced (the same data as results.h5)."""

    config: JobConfig
    out_dir: Path
    surface: Any
    scan: Any
    bem: BemReference
    resolution: ResolutionChoice
    mode_mixity: ModeMixityChoice
    friction: FrictionPrediction
    stages: list[StageRun] = field(default_factory=list)
    total_seconds: float = 0.0
    input_sha256: str = ""

    @property
    def results_path(self) -> Path:
        """The HDF5 result file."""
        return self.out_dir / "results.h5"

    @property
    def converged(self) -> bool:
        """Every solver converged (BEM sweeps, shear curves, the lambda fit)."""
        fit_ok = self.mode_mixity.fit is None or self.mode_mixity.fit.success
        return self.bem.all_converged and self.friction.all_converged and fit_ok

    def problems(self) -> list[str]:
        """One line per solver that did not converge."""
        lines = list(self.bem.messages)
        lines += [
            f"shear curve F_z={f:.4g} N: {m}"
            for f, ok, m in zip(
                self.friction.normal_load,
                self.friction.converged,
                self.friction.messages,
                strict=True,
            )
            if not ok
        ]
        if self.mode_mixity.fit is not None and not self.mode_mixity.fit.success:
            lines.append(f"lambda fit: {self.mode_mixity.fit.message}")
        return lines


def _hash(*parts: Any) -> str:
    text = json.dumps(parts, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def stage_keys(config: JobConfig, input_hash: str) -> dict[str, str]:
    """The cache key of each stage (hash of what it depends on, chained through its inputs)."""
    d = config.to_dict()
    surface = dict(d["surface"])
    max_stride = surface.pop("max_stride")
    m, ld = d["material"], d["loading"]
    measured_normal = config.measured.normal_area
    measured_shear = [
        (str(c.file), c.normal_load, file_sha256(c.file)) for c in config.measured.shear_area
    ]
    k1 = _hash("surface", surface, input_hash)
    k2 = _hash("scan", k1, max_stride)
    k3 = _hash(
        "bem",
        k1,
        m["E_star"],
        m["work_of_adhesion"],
        ld["nominal_area"],
        ld["normal_loads"],
        d["bem"],
    )
    k4 = _hash(
        "statmodel",
        k2,
        k3,
        m["E_star"],
        m["work_of_adhesion"],
        m["equilibrium_distance"],
        ld["nominal_area"],
        ld["normal_loads"],
        None if measured_normal is None else file_sha256(measured_normal),
    )
    k5 = _hash(
        "lambda",
        k4,
        m,
        measured_shear,
        d["fit"],
        ld["max_tangential_displacement"],
        ld["steps"],
        d["statmodel"],
    )
    k6 = _hash("friction", k5, m, ld, d["statmodel"])
    return dict(zip(STAGES, (k1, k2, k3, k4, k5, k6), strict=True))


def read_measured_shear(config: JobConfig) -> list[ShearAreaCurve]:
    """All measured A_r(F_x) curves of the configuration."""
    curves: list[ShearAreaCurve] = []
    for item in config.measured.shear_area:
        curves += read_shear_area(item.file, item.normal_load)
    return curves


def run_job(
    config: JobConfig,
    out_dir: str | Path,
    *,
    force: bool = False,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = False,
    log: Callable[[str], None] | None = None,
) -> JobResult:
    """Run (or resume) the six stages and write ``results.h5`` in ``out_dir``.

    Parameters
    ----------
    config : JobConfig
        The validated configuration.
    out_dir : path
        Output directory (created).
    force : bool
        Recompute every stage even when stored.
    workers : int, optional
        Worker processes for the sweeps (default: ``config.run.workers``).
    scheduler : str or distributed.Client, optional
        Run the sweeps on a dask.distributed cluster instead.
    progress : bool
        Show tqdm progress bars on stderr.
    log : callable, optional
        Receives one line per stage (e.g. ``print``).

    Returns
    -------
    JobResult
        Figures and the report are written separately by :func:`pipelines.report.write_report`.
    """
    t_job = time.perf_counter()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    store = ResultStore(out_dir / "results.h5")
    # Measured files are read first: a malformed CSV fails before any heavy work.
    measured_normal = (
        None
        if config.measured.normal_area is None
        else read_normal_area(config.measured.normal_area)
    )
    measured_shear = read_measured_shear(config)
    input_hash = input_sha256(config.surface)
    keys = stage_keys(config, input_hash)
    store.write(
        None,
        None,
        root_attrs={
            "asperity_version": __version__,
            "config_toml": config.to_toml(),
            "config_source": config.source,
            "input_sha256": input_hash,
            "input": str(config.surface.file) if config.surface.file else "synthetic recipe",
            "conventions": "SI units; each group is a netCDF-4-style dataset (h5netcdf)",
        },
    )
    runs: list[StageRun] = []
    say = log or (lambda line: None)
    workers = config.run.workers if workers is None else workers

    def stage(
        name: str,
        compute: Callable[[], Any],
        to_record: Callable[[Any], StageRecord],
        from_record: Callable[[StageRecord], Any],
    ) -> Any:
        key = keys[name]
        if not force and store.has_stage(name, key):
            record = store.read_stage(name)
            runs.append(StageRun(name, key, True, float(record.attrs.get("seconds", 0.0))))
            say(f"{STAGE_TITLES[name]}: stored, skipped")
            return from_record(record)
        t0 = time.perf_counter()
        value = compute()
        seconds = time.perf_counter() - t0
        store.write(name, to_record(value), key=key, seconds=seconds)
        runs.append(StageRun(name, key, False, seconds))
        say(f"{STAGE_TITLES[name]}: {seconds:.2f} s")
        return value

    material = material_from_config(config.material)
    loads = config.loading.normal_loads
    a_n = config.loading.nominal_area
    with make_executor(workers, scheduler=scheduler) as executor:
        surface = stage(
            "surface", lambda: read_and_level(config.surface), surface_record, surface_from_record
        )
        scan = stage(
            "resolution_scan",
            lambda: scan_resolutions(surface, config.surface.max_stride),
            scan_record,
            StoredScan,
        )
        check_loads_above_pull_off(material, scan, a_n, loads)
        b = config.bem
        bem_ref = stage(
            "bem_reference",
            lambda: bem_reference(
                surface,
                config.material.E_star,
                config.material.work_of_adhesion,
                loads,
                a_n,
                tol=b.tol,
                max_iter=b.max_iter,
                area_tolerance=b.area_tolerance,
                max_stride=b.max_stride,
                adhesive=b.adhesive,
                executor=executor,
                progress=progress,
            ),
            bem_record,
            bem_from_record,
        )
        resolution = stage(
            "statistical_model",
            lambda: statistical_model_scan(
                scan,
                material,
                a_n,
                loads,
                bem=bem_ref,
                measured=measured_normal,
                executor=executor,
                progress=progress,
            ),
            lambda r: resolution_record(r, a_n),
            resolution_from_record,
        )
        path = dict(
            max_tangential_displacement=config.loading.max_tangential_displacement,
            steps=config.loading.steps,
        )
        lam = stage(
            "mode_mixity",
            lambda: calibrate_mode_mixity(
                material,
                resolution.roughness,
                a_n,
                measured_shear,
                bounds=config.fit.mode_mixity_bounds,
                executor=executor,
                **path,
            ),
            lambda r: lambda_record(r, a_n),
            lambda_from_record,
        )
        fitted_material = material_from_config(config.material, mode_mixity=lam.mode_mixity)
        friction = stage(
            "friction",
            lambda: friction_prediction(
                fitted_material,
                resolution.roughness,
                a_n,
                loads,
                quadrature_tolerance=config.statmodel.area_tolerance,
                executor=executor,
                progress=progress,
                **path,
            ),
            friction_record,
            friction_from_record,
        )
    return JobResult(
        config=config,
        out_dir=out_dir,
        surface=surface,
        scan=scan,
        bem=bem_ref,
        resolution=resolution,
        mode_mixity=lam,
        friction=friction,
        stages=runs,
        total_seconds=time.perf_counter() - t_job,
        input_sha256=input_hash,
    )


def progress_enabled() -> bool:
    """Progress bars only when stderr is a terminal."""
    return sys.stderr.isatty()
