"""Subsurface stresses (elasticity/subsurface.py) against Huber's Hertz field, McEwen's sliding
line contact, equilibrium and the traction boundary conditions."""

import numpy as np
import pytest

from tribobem.analytic.subsurface import hertz_axis_stresses, huber_stresses, mcewen_stresses
from tribobem.elasticity.subsurface import body_stresses, subsurface_stress
from tribobem.errors import InputError
from tribobem.grid import Grid

NU = 0.3


def _hertz_grid(n, span=4.0):
    g = Grid(n, n, span, span, periodic=False)
    x = (np.arange(n) - n / 2 + 0.5) * g.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    R = np.hypot(X, Y)
    return g, X, Y, R, np.sqrt(np.clip(1 - R ** 2, 0, None))  # a = 1, p0 = 1


@pytest.mark.parametrize("n", [64, 128])
def test_hertz_field_against_huber(n):
    g, X, Y, R, p = _hertz_grid(n)
    for z in (0.48, 1.0):
        s = subsurface_stress(g, p, depths=[z], nu=NU)
        h = huber_stresses(R, z, 1.0, 1.0, NU)
        c, sn = X / R, Y / R
        ref = {"xx": h["rr"] * c ** 2 + h["tt"] * sn ** 2, "yy": h["rr"] * sn ** 2 + h["tt"] * c ** 2,
               "xy": (h["rr"] - h["tt"]) * c * sn, "zz": h["zz"], "xz": h["rz"] * c, "yz": h["rz"] * sn}
        for k, v in ref.items():
            # measured 1e-3 p0 at most (128^2); the padded images' O((a / 4L)^2) and the grid
            assert np.abs(s.component(k)[0] - v).max() < 2.5e-3, (z, k)


def test_hertz_max_shear_on_the_axis():
    """Huber's classic: for nu = 0.3 the largest shear stress is 0.31 p0 at 0.48 a on the axis."""
    g, X, Y, R, p = _hertz_grid(128)
    z = np.linspace(0.3, 0.7, 41)
    s = subsurface_stress(g, p, depths=z, nu=NU)
    c = 64
    tau = s.max_shear()[:, c - 1:c + 1, c - 1:c + 1].mean(axis=(1, 2))
    sr, sz = hertz_axis_stresses(z, 1.0, 1.0, NU)
    assert np.abs(tau - 0.5 * (sr - sz)).max() < 2e-3
    i = int(np.argmax(tau))
    assert z[i] == pytest.approx(0.48, abs=0.02)
    assert tau[i] == pytest.approx(0.31, abs=0.005)


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_sliding_line_contact_against_mcewen(mu):
    # a Hertz strip of half-width 1 on a long periodic cell (the uniform mode of an infinite strip
    # differs from the cell's by -(1 - 2 nu) / 2 ... of the mean pressure: 2.3e-3 p0 at this period)
    nx, ny, L = 8192, 4, 128.0
    g = Grid(nx, ny, L, L * ny / nx, periodic=True)
    x = (np.arange(nx) - nx / 2 + 0.5) * g.dx
    P = np.sqrt(np.clip(1 - x ** 2, 0, None))[:, None] * np.ones((1, ny))
    near = np.abs(x) < 2
    for z in (0.3, 0.78):
        s = subsurface_stress(g, P, np.stack([mu * P, 0 * P]), depths=[z], nu=NU)
        m = mcewen_stresses(x, z, 1.0, 1.0, mu, NU)
        for k, tol in (("xx", 3e-3), ("yy", 3e-3), ("zz", 5e-4), ("xz", 5e-4)):
            assert np.abs(s.component(k)[0][near, 0] - m[k][near]).max() < tol, (z, k)


def test_equilibrium_and_surface_tractions():
    """div sigma = 0 inside (spectral x, y derivatives, central differences in z) and
    sigma . e_z = -(q_x, q_y, p) at the surface, for a rough periodic traction with shear."""
    n, L = 128, 1.0
    g = Grid(n, n, L, L, periodic=True)
    rng = np.random.default_rng(1)
    band = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n), indexing="ij")) < 0.08
    f = np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * band).real
    p = np.maximum(f, 0) * 1e9
    q = np.stack([0.3 * p, -0.1 * p])
    h = 1e-4
    zs = np.array([0.05 - h, 0.05, 0.05 + h])
    s = subsurface_stress(g, p, q, depths=zs, nu=NU)
    kx = 2 * np.pi * np.fft.fftfreq(n, g.dx)[:, None]
    ky = 2 * np.pi * np.fft.fftfreq(n, g.dy)[None, :]

    def d(a, k):
        return np.fft.ifft2(1j * k * np.fft.fft2(a)).real

    C = {k: s.component(k) for k in ("xx", "yy", "zz", "xy", "xz", "yz")}
    dz = {k: (C[k][2] - C[k][0]) / (2 * h) for k in ("xz", "yz", "zz")}
    scale = np.abs(p).max() / 0.05
    for res in (d(C["xx"][1], kx) + d(C["xy"][1], ky) + dz["xz"],
                d(C["xy"][1], kx) + d(C["yy"][1], ky) + dz["yz"],
                d(C["xz"][1], kx) + d(C["yz"][1], ky) + dz["zz"]):
        assert np.abs(res).max() < 1e-4 * scale
    s0 = subsurface_stress(g, p, q, depths=[0.0], nu=NU)
    # at z = 0 the cell-average traction's shape factor smooths the field: compare its
    # cell averages (the mean and the band-limited load are exact)
    assert s0.component("zz")[0].mean() == pytest.approx(-p.mean(), rel=1e-12)
    assert s0.component("xz")[0].mean() == pytest.approx(-q[0].mean(), rel=1e-12)
    assert s0.component("yz")[0].mean() == pytest.approx(-q[1].mean(), rel=1e-12)


def test_plane_force_balance_at_every_depth():
    g, X, Y, R, p = _hertz_grid(64)
    s = subsurface_stress(g, p, np.stack([0.2 * p, 0 * p]), depths=[0.3, 1.0], nu=NU, pad=4)
    # the padded period carries the whole load: the free grid's own window holds most of it
    assert np.all(s.component("zz").sum(axis=(1, 2)) * g.cell_area > -1.01 * p.sum() * g.cell_area)


def test_body_two_mirrors_the_shear():
    g, X, Y, R, p = _hertz_grid(64)
    q = np.stack([0.3 * p, 0 * p])
    s1 = body_stresses(g, p, q, depths=[0.1], nu=NU, body=1)
    s2 = body_stresses(g, p, q, depths=[0.1], nu=NU, body=2)
    # body 2 is sheared the other way: its von Mises field is body 1's mirrored in x
    assert np.allclose(s2.von_mises()[0], s1.von_mises()[0][::-1, :], rtol=1e-9, atol=1e-12)


def test_bad_input():
    g, X, Y, R, p = _hertz_grid(16)
    with pytest.raises(InputError, match="depths"):
        subsurface_stress(g, p, depths=[-1.0], nu=NU)
    with pytest.raises(InputError, match="nu"):
        subsurface_stress(g, p, depths=[0.1], nu=0.7)
