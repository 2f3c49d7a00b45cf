"""The normal solver with a smooth, gap-dependent stress law outside the contact.

A smooth law changes every outside stress at every iteration; the solver defers such changes
(interactions.base: ``outside_branch``) instead of restarting its conjugate directions.  Checked
here: the solution satisfies the discrete problem (complementarity, the law on every
non-contact node, force balance), it is the same solution as the restart-every-iteration path
(a reference computed another way) found in fewer iterations, and in the DMT limit the
adhesive force and the contact radius match the Hertz gap integrated through the law.
"""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import quad

from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.geometry.rough import gaussian_surface
from tribobem.geometry.shapes import sphere
from tribobem.grid import Grid
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers.normal import solve_normal

PAIR = ContactPair(Material(73e9, 0.17), Material.rigid())


class ShiftedVdW:
    """s(g) = -A / (6 pi (g + z)^3): smooth, attractive, finite at contact (one piece)."""

    def __init__(self, A=1e-20, z=0.3e-9):
        self.A, self.z = A, z
        self.floor = self.stress(0.0)

    def stress(self, g, xp=np):
        return -self.A / (6 * math.pi * (xp.maximum(g, 0.0) + self.z) ** 3)

    def outside_stress(self, gap, xp):
        return self.stress(gap, xp)

    def outside_branch(self, gap, xp):
        return xp.zeros(gap.shape, dtype=bool)


class DugdaleWithTail:
    """Dugdale step (-sigma0 below h0) with a smooth tail -A/(6 pi g^3) beyond: two pieces."""

    def __init__(self, dugdale, A):
        self.d, self.A = dugdale, A
        self.floor = -dugdale.sigma0

    def outside_stress(self, gap, xp):
        g = xp.maximum(gap, self.d.h0)
        return xp.where(gap < self.d.h0, -self.d.sigma0, -self.A / (6 * math.pi * g**3))

    def outside_branch(self, gap, xp):
        return gap < self.d.h0


class Hidden:
    """The same law without ``outside_branch``: every change restarts the CG (the old path)."""

    def __init__(self, inner):
        self.inner, self.floor = inner, inner.floor

    def outside_stress(self, gap, xp):
        return self.inner.outside_stress(gap, xp)


def _solve(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a ConvergenceWarning fails the test
        return solve_normal(*args, **kw)


def check_discrete_problem(op, h, res, law, force=None):
    """Complementarity, the law on non-contact nodes, force balance (tight tolerances)."""
    g = h + res.displacement - res.approach
    scale = float(h.max() - h.min())
    c = res.contact
    assert c.any() and (~c).any()
    assert np.max(np.abs(g[c])) < 1e-8 * scale                   # closed contact
    assert res.pressure[c].min() >= law.floor                       # p >= floor on contact
    assert g[~c].min() > -1e-8 * scale                              # no penetration
    s = law.outside_stress(g[~c], np)
    np.testing.assert_allclose(res.pressure[~c], s, rtol=1e-6, atol=1e-7 * np.abs(res.pressure).max())
    if force is not None:
        assert res.force == pytest.approx(force, rel=1e-9)


@pytest.fixture(scope="module")
def sphere128():
    grid = Grid.square(128, 250e-9)
    return free_boundary_operator(grid, PAIR), sphere(grid, 1e-6)


@pytest.mark.parametrize("load", [dict(force=2e-6), dict(force=-5e-9), dict(approach=1.5e-9)])
def test_smooth_law_solves_the_discrete_problem(sphere128, load):
    op, h = sphere128
    law = ShiftedVdW()
    res = _solve(op, h, interaction=law, **load)
    assert res.converged
    check_discrete_problem(op, h, res, law, load.get("force"))


def test_smooth_law_same_solution_as_restarting_in_fewer_iterations(sphere128):
    op, h = sphere128
    law = ShiftedVdW(A=5e-20, z=0.2e-9)
    for load in (dict(force=2e-6), dict(approach=1.5e-9)):
        new = _solve(op, h, interaction=law, **load)
        old = _solve(op, h, interaction=Hidden(law), **load)
        assert new.converged and old.converged
        np.testing.assert_array_equal(new.contact, old.contact)
        assert np.abs(new.pressure - old.pressure).sum() < 1e-7 * np.abs(old.pressure).sum()
        # Measured 1.4-3.9x fewer on such spheres; demand at least 1.25x.
        assert new.iterations * 1.25 < old.iterations, (new.iterations, old.iterations)


def test_piecewise_law_step_plus_tail(sphere128):
    """A Dugdale step with a smooth tail: restarts at the step, deferral on the tail."""
    op, h = sphere128
    law = DugdaleWithTail(DugdaleAdhesion(0.05, 0.3e-9), 1e-20)
    for load in (dict(force=1e-6), dict(approach=1e-9)):
        res = _solve(op, h, interaction=law, **load)
        assert res.converged
        check_discrete_problem(op, h, res, law, load.get("force"))
        ref = _solve(op, h, interaction=Hidden(law), **load)
        assert abs(res.force - ref.force) < 1e-6 * abs(ref.force)


def test_rough_periodic_smooth_law():
    grid = Grid.square(64, 2e-6, periodic=True)
    z = gaussian_surface(grid, 5e-9, 0.1e-6, seed=4)
    h = z.max() - z
    op = periodic_operator(grid, PAIR)
    law = ShiftedVdW(A=6.5e-20, z=0.3e-9)
    res = _solve(op, h, interaction=law, force=20e-6)
    check_discrete_problem(op, h, res, law, 20e-6)


def _hertz_gap(r, a, R):
    """Gap outside a Hertz contact of radius a (sphere R on a flat)."""
    return (a * a / (math.pi * R)) * ((2 - r * r / (a * a)) * np.arcsin(a / r) + np.sqrt(r * r / (a * a) - 1)) \
        + r * r / (2 * R) - a * a / R


def test_dmt_limit_of_a_weak_smooth_law():
    """Tabor parameter ~0.04: the attraction barely deforms the sphere, so the outside force is
    the law integrated over the Hertz gap, with the Hertz radius of the load F0 - F_adh (DMT).
    Discretisation error falls like dx (measured -5.7 %, -2.7 %, -1.7 % at 128^2, 256^2,
    384^2); 256^2 checked to 4 %, the contact radius to 1 % (measured 0.6 %)."""
    R, F0, L = 1e-6, 5e-6, 250e-9
    grid = Grid.square(256, L)
    op, h = free_boundary_operator(grid, PAIR), sphere(grid, R)
    law = ShiftedVdW(A=1e-20, z=0.3e-9)
    res = _solve(op, h, interaction=law, force=F0)
    X, Y = grid.meshgrid()
    inside = (np.hypot(X, Y) < L / 2) & ~res.contact
    F_adh = float(res.pressure[inside].sum()) * grid.cell_area
    Es = PAIR.effective_modulus
    Fa, a = 0.0, 0.0
    for _ in range(30):  # DMT: Hertz radius at F0 - F_adh, F_adh over the Hertz gap
        a = (3 * (F0 - Fa) * R / (4 * Es)) ** (1 / 3)
        Fa = quad(lambda r: float(law.stress(_hertz_gap(r, a, R))) * 2 * math.pi * r, a, L / 2,
                  limit=200, points=[1.01 * a, 1.1 * a])[0]
    assert Fa < -0.005 * F0  # the attraction is not negligible against the load balance
    assert F_adh == pytest.approx(Fa, rel=0.04)
    assert res.contact_radius() == pytest.approx(a, rel=0.01)
