"""Random rough surfaces: exact scaling, reproducibility, ACF, PSD shape, moments."""

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.geometry import (
    correlation_length,
    gaussian_surface,
    johnson_quantiles,
    kurtosis,
    psd,
    rms_height,
    rms_slope,
    scale_to_rms,
    self_affine_surface,
    skewness,
)
from tribobem.grid import Grid

L = 10e-6


@pytest.fixture(scope="module")
def g256():
    return Grid.square(256, L, periodic=True)


@pytest.fixture
def g64():
    return Grid(64, 48, 2e-6, 1.5e-6, periodic=True)


# ----------------------------------------------------------------------------- Gaussian
def test_gaussian_exact_rms_zero_mean(g64):
    h = gaussian_surface(g64, 5e-9, 0.2e-6, seed=1)
    assert h.shape == g64.shape
    assert rms_height(h) == pytest.approx(5e-9, rel=1e-10)
    assert abs(h.mean()) < 1e-12 * 5e-9


def test_gaussian_seed_reproducible(g64):
    a = gaussian_surface(g64, 1e-9, 0.2e-6, seed=7)
    b = gaussian_surface(g64, 1e-9, 0.2e-6, seed=7)
    c = gaussian_surface(g64, 1e-9, 0.2e-6, seed=8)
    d = gaussian_surface(g64, 1e-9, 0.2e-6, seed=np.random.default_rng(7))
    assert np.array_equal(a, b) and np.array_equal(a, d)
    assert np.abs(a - c).max() > 0.5 * rms_height(a)


def test_gaussian_correlation_length(g256):
    beta = L / 16
    cl = [correlation_length(gaussian_surface(g256, 1e-9, beta, seed=s), g256) for s in range(4)]
    assert np.mean(cl) == pytest.approx(beta, rel=0.15)


def _axis_correlation_length(h, axis, step):
    """Lag along one axis where the (periodic) ACF along it drops to 10 %."""
    d = h - h.mean()
    f = np.fft.fft(d, axis=axis)
    r = np.fft.ifft(np.abs(f) ** 2, axis=axis).real.mean(axis=1 - axis)
    r /= r[0]
    i = int(np.nonzero(r < 0.1)[0][0])
    return step * (i - 1 + (r[i - 1] - 0.1) / (r[i - 1] - r[i]))


def test_gaussian_anisotropic(g256):
    bx, by = L / 10, L / 30
    lx = []
    ly = []
    for s in range(3):
        h = gaussian_surface(g256, 1e-9, bx, correlation_length_y=by, seed=s)
        lx.append(_axis_correlation_length(h, 0, g256.dx))
        ly.append(_axis_correlation_length(h, 1, g256.dy))
    assert np.mean(lx) == pytest.approx(bx, rel=0.2)
    assert np.mean(ly) == pytest.approx(by, rel=0.2)


@pytest.mark.parametrize("sk,ku", [(0.5, 4.0), (-1.0, 5.0), (0.3, 2.5), (0.0, 2.0), (0.0, 6.0), (1.0, 3.0)])
def test_gaussian_skewness_kurtosis(g64, sk, ku):
    h = gaussian_surface(g64, 2e-9, 0.2e-6, seed=4, skewness=sk, kurtosis=ku)
    assert skewness(h) == pytest.approx(sk, abs=1e-6)
    assert kurtosis(h) == pytest.approx(ku, rel=1e-6)
    assert rms_height(h) == pytest.approx(2e-9, rel=1e-10)
    assert abs(h.mean()) < 1e-12 * 2e-9
    # rank-preserving: the same peaks and valleys as the Gaussian surface of the same seed
    g = gaussian_surface(g64, 2e-9, 0.2e-6, seed=4)
    assert np.array_equal(np.argsort(h, axis=None), np.argsort(g, axis=None))


def test_gaussian_only_skewness_defaults_kurtosis_3(g64):
    h = gaussian_surface(g64, 1e-9, 0.2e-6, seed=2, skewness=0.4)
    assert skewness(h) == pytest.approx(0.4, abs=1e-6) and kurtosis(h) == pytest.approx(3.0, rel=1e-6)


def test_gaussian_infeasible_moments(g64):
    with pytest.raises(InputError) as e:
        gaussian_surface(g64, 1e-9, 0.2e-6, skewness=2.0, kurtosis=4.0)
    assert e.value.field == "roughness.kurtosis" and "1 + skewness^2" in str(e.value)


def test_johnson_quantiles_lognormal_line():
    # a (skewness, kurtosis) pair on the lognormal line takes the S_L branch
    from tribobem.geometry.rough import _lognormal_kurtosis

    k = _lognormal_kurtosis(1.0)
    x = johnson_quantiles(4096, 1.0, k)
    d = x - x.mean()
    assert np.mean(d**3) / np.mean(d**2) ** 1.5 == pytest.approx(1.0, abs=1e-6)
    # the S_L branch: the standardised exp(a u) at the normal quantiles u, with a fixed by the
    # skewness (solved here independently); strictly increasing (the values are sorted by
    # construction, so a >= 0 check on the differences could not fail)
    from scipy.optimize import brentq
    from scipy.special import ndtri

    u = ndtri((np.arange(4096) + 0.5) / 4096)

    def skew(a):
        e = np.exp(a * u) - np.exp(a * u).mean()
        return np.mean(e**3) / np.mean(e**2) ** 1.5

    a = brentq(lambda a: skew(a) - 1.0, 1e-3, 3.0, xtol=1e-14)
    ref = np.exp(a * u)
    ref = (ref - ref.mean()) / ref.std()
    assert np.abs(x - ref).max() < 1e-6
    assert np.all(np.diff(x) > 0)


