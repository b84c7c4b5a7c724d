"""The compiled kernels are cached on disk: a second process loads them instead of compiling."""

import os
import subprocess
import sys

SCRIPT = (
    "import numpy as np\n"
    "from statmodel import Material, Roughness, shear_curve\n"
    "shear_curve(Material(2.133e6, 0.04, 0.2, 0.13e6), Roughness(652.1e6, 0.041e-3, 0.032e-3),"
    " 700e-6, 3.1, np.linspace(0.0, 14e-6, 5))\n"
)


def _run() -> str:
    env = {**os.environ, "NUMBA_DEBUG_CACHE": "1"}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    return done.stdout + done.stderr


def test_second_process_loads_every_kernel_from_the_disk_cache():
    _run()  # compiles and saves whatever is not cached yet
    log = _run()
    assert "data saved" not in log  # nothing recompiled
    loaded = [line for line in log.splitlines() if "data loaded from" in line]
    for kernel in ("integrals.shear_path", "integrals.asperity_integrals", "jkr._jkr_radius_ufunc"):
        assert any(kernel in line for line in loaded), kernel
