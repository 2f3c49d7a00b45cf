"""Reliability: clear errors for bad input, non-convergence is never silent."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tribobem import ContactPair, ConvergenceError, ConvergenceWarning, Grid, InputError, Material
from tribobem.analytic import maugis_dugdale_pull_off_force
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.errors import MemoryBudgetError
from tribobem.geometry.shapes import sphere
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.solvers.normal import solve_normal

SILICA = Material(73e9, 0.17, "silica")
PAIR = ContactPair(SILICA, Material.rigid())
R = 1e-3


@pytest.fixture(scope="module")
def sphere_problem():
    grid = Grid.square(32, 4e-6)
    return grid, free_boundary_operator(grid, PAIR), sphere(grid, R)


# --------------------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_heights(sphere_problem, bad):
    grid, op, h = sphere_problem
    h = h.copy()
    h[3, 4] = bad
    h[10, 11] = np.nan
    h[0, 0] = bad
    with pytest.raises(InputError) as err:
        solve_normal(op, h, force=1e-3)
    assert err.value.field == "gap"
    assert "gap" in str(err.value) and "3" in str(err.value)


def test_gap_of_wrong_shape(sphere_problem):
    grid, op, h = sphere_problem
    with pytest.raises(InputError, match="gap"):
        solve_normal(op, h[:-1], force=1e-3)


@pytest.mark.parametrize("nu", [0.5000001, 0.6, -1.0, -1.5, math.nan])
def test_poisson_ratio_out_of_range(nu):
    with pytest.raises(InputError) as err:
        Material(70e9, nu, "body1")
    assert err.value.field == "body1.nu"
    assert "(-1, 0.5]" in str(err.value)


@pytest.mark.parametrize("nu", [0.5, -0.999, 0.0])
def test_poisson_ratio_limits_accepted(nu):
    assert Material(70e9, nu).nu == nu


@pytest.mark.parametrize("E", [0.0, -1e9, math.nan])
def test_youngs_modulus_not_positive(E):
    with pytest.raises(InputError) as err:
        Material(E, 0.3, "body2")
    assert err.value.field == "body2.E"
    assert "> 0" in str(err.value)


def test_unnamed_material_still_names_the_field():
    with pytest.raises(InputError, match=r"\.nu"):
        Material(1e9, 0.7)


def test_both_bodies_rigid():
    with pytest.raises(InputError) as err:
        ContactPair(Material.rigid(), Material.rigid())
    assert "rigid" in str(err.value)


@pytest.mark.parametrize("force", [0.0, -1e-3])
def test_non_positive_force_without_adhesion(sphere_problem, force):
    grid, op, h = sphere_problem
    with pytest.raises(InputError) as err:
        solve_normal(op, h, force=force)
    assert err.value.field == "solve_normal.force"
    assert "> 0" in str(err.value)


def test_negative_force_allowed_with_adhesion(sphere_problem):
    grid, op, h = sphere_problem
    ad = DugdaleAdhesion(0.05, 0.3e-9)
    # no InputError: a small tensile force is meaningful with adhesion, and it is solved
    # (37 iterations; any ConvergenceWarning is an error here)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        res = solve_normal(op, h, force=-1e-9, interaction=ad)
    assert res.converged, res.message
    assert res.force == pytest.approx(-1e-9, rel=1e-6)
    assert res.pressure.sum() * grid.cell_area == pytest.approx(-1e-9, rel=1e-6)
    assert res.contact.any() and res.adhesive.any() and res.pressure.min() == pytest.approx(-ad.sigma0)
    # cut short, the same solve reports its non-convergence: a ConvergenceWarning naming the
    # iteration limit and a result marked unconverged; strict=True raises instead
    with pytest.warns(ConvergenceWarning, match="not converged after 5 iterations"):
        short = solve_normal(op, h, force=-1e-9, interaction=ad, max_iterations=5)
    assert short.converged is False and short.iterations == 5
    assert "not converged after 5 iterations" in short.message
    with pytest.raises(ConvergenceError, match="not converged after 5 iterations"):
        solve_normal(op, h, force=-1e-9, interaction=ad, max_iterations=5, strict=True)


def test_load_must_be_force_xor_approach(sphere_problem):
    grid, op, h = sphere_problem
    with pytest.raises(InputError, match="exactly one"):
        solve_normal(op, h)
    with pytest.raises(InputError, match="exactly one"):
        solve_normal(op, h, force=1e-3, approach=1e-9)


@pytest.mark.parametrize("kw,field", [({"tol": 0.0}, "solve_normal.tol"), ({"tol": math.nan}, "solve_normal.tol"),
                                      ({"max_iterations": 0}, "solve_normal.max_iterations")])
def test_bad_solver_settings(sphere_problem, kw, field):
    grid, op, h = sphere_problem
    with pytest.raises(InputError) as err:
        solve_normal(op, h, force=1e-3, **kw)
    assert err.value.field == field


def test_grid_too_large_for_memory():
    """Estimated before allocating: a 2e5 x 2e5 grid is never allocated here."""
    big = Grid.square(200_000, 1e-3)
    need = big.estimate_bytes()
    assert need > 1 << 40
    with pytest.raises(MemoryBudgetError) as err:
        big.check_memory(budget=64 << 30)
    msg = str(err.value)
    assert "200000 x 200000" in msg and "GiB" in msg
    # the periodic grid needs less (no zero padding) but still too much
    with pytest.raises(MemoryBudgetError):
        Grid.square(200_000, 1e-3, periodic=True).check_memory(budget=64 << 30)
    # a small grid fits a small budget
    Grid.square(64, 1e-6).check_memory(budget=1 << 30)
    # the budget is what decides
    g = Grid.square(2048, 1e-6)
    g.check_memory(budget=4 * g.estimate_bytes())
    with pytest.raises(MemoryBudgetError):
        g.check_memory(budget=g.estimate_bytes() // 2)


@pytest.mark.parametrize("n,field", [(1, "grid.nx"), (2.5, "grid.nx")])
def test_bad_grid(n, field):
    with pytest.raises(InputError) as err:
        Grid(n, 8, 1e-6, 1e-6)
    assert err.value.field == field


def test_bad_grid_length():
    with pytest.raises(InputError) as err:
        Grid(8, 8, 1e-6, -1.0)
    assert err.value.field == "grid.ly"


# --------------------------------------------------------------------------------------
# non-convergence is never silent
# --------------------------------------------------------------------------------------

def test_non_convergence_warns(sphere_problem):
    grid, op, h = sphere_problem
    with pytest.warns(ConvergenceWarning, match="not converged"):
        res = solve_normal(op, h, force=1e-3, max_iterations=3)
    assert res.converged is False
    assert len(res.residual_history) == 3
    assert res.iterations == 3
    assert "not converged" in res.message
    assert res.residual == res.residual_history[-1] > 1e-10
    assert np.all(np.isfinite(res.pressure))


def test_non_convergence_strict_raises(sphere_problem):
    grid, op, h = sphere_problem
    with pytest.raises(ConvergenceError, match="not converged"):
        solve_normal(op, h, force=1e-3, max_iterations=3, strict=True)


def test_non_convergence_periodic_displacement_control():
    grid = Grid.square(32, 1e-6, periodic=True)
    h = 1e-9 * np.cos(2 * np.pi * grid.x / grid.lx)[:, None] * np.cos(2 * np.pi * grid.y / grid.ly)[None, :]
    with pytest.warns(ConvergenceWarning):
        res = solve_normal(periodic_operator(grid, PAIR), h - h.min(), approach=0.5e-9, max_iterations=3)
    assert not res.converged and len(res.residual_history) == 3


def test_converged_solution_does_not_warn(sphere_problem):
    grid, op, h = sphere_problem
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        res = solve_normal(op, h, force=1e-3)
    assert res.converged and "converged" in res.message


def test_force_control_beyond_pull_off():
    """A tensile force beyond the pull-off force has no equilibrium under force control."""
    E_star = PAIR.effective_modulus
    Rs, z0 = 2.5e-6, 0.3e-9
    ad = DugdaleAdhesion.from_maugis(1.0, Rs, E_star, z0)
    grid = Grid.square(64, 0.2e-6)
    op = free_boundary_operator(grid, PAIR)
    F_po = maugis_dugdale_pull_off_force(Rs, ad.work_of_adhesion, E_star, z0)
    with pytest.warns(ConvergenceWarning, match="pull-off"):
        res = solve_normal(op, sphere(grid, Rs), force=2.0 * F_po, interaction=ad)
    assert res.converged is False
    assert "pull-off" in res.message
    with pytest.raises(ConvergenceError, match="pull-off"):
        solve_normal(op, sphere(grid, Rs), force=2.0 * F_po, interaction=ad, strict=True)
