"""Westergaard, bisinusoidal (JGH 1985) asymptotes and the Paper A bisinusoidal pull-off fit."""

import numpy as np
import pytest
from scipy import fft
from scipy.integrate import quad

from tribobem.analytic import (
    bisinusoidal_asymptotes, bisinusoidal_curvature_radius, bisinusoidal_full_contact_pressure,
    bisinusoidal_pull_off_fit, bisinusoidal_pull_off_fit_magnitude, hertz, westergaard,
    westergaard_contact_fraction, westergaard_pressure,
)
from tribobem.errors import InputError

A, L, ES = 1e-8, 1e-6, 1e11


# ----------------------------------------------------------------------------------------------
# Westergaard
# ----------------------------------------------------------------------------------------------

def test_westergaard_contact_width_and_mean_pressure():
    ps = np.pi * ES * A / L
    for r in (0.05, 0.3, 0.8):
        w = westergaard(r * ps, A, L, ES)
        assert w.p_star == pytest.approx(ps, rel=1e-15)
        assert np.sin(np.pi * w.contact_half_width / L) ** 2 == pytest.approx(r, rel=1e-12)
        assert w.contact_fraction == pytest.approx(2 * w.contact_half_width / L, rel=1e-15)
        a = w.contact_half_width
        mean = quad(w.pressure, -a, a, epsrel=1e-12, limit=200)[0] / L
        assert mean == pytest.approx(r * ps, rel=1e-8)
        assert w.pressure(a * 1.0001) == 0.0
        assert w.pressure(0.0) == pytest.approx(w.max_pressure, rel=1e-12)
        assert w.pressure(L) == pytest.approx(w.max_pressure, rel=1e-12)   # periodic
    assert westergaard_contact_fraction(2 * ps, A, L, ES) == 1.0
    full = westergaard(1.5 * ps, A, L, ES)
    x = np.linspace(-L / 2, L / 2, 7)
    np.testing.assert_allclose(full.pressure(x), 1.5 * ps + ps * np.cos(2 * np.pi * x / L), rtol=1e-12)


@pytest.mark.parametrize("ratio", [0.2, 0.6])
def test_westergaard_pressure_closes_the_gap(ratio):
    """Elastic check: the half-plane displacement of p(x) flattens h inside the contact only."""
    n = 2**14
    x = (np.arange(n) + 0.5) / n * L - L / 2
    ps = np.pi * ES * A / L
    p = westergaard_pressure(x, ratio * ps, A, L, ES)
    k = 2 * np.pi * np.abs(fft.rfftfreq(n, d=L / n))
    with np.errstate(divide="ignore"):
        green = np.where(k > 0, 2.0 / (ES * k), 0.0)      # plane strain: u_k = 2 p_k / (E* |k|)
    u = fft.irfft(green * fft.rfft(p), n=n)
    h = A * (1 - np.cos(2 * np.pi * x / L))
    g = h + u
    a = westergaard(ratio * ps, A, L, ES).contact_half_width
    inside = np.abs(x) < 0.98 * a
    g0 = np.mean(g[inside])
    assert np.std(g[inside]) < 1e-4 * A                   # flat in contact
    assert np.min(g[~inside] - g0) > -1e-4 * A            # no interpenetration outside
    assert np.mean(g[~inside] - g0) > 0.05 * A
    # a wrong profile (e.g. Hertz-like semi-ellipse of the same width and load) does not close it
    p_bad = np.where(np.abs(x) < a, np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)), 0.0)
    p_bad *= ratio * ps * n / p_bad.sum()
    g_bad = h + fft.irfft(green * fft.rfft(p_bad), n=n)
    assert np.std(g_bad[inside]) > 30 * np.std(g[inside])


def test_westergaard_bad_input():
    with pytest.raises(InputError):
        westergaard(-1.0, A, L, ES)
    with pytest.raises(InputError):
        westergaard(1.0, A, -L, ES)


# ----------------------------------------------------------------------------------------------
# bisinusoidal asymptotes
# ----------------------------------------------------------------------------------------------

def _pk_periodic(h, size, E, pbar, tol=1e-10, maxit=2000):
    """Minimal Polonsky-Keer solver on a periodic grid (spectral kernel 2/(E* |q|)), test only."""
    n = h.shape[0]
    q = 2 * np.pi * fft.fftfreq(n, d=size / n)
    qr = 2 * np.pi * fft.rfftfreq(n, d=size / n)
    Q = np.sqrt(q[:, None] ** 2 + qr[None, :] ** 2)
    with np.errstate(divide="ignore"):
        G = np.where(Q > 0, 2 / (E * Q), 0.0)

    def conv(p):
        return fft.irfft2(G * fft.rfft2(p), s=h.shape)

    p = np.full(h.shape, pbar)
    t = np.zeros_like(p)
    g_old, delta = 1.0, 0.0
    for _ in range(maxit):
        S = p > 0
        g = conv(p) + h
        g -= g[S].mean()
        Gn = np.sum(g[S] ** 2)
        t[S] = g[S] + delta * Gn / g_old * t[S]
        t[~S] = 0
        g_old = Gn
        r = conv(t)
        r -= r[S].mean()
        tau = np.sum(g[S] * t[S]) / np.sum(r[S] * t[S])
        p_old = p.copy()
        p[S] -= tau * t[S]
        p[p < 0] = 0
        overlap = (p == 0) & (g < 0)
        delta = 0.0 if overlap.any() else 1.0
        p[overlap] -= tau * g[overlap]
        p *= pbar / p.mean()
        if np.abs(p - p_old).sum() / p.sum() < tol:
            return p
    raise RuntimeError("test PK solver did not converge")


