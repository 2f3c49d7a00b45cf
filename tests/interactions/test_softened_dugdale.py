"""The softened Dugdale law: one equilibrium per node, the same state from either solver.

The criterion (tribobem.interactions.dugdale): a node under a fixed load from the others
solves g = g_ext + C s(g); with a ramp of width w = 3 sigma0 C the left side minus the right
increases with slope >= 2/3, so each g_ext has one g.  The step law has two for g_ext within
sigma0 C of h0.  The solver-agreement tests are those that failed with the step law: on the
Maugis-Dugdale sphere at lambda = 1 Polonsky-Keer and NormCG stopped 1-4 % apart in force.
"""

import warnings

import numpy as np
import pytest

from tribobem.elasticity import free_boundary_operator
from tribobem.elasticity.bodies.halfspace import halfspace_self_compliance
from tribobem.geometry import self_affine_surface
from tribobem.grid import Grid
from tribobem.interactions.dugdale import AUTO_MAX_WIDTH, SOFTENING, DugdaleAdhesion, SoftenedDugdale, build_dugdale
from tribobem.interactions.registry import LawContext
from tribobem.scenario.schema import DugdaleAdhesionSpec
from tribobem.solvers.normal import solve_normal
from tribobem.validation.adhesion import guduru_problem, maugis_dugdale_problem
from tribobem.validation.common import PAIR

LAW = DugdaleAdhesion(0.088, 0.3e-9)
C = halfspace_self_compliance(2e-9, 2e-9, PAIR.effective_modulus)


def _roots(law, g_ext, compliance):
    """Every gap g >= 0 with g = g_ext + C s(g) on a fine scan (sign changes)."""
    g = np.linspace(0.0, 3 * law.h0, 200001)
    f = g - g_ext - compliance * law.outside_stress(g, np)
    return int(np.count_nonzero(np.diff(np.sign(f)) != 0))


def test_width_is_twice_sigma0_times_the_cell_compliance():
    soft = SoftenedDugdale.for_cell(LAW.work_of_adhesion, LAW.z0, C)
    assert soft.width == pytest.approx(SOFTENING * LAW.sigma0 * C, rel=1e-12)
    assert soft.sigma0 == LAW.sigma0 and soft.h0 == LAW.h0
    assert soft.range == pytest.approx(LAW.h0 + soft.width / 2, rel=1e-12)
    with pytest.raises(ValueError, match="softening"):
        SoftenedDugdale.for_cell(LAW.work_of_adhesion, LAW.z0, C, softening=1.0)


@pytest.mark.parametrize("width_over_h0", [0.05, 0.6, 2.0, 5.0])
def test_the_ramp_keeps_the_work_of_adhesion(width_over_h0):
    law = SoftenedDugdale(LAW.work_of_adhesion, LAW.z0, width_over_h0 * LAW.h0)
    g = np.linspace(0.0, law.range * 1.01, 400001)
    s = law.outside_stress(g, np)
    work = -float(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(g)))
    assert work == pytest.approx(LAW.work_of_adhesion, rel=1e-5)
    assert float(s[0]) == pytest.approx(law.floor, rel=1e-12)
    # the slope never exceeds sigma0 / w (the triangle keeps it too)
    assert float(np.max(np.diff(s) / np.diff(g))) <= LAW.sigma0 / law.width * (1 + 1e-6)
    assert law.floor >= -LAW.sigma0 * (1 + 1e-12)


def test_one_root_per_node_where_the_step_has_two():
    soft = SoftenedDugdale.for_cell(LAW.work_of_adhesion, LAW.z0, C)
    jump = LAW.sigma0 * C
    two = 0
    for g_ext in LAW.h0 + np.linspace(-3 * jump, 3 * jump, 61):
        assert _roots(soft, g_ext, C) == 1
        two += _roots(LAW, g_ext, C) > 1
    # the step law is two-valued (a root on each piece) for g_ext in (h0, h0 + sigma0 C)
    assert two >= 8


