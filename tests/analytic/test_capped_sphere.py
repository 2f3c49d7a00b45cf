"""The axisymmetric capped-sphere reference: Hertz without a cap, the rigid-plastic bound."""

import math

import numpy as np
import pytest

from tribobem.analytic.capped_sphere import capped_sphere, disc_displacement

R, E_STAR, F = 1e-3, 100e9, 1.0
A = (3 * F * R / (4 * E_STAR)) ** (1 / 3)
P0 = 3 * F / (2 * math.pi * A * A)


def test_disc_displacement_centre_and_far_field():
    # centre: 2 q b / E*; far: the point load q pi b^2 / (pi E* r)
    b = 1e-6
    assert disc_displacement(np.array([0.0]), b, E_STAR)[0] == pytest.approx(2 * b / E_STAR, rel=1e-12)
    r = np.array([1e3 * b])
    assert disc_displacement(r, b, E_STAR)[0] == pytest.approx(b * b / (E_STAR * r[0]), rel=1e-5)


def test_hertz_without_cap():
    s = capped_sphere(R, E_STAR, math.inf, force=F, rings=300)
    assert s.approach == pytest.approx(A * A / R, rel=1e-4)
    assert s.pressure.max() == pytest.approx(P0, rel=2e-3)
    assert s.plastic_radius == 0.0


@pytest.mark.parametrize("h_rel", [0.8, 0.5])
def test_cap_bounds(h_rel):
    H = h_rel * P0
    s = capped_sphere(R, E_STAR, H, force=F, rings=300)
    assert s.force == pytest.approx(F, rel=1e-6)
    assert s.pressure.max() <= H * (1 + 1e-9)
    # the cap loads a larger area than Hertz, at least the rigid-plastic one F / H
    assert s.contact_radius > A
    assert math.pi * s.contact_radius ** 2 >= F / H
    assert 0 < s.plastic_radius <= s.contact_radius
    # and needs a larger approach
    assert s.approach > A * A / R
