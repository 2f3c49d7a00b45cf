"""The hardness cap of the normal solvers (interactions/hardness.py, NormCG's upper bound).

References: Hertz below the cap (unchanged), the axisymmetric capped sphere
(analytic/capped_sphere.py, an independent box-constrained programme on rings), the
rigid-plastic limit A -> F / H, and the plastic history (idempotent, kept for later solves).
"""

import math

import numpy as np
import pytest

from tribobem.analytic.capped_sphere import capped_sphere
from tribobem.elasticity import free_boundary_operator, make_operator
from tribobem.errors import InputError
from tribobem.geometry.rough import self_affine_surface
from tribobem.grid import Grid
from tribobem.interactions import HardnessCap
from tribobem.materials import ContactPair, Material
from tribobem.solvers import solve_normal

PAIR = ContactPair(Material(100e9, 0.3), Material.rigid())
ES = PAIR.effective_modulus
R, F = 1e-3, 1.0
A = (3 * F * R / (4 * ES)) ** (1 / 3)
P0 = 3 * F / (2 * math.pi * A * A)


def _sphere(n, span=3.0):
    g = Grid(n, n, span * A, span * A, periodic=False)
    x = (np.arange(n) - n / 2 + 0.5) * g.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    return g, (X ** 2 + Y ** 2) / (2 * R), np.hypot(X, Y)


def test_hertz_unchanged_below_the_cap():
    g, h, _ = _sphere(64)
    op = free_boundary_operator(g, PAIR)
    free = solve_normal(op, h, force=F, tol=1e-10)
    capped = solve_normal(op, h, force=F, tol=1e-10, interaction=HardnessCap(1.2 * P0))
    assert capped.info["method"] == "normcg"
    assert np.array_equal(free.contact, capped.contact)
    assert not capped.plastic.any()
    assert capped.plastic_increment is None
    assert np.abs(capped.pressure - free.pressure).max() < 1e-7 * P0
    assert capped.approach == pytest.approx(free.approach, rel=1e-8)


@pytest.mark.parametrize("n, tol_a", [(64, 0.012), (128, 0.006)])
@pytest.mark.parametrize("h_rel", [0.8, 0.5])
def test_flat_topped_sphere_against_axisymmetric_reference(n, tol_a, h_rel):
    H = h_rel * P0
    ref = capped_sphere(R, ES, H, force=F, rings=400)
    g, h, rr = _sphere(n)
    cap = HardnessCap(H)
    r = solve_normal(free_boundary_operator(g, PAIR), h, force=F, tol=1e-10, interaction=cap)
    assert r.converged
    assert r.pressure.max() <= H * (1 + 1e-12)
    assert np.all(r.pressure[r.plastic] == H)
    assert r.approach == pytest.approx(ref.approach, rel=3e-4)
    assert math.sqrt(r.contact_area / math.pi) == pytest.approx(ref.contact_radius, rel=tol_a)
    assert math.sqrt(r.plastic_area / math.pi) == pytest.approx(ref.plastic_radius, rel=tol_a)
    # the plastic displacement is the overlap of the capped nodes, largest at the centre
    centre = np.unravel_index(np.argmin(rr), rr.shape)
    assert cap.plastic[centre] == pytest.approx(cap.max_plastic_displacement, rel=0.02)
    assert np.all(cap.plastic[~r.plastic] == 0)


