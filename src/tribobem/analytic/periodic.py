r"""Periodic (wavy) contacts: Westergaard sinusoid, bisinusoidal asymptotes, Paper A pull-off fit.

All functions use SI units; ``E_star`` is the composite modulus, mean pressures are positive
(compressive) nominal pressures (force per period area).

Westergaard (1939); Johnson, *Contact Mechanics* (1985) section 13.2
--------------------------------------------------------------------
1D profile (plane strain, period L)::

    h(x) = A (1 - cos(2 pi x/L)),      p* = pi E* A / L   (pressure for full contact)

For a mean pressure pbar < p* the contact is |x| < a (mod L) with
``sin^2(pi a/L) = pbar/p*`` and, for |x| <= a,
``p(x) = 2 pbar cos(pi x/L) / sin^2(pi a/L) * sqrt(sin^2(pi a/L) - sin^2(pi x/L))``;
for pbar >= p*, ``p(x) = pbar + p* cos(2 pi x/L)``; x is measured from the contact centre
(the minimum of h).

Bisinusoidal surface: Johnson, Greenwood & Higginson (JGH), "The contact of elastic regular
wavy surfaces", Int. J. Mech. Sci. 27 (1985) 383-396
------------------------------------------------------------------------------------------
Form used here (Paper A Eq. 31 with S = Delta and equal wavelengths, an "egg-box")::

    h(x, y) = Delta cos(2 pi x/L) cos(2 pi y/L)

Its spectrum is the single wavevector |q| = 2 sqrt(2) pi / L, so full contact needs
``p* = sqrt(2) pi E* Delta / L``.  The gap minima ("crests" of the rough body, where contact
starts) and maxima ("troughs", where the last non-contact lakes sit) are both twice per L x L
cell; both have curvature radius ``R = L^2/(4 pi^2 Delta)``, the same in x and y.

* Light load (independent Hertz crests, each carrying pbar L^2/2)::

      A/L^2 = 2 pi a^2/L^2 = pi (3/(8 pi))^(2/3) (pbar/p*)^(2/3),   a^3 = 3 (pbar L^2/2) R/(4 E*)

* Near full contact (two circular non-contact lakes per cell, of radius b; each is a
  penny-shaped gap in the full-contact field p = (pbar - p*) + p* (2 pi/L)^2 r^2/2 closing with
  zero stress-intensity factor, int_0^b r p(r)/sqrt(b^2 - r^2) dr = 0)::

      b^2 = 3 (1 - pbar/p*) L^2/(4 pi^2),   1 - A/L^2 = (3/(2 pi)) (1 - pbar/p*)

These are the JGH asymptotes (also quoted by Yastrebov, Anciaux & Molinari, Tribol. Lett. 65
(2017) 148); the tests re-check both, with the constants re-derived here, against a periodic
boundary-element solution.  (A sum form h = A (2 - cos - cos) is a different surface: one
crest per cell, p* = pi E* A/L for each of its two harmonics; it is not what these formulas
describe.)

Paper A section 6: bisinusoidal pull-off fit (Eq. 35, Table 2)
---------------------------------------------------------------
``|F_pull-off| = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b`` with a = 10.39, b = 0.041,
beta = 0, R_c = sqrt(Rx Ry), Rx = lx^2/(4 pi^2 S), Ry = ly^2/(4 pi^2 S), k = ly/lx <= 1, per
lx x ly cell (two crests) of h = S cos(2 pi x/lx) cos(2 pi y/ly); fitted for S = 5 nm,
dgamma 30-70 mJ/m^2, R_c 100-500 um, E* 80-120 GPa, k 0.1-0.9 (Paper A Table 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = [
    "WestergaardSolution", "westergaard", "westergaard_pressure", "westergaard_contact_fraction",
    "BisinusoidalAsymptotes", "bisinusoidal_asymptotes", "bisinusoidal_full_contact_pressure",
    "bisinusoidal_curvature_radius", "bisinusoidal_pull_off_fit",
    "bisinusoidal_pull_off_fit_magnitude",
]


def _pos(name, v):
    a = np.asarray(v, float)
    if a.size == 0 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError(name, f"must be finite and > 0, got {v!r}")
    return float(a) if a.ndim == 0 else a


def _nonneg(name, v):
    a = np.asarray(v, float)
    if not np.all(np.isfinite(a)) or np.any(a < 0):
        raise InputError(name, f"must be finite and >= 0, got {v!r}")
    return a


def _out(x):
    x = np.asarray(x, float)
    return float(x) if x.ndim == 0 else x


# ----------------------------------------------------------------------------------------------
# Westergaard
# ----------------------------------------------------------------------------------------------

def westergaard_contact_fraction(mean_pressure, amplitude, wavelength, E_star):
    """Contact fraction 2a/L of the Westergaard sinusoid: (2/pi) asin(sqrt(pbar/p*)), 1 beyond p*.

    Parameters
    ----------
    mean_pressure : float or array_like
        Mean (nominal) pressure pbar >= 0 (Pa): force per unit length / L.
    amplitude : float
        A in h = A (1 - cos(2 pi x/L)) (m): half the peak-to-valley height.
    wavelength : float
        L (m).
    E_star : float
        Composite plane-strain modulus (Pa).

    Returns
    -------
    float or ndarray
        2a/L (dimensionless, in [0, 1]), shape of ``mean_pressure``; p* = pi E* A / L.
    """
    pb = _nonneg("mean_pressure", mean_pressure)
    ps = np.pi * _pos("E_star", E_star) * _pos("amplitude", amplitude) / _pos("wavelength", wavelength)
    ratio = np.clip(pb / ps, 0.0, 1.0)
    return _out(2.0 / np.pi * np.arcsin(np.sqrt(ratio)))


def westergaard_pressure(x, mean_pressure, amplitude, wavelength, E_star):
    """Westergaard pressure p(x) (Pa), x measured from a contact centre (minimum of h), periodic.

    Parameters
    ----------
    x : array_like
        Positions (m) from a contact centre; any x (the profile has period L).
    mean_pressure : float
        Mean (nominal) pressure pbar >= 0 (Pa).
    amplitude : float
        A in h = A (1 - cos(2 pi x/L)) (m).
    wavelength : float
        L (m).
    E_star : float
        Composite plane-strain modulus (Pa).

    Returns
    -------
    float or ndarray
        Pressure (Pa, compressive positive), shape of ``x``: ``pbar + p* cos(2 pi x/L)`` at
        full contact (pbar >= p*), the partial-contact profile (0 outside |x| < a) below it.
    """
    pb = float(_nonneg("mean_pressure", mean_pressure))
    L = float(_pos("wavelength", wavelength))
    ps = np.pi * float(_pos("E_star", E_star)) * float(_pos("amplitude", amplitude)) / L
    x = np.asarray(x, float)
    xr = np.mod(x + 0.5 * L, L) - 0.5 * L
    if pb >= ps:
        return _out(pb + ps * np.cos(2.0 * np.pi * xr / L))
    if pb == 0.0:
        return _out(np.zeros_like(xr))
    s2a = pb / ps
    s2x = np.sin(np.pi * xr / L) ** 2
    p = 2.0 * pb * np.cos(np.pi * xr / L) / s2a * np.sqrt(np.clip(s2a - s2x, 0.0, None))
    return _out(np.where(s2x < s2a, p, 0.0))


@dataclass(frozen=True)
class WestergaardSolution:
    """Westergaard solution of h = A (1 - cos(2 pi x/L)) pressed with mean pressure pbar.

    Attributes
    ----------
    mean_pressure : float
        pbar (Pa).
    amplitude : float
        A (m).
    wavelength : float
        L (m).
    E_star : float
        Composite modulus (Pa), plane strain.
    p_star : float
        Full-contact pressure pi E* A / L (Pa).
    contact_half_width : float
        a (m); L/2 at full contact.
    contact_fraction : float
        2a/L.
    max_pressure : float
        p(0) = 2 pbar / sin(pi a/L) below p*, pbar + p* beyond (Pa).
    """

    mean_pressure: float
    amplitude: float
    wavelength: float
    E_star: float
    p_star: float
    contact_half_width: float
    contact_fraction: float
    max_pressure: float

    @property
    def full_contact(self) -> bool:
        """True when pbar >= p*."""
        return self.mean_pressure >= self.p_star

    def pressure(self, x):
        """Pressure p(x) (Pa) at positions x (m) measured from a contact centre.

        Parameters
        ----------
        x : array_like
            Positions (m) from a contact centre.

        Returns
        -------
        float or ndarray
            :func:`westergaard_pressure` of this solution (Pa), shape of ``x``.
        """
        return westergaard_pressure(x, self.mean_pressure, self.amplitude, self.wavelength,
                                    self.E_star)


def westergaard(mean_pressure, amplitude, wavelength, E_star) -> WestergaardSolution:
    """Westergaard (1939) contact of a 1D sinusoid in plane strain (Johnson 1985, 13.2).

    Parameters
    ----------
    mean_pressure : float
        Mean (nominal) pressure pbar >= 0 (Pa): force per unit length / L.
    amplitude : float
        A in h = A (1 - cos(2 pi x/L)) (m): half the peak-to-valley height.
    wavelength : float
        L (m).
    E_star : float
        Composite plane-strain modulus (Pa).

    Returns
    -------
    WestergaardSolution
        With ``sin^2(pi a/L) = pbar/p*``, p* = pi E* A/L, and a ``pressure(x)`` method.
    """
    pb = float(_nonneg("mean_pressure", mean_pressure))
    A = float(_pos("amplitude", amplitude))
    L = float(_pos("wavelength", wavelength))
    Es = float(_pos("E_star", E_star))
    ps = np.pi * Es * A / L
    frac = float(westergaard_contact_fraction(pb, A, L, Es))
    if pb >= ps:
        pmax = pb + ps
    elif pb == 0:
        pmax = 0.0
    else:
        pmax = 2.0 * pb / np.sqrt(pb / ps)
    return WestergaardSolution(mean_pressure=pb, amplitude=A, wavelength=L, E_star=Es, p_star=ps,
                               contact_half_width=0.5 * frac * L, contact_fraction=frac,
                               max_pressure=pmax)


# ----------------------------------------------------------------------------------------------
# bisinusoidal
# ----------------------------------------------------------------------------------------------

def bisinusoidal_full_contact_pressure(amplitude, wavelength, E_star):
    """p* = sqrt(2) pi E* Delta / L for h = Delta cos(2 pi x/L) cos(2 pi y/L) (Pa).

    The mean pressure above which the square bisinusoid is in full contact (JGH 1985).

    Parameters
    ----------
    amplitude : float or array_like
        Delta (m).
    wavelength : float or array_like
        L (m), the same in x and y.
    E_star : float or array_like
        Composite modulus (Pa).

    Returns
    -------
    float or ndarray
        p* (Pa), broadcast over the inputs.
    """
    return _out(np.sqrt(2.0) * np.pi * np.asarray(E_star, float) * np.asarray(amplitude, float)
                / np.asarray(wavelength, float))


@dataclass(frozen=True)
class BisinusoidalAsymptotes:
    """JGH (1985) asymptotes for h = Delta cos(2 pi x/L) cos(2 pi y/L) (see module docstring).

    Attributes
    ----------
    mean_pressure : float or ndarray
        pbar (Pa), force per L^2.
    p_star : float
        Full-contact pressure sqrt(2) pi E* Delta/L (Pa).
    crest_radius : float
        L^2/(4 pi^2 Delta) (m).
    hertz_contact_radius : float or ndarray
        Radius of each of the two Hertz spots per cell at light load (m).
    contact_fraction_light : float or ndarray
        pi (3/(8 pi))^(2/3) (pbar/p*)^(2/3) (light-load asymptote; meaningful for pbar << p*).
    lake_radius : float or ndarray
        Radius b of each of the two non-contact lakes per cell near full contact (m); 0 beyond p*.
    contact_fraction_full : float or ndarray
        1 - (3/(2 pi)) (1 - pbar/p*) (near-full asymptote; meaningful for pbar -> p*), 1 beyond p*.
    """

    mean_pressure: float | np.ndarray
    p_star: float
    crest_radius: float
    hertz_contact_radius: float | np.ndarray
    contact_fraction_light: float | np.ndarray
    lake_radius: float | np.ndarray
    contact_fraction_full: float | np.ndarray


def bisinusoidal_asymptotes(mean_pressure, amplitude, wavelength, E_star) -> BisinusoidalAsymptotes:
    """Light-load (Hertz) and near-full-contact (JGH lakes) asymptotes of the bisinusoid.

    Parameters
    ----------
    mean_pressure : float or array_like
        Mean nominal pressure pbar >= 0 (Pa).
    amplitude : float
        Delta in h = Delta cos(2 pi x/L) cos(2 pi y/L) (m).
    wavelength : float
        L (m), the same in x and y.
    E_star : float
        Composite modulus (Pa).

    Returns
    -------
    BisinusoidalAsymptotes
    """
    pb = _nonneg("mean_pressure", mean_pressure)
    D = float(_pos("amplitude", amplitude))
    L = float(_pos("wavelength", wavelength))
    Es = float(_pos("E_star", E_star))
    ps = float(bisinusoidal_full_contact_pressure(D, L, Es))
    Rc = L**2 / (4.0 * np.pi**2 * D)
    W = 0.5 * pb * L**2                                   # load per crest (two crests per cell)
    a = np.cbrt(3.0 * W * Rc / (4.0 * Es))
    light = 2.0 * np.pi * a**2 / L**2
    deficit = np.clip(1.0 - pb / ps, 0.0, None)
    b = L * np.sqrt(3.0 * deficit) / (2.0 * np.pi)
    full = 1.0 - 3.0 / (2.0 * np.pi) * deficit
    return BisinusoidalAsymptotes(mean_pressure=_out(pb), p_star=ps, crest_radius=Rc,
                                  hertz_contact_radius=_out(a), contact_fraction_light=_out(light),
                                  lake_radius=_out(b), contact_fraction_full=_out(full))


def bisinusoidal_curvature_radius(amplitude, wavelength_x, wavelength_y):
    """Effective crest radius R_c = sqrt(Rx Ry) of h = S cos(2 pi x/lx) cos(2 pi y/ly) (m).

    Rx = lx^2/(4 pi^2 S), Ry = ly^2/(4 pi^2 S) (Paper A Eqs. 32-33), so R_c = lx ly/(4 pi^2 S).

    Parameters
    ----------
    amplitude : float or array_like
        S (m), > 0.
    wavelength_x, wavelength_y : float or array_like
        lx, ly (m).

    Returns
    -------
    float or ndarray
        R_c (m), broadcast over the inputs.
    """
    S = np.asarray(amplitude, float)
    lx = np.asarray(wavelength_x, float)
    ly = np.asarray(wavelength_y, float)
    return _out(np.sqrt((lx**2 / (4.0 * np.pi**2 * S)) * (ly**2 / (4.0 * np.pi**2 * S))))


def bisinusoidal_pull_off_fit(E_star, R_c, dgamma, k, a=10.39, b=0.041, beta=0.0):
    """Paper A Eq. 35 fit of the bisinusoidal pull-off force, returned NEGATIVE (N).

    F_pull-off = -a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b per lx x ly cell (two crests), with
    Table 2 constants a = 10.39, b = 0.041, beta = 0 (independent of E*).

    Parameters
    ----------
    E_star : float or array_like
        Composite modulus (Pa).
    R_c : float or array_like
        sqrt(Rx Ry) (m), see :func:`bisinusoidal_curvature_radius`.
    dgamma : float or array_like
        Work of adhesion (J/m^2).
    k : float or array_like
        Wavelength ratio ly/lx in (0, 1].
    a, b, beta : float
        Fit constants (Paper A Table 2).

    Returns
    -------
    float or ndarray
        Pull-off force per cell (N, negative), broadcast over the inputs.

    Raises
    ------
    InputError
        ``k`` outside (0, 1].
    """
    return _out(-np.asarray(bisinusoidal_pull_off_fit_magnitude(E_star, R_c, dgamma, k, a, b, beta)))


def bisinusoidal_pull_off_fit_magnitude(E_star, R_c, dgamma, k, a=10.39, b=0.041, beta=0.0):
    """|Paper A Eq. 35 pull-off force| = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b (N, positive).

    Parameters
    ----------
    E_star : float or array_like
        Composite modulus (Pa).
    R_c : float or array_like
        sqrt(Rx Ry) (m), see :func:`bisinusoidal_curvature_radius`.
    dgamma : float or array_like
        Work of adhesion (J/m^2).
    k : float or array_like
        Wavelength ratio ly/lx in (0, 1].
    a, b, beta : float
        Fit constants (Paper A Table 2: 10.39, 0.041, 0).

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force per lx x ly cell (N, positive).

    Raises
    ------
    InputError
        ``k`` outside (0, 1].
    """
    E = np.asarray(E_star, float)
    R = np.asarray(R_c, float)
    g = np.asarray(dgamma, float)
    kk = np.asarray(k, float)
    if np.any(kk <= 0) or np.any(kk > 1):
        raise InputError("k", "wavelength ratio ly/lx must lie in (0, 1]")
    return _out(a * E**beta * R ** (1.0 + beta) * g ** (1.0 - beta) * kk**b)
