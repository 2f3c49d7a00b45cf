"""Exponential adhesion with a hard wall: the law, its solutions, and the references.

References: the rigid sphere's exact force -2 pi R w exp(-D / rho) (a paraboloid over the
plane), the DMT limit -2 pi R w of the elastic sphere's pull-off at small Tabor parameter,
Tamaas's ExponentialAdhesionFunctional on the same periodic rough problem (where Tamaas is
installed), and the conditions of the law checked on the solved fields.
"""

import math
import warnings

import numpy as np
import pytest

from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.elasticity.bodies.halfspace import halfspace_self_compliance
from tribobem.geometry import self_affine_surface, sphere
from tribobem.grid import Grid
from tribobem.interactions.exponential import ExponentialAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.scenario.schema import ExponentialAdhesionSpec
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.normal_paths import pull_off
from tribobem.validation.common import PAIR


def test_the_law_integrates_to_the_work_of_adhesion():
    law = ExponentialAdhesion(0.05, 2.071e-9)
    g = np.linspace(0.0, 60 * law.rho, 600001)
    s = law.outside_stress(g, np)
    assert -float(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(g))) == pytest.approx(0.05, rel=1e-6)
    assert law.floor == pytest.approx(-0.05 / 2.071e-9, rel=1e-12) == float(s[0])
    # an overlapping node takes the wall's value (no overflow of exp(-g / rho))
    with np.errstate(over="raise"):
        assert float(law.outside_stress(np.array([-1e-6]), np)[0]) == law.floor
    assert law.adhesive_mask(np.array([0.5, 1.5]) * law.rho, np).tolist() == [True, False]
    with pytest.raises(ValueError, match="rho"):
        ExponentialAdhesion(0.05, 0.0)
    with pytest.raises(ValueError, match="required with model = 'exponential'"):
        ExponentialAdhesionSpec(work_of_adhesion=0.05)


def test_a_stiff_sphere_pulls_with_minus_2_pi_R_w_exp_minus_D_over_rho():
    R, rho, w = 2.5e-6, 0.3e-9, 0.05
    half = math.sqrt(2 * R * rho * 14)  # gap 14 rho at the edge: exp(-14) of the peak
    grid = Grid.square(128, 2 * half)
    stiff = ContactPair(Material(1e16, 0.2), Material.rigid())
    op = free_boundary_operator(grid, stiff)
    law = ExponentialAdhesion(w, rho)
    for D in (0.5 * rho, 2 * rho):
        r = solve_normal(op, sphere(grid, R), approach=-D, interaction=law, tol=1e-12)
        assert r.converged and not r.contact.any()
        assert r.force == pytest.approx(-2 * math.pi * R * w * math.exp(-D / rho), rel=1e-3)


def test_the_elastic_sphere_pull_off_tends_to_dmt_at_small_tabor_parameter():
    E = PAIR.effective_modulus
    R, rho = 2.5e-6, 0.3e-9
    law = ExponentialAdhesion.from_tabor(0.01, R, E, rho)
    assert law.tabor_parameter(R, E) == pytest.approx(0.01, rel=1e-12)
    grid = Grid.square(128, 2 * math.sqrt(2 * R * rho * 12))
    op = free_boundary_operator(grid, PAIR)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        po = pull_off(op, sphere(grid, R), law, preload=math.pi * R * law.work_of_adhesion, n_steps=40, refine=16)
    dmt = -2 * math.pi * R * law.work_of_adhesion
    assert po.force == pytest.approx(dmt, rel=0.015)
    # the JKR limit is -1.5 pi R w: a Tabor parameter of 0.3 is already on its way there
    law3 = ExponentialAdhesion.from_tabor(0.3, R, E, rho)
    grid3 = Grid.square(128, 2 * math.sqrt(2 * R * rho * 12))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        po3 = pull_off(free_boundary_operator(grid3, PAIR), sphere(grid3, R), law3,
                       preload=math.pi * R * law3.work_of_adhesion, n_steps=40, refine=16)
    ratio = po3.force / (math.pi * R * law3.work_of_adhesion)
    assert -2.0 < ratio < -1.5 and ratio > po.force / (math.pi * R * law.work_of_adhesion) + 0.05


def _rough_problem(n=128):
    grid = Grid.square(n, 1.0, periodic=True)
    z = self_affine_surface(grid, hurst=0.8, rms_slope=1.0, short_cutoff=4 * grid.dx, long_cutoff=0.25, seed=7)
    pair = ContactPair(Material(1.0, 0.3), Material.rigid())
    rms = float(z.std())
    rho = 0.1 * rms
    law = ExponentialAdhesion(0.05 * pair.effective_modulus * rho, rho)
    return grid, z, pair, law, rms


