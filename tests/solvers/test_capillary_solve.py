"""The capillary stress law, the self-consistent capillary solve and the sphere-flat reference."""

import math

import numpy as np
import pytest

from tribobem.analytic.capillary import sphere_flat_capillary, sphere_flat_island_force
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.errors import ConvergenceError, ConvergenceWarning, InputError
from tribobem.geometry.rough import gaussian_surface
from tribobem.geometry.shapes import sphere
from tribobem.grid import Grid
from tribobem.interactions.capillary import CapillaryInteraction
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.interactions.menisci import Islands, contribution_coefficient, meniscus_islands
from tribobem.interactions.van_der_waals import VanDerWaals, air_gap_stress, combine_hamaker
from tribobem.materials import ContactPair, Material
from tribobem.solvers.capillary import island_fixed_point, solve_capillary

GAMMA, VM, RG, T = 0.0725, 18.05e-6, 8.314462618, 295.0
A_SIO2, A_SI, A_W = 6.5e-20, 19e-20, 3.7e-20
SIO2_FILM = {0.3: 0.80e-9, 0.4: 0.95e-9, 0.5: 1.05e-9, 0.6: 1.20e-9, 0.7: 1.35e-9, 0.9: 2.0e-9}  # the shipped SiO2 table


def kelvin(rh):
    return GAMMA * VM / (RG * T * math.log(rh)) if rh < 1 else -math.inf


def laplace(rh):
    return RG * T * math.log(rh) / VM


def rigid_sphere(R, n, size):
    grid = Grid.square(n, size)
    h = sphere(grid, R, exact=True)
    return grid, h


# ----------------------------------------------------------------------------- analytic reference
def test_analytic_meniscus_solves_kelvin_and_the_geometry():
    R, rh, t1, t2 = 1e-6, 0.6, 1.2e-9, 0.7e-9
    s = sphere_flat_capillary(R, kelvin(rh), laplace(rh), film_ball=t1, film_flat=t2)
    assert 1 / s.neck_radius - 1 / s.meridional_radius == pytest.approx(1 / kelvin(rh), rel=1e-10)
    # The meridian circle touches the flat's film (centre at t2 + r1) and the sphere's film
    # (centre at distance R + t1 + r1 from the sphere's centre (0, R)), at angle phi.
    phi, r1 = s.filling_angle, s.meridional_radius
    xc = (R + t1 + r1) * math.sin(phi)
    zc = R - (R + t1 + r1) * math.cos(phi)
    assert zc == pytest.approx(t2 + r1, rel=1e-9)
    assert math.hypot(xc, zc - R) == pytest.approx(R + t1 + r1, rel=1e-12)
    assert s.force == pytest.approx(math.pi * (R * math.sin(phi)) ** 2 * laplace(rh), rel=1e-14)


def test_analytic_large_sphere_without_films_is_4_pi_R_gamma():
    """r_k << R, no films, zero contact angle: F -> -4 pi R gamma (Israelachvili), the first-order
    correction being the neck curvature, |r_k| / r2 with r2 ~ sqrt(4 R |r_k|)."""
    rk = abs(kelvin(0.5))
    errs = []
    for R in (1e-5, 1e-4, 1e-3):
        s = sphere_flat_capillary(R, kelvin(0.5), laplace(0.5))
        err = abs(s.force / (-4 * math.pi * R * GAMMA) - 1)
        assert 0.5 < err / (rk / math.sqrt(4 * R * rk)) < 2
        errs.append(err)
    assert errs[2] < errs[1] < errs[0] < 0.01


def test_analytic_island_rule_and_limits():
    R, rh, e = 1e-6, 0.7, 1.35e-9
    S = 2 * abs(kelvin(rh)) + 2 * e
    assert sphere_flat_island_force(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e) == \
        pytest.approx(math.pi * (2 * R * S - S * S) * laplace(rh), rel=1e-14)
    assert sphere_flat_island_force(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e, exact=False) == \
        pytest.approx(math.pi * 2 * R * S * laplace(rh), rel=1e-14)
    # The island rule overestimates the toroidal meniscus by the neck curvature: ~1 % at 0.7, more near 1.
    ref = sphere_flat_capillary(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e).force
    assert 0 < sphere_flat_island_force(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e) / ref - 1 < 0.02
    assert sphere_flat_capillary(R, -math.inf, 0.0).force == 0.0
    with pytest.raises(InputError):
        sphere_flat_capillary(R, kelvin(0.5), 0.0)  # r_k finite with dP = 0
    with pytest.raises(InputError):
        sphere_flat_capillary(R, -kelvin(0.5), laplace(0.5))  # positive r_k
    with pytest.raises(InputError):
        sphere_flat_capillary(10e-9, kelvin(0.999), laplace(0.999), film_flat=2e-9)  # meniscus past the equator


