"""Polonsky-Keer with a preconditioned tail (``solve_normal(precondition=True)``, the default).

Once the contact set and the outside stresses stop changing, the CG is preconditioned with the
half-space's stiffness on the contact's box.  The steps that change the sets are the plain
iteration's, so where the equilibrium is unique the two must reach the same one: the same
contact and cohesive nodes, and forces and approaches within the solver tolerance.  The
references are the analytic Hertz and Maugis-Dugdale solutions and the plain iteration.
"""

from __future__ import annotations

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.analytic import hertz
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.geometry.rough import self_affine_surface
from tribobem.geometry.shapes import sphere
from tribobem.solvers.normal import solve_normal

PAIR = ContactPair(Material(73e9, 0.17, "silica"), Material.rigid())


def _both(op, h, **kw):
    pre = solve_normal(op, h, tol=1e-10, method="polonsky_keer", **kw)
    plain = solve_normal(op, h, tol=1e-10, precondition=False, method="polonsky_keer", **kw)
    assert pre.converged and plain.converged, (pre.message, plain.message)
    return pre, plain


def _same_equilibrium(pre, plain, force_scale, approach_scale):
    assert np.array_equal(pre.contact, plain.contact)
    assert np.array_equal(pre.adhesive, plain.adhesive)
    # the solver tolerance (1e-10 relative pressure change) with a margin of 100
    assert abs(pre.force - plain.force) < 1e-8 * force_scale
    assert abs(pre.approach - plain.approach) < 1e-8 * approach_scale
    assert np.abs(pre.pressure - plain.pressure).sum() < 1e-8 * np.abs(plain.pressure).sum()


@pytest.mark.parametrize("n", [64, 128])
def test_hertz_same_contact_fewer_iterations(n):
    """Free-boundary Hertz, force control: the contact of the plain iteration, within 2 % of
    Hertz (64-128 cells across the contact), in fewer iterations."""
    a, R = 1e-6, 1e-3
    E = PAIR.effective_modulus
    F = 4 * E * a**3 / (3 * R)
    grid = Grid.square(n, 4 * a)
    op = free_boundary_operator(grid, PAIR)
    h = sphere(grid, R)
    pre, plain = _both(op, h, force=F)
    ref = hertz(force=F, radius=R, E_star=E)
    _same_equilibrium(pre, plain, F, ref.approach)
    assert pre.approach == pytest.approx(ref.approach, rel=0.02)
    assert pre.iterations < plain.iterations
    assert pre.info["counters"]["preconditioned"] > 0


@pytest.mark.parametrize("control", ["force", "approach"])
def test_maugis_dugdale_same_cohesive_zone(control):
    """Maugis-Dugdale sphere (lambda = 1, 160^2): the same contact and cohesive nodes as the
    plain iteration, the contact and cohesive radii within 3 % of Maugis's, and at most two
    thirds of the plain iteration's count (measured about half)."""
    from tribobem.validation import maugis_dugdale_problem

    prob = maugis_dugdale_problem(1.0)
    if control == "force":
        load = {"force": prob.F_scale}
        ref = prob.reference(force=prob.F_scale)
    else:
        d = prob.approach_points()[0]
        load = {"approach": d}
        ref = prob.reference(approach=d)
    pre, plain = _both(prob.operator, prob.gap, interaction=prob.adhesion, **load)
    _same_equilibrium(pre, plain, prob.F_scale, prob.d_scale)
    cell = prob.grid.cell_area
    a = np.sqrt(np.count_nonzero(pre.contact) * cell / np.pi)
    c = np.sqrt(np.count_nonzero(pre.contact | pre.adhesive) * cell / np.pi)
    assert a == pytest.approx(ref.contact_radius, rel=0.03)
    assert c == pytest.approx(ref.cohesive_radius, rel=0.03)
    assert pre.iterations <= 2 * plain.iterations // 3


