"""The Polonsky-Keer solver's sparse displacement updates (solvers/normal.py, issue 9).

When a few nodes change status in an iteration the solver adds their columns of K in real
space (elasticity/columns.py) instead of recomputing u = K p with a convolution, and it
convolves with a split inverse transform (``columns.convolve``).  Checked here:

* a sum of kernel columns equals ``op.apply`` of the sparse vector to 1e-12 relative, on
  periodic and free-boundary grids (square, rectangular, odd sizes, nodes on the edges);
* ``convolve`` equals ``op.apply`` to round-off;
* solves with the sparse path give the same contact nodes and pressures within 1e-9
  relative as solves that recompute the displacement exactly after every status change
  (``_SPARSE_MAX_NODES = -1``), and the sparse path was taken.
"""

from __future__ import annotations

import numpy as np
import pytest

import tribobem.solvers.normal as normal
from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.elasticity.columns import KernelColumns, convolve
from tribobem.geometry.shapes import sphere
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.solvers.normal import solve_normal

PAIR = ContactPair(Material(1.0, 0.3), Material.rigid())
E_STAR = PAIR.effective_modulus


def _operator(periodic, nx, ny, lx=1.0, ly=1.3):
    grid = Grid(nx, ny, lx, ly, periodic)
    return periodic_operator(grid, PAIR) if periodic else free_boundary_operator(grid, PAIR)


