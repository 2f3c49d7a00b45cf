"""The tangential convolution on the contact's bounding box (free boundary).

``_Tangential._apply`` evaluates K_tt q on the contact nodes with a cyclic convolution of
N >= 2m - 1 points per axis of the contact's box instead of the padded 2n grid.  It must be the
same linear operator: checked against the padded operator for random tractions (to round-off),
and a full solve must give the same stick nodes, tractions and rigid shift as with the padded
operator (to the solver tolerance), on an identical-material sphere and on a dissimilar pair with
the coupling loop.  Periodic operators never use the box (their cyclic convolution is the
operator itself).
"""

from __future__ import annotations

import contextlib
import warnings

import numpy as np
import pytest

import tribobem.solvers.tangential as T
from tribobem.elasticity.tangential import tangential_operator
from tribobem.errors import ConvergenceWarning
from tribobem.grid import Grid
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.tangential import solve_tangential
from tribobem.validation.tangential import cattaneo_problem, paper_d_problem

TOL = 1e-9


@pytest.mark.parametrize("box", [(16, 16), (24, 40), (33, 17), (48, 40)])
def test_box_convolution_equals_padded(box):
    from tribobem.elasticity.operators import free_boundary_operator
    from tribobem.materials import ContactPair, Material

    grid = Grid(48, 40, 48e-6, 40e-6, False)
    pair = ContactPair(Material(70e9, 0.3, "a"), Material(200e9, 0.25, "b"))  # dissimilar: K_xy, K_yx differ
    op = free_boundary_operator(grid, pair, ("x", "y", "z"))
    top = tangential_operator(op)
    rng = np.random.default_rng(1)
    i0, j0 = 48 - box[0], 0  # box at a corner of the grid: the largest offsets occur
    qx, qy = np.zeros(grid.shape), np.zeros(grid.shape)
    qx[i0:i0 + box[0], j0:j0 + box[1]] = rng.normal(size=box)
    qy[i0:i0 + box[0], j0:j0 + box[1]] = rng.normal(size=box)
    ux, uy = top.shear_displacement(qx, qy)
    bx, by = top.box_shear_displacement(qx[i0:i0 + box[0], j0:j0 + box[1]].copy(),
                                        qy[i0:i0 + box[0], j0:j0 + box[1]].copy())
    scale = np.abs(ux).max()
    assert np.abs(bx - ux[i0:i0 + box[0], j0:j0 + box[1]]).max() < 1e-12 * scale
    assert np.abs(by - uy[i0:i0 + box[0], j0:j0 + box[1]]).max() < 1e-12 * scale
    N, _ = top.box_spectra(box)
    assert N[0] >= 2 * box[0] - 1 and N[1] >= 2 * box[1] - 1


def test_periodic_operator_has_no_box():
    _, _, op, _, _ = cattaneo_problem(32, periodic=True)
    assert tangential_operator(op).box_spectra((8, 8)) is None


@contextlib.contextmanager
def _padded_only(monkeypatch, use_box: bool):
    """Without ``use_box``, K_tt on the padded grid (the box convolution refused, as when its
    transform is not smaller): the reference the box must reproduce."""
    with monkeypatch.context() as m:
        if not use_box:
            m.setattr(T._Tangential, "_apply_box", lambda self: None)
        yield


def _solve(monkeypatch, use_box, *args, **kw):
    with _padded_only(monkeypatch, use_box), warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_tangential(*args, **kw)


@pytest.mark.parametrize("load", [{"force": 0.5 * 0.3 * 10.0}, {"displacement": 2e-7}])
def test_box_solve_equals_padded_cattaneo(monkeypatch, load):
    grid, gap, op, pair, a = cattaneo_problem(96)
    nr = solve_normal(op, gap, force=10.0, tol=1e-12)
    res = {}
    for use_box in (False, True):
        st = _solve(monkeypatch, use_box, op, nr.pressure, nr.contact, friction_coefficient=0.3, tol=TOL, **load)
        assert st.converged, st.message
        res[use_box] = st
    full, boxed = res[False], res[True]
    assert (full.info["convolution_box"] is None and boxed.info["convolution_box"][0] <= 64
            and boxed.info["convolution_box"][1] <= 64)
    assert np.array_equal(full.stick, boxed.stick)
    qscale = 0.3 * nr.pressure.max()
    assert np.abs(full.shear - boxed.shear).max() < 50 * TOL * qscale
    assert boxed.displacement_x == pytest.approx(full.displacement_x, rel=1e-7)
    assert boxed.force_x == pytest.approx(full.force_x, rel=1e-9)
    # the slip fields come from the padded operator in both (the whole grid)
    assert np.abs(full.relative_displacement - boxed.relative_displacement).max() < 1e-6 * abs(full.displacement_x)


def test_box_coupled_equals_padded(monkeypatch):
    grid, gap, op, pair, a, P = paper_d_problem(64)
    res = {}
    for use_box in (False, True):
        with _padded_only(monkeypatch, use_box), warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            r = solve_coupled(op, gap, friction_coefficient=0.2, normal_force=P, tangential_force=(0.1 * P, 0.0),
                              tol=1e-12, tangential_tol=TOL, coupling_tol=1e-9)
        assert r.converged, r.message
        res[use_box] = r
    full, boxed = res[False], res[True]
    assert np.array_equal(full.tangential.stick, boxed.tangential.stick)
    assert np.abs(full.normal.pressure - boxed.normal.pressure).max() < 1e-7 * full.normal.pressure.max()
    assert boxed.tangential.displacement_x == pytest.approx(full.tangential.displacement_x, rel=1e-6)