@pytest.mark.parametrize("factor", [0.7, 0.9])
def test_warm_started_adhesive_step_keeps_the_plain_branch(factor):
    """A warm-started adhesive step (the solve of a load path): from the same start, the same
    contact and cohesive nodes as the plain iteration.  (Preconditioning after one settled
    iteration instead of two put 8-16 contact and 16-24 cohesive nodes of these two steps on
    another, equally valid equilibrium; hence ``PRECONDITION_AFTER = 2``.)"""
    from tribobem.validation import maugis_dugdale_problem

    prob = maugis_dugdale_problem(1.0)
    first = solve_normal(prob.operator, prob.gap, force=prob.F_scale, interaction=prob.adhesion, tol=1e-10)
    pre, plain = _both(prob.operator, prob.gap, force=factor * prob.F_scale, interaction=prob.adhesion,
                       initial_pressure=first)
    _same_equilibrium(pre, plain, prob.F_scale, prob.d_scale)


def test_rough_adhesive_ball_same_branch():
    """A rough adhesive ball on the free-boundary grid (R = 20 um plus a self-affine roughness,
    H = 0.8, rms slope 0.1; Dugdale sigma0 = 0.002 E*, z0 = 0.5 nm; multistable at its many
    contact and cohesive edges): cold and warm-started (0.6 F from F), the same contact and
    cohesive nodes as the plain iteration, in fewer iterations (measured 31 against 37 cold,
    23 against 31 warm)."""
    from tribobem.interactions import DugdaleAdhesion

    grid = Grid.square(128, 2e-6)
    op = free_boundary_operator(grid, PAIR)
    rough = self_affine_surface(Grid.square(128, 2e-6, periodic=True), 0.8, rms_slope=0.1,
                                short_cutoff=4 * grid.dx, long_cutoff=grid.lx / 4, seed=3)
    h = sphere(grid, 20e-6) + rough
    h -= h.min()
    E = PAIR.effective_modulus
    F = 0.5 * E * (0.4e-6) ** 3 / 20e-6
    ad = DugdaleAdhesion(work_of_adhesion=0.002 * E * 0.5e-9, z0=0.5e-9)
    pre, plain = _both(op, h, force=F, interaction=ad)
    assert np.count_nonzero(plain.adhesive) > 50 and np.count_nonzero(plain.contact) > 100
    _same_equilibrium(pre, plain, F, abs(plain.approach))
    pre2, plain2 = _both(op, h, force=0.6 * F, interaction=ad, initial_pressure=plain)
    _same_equilibrium(pre2, plain2, F, abs(plain2.approach))
    assert pre.iterations < plain.iterations and pre2.iterations < plain2.iterations


def test_spread_periodic_contact_is_not_preconditioned():
    """The islands of a rough periodic contact spread over the cell: the preconditioner's box
    would be the whole cell, as costly as the operator, so the plain iteration runs (the same
    iterates)."""
    grid = Grid.square(128, 1e-6, periodic=True)
    s = self_affine_surface(grid, 0.8, rms_slope=1.0, short_cutoff=4 * grid.dx, long_cutoff=grid.lx / 4, seed=3)
    op = periodic_operator(grid, PAIR)
    F = 0.01 * PAIR.effective_modulus * grid.lx * grid.ly
    pre, plain = _both(op, s.max() - s, force=F)
    assert pre.info["counters"]["preconditioned"] == 0
    assert pre.iterations == plain.iterations
    assert np.array_equal(pre.pressure, plain.pressure)


def test_periodic_axis_spanned_by_the_contact_is_taken_whole():
    """A ridge along x on a periodic cell (contact across the whole x axis, a strip in y): the
    preconditioner's box takes the x axis whole, where its periodic M is exact, so the 64
    columns stay identical."""
    grid = Grid(64, 256, 0.5e-6, 2e-6, periodic=True)
    op = periodic_operator(grid, PAIR)
    y = (np.arange(256) + 0.5) * grid.dy
    h = np.repeat((1e-8 * (1 + np.cos(2 * np.pi * y / 2e-6)))[None, :], 64, axis=0)  # contact mid-cell
    F = 0.05 * np.pi * PAIR.effective_modulus * 1e-8 / 2e-6 * grid.lx * grid.ly
    pre, plain = _both(op, h, force=F)
    assert pre.info["counters"]["preconditioned"] > 0
    assert np.allclose(pre.pressure, pre.pressure[:1, :], rtol=0, atol=1e-9 * pre.pressure.max())
    _same_equilibrium(pre, plain, F, 1e-8)
