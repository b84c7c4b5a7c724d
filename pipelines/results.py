"""Reopen a run: ``asperity.open_results("out/results.h5")`` gives back the typed stage results.

Every stage of :data:`asperity.pipelines.stages.STAGES` stored in the file is read through the
generic store (:meth:`~asperity.pipelines.engine.store.ResultStore.read`, checksum checked) into
its result dataclass, exactly as the job returned it; a stage that is not stored is None.
Nothing is recomputed, so :func:`pipelines.report.write_report` can redraw every figure and
the report from the file (``asperity report OUT_DIR``). Example::

    import asperity
    run = asperity.open_results("asperity-out")        # the folder or results.h5
    run.statistical_model.effective_resolution          # m
    run.friction.static_friction                        # N, one per load
    datasets = run.to_xarray()                          # {group: xarray.Dataset}

Each stage's result is the field named by its group in results.h5 (:class:`StageResults`,
shared by this module's :class:`Results` and ``job.JobResult``). The second names of asperity
0.3 (``run.scan``, ``run.bem``, ``run.resolution``) still answer, with a
:class:`DeprecationWarning`; they are removed in asperity 0.5.

``to_xarray`` and ``to_datatree`` need xarray and h5netcdf (the ``test`` extra, or
``pip install xarray h5netcdf``); they are imported only when called.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import h5py

import asperity
from asperity.errors import InputError, cut
from asperity.pipelines.engine.stage import StageRun
from asperity.pipelines.engine.store import ResultStore, StoredStageError
from asperity.pipelines.stages import STAGES
from asperity.pipelines.stages.bem import BemReference
from asperity.pipelines.stages.bem_shear import BemShearComparison
from asperity.pipelines.stages.friction import FrictionPrediction, ModeMixityChoice
from asperity.pipelines.stages.friction_curves import FrictionTestComparison
from asperity.pipelines.stages.psd import PsdResult
from asperity.pipelines.stages.realisations import RealisationSpread
from asperity.pipelines.stages.statistical_model import ResolutionChoice
from asperity.pipelines.stages.surface import LevelledSurface, ScanResult
from asperity.pipelines.stages.verdict import Verdict

if TYPE_CHECKING:
    import xarray

#: The version that removes the deprecated second names of the stages.
ALIAS_REMOVAL = "0.5"

#: Deprecated second name -> group name, from the stage declarations (``Stage.attribute``).
ALIASES: dict[str, str] = {
    stage.attribute: stage.name
    for stage in STAGES
    if stage.attribute is not None and stage.attribute != stage.name
}


def _deprecated_alias(alias: str, group: str) -> property:
    def get(self: StageResults) -> object:
        warnings.warn(
            f"{type(self).__name__}.{alias} is deprecated: use .{group} (the stage's group in "
            f"results.h5); .{alias} is removed in asperity {ALIAS_REMOVAL}",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(self, group)

    return property(get, doc=f"Deprecated name of :attr:`{group}` (removed in {ALIAS_REMOVAL}).")


@dataclass(kw_only=True)
class StageResults:
    """One field per stage of :data:`~asperity.pipelines.stages.STAGES`, named by its group in
    results.h5 and typed by its result dataclass, in the stages' order; None where the stage is
    absent (disabled, or not stored). A test holds these fields to the stage list.

    Attributes
    ----------
    surface : LevelledSurface or None
        Stage 1, the levelled map (m).
    resolution_scan : ScanResult or None
        Stage 2, the summit statistics against resolution.
    bem_reference : BemReference or None
        Stage 3, the BEM reference (None with ``[bem] enabled = false``).
    statistical_model : ResolutionChoice or None
        Stage 4, the statistical model and the effective resolution (m).
    mode_mixity : ModeMixityChoice or None
        Stage 5, lambda.
    friction : FrictionPrediction or None
        Stage 6, the shear curves and friction forces (N).
    psd : PsdResult or None
        Stage 7, the power spectral density.
    realisations : RealisationSpread or None
        Stage 8, the spread over synthesised maps (line-profile input only).
    bem_shear : BemShearComparison or None
        Stage 9, the shear BEM against the model (None unless ``[bem_shear] enabled = true``).
    friction_tests : FrictionTestComparison or None
        Stage 10, measured friction tests F_x(drive) against the model through the drive's
        spring (None without ``measured.friction_curves``).
    verdict : Verdict or None
        Stage 11, whether the report stands behind the numbers.
    """

    surface: LevelledSurface | None = None
    resolution_scan: ScanResult | None = None
    bem_reference: BemReference | None = None
    statistical_model: ResolutionChoice | None = None
    mode_mixity: ModeMixityChoice | None = None
    friction: FrictionPrediction | None = None
    psd: PsdResult | None = None
    realisations: RealisationSpread | None = None
    bem_shear: BemShearComparison | None = None
    friction_tests: FrictionTestComparison | None = None
    verdict: Verdict | None = None

    # asperity 0.3's second names (docs/pipelines.md promised run.scan and run.resolution)
    scan = _deprecated_alias("scan", "resolution_scan")
    bem = _deprecated_alias("bem", "bem_reference")
    resolution = _deprecated_alias("resolution", "statistical_model")

    def stage_results(self) -> dict[str, object]:
        """Each stage's result (None where absent), by group name, in the stages' order."""
        return {stage.name: getattr(self, stage.name) for stage in STAGES}

    def problems(self) -> list[str]:
        """One line per solver that did not converge (BEM sweeps, shear curves, the lambda
        fit)."""
        return solver_problems(self)

    @property
    def converged(self) -> bool:
        """Every solver converged."""
        return not self.problems()


def solver_problems(result: StageResults) -> list[str]:
    """One line per solver that did not converge, from a job's or a reopened run's results."""
    bem, friction, mode_mixity = result.bem_reference, result.friction, result.mode_mixity
    lines = [] if bem is None else list(bem.messages)
    if bem is not None and not bem.all_converged and not lines:
        lines.append("BEM: a solve did not converge")
    if friction is not None:
        lines += [
            f"shear curve F_z={f:.4g} N: {m}"
            for f, ok, m in zip(
                friction.normal_load, friction.converged, friction.messages, strict=True
            )
            if not ok
        ]
    if mode_mixity is not None and mode_mixity.fitted and not mode_mixity.success:
        lines.append(f"lambda fit: {mode_mixity.message}")
    shear = getattr(result, "bem_shear", None)
    if shear is not None:
        lines += [f"shear BEM {m}" for m in shear.messages]
        if not shear.all_converged and not shear.messages:
            lines.append("shear BEM: a curve did not converge")
    return lines


@dataclass(kw_only=True)
class Results(StageResults):
    """The stage results stored in one ``results.h5`` (None where a stage is absent).

    Attributes
    ----------
    path : Path
        The file read.
    surface, resolution_scan, bem_reference, statistical_model, mode_mixity, friction, psd, \
