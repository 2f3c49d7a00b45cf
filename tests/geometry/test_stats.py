"""Statistics: analytic sines, planes, paraboloids, the PSD normalisation, the ACF."""

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.geometry import (
    acf,
    correlation_length,
    gaussian_surface,
    kurtosis,
    psd,
    rms_curvature,
    rms_height,
    rms_slope,
    self_affine_surface,
    skewness,
    summary,
)
from tribobem.grid import Grid

A = 3e-9


@pytest.fixture
def pgrid():
    return Grid(64, 32, 2e-6, 1e-6, periodic=True)


def test_sine_periodic_exact(pgrid):
    k = 2 * np.pi * 3 / pgrid.lx
    X, _ = pgrid.meshgrid()
    h = A * np.sin(k * X)
    assert rms_height(h, pgrid) == pytest.approx(A / np.sqrt(2), rel=1e-12)
    assert rms_slope(h, pgrid) == pytest.approx(A * k / np.sqrt(2), rel=1e-12)
    assert rms_curvature(h, pgrid) == pytest.approx(A * k**2 / (2 * np.sqrt(2)), rel=1e-12)
    assert skewness(h) == pytest.approx(0.0, abs=1e-12)
    assert kurtosis(h) == pytest.approx(1.5, rel=1e-12)


def test_product_of_sines_periodic(pgrid):
    kx, ky = 2 * np.pi * 2 / pgrid.lx, 2 * np.pi * 5 / pgrid.ly
    X, Y = pgrid.meshgrid()
    h = A * np.sin(kx * X) * np.cos(ky * Y) + 1e-6  # a mean offset must not matter
    assert rms_height(h, pgrid) == pytest.approx(A / 2, rel=1e-12)
    assert rms_slope(h, pgrid) == pytest.approx(A * np.hypot(kx, ky) / 2, rel=1e-12)
    assert rms_curvature(h, pgrid) == pytest.approx(A * (kx**2 + ky**2) / 4, rel=1e-12)


def test_sine_non_periodic_finite_differences():
    # 200 cells per wavelength: the stencil error ~ (k dx)^2 / 24 is 4e-5; the one-sided
    # differences miss one row of 400, hence the 5e-3 tolerance
    g = Grid(400, 8, 1.0, 0.02)
    k = 2 * np.pi * 2
    X, _ = g.meshgrid()
    h = A * np.sin(k * X)
    assert rms_slope(h, g) == pytest.approx(A * k / np.sqrt(2), rel=5e-3)
    assert rms_slope(h, g, method="central") == pytest.approx(A * k / np.sqrt(2), rel=5e-3)
    assert rms_curvature(h, g) == pytest.approx(A * k**2 / (2 * np.sqrt(2)), rel=5e-3)


def test_plane_and_paraboloid_exact_fd():
    g = Grid(30, 20, 3e-6, 1e-6)
    X, Y = g.meshgrid()
    h = 0.01 * X - 0.02 * Y
    for method in ("forward", "central"):
        assert rms_slope(h, g, method=method) == pytest.approx(np.hypot(0.01, 0.02), rel=1e-10)
    R = 1e-3
    assert rms_curvature((X**2 + Y**2) / (2 * R), g) == pytest.approx(1 / R, rel=1e-8)


def test_method_validation(pgrid):
    with pytest.raises(InputError, match="stats.method"):
        rms_slope(np.zeros(pgrid.shape), pgrid, method="magic")
    with pytest.raises(InputError, match="does not match"):
        rms_slope(np.zeros((3, 3)), pgrid)


def test_psd_identity_annulus_exact(pgrid):
    h = gaussian_surface(pgrid, 1e-9, pgrid.lx / 40, seed=1)
    q, C = psd(h, pgrid, average="annulus")
    dq = q[1] - q[0]
    assert np.sum(C * 2 * np.pi * q * dq) / (2 * np.pi) ** 2 == pytest.approx(rms_height(h) ** 2, rel=1e-10)
    # second moment ~ rms slope^2 (spectral derivative on the periodic grid); not exact,
    # as q is the bin centre rather than each mode's |q|
    assert np.sum(q**2 * C * 2 * np.pi * q * dq) / (2 * np.pi) ** 2 == pytest.approx(
        rms_slope(h, pgrid) ** 2, rel=0.02
    )
    q, C = psd(h, pgrid, nbins=7, average="annulus")
    assert np.sum(C * q) * (q[1] - q[0]) / (2 * np.pi) == pytest.approx(rms_height(h) ** 2, rel=1e-10)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_psd_identity_mean_estimator(seed):
    g = Grid.square(256, 1e-5, periodic=True)
    for h in (gaussian_surface(g, 2e-9, g.lx / 8, seed=seed),
              self_affine_surface(g, 0.7, rms_height=2e-9, rolloff_wavelength=g.lx / 16, seed=seed)):
        q, C = psd(h, g)
        dq = q[1] - q[0]
        assert np.sum(C * 2 * np.pi * q * dq) / (2 * np.pi) ** 2 == pytest.approx(rms_height(h) ** 2, rel=0.02)


