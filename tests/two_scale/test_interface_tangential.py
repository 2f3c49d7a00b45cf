"""The tangential interface law and the macro partial-slip solve with it.

* A stiff interface (its slip 1e-6 of the displacement) on a sharp flat punch of an
  incompressible body against a rigid one (no normal-tangential coupling) is the full-stick punch:
  F/delta = 8 b/k (Mindlin's full-stick stiffness).
* A linear slip law s = c tau on a uniformly loaded periodic cell: a uniform shear carries no
  periodic displacement, so delta = c F / A exactly.
* The macro state satisfies its discrete problem: G tau + s = delta on the cells that stick,
  tau at the window's sliding shear on the others, the force balance.
"""

import math

import numpy as np
import pytest

from tribobem.analytic.punch import flat_punch, full_stick_stiffness
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.errors import InputError
from tribobem.geometry.shapes import burl
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.two_scale.laws import NormalInterfaceLaw
from tribobem.two_scale.macro import solve_interface_normal
from tribobem.two_scale.tangential import SLIP_FRACTIONS, TangentialInterfaceLaw, solve_interface_tangential

INCOMPRESSIBLE = Material(1e9, 0.5)
MU = 0.5


def slip_law(slope, pressures=None, mu=MU):
    """s = slope * tau (m/Pa) at every pressure: a linear (Winkler-like) tangential layer."""
    ps = np.geomspace(1e3, 1e12, 10) if pressures is None else pressures
    f = np.asarray(SLIP_FRACTIONS)
    slips = np.array([slope * f * mu * p for p in ps])
    return TangentialInterfaceLaw(ps, f, slips, np.ones_like(slips) * 0.5, mu, np.zeros_like(slips))


def stiff_normal_law():
    ps = np.geomspace(1e2, 1e11, 64)
    return NormalInterfaceLaw(ps, 1e-10 - 1e-15 * np.log(ps / 1e2), 1e-10 + 1e-15, np.full(64, 0.1), ps,
                              np.zeros(64), np.zeros(64))


def test_the_slip_law_interpolates_its_table():
    law = slip_law(1e-18)
    p = np.array([1e5, 3e7, 2e10])
    tau = 0.37 * MU * p
    s, ds = law.slip(tau, p)
    assert np.allclose(s, 1e-18 * tau, rtol=1e-9)
    assert np.allclose(ds, 1e-18, rtol=1e-9)
    assert law.stick_ratio(np.zeros(3), p) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="increase"):
        TangentialInterfaceLaw(law.pressures, law.fractions, -law.slips, law.stick_ratios, MU, law.slip_spread)


@pytest.mark.parametrize("n", [64, 96])
def test_a_stiff_interface_is_the_full_stick_flat_punch(n):
    b = 1e-6
    pair = ContactPair(INCOMPRESSIBLE, Material.rigid("punch"))
    grid = Grid(n, n, 3 * b, 3 * b)
    op = free_boundary_operator(grid, pair, components=("x", "y", "z"))
    P = flat_punch(approach=5e-9, radius=b, E_star=pair.effective_modulus).force
    normal = solve_interface_normal(op.normal, burl(grid, b, 1e-10), stiff_normal_law(), P, tol=1e-10)
    F = 0.02 * MU * normal.force
    K_ref = full_stick_stiffness(b, INCOMPRESSIBLE.E, INCOMPRESSIBLE.nu, math.inf, 0.0)
    # an interface slip of 1e-6 of the punch's displacement at the mean shear
    slope = 1e-6 * (F / K_ref) / (F / (math.pi * b * b))
    res = solve_interface_tangential(op, normal.pressure, slip_law(slope), F, tol=1e-9)
    assert res.converged and res.force == pytest.approx(F, rel=1e-10)
    # the grid's error of the full-stick punch (validation.burl): dx / (2 b)
    assert F / res.displacement == pytest.approx(K_ref, rel=grid.dx / (2 * b))


def test_a_linear_layer_under_uniform_pressure_is_its_closed_form():
    grid = Grid(32, 32, 1e-5, 1e-5, periodic=True)
    op = periodic_operator(grid, ContactPair(Material(100e9, 0.3), Material.rigid()), components=("x", "y", "z"))
    p = np.full(grid.shape, 1e8)
    c = 3e-18
    F = 0.4 * MU * 1e8 * grid.lx * grid.ly
    res = solve_interface_tangential(op, p, slip_law(c), F, tol=1e-12)
    assert res.converged
    assert res.displacement == pytest.approx(c * F / (grid.lx * grid.ly), rel=1e-9)
    assert np.allclose(res.shear, F / (grid.lx * grid.ly), rtol=1e-9)