def test_the_scenario_builds_the_softened_law_by_default_where_its_ramp_is_narrow():
    grid = Grid.square(64, 128e-9)
    ctx = LawContext(grid, PAIR.effective_modulus)
    spec = DugdaleAdhesionSpec(work_of_adhesion=0.088, z0=0.3e-9)
    assert spec.discretisation == "auto"
    law = build_dugdale(spec, ctx)
    assert isinstance(law, SoftenedDugdale)
    assert law.width == pytest.approx(3 * LAW.sigma0 * C, rel=1e-12)
    assert law.width <= AUTO_MAX_WIDTH * LAW.h0
    # a cell so coarse that the ramp would be wider than h0 / 5: auto keeps the step, softened does not
    coarse = LawContext(Grid.square(64, 64 * 12e-9), PAIR.effective_modulus)
    assert type(build_dugdale(spec, coarse)) is DugdaleAdhesion
    forced = build_dugdale(DugdaleAdhesionSpec(work_of_adhesion=0.088, z0=0.3e-9, discretisation="softened"), coarse)
    assert isinstance(forced, SoftenedDugdale) and forced.width > AUTO_MAX_WIDTH * LAW.h0
    step = build_dugdale(DugdaleAdhesionSpec(work_of_adhesion=0.088, z0=0.3e-9, discretisation="step"), ctx)
    assert type(step) is DugdaleAdhesion
    # rigid bodies: nothing deforms, the step law is single-valued
    assert type(build_dugdale(spec, LawContext(grid, None))) is DugdaleAdhesion
    with pytest.raises(ValueError, match="discretisation"):
        DugdaleAdhesionSpec(work_of_adhesion=0.088, z0=0.3e-9, discretisation="subcell")


def _both(op, gap, law, **load):
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for m in ("polonsky_keer", "normcg"):
            r = solve_normal(op, gap, interaction=law, tol=1e-10, method=m, max_iterations=20000, **load)
            assert r.converged, (m, r.message)
            out[m] = r
    return out["polonsky_keer"], out["normcg"]


def _same_state(a, b, rtol=1e-7):
    assert np.array_equal(a.contact, b.contact)
    assert np.array_equal(a.adhesive, b.adhesive)
    scale = float(np.abs(a.pressure).max())
    assert float(np.abs(a.pressure - b.pressure).max()) < rtol * scale
    assert b.force == pytest.approx(a.force, rel=rtol, abs=rtol * a.repulsive_force)
    assert b.repulsive_force == pytest.approx(a.repulsive_force, rel=rtol)


@pytest.mark.parametrize("n", [80, 160])
def test_polonsky_keer_and_normcg_agree_on_the_maugis_dugdale_sphere(n):
    prob = maugis_dugdale_problem(1.0, n=n, discretisation="softened")
    d = float(prob.reference(force=prob.F_scale).approach)
    pk, cg = _both(prob.operator, prob.gap, prob.law, approach=d)
    _same_state(pk, cg)
    # and from another start: NormCG warm-started from the step law's (different) equilibrium
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        step = solve_normal(prob.operator, prob.gap, approach=d, interaction=prob.adhesion, tol=1e-10,
                            method="normcg")
        warm = solve_normal(prob.operator, prob.gap, approach=d, interaction=prob.law, tol=1e-10,
                            method="normcg", initial_pressure=step)
    _same_state(pk, warm)
    # the step law's two solvers do not agree (the defect this law removes)
    pk0, cg0 = _both(prob.operator, prob.gap, prob.adhesion, approach=d)
    assert abs(cg0.repulsive_force / pk0.repulsive_force - 1) > 1e-3
    # and the softened state is Maugis-Dugdale's within 1 % on these coarse grids
    assert pk.force == pytest.approx(prob.F_scale, rel=0.01)


def test_polonsky_keer_and_normcg_agree_under_force_control():
    prob = maugis_dugdale_problem(2.0, n=160, discretisation="softened")
    pk, cg = _both(prob.operator, prob.gap, prob.law, force=0.0)
    _same_state(pk, cg, rtol=1e-6)
    assert pk.approach == pytest.approx(cg.approach, rel=1e-7, abs=1e-9 * prob.d_scale)


def test_polonsky_keer_and_normcg_agree_on_the_wavy_sphere():
    prob = guduru_problem(0.3, n=128, domain=5.0)
    soft = SoftenedDugdale.for_cell(prob.adhesion.work_of_adhesion, prob.adhesion.z0,
                                    halfspace_self_compliance(prob.grid.dx, prob.grid.dy,
                                                              PAIR.effective_modulus))
    pk, cg = _both(prob.operator, prob.gap, soft, approach=-0.5 * prob.D_unit)
    _same_state(pk, cg, rtol=1e-6)


def test_polonsky_keer_and_normcg_agree_on_a_rough_adhesive_contact():
    n, L = 128, 1e-6
    grid = Grid.square(n, L)
    z = self_affine_surface(grid, hurst=0.8, rms_height=2e-9, long_cutoff=L / 4, short_cutoff=L / 32, seed=3)
    R = 20e-6
    gap = grid.radius() ** 2 / (2 * R) + (z.max() - z)
    gap -= gap.min()
    op = free_boundary_operator(grid, PAIR)
    law = SoftenedDugdale.for_cell(0.1, 0.3e-9, halfspace_self_compliance(grid.dx, grid.dy, PAIR.effective_modulus))
    pk, cg = _both(op, gap, law, approach=3e-9)
    assert np.count_nonzero(pk.contact) > 20 and np.count_nonzero(pk.adhesive) > 20
    _same_state(pk, cg, rtol=1e-6)
