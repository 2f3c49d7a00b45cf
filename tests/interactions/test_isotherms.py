"""Adsorption isotherms and the disjoining pressure they imply (Papers B and C)."""

import math

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.interactions.isotherms import (
    RH_FLOOR, SI, SIO2, DryIsotherm, FHHIsotherm, TableIsotherm, isotherm_from_spec,
)
from tribobem.interactions.water import Water

SPEC_RH = [0, .1, .2, .3, .35, .4, .5, .6, .7, .8, .9, .95]
SPEC_NM = [0, .30, .55, .80, .90, .95, 1.05, 1.20, 1.35, 1.60, 2.00, 2.60]


def test_shipped_tables_are_the_spec_values():
    np.testing.assert_allclose(SIO2.thickness(SPEC_RH), np.array(SPEC_NM) * 1e-9, rtol=1e-14, atol=0)
    np.testing.assert_allclose(SI.thickness(SPEC_RH), np.array(SPEC_NM) * 1e-9 * 2 / 3, rtol=1e-14, atol=0)
    # Paper C: 0.9 nm on SiO2 and 0.6 nm on Si at 35 % RH
    assert SIO2.thickness(0.35) == pytest.approx(0.9e-9, rel=1e-14)
    assert SI.thickness(0.35) == pytest.approx(0.6e-9, rel=1e-14)
    assert SIO2.thickness(0.0) == 0.0 and not SIO2.dry


def test_monotone_inverse_pair():
    rh = np.linspace(0.0, 0.9999, 4001)
    e = SIO2.thickness(rh)
    assert np.all(np.diff(e) > 0) and np.all(np.isfinite(e))
    np.testing.assert_allclose(SIO2.relative_humidity(e), rh, rtol=0, atol=1e-14)
    ee = np.linspace(0.0, 8e-9, 4001)
    r = SIO2.relative_humidity(ee)
    assert np.all(np.diff(r) > 0) and r[0] == 0.0 and r[-1] < 1.0
    np.testing.assert_allclose(SIO2.thickness(r), ee, rtol=1e-12, atol=1e-22)


def test_no_overshoot_between_points():
    # PCHIP stays within each interval's bracket (a cubic spline would not)
    rh = np.linspace(0.0, 0.95, 2000)
    e = SIO2.thickness(rh)
    idx = np.clip(np.searchsorted(SPEC_RH, rh, side="right") - 1, 0, len(SPEC_RH) - 2)
    lo = np.array(SPEC_NM)[idx] * 1e-9
    hi = np.array(SPEC_NM)[idx + 1] * 1e-9
    assert np.all(e >= lo - 1e-24) and np.all(e <= hi + 1e-24)


def test_tail_above_table_is_fhh_matched_c1_and_diverges_at_one():
    e_end = 2.6e-9
    s = SIO2.tail_exponent
    # s = e_n * secant / (RH_n |ln RH_n|) with the last secant 0.05 / 0.6 nm
    assert s == pytest.approx(2.6 * (0.05 / 0.6) / (0.95 * -math.log(0.95)), rel=1e-12)
    assert SIO2.thickness(0.99) == pytest.approx(e_end * (math.log(0.95) / math.log(0.99)) ** (1 / s), rel=1e-12)
    assert SIO2.thickness(1.0) == math.inf
    rh = 1.0 - np.logspace(-1.2, -12, 200)
    e = SIO2.thickness(rh)
    assert np.all(np.isfinite(e)) and np.all(np.diff(e) > 0)
    # C1 at the table end: one-sided slopes of ln RH_iso agree (to the finite-difference error)
    h = 1e-15
    g = SIO2.log_relative_humidity(np.array([e_end - 2 * h, e_end - h, e_end, e_end + h, e_end + 2 * h]))
    left = (3 * g[2] - 4 * g[1] + g[0]) / (2 * h)
    right = (-3 * g[2] + 4 * g[3] - g[4]) / (2 * h)
    assert right == pytest.approx(left, rel=1e-4)
    _, dg = SIO2.log_relative_humidity(e_end, derivative=True)
    assert dg == pytest.approx((0.05 / 0.6e-9) / 0.95, rel=1e-12)


