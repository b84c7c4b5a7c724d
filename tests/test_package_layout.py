"""The package layout and the command line as a whole: public names, sub-commands, start-up cost."""

from __future__ import annotations

import importlib
import pkgutil
import subprocess
import sys

import pytest

from pipelines.cli import build_parser, main

PACKAGES = ("topo", "bem", "statmodel", "pipelines")
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
        if public in submodules:
            assert value is importlib.import_module(f"{name}.{public}")
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
        "import sys; from pipelines.cli import build_parser; build_parser(); "
        "print(','.join(m for m in ('numba', 'scipy', 'h5py', 'matplotlib') if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    ).stdout.strip()
    assert out == ""


def test_python_dash_m_is_the_same_command() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "pipelines", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0
    assert done.stdout.startswith("asperity ")
