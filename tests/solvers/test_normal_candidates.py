"""Candidate-set solves and single-precision NormCG against the whole-grid double solve."""

import numpy as np
import pytest

from tribobem.elasticity.operators import make_operator
from tribobem.errors import InputError
from tribobem.grid import Grid
from tribobem.interactions import DugdaleAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers import candidates as cand
from tribobem.solvers.normal_cg import solve_normal_cg

E_STAR = 1.0
TOL = 1e-10


def _crowned_rough(n, seed=7, slope=0.05):
    """The peers' free-boundary problem (unit square, E* = 1): a self-affine field of rms slope
    ``slope`` on a crown of radius 2, gap shifted to min 0; force 2e-4 E* over the square."""
    rng = np.random.default_rng(seed)
    k = np.fft.fftfreq(n) * n
    kr = np.fft.rfftfreq(n) * n
    q = np.hypot(k[:, None], kr[None, :])
    with np.errstate(divide="ignore"):
        amp = np.where(q < n / 16, (n / 16) ** -1.8, q ** -1.8)
    amp[q > n / 4] = 0.0
    amp[0, 0] = 0.0
    z = np.fft.irfft2(amp * np.exp(2j * np.pi * rng.random(q.shape)), s=(n, n))
    gx, gy = np.gradient(z, 1.0 / n)
    z *= slope / np.sqrt(np.mean(gx**2 + gy**2))
    x = (np.arange(n) + 0.5) / n - 0.5
    gap = (x[:, None] ** 2 + x[None, :] ** 2) / 4.0 + z.max() - z
    return gap - gap.min()


def _op(n, periodic=False):
    return make_operator(Grid.square(n, 1.0, periodic=periodic), ContactPair(Material(E_STAR, 0.0), Material.rigid()))


def _same(res, ref, gap):
    """The same contact nodes, pressures within 1e-6 of the largest, gaps within 1e-9 of the gap
    range, approaches within 1e-9 (the solver tolerance 1e-10 bounds the rest)."""
    assert res.converged and ref.converged
    assert np.array_equal(res.contact, ref.contact)
    assert np.abs(res.pressure - ref.pressure).max() <= 1e-6 * ref.pressure.max()
    assert np.abs(res.gap - ref.gap).max() <= 1e-9 * np.ptp(gap)
    assert np.abs(res.displacement - ref.displacement).max() <= 1e-9 * np.abs(ref.displacement).max()
    assert abs(res.approach - ref.approach) <= 1e-9 * abs(ref.approach)
    assert abs(res.force - ref.force) <= 1e-9 * ref.force


@pytest.mark.parametrize("n", [128, 256])
def test_candidate_solve_is_the_whole_grid_solve(n):
    gap = _crowned_rough(n)
    op = _op(n)
    ref = solve_normal_cg(op, gap, force=2e-4, tol=TOL, candidates=False)
    res = solve_normal_cg(op, gap, force=2e-4, tol=TOL, candidates=True)
    c = res.info["candidates"]
    assert "candidates" not in ref.info
    assert c["rounds"] >= 1 and 0 < c["box_fraction"] < cand.MAX_FRACTION and c["verified_margin"] > 0
    _same(res, ref, gap)


def test_a_box_too_small_grows_until_verified(monkeypatch):
    """An approach estimate far too low: the first box misses nodes below the approach, the
    check finds them, and the grown box gives the whole grid's state."""
    monkeypatch.setattr(cand, "SAFETY", -0.9)
    n = 256
    gap = _crowned_rough(n)
    op = _op(n)
    ref = solve_normal_cg(op, gap, force=2e-4, tol=TOL, candidates=False)
    res = solve_normal_cg(op, gap, force=2e-4, tol=TOL, candidates=True)
    assert res.info["candidates"]["rounds"] >= 2
    _same(res, ref, gap)


