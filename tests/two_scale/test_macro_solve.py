"""The macro solve with an interface law against closed forms.

* A stiff interface (its mean gap changes by 1e-5 of the approach over the pressures that
  occur) is the smooth contact: a sphere gives Hertz's approach and contact radius.
* A linear interface law g = g0 - p/k is a uniform compliant (Winkler) layer; on a periodic
  sinusoidal macro gap in full contact the exact solution is one harmonic,
  P1 = A / (2/(E* q) + 1/k), and delta = A - g0 + P0/k.
* The solver's solution satisfies its discrete equations (law on the loaded cells, the
  inequality on the others, force balance).
"""

import math

import numpy as np
import pytest

from tribobem.analytic import hertz
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.geometry.shapes import burl
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.two_scale.laws import NormalInterfaceLaw
from tribobem.two_scale.macro import solve_interface_normal

PAIR = ContactPair(Material(100e9, 0.3), Material.rigid())
E_STAR = 100e9 / (1 - 0.09)


def tabulated(gap_of_p, p_lo, p_hi, n=64, touch=None):
    ps = np.geomspace(p_lo, p_hi, n)
    gs = gap_of_p(ps)
    g0 = float(gap_of_p(np.array([0.0]))[0]) if touch is None else touch
    return NormalInterfaceLaw(ps, gs, g0, np.full(n, 0.1), ps * 10, np.zeros(n), np.zeros(n))


def centred(grid):
    x = (np.arange(grid.nx) + 0.5) * grid.dx - grid.lx / 2
    y = (np.arange(grid.ny) + 0.5) * grid.dy - grid.ly / 2
    return np.meshgrid(x, y, indexing="ij")


@pytest.mark.parametrize("n", [64, 128])
def test_a_stiff_interface_is_hertz(n):
    grid = Grid(n, n, 4e-6, 4e-6)
    X, Y = centred(grid)
    R, F = 10e-6, 1e-3
    h = (X**2 + Y**2) / (2 * R)
    # mean gap 1 nm, falling by 1e-14 m per e-fold of pressure (1e-5 of Hertz's 17 nm approach)
    law = tabulated(lambda p: 1e-9 - 1e-14 * np.log(np.maximum(p, 1e3) / 1e3), 1e3, 1e11, touch=1e-9 + 1e-14)
    res = solve_interface_normal(free_boundary_operator(grid, PAIR), h, law, F, tol=1e-9)
    hz = hertz(force=F, radius=R, E_star=E_STAR)
    assert res.converged
    assert res.force == pytest.approx(F, rel=1e-12)
    # the approach of the mean planes less the layer's (1 nm) is Hertz's; the grid's own error at
    # 36-72 cells across the contact is below 0.2 %
    assert res.approach + 1e-9 == pytest.approx(hz.approach, rel=2e-3)
    assert math.sqrt(res.nominal_area / math.pi) == pytest.approx(hz.contact_radius, rel=0.03)


@pytest.mark.parametrize("k_layer", [1e16, 1e17, 1e18])
def test_a_linear_law_is_a_winkler_layer_closed_form(k_layer):
    n, lam = 64, 10e-6
    grid = Grid(n, n, lam, lam, periodic=True)
    X, _ = centred(grid)
    q = 2 * math.pi / lam
    A = 2e-9
    h = A * (1 - np.cos(q * (X + lam / 2)))
    P0 = 2e8
    P1 = A / (2 / (E_STAR * q) + 1 / k_layer)
    assert P1 < 0.8 * P0  # full contact: the closed form holds
    g0 = 20e-9
    law = tabulated(lambda p: g0 - p / k_layer, 1e6, 1e9, n=256)
    res = solve_interface_normal(periodic_operator(grid, PAIR), h, law, P0 * lam * lam, tol=1e-10)
    assert res.converged
    expected = P0 + P1 * np.cos(q * (X + lam / 2))
    # the discrete operator's harmonic (2/(E* q) sampled on 64 cells) is the continuous one; the
    # PCHIP table of a linear law in ln p is linear to ~1e-5 of g0 over 256 points
    assert np.max(np.abs(res.pressure - expected)) / P1 < 2e-3
    assert res.approach == pytest.approx(A - g0 + P0 / k_layer, abs=1e-3 * A)


def test_the_solution_satisfies_its_discrete_problem():
    grid = Grid(96, 96, 10e-6, 10e-6)
    h = burl(grid, 2e-6, 10e-6)
    # a rough-contact-like law: g = u0 ln(p_ref / p) + Hertz tail below the table
    law = tabulated(lambda p: 2e-9 * np.log(1e10 / np.maximum(p, 1.0)), 1e5, 1e10, n=32,
                    touch=2e-9 * np.log(1e10 / 1e5) + 1e-9)
    op = free_boundary_operator(grid, PAIR)
    F = 2e-4
    res = solve_interface_normal(op, h, law, F, tol=1e-9)
    assert res.converged
    loaded = res.pressure > 0
    sep = h + op.apply(res.pressure) - res.approach
    scale = law.touch_gap + np.abs(op.apply(res.pressure)).max()
    assert np.max(np.abs(sep[loaded] - law.gap(res.pressure[loaded]))) <= 1e-8 * scale
    assert np.all(sep[~loaded] >= law.touch_gap - 1e-8 * scale)
    assert res.pressure.sum() * grid.dx * grid.dy == pytest.approx(F, rel=1e-12)
    # the interface spreads the load: nominal pressure below the smooth burl's, larger area
    assert loaded.sum() * grid.dx * grid.dy > math.pi * (2e-6) ** 2


def test_bad_input_names_the_argument():
    grid = Grid(32, 32, 1e-6, 1e-6)
    law = tabulated(lambda p: 1e-9 - 1e-12 * np.log(np.maximum(p, 1.0)), 1e3, 1e9)
    op = free_boundary_operator(grid, PAIR)
    from tribobem.errors import InputError
    with pytest.raises(InputError, match="force"):
        solve_interface_normal(op, np.zeros(grid.shape), law, -1.0)
    with pytest.raises(InputError, match="gap"):
        solve_interface_normal(op, np.zeros((3, 3)), law, 1e-6)
