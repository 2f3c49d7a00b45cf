"""Convolution operators: DC-FFT free boundary and periodic (spectral / influence).

* the zero-padded DC-FFT equals the brute-force linear convolution with the influence
  coefficients (normal block and full 3x3 block of dissimilar bodies);
* the periodic spectral kernel reproduces the analytic response of a cosine pressure;
* the periodic "influence" kernel (DFT of the periodised Love coefficients) agrees with the
  spectral one for smooth fields and converges to it at second order in dx;
* kernel spectra are cached per (grid, pair);
* a small loaded patch in a large periodic cell sees the free-boundary field up to a constant.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import (composite_coefficients, free_boundary_operator, make_operator,
                                 periodic_operator)

SILICON = Material(130e9, 0.28, "silicon")
SILICA = Material(73e9, 0.17, "silica")
DISSIMILAR = ContactPair(SILICON, SILICA)          # nonzero normal-tangential coupling
ON_RIGID = ContactPair(SILICA, Material.rigid())


def _brute_force(grid, pair, traction, components):
    """u_i(x_a) = sum_j sum_b C_ij(x_a - x_b) t_j(x_b): the linear convolution, O(N^2)."""
    X, Y = grid.meshgrid()
    xs, ys = X.ravel(), Y.ravel()
    DXo = xs[:, None] - xs[None, :]
    DYo = ys[:, None] - ys[None, :]
    out = np.zeros((len(components),) + grid.shape)
    for i, ci in enumerate(components):
        for j, cj in enumerate(components):
            C = composite_coefficients(ci + cj, pair, DXo, DYo, grid.dx, grid.dy)
            out[i] += (C @ traction[j].ravel()).reshape(grid.shape)
    return out


def test_dcfft_normal_equals_direct_convolution():
    grid = Grid(16, 12, 16e-7, 9e-7)                    # dx != dy
    rng = np.random.default_rng(1)
    p = rng.normal(size=grid.shape) * 1e6
    op = free_boundary_operator(grid, DISSIMILAR)
    u = op.apply(p)
    ref = _brute_force(grid, DISSIMILAR, p[None], ("z",))[0]
    np.testing.assert_allclose(u, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


def test_dcfft_block_operator_equals_direct_convolution():
    grid = Grid(16, 12, 16e-7, 9e-7)
    rng = np.random.default_rng(2)
    t = rng.normal(size=(3,) + grid.shape) * 1e6
    op = free_boundary_operator(grid, DISSIMILAR, components=("x", "y", "z"))
    u = op.apply(t)
    ref = _brute_force(grid, DISSIMILAR, t, ("x", "y", "z"))
    scale = np.abs(ref).max()
    np.testing.assert_allclose(u, ref, rtol=1e-12, atol=1e-12 * scale)
    # the coupling blocks are really exercised (dissimilar materials)
    assert np.abs(op.block("z", "x").apply(t[0])).max() > 1e-3 * scale
    # the normal block of the 3x3 operator is the 1-component operator
    np.testing.assert_allclose(op.normal.apply(t[2]), free_boundary_operator(grid, DISSIMILAR).apply(t[2]),
                               rtol=1e-13, atol=1e-14 * scale)


def test_dcfft_identical_materials_have_no_coupling_blocks():
    grid = Grid(8, 8, 1e-6, 1e-6)
    pair = ContactPair(SILICA, Material(SILICA.E, SILICA.nu, "other"))
    op = free_boundary_operator(grid, pair, components=("x", "y", "z"))
    assert op.spectrum("z", "x") is None and op.spectrum("x", "z") is None
    assert op.spectrum("z", "z") is not None and op.spectrum("x", "x") is not None


# --------------------------------------------------------------------------------------
# Periodic operators
# --------------------------------------------------------------------------------------

def _cosine(grid, mode=1):
    return np.cos(2 * np.pi * mode * grid.x / grid.lx)[:, None] * np.ones(grid.ny)[None, :]


@pytest.mark.parametrize("shape", [(64, 64), (128, 8), (96, 40)])
def test_periodic_spectral_cosine_is_exact(shape):
    """u of p0 cos(2 pi x/L) is 2 p0/(E* q) cos(2 pi x/L) with q = 2 pi/L."""
    L = 3e-6
    grid = Grid(shape[0], shape[1], L, L * shape[1] / shape[0], periodic=True)
    p0 = 1e7
    for mode in (1, 3):
        p = p0 * _cosine(grid, mode)
        u = periodic_operator(grid, ON_RIGID).apply(p)
        q = 2 * np.pi * mode / L
        ref = 2 * p0 / (ON_RIGID.effective_modulus * q) * _cosine(grid, mode)
        np.testing.assert_allclose(u, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def test_periodic_mean_pressure_gives_no_displacement():
    grid = Grid.square(32, 1e-6, periodic=True)
    for kernel in ("spectral", "influence"):
        u = periodic_operator(grid, ON_RIGID, kernel=kernel).apply(np.full(grid.shape, 1e6))
        assert np.abs(u).max() < 1e-25


def test_periodic_kernels_agree_for_smooth_field():
    grid = Grid.square(64, 2e-6, periodic=True)
    p = 1e6 * (_cosine(grid, 1) + 0.5 * np.sin(2 * np.pi * grid.y / grid.ly)[None, :])
    us = periodic_operator(grid, ON_RIGID, kernel="spectral").apply(p)
    ui = periodic_operator(grid, ON_RIGID, kernel="influence").apply(p)
    err = np.abs(ui - us).max() / np.abs(us).max()
    assert err < 1e-3
    assert err > 0  # they are different kernels


def _influence_vs_spectral(n):
    grid = Grid(n, 8, 1e-6, 1e-6 * 8 / n, periodic=True)
    p = _cosine(grid, 1)
    us = periodic_operator(grid, ON_RIGID, kernel="spectral").apply(p)
    ui = periodic_operator(grid, ON_RIGID, kernel="influence").apply(p)
    return np.abs(ui - us).max() / np.abs(us).max()


def test_periodic_influence_kernel_converges_at_second_order():
    """At a fixed wavelength the influence kernel tends to 2/(E* q) like (q dx)^2:
    the piecewise-constant cell average (sinc) and the aliases both are O(dx^2)."""
    ns = [16, 32, 64, 128]
    errs = [_influence_vs_spectral(n) for n in ns]
    assert all(e1 < e0 for e0, e1 in zip(errs, errs[1:])), errs
    orders = [math.log2(e0 / e1) for e0, e1 in zip(errs, errs[1:])]
    assert all(1.8 < o < 2.2 for o in orders), orders


def test_spectra_are_cached_per_grid_and_pair():
    grid = Grid.square(32, 1e-6)
    a = free_boundary_operator(grid, ON_RIGID)
    b = free_boundary_operator(Grid.square(32, 1e-6), ContactPair(SILICA, Material.rigid()))
    assert a.spectra is b.spectra
    assert a.spectrum() is b.spectrum()
    pgrid = Grid.square(32, 1e-6, periodic=True)
    assert periodic_operator(pgrid, ON_RIGID).spectra is make_operator(pgrid, ON_RIGID).spectra
    assert (periodic_operator(pgrid, ON_RIGID, kernel="influence").spectra
            is periodic_operator(pgrid, ON_RIGID, kernel="influence").spectra)
    # a different grid or pair gets its own spectra
    assert free_boundary_operator(Grid.square(32, 2e-6), ON_RIGID).spectra is not a.spectra
    assert free_boundary_operator(grid, DISSIMILAR).spectra is not a.spectra
    assert periodic_operator(pgrid, ON_RIGID, kernel="influence").spectra is not periodic_operator(pgrid, ON_RIGID).spectra


def test_make_operator_dispatches_on_grid():
    assert make_operator(Grid.square(8, 1e-6, periodic=True), ON_RIGID).periodic
    op = make_operator(Grid.square(8, 1e-6), ON_RIGID)
    assert not op.periodic and op.fft_shape == (16, 16)


# --------------------------------------------------------------------------------------
# Free boundary vs periodic: an isolated load in a large cell
# --------------------------------------------------------------------------------------

def _compare_near_patch(u_free, u_per, mask):
    """Max difference after removing each field's mean over ``mask``, relative to the
    variation of the free field there."""
    df = u_free[mask] - u_free[mask].mean()
    dp = u_per[mask] - u_per[mask].mean()
    return np.abs(df - dp).max() / (df.max() - df.min())


def test_free_and_periodic_agree_for_small_patch_influence_kernel():
    """A uniform patch of radius L/32: the periodic images and the removed mean pressure
    change the field near the patch only by a constant plus O((r0/L)(r/L)^2)."""
    n, L = 256, 32e-6
    r0 = L / 32
    gp, gf = Grid.square(n, L, periodic=True), Grid.square(n, L)
    r = gf.radius()
    p = np.where(r < r0, 1e8, 0.0)
    u_free = free_boundary_operator(gf, ON_RIGID).apply(p)
    u_per = periodic_operator(gp, ON_RIGID, kernel="influence").apply(p)
    assert _compare_near_patch(u_free, u_per, r < 4 * r0) < 0.01


def test_free_and_periodic_agree_for_small_smooth_load_spectral_kernel():
    """Same with the spectral kernel, for a smooth (Gaussian) load: the spectral kernel and
    the piecewise-constant one differ only at the grid scale."""
    n, L = 256, 32e-6
    r0 = L / 32
    gp, gf = Grid.square(n, L, periodic=True), Grid.square(n, L)
    r = gf.radius()
    p = 1e8 * np.exp(-(r / r0) ** 2)
    u_free = free_boundary_operator(gf, ON_RIGID).apply(p)
    u_per = periodic_operator(gp, ON_RIGID, kernel="spectral").apply(p)
    assert _compare_near_patch(u_free, u_per, r < 4 * r0) < 0.01


def test_free_boundary_kernel_does_not_depend_on_threads(monkeypatch):
    """The padded kernel spectra are computed in row blocks on up to 8 threads, the block size
    shrinking with the threads: the spectra are bitwise the same for any thread count."""
    from tribobem.elasticity.operators import _padded_kernel_spectrum

    pair = ContactPair(Material(130e9, 0.28), Material(70e9, 0.2))
    spectra = {}
    for workers in ("1", "3", "8"):
        monkeypatch.setenv("TRIBOBEM_FFT_WORKERS", workers)
        spectra[workers] = [_padded_kernel_spectrum(k, pair, 1000, 300, 1e-8, 2e-8) for k in ("zz", "zx", "xy")]
    for workers in ("3", "8"):
        for a, b in zip(spectra["1"], spectra[workers]):
            np.testing.assert_array_equal(a, b)
