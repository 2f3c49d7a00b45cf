"""The same solver on CuPy arrays (skipped without CuPy and a CUDA device; CI has none)."""

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import cupy_available, free_boundary_operator, periodic_operator
from tribobem.interactions import DugdaleAdhesion
from tribobem.solvers import solve_normal

pytestmark = [
    pytest.mark.gpu,
    pytest.mark.skipif(not cupy_available(), reason="CuPy with a CUDA device is not available"),
]

PAIR = ContactPair(Material(100e9, 0.3), Material.rigid())


@pytest.mark.parametrize("periodic", [False, True])
def test_operator_matches_numpy(periodic):
    grid = Grid.square(64, 1e-6, periodic=periodic)
    make = periodic_operator if periodic else free_boundary_operator
    p = np.random.default_rng(0).random(grid.shape) * 1e6
    u_cpu = make(grid, PAIR).apply(p)
    op_gpu = make(grid, PAIR, backend="cupy")
    u_gpu = op_gpu.backend.to_numpy(op_gpu.apply(op_gpu.backend.asarray(p)))
    np.testing.assert_allclose(u_gpu, u_cpu, rtol=1e-10, atol=1e-12 * np.abs(u_cpu).max())


def test_adhesive_solve_matches_numpy():
    grid = Grid.square(128, 200e-9)
    R = 2.5e-6
    gap = grid.radius() ** 2 / (2 * R)
    adh = DugdaleAdhesion.from_maugis(1.0, R, PAIR.effective_modulus, 0.3e-9)
    cpu = solve_normal(free_boundary_operator(grid, PAIR), gap, force=1e-6, interaction=adh)
    gpu = solve_normal(free_boundary_operator(grid, PAIR, backend="cupy"), gap, force=1e-6, interaction=adh)
    assert gpu.converged
    assert gpu.contact_area == pytest.approx(cpu.contact_area, rel=1e-6)
    assert gpu.approach == pytest.approx(cpu.approach, rel=1e-8)
