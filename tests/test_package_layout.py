"""The package layout and the command line as a whole: public names, sub-commands, start-up cost."""

from __future__ import annotations

import importlib
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

from asperity.pipelines.cli import build_parser, main

PACKAGES = ("asperity.topo", "asperity.bem", "asperity.statmodel", "asperity.pipelines")
COMMANDS = ("stats", "scan", "synth", "bem", "friction", "figures", "run")


@pytest.mark.parametrize("name", PACKAGES)
def test_public_names_resolve_to_objects_not_shadowing_submodules(name: str) -> None:
    """Every name in ``__all__`` resolves, even after all submodules were imported.

    A public function that shares its name with a submodule is replaced by the module as soon
    as the submodule is imported (the import system sets the attribute), so ``from pkg import f``
    would hand back a module: such a clash must not exist.
    """
    package = importlib.import_module(name)
    submodules = {info.name for info in pkgutil.iter_modules(package.__path__)}
    for info in pkgutil.iter_modules(package.__path__):
        if not info.name.startswith("_"):
            importlib.import_module(f"{name}.{info.name}")
    for public in getattr(package, "__all__", ()):
        value = getattr(package, public)
        if public in submodules:  # exported as the module itself, never as its namesake
            module = importlib.import_module(f"{name}.{public}")
            assert value is module
            assert not callable(getattr(module, public, None)), (
                f"{name}.{public}: the module defines a public {public} of the same name, "
                "which the module object shadows"
            )
        else:
            assert not isinstance(value, type(sys)), f"{name}.{public} is a module"


def test_every_documented_sub_command_is_registered() -> None:
    parser = build_parser()
    choices = next(a for a in parser._actions if a.dest == "command").choices
    assert set(COMMANDS) <= set(choices)


