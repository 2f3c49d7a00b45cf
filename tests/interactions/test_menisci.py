"""Meniscus islands (Paper B 2.2) and Paper C's contribution coefficient."""

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from tribobem.errors import InputError
from tribobem.interactions.menisci import contribution_coefficient, cut_height, meniscus_islands

# Kelvin radius computed here (independent of interactions.water): r_k = gamma V / (R_g T ln RH).
GAMMA, VM, RG, T = 0.0725, 18.05e-6, 8.314462618, 295.0


def kelvin(rh):
    return GAMMA * VM / (RG * T * math.log(rh)) if rh < 1 else -math.inf


def paraboloid(n, L, R):
    x = (np.arange(n) + 0.5) * L / n - L / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return (X**2 + Y**2) / (2 * R), X, Y


def test_cut_height_is_two_kelvin_radii_plus_local_films():
    rk = kelvin(0.5)
    e1 = np.array([[0.5e-9, 1.0e-9]])
    S = cut_height(e1, 0.3e-9, rk)
    np.testing.assert_allclose(S, 2 * abs(rk) + e1 + 0.3e-9, rtol=1e-14)
    # Contact angles: |r_k| (cos t1 + cos t2).
    S60 = cut_height(0.0, 0.0, rk, contact_angles=(math.pi / 3, 0.0))
    assert S60 == pytest.approx(1.5 * abs(rk), rel=1e-14)
    # cos sum 0: no meniscus term, even at RH = 1 (no inf * 0).
    assert cut_height(1e-9, 0.0, -math.inf, contact_angles=(math.pi / 2, math.pi / 2)) == pytest.approx(1e-9)
    assert cut_height(1e-9, 0.0, -math.inf) == math.inf


def test_sphere_island_is_the_disk_of_the_cut_height():
    """Paraboloid gap touching at the centre: one active island, the disk g < S, radius sqrt(2 R S)."""
    n, L, R = 256, 400e-9, 1e-6
    g, X, Y = paraboloid(n, L, R)
    g -= g.min()
    rk, e = kelvin(0.6), 1.2e-9
    isl = meniscus_islands(g, e, e, rk, g <= 0, periodic=False)
    S = 2 * abs(rk) + 2 * e
    assert isl.count == 1 and isl.active_count == 1
    np.testing.assert_array_equal(isl.active, g < S)
    dx = L / n
    area = np.count_nonzero(isl.active) * dx * dx
    # Cell-counted disk area against pi 2 R S (disk radius ~90 cells: counting error << 1%).
    assert area == pytest.approx(math.pi * 2 * R * (S + g.min()), rel=5e-3)


def test_only_islands_with_a_seed_are_active():
    n, L, R = 128, 400e-9, 1e-6
    g1, X, Y = paraboloid(n, L, R)
    # Two bumps of the lower surface: one in contact at x = -100 nm, one whose film-to-film
    # gap is 1.5 nm (> d_cr = 0.84 nm, not wetted) at x = +100 nm.
    g = np.minimum(((X + 100e-9) ** 2 + Y**2) / (2 * R), ((X - 100e-9) ** 2 + Y**2) / (2 * R) + 2.5e-9)
    g -= g.min()
    rk, e = kelvin(0.7), 0.5e-9
    isl = meniscus_islands(g, e, e, rk, g <= 0, periodic=False)
    assert isl.count == 2 and isl.active_count == 1
    assert isl.active[np.unravel_index(np.argmin(g), g.shape)]
    right = X > 50e-9
    assert not isl.active[right].any() and (isl.labels[right] > 0).any()
    # A thicker film makes the second bump a film-to-film gap below d_cr: 2.5 - 2 x 0.9 = 0.7 nm.
    isl2 = meniscus_islands(g, 0.9e-9, 0.9e-9, rk, g <= 0, periodic=False)
    assert isl2.active_count == 2
    # ... and thicker still, a wetted node (g < e1 + e2): also a seed.
    isl3 = meniscus_islands(g, 1.3e-9, 1.3e-9, rk, g <= 0, periodic=False, critical_distance=0.0)
    assert isl3.active_count == 2
    # No seed at all (bodies apart by 10 nm): nothing is active.
    isl4 = meniscus_islands(g + 10e-9, e, e, rk, None, periodic=False)
    assert isl4.active_count == 0 and not isl4.active.any()


def test_local_films_move_the_island_edge():
    n, L, R = 128, 400e-9, 1e-6
    g, X, Y = paraboloid(n, L, R)
    g -= g.min()
    rk = kelvin(0.5)
    e_thick = np.where(X > 0, 2e-9, 0.5e-9)
    isl = meniscus_islands(g, e_thick, 0.0, rk, g <= 0, periodic=False)
    np.testing.assert_array_equal(isl.active, g < 2 * abs(rk) + e_thick)
    assert np.count_nonzero(isl.active & (X > 0)) > 1.2 * np.count_nonzero(isl.active & (X < 0))


def _torus_reference(mask, connectivity):
    """Connected components of a mask on the torus by an explicit neighbour graph (independent of
    the label-merging in meniscus_islands)."""
    nx, ny = mask.shape
    idx = np.arange(mask.size).reshape(mask.shape)
    shifts = [(1, 0), (0, 1)] + ([(1, 1), (1, -1)] if connectivity == 8 else [])
    a, b = [], []
    for sx, sy in shifts:
        nb = np.roll(idx, (-sx, -sy), axis=(0, 1))
        both = mask & np.roll(mask, (-sx, -sy), axis=(0, 1))
        a.append(idx[both])
        b.append(nb[both])
    a, b = np.concatenate(a), np.concatenate(b)
    graph = coo_matrix((np.ones(a.size), (a, b)), shape=(mask.size, mask.size))
    _, comp = connected_components(graph, directed=False)
    return comp.reshape(mask.shape)


