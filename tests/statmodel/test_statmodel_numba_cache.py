"""The compiled kernels are cached on disk: a second process loads them instead of compiling."""

import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numba.core.caching import FunctionCache
from numba.core.dispatcher import Dispatcher
from numba.np.ufunc.dufunc import DUFunc

#: The modules with compiled kernels: the statistical model's and the single-asperity closed
#: forms it stands on.
KERNEL_MODULES = (
    "asperity.statmodel.integrals",
    "asperity.statmodel.jkr",
    "asperity.statmodel.status_map",
    "asperity.single_asperity.jkr",
    "asperity.single_asperity.papangelo_ciavarella",
)

SCRIPT = (
    "import numpy as np\n"
    "from asperity.statmodel import Material, Roughness, shear_curve\n"
    "shear_curve(Material(2.133e6, 0.04, 0.2, 0.13e6), Roughness(652.1e6, 0.041e-3, 0.032e-3),"
    " 700e-6, 3.1, np.linspace(0.0, 14e-6, 5))\n"
)


def _kernels():
    """(module.name, numba disk cache or None) of every compiled function and ufunc."""
    for path in KERNEL_MODULES:
        module = importlib.import_module(path)
        short = path.rsplit(".", 1)[1]
        for name, obj in vars(module).items():
            if isinstance(obj, DUFunc):
                yield f"{short}.{name}", getattr(obj._dispatcher, "cache", None)
            elif isinstance(obj, Dispatcher) and obj.__module__ == module.__name__:
                yield f"{short}.{name}", obj._cache


def test_every_kernel_is_compiled_with_a_disk_cache():
    kernels = dict(_kernels())
    assert len(kernels) > 20
    uncached = [name for name, cache in kernels.items() if not isinstance(cache, FunctionCache)]
    assert not uncached, f"@njit/@vectorize without cache=True: {uncached}"


def test_the_shear_kernels_leave_their_cache_index_on_disk():
    from asperity.statmodel import Material, Roughness, shear_curve

    shear_curve(
        Material(2.133e6, 0.04, 0.2, 0.13e6),
        Roughness(652.1e6, 0.041e-3, 0.032e-3),
        700e-6,
        3.1,
        np.linspace(0.0, 14e-6, 5),
    )
    kernels = dict(_kernels())
    for name in ("integrals.shear_path", "integrals.asperity_integrals", "jkr._jkr_radius_ufunc"):
        index = Path(kernels[name]._cache_file._index_path)
        assert index.is_file(), f"{name}: no cache index {index}"


def _run() -> str:
    env = {**os.environ, "NUMBA_DEBUG_CACHE": "1"}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return done.stdout + done.stderr


@pytest.mark.slow  # two fresh interpreters importing numba: ~5 s
def test_second_process_loads_every_kernel_from_the_disk_cache():
    _run()  # compiles and saves whatever is not cached yet
    log = _run()
    assert "data saved" not in log  # nothing recompiled
    loaded = [line for line in log.splitlines() if "data loaded from" in line]
    for kernel in ("integrals.shear_path", "integrals.asperity_integrals", "jkr._jkr_radius_ufunc"):
        assert any(kernel in line for line in loaded), kernel
