"""Body models (tribobem.elasticity.bodies): the operators, solvers and checks take the bodies'
response from the pair's model, whatever its type.

Two models defined only here, registered for the tests and removed after them:

* ``DepthLimited`` -- a half-space whose normal compliance is cut off below the wavenumber
  1/depth: K(q) = 2 tanh(q d) / (E* q) (a finite-thickness-like body: a half-space for q d >> 1,
  a Winkler bed of compliance 2d/E* for q d << 1).  It supplies its Fourier symbol only, so it
  runs on periodic grids through the base class's defaults (spectra, kernel="influence",
  Polonsky-Keer's box preconditioner) and refuses free-boundary grids.  Checked on a periodic
  sinusoid in full contact, whose pressure is analytic: p = p_mean - (a / K(q0)) cos(q0 x) for
  the gap a cos(q0 x); and, at a depth where tanh(q d) = 1 to the last bit, against the
  half-space on a partial rough contact.
* ``Scaled`` -- the half-space with every compliance times c (real-space coefficients too): a
  free-boundary Hertz contact equals the half-space of modulus E*/c, and so does its partial
  slip under TangCG with the FFT preconditioner (whose box spectra and preconditioner come from
  the operator's own spectra, whatever the body).

And the half-space itself: the pair's default model, its self-compliance path of
:func:`~tribobem.output.checks.cell_self_compliance` equal to the E* path bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import free_boundary_operator, make_operator, periodic_operator
from tribobem.elasticity.bodies import (BODY_MODELS, DEFAULT_BODY_MODEL, BodyModel, HalfSpace, body_model,
                                        body_model_of, halfspace_self_compliance, register_body_model,
                                        unregister_body_model)
from tribobem.elasticity.influence import lattice_coefficients
from tribobem.errors import InputError
from tribobem.geometry.shapes import sphere
from tribobem.output.checks import cell_self_compliance
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.tangential import solve_tangential

E_STAR = 1e9
FLAT = Material(E_STAR, 0.0, "flat")   # nu = 0 on a rigid counterface: E* = E


@dataclass(frozen=True)
class DepthLimited(BodyModel):
    """Normal compliance 2 tanh(q depth) / (E* q) (m/Pa); the normal block only."""

    name: ClassVar[str] = "depth_limited"
    depth: float = 1e-6

    def symbol(self, pair, key, qx, qy):
        if key != "zz":
            raise InputError("components", "the depth-limited test body has a normal block only")
        q = np.sqrt(qx * qx + qy * qy)
        return 2.0 * np.tanh(q * self.depth) / (pair.effective_modulus * q)


@dataclass(frozen=True)
class Scaled(BodyModel):
    """The half-space with every compliance times ``factor``."""

    name: ClassVar[str] = "scaled"
    factor: float = 2.0

    def periodic_spectra(self, pair, grid, components, kernel="spectral", n_alias=8):
        base = HalfSpace().periodic_spectra(pair, grid, components, kernel, n_alias)
        return {k: self.factor * v for k, v in base.items()}

    def influence_coefficients(self, pair, key, xc, yc):
        return self.factor * lattice_coefficients(key, pair, xc, yc)


@pytest.fixture(autouse=True)
def registered():
    register_body_model(DepthLimited)
    register_body_model(Scaled)
    yield
    unregister_body_model("depth_limited")
    unregister_body_model("scaled")


def _q(grid):
    qx = 2.0 * np.pi * np.fft.fftfreq(grid.nx, grid.dx)[:, None]
    qy = 2.0 * np.pi * np.fft.rfftfreq(grid.ny, grid.dy)[None, :]
    return np.sqrt(qx**2 + qy**2)


# -- the registry and the pair ---------------------------------------------------------------

def test_registry_builds_models_by_name():
    assert BODY_MODELS["halfspace"] is HalfSpace
    assert body_model("halfspace") == HalfSpace()
    assert body_model("depth_limited", depth=3e-6) == DepthLimited(3e-6)
    with pytest.raises(InputError, match="body_model"):
        body_model("no_such_body")

    @dataclass(frozen=True)
    class Impostor(BodyModel):
        name: ClassVar[str] = "scaled"

    with pytest.raises(ValueError, match="already registered"):
        register_body_model(Impostor)
    with pytest.raises(ValueError):
        unregister_body_model("halfspace")


def test_pair_carries_its_model():
    plain = ContactPair(FLAT, Material.rigid())
    assert plain.model is None and body_model_of(plain) is DEFAULT_BODY_MODEL
    grid = Grid(8, 8, 1e-6, 1e-6, periodic=True)
    assert make_operator(grid, plain).body_model is DEFAULT_BODY_MODEL
    layered = ContactPair(FLAT, Material.rigid(), model=DepthLimited(2e-6))
    assert body_model_of(layered) == DepthLimited(2e-6)
    assert layered.effective_modulus == plain.effective_modulus  # the materials are unchanged
    with pytest.raises(InputError, match="bodies.model"):
        make_operator(grid, ContactPair(FLAT, Material.rigid(), model="depth_limited"))


# -- a q-dependent body on a periodic grid ---------------------------------------------------

def test_depth_limited_spectrum_is_its_own():
    grid = Grid(32, 16, 1e-5, 5e-6, periodic=True)
    depth = 1e-6
    pair = ContactPair(FLAT, Material.rigid(), model=DepthLimited(depth))
    op = make_operator(grid, pair)
    assert "depth_limited" in op.kind and op.body_model == DepthLimited(depth)
    q = _q(grid)
    q[0, 0] = 1.0
    ref = 2.0 * np.tanh(q * depth) / (E_STAR * q)
    ref[0, 0] = 0.0
    np.testing.assert_allclose(op.spectrum(), ref, rtol=1e-14, atol=0.0)
    half = make_operator(grid, ContactPair(FLAT, Material.rigid()))
    assert not np.allclose(op.spectrum()[1:4, 0], half.spectrum()[1:4, 0], rtol=1e-3, atol=0.0)
    # the body supplies no free-boundary coefficients: a free grid is refused
    with pytest.raises(InputError, match="periodic grid"):
        free_boundary_operator(Grid(16, 16, 1e-5, 1e-5), pair)
    with pytest.raises(InputError, match="periodic grid"):
        cell_self_compliance(grid.dx, grid.dy, pair=pair)


@pytest.mark.parametrize("method", ["normcg", "polonsky_keer"])
def test_depth_limited_full_contact_sinusoid_is_analytic(method):
    """Full contact of the gap a cos(q0 x): p = p_mean - (a / K(q0)) cos(q0 x), with the body's
    own K(q0) = 2 tanh(q0 d) / (E* q0) (q0 d = 1: 0.76 of the half-space's compliance)."""
    lam, a = 1e-5, 1e-8
    grid = Grid(32, 4, lam, lam * 4 / 32, periodic=True)
    q0 = 2.0 * np.pi / lam
    depth = 1.0 / q0
    pair = ContactPair(FLAT, Material.rigid(), model=DepthLimited(depth))
    op = periodic_operator(grid, pair)
    X, _ = grid.meshgrid()
    h = a * np.cos(q0 * X)
    amplitude = a * E_STAR * q0 / (2.0 * np.tanh(q0 * depth))
    p_mean = 2.0 * amplitude
    res = solve_normal(op, h - h.min(), force=p_mean * grid.lx * grid.ly, tol=1e-12, method=method)
    assert res.converged, res.message
    assert bool(np.asarray(res.contact).all())
    np.testing.assert_allclose(res.pressure, p_mean - amplitude * np.cos(q0 * X), rtol=0.0, atol=1e-9 * amplitude)
    # the half-space's amplitude would be tanh(1) = 0.76 of this one
    assert amplitude * np.tanh(1.0) == pytest.approx(a * E_STAR * q0 / 2.0, rel=1e-14)


def test_deep_body_is_the_half_space():
    """At q d >= 1e3 tanh is 1 to the last bit: the base class's spectra (both kernels) and
    Polonsky-Keer's box preconditioner reproduce the half-space's, and so does a partial rough
    contact solved with them."""
    n, L = 64, 1e-4
    grid = Grid.square(n, L, periodic=True)
    deep = DepthLimited(depth=1e3 * L)
    half_pair = ContactPair(FLAT, Material.rigid())
    deep_pair = ContactPair(FLAT, Material.rigid(), model=deep)
    for kernel in ("spectral", "influence"):
        ref = HalfSpace().periodic_spectra(half_pair, grid, ("z",), kernel)["zz"]
        got = deep.periodic_spectra(deep_pair, grid, ("z",), kernel)["zz"]
        np.testing.assert_allclose(got, ref, rtol=1e-13, atol=0.0)
    M = deep.preconditioner_stiffness(deep_pair, (24, 20), grid.dx, grid.dy)
    np.testing.assert_allclose(M, 0.5 * E_STAR * HalfSpace().preconditioner_stiffness(half_pair, (24, 20),
                                                                                      grid.dx, grid.dy), rtol=1e-13)
    # a bump in the cell: a small contact, so that Polonsky-Keer's settled phase uses the box
    X, Y = grid.meshgrid()
    h = (X**2 + Y**2) / (2 * 1e-3)
    F = 0.2 * E_STAR * (0.05 * L) ** 2
    results = {}
    for name, pair in (("half", half_pair), ("deep", deep_pair)):
        op = periodic_operator(grid, pair)
        res = solve_normal(op, h, force=F, tol=1e-12, method="polonsky_keer")
        assert res.converged, res.message
        results[name] = (res, op)
    (rh, _), (rd, opd) = results["half"], results["deep"]
    assert opd.cache.stiffness_box_spectra, "the box preconditioner of the body model was not used"
    np.testing.assert_array_equal(np.asarray(rd.contact), np.asarray(rh.contact))
    np.testing.assert_allclose(rd.pressure, rh.pressure, rtol=0.0, atol=1e-9 * float(rh.pressure.max()))
    assert rd.approach == pytest.approx(rh.approach, rel=1e-9)


# -- a body with real-space coefficients: the free boundary ----------------------------------

def test_scaled_body_on_a_free_boundary_is_the_softer_half_space():
    """K -> c K is the half-space of modulus E*/c: the same Hertz contact under the same force."""
    c = 2.5
    grid = Grid.square(64, 8e-6)
    h = sphere(grid, 1e-3)
    F = 1e-4
    scaled = free_boundary_operator(grid, ContactPair(FLAT, Material.rigid(), model=Scaled(c)))
    softer = free_boundary_operator(grid, ContactPair(Material(E_STAR / c, 0.0), Material.rigid()))
    np.testing.assert_allclose(scaled.spectrum(), softer.spectrum(), rtol=1e-13, atol=0.0)
    rs = solve_normal(scaled, h, force=F, tol=1e-12)
    rr = solve_normal(softer, h, force=F, tol=1e-12)
    assert rs.converged and rr.converged
    np.testing.assert_array_equal(np.asarray(rs.contact), np.asarray(rr.contact))
    np.testing.assert_allclose(rs.pressure, rr.pressure, rtol=0.0, atol=1e-9 * float(rr.pressure.max()))
    # the default self-compliance, from the body's own coefficients
    pair = ContactPair(FLAT, Material.rigid(), model=Scaled(c))
    assert cell_self_compliance(grid.dx, grid.dy, pair=pair) == pytest.approx(
        c * cell_self_compliance(grid.dx, grid.dy, E_STAR), rel=1e-13)


def test_scaled_body_partial_slip_is_the_softer_half_space():
    """All nine blocks scale with 1/G at a fixed nu: Scaled(c) on (E, nu) is the half-space
    (E/c, nu), coupling included; TangCG (FFT preconditioner, box convolutions) agrees."""
    c, nu, mu = 2.0, 0.3, 0.3
    grid = Grid.square(48, 8e-6)
    h = sphere(grid, 1e-3)
    F = 1e-4
    body = Material(E_STAR, nu)
    runs = []
    for pair in (ContactPair(body, Material.rigid(), model=Scaled(c)),
                 ContactPair(Material(E_STAR / c, nu), Material.rigid())):
        op = free_boundary_operator(grid, pair, ("x", "y", "z"))
        nr = solve_normal(op, h, force=F, tol=1e-12)
        tr = solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=mu, force=(0.5 * mu * F, 0.0),
                              preconditioner="fft", tol=1e-10)
        assert nr.converged and tr.converged, tr.message
        assert tr.info["preconditioner_convolutions"] > 0
        runs.append((nr, tr))
    (ns, ts), (nh, th) = runs
    np.testing.assert_array_equal(np.asarray(ns.contact), np.asarray(nh.contact))
    np.testing.assert_array_equal(np.asarray(ts.stick), np.asarray(th.stick))
    qscale = mu * float(nh.pressure.max())
    assert np.abs(np.asarray(ts.shear) - np.asarray(th.shear)).max() < 1e-7 * qscale
    assert ts.displacement_x == pytest.approx(th.displacement_x, rel=1e-7)