# ----------------------------------------------------------------------------- the stress law
def test_law_precedence_floor_and_continuity():
    n = 8
    active = np.zeros((n, n), bool)
    active[:, :4] = True
    e1, e2 = 0.5e-9, 0.3e-9
    ad = DugdaleAdhesion(0.2, 0.3e-9)   # sigma0 = 684 MPa, larger than the meniscus law below
    vdw = VanDerWaals(A_SIO2, A_SI, A_W, cutoff=0.2e-9)
    dp = laplace(0.5)
    law = CapillaryInteraction(active, e1, e2, dp, adhesion=ad, van_der_waals=vdw)
    g = np.full((n, n), 3e-9)
    g[0, :] = 0.1e-9  # Dugdale zone everywhere on this row
    s = law.outside_stress(g)
    assert np.all(s[0] == -ad.sigma0)
    a1w2 = combine_hamaker(A_SIO2, A_SI, A_W)
    np.testing.assert_allclose(s[1:, :4], dp - a1w2 / (6 * math.pi * 3e-9**3), rtol=1e-14)
    np.testing.assert_allclose(s[1:, 4:], air_gap_stress(3e-9, e1, e2, A_SIO2, A_SI, A_W), rtol=1e-14)
    # Flat (solver) and grid-shaped gaps give the same law.
    np.testing.assert_array_equal(law.outside_stress(g.ravel()), s.ravel())
    assert law.floor == -ad.sigma0
    assert not law.outside_branch(g.ravel())[n:].any() and law.outside_branch(g.ravel())[:n].all()
    # Without Dugdale: floor = the island law at zero gap (dP + water-filled term at the cut-off).
    law2 = CapillaryInteraction(active, e1, e2, dp, van_der_waals=vdw)
    assert law2.floor == pytest.approx(dp - a1w2 / (6 * math.pi * 0.2e-9**3), rel=1e-14)
    assert law2.outside_stress(np.zeros((n, n)))[0, 0] == pytest.approx(law2.floor, rel=1e-14)
    # Without van der Waals: dP in the islands, nothing outside.
    law3 = CapillaryInteraction(active, e1, e2, dp)
    s3 = law3.outside_stress(g)
    assert np.all(s3[:, :4] == dp) and np.all(s3[:, 4:] == 0)


def test_law_edge_ramp_when_the_meniscus_pulls_harder_than_sigma0():
    """|dP + water term| > sigma0 beyond h0 would make the law jump to MORE tension when the gap
    opens (no discrete equilibrium at the edge): a ramp over edge_width h0 makes it continuous."""
    active = np.ones((4, 4), bool)
    ad = DugdaleAdhesion(0.05, 0.3e-9)  # sigma0 = 171 MPa
    dp = laplace(0.15)  # -257 MPa
    law = CapillaryInteraction(active, 0.0, 0.0, dp, adhesion=ad, edge_width=0.05)
    h0 = ad.h0
    g = np.array([0.999 * h0, 1.0 * h0, 1.025 * h0, 1.05 * h0, 1.2 * h0]).reshape(5, 1) * np.ones((1, 4))
    law = CapillaryInteraction(np.ones(g.shape, bool), 0.0, 0.0, dp, adhesion=ad, edge_width=0.05)
    s = law.outside_stress(g)[:, 0]
    assert s[0] == -ad.sigma0 and s[1] == pytest.approx(-ad.sigma0)
    assert s[2] == pytest.approx(0.5 * (-ad.sigma0 + dp), rel=1e-12)
    assert s[3] == pytest.approx(dp) and s[4] == dp
    assert not law.outside_branch(g).any()  # one continuous piece
    # A monotone step (|dP| < sigma0) keeps the thesis' step and its branch.
    law_m = CapillaryInteraction(np.ones(g.shape, bool), 0.0, 0.0, laplace(0.6), adhesion=ad)
    assert law_m.outside_stress(g)[2, 0] == laplace(0.6)
    assert law_m.outside_branch(g)[0].all()


