"""Reopen a run: ``asperity.open_results("out/results.h5")`` gives back the typed stage results.

Every stage of :data:`asperity.pipelines.stages.STAGES` stored in the file is read through the
generic store (:meth:`~asperity.pipelines.engine.store.ResultStore.read`, checksum checked) into
its result dataclass, exactly as the job returned it; a stage that is not stored is None.
Nothing is recomputed, so :func:`pipelines.report.write_report` can redraw every figure and
the report from the file (``asperity report OUT_DIR``). Example::

    import asperity
    run = asperity.open_results("asperity-out")        # the folder or results.h5
    run.resolution.effective_resolution                 # m
    run.friction.static_friction                        # N, one per load
    datasets = run.to_xarray()                          # {group: xarray.Dataset}

``to_xarray`` and ``to_datatree`` need xarray and h5netcdf (the ``test`` extra, or
``pip install xarray h5netcdf``); they are imported only when called.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import asperity
from asperity.errors import InputError
from asperity.pipelines.stages import STAGES

#: Group name -> attribute of :class:`Results` (and of ``job.JobResult``), from the stages.
ATTRIBUTES: dict[str, str] = {stage.name: stage.attribute for stage in STAGES}


class StageAttributes:
    """Mixin: a stage's result is also reachable by its group name (``run.bem_reference``)."""

    def __getattr__(self, name: str) -> Any:
        # only called for names that are not fields: the group names
        if name in ATTRIBUTES and ATTRIBUTES[name] != name:
            return getattr(self, ATTRIBUTES[name])
        raise AttributeError(f"{type(self).__name__} has no attribute or stage {name!r}")


def stage_dataclass(cls: type) -> type:
    """``cls`` as a dataclass with one field per stage of :data:`STAGES` (default None).

    The stage fields, named by each stage's ``attribute``, come after the fields of ``cls``
    without a default and before those with one, in the order of the stage list: the stage
    declarations are the only list of them.
    """
    own = dict(cls.__dict__.get("__annotations__", {}))
    required = {k: v for k, v in own.items() if k not in cls.__dict__}
    optional = {k: v for k, v in own.items() if k in cls.__dict__}
    stage_fields = {stage.attribute: "Any" for stage in STAGES}
    cls.__annotations__ = {**required, **stage_fields, **optional}
    for name in stage_fields:
        setattr(cls, name, None)
    return dataclass(cls)


@stage_dataclass
class Results(StageAttributes):
    """The stage results stored in one ``results.h5`` (None where a stage is absent).

    Attributes
    ----------
    path : Path
        The file read.
    surface, scan, bem, resolution, mode_mixity, friction, psd, verdict
        One field per stage of :data:`asperity.pipelines.stages.STAGES`, named by its
        declaration, in its order (see ``docs/pipelines.md``); also reachable by the group
        names (``results.resolution_scan``, ``results.statistical_model``, ...).
    stages : list of StageRun
        One "stored" row per stage read, with the seconds it took to compute.
    source, config_toml, input_sha256, asperity_version : str
        The file's provenance (configuration file, resolved configuration as TOML, SHA-256 of
        the input, version that wrote it).
    """

    path: Path
    stages: list[Any] = field(default_factory=list)
    source: str = ""
    config_toml: str = ""
    input_sha256: str = ""
    asperity_version: str = ""

    @property
    def out_dir(self) -> Path:
        """The folder holding results.h5."""
        return self.path.parent

    @property
    def total_seconds(self) -> float:
        """Seconds the stored stages took to compute, s."""
        return float(sum(s.seconds for s in self.stages))

    def problems(self) -> list[str]:
        """One line per solver that did not converge (as ``job.JobResult.problems``)."""
        from asperity.pipelines.job import solver_problems

        return solver_problems(self)

    @property
    def converged(self) -> bool:
        """Every solver converged."""
        return not self.problems()

    def to_xarray(self) -> dict[str, Any]:
        """Every stored group as an ``xarray.Dataset`` (named dims, ``units`` attributes).

        Needs xarray and h5netcdf, imported here (not a dependency of asperity).
        """
        xarray = _import_xarray()
        names = [s.name for s in self.stages]
        return {
            name: xarray.load_dataset(self.path, group=name, engine="h5netcdf") for name in names
        }

    def to_datatree(self) -> Any:
        """The stored groups as one ``xarray.DataTree`` (xarray >= 2024.10)."""
        xarray = _import_xarray()
        if not hasattr(xarray, "DataTree"):
            raise ImportError(
                f"to_datatree needs xarray >= 2024.10 (DataTree); found {xarray.__version__}"
            )
        return xarray.DataTree.from_dict({f"/{k}": v for k, v in self.to_xarray().items()})


def _import_xarray() -> Any:
    try:
        import xarray
    except ImportError as exc:  # pragma: no cover - the test extra has it
        raise ImportError(
            "to_xarray needs xarray and h5netcdf: pip install xarray h5netcdf"
        ) from exc
    return xarray


def results_file(path: str | Path) -> Path:
    """``path`` itself, or ``path/results.h5`` for a folder; checked to be an HDF5 file."""
    import h5py

    path = Path(path)
    if path.is_dir():
        path = path / "results.h5"
    if not path.is_file():
        raise InputError(f"{path}: results file not found (expected an asperity run's results.h5)")
    if not h5py.is_hdf5(path):
        raise InputError(f"{path}: not an HDF5 file (expected an asperity run's results.h5)")
    return path


def open_results(path: str | Path) -> Results:
    """Read every stored stage of an asperity run (nothing is recomputed).

    Parameters
    ----------
    path : str or Path
        ``results.h5`` or the output folder holding it.

    Returns
    -------
    Results
        One attribute per stage (its typed result, None where not stored), the provenance
        and ``to_xarray()``.

    Raises
    ------
    InputError
        No such file, not HDF5, or a stored stage that does not read back (changed after it
        was written, or written by an incompatible version): the message names the file and
        the stage.
    """
    from asperity.pipelines.engine.stage import StageRun
    from asperity.pipelines.engine.store import ResultStore, StoredStageError

    path = results_file(path)
    store = ResultStore(path)
    stored = store.stored()
    attrs = store.root_attrs()
    results = Results(
        path=path,
        source=str(attrs.get("config_source", "")),
        config_toml=str(attrs.get("config_toml", "")),
        input_sha256=str(attrs.get("input_sha256", "")),
        asperity_version=str(attrs.get("asperity_version", "")),
    )
    for stage in STAGES:
        if stage.name not in stored:
            continue
        try:
            value = store.read(stage.name, stage.result)
        except (StoredStageError, TypeError, ValueError, KeyError) as exc:
            raise InputError(
                f"{path}: stage {stage.name!r} does not read back ({exc}); the file was written "
                f"by asperity {results.asperity_version or '?'}, this is {asperity.__version__}: "
                "run `asperity run` with the same configuration to recompute it"
            ) from exc
        setattr(results, stage.attribute, value)
        info = stored[stage.name]
        results.stages.append(StageRun(stage.name, info.key, "stored", info.seconds))
    return results
