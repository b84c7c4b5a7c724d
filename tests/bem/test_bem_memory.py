"""Memory of the BEM solver: what it holds per grid point, and that the savings keep the numbers.

The footprint is measured with tracemalloc (numpy's and pyFFTW's arrays are traced) on
small grids, in bytes per height point above the heights themselves; the floors named in the
messages are the arrays :mod:`asperity.bem.normal.iteration` keeps (p, w, t, one work array: 8 B
each,
the contact set: 1 B) and the transform workspace shared by the operators (8 B).
"""

from __future__ import annotations

import gc
import tracemalloc

import numpy as np
import pytest

from asperity import bem
from asperity.bem.elastic.fft_backend import (
    Convolution,
    RadialMultiplier,
    available_backends,
    new_workspace,
)
from asperity.bem.elastic.influence import (
    love_patch_deflection,
    padded_love_multiplier,
    point_force_multiplier,
    wavevectors_squared,
)
from asperity.bem.elastic.operators import influence_operator, stiffness_preconditioner

E_STAR = 2.133e6  # Pa
DX = 2e-6  # m

needs_pyfftw = pytest.mark.skipif(
    "pyfftw" not in available_backends(), reason="the shared workspace is pyFFTW's"
)


def _rough(n: int, seed: int = 3) -> np.ndarray:
    """A random periodic rough surface (m), rms about 1 um, red spectrum."""
    rng = np.random.default_rng(seed)
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.rfftfreq(n), indexing="ij"))
    q[0, 0] = 1.0
    spec = (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape)) * q**-1.8
    spec[0, 0] = 0.0
    h = np.fft.irfft2(spec, s=(n, n))
    return h * (1e-6 / h.std())


def test_radial_multipliers_equal_the_stored_ones_bit_for_bit():
    nx, ny, dx, dy = 48, 30, 2e-6, 3e-6
    qx2, qy2 = wavevectors_squared(nx, ny, dx, dy)
    point = RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1).materialise()
    assert np.array_equal(point, point_force_multiplier(nx, ny, dx, dy, E_STAR))
    # the stiffness E* |q| / 2 with |q| at q = 0 replaced (the preconditioner)
    qx = 2.0 * np.pi * np.fft.fftfreq(nx, d=dx)
    qy = 2.0 * np.pi * np.fft.rfftfreq(ny, d=dy)
    q = np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
    q[0, 0] = 0.1 * q[0, 1]
    stiff = RadialMultiplier(qx2, qy2, 0.5 * E_STAR, 1, q[0, 0]).materialise()
    assert np.array_equal(stiff, 0.5 * E_STAR * q)


@pytest.mark.parametrize("precision", ["double", "single"])
@pytest.mark.parametrize("backend", available_backends())
def test_radial_and_stored_multipliers_convolve_identically(precision, backend):
    nx, ny = 40, 26
    qx2, qy2 = wavevectors_squared(nx, ny, DX, DX)
    radial = RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1)
    a = Convolution(radial, (nx, ny), backend=backend, threads=1, precision=precision)
    b = Convolution(radial.materialise(), (nx, ny), backend=backend, threads=1, precision=precision)
    x = np.random.default_rng(1).standard_normal((nx, ny))
    ya, yb = a.empty(), b.empty()
    assert a.with_energy(x, ya) == b.with_energy(x, yb)
    assert np.array_equal(ya, yb)
    assert np.array_equal(a(x), b(x))


@needs_pyfftw
def test_operators_sharing_a_workspace_give_their_own_results():
    """Double and single precision, kernel and stiffness, on one workspace, interleaved: each
    result equals that of an operator with buffers of its own."""
    n = 64
    qx2, qy2 = wavevectors_squared(n, n, DX, DX)
    mults = [
        RadialMultiplier(qx2, qy2, 2.0 / E_STAR, -1),
        RadialMultiplier(qx2, qy2, 0.5 * E_STAR, 1, 1.0),
    ]
    ws = new_workspace((n, n))
    x = np.random.default_rng(2).standard_normal((n, n))
    shared, alone = [], []
    for m in mults:
        for precision in ("double", "single"):
            kw = dict(backend="pyfftw", threads=1, precision=precision)
            shared.append(Convolution(m, (n, n), workspace=ws, **kw))
            alone.append(Convolution(m, (n, n), **kw))
    for _ in range(2):
        for s, a in zip(shared, alone, strict=True):
            ys, ya = s.empty(), a.empty()
            assert s.with_energy(x, ys) == a.with_energy(x, ya)
            assert np.array_equal(ys, ya)


