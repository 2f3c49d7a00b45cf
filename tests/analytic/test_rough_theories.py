"""Greenwood-Williamson and Persson (thesis Eqs. 2.1-2.12)."""

import numpy as np
import pytest
from scipy import fft
from scipy.integrate import quad
from scipy.special import erf, erfc

from tribobem.analytic import (
    greenwood_williamson, greenwood_williamson_F, persson_area_self_affine, persson_contact_area,
    persson_G, persson_P_sigma, persson_self_affine_C0, persson_self_affine_G,
    persson_self_affine_psd,
)

ES = 1e11


# ----------------------------------------------------------------------------------------------
# Greenwood-Williamson
# ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("n", [0.0, 1.0, 1.5])
def test_gw_F_against_quadrature(n):
    for h in (-25.0, -3.0, -0.5, 0.0, 0.7, 2.0, 4.5, 7.0):
        ref = quad(lambda s: (s - h) ** n * np.exp(-s * s / 2), h, np.inf, epsrel=1e-13)[0] / np.sqrt(2 * np.pi)
        assert greenwood_williamson_F(n, h) == pytest.approx(ref, rel=1e-9)


def test_gw_F_closed_forms():
    h = np.linspace(-4, 6, 41)
    phi = np.exp(-h * h / 2) / np.sqrt(2 * np.pi)
    np.testing.assert_allclose(greenwood_williamson_F(0, h), erfc(h / np.sqrt(2)) / 2, rtol=1e-13)
    np.testing.assert_allclose(greenwood_williamson_F(1, h), phi - h * erfc(h / np.sqrt(2)) / 2, rtol=1e-11)
    # F_0(-inf) = 1: the normalised Gaussian (thesis Eq. 2.1 omits the sqrt(2 pi))
    assert greenwood_williamson_F(0, -40.0) == pytest.approx(1.0, rel=1e-14)


def test_gw_against_monte_carlo_summits():
    """Sum Hertz contacts over explicitly sampled Gaussian summits (independent of the F_n)."""
    rng = np.random.default_rng(12345)
    sigma, beta, eta, area = 2e-9, 5e-6, 1e12, 4e-7         # N = 400000 summits
    N = int(eta * area)
    z = rng.normal(0.0, sigma, N)
    for d in (0.0, 0.5 * sigma, 1.5 * sigma):
        w = np.clip(z - d, 0, None)
        n_mc = np.count_nonzero(w)
        A_mc = np.pi * beta * w.sum()
        F_mc = 4 / 3 * ES * np.sqrt(beta) * np.sum(w**1.5)
        gw = greenwood_williamson(d, sigma, beta, eta, ES, area)
        assert gw.n_contacts == pytest.approx(n_mc, rel=0.02)
        assert gw.contact_area == pytest.approx(A_mc, rel=0.02)
        assert gw.force == pytest.approx(F_mc, rel=0.02)
        assert gw.mean_pressure == pytest.approx(gw.force / area)


def test_gw_vectorised_and_monotone():
    d = np.linspace(-2, 4, 25) * 1e-9
    gw = greenwood_williamson(d, 1e-9, 1e-6, 1e12, ES, 1e-8)
    assert np.all(np.diff(gw.force) < 0) and np.all(np.diff(gw.contact_area) < 0)
    # large separation: F_n(h) ~ Gamma(n+1) phi(h)/h^(n+1)  -> A/F ratio grows like sqrt(h)
    h = 8.0
    phi = np.exp(-h * h / 2) / np.sqrt(2 * np.pi)
    assert greenwood_williamson_F(1.5, h) == pytest.approx(1.329340 * phi / h**2.5, rel=0.1)


# ----------------------------------------------------------------------------------------------
# Persson
# ----------------------------------------------------------------------------------------------

def test_persson_P_sigma_normalisation_and_force_balance():
    G, su = 4e14, 3e7
    top = su + 40 * np.sqrt(G)
    area = quad(lambda s: persson_P_sigma(s, su, G), 0, top, epsrel=1e-12, limit=200)[0]
    assert area == pytest.approx(persson_contact_area(su, G), rel=1e-9)
    assert area == pytest.approx(erf(su / (2 * np.sqrt(G))), rel=1e-9)
    load = quad(lambda s: s * persson_P_sigma(s, su, G), 0, top, epsrel=1e-12, limit=200)[0]
    assert load == pytest.approx(su, rel=1e-9)           # the contact carries the load
    assert persson_P_sigma(0.0, su, G) == 0.0            # boundary condition P(0) = 0


def test_persson_small_load_limits():
    G = 2.5e15
    su = 1e-4 * np.sqrt(G)
    assert persson_contact_area(su, G) == pytest.approx(su / np.sqrt(np.pi * G), rel=1e-7)
    # with G = E*^2 h'^2/8:  A/A0 -> sqrt(8/pi) sigma_u/(E* h')
    slope = 0.2
    a = persson_area_self_affine(1e3, ES, rms_slope=slope)
    assert a == pytest.approx(np.sqrt(8 / np.pi) * 1e3 / (ES * slope), rel=1e-7)


