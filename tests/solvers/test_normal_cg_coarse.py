"""NormCG's coarse-grid start (``solve_normal_cg(coarse_levels=...)``, issue 20 item 3).

A small rough burl (free boundary, a crowned flat top with a 2 nm rms self-affine wafer, the
problem of benchmarks/burl_whole.py at 128^2 and 256^2) and a rough periodic cell: the solve
started from the pressure of the same problem on 2x / 4x coarser grids must converge to the
cold start's solution -- the same contact nodes, pressures within the tolerance's accuracy,
the same force and approach.  Also: displacement control, the automatic choice, the info
entries, and bad input.  The operators' ``out=`` and the backend's shared buffers must leave
``op.apply`` bitwise unchanged.
"""

from __future__ import annotations

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.errors import InputError
from tribobem.geometry.rough import self_affine_surface
from tribobem.geometry.shapes import burl
from tribobem.interactions import DugdaleAdhesion
from tribobem.solvers.normal_cg import solve_normal_cg

PAIR = ContactPair(Material(130e9, 0.28, "Si"), Material.rigid())


def _burl_problem(n):
    # the whole-burl benchmark scaled down: 30 um top on an 82 um window, 2 nm rms
    grid = Grid(n, n, 82e-6, 82e-6, False)
    h = burl(grid, 30e-6, 500e-6, 0.5) - self_affine_surface(grid, 0.8, rms_height=2e-9,
                                                             rolloff_wavelength=10e-6, seed=1)
    return free_boundary_operator(grid, PAIR), h - h.min()


def _same(cold, warm, tol_p=1e-8):
    assert cold.converged and warm.converged
    assert np.array_equal(cold.contact, warm.contact)
    pmax = np.abs(cold.pressure).max()
    assert np.abs(cold.pressure - warm.pressure).max() <= tol_p * pmax
    assert warm.force == pytest.approx(cold.force, rel=1e-10)
    assert warm.approach == pytest.approx(cold.approach, rel=1e-8)


@pytest.mark.parametrize("n,levels", [(128, 1), (256, 1), (256, 2)])
@pytest.mark.parametrize("prolong", ["constant", "linear"])
def test_coarse_start_burl_force_control(n, levels, prolong):
    op, h = _burl_problem(n)
    cold = solve_normal_cg(op, h, force=0.025, tol=1e-10, coarse_levels=0)
    warm = solve_normal_cg(op, h, force=0.025, tol=1e-10, coarse_levels=levels, coarse_prolong=prolong)
    assert cold.info["coarse"] is None
    c = warm.info["coarse"]
    assert c["levels"] == levels and len(c["iterations"]) == levels
    assert c["grid"] == [n // 2, n // 2]
    assert int(cold.contact.sum()) > 20
    _same(cold, warm)


def test_coarse_start_displacement_control_and_restriction():
    op, h = _burl_problem(256)
    cold = solve_normal_cg(op, h, approach=6e-9, tol=1e-10, coarse_levels=0)
    for restrict in ("mean", "min"):
        warm = solve_normal_cg(op, h, approach=6e-9, tol=1e-10, coarse_levels=2, coarse_restrict=restrict)
        _same(cold, warm)


def test_coarse_start_periodic():
    n = 256
    grid = Grid(n, n, 1.0, 1.0, True)
    E = Material(1.0, 0.3)
    pair = ContactPair(E, Material.rigid())
    s = self_affine_surface(grid, 0.8, rms_slope=1.0, seed=3)
    h = s.max() - s
    op = periodic_operator(grid, pair)
    F = 0.01 * pair.effective_modulus
    cold = solve_normal_cg(op, h, force=F, tol=1e-10, coarse_levels=0)
    warm = solve_normal_cg(op, h, force=F, tol=1e-10, coarse_levels=2)
    _same(cold, warm)


def test_coarse_start_automatic_choice():
    op, h = _burl_problem(128)
    # small grids: no coarse level
    assert solve_normal_cg(op, h, force=0.025, tol=1e-8).info["coarse"] is None
    grid = Grid(512, 512, 82e-6, 82e-6, False)
    op512 = free_boundary_operator(grid, PAIR)
    h512 = burl(grid, 30e-6, 500e-6, 0.5) - self_affine_surface(grid, 0.8, rms_height=2e-9,
                                                               rolloff_wavelength=10e-6, seed=1)
    h512 -= h512.min()
    # (the whole grid's nested start: the candidate-set solve, automatic from 512^2, solves the box)
    res = solve_normal_cg(op512, h512, force=0.025, tol=1e-8, candidates=False)
    assert res.info["coarse"]["levels"] == 1
    assert solve_normal_cg(op512, h512, force=0.025, tol=1e-8).info["candidates"]["rounds"] == 1
    # a warm start or adhesion switch it off
    assert solve_normal_cg(op512, h512, force=0.025, tol=1e-8, initial_pressure=res).info["coarse"] is None
    dug = DugdaleAdhesion(0.1, 1e-9)
    assert solve_normal_cg(op, h, force=0.025, tol=1e-6, interaction=dug).info["coarse"] is None


def test_coarse_start_bad_input():
    op, h = _burl_problem(128)
    for bad in (-1, 1.5, "2", True):
        with pytest.raises(InputError, match="coarse_levels"):
            solve_normal_cg(op, h, force=0.025, coarse_levels=bad)
    with pytest.raises(InputError, match="coarse_levels"):
        solve_normal_cg(op, h, force=0.025, coarse_levels=6)  # 128 / 64 = 2 nodes
    with pytest.raises(InputError, match="coarse_levels"):
        solve_normal_cg(op, h, force=0.025, coarse_levels=1, initial_pressure=np.ones(h.shape))
    grid = Grid(100, 102, 1e-6, 1e-6, False)
    with pytest.raises(InputError, match="coarse_levels"):
        solve_normal_cg(free_boundary_operator(grid, PAIR), np.zeros(grid.shape), force=1e-3, coarse_levels=2)


@pytest.mark.parametrize("periodic", [False, True])
def test_apply_out_and_shared_buffers_bitwise(periodic):
    grid = Grid(96, 64, 1e-6, 1e-6, periodic)
    op = (periodic_operator if periodic else free_boundary_operator)(grid, PAIR)
    rng = np.random.default_rng(0)
    a, b = rng.random(grid.shape), rng.random(grid.shape)
    ua = op.apply(a).copy()
    out = np.empty(grid.shape)
    # interleave with another operator on the same backend (the preconditioner shares buffers)
    from tribobem.solvers.normal_cg import fft_preconditioner

    pre = fft_preconditioner(op)
    zb = pre.apply(b).copy()
    assert np.array_equal(op.apply(a, out=out), ua) and np.array_equal(out, ua)
    assert np.array_equal(pre.apply(b), zb)
    assert np.array_equal(op.apply(a), ua)
    assert np.array_equal(pre.apply(b, out=out), zb)
