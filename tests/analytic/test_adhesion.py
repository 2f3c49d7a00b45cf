"""Bradley, JKR, DMT and Maugis-Dugdale (thesis A.9-A.24)."""

import numpy as np
import pytest
from scipy.integrate import quad

from tribobem.analytic import (
    MAUGIS_PER_TABOR, bradley_pull_off, bradley_pull_off_magnitude, dmt, dmt_pull_off,
    dmt_pull_off_magnitude, dugdale_range, dugdale_stress, hertz, jkr, jkr_pressure,
    jkr_pull_off, jkr_pull_off_magnitude, johnson_greenwood_pull_off_fit, maugis_dugdale,
    maugis_dugdale_curve, maugis_dugdale_pressure, maugis_dugdale_pull_off,
    maugis_dugdale_pull_off_force, maugis_dugdale_pull_off_magnitude,
    maugis_dugdale_pull_off_point, maugis_dugdale_scales, maugis_parameter, tabor_parameter,
)
from tribobem.errors import InputError

R, DG, ES, Z0 = 2.5e-6, 0.05, 75e9, 0.3e-9


# ----------------------------------------------------------------------------------------------
# parameters
# ----------------------------------------------------------------------------------------------

def test_dugdale_parameters():
    s0 = dugdale_stress(DG, Z0)
    h0 = dugdale_range(Z0)
    assert s0 == pytest.approx(16 * DG / (9 * np.sqrt(3) * Z0), rel=1e-15)
    assert h0 / Z0 == pytest.approx(0.9743, abs=1e-4)   # not 9 sqrt(3) (Paper D misprint)
    assert s0 * h0 == pytest.approx(DG, rel=1e-14)        # dgamma = sigma0 h0 (A.16)


def test_maugis_and_tabor_parameters():
    mu = tabor_parameter(R, DG, ES, Z0)
    lam = maugis_parameter(R, DG, ES, Z0)
    assert mu == pytest.approx((R * DG**2 / (ES**2 * Z0**3)) ** (1 / 3), rel=1e-14)
    assert lam / mu == pytest.approx(MAUGIS_PER_TABOR, rel=1e-13)
    assert MAUGIS_PER_TABOR == pytest.approx(1.157, abs=1e-3)   # "lambda = 1.16 mu_T"
    # definition A.20 written out
    s0 = dugdale_stress(DG, Z0)
    assert lam == pytest.approx(2 * s0 * (9 * R / (16 * np.pi * DG * ES**2)) ** (1 / 3), rel=1e-14)


# ----------------------------------------------------------------------------------------------
# Bradley, JKR, DMT
# ----------------------------------------------------------------------------------------------

def test_classical_pull_off_values_and_signs():
    assert bradley_pull_off(R, DG) == pytest.approx(-2 * np.pi * R * DG)
    assert dmt_pull_off(R, DG) == pytest.approx(-2 * np.pi * R * DG)
    assert jkr_pull_off(R, DG) == pytest.approx(-1.5 * np.pi * R * DG)
    assert jkr_pull_off(R, DG, control="displacement") == pytest.approx(-5 / 6 * np.pi * R * DG)
    assert bradley_pull_off_magnitude(R, DG) == pytest.approx(2 * np.pi * R * DG)
    assert dmt_pull_off_magnitude(R, DG) == pytest.approx(2 * np.pi * R * DG)
    assert jkr_pull_off_magnitude(R, DG) == pytest.approx(1.5 * np.pi * R * DG)
    with pytest.raises(InputError):
        jkr_pull_off(R, DG, control="bogus")


def test_jkr_zero_load_radius_and_pull_off_state():
    a0 = jkr(R, DG, ES, force=0.0).contact_radius
    assert a0**3 == pytest.approx(9 * np.pi * R**2 * DG / (2 * ES), rel=1e-12)   # A.11
    Fp = jkr_pull_off(R, DG)
    sol = jkr(R, DG, ES, force=Fp)
    # at pull-off a^3 = (3R/4E*)(3 pi R dgamma / 2) (the square root of A.10 vanishes)
    assert sol.contact_radius**3 == pytest.approx(3 * R / (4 * ES) * 1.5 * np.pi * R * DG, rel=1e-10)
    with pytest.raises(InputError):
        jkr(R, DG, ES, force=1.01 * Fp)