def test_interaction_bad_input():
    active = np.ones((4, 4), bool)
    with pytest.raises(InputError):
        CapillaryInteraction(active, 0.0, 0.0, 1e6)  # positive (compressive) capillary pressure
    with pytest.raises(InputError):
        CapillaryInteraction(active, -1e-9, 0.0, -1e6)
    with pytest.raises(InputError):
        CapillaryInteraction(active, np.zeros((3, 3)), 0.0, -1e6)
    with pytest.raises(InputError):
        CapillaryInteraction(active, 0.0, 0.0, -1e6, adhesion="dugdale")
    with pytest.raises(InputError):
        CapillaryInteraction(active, 0.0, 0.0, -1e6).outside_stress(np.ones(5))


# ----------------------------------------------------------------------------- rigid sphere on flat
@pytest.mark.parametrize("R, size", [(1e-6, 400e-9), (10e-6, 1.3e-6)])
def test_rigid_sphere_flat_against_a27_a29(R, size):
    """Paper B 4.1: rigid sphere touching a rigid flat, SiO2 films on both, no van der Waals:
    within 3 % of A.27-A.29 for RH 0.3-0.7 (measured <= 1.0 %), and within 0.5 % of the island
    rule's exact value (pure discretisation: 256^2, >= 40 cells across the meniscus)."""
    grid, h = rigid_sphere(R, 256, size)
    for rh in (0.3, 0.5, 0.7):
        e = SIO2_FILM[rh]
        r = solve_capillary(None, h, grid=grid, approach=float(h.min()), film1=e, film2=e,
                            kelvin_radius=kelvin(rh), capillary_pressure=laplace(rh), van_der_waals=False)
        ref = sphere_flat_capillary(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e).force
        isl = sphere_flat_island_force(R, kelvin(rh), laplace(rh), film_ball=e, film_flat=e)
        assert r.capillary_force == pytest.approx(ref, rel=0.03)
        assert r.capillary_force == pytest.approx(isl, rel=0.005)
        assert r.capillary_force == pytest.approx(laplace(rh) * r.wetted_area, rel=1e-12)
        assert r.island_count == 1 and r.converged and r.outer_iterations == 1
        assert r.solid_solid_force == 0 and r.water_solid_force == 0
        assert math.isnan(r.total_force) and math.isnan(r.repulsive_force)  # rigid contact: indeterminate


def test_rigid_apart_gives_the_total_force():
    """Not touching: no reaction, the total force is the sum of the outside stresses; a meniscus
    still forms across a film-to-film gap below d_cr."""
    grid, h = rigid_sphere(1e-6, 128, 400e-9)
    e = 1.05e-9
    r = solve_capillary(None, h, grid=grid, approach=float(h.min()) - 2.5e-9, film1=e, film2=e,
                        kelvin_radius=kelvin(0.5), capillary_pressure=laplace(0.5), hamaker=(A_SIO2, A_SIO2))
    assert not r.normal.contact.any() and r.island_count == 1  # 2.5 - 2.1 = 0.4 nm < d_cr
    assert r.total_force == pytest.approx(float(r.normal.pressure.sum()) * grid.cell_area, rel=1e-12)
    assert r.total_force == pytest.approx(r.capillary_force + r.water_solid_force, rel=1e-12)
    assert r.repulsive_force == 0.0
    # Farther: the films no longer come within d_cr, no meniscus; only the air-gap term pulls.
    r = solve_capillary(None, h, grid=grid, approach=float(h.min()) - 4e-9, film1=e, film2=e,
                        kelvin_radius=kelvin(0.5), capillary_pressure=laplace(0.5))
    assert r.island_count == 0 and r.capillary_force == 0 and r.water_solid_force < 0


# ----------------------------------------------------------------------------- elastic solves
PAIR = ContactPair(Material(73e9, 0.17), Material.rigid())


@pytest.fixture(scope="module")
def sphere128():
    grid = Grid.square(128, 400e-9)
    return free_boundary_operator(grid, PAIR), sphere(grid, 1e-6)


def test_stiff_flat_matches_the_rigid_bodies():
    grid = Grid.square(128, 400e-9)
    h = sphere(grid, 1e-6)
    op = free_boundary_operator(grid, ContactPair(Material(1e15, 0.2), Material.rigid()))
    kw = dict(film1=1.2e-9, film2=1.2e-9, kelvin_radius=kelvin(0.6), capillary_pressure=laplace(0.6),
              van_der_waals=False, approach=float(h.min()))
    stiff = solve_capillary(op, h, **kw)
    rigid = solve_capillary(None, h, grid=grid, **kw)
    assert stiff.converged
    np.testing.assert_array_equal(stiff.islands.active, rigid.islands.active)
    assert stiff.capillary_force == pytest.approx(rigid.capillary_force, rel=1e-12)
    assert np.isfinite(stiff.total_force)  # the elastic contact carries a definite reaction