def test_self_affine_C0_matches_rms_and_eq_2_12():
    H, q0, qL, q1, rms = 0.8, 1e6, 1e5, 1e9, 5e-9
    C0 = persson_self_affine_C0(rms, H, q0, qL, q1)
    q = np.geomspace(qL, q1, 200001)
    C = persson_self_affine_psd(q, C0, H, q0, qL, q1)
    h2 = 2 * np.pi * np.trapezoid(q * C, q)
    assert h2 == pytest.approx(rms**2, rel=1e-6)
    # q1 -> inf: exactly Eq. 2.12, h^2 = pi C0 q0^2 / (alpha H), alpha = 1/(1 + H - H (qL/q0)^2)
    C0inf = persson_self_affine_C0(rms, H, q0, qL)
    alpha = 1 / (1 + H - H * (qL / q0) ** 2)
    assert rms**2 == pytest.approx(np.pi * C0inf * q0**2 / (alpha * H), rel=1e-14)


def test_persson_G_tabulated_callable_and_closed_form():
    H, q0, qL, q1 = 0.7, 1e6, 2e5, 5e8
    C0 = persson_self_affine_C0(3e-9, H, q0, qL, q1)
    q = np.geomspace(qL, q1, 100001)
    C = persson_self_affine_psd(q, C0, H, q0, qL, q1)
    G_closed = persson_self_affine_G(ES, C0, H, q0, qL, q1)
    assert persson_G(q, C, ES) == pytest.approx(G_closed, rel=1e-5)
    qq = np.array([qL, q0, q1])
    f = lambda x: persson_self_affine_psd(x, C0, H, q0, qL, q1)  # noqa: E731
    assert persson_G(qq, f, ES) == pytest.approx(G_closed, rel=1e-8)
    # partial band (magnification zeta = 20 from qL)
    assert persson_G(q, C, ES, q_upper=20 * qL) == pytest.approx(
        persson_self_affine_G(ES, C0, H, q0, qL, 20 * qL), rel=1e-5)
    Gc = persson_G(q, C, ES, cumulative=True)
    assert Gc[0] == 0 and Gc[-1] == pytest.approx(G_closed, rel=1e-5) and np.all(np.diff(Gc) > 0)
    # ... and on the way: the partial band up to zeta = 20
    assert np.interp(20 * qL, q, Gc) == pytest.approx(persson_self_affine_G(ES, C0, H, q0, qL, 20 * qL), rel=1e-5)
    # contact area from the PSD parameters equals the rms-slope route with h'^2 = 8 G / E*^2
    slope = np.sqrt(8 * G_closed) / ES
    a1 = persson_area_self_affine(1e6, ES, rms=3e-9, hurst=H, q0=q0, qL=qL, q1=q1)
    a2 = persson_area_self_affine(1e6, ES, rms_slope=slope)
    assert a1 == pytest.approx(a2, rel=1e-12)
    # larger magnification -> smaller area
    a_low = persson_area_self_affine(1e6, ES, rms=3e-9, hurst=H, q0=q0, qL=qL, q1=q1, magnification=10)
    assert a_low > a1


def test_psd_convention_on_a_synthetic_surface():
    """h_rms^2 = int d^2q C and h'^2 = int d^2q q^2 C = 8 G/E*^2 on a random-phase surface."""
    n, size = 512, 1e-6
    dq = 2 * np.pi / size
    H, qL, q0, q1 = 0.8, 8 * dq, 16 * dq, 200 * dq
    C0 = persson_self_affine_C0(2e-9, H, q0, qL, q1)
    kx = 2 * np.pi * fft.fftfreq(n, d=size / n)
    Q = np.hypot(kx[:, None], kx[None, :])
    amp = np.sqrt(persson_self_affine_psd(Q, C0, H, q0, qL, q1) * dq**2)
    phase = np.exp(2j * np.pi * np.random.default_rng(1).random((n, n)))
    hq = amp * phase
    h = np.real(fft.ifft2(hq)) * n * n * np.sqrt(2)      # real part keeps half the power
    hx = np.real(fft.ifft2(1j * kx[:, None] * hq)) * n * n * np.sqrt(2)
    hy = np.real(fft.ifft2(1j * kx[None, :] * hq)) * n * n * np.sqrt(2)
    assert np.sqrt(np.mean(h**2)) == pytest.approx(2e-9, rel=0.05)
    q = np.geomspace(qL, q1, 20001)
    G = persson_G(q, persson_self_affine_psd(q, C0, H, q0, qL, q1), ES)
    assert np.mean(hx**2 + hy**2) == pytest.approx(8 * G / ES**2, rel=0.05)