def test_disjoining_pressure_balances_kelvin_pressure_on_a_flat():
    w = Water()
    rh = np.array([0.05, 0.2, 0.35, 0.6, 0.9, 0.97, 0.995])
    for iso in (SIO2, SI, FHHIsotherm(1.5, 0.3e-9, 2.5)):
        e = iso.thickness(rh)
        # -Pi(e_iso(RH)) = (R_g T / V) ln RH
        np.testing.assert_allclose(-iso.disjoining_pressure(e, w), w.capillary_pressure(rh), rtol=1e-10)
        pi = iso.disjoining_pressure(np.linspace(1e-12, 6e-9, 3000), w)
        assert np.all(pi > 0) and np.all(np.diff(pi) < 0)


def test_disjoining_pressure_derivative_matches_finite_differences():
    w = Water()
    e = np.array([0.1e-9, 0.7e-9, 1.1e-9, 1.9e-9, 3e-9, 5e-9])
    for iso in (SIO2, FHHIsotherm(1.0)):
        d = iso.disjoining_pressure_derivative(e, w)
        h = 1e-16
        fd = (iso.disjoining_pressure(e + h, w) - iso.disjoining_pressure(e - h, w)) / (2 * h)
        assert np.all(d < 0)
        np.testing.assert_allclose(d, fd, rtol=1e-5)


def test_fhh_closed_form():
    w = Water()
    iso = FHHIsotherm(a=2.0, monolayer=0.25e-9, exponent=3.0)
    e = np.array([0.2e-9, 0.5e-9, 2e-9])
    np.testing.assert_allclose(iso.disjoining_pressure(e, w), w.pressure_scale * 2.0 * (0.25e-9 / e) ** 3, rtol=1e-13)
    np.testing.assert_allclose(iso.disjoining_pressure_derivative(e, w),
                               -3 * w.pressure_scale * 2.0 * (0.25e-9 / e) ** 3 / e, rtol=1e-13)
    assert iso.thickness(math.exp(-2.0)) == pytest.approx(0.25e-9, rel=1e-13)  # one monolayer at -ln RH = a
    assert iso.thickness(0.0) == 0.0 and iso.thickness(1.0) == math.inf
    with pytest.raises(InputError):
        FHHIsotherm(a=-1.0)
    with pytest.raises(InputError):
        FHHIsotherm(a=1.0, exponent=0.0)


def test_floor_continuation_is_logarithmic_c1_and_decreasing():
    w = Water()
    f = SIO2.floor
    assert SIO2.relative_humidity(f) == pytest.approx(RH_FLOOR, rel=1e-9)
    e = np.array([1e-30, 1e-20, 0.5 * f, f, 1.5 * f, 1e-12])
    pi = SIO2.disjoining_pressure(e, w)
    assert np.all(np.isfinite(pi)) and np.all(np.diff(pi) < 0)
    # at the floor Pi = -(R_g T / V) ln 1e-6 = 1.877 GPa
    assert SIO2.disjoining_pressure(f, w) == pytest.approx(w.pressure_scale * math.log(1e6), rel=1e-9)
    # a table rising linearly from (0, 0) has RH ~ c e: the continuation is its own ln e law
    # (b = floor RH'/RH = 1 + O(floor / 0.3 nm); measured 1 + 1.6e-6)
    assert SIO2.disjoining_pressure(f / 10, w) - SIO2.disjoining_pressure(f, w) == pytest.approx(
        w.pressure_scale * math.log(10), rel=1e-5)
    # slope continuous across the floor
    d = SIO2.disjoining_pressure_derivative(np.array([f * (1 - 1e-9), f * (1 + 1e-9)]), w)
    assert d[0] == pytest.approx(d[1], rel=1e-6)
    # no film at all: infinite disjoining pressure; a negative film is an input error
    assert SIO2.disjoining_pressure(0.0, w) == math.inf
    with pytest.raises(InputError):
        SIO2.disjoining_pressure(-1e-12, w)
    # the FHH power law is continued the same way, without overflow
    fhh = FHHIsotherm(1.0)
    assert np.all(np.isfinite(fhh.disjoining_pressure(np.array([1e-25, 1e-15, fhh.floor]), w)))


