"""Water: Kelvin radius, capillary pressure and RH validation (thesis Eqs. A.25-A.26)."""

import math

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.interactions.water import GAS_CONSTANT, Water, check_rh


def test_defaults_and_pressure_scale():
    w = Water()
    assert (w.temperature, w.surface_tension, w.molar_volume) == (295.0, 0.0725, 18.05e-6)
    assert GAS_CONSTANT == 8.314462618
    # R_g T / V = 8.314462618 * 295 / 18.05e-6 = 1.358873e8 Pa
    assert w.pressure_scale == pytest.approx(1.358873e8, rel=1e-6)
    assert w.critical_distance == pytest.approx(0.84e-9, rel=1e-12)
    assert 0.25e-9 < w.molecule_diameter < 0.32e-9


def test_kelvin_radius_against_israelachvili():
    # Israelachvili (Intermolecular and Surface Forces, 3rd ed., Eq. 17.13): for water at
    # 20 C, r_k = 0.54 nm / ln(RH) (gamma = 72.8 mN/m, V = 18 cm^3/mol, T = 293 K).
    w = Water(temperature=293.0, surface_tension=0.0728, molar_volume=18.0e-6)
    for rh in (0.1, 0.5, 0.9):
        assert w.kelvin_radius(rh) * math.log(rh) == pytest.approx(0.54e-9, rel=0.01)
    # the default water: gamma V / (R_g T) = 0.5336 nm, r_k(0.5) = -0.7697 nm
    assert Water().kelvin_radius(0.5) == pytest.approx(0.0725 * 18.05e-6 / (8.314462618 * 295.0 * math.log(0.5)), rel=1e-13)
    assert Water().kelvin_radius(0.5) == pytest.approx(-0.76972e-9, rel=1e-4)


def test_laplace_pressure_is_gamma_over_kelvin_radius():
    w = Water()
    rh = np.array([0.05, 0.3, 0.6, 0.95, 0.999])
    r = w.kelvin_radius(rh)
    p = w.capillary_pressure(rh)
    assert np.all(r < 0) and np.all(p < 0)  # concave meniscus, tensile pressure
    np.testing.assert_allclose(p, w.surface_tension / r, rtol=1e-13)
    np.testing.assert_allclose(w.chemical_potential_pressure(rh), p, rtol=0)
    # -94.19 MPa at 50 % RH
    assert w.capillary_pressure(0.5) == pytest.approx(-94.19e6, rel=1e-3)
    np.testing.assert_allclose(w.relative_humidity(r), rh, rtol=1e-13)


def test_saturation_gives_flat_meniscus():
    w = Water()
    assert w.kelvin_radius(1.0) == -math.inf
    p = w.capillary_pressure(1.0)
    assert p == 0.0 and not math.copysign(1.0, p) < 0
    assert isinstance(w.kelvin_radius(0.5), float) and isinstance(p, float)
    np.testing.assert_array_equal(w.kelvin_radius([0.5, 1.0])[1:], [-math.inf])
    assert w.relative_humidity(-math.inf) == 1.0


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.0000001, 35.0, math.nan, math.inf, "x", []])
def test_check_rh_rejects(bad):
    with pytest.raises(InputError, match="humidity.rh"):
        check_rh(bad)
    with pytest.raises(InputError):
        Water().kelvin_radius(bad)


def test_check_rh_percentage_hint_and_arrays():
    with pytest.raises(InputError, match="percentage"):
        check_rh(35)
    with pytest.raises(InputError):
        check_rh([0.3, 1.2])
    assert check_rh(1) == 1.0
    np.testing.assert_array_equal(check_rh([0.3, 1.0]), [0.3, 1.0])


@pytest.mark.parametrize("kw", [{"temperature": 0.0}, {"temperature": -1.0}, {"surface_tension": math.nan},
                                {"molar_volume": math.inf}, {"temperature": "warm"}])
def test_water_rejects_bad_parameters(kw):
    with pytest.raises(InputError):
        Water(**kw)