def test_psd_of_sine_peaks_at_k(pgrid):
    k = 2 * np.pi * 6 / pgrid.lx
    X, _ = pgrid.meshgrid()
    q, C = psd(A * np.cos(k * X), pgrid)
    assert q[np.argmax(C)] == pytest.approx(k, rel=0.5 * (q[1] - q[0]) / k)
    with pytest.raises(InputError, match="stats.average"):
        psd(X, pgrid, average="median")


def test_acf_periodic_sine(pgrid):
    k = 2 * np.pi * 4 / pgrid.lx
    X, _ = pgrid.meshgrid()
    h = A * np.cos(k * X)
    r, R = acf(h, pgrid)
    assert r[0] == 0.0 and R[0] == pytest.approx(A**2 / 2, rel=1e-12)
    assert r.max() <= 0.5 * min(pgrid.lx, pgrid.ly) * (1 + 1e-12)
    assert np.all(np.diff(r) > 0)


def _acf_brute_force(h, g):
    """Radial ACF by explicit loops over lags (reference for :func:`acf`)."""
    d = h - h.mean()
    nx, ny = d.shape
    rmax, step = 0.5 * min(g.lx, g.ly), min(g.dx, g.dy)
    sums, cnts, rs = {}, {}, {}
    for ix in range(-(nx - 1), nx):
        for iy in range(-(ny - 1), ny):
            r = np.hypot(ix * g.dx, iy * g.dy)
            if r > rmax * (1 + 1e-12):
                continue
            if g.periodic:
                if ix < -(nx // 2) or ix >= nx - nx // 2 or iy < -(ny // 2) or iy >= ny - ny // 2:
                    continue
                val = np.mean(d * np.roll(d, (-ix, -iy), axis=(0, 1)))
            else:
                a = d[max(0, -ix): nx - max(0, ix), max(0, -iy): ny - max(0, iy)]
                b = d[max(0, ix): nx - max(0, -ix), max(0, iy): ny - max(0, -iy)]
                val = np.mean(a * b)
            b_ = int(np.rint(r / step))
            sums[b_] = sums.get(b_, 0.0) + val
            cnts[b_] = cnts.get(b_, 0) + 1
            rs[b_] = rs.get(b_, 0.0) + r
    keys = sorted(sums)
    return np.array([rs[k] / cnts[k] for k in keys]), np.array([sums[k] / cnts[k] for k in keys])


@pytest.mark.parametrize("periodic", [True, False])
def test_acf_matches_brute_force(periodic):
    g = Grid(12, 10, 1.2e-6, 1.0e-6, periodic=periodic)
    h = np.random.default_rng(5).standard_normal(g.shape) + np.linspace(0, 1, 12)[:, None]
    r, R = acf(h, g)
    rb, Rb = _acf_brute_force(h, g)
    assert np.allclose(r, rb, rtol=1e-12) and np.allclose(R, Rb, rtol=1e-10, atol=1e-14)


def test_correlation_length_edge_cases(pgrid):
    X, _ = pgrid.meshgrid()
    assert np.isnan(correlation_length(np.zeros(pgrid.shape), pgrid))
    with pytest.raises(InputError, match="stats.threshold"):
        correlation_length(X, pgrid, threshold=1.5)


def test_correlation_length_white_noise_is_short(pgrid):
    h = np.random.default_rng(0).standard_normal(pgrid.shape)
    assert correlation_length(h, pgrid) < 1.5 * pgrid.dx


def test_summary_keys(pgrid):
    h = gaussian_surface(pgrid, 1e-9, pgrid.lx / 20, seed=3)
    s = summary(h + 5e-9, pgrid)
    assert set(s) == {"rms_height", "rms_slope", "rms_curvature", "skewness", "kurtosis",
                      "correlation_length", "peak_to_valley", "mean"}
    assert s["rms_height"] == pytest.approx(1e-9, rel=1e-10)
    assert s["mean"] == pytest.approx(5e-9, rel=1e-10)
    assert s["peak_to_valley"] > 0 and all(np.isfinite(v) for v in s.values())
