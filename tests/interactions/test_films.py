"""Adsorbed water films: uniform, equilibrium (open / closed) and thin-film levelling."""

import math

import numpy as np
import pytest

from tribobem.errors import ConvergenceWarning, InputError
from tribobem.geometry import gaussian_surface
from tribobem.grid import Grid
from tribobem.interactions.films import film_thickness, levelling_time
from tribobem.interactions.isotherms import SIO2, FHHIsotherm, TableIsotherm
from tribobem.interactions.water import Water

WATER = Water()
GAMMA = WATER.surface_tension


def cos_surface(n, size, cycles, amplitude, periodic=True):
    g = Grid(n, 4, size, size * 4 / n, periodic=periodic)  # quasi-1-D: 4 cells across
    X, _ = g.meshgrid()
    k = 2 * np.pi * cycles / size
    return g, amplitude * np.cos(k * X), k, X


def first_harmonic(e, k, X):
    """Amplitude of cos(k x) in e (least squares on the grid)."""
    return 2.0 * np.mean((e - e.mean()) * np.cos(k * X))


def linear_amplitude(a, k, iso, rh):
    """e1 = -a gamma k^2 / (gamma k^2 + |Pi'(e0)|): linearised film equation on h_s = a cos kx."""
    e0 = iso.thickness(rh)
    slope = abs(iso.disjoining_pressure_derivative(e0, WATER))
    return -a * GAMMA * k * k / (GAMMA * k * k + slope)


# ----------------------------------------------------------------------------- flat surfaces
@pytest.mark.parametrize("periodic", [True, False])
def test_flat_surface_gives_isotherm_thickness_in_every_mode(periodic):
    g = Grid.square(16, 50e-9, periodic=periodic)
    h = np.full(g.shape, 3e-9)
    for rh in (0.2, 0.45, 0.97):
        e_iso = SIO2.thickness(rh)
        for kw in ({"mode": "uniform"}, {"mode": "equilibrium", "system": "open"},
                   {"mode": "equilibrium", "system": "closed"}, {"mode": "thin_film"},
                   {"mode": "thin_film", "disjoining": True}):
            r = film_thickness(h, g, SIO2, rh, **kw)
            assert r.converged, (kw, r.message)
            np.testing.assert_allclose(r.thickness, e_iso, rtol=1e-10, atol=0)
            np.testing.assert_allclose(r.water_surface, h + e_iso, rtol=1e-12)
            assert r.mean_thickness == pytest.approx(e_iso, rel=1e-10)
    # the liquid pressure of the open equilibrium is the Kelvin pressure
    r = film_thickness(h, g, SIO2, 0.45)
    assert r.liquid_pressure == pytest.approx(WATER.capillary_pressure(0.45), rel=1e-10)
    assert r.system == "open" and r.mode == "equilibrium" and math.isnan(r.volume_error)


# ----------------------------------------------------------------------------- equilibrium
@pytest.mark.parametrize("iso, rh", [(SIO2, 0.45), (FHHIsotherm(1.2, 0.28e-9, 3.0), 0.6)])
@pytest.mark.parametrize("system", ["open", "closed"])
@pytest.mark.parametrize("cycles", [3, 8, 20])
def test_linearised_equilibrium_amplitude(iso, rh, system, cycles):
    # 64 nm window, 1 nm cells: wavelengths 21, 8 and 3.2 nm span gamma k^2 / |Pi'| ~ 0.05 - 2
    g, h, k, X = cos_surface(64, 64e-9, cycles, 2e-12)
    r = film_thickness(h, g, iso, rh, system=system)
    assert r.converged
    expected = linear_amplitude(2e-12, k, iso, rh)
    assert -1.0 < expected / 2e-12 < 0.0  # thinner on the peak, partly levelled
    assert first_harmonic(r.thickness, k, X) == pytest.approx(expected, rel=0.01)


def test_linear_amplitude_limits():
    # long wavelength: the film follows the surface (e1 -> 0); short: it levels (e1 -> -a)
    for cycles, lo, hi in ((1, -0.01, 0.0), (16, -1.0, -0.9)):
        g, h, k, X = cos_surface(64, 16e-9 if cycles == 16 else 2e-6, cycles, 1e-12)
        r = film_thickness(h, g, SIO2, 0.45)
        ratio = first_harmonic(r.thickness, k, X) / 1e-12
        assert lo <= ratio <= hi
        assert ratio == pytest.approx(linear_amplitude(1.0, k, SIO2, 0.45), rel=0.01, abs=1e-6)