def _same_partition(l1, l2, mask):
    pairs = np.unique(np.stack([l1[mask], l2[mask]]), axis=1)
    return pairs.shape[1] == np.unique(l1[mask]).size == np.unique(l2[mask]).size


@pytest.mark.parametrize("connectivity", [4, 8])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_periodic_merge_matches_torus_graph(connectivity, seed):
    rng = np.random.default_rng(seed)
    g = rng.random((40, 33)) * 4e-9
    rk = -1e-9
    isl = meniscus_islands(g, 0.0, 0.0, rk, np.zeros_like(g, bool), periodic=True, connectivity=connectivity,
                           critical_distance=0.0)
    mask = g < 2e-9
    assert (isl.labels > 0).sum() == mask.sum()
    ref = _torus_reference(mask, connectivity)
    assert _same_partition(isl.labels, ref, mask)
    assert isl.count == np.unique(ref[mask]).size
    assert set(np.unique(isl.labels[mask])) == set(range(1, isl.count + 1))


def test_island_across_the_edge_is_one_island_on_a_periodic_grid():
    g = np.full((16, 16), 10e-9)
    g[0:2, 5] = 0.0  # contact at the x = 0 edge
    g[14:16, 5] = 1e-9  # below S at the opposite edge, no seed of its own
    rk = -1e-9
    per = meniscus_islands(g, 0.0, 0.0, rk, g <= 0, periodic=True, critical_distance=0.0)
    free = meniscus_islands(g, 0.0, 0.0, rk, g <= 0, periodic=False, critical_distance=0.0)
    assert per.count == 1 and per.active[15, 5]
    assert free.count == 2 and not free.active[15, 5]
    # A diagonal touch across the corner joins only with 8-connectivity.
    g = np.full((16, 16), 10e-9)
    g[0, 0] = 0.0
    g[15, 15] = 1e-9
    assert meniscus_islands(g, 0.0, 0.0, rk, g <= 0, connectivity=4, critical_distance=0.0).count == 2
    isl8 = meniscus_islands(g, 0.0, 0.0, rk, g <= 0, connectivity=8, critical_distance=0.0)
    assert isl8.count == 1 and isl8.active[15, 15]


def test_rh_one_floods_everything_with_a_seed():
    n, L, R = 64, 400e-9, 1e-6
    g, X, Y = paraboloid(n, L, R)
    g -= g.min()
    isl = meniscus_islands(g, 2e-9, 2e-9, -math.inf, g <= 0, periodic=False)
    assert np.all(np.isinf(isl.cut_height))
    assert isl.count == 1 and isl.active.all()
    # Bodies apart (no seed): one island, inactive.
    isl = meniscus_islands(g + 50e-9, 2e-9, 2e-9, -math.inf, None, periodic=False)
    assert isl.count == 1 and not isl.active.any()


def test_hydrophobic_angles_remove_the_islands():
    g = np.zeros((8, 8))
    g[4:, :] = 1e-9
    isl = meniscus_islands(g, 0.0, 0.0, kelvin(0.9), g <= 0, contact_angles=(math.pi, math.pi))
    assert isl.count == 0 and not isl.active.any()


def test_island_key_tells_masks_apart():
    g = np.zeros((8, 8))
    a = meniscus_islands(g + 5e-9, 0.0, 0.0, -1e-9, None)
    b = meniscus_islands(g, 0.0, 0.0, -1e-9, None)
    assert a.key != b.key and a.key == meniscus_islands(g + 5e-9, 0.0, 0.0, -1e-9, None).key


@pytest.mark.parametrize("kwargs, field", [
    (dict(kelvin_radius=1e-9), "kelvin_radius"),
    (dict(kelvin_radius=math.nan), "kelvin_radius"),
    (dict(film1=-1e-9), "film1"),
    (dict(film2=np.zeros((3, 3))), "film2"),
    (dict(connectivity=6), "connectivity"),
    (dict(contact_angles=(0.0, 4.0)), "contact_angles[1]"),
    (dict(critical_distance=-1.0), "critical_distance"),
    (dict(contact=np.zeros((3, 3), bool)), "contact"),
])
def test_bad_input_is_named(kwargs, field):
    args = dict(gap=np.ones((8, 8)) * 1e-9, film1=0.0, film2=0.0, kelvin_radius=-1e-9, contact=None)
    args.update(kwargs)
    with pytest.raises(InputError) as err:
        meniscus_islands(**args)
    assert err.value.field == field


def test_contribution_coefficient_paper_c():
    assert contribution_coefficient(0.35) == pytest.approx(1 / 6)
    assert round(contribution_coefficient(0.35), 2) == 0.17  # Paper C's value at 35 % RH
    np.testing.assert_allclose(contribution_coefficient([0.1, 0.3, 0.45, 0.6, 0.9, 1.0]),
                               [0.0, 0.0, 0.5, 1.0, 1.0, 1.0], atol=1e-15)
    assert contribution_coefficient(0.35, kind="none") == 1.0
    with pytest.raises(InputError):
        contribution_coefficient(35.0)
    with pytest.raises(InputError):
        contribution_coefficient(0.0)
    with pytest.raises(InputError):
        contribution_coefficient(0.5, kind="quadratic")