@pytest.mark.parametrize("kw,field", [
    ({"rms": -1.0}, "roughness.rms"),
    ({"correlation_length": 0.0}, "roughness.correlation_length"),
    ({"correlation_length_y": np.nan}, "roughness.correlation_length_y"),
])
def test_gaussian_bad_input(g64, kw, field):
    args = {"rms": 1e-9, "correlation_length": 1e-7} | kw
    with pytest.raises(InputError) as e:
        gaussian_surface(g64, **args)
    assert e.value.field == field


# ----------------------------------------------------------------------------- self-affine
def test_self_affine_exact_rms_height(g64):
    h = self_affine_surface(g64, 0.8, rms_height=3e-9, seed=1)
    assert rms_height(h) == pytest.approx(3e-9, rel=1e-10)
    assert abs(h.mean()) < 1e-12 * 3e-9


@pytest.mark.parametrize("periodic", [True, False])
def test_self_affine_exact_rms_slope(periodic):
    g = Grid(64, 48, 2e-6, 1.5e-6, periodic=periodic)
    h = self_affine_surface(g, 0.5, rms_slope=0.12, rolloff_wavelength=0.5e-6, seed=2)
    assert rms_slope(h, g) == pytest.approx(0.12, rel=1e-10)


def test_self_affine_reproducible(g64):
    a = self_affine_surface(g64, 0.7, rms_height=1e-9, seed=3)
    b = self_affine_surface(g64, 0.7, rms_height=1e-9, seed=3)
    c = self_affine_surface(g64, 0.7, rms_height=1e-9, seed=4)
    assert np.array_equal(a, b) and np.abs(a - c).max() > 0.5 * rms_height(a)


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_self_affine_psd_slope(g256, hurst):
    lam_r = L / 8
    h = self_affine_surface(g256, hurst, rms_height=1e-9, rolloff_wavelength=lam_r, seed=5)
    q, C = psd(h, g256)
    qr, qs = 2 * np.pi / lam_r, np.pi / g256.dx
    fit = (q > 1.5 * qr) & (q < 0.8 * qs)
    slope = np.polyfit(np.log(q[fit]), np.log(C[fit]), 1)[0]
    assert slope == pytest.approx(-2 * (hurst + 1), rel=0.05)
    # plateau below the roll-off: flat
    plateau = (q < 0.8 * qr)
    assert np.ptp(np.log(C[plateau])) < 0.05


def test_self_affine_cutoffs(g256):
    lam_s, lam_L = L / 32, L / 4
    h = self_affine_surface(g256, 0.6, rms_height=1e-9, short_cutoff=lam_s, long_cutoff=lam_L, seed=6)
    q, C = psd(h, g256)
    inside = (q > 2 * np.pi / lam_L + (q[1] - q[0])) & (q < 2 * np.pi / lam_s - (q[1] - q[0]))
    outside = (q < 2 * np.pi / lam_L - (q[1] - q[0])) | (q > 2 * np.pi / lam_s + (q[1] - q[0]))
    assert C[outside].max() < 1e-20 * C[inside].max()


@pytest.mark.parametrize("kw,field", [
    ({}, "roughness.rms_height"),
    ({"rms_height": 1e-9, "rms_slope": 0.1}, "roughness.rms_height"),
    ({"rms_height": 1e-9, "hurst": 1.5}, "roughness.hurst"),
    ({"rms_height": 1e-9, "hurst": 0.0}, "roughness.hurst"),
    ({"rms_height": 1e-9, "rolloff_wavelength": 1.0}, "roughness.rolloff_wavelength"),
    ({"rms_height": 1e-9, "short_cutoff": 1.0}, "roughness.short_cutoff"),
    ({"rms_slope": -0.1}, "roughness.rms_slope"),
])
def test_self_affine_bad_input(g64, kw, field):
    args = {"hurst": 0.8} | kw
    with pytest.raises(InputError) as e:
        self_affine_surface(g64, **args)
    assert e.value.field == field


# ----------------------------------------------------------------------------- scaling
def test_scale_to_rms_keeps_higher_moments(g64):
    h = gaussian_surface(g64, 1e-9, 0.2e-6, seed=9, skewness=0.6, kurtosis=4.2) + 7e-9
    s = scale_to_rms(h, 10e-9)
    assert rms_height(s) == pytest.approx(10e-9, rel=1e-12)
    assert abs(s.mean()) < 1e-12 * 10e-9
    assert skewness(s) == pytest.approx(skewness(h), rel=1e-10)
    assert kurtosis(s) == pytest.approx(kurtosis(h), rel=1e-10)
    assert np.array_equal(np.argsort(s, axis=None), np.argsort(h, axis=None))


def test_scale_to_rms_edge_cases():
    assert not scale_to_rms(np.ones((4, 4)), 0.0).any()
    with pytest.raises(InputError, match="flat"):
        scale_to_rms(np.ones((4, 4)), 1e-9)
    with pytest.raises(InputError, match="roughness.rms"):
        scale_to_rms(np.arange(4.0), np.inf)
