"""The array-library Polonsky-Keer (bem.normal.array_solver) against the CPU solver on the same
maps.

Two implementations of E:BEM_eq1..E:BEM_eq4 that share no iteration code must give the same
contact set and pressures within their tolerance; the GPU (CuPy) path runs only where CuPy and a
GPU are present (never in CI), its NumPy twin everywhere.
"""

from __future__ import annotations

import numpy as np
import pytest

from asperity.bem import SolverOptions, solve_contact
from asperity.bem.errors import BemInputError
from asperity.bem.normal.array_solver import array_module, solve_periodic_array
from asperity.topo.synthetic import self_affine

E_STAR = 2.0e6  # Pa
DX = 1.0e-6  # m


def _map(n: int, ny: int, seed: int) -> np.ndarray:
    return self_affine(n, DX, rms_height=1e-6, rolloff_wavelength=32e-6, seed=seed, ny=ny).heights


def _load(heights: np.ndarray, fraction: float) -> float:
    """A force (N) giving about ``fraction`` contact: A_r/A_n ~ 2 p / (E* h'_rms)."""
    slope = np.sqrt(np.mean(np.gradient(heights, DX, axis=0) ** 2) * 2)
    return fraction * E_STAR * slope / 2 * heights.size * DX * DX


@pytest.mark.parametrize(("n", "ny", "seed", "fraction"), [(128, 128, 1, 0.02), (96, 160, 2, 0.2)])
@pytest.mark.parametrize("tol", [1e-6, 1e-9])
def test_numpy_path_matches_cpu_solver(n: int, ny: int, seed: int, fraction: float, tol: float):
    heights = _map(n, ny, seed)
    force = _load(heights, fraction)
    cpu = solve_contact(heights, DX, DX, E_STAR, normal_force=force, options=SolverOptions(tol=tol))
    arr = solve_periodic_array(heights, DX, DX, E_STAR, force, tol=tol)
    assert cpu.success and arr.success, arr.message
    assert arr.residual < tol
    assert np.count_nonzero(cpu.contact_mask != arr.contact_mask) <= 2
    rel = np.linalg.norm(cpu.pressure - arr.pressure) / np.linalg.norm(cpu.pressure)
    assert rel < 20 * tol
    assert arr.normal_force == pytest.approx(force, rel=1e-12)
    assert arr.separation == pytest.approx(cpu.separation, rel=50 * tol)
    assert np.min(arr.gap) > -tol * np.ptp(heights)
    assert np.all(arr.pressure >= 0)


def test_iteration_cap_is_reported_not_converged():
    heights = _map(64, 64, 3)
    arr = solve_periodic_array(heights, DX, DX, E_STAR, _load(heights, 0.05), tol=1e-12, max_iter=3)
    assert not arr.success
    assert arr.status == 1 and arr.message.startswith("iteration cap")
    assert arr.nit == 3


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"dx": 0.0}, "dx"),
        ({"normal_force": -1.0}, "normal_force"),
        ({"normal_force": float("nan")}, "normal_force"),
        ({"heights": np.zeros(5)}, "heights"),
        ({"heights": np.full((4, 4), np.nan)}, "heights"),
        ({"xp": "torch"}, "array library"),
    ],
)
def test_bad_input_names_the_argument(kwargs: dict, named: str):
    args = {"heights": np.zeros((8, 8)), "dx": DX, "dy": DX, "e_star": E_STAR, "normal_force": 1.0}
    args.update(kwargs)
    with pytest.raises(BemInputError, match=named):
        solve_periodic_array(**args)


def test_cupy_path_matches_numpy_path_on_a_gpu():
    try:
        array_module("cupy")
    except BemInputError as exc:
        pytest.skip(f"no GPU path here: {exc}")
    heights = _map(256, 256, 4)
    force = _load(heights, 0.05)
    gpu = solve_periodic_array(heights, DX, DX, E_STAR, force, xp="cupy", tol=1e-9)
    cpu = solve_periodic_array(heights, DX, DX, E_STAR, force, tol=1e-9)
    assert gpu.success and gpu.extra["array_library"] == "cupy"
    assert np.count_nonzero(gpu.contact_mask != cpu.contact_mask) <= 2
    assert np.linalg.norm(gpu.pressure - cpu.pressure) / np.linalg.norm(cpu.pressure) < 2e-8