@pytest.mark.parametrize("adhesion", [None, DugdaleAdhesion(0.05, 0.3e-9)])
def test_elastic_sphere_force_split_and_self_consistency(sphere128, adhesion):
    op, h = sphere128
    F0 = 1e-6
    r = solve_capillary(op, h, normal_force=F0, film1=1.05e-9, film2=1.05e-9, kelvin_radius=kelvin(0.5),
                        capillary_pressure=laplace(0.5), adhesion=adhesion, hamaker=(A_SIO2, A_SIO2))
    assert r.converged and r.normal.converged
    # Force balance: every prescribed stress is subtracted, the parts add up to F0.
    assert r.total_force == pytest.approx(F0, rel=1e-9)
    assert r.contact_force + r.capillary_force + r.solid_solid_force + r.water_solid_force == pytest.approx(F0, rel=1e-9)
    assert r.capillary_force == pytest.approx(laplace(0.5) * r.wetted_area, rel=1e-12)
    assert r.capillary_force < 0 and r.water_solid_force < 0 and r.repulsive_force > F0
    assert (r.solid_solid_force < 0) == (adhesion is not None)
    # Self-consistent: the islands of the final gap are the ones the final solve used.
    again = meniscus_islands(r.normal.gap, 1.05e-9, 1.05e-9, kelvin(0.5), r.normal.contact, periodic=False)
    np.testing.assert_array_equal(again.active, r.islands.active)
    # The meniscus is (about) the disk the cut height gives on the deformed gap: F_cap near
    # the rigid island value (the load flattens the sphere a little).
    isl = sphere_flat_island_force(1e-6, kelvin(0.5), laplace(0.5), film_ball=1.05e-9, film_flat=1.05e-9, exact=False)
    assert r.capillary_force == pytest.approx(isl, rel=0.1)


def test_warm_start_reaches_the_same_state(sphere128):
    op, h = sphere128
    kw = dict(film1=1.05e-9, film2=1.05e-9, kelvin_radius=kelvin(0.5), capillary_pressure=laplace(0.5))
    cold = solve_capillary(op, h, normal_force=1e-6, **kw)
    warm = solve_capillary(op, h, normal_force=1e-6, initial=cold, **kw)
    assert warm.outer_iterations == 1 and warm.converged
    assert warm.capillary_force == pytest.approx(cold.capillary_force, rel=1e-12)
    assert warm.normal.iterations < cold.normal.iterations


def test_contribution_scales_the_capillary_pressure(sphere128):
    op, h = sphere128
    c = contribution_coefficient(0.35)
    r = solve_capillary(op, h, normal_force=1e-6, film1=0.9e-9, film2=0.6e-9, kelvin_radius=kelvin(0.35),
                        capillary_pressure=laplace(0.35), contribution=c, van_der_waals=False)
    assert r.capillary_pressure == pytest.approx(c * laplace(0.35), rel=1e-14)
    assert r.capillary_force == pytest.approx(c * laplace(0.35) * r.wetted_area, rel=1e-12)


def test_meniscus_stronger_than_sigma0_converges(sphere128):
    """RH 0.15 (dP = -257 MPa) against sigma0 = 171 MPa and Si/water/Si van der Waals: the
    Dugdale edge needs the ramp; the solve converges and balances the force."""
    op, h = sphere128
    r = solve_capillary(op, h, normal_force=0.5e-6, film1=0.3e-9, film2=0.3e-9, kelvin_radius=kelvin(0.15),
                        capillary_pressure=laplace(0.15), adhesion=DugdaleAdhesion(0.05, 0.3e-9),
                        hamaker=(A_SI, A_SI))
    assert r.converged
    assert r.total_force == pytest.approx(0.5e-6, rel=1e-9)


def test_rough_periodic_islands_grow_self_consistently():
    grid = Grid.square(128, 5e-6, periodic=True)
    z = gaussian_surface(grid, 5e-9, 0.1e-6, seed=2)
    h = z.max() - z
    op = periodic_operator(grid, ContactPair(Material(64e9, 0.17), Material.rigid()))
    r = solve_capillary(op, h, normal_force=100e-6, film1=2.0e-9, film2=0.0, kelvin_radius=kelvin(0.9),
                        capillary_pressure=laplace(0.9), adhesion=DugdaleAdhesion(0.05, 0.3e-9))
    assert r.converged and r.outer_iterations > 1
    assert r.history == sorted(r.history)  # the meniscus pull closes gaps: islands only grow here
    assert r.total_force == pytest.approx(100e-6, rel=1e-9)
    again = meniscus_islands(r.normal.gap, 2.0e-9, 0.0, kelvin(0.9), r.normal.contact, periodic=True)
    np.testing.assert_array_equal(again.active, r.islands.active)


