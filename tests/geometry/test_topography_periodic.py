"""The periodic-plus-smooth split of a non-periodic scan and the split at a wavelength (the
measured windows of a two-scale run)."""

import numpy as np

from tribobem.geometry.topography import periodic_component, split_at_wavelength


def _rough(n=64, seed=0):
    from scipy.ndimage import gaussian_filter

    return gaussian_filter(np.random.default_rng(seed).normal(size=(n, n)), 3, mode="wrap")


def test_the_periodic_component_has_no_steps_at_its_edges():
    n = 64
    x = np.arange(n)
    u = _rough(n) + 0.05 * x[:, None] + 0.03 * x[None, :] ** 1.2  # a tilted, curved, non-periodic map
    p = periodic_component(u)
    interior = np.abs(np.diff(p, axis=0)).mean()
    # the jump across the edges falls from 160 interior steps to a few (measured: 3.2 -> 0.05, interior 0.019)
    assert np.abs(u[-1] - u[0]).mean() > 100 * interior
    assert np.abs(p[-1] - p[0]).mean() < 4 * interior and np.abs(p[:, -1] - p[:, 0]).mean() < 4 * interior
    assert abs(p.mean() - u.mean()) < 1e-12
    # what it removes is smooth: the Laplacian of u - p vanishes inside
    s = u - p
    lap = s[2:, 1:-1] + s[:-2, 1:-1] + s[1:-1, 2:] + s[1:-1, :-2] - 4 * s[1:-1, 1:-1]
    assert np.abs(lap).max() < 1e-10 * np.abs(s).max()


def test_the_split_at_a_wavelength_separates_long_and_short_sinusoids():
    n, L = 128, 10e-6
    x = (np.arange(n) + 0.5) * L / n
    X, Y = np.meshgrid(x, x, indexing="ij")
    long = 2e-9 * np.cos(2 * np.pi * X / (L / 2))
    short = 1e-9 * np.sin(2 * np.pi * Y / (L / 16)) * np.cos(2 * np.pi * X / (L / 32))
    lo, sh = split_at_wavelength(long + short, L / n, L / n, L / 8)
    np.testing.assert_allclose(lo + sh, long + short, atol=1e-22)
    # away from the edges (where the smooth part absorbs the map's edge steps) each part is its sinusoid
    # (measured: 8e-11 and 4e-11 of the amplitudes); over the whole map the short part is 3 % off in rms
    c = slice(16, 112)
    assert np.abs(sh - short)[c, c].max() < 1e-8 * 1e-9
    assert np.abs(lo - long)[c, c].max() < 1e-8 * 2e-9
    assert np.sqrt(np.mean((sh - short) ** 2)) < 0.05 * np.sqrt(np.mean(short ** 2))