def test_a_workspace_too_small_is_refused():
    n = 16
    qx2, qy2 = wavevectors_squared(n, n, DX, DX)
    with pytest.raises(bem.BemInputError, match="workspace"):
        Convolution(
            RadialMultiplier(qx2, qy2, 1.0, -1),
            (n, n),
            backend="scipy",
            workspace=np.empty(10, dtype=np.uint8),
        )


def _traced_solve(h: np.ndarray, **kw) -> tuple[float, float, bem.ContactResult]:
    """Peak and held-after traced bytes per point of one solve (operators warmed first)."""
    n = h.shape[0]
    load = 2e-4 * E_STAR * h.size * DX * DX
    opts = bem.SolverOptions(tol=1e-6, fft_backend="pyfftw", threads=1, precision="mixed")
    bem.solve_contact(h, DX, DX, E_STAR, normal_force=load, options=opts, **kw)
    gc.collect()
    tracemalloc.start()
    try:
        res = bem.solve_contact(h, DX, DX, E_STAR, normal_force=load, options=opts, **kw)
        cur, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return peak / n**2, cur / n**2, res


@needs_pyfftw
def test_a_periodic_solve_holds_its_state_and_one_spectrum():
    """Peak <= p, w, t, work (8 B each) and the contact set (1 B) plus 3 B of slack (the
    operators and their shared workspace were made by the warm-up solve); after the solve the
    result alone (pressure, gap, mask: 17 B, taken from the state without copies).
    """
    peak, held, res = _traced_solve(_rough(256))
    assert res.converged and 0.01 < res.contact_fraction < 0.5
    assert peak <= 36.0, f"peak {peak:.1f} B/point"
    assert held <= 18.0, f"held {held:.1f} B/point"


@needs_pyfftw
def test_a_periodic_maugis_solve_drops_its_warm_start():
    """The Maugis iteration adds the lifted heights (8 B) and the attractive set (1 B), not the
    previous inner solution (17 B, its gap dropped before the next lift) while the next one
    iterates; its inner solves store the direction in float32 and keep the work array in the
    transform workspace: p, w (8 B), t (4 B), c (1 B) and those 9 B, 30 B, plus 3 B of slack
    (measured 31.4; 36.4 with a float32 work array of its own, 45.9 before that)."""
    peak, _, res = _traced_solve(
        _rough(256), work_of_adhesion=0.002, adhesion="maugis", adhesion_range=0.5e-6
    )
    assert res.converged and 0.01 < res.contact_fraction < 0.5
    assert res.extra["set_solves"] >= 2
    assert peak <= 33.0, f"peak {peak:.1f} B/point"


@pytest.mark.parametrize("precision", ["double", "single"])
@pytest.mark.parametrize("backend", available_backends())
def test_the_padded_operator_is_the_free_space_convolution(precision, backend):
    """The finite-specimen operator (arrays on the map, transform padded in place) against the
    direct real-space sum of Love's patch deflections over every pressure pixel."""
    nx, ny, dx, dy = 9, 7, 2e-6, 3e-6
    op = influence_operator((nx, ny), dx, dy, E_STAR, "point", False, backend, 1, precision)
    assert op.shape == (nx, ny)
    p = np.random.default_rng(4).standard_normal((nx, ny))
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    direct = np.zeros((nx, ny))
    for i in range(nx):
        for j in range(ny):
            patch = love_patch_deflection((ix - i) * dx, (iy - j) * dy, dx, dy, E_STAR)
            direct += p[i, j] * patch
    out = op.empty()
    energy = op.with_energy(p, out)
    rtol = 1e-12 if precision == "double" else 1e-6
    scale = np.abs(direct).max()
    assert np.abs(out - direct).max() <= rtol * scale
    assert energy == pytest.approx(float(np.sum(p * direct)), rel=10 * rtol)
    # float32 input and output (the compact state's direction and work arrays)
    out32 = np.empty((nx, ny), dtype=np.float32)
    op(p.astype(np.float32), out=out32)
    assert np.abs(out32 - direct).max() <= 1e-6 * scale


@pytest.mark.parametrize("backend", available_backends())
def test_the_in_place_periodic_operator_equals_the_out_of_place_one(backend):
    nx, ny = 40, 26
    args = ((nx, ny), DX, DX, E_STAR, "point", True, backend, 1)
    plain = influence_operator(*args)
    in_place = influence_operator(*args, in_place=True)
    assert in_place is not plain and in_place.shape == (nx, ny)
    x = np.random.default_rng(5).standard_normal((nx, ny))
    y0, y1 = plain.empty(), in_place.empty()
    e0, e1 = plain.with_energy(x, y0), in_place.with_energy(x, y1)
    assert np.abs(y1 - y0).max() <= 1e-13 * np.abs(y0).max()
    assert e1 == pytest.approx(e0, rel=1e-13)
    assert e0 == pytest.approx(float(np.sum(x * y0)), rel=1e-12)