# -- the half-space: the model path is the old one, bit for bit ------------------------------

def test_half_space_self_compliance_paths_agree_bitwise():
    pair = ContactPair(Material(73e9, 0.17), Material(130e9, 0.28))
    for dx, dy in ((1e-7, 1e-7), (2e-7, 0.5e-7)):
        old = cell_self_compliance(dx, dy, pair.effective_modulus)
        assert cell_self_compliance(dx, dy, pair=pair) == old
        assert halfspace_self_compliance(dx, dy, pair.effective_modulus) == old
        assert HalfSpace().self_compliance(pair, dx, dy) == old


def test_cohesive_edge_band_takes_the_body_models_self_compliance():
    """The grid-band check of a Dugdale state: the pair path equals the E* path for the half-space
    and uses the model's own self-compliance for another body (gap band sigma0 C, C times c)."""
    import dataclasses

    from tribobem.output.checks import cohesive_edge_band
    from tribobem.validation import maugis_dugdale_problem

    prob = maugis_dugdale_problem(1.0, n=64)
    ad, op = prob.adhesion, prob.operator
    r = solve_normal(op, prob.gap, force=0.0, interaction=ad, tol=1e-10)
    old = cohesive_edge_band([r], ad, op.pair.effective_modulus)
    assert old is not None
    assert cohesive_edge_band([r], ad, None, pair=op.pair) == old
    scaled = cohesive_edge_band([r], ad, None, pair=dataclasses.replace(op.pair, model=Scaled(3.0)))
    assert scaled["gap_band"] == pytest.approx(3.0 * old["gap_band"], rel=1e-13)