def test_rh_one_floods_the_gap(sphere128):
    """RH = 1: no Laplace pressure; the one island covers the whole gap and carries only the
    water-filled van der Waals term."""
    op, h = sphere128
    r = solve_capillary(op, h, normal_force=1e-6, film1=2e-9, film2=2e-9, kelvin_radius=-math.inf,
                        capillary_pressure=0.0, hamaker=(A_SIO2, A_SIO2))
    assert r.converged and r.capillary_force == 0.0 and r.island_count == 1
    assert r.wetted_area == pytest.approx(h.size * op.grid.cell_area - r.contact_area, rel=1e-12)
    vdw = VanDerWaals(A_SIO2, A_SIO2, A_W)
    free = ~r.normal.contact
    ws = float(vdw.water_filled_stress(r.normal.gap[free]).sum()) * op.grid.cell_area
    assert r.water_solid_force == pytest.approx(ws, rel=1e-6)


# ----------------------------------------------------------------------------- reliability
def _fake_islands(tag):
    a = np.zeros((2, 2), bool)
    a.flat[tag] = True
    return Islands(labels=a.astype(int), active=a, count=1, active_count=1, cut_height=np.ones((2, 2)), seeds=a)


def test_island_fixed_point_detects_a_cycle():
    # A -> B -> C -> B: a mask seen before (not the last) comes back.
    nxt = {0: 1, 1: 2, 2: 1}

    def step(isl):
        tag = int(np.flatnonzero(isl.active)[0])
        return ("state", tag), _fake_islands(nxt[tag])

    state, used, outer, status, history = island_fixed_point(_fake_islands(0), step, 50)
    assert status == "cycle" and outer == 3 and state == ("state", 2)
    # A fixed point: B -> B.
    _, _, outer, status, _ = island_fixed_point(_fake_islands(1), lambda isl: (None, _fake_islands(1)), 50)
    assert status == "converged" and outer == 1


def test_unsettled_islands_are_flagged(sphere128):
    op, h = sphere128
    kw = dict(normal_force=1e-6, film1=1.05e-9, film2=1.05e-9, kelvin_radius=kelvin(0.9),
              capillary_pressure=laplace(0.9), max_outer=1)
    with pytest.warns(ConvergenceWarning, match="max_outer"):
        r = solve_capillary(op, h, **kw)
    assert not r.converged and "did not settle" in r.message
    with pytest.raises(ConvergenceError):
        solve_capillary(op, h, strict=True, **kw)


@pytest.mark.parametrize("kwargs, field", [
    (dict(normal_force=1e-6, approach=0.0), "load"),
    (dict(operator=None, normal_force=1e-6), "load"),
    (dict(operator=None, approach=0.0, grid=None), "grid"),
    (dict(capillary_pressure=1e6), "capillary_pressure"),
    (dict(capillary_pressure=0.0), "capillary_pressure"),
    (dict(contribution=1.5), "solve_capillary.contribution"),
    (dict(adhesion=0.05), "adhesion"),
    (dict(hamaker=(-1e-20, 1e-20)), "hamaker1"),
    (dict(hamaker=1e-20), "hamaker"),
    (dict(film1=np.zeros((3, 3))), "film1"),
    (dict(max_outer=0), "max_outer"),
])
def test_bad_input_is_named(sphere128, kwargs, field):
    op, h = sphere128
    args = dict(operator=op, gap=h, approach=0.0, film1=1e-9, film2=1e-9, kelvin_radius=kelvin(0.5),
                capillary_pressure=laplace(0.5), grid=op.grid)
    if "normal_force" in kwargs:
        args.pop("approach")
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        solve_capillary(args.pop("operator"), args.pop("gap"), **args)
    assert err.value.field == field


def test_validation_cases_registered_and_passing():
    from tribobem.validation import CASES, PHYSICS_CASES, run_validation

    names = ("sphere_flat_capillary", "capillary_force_balance", "capillary_force_balance_normcg",
             "thin_film_levelling")
    assert PHYSICS_CASES["capillary"] == names
    assert set(names) <= set(CASES)
    rows = run_validation(level="quick", physics=["capillary"])
    assert rows and all(r.passed for r in rows), [r for r in rows if not r.passed]
    info = [r for r in rows if math.isinf(r.tolerance)]
    assert info and all("RH 0.9" in r.quantity for r in info)  # the informational rows
