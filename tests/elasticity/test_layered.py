"""The coated half-space (elasticity/bodies/layered.py): limits, the half-space when the layer is
the substrate, reciprocity, finite elements, and the free-boundary coefficients against the
periodic symbol."""

import numpy as np
import pytest

from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.elasticity.bodies import CoatedHalfSpace, HalfSpace
from tribobem.elasticity.bodies.layered import layer_factors
from tribobem.elasticity.influence import lattice_coefficients
from tribobem.errors import InputError
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.solvers import solve_normal

SI = Material(130e9, 0.28)
SIO2 = Material(64e9, 0.17)


@pytest.mark.parametrize("ratio", [0.25, 1.0, 4.0])
def test_factor_limits_and_reciprocity(ratio):
    nl, ns = 0.2, 0.3
    f = layer_factors(np.array([1e-6, 1.0, 50.0]), nl, ns, ratio)
    assert f["zz"][0] == pytest.approx((1 - ns) / ratio, rel=1e-5)
    assert f["T"][0] == pytest.approx(1 / ratio, rel=1e-5)
    assert f["zz"][2] == pytest.approx(1 - nl, rel=1e-12)
    assert f["L"][2] == pytest.approx(1 - nl, rel=1e-12)
    assert np.allclose(f["zx"], -f["xz"], rtol=1e-10, atol=0)  # Betti
    assert np.allclose(f["xz"].real, 0) and f["xz"][2].imag == pytest.approx(0.5 * (1 - 2 * nl), rel=1e-12)


def test_rigid_substrate_stiffens():
    soft = layer_factors(np.array([0.5]), 0.3, 0.3, np.inf)
    free = layer_factors(np.array([0.5]), 0.3, 0.3, 1.0)
    assert 0 < soft["zz"][0] < free["zz"][0]


def test_layer_of_the_substrate_material_is_the_half_space():
    g = Grid(32, 32, 1e-6, 1e-6, periodic=True)
    for other in (Material.rigid(), Material(210e9, 0.3)):
        pair = ContactPair(SI, other)
        coated = ContactPair(SI, other, model=CoatedHalfSpace(1, SI.E, SI.nu, 40e-9))
        a = HalfSpace().periodic_spectra(pair, g, ("x", "y", "z"))
        b = CoatedHalfSpace(1, SI.E, SI.nu, 40e-9).periodic_spectra(coated, g, ("x", "y", "z"))
        for k, v in a.items():
            assert np.abs(b[k] - v).max() <= 1e-12 * np.abs(v).max(), k
    xc = (np.arange(-24, 25) - 0.5) * 10e-9
    pair = ContactPair(SI, Material.rigid())
    c = CoatedHalfSpace(1, SI.E, SI.nu, 40e-9).influence_coefficients(pair, "zz", xc, xc)
    assert np.abs(c - lattice_coefficients("zz", pair, xc, xc)).max() < 1e-9 * c.max()


def test_free_boundary_sphere_matches_the_periodic_symbol():
    """Two routes to the same kernel: the Hankel-transformed coefficients of the free grid and
    the symbol on a periodic cell four times wider (the cell's images are far)."""
    model = CoatedHalfSpace(1, SIO2.E, SIO2.nu, 40e-9)
    pair = ContactPair(SI, SIO2, model=model)
    n, L, R, F = 64, 0.2e-6, 2.5e-6, 1e-6
    free = Grid(n, n, L, L, periodic=False)
    x = (np.arange(n) - n / 2 + 0.5) * free.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    rf = solve_normal(free_boundary_operator(free, pair), (X ** 2 + Y ** 2) / (2 * R), force=F)
    per = Grid(4 * n, 4 * n, 4 * L, 4 * L, periodic=True)
    x = (np.arange(4 * n) - 2 * n + 0.5) * per.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    rp = solve_normal(periodic_operator(per, pair), (X ** 2 + Y ** 2) / (2 * R), force=F)
    assert rf.contact_area == pytest.approx(rp.contact_area, rel=0.01)
    assert rf.pressure.max() == pytest.approx(rp.pressure.max(), rel=2e-3)


