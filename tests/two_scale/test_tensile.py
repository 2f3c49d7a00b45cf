"""The tensile interface law and the macro solve at a prescribed approach (two_scale.tensile)."""

import math

import numpy as np
import pytest

from tribobem.elasticity.operators import free_boundary_operator, periodic_operator
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.two_scale.tensile import TensileInterfaceLaw, solve_interface_at_approach

PAIR = ContactPair(Material(100e9, 0.3), Material.rigid())


def _law(pressure_of, s=None, preloads=(0.0, 1e8)):
    """A law whose branches are ``pressure_of(s, j)`` on a fine ladder (Pa, m)."""
    s = np.linspace(-5e-9, 20e-9, 2001) if s is None else s
    P = np.array([pressure_of(s, j) for j in range(len(preloads))])
    cols = {k: np.zeros_like(P) for k in ("contact_fractions", "repulsive_pressures", "capillary_pressures",
                                           "wetted_fractions")}
    return TensileInterfaceLaw(separations=s, preloads=np.array(preloads, float), pressure=P, columns=cols,
                               step=float(s[1] - s[0]))


def test_law_interpolates_between_branches_in_pmax():
    law = _law(lambda s, j: -(1.0 + j) * 1e6 * np.ones_like(s), preloads=(0.0, 1e8, 3e8))
    p, d = law.evaluate(np.full(4, 1e-9), np.array([0.0, 0.5e8, 2e8, 9e8]))
    # p_max 0: loading branch; halfway between 0 and 1e8; halfway between 1e8 and 3e8; above: last
    assert np.allclose(p, [-1e6, -1.5e6, -2.5e6, -3e6], rtol=1e-12)
    assert np.allclose(d, 0.0, atol=1e-3)
    assert law.strength == pytest.approx(3e6)
    # above the ladder nothing acts
    assert law.evaluate(np.array([25e-9]), np.array([0.0]))[0][0] == 0.0


def test_linear_layer_in_tension_matches_closed_form():
    """A uniform linear layer P = k (g0 - s) (no sign constraint) under a wavy rigid surface on a
    periodic half-space: the harmonic P1 = A / (2/(E* q) + 1/k) and the mean k (g0 + delta) hold in
    tension as in compression."""
    n, lam, A, g0, k = 64, 10e-6, 2e-9, 3e-9, 1e17
    grid = Grid(n, n, lam, lam, periodic=True)
    x = (np.arange(n) + 0.5) * grid.dx
    X = np.broadcast_to(x[:, None], grid.shape)
    q = 2 * math.pi / lam
    h = A * (1 - np.cos(q * X))
    law = _law(lambda s, j: k * (g0 - s), s=np.linspace(-20e-9, 40e-9, 6001))
    E = PAIR.effective_modulus
    for delta in (-6e-9, 1e-9):  # mean tension, mean compression
        st = solve_interface_at_approach(periodic_operator(grid, PAIR), h, law, delta, None, tol=1e-11)
        assert st.converged
        P1 = A / (2 / (E * q) + 1 / k)
        assert float(2 * np.mean(st.pressure * np.cos(q * X))) == pytest.approx(P1, rel=2e-3)
        assert float(np.mean(st.pressure)) == pytest.approx(k * (g0 - A + delta), rel=1e-6)


def _dense_newton(G, h, law, delta, iterations=40):
    """The root of p = P(h + G p - delta) by Newton's method with the dense Jacobian I - D G."""
    p = np.zeros_like(h)
    for _ in range(iterations):
        P, D = law.evaluate(h + G @ p - delta, np.zeros_like(h))
        r = p - P
        if np.max(np.abs(r)) <= 1e-9 * law.strength:
            return p
        p = p + np.linalg.solve(np.eye(h.size) - D[:, None] * G, -r)
    raise AssertionError("the dense reference did not converge")


def test_softening_law_on_a_free_grid_matches_a_dense_solve():
    """A cohesive law with a tensile peak and a softening tail, on a small free-boundary grid
    under a crowned gap: the Newton-GMRES state (active set, line search) equals a plain dense Newton
    root of p = P(h + G p - delta) with the influence matrix, at approaches before, at and past the peak."""
    n = 12
    grid = Grid(n, n, 12e-6, 12e-6)
    op = free_boundary_operator(grid, PAIR)
    x = (np.arange(n) + 0.5) * grid.dx - 6e-6
    h = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * 2e-3)
    sig, rho = 2e7, 2e-9

    def P(s, j=0):  # compressive stiff wall below 0, exponential cohesion above
        return np.where(s < 0, -1e17 * s, -sig * (s / rho) * np.exp(1 - s / rho))

    law = _law(P, s=np.linspace(-3e-9, 30e-9, 33001))
    G = np.array([op.apply(e.reshape(grid.shape)).ravel() for e in np.eye(n * n)]).T
    prev = None
    for delta in (1e-9, -1e-9, -2.5e-9, -4e-9):
        st = solve_interface_at_approach(op, h, law, delta, None, initial=prev, tol=1e-10)
        assert st.converged and st.unstable_cells == 0
        ref = _dense_newton(G, h.ravel(), law, delta)
        assert np.max(np.abs(st.pressure.ravel() - ref)) <= 1e-6 * sig
        prev = st.pressure


def test_a_flat_periodic_interface_pulls_off_at_its_strength():
    """A flat interface on a periodic grid carries a uniform pressure p = P(-delta) (no q = 0
    displacement): the pull-off force is the law's strength times the area, reached from the
    preload with adaptive steps and the refinement about the minimum."""
    from tribobem.two_scale.tensile import interface_pull_off

    n, L = 16, 4e-6
    grid = Grid(n, n, L, L, periodic=True)
    sig, rho = 3e6, 1.5e-9

    def P(s, j=0):  # a stiff wall below 0, exponential cohesion above (minimum -sig at s = rho)
        return np.where(s < 0, -1e17 * s, -sig * (s / rho) * np.exp(1 - s / rho))

    law = _law(P, s=np.linspace(-3e-9, 40e-9, 43001))
    law.step = rho / 16
    po = interface_pull_off(periodic_operator(grid, PAIR), np.zeros(grid.shape), law, 1e6 * L * L, 0.0,
                            n_steps=20, refine=4)
    assert po.converged
    assert po.preload_state.force == pytest.approx(1e6 * L * L, rel=1e-6)  # 1 MPa
    assert po.force == pytest.approx(-sig * L * L, rel=1e-4)
    # the separation at pull-off is the law's own (delta = -rho), to a fraction of a step
    assert po.approach == pytest.approx(-rho, abs=0.2 * law.step)