def test_jkr_force_radius_approach_consistency():
    F = np.array([-1.0, -0.5, 0.0, 2.0, 20.0]) * np.pi * R * DG
    s = jkr(R, DG, ES, force=F)
    s2 = jkr(R, DG, ES, contact_radius=s.contact_radius)
    np.testing.assert_allclose(s2.force, F, atol=1e-12 * np.pi * R * DG, rtol=1e-10)
    s3 = jkr(R, DG, ES, approach=s.approach)
    np.testing.assert_allclose(s3.contact_radius, s.contact_radius, rtol=1e-9)
    # A.10 on the stable branch: dF/da > 0
    a = s.contact_radius
    dFda = 4 * ES * a**2 / R - 1.5 * np.sqrt(8 * np.pi * a * ES * DG)
    assert np.all(dFda > 0)


def test_jkr_fixed_grip_minimum():
    a = np.linspace(1e-3, 3, 200001) * (3 * np.pi * DG * R**2 / (4 * ES)) ** (1 / 3)
    s = jkr(R, DG, ES, contact_radius=a)
    i = np.argmin(s.approach)
    assert s.force[i] == pytest.approx(jkr_pull_off(R, DG, "displacement"), rel=1e-4)
    assert np.min(s.force) == pytest.approx(jkr_pull_off(R, DG), rel=1e-6)


def test_jkr_pressure_integrates_to_force():
    a = jkr(R, DG, ES, force=0.7 * np.pi * R * DG).contact_radius
    # r = a sin(t) removes the edge singularity
    f = lambda t: 2 * np.pi * a * np.sin(t) * a * np.cos(t) * jkr_pressure(a * np.sin(t), a, R, DG, ES)  # noqa: E731
    total = quad(f, 0, np.pi / 2, epsrel=1e-12)[0]
    assert total == pytest.approx(0.7 * np.pi * R * DG, rel=1e-8)


def test_dmt():
    s = dmt(R, DG, ES, force=0.0)
    assert s.contact_radius**3 == pytest.approx(3 * R * 2 * np.pi * R * DG / (4 * ES), rel=1e-12)
    s2 = dmt(R, DG, ES, approach=s.approach)
    assert s2.force == pytest.approx(0.0, abs=1e-12 * np.pi * R * DG)
    # DMT = Hertz shifted by the adhesive load
    h = hertz(force=2 * np.pi * R * DG + 1e-9, radius=R, E_star=ES)
    assert dmt(R, DG, ES, force=1e-9).contact_radius == pytest.approx(h.contact_radius, rel=1e-12)
    with pytest.raises(InputError):
        dmt(R, DG, ES, force=-2.1 * np.pi * R * DG)


# ----------------------------------------------------------------------------------------------
# Maugis-Dugdale: dimensionless curve
# ----------------------------------------------------------------------------------------------

def _a22(A, m, lam):
    s = np.sqrt(m * m - 1)
    T = np.arctan(s)
    return lam * A**2 / 2 * (s + (m * m - 2) * T) + 4 * lam**2 * A / 3 * (s * T - m + 1)