realisations, bem_shear, friction_tests, verdict
        One field per stage of :data:`asperity.pipelines.stages.STAGES`, named by its group in
        results.h5 (:class:`StageResults`; see ``docs/pipelines.md``).
    stages : list of StageRun
        One "stored" row per stage read, with the seconds it took to compute.
    source, config_toml, input_sha256, asperity_version : str
        The file's provenance (configuration file, resolved configuration as TOML, SHA-256 of
        the input, version that wrote it).
    verdict_problem : str or None
        Why the file's verdict cannot be relied on (not stored, or stored but malformed), or
        None; listed by :meth:`problems` and warned about by :func:`open_results`.
    """

    path: Path
    stages: list[StageRun] = field(default_factory=list)
    source: str = ""
    config_toml: str = ""
    input_sha256: str = ""
    asperity_version: str = ""
    verdict_problem: str | None = None

    def problems(self) -> list[str]:
        """One line per solver that did not converge, and one for a missing or malformed
        verdict: numbers without a verdict are never presented as problem-free."""
        lines = solver_problems(self)
        return lines if self.verdict_problem is None else [*lines, self.verdict_problem]

    @property
    def converged(self) -> bool:
        """Every solver converged (the verdict's state is :attr:`verdict_problem`)."""
        return not solver_problems(self)

    @property
    def out_dir(self) -> Path:
        """The folder holding results.h5."""
        return self.path.parent

    @property
    def total_seconds(self) -> float:
        """Seconds the stored stages took to compute, s."""
        return float(sum(s.seconds for s in self.stages))

    def to_xarray(self) -> dict[str, xarray.Dataset]:
        """Every stored group as an ``xarray.Dataset`` (named dims, ``units`` attributes).

        Needs xarray and h5netcdf, imported here (not a dependency of asperity).
        """
        xr = _import_xarray()
        names = [s.name for s in self.stages]
        return {name: xr.load_dataset(self.path, group=name, engine="h5netcdf") for name in names}

    def to_datatree(self) -> xarray.DataTree:
        """The stored groups as one ``xarray.DataTree`` (xarray >= 2024.10)."""
        xr = _import_xarray()
        if not hasattr(xr, "DataTree"):
            raise ImportError(
                f"to_datatree needs xarray >= 2024.10 (DataTree); found {xr.__version__}"
            )
        return xr.DataTree.from_dict({f"/{k}": v for k, v in self.to_xarray().items()})


def _import_xarray() -> ModuleType:
    try:
        import xarray  # optional: the test extra
    except ImportError as exc:  # pragma: no cover - the test extra has it
        raise ImportError(
            "to_xarray needs xarray and h5netcdf: pip install xarray h5netcdf"
        ) from exc
    return xarray


def results_file(path: str | Path) -> Path:
    """``path`` itself, or ``path/results.h5`` for a folder; checked to be an HDF5 file."""
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
            if stage.name == "verdict":  # the numbers still read; their judgement does not
                results.verdict_problem = f"verdict: stored but does not read back ({exc})"
                continue
            raise InputError(
                f"{path}: stage {stage.name!r} does not read back ({exc}); the file was written "
                f"by asperity {results.asperity_version or '?'}, this is {asperity.__version__}: "
                "run `asperity run` with the same configuration to recompute it"
            ) from exc
        setattr(results, stage.name, value)
        info = stored[stage.name]
        results.stages.append(StageRun(stage.name, info.key, "stored", info.seconds))
    _judge_verdict(results)
    return results


class VerdictWarning(UserWarning):
    """A reopened run's verdict is missing or malformed: its numbers are not vouched for."""


#: The verdicts a run stores, and the severities of their reasons.
_VERDICTS = ("valid", "warnings", "invalid")
_SEVERITIES = ("invalid", "warning")


def verdict_defect(verdict: Verdict) -> str | None:
    """What is wrong with a stored verdict (None: it is well formed).

    Its word must be one of valid/warnings/invalid, each reason must have a code and a
    severity (invalid or warning), and the word may not be milder than the severities make
    it (invalid if one reason is, warnings if there are reasons).
    """
    if verdict.verdict not in _VERDICTS:
        return f"is {cut(repr(verdict.verdict))}; expected one of {', '.join(_VERDICTS)}"
    counts = {len(verdict.reasons), len(verdict.codes), len(verdict.severities)}
    if len(counts) != 1:
        return "has reasons, codes and severities of different lengths"
    if any(severity not in _SEVERITIES for severity in verdict.severities):
        return "has a reason whose severity is neither invalid nor warning"
    implied = (
        "invalid"
        if "invalid" in verdict.severities
        else ("warnings" if verdict.severities else "valid")
    )
    if _VERDICTS.index(verdict.verdict) < _VERDICTS.index(implied):  # milder than its reasons
        return f"says {verdict.verdict!r} but its reasons make it {implied!r}"
    return None


def _judge_verdict(results: Results) -> None:
    """Record (and warn) when the run's verdict is missing or malformed."""
    if results.verdict_problem is None:
        if results.verdict is None:
            results.verdict_problem = (
                "verdict: not stored (the run did not finish, or the verdict group was "
                "removed): nothing says whether these numbers can be relied on"
            )
        else:
            defect = verdict_defect(results.verdict)
            if defect is not None:  # not presented as the run's judgement
                results.verdict_problem = f"verdict: malformed: it {defect}"
                results.verdict = None
    if results.verdict_problem is not None:
        warnings.warn(f"{results.path}: {results.verdict_problem}", VerdictWarning, stacklevel=3)