@pytest.mark.parametrize("system", ["open", "closed"])
def test_thinner_on_peaks_thicker_in_valleys(system):
    g, h, k, X = cos_surface(64, 32e-9, 2, 1.5e-9)
    rh = 0.6
    r = film_thickness(h, g, SIO2, rh, system=system)
    assert r.converged
    e_iso = SIO2.thickness(rh)
    row = r.thickness[:, 0]
    hs = h[:, 0]
    peak, valley = np.argmax(hs), np.argmin(hs)
    assert row[peak] < 0.95 * e_iso and row[valley] > 1.05 * e_iso
    # along the profile the film thickness falls monotonically with the height
    order = np.argsort(hs)
    assert np.all(np.diff(row[order]) <= 1e-15)


def test_closed_system_conserves_mean_thickness():
    g = Grid.square(64, 1e-6, periodic=True)
    h = gaussian_surface(g, 3e-9, 60e-9, seed=3)
    for rh in (0.3, 0.9):
        r = film_thickness(h, g, SIO2, rh, system="closed")
        assert r.converged and r.volume_error <= 1e-10
        assert r.mean_thickness == pytest.approx(SIO2.thickness(rh), rel=1e-10)
        r2 = film_thickness(h, g, SIO2, rh, system="closed", mean_thickness=1.7e-9)
        assert r2.mean_thickness == pytest.approx(1.7e-9, rel=1e-10)
    # the open film on the same surface is not volume constrained: its mean differs
    r_open = film_thickness(h, g, SIO2, 0.9, system="open")
    assert abs(r_open.mean_thickness / SIO2.thickness(0.9) - 1) > 1e-6


def test_steep_peaks_converge_with_dry_nodes():
    # 0.5 nm cells, rms 3 nm, L_ac 5 nm: Laplace pressures of GPa on the peaks squeeze the
    # film to the isotherm floor there; the projected Newton still converges
    g = Grid.square(64, 32e-9, periodic=True)
    h = gaussian_surface(g, 3e-9, 5e-9, seed=1)
    for system in ("open", "closed"):
        r = film_thickness(h, g, SIO2, 0.6, system=system)
        assert r.converged and r.residual <= 1e-10, r.message
        assert r.thickness.min() >= SIO2.floor * (1 - 1e-12)
        assert r.clipped > 0 and "dry" in r.message
        assert r.thickness.max() > 2 * SIO2.thickness(0.6)  # the valleys fill


def test_non_convergence_warns_and_flags():
    g = Grid.square(64, 32e-9, periodic=True)
    h = gaussian_surface(g, 3e-9, 5e-9, seed=1)
    with pytest.warns(ConvergenceWarning):
        r = film_thickness(h, g, SIO2, 0.6, max_iterations=1)
    assert not r.converged and "Newton" in r.message


# ----------------------------------------------------------------------------- free boundary
def test_free_boundary_mirror_extension():
    # a cosine that is even about both edges is smooth under the mirror extension: its
    # wavenumber is pi / L (half a period across the window)
    n, size = 64, 8e-9
    g = Grid(n, 4, size, size * 4 / n, periodic=False)
    X, _ = g.meshgrid()
    k = np.pi / size
    h = 2e-12 * np.cos(k * (X + size / 2))
    r = film_thickness(h, g, SIO2, 0.45)
    assert r.converged
    amp = 2.0 * np.mean((r.thickness - r.thickness.mean()) * np.cos(k * (X + size / 2)))
    assert amp == pytest.approx(linear_amplitude(2e-12, k, SIO2, 0.45), rel=0.01)
    # identical to the periodic solution on the explicitly mirrored surface
    g2 = Grid.square(32, 40e-9, periodic=False)
    h2 = gaussian_surface(Grid.square(32, 40e-9, periodic=True), 1e-9, 8e-9, seed=2)
    big = Grid.square(64, 80e-9, periodic=True)
    top = np.concatenate([h2, h2[:, ::-1]], axis=1)
    hm = np.concatenate([top, top[::-1, :]], axis=0)
    for system in ("open", "closed"):
        r_free = film_thickness(h2, g2, SIO2, 0.7, system=system)
        r_big = film_thickness(hm, big, SIO2, 0.7, system=system)
        np.testing.assert_allclose(r_free.thickness, r_big.thickness[:32, :32], rtol=1e-9)
    # periodic=True on a free-boundary grid is honoured (no mirror)
    r_p = film_thickness(h2, g2, SIO2, 0.7, periodic=True)
    assert np.abs(r_p.thickness - r_free.thickness).max() > 1e-13