@pytest.mark.parametrize("command", COMMANDS)
def test_sub_command_help_exits_zero(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main([command, "--help"])
    assert stop.value.code == 0
    assert "usage: asperity" in capsys.readouterr().out


def test_no_command_prints_help_and_fails(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([]) == 2
    assert "COMMAND" in capsys.readouterr().out


def test_help_does_not_load_numerical_kernels() -> None:
    """``asperity --help`` stays fast: building the parser imports no numba, scipy or h5py."""
    code = (
        "import sys; from asperity.pipelines.cli import build_parser; build_parser(); "
        "print(','.join(m for m in ('numba', 'scipy', 'h5py', 'matplotlib') if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    ).stdout.strip()
    assert out == ""


def test_python_dash_m_is_the_same_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "asperity", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0
    assert done.stdout.startswith("asperity ")


REPO = Path(__file__).resolve().parents[1]


def _declared_packages() -> dict[str, str]:
    """The packages pyproject.toml ships, each with the folder it comes from."""
    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    folders = config["package-dir"]
    declared = {}
    for package in config["packages"]:
        parent = max((p for p in folders if package == p or package.startswith(p + ".")), key=len)
        tail = package[len(parent) :].lstrip(".").replace(".", "/")
        declared[package] = str(Path(folders[parent]) / tail) if tail else folders[parent]
    return declared


def test_every_package_folder_is_shipped_under_the_asperity_namespace() -> None:
    """A new sub-package folder that pyproject.toml forgets would be missing from a wheel."""
    on_disk = {
        str(init.parent.relative_to(REPO))
        for top in ("asperity", "topo", "bem", "statmodel", "pipelines")
        for init in (REPO / top).rglob("__init__.py")
    }
    assert set(_declared_packages().values()) == on_disk


def test_import_asperity_is_lazy_and_versioned() -> None:
    code = (
        "import sys, asperity; loaded = [m for m in ('asperity.bem', 'numba', 'scipy') "
        "if m in sys.modules]; print(asperity.__version__, loaded, asperity.bem.__name__)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    ).stdout.split()
    assert out[1:] == ["[]", "asperity.bem"]
    assert out[0][0].isdigit()


@pytest.mark.slow
def test_a_wheel_installs_only_the_asperity_namespace(tmp_path: Path) -> None:
    """After ``pip install .`` in a fresh venv, outside the tree: ``asperity.bem`` only.

    The names ``bem``, ``topo`` and ``pipelines`` belong to unrelated projects on PyPI; a wheel
    that installed them as top-level packages would be silently replaced by (or replace) those.
    """
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run(
        [str(python), "-m", "pip", "install", "-q", "--no-deps", str(REPO)],
        check=True,
        cwd=tmp_path,
    )
    code = (
        "import importlib.util as u, sys; sys.path = [p for p in sys.path if p not in ('', '.')]; "
        "import asperity.bem, asperity.topo.io, asperity.pipelines.presets; "
        "print([n for n in ('topo', 'bem', 'statmodel', 'pipelines') if u.find_spec(n)]); "
        "print(asperity.bem.__file__)"
    )
    done = subprocess.run(
        [str(python), "-I", "-c", code], capture_output=True, text=True, cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    found, location = done.stdout.splitlines()
    assert found == "[]"
    assert Path(location).is_relative_to(venv)  # the wheel's copy, not the source tree


#: Code (not prose) that imports pyplot or selects a backend.
FORCES_BACKEND = re.compile(
    r"^\s*(import matplotlib\.pyplot|from matplotlib import pyplot|from matplotlib\.pyplot import)"
    r"|matplotlib\.use\(",
    re.MULTILINE,
)


def test_library_source_never_forces_a_matplotlib_backend() -> None:
    """No library module calls ``matplotlib.use`` or imports ``pyplot`` (a notebook's backend
    is the user's): figures are ``matplotlib.figure.Figure`` objects. The behaviour itself is
    checked in a fresh interpreter by tests/test_plotting.py."""
    offenders = []
    for top in ("asperity", "topo", "bem", "statmodel", "pipelines"):
        for source in sorted((REPO / top).rglob("*.py")):
            name = str(source.relative_to(REPO))
            text = source.read_text()
            if FORCES_BACKEND.search(text):
                offenders.append(name)
    assert offenders == []


#: Import paths of asperity 0.2 (README, docs, users' scripts) -> the module now behind them.
OLD_PATHS = {
    "asperity.pipelines.surface_stage": "asperity.pipelines.stages.surface",
    "asperity.pipelines.bem_stage": "asperity.pipelines.stages.bem",
    "asperity.pipelines.resolution_stage": "asperity.pipelines.stages.statistical_model",
    "asperity.pipelines.friction_stage": "asperity.pipelines.stages.friction",
    "asperity.pipelines.psd_stage": "asperity.pipelines.stages.psd",
    "asperity.pipelines.verdict": "asperity.pipelines.stages.verdict",
    "asperity.pipelines.fitting": "asperity.pipelines.stages.fitting",
    "asperity.pipelines.store": "asperity.pipelines.engine.store",
    "asperity.pipelines.outdir": "asperity.pipelines.engine.outdir",
    "asperity.pipelines.parallel": "asperity.pipelines.engine.parallel",
    "asperity.pipelines.fields": "asperity.fields",
    "asperity.pipelines.html_report": "asperity.pipelines.report.html",
    "asperity.pipelines.figure_output": "asperity.pipelines.report.figure_output",
    "asperity.pipelines.run_cli": "asperity.pipelines.cli.run",
    "asperity.pipelines.batch_summary": "asperity.pipelines.batch.summary",
}


@pytest.mark.parametrize("old", sorted(OLD_PATHS))
def test_old_import_paths_give_the_module_at_its_new_path(old: str) -> None:
    """``import`` and ``from ... import`` of a 0.2 path give the same module object (so that
    attributes, isinstance and monkeypatching act on the one module)."""
    new = importlib.import_module(OLD_PATHS[old])
    assert importlib.import_module(old) is new
    package, _, name = old.rpartition(".")
    assert getattr(importlib.import_module(package), name) is new
    assert new.__spec__.name == OLD_PATHS[old]


def test_documented_entry_points_still_resolve() -> None:
    import asperity
    from asperity.pipelines import config, job
    from asperity.pipelines.stages import Runner, Stage, StageContext

    assert callable(job.run_job) and callable(config.load_preset)
    assert callable(asperity.open_results)
    assert Stage.__module__ == "asperity.pipelines.engine.stage"
    assert Runner and StageContext
    assert [s.name for s in job.STAGES] == list(job.STAGE_NAMES)