def _bisinusoid(n, size, amp):
    x = (np.arange(n) + 0.5) / n * size - size / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return amp * np.cos(2 * np.pi * X / size) * np.cos(2 * np.pi * Y / size)


def test_bisinusoidal_formulas():
    D = 5e-9
    ps = bisinusoidal_full_contact_pressure(D, L, ES)
    assert ps == pytest.approx(np.sqrt(2) * np.pi * ES * D / L, rel=1e-15)
    r = np.array([1e-3, 0.01, 0.5, 0.97, 1.2])
    s = bisinusoidal_asymptotes(r * ps, D, L, ES)
    assert s.crest_radius == pytest.approx(L**2 / (4 * np.pi**2 * D))
    np.testing.assert_allclose(s.contact_fraction_light, np.pi * (3 / (8 * np.pi)) ** (2 / 3) * r ** (2 / 3),
                               rtol=1e-12)
    # = two Hertz crests per cell, each carrying half the cell load
    hz = hertz(force=r * ps * L**2 / 2, radius=s.crest_radius, E_star=ES)
    np.testing.assert_allclose(s.contact_fraction_light, 2 * np.pi * hz.contact_radius**2 / L**2, rtol=1e-12)
    np.testing.assert_allclose(s.contact_fraction_full, 1 - 3 / (2 * np.pi) * np.clip(1 - r, 0, None), rtol=1e-12)
    np.testing.assert_allclose(1 - s.contact_fraction_full, 2 * np.pi * s.lake_radius**2 / L**2, rtol=1e-12,
                               atol=1e-15)
    assert s.contact_fraction_full[-1] == 1.0 and s.lake_radius[-1] == 0.0


def test_bisinusoidal_asymptotes_against_periodic_bem():
    """Independent check of both JGH asymptotes with a periodic boundary-element solution."""
    D, size, E = 0.01, 1.0, 1.0
    ps = bisinusoidal_full_contact_pressure(D, size, E)
    # light load: Hertz spots (pixel counting at 256^2, about 20 cells per spot radius)
    h = _bisinusoid(256, size, D)
    p = _pk_periodic(h, size, E, 0.005 * ps)
    light = bisinusoidal_asymptotes(0.005 * ps, D, size, E).contact_fraction_light
    assert np.mean(p > 0) == pytest.approx(light, rel=0.06)
    # near full contact: two lakes per cell, 1 - A/A0 = 3/(2 pi) (1 - pbar/p*)
    h = _bisinusoid(128, size, D)
    for r in (0.9, 0.95):
        p = _pk_periodic(h, size, E, r * ps)
        lakes = 1 - bisinusoidal_asymptotes(r * ps, D, size, E).contact_fraction_full
        assert 1 - np.mean(p > 0) == pytest.approx(lakes, rel=0.06)


# ----------------------------------------------------------------------------------------------
# Paper A bisinusoidal pull-off fit
# ----------------------------------------------------------------------------------------------

def test_bisinusoidal_curvature_radius():
    S, lx, ly = 5e-9, 40e-6, 12e-6
    Rx, Ry = lx**2 / (4 * np.pi**2 * S), ly**2 / (4 * np.pi**2 * S)
    assert bisinusoidal_curvature_radius(S, lx, ly) == pytest.approx(np.sqrt(Rx * Ry), rel=1e-14)
    assert bisinusoidal_curvature_radius(S, lx, ly) == pytest.approx(lx * ly / (4 * np.pi**2 * S), rel=1e-14)


def test_bisinusoidal_pull_off_fit():
    Rc, dg = 300e-6, 0.05
    F1 = bisinusoidal_pull_off_fit(100e9, Rc, dg, 1.0)
    assert F1 == pytest.approx(-10.39 * Rc * dg, rel=1e-14)
    assert bisinusoidal_pull_off_fit_magnitude(100e9, Rc, dg, 1.0) == pytest.approx(-F1)
    # two crests per cell: between 2x JKR (1.5 pi) and 2x DMT (2 pi) per crest
    assert 2 * 1.5 * np.pi * Rc * dg < -F1 < 2 * 2 * np.pi * Rc * dg
    # beta = 0: independent of E*; linear in R_c and dgamma; k^0.041
    assert bisinusoidal_pull_off_fit(80e9, Rc, dg, 1.0) == pytest.approx(F1, rel=1e-14)
    assert bisinusoidal_pull_off_fit(80e9, 2 * Rc, 3 * dg, 1.0) == pytest.approx(6 * F1, rel=1e-14)
    assert bisinusoidal_pull_off_fit(80e9, Rc, dg, 0.1) == pytest.approx(F1 * 0.1**0.041, rel=1e-14)
    # general beta keeps the dimension of a force
    f = bisinusoidal_pull_off_fit_magnitude(1e11, Rc, dg, 0.5, beta=0.2)
    g = bisinusoidal_pull_off_fit_magnitude(1e11 * 7, Rc / 7, dg * 7, 0.5, beta=0.2)
    assert g == pytest.approx(f * 7 ** 0.2 * 7 ** -1.2 * 7 ** 0.8, rel=1e-12)
    with pytest.raises(InputError):
        bisinusoidal_pull_off_fit(1e11, Rc, dg, 1.5)
