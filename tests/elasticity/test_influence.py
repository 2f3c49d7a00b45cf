"""Love influence coefficients against numerical quadrature of the point kernels.

Every one of the nine (displacement, traction) components is checked against a direct
numerical integration of :func:`point_kernel` over the loaded cell, for offsets in the loaded
cell itself (singular integrand), in neighbouring cells and in the far field.  Then the
composite rules of two bodies and the reciprocity K_xz = -K_zx.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from tribobem import ContactPair, Material
from tribobem.elasticity import composite_coefficients, lattice_coefficients, point_kernel, single_body_coefficients
from tribobem.elasticity.influence import COMPONENTS

# Non-square cell and a material with G = 1 (E = 2 (1 + nu)): the quadrature runs on O(1)
# numbers, so absolute tolerances are meaningful.  A second material checks the 1/G scaling.
DX, DY = 1.0, 0.75
MAT = Material(2.0 * 1.3, 0.3)          # G = 1, nu = 0.3
MAT_SI = Material(73e9, 0.17)            # fused-silica-like, SI units

# (x, y) offsets of the observation point from the loaded cell's centre, in cells.
SELF_OFFSETS = [(0.0, 0.0), (0.3, -0.2), (-0.45, 0.1)]           # inside the loaded cell
NEAR_OFFSETS = [(1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (-2.0, 1.0), (3.0, -2.0)]
FAR_OFFSETS = [(17.0, 9.0), (-40.0, 25.0), (200.0, -130.0)]


def _quad_regular(component, material, x, y, dx, dy):
    """Coefficient by dblquad over the cell; the integrand is smooth (point outside cell)."""
    a, b = 0.5 * dx, 0.5 * dy
    epsabs = 1e-15 * _scale(material, dx, dy)  # for components that vanish by symmetry

    def f(Y, X):
        return float(point_kernel(component, material, X, Y))

    # integrate k(X, Y) over X in [x - a, x + a], Y in [y - b, y + b]
    val, err = integrate.dblquad(f, x - a, x + a, y - b, y + b, epsabs=epsabs, epsrel=1e-12)
    return val


def _quad_corner(component, material, sx, sy, A, B):
    """Integral of k over the rectangle with corners (0, 0) and (sx A, sy B), singular at (0, 0).

    Polar coordinates X = sx r cos(phi), Y = sy r sin(phi): the Jacobian r cancels the
    1/r singularity of every kernel, so the integrand is bounded and dblquad converges.
    """
    if A == 0.0 or B == 0.0:
        return 0.0
    phic = math.atan2(B, A)

    def f(r, phi):
        return float(point_kernel(component, material, sx * r * math.cos(phi), sy * r * math.sin(phi))) * r

    v1, _ = integrate.dblquad(f, 0.0, phic, 0.0, lambda phi: A / math.cos(phi), epsabs=0.0, epsrel=1e-12)
    v2, _ = integrate.dblquad(f, phic, 0.5 * math.pi, 0.0, lambda phi: B / math.sin(phi), epsabs=0.0, epsrel=1e-12)
    return v1 + v2


def _quad_singular(component, material, x, y, dx, dy):
    """Coefficient at a point inside the loaded cell: split the cell at the singular point
    into four rectangles that each have it as a corner."""
    a, b = 0.5 * dx, 0.5 * dy
    # integration domain in (X, Y) = (x - xi, y - eta): [x - a, x + a] x [y - b, y + b]
    total = 0.0
    for sx, A in ((1.0, x + a), (-1.0, a - x)):
        for sy, B in ((1.0, y + b), (-1.0, b - y)):
            total += _quad_corner(component, material, sx, sy, A, B)
    return total


def _reference(component, material, x, y, dx, dy):
    if abs(x) < 0.5 * dx and abs(y) < 0.5 * dy:
        return _quad_singular(component, material, x, y, dx, dy)
    return _quad_regular(component, material, x, y, dx, dy)


def _scale(material, dx, dy):
    """Magnitude of the self coefficient (zz at the cell centre), for absolute tolerances."""
    return float(single_body_coefficients("zz", material, 0.0, 0.0, dx, dy))


@pytest.mark.parametrize("component", COMPONENTS)
@pytest.mark.parametrize("offset", SELF_OFFSETS + NEAR_OFFSETS + FAR_OFFSETS)
def test_coefficient_matches_quadrature(component, offset):
    x, y = offset[0] * DX, offset[1] * DY
    ref = _reference(component, MAT, x, y, DX, DY)
    got = float(single_body_coefficients(component, MAT, x, y, DX, DY))
    # rel 1e-8; components that vanish by symmetry (e.g. xy on an axis) get an absolute
    # floor far below the coefficients' size.
    atol = 1e-13 * _scale(MAT, DX, DY)
    assert abs(got - ref) <= 1e-8 * abs(ref) + atol, (component, offset, got, ref)


@pytest.mark.parametrize("component", ["zz", "xx", "xy", "zx", "yz"])
def test_coefficient_si_units(component):
    """SI units and dx != dy in metres: the 1/G scaling and the sizes are right."""
    dx, dy = 2e-8, 3e-8
    for ox, oy in [(0.0, 0.0), (0.2, 0.1), (2.0, 1.0), (30.0, -11.0)]:
        x, y = ox * dx, oy * dy
        ref = _reference(component, MAT_SI, x, y, dx, dy)
        got = float(single_body_coefficients(component, MAT_SI, x, y, dx, dy))
        atol = 1e-13 * _scale(MAT_SI, dx, dy)
        assert abs(got - ref) <= 1e-8 * abs(ref) + atol, (component, (ox, oy), got, ref)


def test_self_coefficient_closed_form():
    """The centre of a square cell: zz = (1 - nu^2)/(pi E) * 4 a asinh(1) * 2 (classic)."""
    d = 1e-6
    c = float(single_body_coefficients("zz", MAT_SI, 0.0, 0.0, d, d))
    # integral of 1/rho over a square of side d about its centre = 4 d asinh(1)
    expected = MAT_SI.normal_compliance / math.pi * 4.0 * d * math.asinh(1.0)
    assert c == pytest.approx(expected, rel=1e-13)


def test_vectorised_evaluation_matches_scalar():
    X, Y = np.meshgrid(np.arange(-3, 4) * DX, np.arange(-2, 3) * DY, indexing="ij")
    for comp in COMPONENTS:
        arr = single_body_coefficients(comp, MAT, X, Y, DX, DY)
        assert arr.shape == X.shape
        assert np.all(np.isfinite(arr))
        for i, j in [(0, 0), (3, 2), (6, 4), (1, 3)]:
            assert arr[i, j] == float(single_body_coefficients(comp, MAT, X[i, j], Y[i, j], DX, DY))


# --------------------------------------------------------------------------------------
# Symmetries and reciprocity
# --------------------------------------------------------------------------------------

def _offset_grid():
    X, Y = np.meshgrid(np.arange(-5, 6) * DX, np.arange(-4, 5) * DY, indexing="ij")
    return X, Y


def test_reciprocity_xz_equals_minus_zx():
    X, Y = _offset_grid()
    for m in (MAT, MAT_SI, Material(1e9, -0.5), Material(200e9, 0.5)):
        np.testing.assert_array_equal(single_body_coefficients("xz", m, X, Y, DX, DY),
                                      -single_body_coefficients("zx", m, X, Y, DX, DY))
        np.testing.assert_array_equal(single_body_coefficients("yz", m, X, Y, DX, DY),
                                      -single_body_coefficients("zy", m, X, Y, DX, DY))


def test_in_plane_symmetry_and_parity():
    X, Y = _offset_grid()
    c = {k: single_body_coefficients(k, MAT, X, Y, DX, DY) for k in COMPONENTS}
    np.testing.assert_array_equal(c["xy"], c["yx"])
    # zz, xx, yy even in X and Y; xy odd in both; zx odd in X, even in Y.
    flipx = lambda a: a[::-1, :]  # noqa: E731  (X -> -X on the symmetric offset grid)
    flipy = lambda a: a[:, ::-1]  # noqa: E731
    for k in ("zz", "xx", "yy"):
        np.testing.assert_allclose(flipx(c[k]), c[k], rtol=1e-13)
        np.testing.assert_allclose(flipy(c[k]), c[k], rtol=1e-13)
    s = np.abs(c["zz"]).max()
    np.testing.assert_allclose(flipx(c["xy"]), -c["xy"], atol=1e-14 * s)
    np.testing.assert_allclose(flipx(c["zx"]), -c["zx"], atol=1e-14 * s)
    np.testing.assert_allclose(flipy(c["zx"]), c["zx"], atol=1e-14 * s)
    # the self coefficient of the coupling terms vanishes (odd kernel over a symmetric cell)
    assert abs(float(single_body_coefficients("zx", MAT, 0.0, 0.0, DX, DY))) < 1e-15 * s
    # incompressible body: no normal-tangential coupling
    assert np.all(single_body_coefficients("zx", Material(1e9, 0.5), X, Y, DX, DY) == 0.0)


# --------------------------------------------------------------------------------------
# Composite rules of two bodies
# --------------------------------------------------------------------------------------

M1 = Material(130e9, 0.28, "silicon")
M2 = Material(73e9, 0.17, "silica")


@pytest.mark.parametrize("component", COMPONENTS)
def test_composite_rules(component):
    X, Y = _offset_grid()
    dx, dy = 1e-7, 0.75e-7
    X, Y = X * 1e-7, Y * 1e-7
    pair = ContactPair(M1, M2)
    c1 = single_body_coefficients(component, M1, X, Y, dx, dy)
    c2 = single_body_coefficients(component, M2, X, Y, dx, dy)
    comp = composite_coefficients(component, pair, X, Y, dx, dy)
    if component in ("xz", "zx", "yz", "zy"):
        np.testing.assert_array_equal(comp, c1 - c2)   # coupling subtracts
    else:
        np.testing.assert_array_equal(comp, c1 + c2)   # normal and in-plane parts add


def test_composite_normal_is_one_over_pi_E_star():
    """zz of the pair integrates 1/(pi E* rho): it equals the single-body zz scaled by
    (1 - nu^2)/E -> 1/E*."""
    X, Y = _offset_grid()
    pair = ContactPair(M1, M2)
    comp = composite_coefficients("zz", pair, X, Y, DX, DY)
    one = single_body_coefficients("zz", M1, X, Y, DX, DY)
    np.testing.assert_allclose(comp, one / M1.normal_compliance / pair.effective_modulus, rtol=1e-13)


def test_composite_coupling_constant():
    """The composite coupling is C_c times the integral of X/rho^2."""
    X, Y = _offset_grid()
    pair = ContactPair(M1, M2)
    comp = composite_coefficients("zx", pair, X, Y, DX, DY)
    one = single_body_coefficients("zx", M1, X, Y, DX, DY)
    term1 = (1 - 2 * M1.nu) / (4 * math.pi * M1.shear_modulus)
    np.testing.assert_allclose(comp, one / term1 * pair.coupling_compliance,
                               rtol=1e-12, atol=1e-14 * np.abs(one).max() / term1 * abs(pair.coupling_compliance))
    assert pair.coupling_compliance == pytest.approx(pair.dundurs_beta / (math.pi * pair.effective_modulus), rel=1e-14)


def test_identical_materials_have_no_coupling():
    X, Y = _offset_grid()
    pair = ContactPair(M2, Material(M2.E, M2.nu, "other"))
    for k in ("xz", "zx", "yz", "zy"):
        assert np.all(composite_coefficients(k, pair, X, Y, DX, DY) == 0.0)
    assert pair.coupling_compliance == 0.0
    # ... while the normal and in-plane parts double
    np.testing.assert_array_equal(composite_coefficients("xx", pair, X, Y, DX, DY),
                                  2 * single_body_coefficients("xx", M2, X, Y, DX, DY))


@pytest.mark.parametrize("component", COMPONENTS)
def test_rigid_body_contributes_zero(component):
    X, Y = _offset_grid()
    rigid = Material.rigid()
    assert np.all(single_body_coefficients(component, rigid, X, Y, DX, DY) == 0.0)
    up = composite_coefficients(component, ContactPair(M2, rigid), X, Y, DX, DY)
    down = composite_coefficients(component, ContactPair(rigid, M2), X, Y, DX, DY)
    alone = single_body_coefficients(component, M2, X, Y, DX, DY)
    np.testing.assert_array_equal(up, alone)
    # the rigid body on the other side flips only the coupling sign
    sign = -1.0 if component in ("xz", "zx", "yz", "zy") else 1.0
    np.testing.assert_array_equal(down, sign * alone)


@pytest.mark.parametrize("component", COMPONENTS)
@pytest.mark.parametrize("bodies", ["dissimilar", "rigid_below"])
def test_lattice_coefficients_equal_the_corner_sum(component, bodies):
    """The corner-lattice evaluation (one antiderivative per shared corner: the free-boundary
    operator's build) gives the corner sum of every cell: the same coefficients to round-off,
    with the composite rules (coupling subtracts, a rigid body adds nothing)."""
    pair = ContactPair(M1, M2) if bodies == "dissimilar" else ContactPair(M2, Material.rigid())
    dx, dy = 1e-7, 0.75e-7
    i = np.arange(-7, 12)
    j = np.arange(-13, 6)
    xc = (np.arange(-7, 13) - 0.5) * dx
    yc = (np.arange(-13, 7) - 0.5) * dy
    lat = lattice_coefficients(component, pair, xc, yc)
    ref = composite_coefficients(component, pair, i[:, None] * dx, j[None, :] * dy, dx, dy)
    assert lat.shape == ref.shape == (i.size, j.size)
    scale = np.abs(ref).max()
    if scale == 0.0:  # identical materials' coupling
        assert np.all(lat == 0.0)
    else:
        # round-off of the antiderivative, |F| ~ 20 cells x |coefficient| at the far corners
        np.testing.assert_allclose(lat, ref, rtol=0, atol=1e-13 * scale)
