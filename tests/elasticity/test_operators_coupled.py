"""The coupled 3x3 periodic operator (components x, y, z).

* every block of the "influence" kernel equals the direct spatial sum of the periodised
  closed-form Love coefficients (the ground truth of signs and factors);
* the "spectral" kernel reproduces the plane-strain / antiplane responses to a cosine
  traction exactly, and agrees with the "influence" kernel for smooth (long-wavelength) loads;
* a small smooth load in a large periodic cell sees the free-boundary (DC-FFT) field;
* the coupling blocks vanish for identical materials, change sign when the bodies are swapped,
  and make a rigid-on-elastic surface move toward a compressive load;
* reciprocity of the spectra, and one forward FFT per traction component per apply.
"""

from __future__ import annotations

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import composite_coefficients, free_boundary_operator, periodic_operator
from tribobem.elasticity.backend import Backend

SILICON = Material(130e9, 0.28, "silicon")
SILICA = Material(73e9, 0.17, "silica")
DISSIMILAR = ContactPair(SILICON, SILICA)          # nonzero normal-tangential coupling
AXES = ("x", "y", "z")
KEYS = [o + i for o in AXES for i in AXES]
COUPLING = ("xz", "zx", "yz", "zy")


def _unit(j, grid, where=None):
    """A (3, nx, ny) traction: 1 Pa of component j on one cell (default: the centre cell)."""
    t = np.zeros((3,) + grid.shape)
    ix, iy = where if where is not None else (grid.nx // 2, grid.ny // 2)
    t[j, ix, iy] = 1.0
    return t


def _mean_free(a):
    return a - a.mean()


# --------------------------------------------------------------------------------------
# Ground truth: the periodised Love coefficients summed in real space
# --------------------------------------------------------------------------------------

def _periodised_coefficients(grid, pair, key, M):
    """u at every cell from a unit traction on the centre cell and its (2M+1)^2 images.

    The images of the 1/rho blocks (and the linear term of the x/rho^2 blocks) do not
    converge on their own; the periodic operator sees the traction minus its mean (q = 0 is
    0).  So the mean traction dx dy/(lx ly), spread over the (2M+1) lx x (2M+1) ly square of
    images, is subtracted -- its field is again a Love coefficient.  What remains is the sum of
    neutral cells, which converges (up to a constant: compare mean-free fields).
    """
    X = ((np.arange(grid.nx) - grid.nx // 2) * grid.dx)[:, None]
    Y = ((np.arange(grid.ny) - grid.ny // 2) * grid.dy)[None, :]
    k = np.arange(-M, M + 1)
    Xi = X[None, None] + (k * grid.lx)[:, None, None, None]
    Yi = Y[None, None] + (k * grid.ly)[None, :, None, None]
    u = composite_coefficients(key, pair, Xi, Yi, grid.dx, grid.dy).sum(axis=(0, 1))
    big = composite_coefficients(key, pair, X, Y, (2 * M + 1) * grid.lx, (2 * M + 1) * grid.ly)
    return u - grid.dx * grid.dy / (grid.lx * grid.ly) * big


@pytest.mark.parametrize("shape, ly_over_lx", [((16, 16), 1.0), ((15, 20), 1.3), ((12, 9), 0.6)])
def test_influence_kernel_equals_spatial_sum_of_periodised_coefficients(shape, ly_over_lx):
    """All 9 blocks, even and odd grid sizes, dx != dy.  Measured (n_alias=64, 30 images):
    <= 3e-7 for xx, yy, zz, xy, yx and <= 4.5e-5 for the odd coupling blocks, whose alias sum
    converges like n_alias^-2 (2.3e-3 at the default n_alias=8)."""
    grid = Grid(shape[0], shape[1], 1e-6, 1e-6 * ly_over_lx, periodic=True)
    op = periodic_operator(grid, DISSIMILAR, AXES, kernel="influence", n_alias=64)
    for j, cj in enumerate(AXES):
        u = op.apply(_unit(j, grid))
        for i, ci in enumerate(AXES):
            key = ci + cj
            ref = _mean_free(_periodised_coefficients(grid, DISSIMILAR, key, 30))
            err = np.abs(_mean_free(u[i]) - ref).max() / np.abs(ref).max()
            tol = 1e-4 if key in COUPLING else 2e-6
            assert err < tol, (key, err)


# --------------------------------------------------------------------------------------
# Spectral kernel: exact cosine responses, agreement with the influence kernel
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(64, 64), (96, 40), (33, 17)])
def test_spectral_kernel_cosine_responses(shape):
    """A traction t0 cos(q x) (q = 2 pi m/lx) on two half-spaces.  Plane strain / antiplane
    results, body by body: u_z from p and u_x from q_x are (1-nu)/(G q) t0 cos(qx); u_y from
    q_y is t0 cos(qx)/(G q); u_z from q_x is +(1-2nu)/(2 G q) t0 sin(qx) and u_x from p is
    -(1-2nu)/(2 G q) t0 sin(qx) (the surface moves toward the pressure peak); the coupling of
    body 2 enters with a minus sign.  No in-plane cross term (xy) for a 1-D mode."""
    lx = 3e-6
    grid = Grid(shape[0], shape[1], lx, lx * shape[1] / shape[0] * 0.8, periodic=True)
    op = periodic_operator(grid, DISSIMILAR, AXES, kernel="spectral")
    G1, n1, G2, n2 = SILICON.shear_modulus, SILICON.nu, SILICA.shear_modulus, SILICA.nu
    t0 = 1e7
    for m in (1, 4):
        q = 2 * np.pi * m / lx
        c = np.cos(q * grid.x)[:, None] * np.ones(grid.ny)
        s = np.sin(q * grid.x)[:, None] * np.ones(grid.ny)
        normal = ((1 - n1) / G1 + (1 - n2) / G2) / q
        antiplane = (1 / G1 + 1 / G2) / q
        coupling = ((1 - 2 * n1) / (2 * G1) - (1 - 2 * n2) / (2 * G2)) / q
        expected = {"xx": normal * c, "yy": antiplane * c, "zz": normal * c,
                    "zx": coupling * s, "xz": -coupling * s,
                    "xy": 0 * c, "yx": 0 * c, "zy": 0 * c, "yz": 0 * c}
        for j, cj in enumerate(AXES):
            t = np.zeros((3,) + grid.shape)
            t[j] = t0 * c
            u = op.apply(t)
            for i, ci in enumerate(AXES):
                ref = t0 * expected[ci + cj]
                np.testing.assert_allclose(u[i], ref, rtol=0, atol=1e-12 * t0 * normal, err_msg=ci + cj)


@pytest.mark.parametrize("shape, width_cells", [((128, 96), 16), ((160, 160), 20)])
def test_spectral_and_influence_kernels_agree_at_long_wavelengths(shape, width_cells):
    """A Gaussian traction of width w >> dx: the kernels differ by the cell sinc, a relative
    O((dx/w)^2 / 6) effect.  Measured: <= 1.0e-3 (w = 16 dx), <= 6.5e-4 (w = 20 dx)."""
    lx = 1e-6
    grid = Grid(shape[0], shape[1], lx, lx * shape[1] / shape[0], periodic=True)
    X, Y = grid.meshgrid()
    w = width_cells * grid.dx
    g = 1e6 * np.exp(-(X / w) ** 2 - (Y / w) ** 2)
    spectral = periodic_operator(grid, DISSIMILAR, AXES, kernel="spectral")
    influence = periodic_operator(grid, DISSIMILAR, AXES, kernel="influence")
    tol = 1.3e-3 * (16 / width_cells) ** 2
    for j, cj in enumerate(AXES):
        t = np.zeros((3,) + grid.shape)
        t[j] = g
        us, ui = spectral.apply(t), influence.apply(t)
        for i, ci in enumerate(AXES):
            a, b = _mean_free(us[i]), _mean_free(ui[i])
            err = np.abs(a - b).max() / np.abs(a).max()
            assert 0 < err < tol, (ci + cj, err)


# --------------------------------------------------------------------------------------
# Periodic vs free boundary
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("kernel, tol", [("spectral", 6e-3), ("influence", 4e-3)])
@pytest.mark.parametrize("nx, ny, ly", [(256, 256, 32e-6), (256, 192, 30e-6)])
def test_periodic_and_free_boundary_agree_for_small_smooth_load(kernel, tol, nx, ny, ly):
    """A Gaussian load of width L/32, all 9 blocks, mean-free fields within 3 widths.

    The periodic operator acts on the traction minus its mean (q = 0 is 0), so the free
    operator gets that neutral traction too (else the removed mean of the odd blocks shows
    up as a linear term, ~2e-2 here).  What is left is the field of the periodic images, which
    is largest for the xy block (~ x y / L^3).  Measured: spectral <= 5.1e-3 (the spectral
    kernel vs piecewise-constant coefficients), influence <= 2.8e-3.
    """
    lx = 32e-6
    gp, gf = Grid(nx, ny, lx, ly, periodic=True), Grid(nx, ny, lx, ly)
    r0 = lx / 32
    r = gf.radius()
    p = 1e8 * np.exp(-(r / r0) ** 2)
    free = free_boundary_operator(gf, DISSIMILAR, AXES)
    per = periodic_operator(gp, DISSIMILAR, AXES, kernel=kernel)
    near = r < 3 * r0
    for j, cj in enumerate(AXES):
        t = np.zeros((3,) + gf.shape)
        t[j] = p - p.mean()
        uf, up = free.apply(t), per.apply(t)
        for i, ci in enumerate(AXES):
            a, b = _mean_free(uf[i][near]), _mean_free(up[i][near])
            err = np.abs(a - b).max() / np.abs(a).max()
            assert err < tol, (ci + cj, err)


# --------------------------------------------------------------------------------------
# Coupling: identical materials, swapped bodies, the physical sign
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("kernel", ["spectral", "influence"])
def test_identical_materials_have_no_coupling(kernel):
    grid = Grid(32, 24, 1e-6, 0.8e-6, periodic=True)
    pair = ContactPair(SILICA, Material(SILICA.E, SILICA.nu, "silica 2"))
    op = periodic_operator(grid, pair, AXES, kernel=kernel)
    for key in COUPLING:
        assert op.spectrum(key[0], key[1]) is None
    t = np.random.default_rng(3).normal(size=(3,) + grid.shape)
    t[:2] = 0.0
    u = op.apply(t)  # a pressure alone moves nothing in-plane
    assert np.all(u[:2] == 0.0)


@pytest.mark.parametrize("kernel", ["spectral", "influence"])
def test_swapping_the_bodies_flips_only_the_coupling(kernel):
    grid = Grid(32, 24, 1e-6, 0.8e-6, periodic=True)
    a = periodic_operator(grid, DISSIMILAR, AXES, kernel=kernel)
    b = periodic_operator(grid, ContactPair(SILICA, SILICON), AXES, kernel=kernel)
    for key in KEYS:
        sa, sb = a.spectrum(key[0], key[1]), b.spectrum(key[0], key[1])
        scale = np.abs(sa).max()
        assert scale > 0
        sign = -1.0 if key in COUPLING else 1.0
        np.testing.assert_allclose(sb, sign * sa, rtol=0, atol=1e-13 * scale, err_msg=key)


@pytest.mark.parametrize("kernel", ["spectral", "influence"])
@pytest.mark.parametrize("nu", [0.0, 0.17, 0.3, 0.45])
def test_rigid_indenter_pulls_the_surface_toward_the_load(kernel, nu):
    """Elastic body 1 under a rigid body 2: a compressive pressure patch pulls the surface
    radially inward (Boussinesq, u_r = -(1-2nu) P/(4 pi G r)): u_x < 0 at x > 0 all the way
    to the cell edge.  With the bodies swapped the relative displacement reverses; at
    nu = 0.5 there is no coupling."""
    n, L = 128, 10e-6
    grid = Grid.square(n, L, periodic=True)
    X, Y = grid.meshgrid()
    p = 1e8 * np.exp(-(X**2 + Y**2) / (L / 16) ** 2)
    t = np.zeros((3,) + grid.shape)
    t[2] = p
    row, col = n // 2, n // 2      # cells just beside the axes (y = dy/2, x = dx/2)
    right, left = grid.x > 0, grid.x < 0
    for pair, sign in ((ContactPair(Material(70e9, nu), Material.rigid()), 1.0),
                       (ContactPair(Material.rigid(), Material(70e9, nu)), -1.0)):
        u = periodic_operator(grid, pair, AXES, kernel=kernel).apply(t)
        ux, uy = sign * u[0][:, col], sign * u[1][row, :]
        assert np.all(ux[right] < 0) and np.all(ux[left] > 0)
        assert np.all(uy[right] < 0) and np.all(uy[left] > 0)
        # magnitude: u_x = -(1-2nu)/(4 pi G) [F(r)/r - pi r F/L^2] on the x axis, F(r) the
        # load within r (Gauss's law for the x/rho^2 kernel of an axisymmetric load) and the
        # second term the removed mean pressure (q = 0); the square lattice of images adds
        # nothing at linear order.  Measured: within 1.3e-3 at r = 2 widths.
        G = 70e9 / (2 * (1 + nu))
        F = p.sum() * grid.cell_area
        i = np.argmin(np.abs(grid.x - 2 * L / 16))
        r = np.hypot(grid.x[i], grid.y[col])
        u_r = (1 - 2 * nu) / (4 * np.pi * G) * F * ((1 - np.exp(-(r / (L / 16)) ** 2)) / r - np.pi * r / L**2)
        ref = u_r * grid.x[i] / r
        assert -ux[i] == pytest.approx(ref, rel=3e-3)
    no_coupling = periodic_operator(grid, ContactPair(Material(70e9, 0.5), Material.rigid()), AXES, kernel=kernel)
    assert np.all(no_coupling.apply(t)[:2] == 0.0)


# --------------------------------------------------------------------------------------
# Structure: reciprocity, Nyquist, caching, FFT count
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("kernel", ["spectral", "influence"])
@pytest.mark.parametrize("shape", [(16, 16), (15, 10)])
def test_spectra_reciprocity_and_nyquist(kernel, shape):
    grid = Grid(shape[0], shape[1], 1e-6, 0.7e-6, periodic=True)
    op = periodic_operator(grid, DISSIMILAR, AXES, kernel=kernel)
    S = {k: op.spectrum(k[0], k[1]) for k in KEYS}
    assert all(s is not None and s.shape == (grid.nx, grid.ny // 2 + 1) for s in S.values())
    np.testing.assert_array_equal(S["zx"], -S["xz"])
    np.testing.assert_array_equal(S["zy"], -S["yz"])
    np.testing.assert_array_equal(S["xy"], S["yx"])
    for k in KEYS:
        assert S[k][0, 0] == 0  # q = 0
        if k in COUPLING:       # odd kernels: purely imaginary
            assert np.iscomplexobj(S[k]) and np.all(S[k].real == 0) and np.abs(S[k].imag).max() > 0
        else:                   # even kernels: real
            assert not np.iscomplexobj(S[k])
    # odd in qx: xy, zx, xz; odd in qy: xy, zy, yz -- no Nyquist term on even grids
    if grid.nx % 2 == 0:
        for k in ("xy", "zx", "xz"):
            assert np.all(S[k][grid.nx // 2, :] == 0)
    if grid.ny % 2 == 0:
        for k in ("xy", "zy", "yz"):
            assert np.all(S[k][:, -1] == 0)
    # the normal block is the normal-only operator's
    np.testing.assert_allclose(S["zz"], periodic_operator(grid, DISSIMILAR, kernel=kernel).spectrum(),
                               rtol=1e-14, atol=0)


def test_coupled_spectra_are_cached():
    grid = Grid.square(16, 1e-6, periodic=True)
    a = periodic_operator(grid, DISSIMILAR, AXES, kernel="influence", n_alias=4)
    b = periodic_operator(Grid.square(16, 1e-6, periodic=True), ContactPair(SILICON, SILICA), AXES,
                          kernel="influence", n_alias=4)
    assert a.spectra is b.spectra
    assert periodic_operator(grid, DISSIMILAR, AXES, kernel="influence", n_alias=5).spectra is not a.spectra
    assert periodic_operator(grid, DISSIMILAR, ("x", "z"), kernel="influence", n_alias=4).spectra is not a.spectra
    assert periodic_operator(grid, DISSIMILAR, AXES).spectra is not a.spectra


def test_subset_of_components_matches_the_full_operator():
    grid = Grid(24, 20, 1e-6, 0.9e-6, periodic=True)
    full = periodic_operator(grid, DISSIMILAR, AXES)
    xz = periodic_operator(grid, DISSIMILAR, ("x", "z"))
    t = np.random.default_rng(5).normal(size=(3,) + grid.shape)
    t[1] = 0.0
    u_full, u_xz = full.apply(t), xz.apply(t[[0, 2]])
    np.testing.assert_allclose(u_xz, u_full[[0, 2]], rtol=1e-13, atol=1e-13 * np.abs(u_full).max())


def test_one_forward_fft_per_traction_component(monkeypatch):
    grid = Grid(32, 24, 1e-6, 0.8e-6, periodic=True)
    op = periodic_operator(grid, DISSIMILAR, AXES)
    t = np.random.default_rng(4).normal(size=(3,) + grid.shape)
    u_ref = op.apply(t)
    calls = {"rfft2": 0, "irfft2": 0}
    forward, inverse = Backend.rfft2, Backend.irfft2

    def counting_rfft2(self, a, s=None):
        calls["rfft2"] += 1
        return forward(self, a, s=s)

    def counting_irfft2(self, a, s):
        calls["irfft2"] += 1
        return inverse(self, a, s)

    monkeypatch.setattr(Backend, "rfft2", counting_rfft2)
    monkeypatch.setattr(Backend, "irfft2", counting_irfft2)
    u = op.apply(t)
    assert calls == {"rfft2": 3, "irfft2": 3}
    np.testing.assert_array_equal(u, u_ref)
    assert u.dtype == np.float64 and u.shape == t.shape