def _rough(nx, ny, seed=0, hurst=0.8):
    """Filtered-noise periodic surface (self-affine band), zero mean, rms 1."""
    rng = np.random.default_rng(seed)
    qx = np.fft.fftfreq(nx)[:, None] * nx
    qy = np.fft.rfftfreq(ny)[None, :] * ny
    q = np.hypot(qx, qy)
    amp = np.where((q >= 2) & (q <= max(nx, ny) / 4), np.maximum(q, 1) ** (-1 - hurst), 0.0)
    spec = amp * (rng.standard_normal(q.shape) + 1j * rng.standard_normal(q.shape))
    s = np.fft.irfft2(spec, s=(nx, ny))
    return s / s.std()


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("shape", [(32, 32), (24, 40), (17, 12), (2, 9)])
def test_columns_equal_apply(periodic, shape):
    op = _operator(periodic, *shape)
    nx, ny = shape
    cols = KernelColumns(op)
    rng = np.random.default_rng(1)
    nodes = rng.integers(0, nx * ny, 12).tolist() + [0, nx * ny - 1, ny // 2, ny // 2 + 1, (nx - 1) * ny]
    vals = rng.standard_normal(len(nodes))
    d = np.zeros(nx * ny)
    np.add.at(d, nodes, vals)
    ref = op.apply(d.reshape(shape))
    u0 = rng.standard_normal(shape) * np.abs(ref).max()
    u = u0.copy()
    cols.add(u, nodes, vals, np.empty(shape))
    assert np.abs((u - u0) - ref).max() <= 1e-12 * np.abs(ref).max()
    # one column
    j = nodes[0]
    e = np.zeros(nx * ny)
    e[j] = 1.0
    col_ref = op.apply(e.reshape(shape))
    assert np.abs(cols.column(j) - col_ref).max() <= 1e-12 * np.abs(col_ref).max()


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("shape", [(32, 32), (24, 40), (17, 12)])
def test_convolve_equals_apply(periodic, shape):
    op = _operator(periodic, *shape)
    x = np.random.default_rng(2).random(shape)
    ref = op.apply(x)
    assert np.abs(convolve(op, x) - ref).max() <= 1e-13 * np.abs(ref).max()


def _solve_both(monkeypatch, *args, **kw):
    kw["method"] = "polonsky_keer"  # the sparse updates are Polonsky-Keer's
    res = solve_normal(*args, **kw)
    stats = res.info["counters"]
    monkeypatch.setattr(normal, "_SPARSE_MAX_NODES", -1)
    exact = solve_normal(*args, **kw)
    exact_stats = exact.info["counters"]
    monkeypatch.undo()
    assert res.converged and exact.converged
    assert stats["sparse_updates"] > 0, stats
    assert exact_stats["sparse_updates"] == 0
    assert np.array_equal(res.contact, exact.contact)
    scale = np.abs(exact.pressure).max()
    assert np.abs(res.pressure - exact.pressure).max() <= 1e-9 * scale
    assert abs(res.iterations - exact.iterations) <= 2
    return res, exact


def test_sparse_periodic_rough_force_control(monkeypatch):
    n = 128
    op = _operator(True, n, n, 1.0, 1.0)
    s = _rough(n, n) * 0.01
    h = s.max() - s
    _solve_both(monkeypatch, op, h, force=0.01 * E_STAR, tol=1e-10)


def test_sparse_periodic_rough_displacement_control(monkeypatch):
    n = 96
    op = _operator(True, n, 80, 1.0, 0.8)
    s = _rough(n, 80, seed=3) * 0.01
    h = s.max() - s
    _solve_both(monkeypatch, op, h, approach=0.6 * 0.01, tol=1e-10)


def test_sparse_free_boundary_sphere(monkeypatch):
    n = 64
    grid = Grid.square(n, 4e-6)
    op = free_boundary_operator(grid, PAIR)
    h = sphere(grid, 1e-3) + 2e-10 * _rough(n, n, seed=4)
    h -= h.min()
    force = 4 * E_STAR * (1e-6) ** 3 / (3 * 1e-3)
    _solve_both(monkeypatch, op, h, force=force, tol=1e-10)


def test_sparse_dugdale_displacement_control(monkeypatch):
    n = 96
    op = _operator(True, n, n, 1.0, 1.0)
    s = _rough(n, n, seed=5) * 0.01
    h = s.max() - s
    inter = DugdaleAdhesion.from_stress(0.05 * E_STAR, 0.001)
    _solve_both(monkeypatch, op, h, approach=float(np.mean(h)) - 0.015, interaction=inter, tol=1e-10)


def test_sparse_dugdale_force_control(monkeypatch):
    """Force control with an outside stress: the force balance rescales p - floor on the contact
    only, so the displacement needs W = K(p_out + floor 1_C), which the sparse path carries from
    the old sets by the changed nodes' columns (or convolves once).  The ball of
    benchmarks/adhesive_loop.py (R = 40 um, 100 GPa / 0.25 on a rigid body, Dugdale 40 mJ/m^2,
    z0 = 0.2 nm) at 96^2, warm-started on a tilted gap (as the shear-induced normal displacement
    of the coupling loop tilts it)."""
    op, h, tilted, inter, first = _adhesive_ball(96)
    assert first.adhesive.any()
    _solve_both(monkeypatch, op, tilted, force=8e-6, interaction=inter, tol=1e-10, initial_pressure=first)


def _adhesive_ball(n):
    """The ball of benchmarks/adhesive_loop.py on n^2 cells: (operator, gap, the gap tilted as the
    coupling loop's shear-induced displacement tilts it, the Dugdale law, the solved first state)."""
    pair = ContactPair(Material(100e9, 0.25), Material.rigid())
    grid = Grid.square(n, 0.6e-6)
    op = free_boundary_operator(grid, pair)
    h = sphere(grid, 40e-6)
    inter = DugdaleAdhesion(40e-3, 0.2e-9)
    first = solve_normal(op, h, force=8e-6, interaction=inter, tol=1e-10)
    assert first.converged
    x = (np.arange(n)[:, None] - n // 2) * grid.dx * np.ones((1, n))
    return op, h, h + 3e-6 * x, inter, first


def test_warm_start_with_pressure_outside_contact():
    """A warm start whose pressure is nonzero outside the given contact, under force control:
    the rescale needs K of that pressure (W), which the sparse path convolves or updates."""
    n = 64
    op = _operator(True, n, n, 1.0, 1.0)
    s = _rough(n, n, seed=6) * 0.01
    h = s.max() - s
    first = solve_normal(op, h, force=0.01 * E_STAR, tol=1e-10, method="polonsky_keer")
    contact = first.contact.copy()
    contact[np.argwhere(first.contact)[0][0], np.argwhere(first.contact)[0][1]] = False
    res = solve_normal(op, h, force=0.011 * E_STAR, tol=1e-10, initial_pressure=first.pressure,
                       initial_contact=contact, method="polonsky_keer")
    assert res.converged
    assert abs(res.force - 0.011 * E_STAR) <= 1e-9 * 0.011 * E_STAR


def test_initial_displacement_replaces_the_first_convolution():
    """A warm start from a NormalResult on the same operator may hand over its displacement
    (K p of its pressure, as the coupling loop's passes do): the same iterates to the last bit,
    one exact convolution fewer.  A displacement that does not belong to the warm start (the
    pressure raised to the floor) is not used."""
    op, h, tilted, inter, first = _adhesive_ball(64)
    plain = solve_normal(op, tilted, force=8e-6, interaction=inter, tol=1e-10, initial_pressure=first)
    given = solve_normal(op, tilted, force=8e-6, interaction=inter, tol=1e-10, initial_pressure=first,
                         initial_displacement=first.displacement)
    assert plain.converged and given.converged
    assert np.array_equal(plain.pressure, given.pressure)
    assert np.array_equal(plain.contact, given.contact)
    assert plain.iterations == given.iterations
    assert given.info["counters"]["exact"] == plain.info["counters"]["exact"] - 1
    # a pressure below the floor is raised by the solver: the handed displacement is not its K p
    low = first.pressure.copy()
    low[0, 0] = -1e12
    ref = solve_normal(op, tilted, force=8e-6, interaction=inter, tol=1e-10, initial_pressure=low,
                       initial_contact=first.contact)
    wrong = solve_normal(op, tilted, force=8e-6, interaction=inter, tol=1e-10, initial_pressure=low,
                         initial_contact=first.contact, initial_displacement=first.displacement)
    assert np.array_equal(ref.pressure, wrong.pressure)
    assert wrong.info["counters"]["exact"] == ref.info["counters"]["exact"]
