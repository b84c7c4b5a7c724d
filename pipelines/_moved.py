"""The import paths of asperity 0.2's flat ``pipelines`` modules, kept working after the regroup.

asperity 0.2 had every pipeline module directly in ``asperity.pipelines`` (``surface_stage``,
``bem_stage``, ``store``, ...). They now live in sub-packages (``stages``, ``engine``,
``report``, ``cli``, ``batch``) and the field declarations in :mod:`asperity.fields`. An import
of an old path (``import asperity.pipelines.bem_stage``, ``from asperity.pipelines import
surface_stage``) gives the module at its new path, the same module object, so attributes,
``isinstance`` checks and monkeypatching behave as before.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
from types import ModuleType

#: Old module name under ``asperity.pipelines`` -> the module's import path now.
MOVED: dict[str, str] = {
    "store": "asperity.pipelines.engine.store",
    "outdir": "asperity.pipelines.engine.outdir",
    "parallel": "asperity.pipelines.engine.parallel",
    "fields": "asperity.fields",
    "surface_stage": "asperity.pipelines.stages.surface",
    "resolution_stage": "asperity.pipelines.stages.statistical_model",
    "bem_stage": "asperity.pipelines.stages.bem",
    "pull_off": "asperity.pipelines.stages._pull_off",
    "friction_stage": "asperity.pipelines.stages.friction",
    "fitting": "asperity.pipelines.stages.fitting",
    "psd_stage": "asperity.pipelines.stages.psd",
    "verdict": "asperity.pipelines.stages.verdict",
    "html_report": "asperity.pipelines.report.html",
    "bem_report": "asperity.pipelines.report.bem",
    "figure_output": "asperity.pipelines.report.figure_output",
    "run_cli": "asperity.pipelines.cli.run",
    "report_cli": "asperity.pipelines.cli.report",
    "batch_cli": "asperity.pipelines.cli.batch",
    "batch_summary": "asperity.pipelines.batch.summary",
}

PACKAGE = "asperity.pipelines"


class _AliasLoader(importlib.abc.Loader):
    """Loads an old name as the module at its new path (imported, not re-executed)."""

    def __init__(self, target: str) -> None:
        self.target = target
        self.spec: importlib.machinery.ModuleSpec | None = None

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        module = importlib.import_module(self.target)
        self.spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        module.__spec__ = self.spec  # the import machinery set the alias's spec: restore


class MovedModuleFinder(importlib.abc.MetaPathFinder):
    """Finds ``asperity.pipelines.<old name>`` for every name of :data:`MOVED`."""

    def find_spec(self, fullname: str, path: object = None, target: object = None):
        package, _, name = fullname.rpartition(".")
        if package != PACKAGE or name not in MOVED:
            return None
        return importlib.util.spec_from_loader(fullname, _AliasLoader(MOVED[name]))


def install() -> None:
    """Put the finder on :data:`sys.meta_path` once."""
    if not any(isinstance(f, MovedModuleFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, MovedModuleFinder())


def moved_module(name: str) -> ModuleType:
    """The module an old name under ``asperity.pipelines`` stands for (imported)."""
    if name not in MOVED:
        raise AttributeError(f"module {PACKAGE!r} has no attribute {name!r}")
    return importlib.import_module(f"{PACKAGE}.{name}")
