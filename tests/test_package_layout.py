"""The package layout and the command line as a whole: public names, sub-commands, start-up cost."""

from __future__ import annotations

import ast
import importlib
import pkgutil
import re
import subprocess
import sys
import warnings
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
        if not info.name.startswith("_") and f"{name}.{info.name}" not in DEPRECATED_PATHS:
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
    """``import asperity`` loads no sub-package; ``import asperity.bem`` loads that package's
    namespace but none of its numerical modules (they load on first use of a name)."""
    code = (
        "import sys, asperity; loaded = [m for m in ('asperity.bem', 'asperity.topo', "
        "'asperity.pipelines', 'numba', 'scipy') if m in sys.modules]; import asperity.bem; "
        "heavy = [m for m in ('numba', 'scipy') if m in sys.modules]; "
        "print(asperity.__version__, loaded, heavy, asperity.bem.solve_contact.__module__)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    ).stdout.split()
    assert out[1:] == ["[]", "[]", "asperity.bem.normal.contact"]
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


#: The module paths that asperity 0.2's README and docs named -> the module now behind them.
DEPRECATED_PATHS = {
    "asperity.pipelines.surface_stage": "asperity.pipelines.stages.surface",
    "asperity.pipelines.bem_stage": "asperity.pipelines.stages.bem",
    "asperity.pipelines.resolution_stage": "asperity.pipelines.stages.statistical_model",
    "asperity.pipelines.friction_stage": "asperity.pipelines.stages.friction",
    "asperity.pipelines.psd_stage": "asperity.pipelines.stages.psd",
    "asperity.pipelines.fitting": "asperity.pipelines.stages.fitting",
    "asperity.pipelines.fields": "asperity.fields",
    "asperity.pipelines.verdict": "asperity.pipelines.stages.verdict",
}

#: Names the 0.2 docs and tests used through the old paths, each of which must still work.
DOCUMENTED_NAMES = {
    "asperity.pipelines.surface_stage": ("read_and_level", "scan_resolutions", "LevelledSurface"),
    "asperity.pipelines.bem_stage": ("bem_reference", "check_load_index", "load_chains"),
    "asperity.pipelines.resolution_stage": ("statistical_model_scan", "material_from_config"),
    "asperity.pipelines.friction_stage": ("calibrate_mode_mixity", "friction_prediction"),
    "asperity.pipelines.psd_stage": ("psd_and_persson",),
    "asperity.pipelines.fitting": ("fit_mode_mixity", "area_up_to_peak", "interpolate_area"),
    "asperity.pipelines.fields": ("array", "scalar", "text", "checksum", "field_specs"),
    "asperity.pipelines.verdict": ("job_reasons", "Verdict", "check_shape_scale", "MAX_MISFIT"),
}

#: Documented 0.2 names whose home moved again in 0.4 (the BEM numerics into asperity.bem).
MOVED_AGAIN = {
    "check_load_index": "asperity.bem.reference.load_sweeps",
    "load_chains": "asperity.bem.reference.load_sweeps",
}


@pytest.mark.parametrize("old", sorted(DEPRECATED_PATHS))
def test_deprecated_paths_warn_and_give_the_same_objects(old: str) -> None:
    """A 0.2 path warns, naming the new path and the version that removes it, and gives the
    very objects of the new module (isinstance and identity checks behave as before)."""
    importlib.import_module(DEPRECATED_PATHS[old])  # the new module first: only the shim runs
    sys.modules.pop(old, None)  # a first import in this process warns: make this one the first
    with pytest.warns(DeprecationWarning, match=r"removed in asperity 0\.5") as caught:
        exec(compile(f"import {old}", __file__, "exec"), {})  # a user's import statement
    shim = sys.modules[old]
    assert DEPRECATED_PATHS[old] in str(caught[0].message)
    assert caught[0].filename == __file__  # the user's line, so Python's default filter shows it
    for name in DOCUMENTED_NAMES[old]:
        home = importlib.import_module(MOVED_AGAIN.get(name, DEPRECATED_PATHS[old]))
        assert getattr(shim, name) is getattr(home, name), f"{old}.{name}"


def test_undocumented_paths_of_0_2_are_gone() -> None:
    """Only the documented 0.2 paths have a deprecation module; no finder serves the others."""
    for old in ("store", "outdir", "parallel", "bem_grid", "html_report", "run_cli"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(f"asperity.pipelines.{old}")


def _source_modules() -> dict[str, Path]:
    """Every module of the asperity namespace (folders mapped by pyproject.toml) -> its file."""
    modules = {}
    for package, folder in _declared_packages().items():
        for source in sorted((REPO / folder).glob("*.py")):
            name = package if source.name == "__init__.py" else f"{package}.{source.stem}"
            modules[name] = source
    return modules


def test_no_module_installs_an_import_hook() -> None:
    """No meta-path finder or path hook: an import path is a file a reader can open. Checked in
    the source and, after importing every module, on ``sys.meta_path`` itself."""
    hooks = re.compile(r"sys\.meta_path|sys\.path_hooks|MetaPathFinder|PathEntryFinder")
    assert [name for name, f in _source_modules().items() if hooks.search(f.read_text())] == []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # the 0.2 paths' modules
        for name in _source_modules():
            if not name.endswith("__main__"):
                importlib.import_module(name)
    ours = [f for f in sys.meta_path if type(f).__module__.split(".")[0] == "asperity"]
    assert ours == []


def _is_type_checking_block(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def _imported_modules(name: str, source: Path, known: set[str]) -> set[str]:
    """The asperity modules that ``name`` imports, anywhere in it (functions too), except under
    ``if TYPE_CHECKING:``. ``from pkg import sub`` counts as importing ``pkg.sub``; ``pkg``
    itself only when a name is not a submodule."""
    is_package = source.name == "__init__.py"
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if _is_type_checking_block(child):
                continue
            if isinstance(child, ast.Import):
                found.update(alias.name for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                module = child.module or ""
                if child.level:
                    base = name.split(".")[: None if is_package else -1]
                    base = base[: len(base) - child.level + 1]
                    module = ".".join([*base, module] if module else base)
                subs = {f"{module}.{alias.name}" for alias in child.names} & known
                found.update(subs)
                if len(subs) < len(child.names):
                    found.add(module)
            visit(child)

    visit(ast.parse(source.read_text()))
    return (found & known) - {name}


def _import_cycles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    cycles: list[set[str]] = []

    def connect(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for other in graph[node]:
            if other not in index:
                connect(other)
                low[node] = min(low[node], low[other])
            elif other in stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = set()
            while True:
                member = stack.pop()
                component.add(member)
                if member == node:
                    break
            if len(component) > 1:
                cycles.append(component)

    for node in sorted(graph):
        if node not in index:
            connect(node)
    return cycles


def test_no_import_cycle_between_modules() -> None:
    """No module imports, directly or through others, a module that imports it back (at module
    level or inside a function). The namespace ``asperity`` itself is left out as a target: it
    imports no asperity module when imported (checked here), so importing it closes no cycle."""
    modules = _source_modules()
    known = set(modules)
    graph = {name: _imported_modules(name, f, known) - {"asperity"} for name, f in modules.items()}
    top_level = ast.parse(modules["asperity"].read_text()).body
    assert not [
        ast.unparse(node)
        for node in top_level
        if isinstance(node, (ast.Import, ast.ImportFrom)) and "asperity" in ast.unparse(node)
    ]
    cycles = _import_cycles(graph)
    assert cycles == []


def test_the_cycle_check_finds_a_cycle_through_a_function_level_import(tmp_path: Path) -> None:
    """The checker itself: a private helper imported across two modules inside functions, as
    topo/cli.py and topo/profile_cli.py once did, is a cycle; a one-way import is not."""
    (tmp_path / "a.py").write_text("def f():\n    from pkg.b import g\n")
    (tmp_path / "b.py").write_text("from pkg.c import h\n\ndef g():\n    from pkg.a import f\n")
    (tmp_path / "c.py").write_text("import numpy\n")
    known = {"pkg.a", "pkg.b", "pkg.c"}
    graph = {m: _imported_modules(m, tmp_path / f"{m[4:]}.py", known) for m in known}
    assert graph == {"pkg.a": {"pkg.b"}, "pkg.b": {"pkg.a", "pkg.c"}, "pkg.c": set()}
    assert _import_cycles(graph) == [{"pkg.a", "pkg.b"}]


def test_documented_entry_points_still_resolve() -> None:
    import asperity
    from asperity.pipelines import config, job
    from asperity.pipelines.engine.stage import Runner, Stage, StageContext

    assert callable(job.run_job) and callable(config.load_preset)
    assert callable(asperity.open_results)
    assert Stage.__module__ == "asperity.pipelines.engine.stage"
    assert Runner and StageContext
    assert [s.name for s in job.STAGES] == list(job.STAGE_NAMES)