def test_plastic_history_is_idempotent_and_kept():
    g, h, _ = _sphere(64)
    op = free_boundary_operator(g, PAIR)
    cap = HardnessCap(0.6 * P0)
    first = solve_normal(op, h, force=F, interaction=cap)
    up = cap.plastic.copy()
    again = solve_normal(op, h, force=F, interaction=cap)
    assert np.abs(cap.plastic - up).max() < 1e-9 * up.max()
    assert np.array_equal(first.contact, again.contact)
    # unloading to a tenth: the flattened top carries it elastically (no new plastic nodes),
    # over a larger area than the unflattened sphere would
    low = solve_normal(op, h, force=0.1 * F, interaction=cap)
    assert not low.plastic.any()
    assert np.abs(cap.plastic - up).max() < 1e-9 * up.max()
    virgin = solve_normal(op, h, force=0.1 * F)
    assert low.contact_area > 1.3 * virgin.contact_area
    # reloading beyond the first load yields further
    solve_normal(op, h, force=2 * F, interaction=cap)
    assert cap.max_plastic_displacement > 1.2 * up.max()


@pytest.mark.parametrize("ratio", [1e1, 1e2, 1e3])
def test_rigid_plastic_limit(ratio):
    """A = F / H as E* / H grows: the real area of a capped rough contact tends to the load
    over the hardness (every contact node plastic)."""
    n = 128
    g = Grid(n, n, 1.0, 1.0, periodic=True)
    s = self_affine_surface(g, 0.8, rms_slope=1.0, short_cutoff=4 / n, seed=3)
    pair = ContactPair(Material(1.0, 0.3), Material.rigid())
    H = pair.effective_modulus / ratio
    f = 0.02 * H  # mean pressure 2 % of H
    r = solve_normal(make_operator(g, pair), s.max() - s, force=f, interaction=HardnessCap(H), tol=1e-10)
    assert r.converged
    excess = r.contact_area * H / f - 1.0
    assert excess >= -1e-9
    # measured 0.022, 0.004, 0.001 (128^2): the elastic fringe of each contact spot shrinks
    assert excess < {1e1: 0.05, 1e2: 0.01, 1e3: 0.003}[ratio]
    assert r.plastic_area * H / f == pytest.approx(1.0, abs={1e1: 0.05, 1e2: 0.01, 1e3: 0.003}[ratio])


def test_force_beyond_hardness_times_area_refused():
    g, h, _ = _sphere(32)
    with pytest.raises(InputError, match="hardness"):
        solve_normal(free_boundary_operator(g, PAIR), h, force=2.0 * P0 * g.area, interaction=HardnessCap(P0))


def test_adhesive_pull_off_after_plastic_loading_is_larger():
    """A Dugdale sphere (Maugis lambda ~ 0.8) preloaded to 10 pull-offs past the cap (H = p0 / 2)
    and unloaded adheres more than the same sphere without plasticity: the flattened top stays
    closer to the flat.  Without the cap the pull-off is Maugis-Dugdale's (between 1.5 and 2
    pi R w); measured -56.5 nN without and -159 nN with the cap (128^2)."""
    from types import SimpleNamespace

    from tribobem.interactions.dugdale import build_dugdale
    from tribobem.interactions.registry import LawContext
    from tribobem.solvers.normal_paths import pull_off

    pair = ContactPair(Material(10e9, 0.0), Material.rigid())
    es = pair.effective_modulus
    radius, w, load = 100e-9, 0.1, 6e-7
    a = (3 * load * radius / (4 * es)) ** (1 / 3)
    p0 = 3 * load / (2 * math.pi * a * a)
    n = 128
    g = Grid(n, n, 8 * a, 8 * a, periodic=False)
    x = (np.arange(n) - n / 2 + 0.5) * g.dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    h = (X ** 2 + Y ** 2) / (2 * radius)
    op = free_boundary_operator(g, pair)
    law = build_dugdale(SimpleNamespace(work_of_adhesion=w, z0=0.3e-9, discretisation="auto"), LawContext(g, es))
    elastic = pull_off(op, h, law, preload=load)
    cap = HardnessCap(0.5 * p0, law)
    plastic = pull_off(op, h, cap, preload=load)
    assert -2.0 * math.pi * radius * w < elastic.force < -1.5 * math.pi * radius * w
    assert cap.max_plastic_displacement > 0.5e-9
    assert plastic.force < 2.0 * elastic.force
