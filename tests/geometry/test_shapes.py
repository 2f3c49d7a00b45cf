"""Shapes of the upper body: values at known points and input errors."""

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.geometry import bisinusoidal, cylinder, flat, sphere, wavy_sphere
from tribobem.grid import Grid


@pytest.fixture
def g4():
    # cell centres x, y = -1.5, -0.5, 0.5, 1.5 m
    return Grid(4, 4, 4.0, 4.0)


def test_flat(g4):
    h = flat(g4)
    assert h.shape == (4, 4) and not h.any()


def test_sphere_paraboloid(g4):
    R = 10.0
    h = sphere(g4, R)
    assert h[0, 0] == pytest.approx((1.5**2 + 1.5**2) / (2 * R), rel=1e-15)
    assert h[1, 2] == pytest.approx((0.5**2 + 0.5**2) / (2 * R), rel=1e-15)
    assert np.allclose(h, h[::-1, :]) and np.allclose(h, h.T)


def test_sphere_center_offset():
    g = Grid(5, 5, 5.0, 5.0)  # centres -2, -1, 0, 1, 2
    h = sphere(g, 2.0, center=(1.0, -2.0))
    assert h[3, 0] == 0.0
    assert h[3, 1] == pytest.approx(1 / 4)
    assert np.unravel_index(np.argmin(h), h.shape) == (3, 0)


def test_sphere_exact(g4):
    R = 3.0
    h = sphere(g4, R, exact=True)
    r2 = 1.5**2 + 1.5**2
    assert h[0, 0] == pytest.approx(R - np.sqrt(R**2 - r2), rel=1e-14)
    # close to the paraboloid for r << R
    big = sphere(g4, 1e4, exact=True)
    assert np.allclose(big, sphere(g4, 1e4), rtol=1e-7)


def test_sphere_exact_beyond_radius(g4):
    with pytest.raises(InputError) as e:
        sphere(g4, 2.0, exact=True)  # corner at r = 2.12 m
    assert e.value.field == "shape.radius"


@pytest.mark.parametrize("bad", [0.0, -1.0, np.nan, np.inf, "x"])
def test_sphere_bad_radius(g4, bad):
    with pytest.raises(InputError, match="shape.radius"):
        sphere(g4, bad)


def test_cylinder(g4):
    R = 2.0
    hy = cylinder(g4, R)
    assert np.allclose(hy[0, :], 1.5**2 / (2 * R)) and np.allclose(hy[2, :], 0.5**2 / (2 * R))
    hx = cylinder(g4, R, axis="x")
    assert np.allclose(hx, hy.T)
    with pytest.raises(InputError, match="shape.axis"):
        cylinder(g4, R, axis="z")


def test_wavy_sphere_known_points():
    g = Grid(8, 8, 8.0, 8.0)  # centres -3.5 ... 3.5
    R, A, xi = 4.0, 0.1, 2.0
    h = wavy_sphere(g, R, A, xi, center=(-3.5, -3.5))  # cell [k, 0] at r = k
    assert h[0, 0] == 0.0
    assert h[1, 0] == pytest.approx(1 / (2 * R) + 2 * A, rel=1e-14)  # r = xi/2: crest of the wave
    assert h[2, 0] == pytest.approx(4 / (2 * R), rel=1e-14)  # r = xi: trough
    # A = 0 is the paraboloid
    assert np.allclose(wavy_sphere(g, R, 0.0, xi), sphere(g, R))
    with pytest.raises(InputError, match="shape.amplitude"):
        wavy_sphere(g, R, -0.1, xi)


def test_bisinusoidal_odd_grid_crest_at_centre():
    g = Grid(5, 5, 1.0, 1.0, periodic=True)  # centres -0.4 ... 0.4, one at 0
    S = 2e-6
    h = bisinusoidal(g, S, 1.0, 1.0)
    assert h[2, 2] == pytest.approx(S)
    assert h[0, 2] == pytest.approx(S * np.cos(2 * np.pi * 0.4))
    assert abs(h.mean()) < 1e-12 * S


def test_bisinusoidal_even_grid():
    g = Grid(8, 4, 2.0, 1.0, periodic=True)
    S = 1e-6
    h = bisinusoidal(g, S, 2.0, 1.0)
    x, y = g.x[3], g.y[1]
    assert h[3, 1] == pytest.approx(S * np.cos(np.pi * x) * np.cos(2 * np.pi * y), rel=1e-14)
    assert h.max() < S  # the crest at (0, 0) lies between cells
    gap = h.max() - h
    assert gap.min() == 0.0
    # one wavelength per period: periodic continuation is smooth (symmetric about the centre)
    assert np.allclose(h, h[::-1, ::-1])


def test_shapes_are_vectorised_and_float():
    g = Grid(64, 32, 1e-3, 0.5e-3)
    for h in (sphere(g, 1e-2), cylinder(g, 1e-2), wavy_sphere(g, 1e-2, 1e-7, 1e-4),
              bisinusoidal(g, 1e-7, 1e-4, 1e-4), flat(g)):
        assert h.shape == (64, 32) and h.dtype == np.float64