@pytest.mark.parametrize(
    "rh, thickness, match",
    [
        ([0, 0.5, 0.4], [0, 1e-9, 2e-9], "strictly increasing"),
        ([0, 0.4, 0.5], [0, 2e-9, 1e-9], "strictly increasing"),
        ([0, 0.4, 0.5], [0, 1e-9, 1e-9], "plateau"),
        ([0, 0.4, 0.5], [0, -1e-9, 1e-9], ">= 0"),
        ([0, 0.4, math.nan], [0, 1e-9, 2e-9], "finite"),
        ([0, 0.4, 1.2], [0, 1e-9, 2e-9], r"\[0, 1\]"),
        ([-0.1, 0.4], [0, 1e-9], r"\[0, 1\]"),
        ([0.5], [1e-9], "at least 2"),
        ([0, 0.5], [0, 1e-9, 2e-9], "same length"),
        ([0, 0.5], [1e-10, 1e-9], "RH = 0"),
        ([0.1, 0.5], [0.0, 1e-9], "zero film"),
    ],
)
def test_bad_tables_raise(rh, thickness, match):
    with pytest.raises(InputError, match=match):
        TableIsotherm(rh, thickness)


def test_table_without_origin_gets_it_and_table_ending_at_saturation():
    iso = TableIsotherm([0.2, 0.6], [0.5e-9, 1.0e-9])
    assert iso.thickness(0.0) == 0.0 and iso.thickness(0.2) == pytest.approx(0.5e-9, rel=1e-14)
    sat = TableIsotherm([0.0, 0.5, 1.0], [0.0, 1e-9, 3e-9])
    assert sat.thickness(1.0) == pytest.approx(3e-9, rel=1e-14)
    assert sat.relative_humidity(5e-9) == 1.0
    assert sat.disjoining_pressure(5e-9) == 0.0


def test_thickness_rejects_bad_rh():
    for bad in (-0.01, 1.01, math.nan):
        with pytest.raises(InputError):
            SIO2.thickness(bad)
    with pytest.raises(InputError):
        SIO2.relative_humidity(-1e-9)


def test_dry_isotherm():
    d = DryIsotherm()
    assert d.dry and d.thickness(0.7) == 0.0
    np.testing.assert_array_equal(d.thickness([0.1, 1.0]), [0.0, 0.0])
    with pytest.raises(InputError, match="dry"):
        d.relative_humidity(1e-9)
    with pytest.raises(InputError, match="dry"):
        d.disjoining_pressure(1e-9)


def test_isotherm_from_spec():
    assert isotherm_from_spec("SiO2") is SIO2 and isotherm_from_spec("si") is SI
    assert isotherm_from_spec(None).dry and isotherm_from_spec("dry").dry and isotherm_from_spec("none").dry
    assert isotherm_from_spec({"isotherm": "Si"}) is SI
    t = isotherm_from_spec({"rh": [0, 0.5, 0.9], "thickness": [0, "1 nm", 2e-9]})
    assert t.thickness(0.5) == pytest.approx(1e-9, rel=1e-14)
    f = isotherm_from_spec({"fhh": {"a": 1.2, "monolayer": "0.3 nm", "exponent": 2.5}})
    assert isinstance(f, FHHIsotherm) and f.monolayer == pytest.approx(0.3e-9) and f.exponent == 2.5
    assert isotherm_from_spec(f) is f
    for bad in ("glass", {"rh": [0, 1]}, {"fhh": {"monolayer": 1e-9}}, {"fhh": {"a": 1, "b": 2}}, 3.0,
                {"rh": [0, 0.5], "thickness": [0, "1 N"]}, {"rh": [0, 0.5], "thickness": [0, -1e-9]}):
        with pytest.raises(InputError):
            isotherm_from_spec(bad)