# ----------------------------------------------------------------------------- thin film
@pytest.mark.parametrize("disjoining", [False, True])
def test_thin_film_linear_relaxation_in_time(disjoining):
    # small cosine: e1(t) = e1_inf (1 - exp(-t / tau)), rate (e0^3 / 3 eta) k^2 (gamma k^2 + |Pi'|)
    g, h, k, X = cos_surface(32, 64e-9, 4, 1e-11)
    rh = 0.45
    e0 = SIO2.thickness(rh)
    slope = abs(SIO2.disjoining_pressure_derivative(e0, WATER)) if disjoining else 0.0
    tau = levelling_time(2 * np.pi / k, e0, WATER, 1e-3, slope)
    e_inf = -1e-11 * GAMMA * k * k / (GAMMA * k * k + slope)
    for t in (0.3, 1.0, 3.0):
        r = film_thickness(h, g, SIO2, rh, mode="thin_film", time=t * tau, disjoining=disjoining,
                           step_tolerance=1e-7)
        assert r.converged and r.time == pytest.approx(t * tau, rel=1e-12)
        assert first_harmonic(r.thickness, k, X) == pytest.approx(e_inf * (1 - math.exp(-t)), rel=0.01)
        assert r.volume_error <= 1e-10


def test_levelling_time_formula():
    # 1 nm film, 100 nm wavelength, no disjoining: 3 eta / (gamma e0^3 k^4)
    k = 2 * np.pi / 100e-9
    assert levelling_time(100e-9, 1e-9) == pytest.approx(3e-3 / (0.0725 * 1e-27 * k**4), rel=1e-12)
    assert levelling_time(100e-9, 1e-9, disjoining_slope=-1e17) < levelling_time(100e-9, 1e-9)


def test_thin_film_with_disjoining_pressure_reaches_the_closed_equilibrium():
    g = Grid.square(64, 32e-9, periodic=True)
    X, Y = g.meshgrid()
    k = 2 * np.pi * 2 / g.lx
    h = 1.0e-9 * np.cos(k * X) * np.cos(k * Y) + 0.3e-9 * np.sin(2 * k * X)
    eq = film_thickness(h, g, SIO2, 0.6, system="closed")
    tf = film_thickness(h, g, SIO2, 0.6, mode="thin_film", disjoining=True)
    assert tf.converged and "steady" in tf.message and tf.system == "closed"
    assert tf.volume_error <= 1e-10
    # the film varies by 15 % of its mean; the steady thin film matches the equilibrium to
    # 1e-6 of the mean (measured 8e-8; the rest is the Nyquist mode, which the first
    # derivatives of the flux cannot see and so cannot relax)
    assert np.abs(eq.thickness - eq.mean_thickness).max() > 0.1 * eq.mean_thickness
    assert np.abs(tf.thickness - eq.thickness).max() <= 1e-6 * eq.mean_thickness
    assert tf.liquid_pressure == pytest.approx(eq.liquid_pressure, rel=1e-6)


def test_thin_film_conserves_volume_on_rough_surfaces():
    g = Grid.square(24, 150e-9, periodic=True)
    h = gaussian_surface(g, 1e-9, 30e-9, seed=4)
    # without disjoining pressure the peaks drain and dry spots form within 3e-4 tau_slow (the
    # slowest, domain-scale levelling time): that short run already clips and rescales
    for disjoining, duration in ((False, 3e-4), (True, 100.0)):
        r = film_thickness(h, g, SIO2, 0.5, mode="thin_film", disjoining=disjoining, duration=duration)
        assert r.volume_error <= 1e-10 and r.mean_thickness == pytest.approx(SIO2.thickness(0.5), rel=1e-10)
        assert r.converged
        if not disjoining:
            assert r.clipped > 0 and r.thickness.min() == 0.0
        else:
            # the disjoining pressure keeps a film everywhere: nothing clipped (the solver clips
            # negative films to 0, so thickness >= 0 alone could not fail); measured min 0.94 mean
            assert r.clipped == 0 and "went negative" not in r.message
            assert r.thickness.min() > 0.5 * r.mean_thickness
    g2 = Grid.square(16, 100e-9, periodic=False)
    h2 = gaussian_surface(Grid.square(16, 100e-9, periodic=True), 1e-9, 30e-9, seed=4)
    r2 = film_thickness(h2, g2, SIO2, 0.5, mode="thin_film", disjoining=True, time=r.time)
    assert r2.converged and r2.volume_error <= 1e-10