def test_the_state_satisfies_its_discrete_problem_with_sliding_cells():
    grid = Grid(64, 64, 8e-6, 8e-6)
    pair = ContactPair(Material(130e9, 0.28), Material(410e9, 0.14))
    op = free_boundary_operator(grid, pair, components=("x", "y", "z"))
    normal = solve_interface_normal(op.normal, burl(grid, 2e-6, 20e-6), stiff_normal_law(), 1e-3, tol=1e-10)
    law = slip_law(2e-19)
    # a slip that grows steeply towards the window's sliding (a rough interface's shape)
    law = TangentialInterfaceLaw(law.pressures, law.fractions, law.slips / (1.0 - law.fractions[None, :]) ** 0.5,
                                 law.stick_ratios, MU, law.slip_spread)
    F = 0.95 * law.max_fraction * MU * normal.force
    res = solve_interface_tangential(op, normal.pressure, law, F, tol=1e-9)
    assert res.converged and res.force == pytest.approx(F, rel=1e-10)
    loaded = normal.pressure > 0
    top = law.max_fraction * MU * normal.pressure
    sliding = loaded & (res.shear >= top * (1 - 1e-12))
    stick = loaded & ~sliding
    assert sliding.any() and stick.any()  # the edge slides first
    G = op.block("x", "x")
    unit = np.zeros(grid.shape)
    unit[grid.nx // 2, grid.ny // 2] = 1.0
    sign = 1.0 if G.apply(unit)[grid.nx // 2, grid.ny // 2] > 0 else -1.0  # the x-x block as a compliance
    u = sign * G.apply(res.shear)
    scale = np.abs(u[loaded]).max() + np.abs(res.slip[loaded]).max()
    assert np.max(np.abs(u[stick] + res.slip[stick] - res.displacement)) <= 1e-8 * scale
    assert np.all(res.displacement - u[sliding] >= res.slip[sliding] - 1e-8 * scale)
    with pytest.raises(InputError, match="force"):
        solve_interface_tangential(op, normal.pressure, law, 1.01 * MU * normal.force)


def rough_slip_law(mu=MU):
    """A nonlinear slip law (Cattaneo-like, s ~ 1 - (1 - f)^(2/3)) whose slope grows with f."""
    ps = np.geomspace(1e5, 1e10, 12)
    f = np.asarray(SLIP_FRACTIONS)
    slips = np.array([1e-9 * (p / 1e8) ** 0.3 * (1 - (1 - f) ** (2 / 3)) for p in ps])
    stick = np.tile((1 - f) ** (2 / 3), (ps.size, 1))
    return TangentialInterfaceLaw(ps, f, slips, stick, mu, np.zeros_like(slips))


def test_a_masing_loop_is_its_virgin_curve_scaled_by_two_and_balances_its_energy():
    from tribobem.solvers.hysteresis import cycle_path
    from tribobem.two_scale.tangential import interface_loop

    pair = ContactPair(Material(130e9, 0.28), Material(410e9, 0.14))
    grid = Grid(48, 48, 8e-6, 8e-6)
    op = free_boundary_operator(grid, pair, components=("x", "y", "z"))
    x = (np.arange(48) + 0.5) * grid.dx - 4e-6
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    p = np.where(r2 < (3e-6) ** 2, 5e7 * np.sqrt(np.clip(1 - r2 / 9e-12, 0, None)) + 1e6, 0.0)
    law = rough_slip_law()
    F_static = MU * p.sum() * grid.dx * grid.dy
    path = cycle_path(0.8 * F_static, 2, 16, "force")
    loop = interface_loop(op, p, law, path.values, path.turning, path.cycle, tol=1e-9)
    assert all(s.converged for s in loop.states)
    top = next(i for i, t in enumerate(path.turning) if t)
    Fs, ds = loop.forces[top], loop.displacements[top]
    # Masing at macro scale (no cell reaches its bound on this path): delta(F) = delta* - 2 delta_v((F* - F)/2)
    for k in range(top + 1, top + 9):
        virgin = solve_interface_tangential(op, p, law, (Fs - loop.forces[k]) / 2, tol=1e-9)
        assert loop.displacements[k] == pytest.approx(ds - 2 * virgin.displacement, rel=1e-6, abs=1e-7 * abs(ds))
    # the second cycle repeats the first (Masing loops close), and the interface's work is the loop area
    c1 = np.flatnonzero(path.cycle == 1)
    c2 = np.flatnonzero(path.cycle == 2)
    np.testing.assert_allclose(loop.displacements[c2], loop.displacements[c1], rtol=1e-6, atol=1e-7 * abs(ds))
    from tribobem.solvers.hysteresis import loop_energies

    F = np.concatenate([[0.0], loop.forces])
    D = np.concatenate([[0.0], loop.displacements])
    C = np.concatenate([[0], path.cycle])
    energies = loop_energies(F, D, C)
    assert energies[0] > 0
    np.testing.assert_allclose(loop.dissipation, energies, rtol=1e-6)
