"""Regression tests: warm-started adhesive solves along a load path (force control).

Two bugs seen during development, both giving a *false* or *stalled* convergence:
(1) after a warm start at a new load the contact gap is at round-off level, tau = g.t/r.t
becomes a ratio of round-off and the following conjugate direction is parallel to the
pressure, which the force balance undoes (the state froze); (2) a force-balance rescale
without a CG step left the displacement stale, so open gaps looked closed.  Every solve
here must converge *and* close its contact gap.
"""

import warnings

import numpy as np
import pytest

import tribobem as tb
from tribobem.geometry import sphere

PAIR = tb.ContactPair(tb.Material(130e9, 0.3), tb.Material.rigid())
R = 100e-6


def closed_gap(op, h, res):
    """Largest |g| on the contact nodes, recomputed from the returned pressure (m)."""
    g = h + op.apply(res.pressure) - res.approach
    return float(np.abs(g[res.contact]).max())


@pytest.mark.parametrize("tol", [1e-8, 1e-9, 1e-11])
def test_force_steps_with_warm_start_converge_and_match_cold(tol):
    grid = tb.Grid.square(64, 2.5e-6)
    adh = tb.DugdaleAdhesion.from_tabor(1.0, R, PAIR.effective_modulus, 0.25e-9)
    h = sphere(grid, R)
    op = tb.make_operator(grid, PAIR)
    prev = None
    for force in (10e-6, 9.18e-6, 8.37e-6, 5e-6):
        warm = tb.solve_normal(op, h, force=force, interaction=adh, tol=tol, initial_pressure=prev)
        cold = tb.solve_normal(op, h, force=force, interaction=adh, tol=tol)
        assert warm.converged, warm.message
        assert closed_gap(op, h, warm) < 1e-6 * adh.h0
        assert warm.force == pytest.approx(force, rel=1e-8)
        assert warm.contact_area == pytest.approx(cold.contact_area, rel=1e-9)
        assert warm.approach == pytest.approx(cold.approach, rel=1e-6)
        prev = warm


def test_tensile_force_path_closes_the_contact_gap():
    """Unloading a Maugis-Dugdale sphere into tension, each step warm-started."""
    grid = tb.Grid.square(96, 0.2e-6)
    Rs = 2.5e-6
    adh = tb.DugdaleAdhesion.from_maugis(1.0, Rs, PAIR.effective_modulus, 0.3e-9)
    h = sphere(grid, Rs)
    op = tb.make_operator(grid, PAIR)
    scale = np.pi * Rs * adh.work_of_adhesion
    prev = tb.solve_normal(op, h, force=scale, interaction=adh)
    for fm in (0.0, -0.5, -1.0, -1.3):
        with warnings.catch_warnings():
            warnings.simplefilter("error", tb.ConvergenceWarning)
            res = tb.solve_normal(op, h, force=fm * scale, interaction=adh, initial_pressure=prev)
        assert closed_gap(op, h, res) < 1e-6 * adh.h0
        assert res.force == pytest.approx(fm * scale, abs=1e-8 * scale)
        prev = res