def test_thin_film_without_disjoining_pressure_drains_the_peaks():
    g, h, k, X = cos_surface(32, 32e-9, 2, 2e-9)
    rh = 0.3
    e0 = SIO2.thickness(rh)
    peak, valley = np.argmax(h[:, 0]), np.argmin(h[:, 0])
    thinnest = []
    for duration in (0.1, 1.0):
        r = film_thickness(h, g, SIO2, rh, mode="thin_film", duration=duration)
        assert r.converged and "no steady state" in r.message
        # the film thins at the crest but is never driven negative (the solver would clip it
        # to 0 and count it; thickness >= 0 alone could not fail): measured min 0.24 / 0.025 e0
        assert r.volume_error <= 1e-10 and r.clipped == 0 and r.thickness.min() > 0.0
        # the thinnest film sits at or beside the crest (a dimple forms just off it)
        row = r.thickness[:, 0]
        assert h[np.argmin(row), 0] > 0.8 * h[peak, 0]
        thinnest.append(row.min())
        assert row[valley] > e0
    # measured 0.25 and 0.026 e0 (converged in the step tolerance to 1e-3 e0)
    assert thinnest[0] < 0.5 * e0 and thinnest[1] < 0.2 * thinnest[0] and thinnest[1] < 0.05 * e0
    # with the disjoining pressure the peak keeps a film
    r = film_thickness(h, g, SIO2, rh, mode="thin_film", disjoining=True)
    assert r.converged and r.thickness[peak, 0] > 0.5 * e0


# ----------------------------------------------------------------------------- inputs
def test_bad_inputs_raise():
    g = Grid.square(8, 10e-9, periodic=True)
    h = np.zeros(g.shape)
    for rh in (0.0, -0.1, 1.5, math.nan):
        with pytest.raises(InputError):
            film_thickness(h, g, SIO2, rh)
    with pytest.raises(InputError, match="shape"):
        film_thickness(np.zeros((8, 9)), g, SIO2, 0.5)
    with pytest.raises(InputError, match="NaN"):
        film_thickness(np.full(g.shape, np.nan), g, SIO2, 0.5)
    with pytest.raises(InputError):
        film_thickness(h, g, SIO2, 0.5, mode="levelled")
    with pytest.raises(InputError):
        film_thickness(h, g, SIO2, 0.5, system="half-open")
    with pytest.raises(InputError, match="closed"):
        film_thickness(h, g, SIO2, 0.5, mode="thin_film", system="open")
    with pytest.raises(InputError):
        film_thickness(h, g, SIO2, 0.5, mean_thickness=1e-9)  # open system
    with pytest.raises(InputError):
        film_thickness(h, g, SIO2, 0.5, disjoining=True)  # equilibrium
    with pytest.raises(InputError):
        film_thickness(h, g, SIO2, 0.5, tol=0.0)
    with pytest.raises(InputError, match="strictly increasing"):
        film_thickness(h, g, {"rh": [0, 0.5, 0.4], "thickness": [0, 1e-9, 2e-9]}, 0.5)
    with pytest.raises(InputError, match=">= 0"):
        film_thickness(h, g, {"rh": [0, 0.5, 0.6], "thickness": [0, -1e-9, 2e-9]}, 0.5)


def test_saturation():
    g = Grid.square(8, 10e-9, periodic=True)
    h = np.zeros(g.shape)
    # open equilibrium at RH = 1: the Kelvin pressure vanishes, the flat film is bulk water
    with pytest.raises(InputError, match="bulk water"):
        film_thickness(h, g, SIO2, 1.0)
    # the shipped isotherms diverge at RH = 1: no finite closed / uniform film either
    for mode in ("uniform", "thin_film"):
        with pytest.raises(InputError, match="infinite"):
            film_thickness(h, g, SIO2, 1.0, mode=mode)
    with pytest.raises(InputError, match="infinite"):
        film_thickness(h, g, SIO2, 1.0, system="closed")
    # a closed film with a given volume is fine at RH = 1
    r = film_thickness(h, g, SIO2, 1.0, system="closed", mean_thickness=3e-9)
    assert r.converged and r.mean_thickness == pytest.approx(3e-9, rel=1e-12)
    # a table that ends at RH = 1 has a finite saturated film
    sat = TableIsotherm([0, 0.5, 1.0], [0, 1e-9, 3e-9])
    r = film_thickness(h, g, sat, 1.0, mode="uniform")
    assert r.mean_thickness == pytest.approx(3e-9, rel=1e-12)


def test_dry_body_has_no_film():
    g = Grid.square(8, 10e-9, periodic=True)
    h = np.linspace(0, 1e-9, 64).reshape(8, 8)
    for iso in (None, "dry"):
        for mode in ("uniform", "equilibrium", "thin_film"):
            r = film_thickness(h, g, iso, 0.9, mode=mode)
            assert r.converged and np.all(r.thickness == 0.0) and r.mean_thickness == 0.0
            np.testing.assert_array_equal(r.water_surface, h)
