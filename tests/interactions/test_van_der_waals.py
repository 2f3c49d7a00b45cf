"""Water-solid van der Waals terms (Paper B Eqs. 11-12, signs checked against their limits)."""

import math

import numpy as np
import pytest
from scipy.integrate import dblquad

from tribobem.errors import InputError
from tribobem.interactions.van_der_waals import (
    HAMAKER_SI, HAMAKER_SIO2, HAMAKER_WATER, VanDerWaals, air_gap_stress, combine_hamaker, water_filled_stress,
)

A1, A2, AW = HAMAKER_SIO2, HAMAKER_SI, HAMAKER_WATER


def test_combining_rule():
    # Across vacuum: geometric mean.
    assert combine_hamaker(A1, A2) == pytest.approx(math.sqrt(A1 * A2), rel=1e-15)
    # Identical bodies across any medium attract (A_131 >= 0), across themselves nothing.
    assert combine_hamaker(A1, A1, AW) == pytest.approx((math.sqrt(A1) - math.sqrt(AW)) ** 2, rel=1e-15)
    assert combine_hamaker(A1, A1, A1) == 0.0
    # SiO2 / water / Si: (2.5495 - 1.9235)(4.3589 - 1.9235) e-20 = 1.5245e-20 J.
    assert combine_hamaker(A1, A2, AW) == pytest.approx(1.5245e-20, rel=1e-4)
    # A medium between the two bodies' constants: negative (repulsive) A_132.
    assert combine_hamaker(A1, 1e-20, AW) < 0


@pytest.mark.parametrize("bad", [-1e-20, math.nan, math.inf, "x"])
def test_negative_hamaker_is_refused(bad):
    with pytest.raises(InputError):
        combine_hamaker(bad, A2)
    with pytest.raises(InputError) as err:
        VanDerWaals(hamaker1=bad)
    assert err.value.field == "hamaker1"
    with pytest.raises(InputError):
        air_gap_stress(1e-9, 0.0, 0.0, A1, A2, bad)


def test_cutoff_must_be_positive():
    with pytest.raises(InputError):
        VanDerWaals(cutoff=0.0)
    with pytest.raises(InputError):
        water_filled_stress(1e-9, 1e-20, cutoff=-1.0)


def test_water_filled_term_is_attractive_and_cut_off():
    A = combine_hamaker(A1, A2, AW)
    g = np.array([0.1e-9, 0.3e-9, 1e-9, 5e-9])
    p = water_filled_stress(g, A, cutoff=0.3e-9)
    np.testing.assert_allclose(p, -A / (6 * math.pi * np.maximum(g, 0.3e-9) ** 3), rtol=1e-14)
    assert np.all(p < 0)
    assert p[0] == p[1]


def test_air_gap_reduces_to_solid_air_solid_without_films():
    g = np.array([0.5e-9, 1e-9, 3e-9])
    ref = -math.sqrt(A1 * A2) / (6 * math.pi * g**3)
    np.testing.assert_allclose(air_gap_stress(g, 0.0, 0.0, A1, A2, AW), ref, rtol=1e-13)
    # Vanishing films: continuous approach to the same limit (first order in e).
    p = air_gap_stress(g, 1e-15, 2e-15, A1, A2, AW)
    np.testing.assert_allclose(p, ref, rtol=1e-5)
    # The printed Eq. 12 (minus on the middle terms, positive square roots) misses this limit.
    s1, s2, sw = math.sqrt(A1), math.sqrt(A2), math.sqrt(AW)
    printed = AW - sw * abs(s1 - sw) - sw * abs(s2 - sw) + abs(s1 - sw) * abs(s2 - sw)
    assert abs(printed / math.sqrt(A1 * A2) - 1) > 0.5


def test_air_gap_between_water_bodies_is_water_air_water():
    """A body whose own constant equals water's is water: only the A_waw / e_a^3 term and the
    other body's film terms remain, and as e2 -> 0 it is water against solid 2 across air."""
    ea = 1.2e-9
    p = air_gap_stress(ea + 1e-9 + 1e-9, 1e-9, 1e-9, AW, AW, AW)
    assert p == pytest.approx(-AW / (6 * math.pi * ea**3), rel=1e-14)
    p = air_gap_stress(ea + 1e-9, 1e-9, 0.0, AW, A2, AW)
    assert p == pytest.approx(-math.sqrt(AW * A2) / (6 * math.pi * ea**3), rel=1e-13)


