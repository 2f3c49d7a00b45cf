"""Steps solved on a window of a free-boundary grid (solvers/window.py).

The window changes the cost, not the problem: a hysteresis loop on a window must give the
whole grid's states to the solvers' tolerances (same stick nodes, forces, displacements, and the
whole-grid fields outside the window from the embedding); a window too small must be detected
(a node outside it inside the adhesive range) and grown, again to the whole grid's result; and
windows must not be used where they would change the answer (periodic cells, long-range or
position-dependent stress laws).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import tribobem as tb
from tribobem.analytic.hertz import hertz
from tribobem.errors import ConvergenceWarning
from tribobem.geometry import sphere
from tribobem.solvers import window as W
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.hysteresis import hysteresis_loop

MU, F0, R = 0.2, 10e-6, 50e-6
KW = dict(tol=1e-11, tangential_tol=1e-8, coupling_tol=1e-8)


def problem(n=64, half_width=3.0):
    """Rigid ball on E = 70 GPa, nu = 0.3 (dissimilar: coupled), Dugdale 50 mJ/m^2, z0 = 0.2 nm."""
    pair = tb.ContactPair(tb.Material(70e9, 0.3, "flat"), tb.Material.rigid("ball"))
    a = float(hertz(force=F0, radius=R, E_star=pair.effective_modulus).contact_radius) * 1.4
    grid = tb.Grid.square(n, 2 * half_width * a)
    op = tb.make_operator(grid, pair, ("x", "y", "z"))
    return op, sphere(grid, radius=R), tb.DugdaleAdhesion(0.05, 0.2e-9)


def quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return fn(*a, **kw)


@pytest.fixture(scope="module")
def loops():
    op, gap, ad = problem()
    out = {w: quiet(hysteresis_loop, op, gap, normal_force=F0, friction_coefficient=MU, amplitude=0.95, cycles=1,
                    steps=8, interaction=ad, window=w, **KW) for w in (False, True)}
    return op, out[False], out[True]


def test_window_loop_equals_whole_grid(loops):
    op, full, win = loops
    assert not full.failed and not win.failed
    assert all(s.normal.info.get("window") is not None for s in win.steps)  # the window was used
    w = win.steps[-1].normal.info["window"]
    assert (w[1] - w[0]) < op.grid.nx and (w[3] - w[2]) < op.grid.ny
    d_amp = max(abs(s.tangential.displacement_x) for s in full.steps)  # branch amplitude delta*
    p_max = full.start.normal.pressure.max()
    for a, b in zip(full.steps, win.steps):
        assert a.normal.pressure.shape == b.normal.pressure.shape == op.grid.shape
        assert np.array_equal(a.tangential.stick, b.tangential.stick)
        assert np.array_equal(a.normal.contact, b.normal.contact)
        assert b.tangential.force_x == pytest.approx(a.tangential.force_x, rel=1e-12)
        assert abs(b.tangential.displacement_x - a.tangential.displacement_x) < 1e-5 * d_amp
        assert np.abs(a.normal.pressure - b.normal.pressure).max() < 1e-5 * p_max
        assert np.abs(a.tangential.shear - b.tangential.shear).max() < 1e-5 * MU * p_max
        # the whole-grid fields, outside the window too (from the embedding convolution)
        assert np.abs(a.normal.gap - b.normal.gap).max() < 1e-5 * np.abs(a.normal.gap).max()
        assert np.abs(a.tangential.relative_displacement - b.tangential.relative_displacement).max() < 1e-5 * d_amp
        assert np.abs(a.tangential.slip - b.tangential.slip).max() < 1e-5 * d_amp
        assert b.normal.mean_gap == pytest.approx(a.normal.mean_gap, rel=1e-6)
    for da, db in zip(full.dissipation, win.dissipation):
        assert np.abs(da - db).max() < 1e-4 * np.abs(da).max()


def test_too_small_window_grows_to_the_right_result():
    op, gap, ad = problem()
    start = quiet(solve_coupled, op, gap, friction_coefficient=MU, normal_force=F0, interaction=ad, **KW)
    auto = W.auto_window(start, op, ad)
    assert auto is not None
    # a window over the central part of the contact only: nodes of the cohesive zone lie outside
    c = op.grid.nx // 2
    small = W.Window(c - 6, c + 6, c - 6, c + 6)
    ref = start.tangential.relative_displacement
    load = dict(friction_coefficient=MU, normal_force=F0, interaction=ad, tangential_force=(0.3 * MU * F0, 0.0),
                reference=ref, initial=start, **KW)
    # the embedding of the small window's solution flags the nodes outside it
    wop = small.operator(op)
    res_w = quiet(solve_coupled, wop, small.slice(gap), friction_coefficient=MU, normal_force=F0, interaction=ad,
                  tangential_force=(0.3 * MU * F0, 0.0), reference=small.slice(ref),
                  initial=small.slice_result(start, op), **KW)
    _, violation = small.embed(res_w, op, gap, ref, ad)
    assert violation.any()
    res, grown = quiet(W.solve_coupled_windowed, small, op, gap, **load)
    full = quiet(solve_coupled, op, gap, **load)
    assert grown is not None and grown.shape[0] > small.shape[0] and grown.shape[1] > small.shape[1]
    assert np.array_equal(res.tangential.stick, full.tangential.stick)
    assert np.abs(res.normal.pressure - full.normal.pressure).max() < 1e-5 * full.normal.pressure.max()
    assert res.tangential.displacement_x == pytest.approx(full.tangential.displacement_x, rel=1e-5)


def test_no_window_where_it_would_change_the_answer():
    op, gap, ad = problem()
    start = quiet(solve_coupled, op, gap, friction_coefficient=MU, normal_force=F0, interaction=ad, **KW)
    assert W.auto_window(start, op, ad) is not None
    assert W.auto_window(start, op, None) is not None  # no adhesion: a window around the contact
    from tribobem.interactions.van_der_waals import VanDerWaals

    vdw = VanDerWaals.__new__(VanDerWaals)  # the type is what decides (no fields needed)
    assert W.auto_window(start, op, vdw) is None  # long range: every node carries a stress
    # periodic cell: the cyclic convolution of the whole cell is the operator
    grid = tb.Grid(64, 64, op.grid.lx, op.grid.ly, True)
    pop = tb.make_operator(grid, op.pair, ("x", "y", "z"))
    assert W.auto_window(start, pop, ad) is None
    # contact over most of the grid: no gain
    tight, tgap, _ = problem(64, half_width=1.6)
    st2 = quiet(solve_coupled, tight, tgap, friction_coefficient=MU, normal_force=F0, interaction=ad, **KW)
    assert W.auto_window(st2, tight, ad) is None


def test_window_operator_is_the_same_operator():
    """The window's free-boundary operator is the whole grid's restricted to the window."""
    op, gap, ad = problem(48)
    win = W.Window(10, 30, 5, 37)
    wop = win.operator(op)
    rng = np.random.default_rng(0)
    t = np.zeros((3,) + op.grid.shape)
    t[:, 10:30, 5:37] = rng.normal(size=(3, 20, 32))
    u = op.apply(t)
    uw = wop.apply(np.ascontiguousarray(t[:, 10:30, 5:37]))
    assert np.abs(uw - u[:, 10:30, 5:37]).max() < 1e-12 * np.abs(u).max()
