"""TangCG with the FFT-based preconditioner (``solve_tangential(preconditioner="fft")``).

The preconditioner changes the path of the iteration, not the problem: the results must agree
with the diagonally preconditioned TangCG to the solver tolerance -- the same stick nodes, the
same tractions and rigid shift -- on Cattaneo-Mindlin (free boundary and periodic, force and
displacement control, total and incremental modes) and on a dissimilar pair (coupling term
K_tz p, and the full coupling loop).  Also checked: M is the inverse of the operator's symbol
where the box is the whole periodic cell, M is symmetric positive definite, and the
preconditioned solver needs fewer iterations.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import tribobem.solvers.tangential as T
from tribobem.elasticity.tangential import tangential_operator
from tribobem.errors import ConvergenceWarning, InputError
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.tangential import solve_tangential
from tribobem.validation.tangential import cattaneo_problem, paper_d_problem

P, MU = 10.0, 0.3
TOL = 1e-9
MU_D = 0.2


def quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return fn(*a, **kw)


@pytest.fixture(scope="module", params=[(96, False), (64, True)], ids=["free96", "periodic64"])
def cm(request):
    n, periodic = request.param
    grid, gap, op, pair, a = cattaneo_problem(n, periodic=periodic)
    nr = solve_normal(op, gap, force=P, tol=1e-12)
    assert nr.converged
    return op, nr


def _pair(op, nr, **kw):
    kw.setdefault("tol", TOL)
    out = {}
    for pc in ("diagonal", "fft"):
        out[pc] = solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=MU, preconditioner=pc, **kw)
        assert out[pc].converged, out[pc].message
        assert out[pc].info["preconditioner"] == pc
    return out["diagonal"], out["fft"]


def _agree(d, f, qscale, tol=TOL):
    assert np.array_equal(d.stick, f.stick)
    # tractions: both within ~tol of the solution (relative change and slip residual < tol)
    assert np.abs(d.shear - f.shear).max() < 50 * tol * qscale
    assert f.displacement_x == pytest.approx(d.displacement_x, rel=1e-7, abs=1e-7 * abs(d.displacement_x) + 1e-30)
    assert f.force_x == pytest.approx(d.force_x, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("ratio", [0.3, 0.8])
def test_cattaneo_force_control_same_solution(cm, ratio):
    op, nr = cm
    d, f = _pair(op, nr, force=(ratio * MU * P, 0.0))
    _agree(d, f, MU * nr.pressure.max())
    assert f.info["tangcg_iterations"] == f.iterations  # no fallback to the projected gradient
    assert f.info["preconditioner_convolutions"] > 0
    assert d.info["preconditioner_convolutions"] == 0


def test_cattaneo_fewer_iterations(cm):
    op, nr = cm
    d, f = _pair(op, nr, force=(0.3 * MU * P, 0.0))
    assert f.iterations < d.iterations


def test_cattaneo_oblique_displacement_control(cm):
    op, nr = cm
    ref = solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=MU, force=(0.4 * MU * P, 0.2 * MU * P),
                           tol=TOL)
    d, f = _pair(op, nr, displacement=(ref.displacement_x, ref.displacement_y))
    _agree(d, f, MU * nr.pressure.max())
    assert f.force_y == pytest.approx(d.force_y, rel=1e-7)


def test_cattaneo_incremental_unloading(cm):
    """Unloading from 0.8 to 0.4 mu P in the incremental mode (history-dependent, reversed slip)."""
    op, nr = cm
    up = solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=MU, force=(0.8 * MU * P, 0.0), tol=TOL)
    d, f = _pair(op, nr, force=(0.4 * MU * P, 0.0), reference=up.relative_displacement,
                 initial_shear=up.shear, initial_stick=up.stick)
    _agree(d, f, MU * nr.pressure.max())


@pytest.mark.parametrize("swap", [False, True])
def test_dissimilar_pair_with_coupling_term(swap):
    """Paper D (rigid ball on an elastic flat): the slip carries K_tz p."""
    grid, gap, op, pair, a, F0 = paper_d_problem(64, swap)
    assert tangential_operator(op).coupled
    nr = solve_normal(op, gap, force=F0, tol=1e-12)
    d, f = _pair(op, nr, force=(0.5 * MU_D * nr.repulsive_force, 0.0))
    assert 0 < f.stick.sum() < f.contact.sum()
    _agree(d, f, MU_D * nr.pressure.max())


def test_coupling_loop_same_result(monkeypatch):
    """solve_coupled with either preconditioner as the default: the same coupled state."""
    grid, gap, op, pair, a, F0 = paper_d_problem(48)
    out = {}
    for pc in ("diagonal", "fft"):
        monkeypatch.setattr(T, "DEFAULT_PRECONDITIONER", pc)
        z = solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0, tangential_tol=1e-9, coupling_tol=1e-9)
        zx = solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0, tangential_tol=1e-9, coupling_tol=1e-9,
                           tangential_force=(0.6 * MU_D * z.normal.repulsive_force, 0.0), initial=z)
        assert zx.converged and zx.tangential.info["preconditioner"] == pc
        out[pc] = zx
    d, f = out["diagonal"], out["fft"]
    assert np.array_equal(d.tangential.stick, f.tangential.stick)
    assert np.array_equal(d.normal.contact, f.normal.contact)
    pmax = float(d.normal.pressure.max())
    assert np.abs(d.normal.pressure - f.normal.pressure).max() < 1e-6 * pmax
    assert np.abs(d.tangential.shear - f.tangential.shear).max() < 1e-6 * MU_D * pmax


def test_preconditioner_inverts_the_periodic_symbol():
    """On a periodic cell with the box = the cell, M(q) K(q) = I at every q != 0; M is SPD."""
    grid, gap, op, pair, a = cattaneo_problem(32, periodic=True)
    top = tangential_operator(op)
    pre = top.preconditioner_spectra(grid.shape)
    tn = np.asarray
    kxx, kyy, kxy = (np.real(tn(op.spectra[k])) for k in ("xx", "yy", "xy"))
    mxx, myy, mxy = (np.asarray(pre[k]) for k in ("xx", "yy", "xy"))
    nz = np.ones(kxx.shape, dtype=bool)
    nz[0, 0] = False
    np.testing.assert_allclose((mxx * kxx + mxy * kxy)[nz], 1.0, rtol=1e-10)
    np.testing.assert_allclose((mxx * kxy + mxy * kyy)[nz], 0.0, atol=1e-10)
    np.testing.assert_allclose((mxy * kxy + myy * kyy)[nz], 1.0, rtol=1e-10)
    assert np.all(mxx > 0) and np.all(mxx * myy - mxy**2 > 0)
    assert top.preconditioner_spectra(grid.shape) is pre  # cached


@pytest.mark.parametrize("box", [(17, 24), (40, 33)])
def test_box_preconditioner_is_spd_on_the_free_boundary_operator(box):
    grid, gap, op, pair, a = cattaneo_problem(48)
    pre = tangential_operator(op).preconditioner_spectra(box)
    mxx, myy, mxy = (np.asarray(pre[k]) for k in ("xx", "yy", "xy"))
    assert mxx.shape == (box[0], box[1] // 2 + 1)
    assert np.all(mxx > 0) and np.all(myy > 0) and np.all(mxx * myy - mxy**2 > 0)


def test_bad_preconditioner_name():
    grid, gap, op, pair, a = cattaneo_problem(16)
    nr = solve_normal(op, gap, force=P)
    with pytest.raises(InputError, match="preconditioner"):
        solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=MU, force=0.1, preconditioner="jacobi")