@needs_pyfftw
@pytest.mark.parametrize("adhesion", ["none", "maugis"])
def test_a_free_boundary_solve_keeps_its_arrays_on_the_map(adhesion):
    """The state lives on the map, not on the doubled grid (before: p, w, t, r, c and the
    heights padded, 4 x 41 B = 164 B per map point; measured 173 B, Maugis 218 B): p, w (8 B
    each), t (float32, 4 B), the contact set (1 B), 21 B, the work array in the transform
    workspace, plus 3 B of slack (measured 21.8; Maugis: the lifted heights and the
    attractive set, 9 B more, measured 32.4; with a float32 work array of its own and the
    cold start's temporaries: 25.6 and 37.3); the result takes the state's arrays (17 B
    held)."""
    kw = {}
    if adhesion == "maugis":
        kw = dict(work_of_adhesion=0.002, adhesion="maugis", adhesion_range=0.5e-6)
    peak, held, res = _traced_solve(_rough(128), periodic=False, **kw)
    assert res.converged and 0.005 < res.contact_fraction < 0.5
    bound = 24.0 if adhesion == "none" else 35.0
    assert peak <= bound, f"peak {peak:.1f} B/point"
    assert held <= 18.0, f"held {held:.1f} B/point"


@needs_pyfftw
def test_the_operators_of_a_free_grid_share_one_workspace():
    """The influence operators (double, single) and their preconditioners on a doubled grid
    hold one transform workspace (32 B per map point) and one Love multiplier (half its rows,
    float64: 8 B per map point) between them: 40 B plus 3 B of slack. Before, each held a
    workspace of its own and each precision a multiplier (measured 152 B per map point)."""
    n = 128
    gc.collect()
    tracemalloc.start()
    try:
        args = ((n, n), DX, DX, E_STAR, "point", False, "pyfftw", 1)
        ops = [influence_operator(*args), influence_operator(*args, precision="single")]
        ops += [stiffness_preconditioner(op, DX, DX, E_STAR) for op in ops]
        held, _ = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    x = np.random.default_rng(6).standard_normal((n, n))
    assert all(np.isfinite(op(x)).all() for op in ops)
    assert held / n**2 <= 43.0, f"held {held / n**2:.1f} B/point"


@pytest.mark.parametrize("precision", ["double", "single"])
@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("backend", available_backends())
def test_the_workspace_head_is_an_input_and_output_like_any_other(precision, periodic, backend):
    """The work array viewed at the head of the workspace (moved into the padded grid and
    back in place) gives the convolution of a float32 array of its own, bit for bit, and the
    same energy; odd and even sizes (the rows' padding differs)."""
    for shape in ((9, 7), (12, 10), (5, 16)):
        args = (shape, DX, 1.5 * DX, E_STAR, "point", periodic, backend, 1, precision)
        op = influence_operator(*args, in_place=True)
        x = np.random.default_rng(7).standard_normal(shape).astype(np.float32)
        own = np.empty(shape, dtype=np.float32)
        e_own = op.with_energy(x, own)
        head = op.work_array()
        head[...] = x
        e_head = op.with_energy(head, head)
        assert e_head == e_own
        assert np.array_equal(head, own)
        # as the output of a float64 input, and as the input of a float64 output
        y = np.empty(shape)
        op(x.astype(np.float64), out=head)
        assert np.array_equal(head, own)
        op(head, out=y)
        assert np.array_equal(y, op(own.copy(), out=np.empty(shape)))


def test_love_multiplier_stored_as_half_its_rows_is_the_full_one():
    """The free-boundary operator keeps rows 0 .. gx/2 of Love's multiplier on the doubled
    grid (even in qx); rows i and gx - i read from them equal numpy's transform of the same
    real-space kernel within round-off."""
    nx, ny, dx, dy = 24, 17, 2e-6, 3e-6
    full = padded_love_multiplier(nx, ny, dx, dy, E_STAR) / (4 * nx * ny)
    op = influence_operator((nx, ny), dx, dy, E_STAR, "point", False, "scipy", 1)
    half = op._even.half
    gx = 2 * nx
    rows = [min(i, gx - i) for i in range(gx)]
    assert half.shape == (nx + 1, ny + 1)
    assert np.abs(half[rows] - full).max() <= 1e-13 * np.abs(full).max()