def test_air_gap_limits_of_the_air_gap():
    e1, e2 = 0.8e-9, 0.6e-9
    A1w2 = combine_hamaker(A1, A2, AW)
    # e_a -> 0: the films attract each other with water/air/water, A_waw / (6 pi e_a^3), dominating.
    ea = np.array([1e-12, 1e-11])
    p = air_gap_stress(ea + e1 + e2, e1, e2, A1, A2, AW)
    np.testing.assert_allclose(p / (-AW / (6 * math.pi * ea**3)), 1.0, rtol=1e-4)
    # ... and what is left beyond that term tends to the water-filled value at g = e1 + e2 plus the
    # two film/solid terms (the third and fourth terms are continuous at e_a = 0).
    ea = np.array([1e-12, 3e-12])  # the rest differs from its limit by ~3 e_a / e (first order)
    rest = air_gap_stress(ea + e1 + e2, e1, e2, A1, A2, AW) + AW / (6 * math.pi * ea**3)
    sw = math.sqrt(AW)
    limit = -(sw * (math.sqrt(A1) - sw) / e1**3 + sw * (math.sqrt(A2) - sw) / e2**3) / (6 * math.pi) \
        + water_filled_stress(e1 + e2, A1w2)
    np.testing.assert_allclose(rest, limit, rtol=2e-2)
    # Thick films: only water/air/water is left.
    p = air_gap_stress(1e-9 + 2e-6, 1e-6, 1e-6, A1, A2, AW)
    assert p == pytest.approx(-AW / (6 * math.pi * 1e-27), rel=1e-6)


def _quadrature_pressure(ea, e1, e2, a1, a2, aw):
    """Pressure between two layered half-spaces by direct pairwise summation (double quadrature
    of the sheet-sheet force 2 rho1 rho2 / (pi s^5) with rho = sqrt A), lengths in nm, A in 1e-20 J."""
    s1, s2, sw = math.sqrt(a1), math.sqrt(a2), math.sqrt(aw)
    lower = [(-math.inf, 0.0, s1), (0.0, e1, sw)]
    top = e1 + ea
    upper = [(top, top + e2, sw), (top + e2, math.inf, s2)]
    total = 0.0
    for lo1, hi1, r1 in lower:
        for lo2, hi2, r2 in upper:
            if hi1 <= lo1 or hi2 <= lo2:
                continue
            val, _ = dblquad(lambda z2, z1: 2.0 / (math.pi * (z2 - z1) ** 5), lo1, hi1, lo2, hi2,
                             epsabs=0, epsrel=1e-11)
            total += r1 * r2 * val
    return -total  # attraction is negative


@pytest.mark.parametrize("ea, e1, e2", [(0.5, 0.9, 0.6), (2.0, 1.5, 0.3), (0.9, 0.0, 1.2)])
def test_air_gap_matches_pairwise_summation(ea, e1, e2):
    a1, a2, aw = 6.5, 19.0, 3.7  # 1e-20 J
    ref = _quadrature_pressure(ea, e1, e2, a1, a2, aw) * 1e-20 / 1e-27  # J/nm^3 -> Pa
    p = air_gap_stress((ea + e1 + e2) * 1e-9, e1 * 1e-9, e2 * 1e-9, a1 * 1e-20, a2 * 1e-20, aw * 1e-20)
    assert p == pytest.approx(ref, rel=1e-7)


def test_dataclass_and_cutoff_on_the_air_gap():
    vdw = VanDerWaals(A1, A2, AW, cutoff=0.2e-9)
    assert vdw.solid_solid == pytest.approx(math.sqrt(A1 * A2))
    assert vdw.water_filled == pytest.approx(combine_hamaker(A1, A2, AW))
    # Overlapping films (g < e1 + e2) outside a meniscus: finite, evaluated at e_a = cutoff.
    p = vdw.air_gap_stress(np.array([0.5e-9]), 0.4e-9, 0.4e-9)
    assert np.isfinite(p).all()
    assert p[0] == pytest.approx(float(vdw.air_gap_stress(0.2e-9 + 0.8e-9, 0.4e-9, 0.4e-9)), rel=1e-14)