def test_thin_layer_refused_on_a_coarse_free_grid():
    xc = (np.arange(-4, 5) - 0.5) * 100e-9
    with pytest.raises(InputError, match="thinner than half a cell"):
        CoatedHalfSpace(1, SIO2.E, SIO2.nu, 10e-9).influence_coefficients(ContactPair(SI, Material.rigid()), "zz",
                                                                           xc, xc)


def test_finite_elements_agree():
    pytest.importorskip("skfem")
    from tribobem.validation.layer_fem import fem_layer_compliance

    Gl = SIO2.shear_modulus
    f = layer_factors(np.array([1.0]), SIO2.nu, SI.nu, SI.shear_modulus / Gl)
    c = fem_layer_compliance(1.0, 1.0, (SIO2.E, SIO2.nu), (SI.E, SI.nu), "normal")
    assert c == pytest.approx(f["zz"][0] / Gl, rel=0.01)  # measured 0.15 %


def _partial_slip(layer, periodic):
    import tomllib
    import warnings
    from pathlib import Path

    from tribobem.scenario import parse_scenario, run_scenario

    ex = Path(__file__).resolve().parents[2] / "examples"
    d = tomllib.loads((ex / "partial_slip_auto.toml").read_text())
    d.pop("expected", None)
    d["grid"]["periodic"] = periodic
    if layer:
        d["body1"]["layer"] = layer
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_scenario(parse_scenario(d), outdir=None, progress=False, base_dir=ex)


@pytest.mark.slow  # (7 s; the free-vs-periodic block test covers the coated tangential operator)
def test_tangential_kinds_on_a_coated_periodic_cell():
    bare = _partial_slip(None, True)
    # a layer of the substrate's own material is the bare body
    same = _partial_slip({"E": "130 GPa", "nu": 0.3, "thickness": "20 nm"}, True)
    assert same.summary["static_friction_ratio"] == pytest.approx(bare.summary["static_friction_ratio"], rel=1e-9)
    soft = _partial_slip({"E": "64 GPa", "nu": 0.17, "thickness": "20 nm"}, True)
    assert soft.summary["converged"]
    assert soft.summary["static_friction_ratio"] != pytest.approx(bare.summary["static_friction_ratio"], rel=1e-3)
    free = _partial_slip({"E": "64 GPa", "nu": 0.17, "thickness": "20 nm"}, False)
    assert free.summary["converged"]


def test_free_boundary_tangential_blocks_converge_to_the_periodic_symbol():
    """The coated body's in-plane and coupling coefficients on a free grid against the periodic
    symbol on a cell M times wider: the difference is the periodic images' and falls as 1/M^2,
    as it does for the bare half-space's closed-form coefficients (measured coupling: 1.06e-2 at
    M = 8 against 5.8e-3 bare)."""
    model = CoatedHalfSpace(1, SIO2.E, SIO2.nu, 40e-9)
    pair = ContactPair(SI, SIO2, model=model)
    n, L, M = 32, 0.16e-6, 8
    gf = Grid(n, n, L, L, periodic=False)
    gp = Grid(M * n, M * n, M * L, M * L, periodic=True)
    x = (np.arange(n) - n / 2 + 0.5) * gf.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    load = np.sqrt(np.clip(1 - (np.hypot(X, Y) / 40e-9) ** 2, 0, None)) * 1e8
    of = free_boundary_operator(gf, pair, ("x", "y", "z"))
    op = periodic_operator(gp, pair, ("x", "y", "z"))
    s0 = (M * n - n) // 2
    for comp, tols in ((0, (3e-3, 3e-2, 3e-2)), (2, (3e-2, 3e-2, 3e-3))):
        tr = np.zeros((3, n, n))
        tr[comp] = load
        uf = of.apply(tr)
        trp = np.zeros((3, M * n, M * n))
        trp[:, s0:s0 + n, s0:s0 + n] = tr
        up = op.apply(trp)[:, s0:s0 + n, s0:s0 + n]
        for k, tol in zip((0, 1, 2), tols):
            if k == 1:
                continue
            df = uf[k] - uf[k][n // 2, n // 2]
            dp = up[k] - up[k][n // 2, n // 2]
            assert np.abs(df - dp).max() < tol * np.abs(dp).max(), (comp, k)
