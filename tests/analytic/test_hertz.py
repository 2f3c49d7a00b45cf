"""Hertz sphere on flat (thesis A.1-A.3)."""

import numpy as np
import pytest
from scipy.integrate import quad

from tribobem.analytic import hertz, hertz_pressure
from tribobem.errors import InputError

R, ES = 1e-3, 1e11


def test_hertz_known_values_from_force():
    sol = hertz(force=1.0, radius=R, E_star=ES)
    a = (3 * R * 1.0 / (4 * ES)) ** (1 / 3)  # 1.9574e-5 m
    assert sol.contact_radius == pytest.approx(a, rel=1e-14)
    assert sol.contact_radius == pytest.approx(1.95743e-5, rel=1e-5)
    assert sol.approach == pytest.approx(a**2 / R, rel=1e-14)
    assert sol.max_pressure == pytest.approx(3 * 1.0 / (2 * np.pi * a**2), rel=1e-12)
    assert sol.mean_pressure == pytest.approx(1.0 / (np.pi * a**2), rel=1e-12)


def test_hertz_force_approach_roundtrip_vectorised():
    F = np.array([1e-6, 1e-3, 1.0, 10.0])
    s1 = hertz(force=F, radius=R, E_star=ES)
    s2 = hertz(approach=s1.approach, radius=R, E_star=ES)
    np.testing.assert_allclose(s2.force, F, rtol=1e-12)
    np.testing.assert_allclose(s2.contact_radius, s1.contact_radius, rtol=1e-12)
    # F = 4/3 E* sqrt(R) delta^1.5
    np.testing.assert_allclose(F, 4 / 3 * ES * np.sqrt(R) * s1.approach**1.5, rtol=1e-12)


def test_hertz_pressure_integrates_to_force():
    sol = hertz(force=2.5, radius=R, E_star=ES)
    a, p0 = sol.contact_radius, sol.max_pressure
    total = quad(lambda r: 2 * np.pi * r * hertz_pressure(r, a, p0), 0, a, epsrel=1e-12)[0]
    assert total == pytest.approx(2.5, rel=1e-9)
    assert hertz_pressure(1.01 * a, a, p0) == 0.0
    assert hertz_pressure(0.0, a, p0) == pytest.approx(p0)


def test_hertz_bad_input():
    with pytest.raises(InputError):
        hertz(force=-1.0, radius=R, E_star=ES)
    with pytest.raises(InputError):
        hertz(force=1.0, approach=1e-9, radius=R, E_star=ES)
    with pytest.raises(InputError):
        hertz(force=1.0, radius=-R, E_star=ES)