@pytest.mark.parametrize("lam", [0.1, 0.3, 0.5, 1.0, 2.0, 5.0])
def test_md_curve_satisfies_A21_A22_A24(lam):
    A = np.array([0.05, 0.3, 0.8, 1.2, 2.0, 3.0])
    c = maugis_dugdale_curve(lam, A=A)
    np.testing.assert_allclose(_a22(A, c.m, lam), 1.0, rtol=1e-11)
    s = np.sqrt(c.m**2 - 1)
    np.testing.assert_allclose(c.F, A**3 - lam * A**2 * (s + c.m**2 * np.arctan(s)), rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(c.Delta, A**2 - 4 / 3 * A * lam * s, rtol=1e-11, atol=1e-13)
    assert np.all(c.m >= 1)


def test_md_lhs_monotonic_in_m():
    # justification of the single bracketed root: A.22 left side increases with m at fixed A
    m = np.linspace(1, 30, 20001)
    for lam in (0.05, 1.0, 20.0):
        for A in (0.01, 0.5, 3.0):
            assert np.all(np.diff(_a22(A, m, lam)) > 0)


def test_md_curve_m_parametrisation_and_A0_endpoint():
    lam = 0.7
    cm = maugis_dugdale_curve(lam, m=[1.001, 1.3, 2.0, 10.0])
    cA = maugis_dugdale_curve(lam, A=cm.A)
    np.testing.assert_allclose(cA.m, cm.m, rtol=1e-10)
    np.testing.assert_allclose(cA.F, cm.F, rtol=1e-10)
    c0 = maugis_dugdale_curve(lam, A=[0.0, 1e-7])
    assert np.isinf(c0.m[0])
    assert c0.F[1] == pytest.approx(c0.F[0], rel=1e-6)
    assert c0.Delta[1] == pytest.approx(c0.Delta[0], rel=1e-6)
    assert c0.C[1] == pytest.approx(c0.C[0], rel=1e-6)


def test_md_large_lambda_is_jkr_curve():
    A = np.linspace(0.3, 2.5, 12)
    c = maugis_dugdale_curve(200.0, A=A)
    np.testing.assert_allclose(c.F, A**3 - np.sqrt(6 * A**3), atol=1e-3)      # JKR in JG units
    np.testing.assert_allclose(c.Delta, A**2 - np.sqrt(8 * A / 3), atol=1e-3)


def test_md_small_lambda_is_dmt_curve():
    A = np.linspace(0.3, 2.5, 12)
    c = maugis_dugdale_curve(1e-4, A=A)
    np.testing.assert_allclose(c.F, A**3 - 2.0, atol=0.01)                  # DMT in JG units


# ----------------------------------------------------------------------------------------------
# Maugis-Dugdale: pull-off
# ----------------------------------------------------------------------------------------------

def test_md_pull_off_limits():
    assert maugis_dugdale_pull_off(0.01) == pytest.approx(-2.0, rel=0.01)   # DMT
    assert maugis_dugdale_pull_off(20.0) == pytest.approx(-1.5, rel=0.02)   # JKR
    assert maugis_dugdale_pull_off(20.0, "displacement") == pytest.approx(-5 / 6, rel=0.01)


def test_md_pull_off_monotone_and_bounded():
    lams = np.array([0.01, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 20.0])
    F = maugis_dugdale_pull_off(lams)
    assert np.all(np.diff(F) > 0)
    assert np.all(F > -2.0) and np.all(F < -1.5)


def test_md_pull_off_against_johnson_greenwood_fit():
    # JG (1997): F = -7/4 + 1/4 (4.04 lam^1.4 - 1)/(4.04 lam^1.4 + 1), about 1-2 % accurate
    lams = np.array([0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0])
    F = maugis_dugdale_pull_off(lams)
    np.testing.assert_allclose(F, johnson_greenwood_pull_off_fit(lams), rtol=0.02)
    # lambda = 1 value (exact MD): -1.6007 pi R dgamma
    assert maugis_dugdale_pull_off(1.0) == pytest.approx(-1.6007, abs=2e-4)


def test_md_pull_off_point_is_minimum_of_curve():
    for lam in (0.3, 1.0, 3.0):
        p = maugis_dugdale_pull_off_point(lam)
        c = maugis_dugdale_curve(lam, A=np.linspace(0, 3, 3001))
        assert p.force <= c.F.min() + 1e-12
        assert p.force == pytest.approx(c.F.min(), abs=1e-5)
        pd = maugis_dugdale_pull_off_point(lam, "displacement")
        assert pd.approach == pytest.approx(c.Delta.min(), abs=1e-5)
        assert pd.force >= p.force          # fixed grips: jump-off at a smaller tension


def test_md_small_lambda_pull_off_location():
    # force control: the pull-off contact radius shrinks to 0 with lambda (A ~ 2 lambda)
    for lam in (0.01, 0.1):
        assert 0 < maugis_dugdale_pull_off_point(lam).contact_radius < 3 * lam
    # displacement control: no jump (minimum of Delta at the A = 0 end point) below
    # lambda = 0.938 (Johnson & Greenwood 1997), a jump at A > 0 above it
    for lam in (0.1, 0.9):
        p = maugis_dugdale_pull_off_point(lam, "displacement")
        assert p.contact_radius == 0.0
        assert p.force == pytest.approx(maugis_dugdale_curve(lam, A=[0.0]).F[0], rel=1e-12)
    assert maugis_dugdale_pull_off_point(1.0, "displacement").contact_radius > 0.05


# ----------------------------------------------------------------------------------------------
# Maugis-Dugdale: dimensional
# ----------------------------------------------------------------------------------------------

def test_md_dimensional_pull_off():
    lam = maugis_parameter(R, DG, ES, Z0)
    F = maugis_dugdale_pull_off_force(R, DG, ES, Z0)
    assert F == pytest.approx(maugis_dugdale_pull_off(lam) * np.pi * R * DG, rel=1e-12)
    assert F < 0
    assert maugis_dugdale_pull_off_magnitude(R, DG, ES, Z0) == pytest.approx(-F)
    assert -2 * np.pi * R * DG < F < -1.5 * np.pi * R * DG


def test_md_force_control_returns_stable_branch():
    Fp = maugis_dugdale_pull_off_force(R, DG, ES, Z0)
    F = np.array([0.9 * Fp, 0.5 * Fp, 0.0, -3 * Fp])
    s = maugis_dugdale(R, DG, ES, Z0, force=F)
    np.testing.assert_allclose(s.force, F, rtol=1e-9, atol=1e-12 * abs(Fp))
    # stable: dF/da > 0 at the returned state
    s_plus = maugis_dugdale(R, DG, ES, Z0, a=s.contact_radius * (1 + 1e-6))
    assert np.all(s_plus.force > s.force)
    # the unstable branch exists for the tensile forces and has a smaller a
    c = maugis_dugdale_curve(s.lam, A=np.linspace(0, s.A_M[0], 2000))
    assert np.any(np.abs(c.F - s.F_M[0]) < 2e-3)
    with pytest.raises(InputError):
        maugis_dugdale(R, DG, ES, Z0, force=1.01 * Fp)


def test_md_displacement_control_roundtrip():
    s = maugis_dugdale(R, DG, ES, Z0, a=np.array([20e-9, 60e-9, 150e-9]))
    s2 = maugis_dugdale(R, DG, ES, Z0, approach=s.approach)
    np.testing.assert_allclose(s2.contact_radius, s.contact_radius, rtol=1e-8)
    a_s, F_s, d_s = maugis_dugdale_scales(R, DG, ES)
    np.testing.assert_allclose(s.approach, s.Delta_M * d_s, rtol=1e-14)
    # A.24 with E*^2: d_s = (9 pi^2 dgamma^2 R / (16 E*^2))^(1/3)
    assert d_s == pytest.approx((9 * np.pi**2 * DG**2 * R / (16 * ES**2)) ** (1 / 3), rel=1e-14)
    np.testing.assert_allclose(s.cohesive_radius, s.m * s.contact_radius, rtol=1e-14)


@pytest.mark.parametrize("lam_target", [0.3, 1.0, 3.0])
def test_md_pressure_integrates_to_force(lam_target):
    # pick z0 to reach the wanted lambda
    z0 = Z0 * maugis_parameter(R, DG, ES, Z0) / lam_target
    Fp = maugis_dugdale_pull_off_force(R, DG, ES, z0)
    for F in (0.5 * Fp, 2.0 * abs(Fp)):
        s = maugis_dugdale(R, DG, ES, z0, force=F)
        a, c = s.contact_radius, s.cohesive_radius

        def p(r):
            return maugis_dugdale_pressure(r, R, DG, ES, z0, a=a)

        # Gauss-Legendre; r = a sin(t) on [0, a] removes the square-root edge behaviour
        x, w = np.polynomial.legendre.leggauss(200)
        t = np.pi / 4 * (x + 1)
        inner = np.pi / 4 * np.sum(w * 2 * np.pi * a * np.sin(t) * a * np.cos(t) * p(a * np.sin(t)))
        r = a + (c - a) * (x + 1) / 2
        ring = (c - a) / 2 * np.sum(w * 2 * np.pi * r * p(r))
        assert ring == pytest.approx(-s.sigma0 * np.pi * (c**2 - a**2), rel=1e-10)
        assert inner + ring == pytest.approx(F, rel=1e-6)
        assert p(1.0001 * c) == 0.0
        assert p(a) == pytest.approx(-s.sigma0, rel=1e-12)   # continuous at the contact edge


def test_md_hertz_limit():
    # tiny adhesion: lambda -> 0 and dgamma -> 0 recovers a^3 = 3 R F / (4 E*)
    R_, E_, z0 = 1e-3, 1e11, 0.2e-9
    s = maugis_dugdale(R_, 1e-7, E_, z0, force=1e-3)
    h = hertz(force=1e-3, radius=R_, E_star=E_)
    assert s.lam < 1e-3
    assert s.contact_radius == pytest.approx(h.contact_radius, rel=1e-5)
    assert s.approach == pytest.approx(h.approach, rel=1e-5)