def test_displacement_control_box_is_exact_at_once():
    n = 256
    gap = _crowned_rough(n)
    op = _op(n)
    ref = solve_normal_cg(op, gap, approach=0.004, tol=TOL, candidates=False)
    res = solve_normal_cg(op, gap, approach=0.004, tol=TOL, candidates=True)
    assert res.info["candidates"]["rounds"] == 1 and res.info["candidates"]["coarse"] is None
    _same(res, ref, gap)


def test_candidates_refused_or_skipped_where_they_do_not_apply():
    n = 128
    gap = _crowned_rough(n)
    with pytest.raises(InputError, match="periodic"):
        solve_normal_cg(_op(n, periodic=True), gap, force=2e-4, candidates=True)
    law = DugdaleAdhesion(work_of_adhesion=1e-7, z0=1e-4)
    with pytest.raises(InputError, match="outside stress law"):
        solve_normal_cg(_op(n), gap, force=2e-4, interaction=law, candidates=True)
    # automatic: not below MIN_NODES, nor with adhesion
    res = solve_normal_cg(_op(n), gap, force=2e-4, tol=1e-8)
    assert "candidates" not in res.info


@pytest.mark.parametrize("periodic", [False, True])
def test_single_precision_reaches_the_double_state(periodic):
    """Single-precision direction images, double-precision convergence test: the state of the
    double solve at the same tolerance, and the double-precision residuals of the result below it."""
    n = 128
    gap = _crowned_rough(n, slope=1.0 if periodic else 0.05)
    op = _op(n, periodic)
    force = 0.01 if periodic else 2e-4
    ref = solve_normal_cg(op, gap, force=force, tol=TOL, candidates=False)
    res = solve_normal_cg(op, gap, force=force, tol=TOL, candidates=False, precision="single")
    assert res.info["precision"] == "single" and ref.info["precision"] == "double"
    _same(res, ref, gap)
    # the certificate: the double-precision contact gap and the force balance of the result
    rms = np.sqrt(np.mean(res.gap[res.contact] ** 2)) / np.ptp(gap)
    assert rms < TOL
    assert abs(res.pressure.sum() * op.grid.dx * op.grid.dy - force) <= 1e-12 * force


def test_precision_is_checked():
    with pytest.raises(InputError, match="precision"):
        solve_normal_cg(_op(32), _crowned_rough(32), force=2e-4, precision="half")


@pytest.mark.parametrize("kw", [{"candidates": True}, {"candidates": False, "precision": "single"}])
def test_device_clean_on_the_strict_backend(kw):
    """CuPy's host/device rules (the strict backend): no host array meets a device array in the
    candidate-set solve or the single-precision iteration, and the numbers are NumPy's."""
    from tribobem.elasticity import free_boundary_operator

    n = 128
    gap = _crowned_rough(n)
    pair = ContactPair(Material(E_STAR, 0.0), Material.rigid())
    grid = Grid.square(n, 1.0, periodic=False)
    op = free_boundary_operator(grid, pair, backend="strict")
    res = solve_normal_cg(op, op.backend.asarray(gap), force=2e-4, tol=TOL, **kw)
    ref = solve_normal_cg(_op(n), gap, force=2e-4, tol=TOL, **kw)
    be = op.backend
    assert np.array_equal(be.to_numpy(res.contact), ref.contact)
    assert np.abs(be.to_numpy(res.pressure) - ref.pressure).max() <= 1e-9 * ref.pressure.max()


def test_growth_is_device_clean_too(monkeypatch):
    from tribobem.elasticity import free_boundary_operator

    monkeypatch.setattr(cand, "SAFETY", -0.9)
    n = 128
    gap = _crowned_rough(n)
    op = free_boundary_operator(Grid.square(n, 1.0, periodic=False), ContactPair(Material(E_STAR, 0.0), Material.rigid()),
                                backend="strict")
    res = solve_normal_cg(op, op.backend.asarray(gap), force=2e-4, tol=TOL, candidates=True)
    ref = solve_normal_cg(_op(n), gap, force=2e-4, tol=TOL, candidates=False)
    assert res.info["candidates"]["rounds"] >= 2
    assert np.array_equal(op.backend.to_numpy(res.contact), ref.contact)
