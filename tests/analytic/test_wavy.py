"""Sphere on an axisymmetric wavy surface, Maugis-Dugdale (Paper A Eqs. 25-30; Guduru 2007)."""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import struve

from tribobem.analytic import (
    guduru, guduru_cohesive_equation, guduru_curve, guduru_hertz_force, guduru_jkr_curve,
    guduru_parameters, maugis_dugdale, maugis_dugdale_curve, maugis_dugdale_pull_off,
)
from tribobem.analytic.wavy import _struve0

# Paper A section 5.2: rigid sphere, E = 73 GPa, nu = 0.17, R = 2.5 mm, xi = 0.8 um
E_STAR = 73e9 / (1 - 0.17**2)
RADIUS, XI = 2.5e-3, 0.8e-6
DGAMMA, Z0 = 0.05, 0.3e-9          # gives lambda = 3.99, beta = 0.0196


def test_fast_struve_h0_accuracy():
    x = np.random.default_rng(0).uniform(0, 60, 20000)
    np.testing.assert_allclose(_struve0(x), struve(0, x), atol=1e-9)


def test_alpha_zero_is_maugis_dugdale_exactly():
    beta, lam = 0.05, 1.3
    ab = np.linspace(0.01, 3.0, 120)
    c = guduru_curve(0.0, beta, lam, ab)
    b3 = (beta / 3) ** (1 / 3)
    md = maugis_dugdale_curve(lam, A=2 * ab * b3)          # A_M = 2 abar (beta/3)^(1/3)
    np.testing.assert_allclose(c.P, md.F, rtol=1e-8, atol=1e-10)                 # P = F_M
    np.testing.assert_allclose(4 * b3**2 * c.Delta, md.Delta, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(c.m, md.m, rtol=1e-8)


def test_alpha_zero_dimensional_equals_maugis_dugdale():
    a = np.array([0.2, 0.5, 1.5]) * 1e-6
    g = guduru(RADIUS, 0.0, XI, DGAMMA, E_STAR, Z0, a)
    md = maugis_dugdale(RADIUS, DGAMMA, E_STAR, Z0, a=a)
    np.testing.assert_allclose(g.force, md.force, rtol=1e-8)
    np.testing.assert_allclose(g.approach, md.approach, rtol=1e-8)
    np.testing.assert_allclose(g.cohesive_radius, md.cohesive_radius, rtol=1e-8)


def _gap_w_abel(abar, m):
    """gap_w(c)/A by an independent (Abel) form: 2 pi int_a^c (u H0(2 pi u) - a H0(2 pi a))/sqrt(c^2-u^2) du."""
    c = abar * m
    h0a = abar * struve(0, 2 * np.pi * abar)
    f = lambda th: c * np.sin(th) * struve(0, 2 * np.pi * c * np.sin(th)) - h0a  # noqa: E731  u = c sin(th)
    return 2 * np.pi * quad(f, np.arcsin(1 / m), np.pi / 2, epsabs=1e-14, epsrel=1e-13, limit=400)[0]


def test_abel_form_reproduces_hertz_gap():
    # the same Abel representation gives the Hertz gap of A.22:
    # (2/pi) int_a^c (t^2 - a^2)/(R sqrt(c^2-t^2)) dt = a^2/(pi R) [s + (m^2-2) atan s]
    a, Rr = 1.0, 1.0
    for m in (1.01, 1.7, 5.0):
        c = m * a
        num = 2 / np.pi * quad(lambda th: (c**2 * np.sin(th) ** 2 - a**2) / Rr, np.arcsin(1 / m), np.pi / 2)[0]
        s = np.sqrt(m * m - 1)
        assert num == pytest.approx(a**2 / (np.pi * Rr) * (s + (m * m - 2) * np.arctan(s)), rel=1e-10)


@pytest.mark.parametrize("abar,m", [(0.3, 1.01), (0.7, 1.5), (1.3, 2.7), (2.2, 1.2), (0.2, 8.0), (2.9, 4.0)])
def test_eq26_wavy_bracket_against_direct_gap(abar, m):
    alpha, beta, lam = 0.37, 0.08, 1.1
    full = guduru_cohesive_equation(abar, m, alpha, beta, lam)
    md_only = guduru_cohesive_equation(abar, m, 0.0, beta, lam)
    kappa = 2 * np.pi * lam * alpha * (beta / 3) ** (2 / 3)     # = A/h0
    assert (full - md_only) / kappa == pytest.approx(_gap_w_abel(abar, m), rel=1e-8, abs=1e-11)


def test_eq26_vanishes_at_contact_edge():
    ab = np.array([0.1, 0.77, 1.9, 3.3])
    np.testing.assert_allclose(guduru_cohesive_equation(ab, 1.0, 0.3, 0.05, 2.0), 0.0, atol=1e-10)


def test_hertz_force_and_approach_terms_against_sneddon():
    # Sneddon: P = 2E* int_0^a x^2 f'(x)/sqrt(a^2-x^2) dx, delta = a int_0^a f'(x)/sqrt(a^2-x^2) dx,
    # f = r^2/(2R) + A(1 - cos 2 pi r/xi); x = a sin(t)
    Es, Rr, A, xi, dg = 2.0, 1.0, 0.004, 0.1, 0.3
    alpha, beta, _ = guduru_parameters(Rr, A, xi, dg, Es)
    for a in (0.013, 0.05, 0.17, 0.31):
        fp = lambda x: x / Rr + 2 * np.pi * A / xi * np.sin(2 * np.pi * x / xi)  # noqa: E731
        P = 2 * Es * quad(lambda t: (a * np.sin(t)) ** 2 * fp(a * np.sin(t)), 0, np.pi / 2, epsrel=1e-13)[0]
        d = a * quad(lambda t: fp(a * np.sin(t)), 0, np.pi / 2, epsrel=1e-13)[0]
        ab = a / xi
        assert guduru_hertz_force(ab, alpha, beta) * np.pi * dg * Rr == pytest.approx(P, rel=1e-10)
        # Paper A Eq. 29 as printed, with a^3 and pi^2 restored
        z = 2 * np.pi * ab
        p29 = 4 * beta * (2 * ab**3 / 3 + alpha * (4 * np.pi**2 * ab**3 / 3 + np.pi * ab / 2 * struve(1, z)
                                                  - np.pi**2 * ab**2 * struve(2, z)))
        assert p29 == pytest.approx(guduru_hertz_force(ab, alpha, beta), rel=1e-10)
        # approach of the JKR form with its adhesive term removed = Hertz + wavy terms of Eq. 28
        j = guduru_jkr_curve(alpha, beta, ab)
        assert (j.Delta + np.sqrt(ab / beta)) * xi**2 / Rr == pytest.approx(d, rel=1e-10)


def test_solution_satisfies_eq26_and_is_first_root():
    alpha, beta, lam = 0.3, 0.0196, 3.99
    ab = np.linspace(0.05, 4.0, 40)
    c = guduru_curve(alpha, beta, lam, ab)
    np.testing.assert_allclose(guduru_cohesive_equation(ab, c.m, alpha, beta, lam), 1.0, rtol=1e-10)
    # the gap reaches h0 for the first time at c: below it the left side stays < 1
    for a_i, m_i in zip(ab[::4], c.m[::4]):
        mm = np.linspace(1.0, m_i, 400)[:-1]
        assert np.all(guduru_cohesive_equation(a_i, mm, alpha, beta, lam) < 1.0)


def test_jkr_limit():
    ab = np.linspace(0.05, 4.0, 60)
    for alpha in (0.1, 0.3):
        c = guduru_curve(alpha, 0.02, 1000.0, ab)
        j = guduru_jkr_curve(alpha, 0.02, ab)
        np.testing.assert_allclose(c.P, j.P, atol=2e-5)
        np.testing.assert_allclose(c.Delta, j.Delta, atol=2e-4)
        np.testing.assert_allclose(c.m, 1.0, atol=1e-4)
    # and alpha = 0 of the JKR form is JKR in Johnson-Greenwood units
    beta = 0.05
    A = 2 * ab * (beta / 3) ** (1 / 3)
    j0 = guduru_jkr_curve(0.0, beta, ab)
    np.testing.assert_allclose(j0.P, A**3 - np.sqrt(6 * A**3), rtol=1e-12, atol=1e-14)


def _local_minima(y):
    return np.flatnonzero((y[1:-1] < y[:-2]) & (y[1:-1] < y[2:])) + 1


def test_paper_a_wavy_curves_have_jumps_and_toughen():
    alpha0, beta, lam = guduru_parameters(RADIUS, 0.0, XI, DGAMMA, E_STAR, Z0)
    assert lam == pytest.approx(3.99, abs=0.01) and beta == pytest.approx(0.0196, abs=1e-4)
    ab = np.linspace(0.005, 4.0, 400)
    smooth = maugis_dugdale_pull_off(lam)
    pull = []
    for alpha in (0.1, 0.2, 0.3):
        A = alpha * XI**2 / RADIUS
        assert guduru_parameters(RADIUS, A, XI, DGAMMA, E_STAR)[0] == pytest.approx(alpha)
        c = guduru_curve(alpha, beta, lam, ab)
        # continuous, smooth curve (abar step 0.01): no outlier step, i.e. small second
        # differences (a jump J of the cohesive-zone root would show up as ~J here)
        assert np.max(np.abs(np.diff(c.P, 2))) < 0.01
        assert np.max(np.abs(np.diff(c.Delta, 2))) < 0.02
        # several local minima of P (force-controlled jumps, Paper A Fig. 6)
        assert _local_minima(c.P).size >= 2
        pull.append(c.P.min())
    # waviness raises the pull-off force above the smooth sphere's, more so for larger alpha
    assert pull[0] < smooth and np.all(np.diff(pull) < 0)


def test_curve_is_continuous_under_refinement():
    ab1 = np.linspace(0.3, 4.0, 200)
    ab2 = np.linspace(0.3, 4.0, 399)
    c1 = guduru_curve(0.3, 0.0196, 3.99, ab1)
    c2 = guduru_curve(0.3, 0.0196, 3.99, ab2)
    j1 = np.max(np.abs(np.diff(c1.P)))
    j2 = np.max(np.abs(np.diff(c2.P)))
    assert j2 < 0.6 * j1                      # no jump that survives refinement
    np.testing.assert_allclose(c2.P[::2], c1.P, rtol=1e-9, atol=1e-12)


def test_dimensional_wrapper_scaling():
    alpha, beta, lam = guduru_parameters(RADIUS, 0.2 * XI**2 / RADIUS, XI, DGAMMA, E_STAR, Z0)
    a = np.array([0.5, 1.0, 2.0]) * XI
    g = guduru(RADIUS, 0.2 * XI**2 / RADIUS, XI, DGAMMA, E_STAR, Z0, a)
    c = guduru_curve(alpha, beta, lam, a / XI)
    np.testing.assert_allclose(g.force, c.P * np.pi * DGAMMA * RADIUS, rtol=1e-12)
    np.testing.assert_allclose(g.approach, c.Delta * XI**2 / RADIUS, rtol=1e-12)
    np.testing.assert_allclose(g.cohesive_radius, c.m * a, rtol=1e-12)