def test_both_solvers_reach_the_law_s_equilibrium_on_a_periodic_rough_surface():
    grid, z, pair, law, rms = _rough_problem()
    op = periodic_operator(grid, pair)
    h = z.max() - z
    delta = float(z.max() - z.mean()) - 2.0 * rms
    out = {}
    for m in ("polonsky_keer", "normcg"):
        r = solve_normal(op, h, approach=delta, interaction=law, tol=1e-10, method=m)
        assert r.converged, m
        # the conditions, on the solver's own fields recomputed from the pressure
        g = h + op.apply(r.pressure) - delta
        free = ~r.contact
        assert float(np.abs(g[r.contact]).max()) < 1e-8 * rms
        assert float(g[free].min()) > 0
        assert float(np.abs(r.pressure[free] - law.outside_stress(g[free], np)).max()) < 1e-6 * law.peak_stress
        assert float(r.pressure[r.contact].min()) > law.floor
        out[m] = r
    a, b = out["polonsky_keer"], out["normcg"]
    assert np.array_equal(a.contact, b.contact)
    assert b.force == pytest.approx(a.force, rel=1e-7)
    assert a.adhesive_area > 0 and a.adhesive_area < grid.area


def test_the_cell_ratio_is_c_w_over_rho_squared():
    law = ExponentialAdhesion(0.05, 2.071e-9)
    c = halfspace_self_compliance(1e-9, 1e-9, 25e6)
    assert law.cell_ratio(c) == pytest.approx(c * 0.05 / 2.071e-9**2, rel=1e-12)


def test_matches_tamaas_exponential_functional():
    tm = pytest.importorskip("tamaas")
    grid, z, pair, law, rms = _rough_problem()
    n = grid.nx
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], [n, n])
    model.E, model.nu = 1.0, 0.3
    solver = tm.PolonskyKeerRey(model, z, 1e-10, tm.PolonskyKeerRey.gap, tm.PolonskyKeerRey.gap)
    functional = tm.ExponentialAdhesionFunctional(z)
    functional.parameters = {"rho": law.rho, "surface_energy": law.work_of_adhesion}
    solver.addFunctionalTerm(functional)
    solver.max_iter = 20000
    solver.solve(2.0 * rms)
    p_t = np.array(model.traction, dtype=float).reshape(n, n)
    g_t = np.array(model.displacement, dtype=float).reshape(n, n) - z
    F_t = float(p_t.sum()) * grid.cell_area
    A_t = float(np.count_nonzero(g_t <= 1e-8 * law.rho)) * grid.cell_area
    op = periodic_operator(grid, pair)
    h = z.max() - z
    r = solve_normal(op, h, approach=float(z.max() - z.mean()) - 2.0 * rms, interaction=law, tol=1e-10)
    assert r.converged
    assert r.force == pytest.approx(F_t, rel=1e-3)
    assert r.contact_area == pytest.approx(A_t, rel=1e-3)


def test_lennard_jones_9_3_law_work_peak_and_dmt_pull_off():
    """The 9-3 law with its hard wall at D = z0: work dgamma, peak = Dugdale's sigma0 at
    D = 3^(1/6) z0, and the DMT pull-off -2 pi R dgamma of a nearly rigid sphere."""
    from tribobem.interactions.dugdale import DugdaleAdhesion
    from tribobem.interactions.lennard_jones import LennardJonesAdhesion

    law = LennardJonesAdhesion(0.05, 0.3e-9)
    g = np.linspace(0.0, 2000 * law.z0, 4000001)
    s = law.outside_stress(g, np)
    assert float(s[0]) == 0.0 == law.floor
    assert -float(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(g))) == pytest.approx(0.05, rel=1e-5)
    k = int(np.argmin(s))
    assert -float(s[k]) == pytest.approx(DugdaleAdhesion(0.05, 0.3e-9).sigma0, rel=1e-6)
    assert g[k] == pytest.approx((3 ** (1 / 6) - 1) * law.z0, rel=1e-3)
    num = np.diff(s) / np.diff(g)
    mid = 0.5 * (g[1:] + g[:-1])
    assert np.allclose(num[:1000], law.outside_slope(mid[:1000], np), rtol=1e-4, atol=1e-6 * float(np.abs(num).max()))
    # a stiff sphere at contact: the force is 2 pi R times the work from g = 0: -2 pi R dgamma
    R = 2.5e-6
    half = math.sqrt(2 * R * law.z0 * 400)
    grid = Grid.square(256, 2 * half)
    stiff = ContactPair(Material(1e16, 0.2), Material.rigid())
    r = solve_normal(free_boundary_operator(grid, stiff), sphere(grid, R), approach=0.0, interaction=law, tol=1e-12)
    assert r.converged
    assert r.force == pytest.approx(-2 * math.pi * R * 0.05, rel=0.01)
