r"""Rigid sphere on an axisymmetric wavy elastic half-space with a Dugdale cohesive zone.

Geometry (Paper A Eq. 25)::

    h(r) = r^2/(2R) + A (1 - cos(2 pi r / xi))

Dimensionless variables (Paper A Eq. 30)::

    P = F/(pi dgamma R),  alpha = A R/xi^2,  beta = xi^3 E*/(2 pi dgamma R^2),
    abar = a/xi,  Delta = delta R/xi^2,  lambda = Maugis parameter of the sphere (R).

Equations implemented (Paper A Eqs. 26-29, after Guduru, J. Mech. Phys. Solids 55 (2007) 445
(JKR) and its Maugis-Dugdale extension by Waters, Lee & Guduru, Int. J. Solids Struct. 46 (2009)
1033, Paper A ref. [39]).  With z = 2 pi abar, s = sqrt(m^2 - 1),
m = c/a and H_n the Struve functions::

    1 = 2 lam abar^2 (beta/3)^(2/3) [s + (m^2-2) atan s]
      + 8/3 lam^2 abar (beta/3)^(1/3) [s atan s - m + 1]
      + 2 pi lam alpha (beta/3)^(2/3) [ 1 - cos(z m) - pi^2 abar H0(z)
                                        + 2 pi abar H0(z) asin(1/m)
                                        - 2 pi abar int_0^1 t H0(z t)/sqrt(m^2 - t^2) dt ]   (26)
    P = P1(abar) - 4 lam abar^2 (beta/3)^(2/3) [s + m^2 atan s]                                (27)
    Delta = abar^2 + abar [pi^2 alpha H0(z) - 2 lam (1/(9 beta))^(1/3) s]                      (28)
    P1 = 4 beta [2 abar^3/3 + alpha (4 pi^2 abar^3/3 + (pi abar/2) H1(z) - pi^2 abar^2 H2(z))]
       = 8 beta abar^3/3 + alpha beta (4 pi^2 abar^2 H0(z) - 2 pi abar H1(z))                  (29)

The printed Paper A text is garbled by the extraction: in Eq. 26 the last bracket reads
"H0(2 pi abar sin^-1 1/m - 2 pi abar int ...)" -- it is H0(2 pi abar) asin(1/m) minus the
integral term; Eq. 29 prints "2 abar/3" for 2 abar^3/3 and drops the pi^2 of the H2 term.  The
form above was re-derived here from Sneddon's axisymmetric punch solution:

* the non-adhesive (K = 0) solution of the wavy term with contact radius a has approach
  delta_w = pi^2 A a H0(2 pi a/xi)/xi (the H0 term of Eq. 28) and force (29);
* the Dugdale annulus and its flat-punch correction are profile independent (Maugis 1992), so
  the MD terms are those of the sphere with A_M = 2 abar (beta/3)^(1/3),
  F_M = P, Delta_M = 4 (beta/3)^(2/3) Delta;
* Eq. 26 is gap(c) = h0 divided by h0, the wavy bracket being gap_w(c)/A with
  gap_w(r) = A(1 - cos 2 pi r/xi) - delta_w (1 - (2/pi) asin(a/r))
  - (2 pi A/xi) int_0^a t H0(2 pi t/xi)/sqrt(r^2 - t^2) dt.

The tests check it against a direct quadrature of the gap (an independent Abel form) and that
alpha = 0 reproduces :func:`maugis_dugdale_curve` exactly.  lambda -> infinity gives Guduru's
JKR-type result, :func:`guduru_jkr_curve`::

    P = P1(abar) - 4 sqrt(beta abar^3),    Delta = abar^2 + pi^2 alpha abar H0(z) - sqrt(abar/beta).

Root choice: at fixed abar the cohesive equation need not be monotonic in m when the gap of the
wavy profile is not (alpha large); the cohesive zone ends where the gap FIRST reaches h0, i.e.
the smallest root m >= 1 is taken (found by a scan in m finer than the waviness, then a
bracketed solve).  Like Guduru's and Waters' solutions, the model assumes one simply connected
contact zone and one cohesive annulus; it does not check that the gap beyond c stays above h0
or that the bodies do not touch at other crests.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.special import struve

from ..errors import InputError
from .adhesion import _bracketed_root, _md_brackets, _md_lhs, maugis_parameter

__all__ = ["GuduruCurve", "GuduruSolution", "guduru_curve", "guduru_jkr_curve", "guduru",
           "guduru_cohesive_equation", "guduru_parameters", "guduru_hertz_force"]


# ----------------------------------------------------------------------------------------------
# fast Struve H0: clamped cubic spline of scipy's struve(0, x) (about 6 us per call) on a grid
# of step 1/128; interpolation error < 1e-9 (tested)
# ----------------------------------------------------------------------------------------------

@lru_cache(maxsize=8)
def _h0_spline(xmax: float) -> CubicSpline:
    x = np.linspace(0.0, xmax, int(round(128 * xmax)) + 1)
    y = struve(0, x)
    d0 = 2.0 / np.pi                              # H0'(x) = 2/pi - H1(x), H1(0) = 0
    d1 = 2.0 / np.pi - struve(1, xmax)
    return CubicSpline(x, y, bc_type=((1, d0), (1, d1)))


def _struve0(x):
    x = np.asarray(x, dtype=float)
    X = 64.0
    xm = float(np.max(x)) if x.size else 0.0
    while X < xm:
        X *= 2.0
    return _h0_spline(X)(x)


# ----------------------------------------------------------------------------------------------
# equations
# ----------------------------------------------------------------------------------------------

def _nodes(abar_max):
    n = int(32 + 8 * np.ceil(max(abar_max, 0.0)))
    return np.polynomial.legendre.leggauss(n)


def _wavy_bracket(abar, s, H0z, nodes):
    """gap_w(c)/A of the K = 0 wavy solution at c = m a (the bracket of Eq. 26)."""
    x, w = nodes
    m = np.sqrt(1.0 + s * s)
    z = 2.0 * np.pi * abar
    with np.errstate(divide="ignore"):
        th1 = np.arctan2(1.0, s)                  # asin(1/m)
    th = 0.5 * th1[..., None] * (x + 1.0)
    t = m[..., None] * np.sin(th)
    integral = 0.5 * th1 * np.sum(w * t * _struve0(z[..., None] * t), axis=-1)
    one_minus_cos = 2.0 * np.sin(0.5 * z * m) ** 2
    return (one_minus_cos - np.pi**2 * abar * H0z + 2.0 * np.pi * abar * H0z * th1
            - 2.0 * np.pi * abar * integral)


def _coh_lhs(abar, s, alpha, beta, lam, H0z, nodes):
    b3 = np.cbrt(beta / 3.0)
    A = 2.0 * abar * b3
    out = _md_lhs(s, A, lam)
    if alpha != 0.0:
        kappa = 2.0 * np.pi * lam * alpha * b3 * b3
        out = out + kappa * _wavy_bracket(abar, s, H0z, nodes)
    return out


def _check(alpha, beta, lam):
    alpha, beta, lam = float(alpha), float(beta), float(lam)
    if not np.isfinite(alpha) or alpha < 0:
        raise InputError("alpha", f"must be finite and >= 0, got {alpha!r}")
    if not np.isfinite(beta) or beta <= 0:
        raise InputError("beta", f"must be finite and > 0, got {beta!r}")
    if not np.isfinite(lam) or lam <= 0:
        raise InputError("lam", f"must be finite and > 0, got {lam!r}")
    return alpha, beta, lam


def guduru_cohesive_equation(abar, m, alpha, beta, lam):
    """Right-hand side of Paper A Eq. 26 (equals 1 at a solution); vectorised over abar, m.

    Parameters
    ----------
    abar : array_like
        a/xi (> 0).
    m : array_like
        c/a (>= 1).
    alpha, beta, lam : float
        Paper A Eq. 30 parameters and the Maugis parameter.

    Returns
    -------
    ndarray
        gap(c)/h0 of the Maugis-Dugdale wavy solution.
    """
    alpha, beta, lam = _check(alpha, beta, lam)
    abar, m = np.broadcast_arrays(np.asarray(abar, float), np.asarray(m, float))
    s = np.sqrt(np.clip(m * m - 1.0, 0.0, None))
    H0z = struve(0, 2.0 * np.pi * abar)
    nodes = _nodes(float(np.max(abar)) if abar.size else 0.0)
    return _coh_lhs(abar, s, alpha, beta, lam, H0z, nodes)


def guduru_hertz_force(abar, alpha, beta):
    """Non-adhesive force P1(abar) of Eq. 29 (in units of pi dgamma R), H0/H1 form.

    8 beta abar^3/3 + alpha beta (4 pi^2 abar^2 H0(2 pi abar) - 2 pi abar H1(2 pi abar)),
    identical to Paper A's 4 beta [2 abar^3/3 + alpha (4 pi^2 abar^3/3 + pi abar H1/2
    - pi^2 abar^2 H2)] through H0 + H2 = (2/z) H1 + 2z/(3 pi), without its cancellation.

    Parameters
    ----------
    abar : float or array_like
        Contact radii a/xi (dimensionless).
    alpha : float
        A R/xi^2 (dimensionless, see :func:`guduru_parameters`).
    beta : float
        xi^3 E*/(2 pi dgamma R^2) (dimensionless).

    Returns
    -------
    float or ndarray
        P1 (units of pi dgamma R), shape of ``abar``.
    """
    abar = np.asarray(abar, float)
    z = 2.0 * np.pi * abar
    return (8.0 * beta * abar**3 / 3.0
            + alpha * beta * (4.0 * np.pi**2 * abar**2 * struve(0, z) - 2.0 * np.pi * abar * struve(1, z)))


def _solve_s(abar, alpha, beta, lam, H0z, nodes):
    """Smallest s = sqrt(m^2-1) >= 0 solving Eq. 26 at each abar (vectorised)."""
    n = abar.size
    # scan points: s geometric on [1e-9, 1] (m up to sqrt 2), then m growing by 5 % per step
    # but by at most 1/(8 abar), an eighth of the period of cos(2 pi abar m) in Eq. 26
    s_geo = np.concatenate([[0.0], np.geomspace(1e-9, 1.0, 37)])
    r = 0.05
    dm = 1.0 / (8.0 * np.maximum(abar, 1e-300))
    m_sw = np.maximum(dm / r, np.sqrt(2.0))
    k_sw = np.ceil(np.log(m_sw / np.sqrt(2.0)) / np.log1p(r))

    def s_at(k, idx):
        k = np.asarray(k)
        out = np.empty(k.shape)
        geo = k < s_geo.size
        out[geo] = s_geo[k[geo]]
        kk = (k[~geo] - s_geo.size + 1).astype(float)
        ks = k_sw[idx][~geo]
        m_geo = np.sqrt(2.0) * (1.0 + r) ** np.minimum(kk, ks)
        mm = m_geo + np.maximum(kk - ks, 0.0) * dm[idx][~geo]
        out[~geo] = np.sqrt(mm * mm - 1.0)
        return out

    lo = np.zeros(n)
    flo = -np.ones(n)
    hi = np.full(n, np.nan)
    fhi = np.full(n, np.nan)
    active = np.ones(n, dtype=bool)
    k0 = 1
    chunk = 16
    while np.any(active):
        idx = np.flatnonzero(active)
        ks = k0 + np.arange(chunk)
        K = np.broadcast_to(ks, (idx.size, chunk))
        I = np.broadcast_to(idx[:, None], (idx.size, chunk))
        S = s_at(K.ravel(), I.ravel()).reshape(idx.size, chunk)
        F = _coh_lhs(np.repeat(abar[idx], chunk).reshape(idx.size, chunk), S, alpha, beta, lam,
                     np.repeat(H0z[idx], chunk).reshape(idx.size, chunk), nodes) - 1.0
        pos = F > 0
        found = np.any(pos, axis=1)
        first = np.argmax(pos, axis=1)
        for row in np.flatnonzero(found):
            j = idx[row]
            c = first[row]
            hi[j], fhi[j] = S[row, c], F[row, c]
            if c > 0:
                lo[j], flo[j] = S[row, c - 1], F[row, c - 1]
            active[j] = False
        for row in np.flatnonzero(~found):
            j = idx[row]
            lo[j], flo[j] = S[row, -1], F[row, -1]
        k0 += chunk
        if k0 > 10_000_000:
            raise RuntimeError("no root of the cohesive-zone equation found")

    def f(x, idx):
        return _coh_lhs(abar[idx], x, alpha, beta, lam, H0z[idx], nodes) - 1.0

    return _bracketed_root(f, lo, hi, flo, fhi)


@dataclass(frozen=True)
class GuduruCurve:
    """Dimensionless force-approach curve of a sphere on a wavy surface (Paper A Eqs. 26-30).

    Attributes
    ----------
    abar : ndarray
        Contact radius a/xi.
    m : ndarray
        c/a (1 in the JKR limit).
    P : ndarray
        Force F/(pi dgamma R), compressive positive.
    Delta : ndarray
        Approach delta R/xi^2.
    alpha, beta, lam : float
        Parameters (lam = inf for :func:`guduru_jkr_curve`).
    """

    abar: np.ndarray
    m: np.ndarray
    P: np.ndarray
    Delta: np.ndarray
    alpha: float
    beta: float
    lam: float


def guduru_curve(alpha, beta, lam, abar) -> GuduruCurve:
    """Maugis-Dugdale force-approach curve of a rigid sphere on a wavy half-space.

    Solves Eq. 26 for m at every abar (smallest root, see module docstring), then Eqs. 27-29.

    Parameters
    ----------
    alpha : float
        A R/xi^2 (>= 0; 0 is the smooth sphere, identical to Maugis-Dugdale).
    beta : float
        xi^3 E*/(2 pi dgamma R^2).
    lam : float
        Maugis parameter of the sphere, 2 sigma0 (9R/(16 pi dgamma E*^2))^(1/3).
    abar : array_like
        Contact radii a/xi (> 0).

    Returns
    -------
    GuduruCurve
    """
    alpha, beta, lam = _check(alpha, beta, lam)
    ab = np.atleast_1d(np.asarray(abar, dtype=float)).ravel()
    if np.any(ab <= 0) or not np.all(np.isfinite(ab)):
        raise InputError("abar", "contact radii a/xi must be finite and > 0")
    z = 2.0 * np.pi * ab
    H0z = struve(0, z)
    # quadrature nodes: H0 is sampled on [0, 2 pi abar] whatever m (Eq. 26 integral)
    nodes = _nodes(float(ab.max()))
    s = _solve_s(ab, alpha, beta, lam, H0z, nodes)
    b3 = np.cbrt(beta / 3.0)
    _, _, _, bf = _md_brackets(s)
    P = guduru_hertz_force(ab, alpha, beta) - 4.0 * lam * ab**2 * b3 * b3 * bf
    Delta = ab**2 + ab * (np.pi**2 * alpha * H0z - 2.0 * lam * np.cbrt(1.0 / (9.0 * beta)) * s)
    shape = np.shape(abar)
    m = np.sqrt(1.0 + s * s)
    return GuduruCurve(abar=ab.reshape(shape), m=m.reshape(shape), P=P.reshape(shape),
                       Delta=Delta.reshape(shape), alpha=alpha, beta=beta, lam=lam)


def guduru_jkr_curve(alpha, beta, abar) -> GuduruCurve:
    """JKR-type closed form of Guduru (2007) in Paper A's variables (the lambda -> inf limit).

    P = P1(abar) - 4 sqrt(beta abar^3),  Delta = abar^2 + pi^2 alpha abar H0(2 pi abar)
    - sqrt(abar/beta)  (the JKR terms sqrt(8 pi a^3 E* dgamma), sqrt(2 pi a dgamma/E*) in these
    units).

    Parameters
    ----------
    alpha, beta : float
        See :func:`guduru_curve`.
    abar : array_like
        a/xi.

    Returns
    -------
    GuduruCurve
        ``P`` and ``Delta`` at ``abar``, with ``m = 1`` (no cohesive zone) and ``lam = inf``.
    """
    alpha, beta, _ = _check(alpha, beta, 1.0)
    ab = np.asarray(abar, dtype=float)
    P = guduru_hertz_force(ab, alpha, beta) - 4.0 * np.sqrt(beta * ab**3)
    Delta = ab**2 + np.pi**2 * alpha * ab * struve(0, 2.0 * np.pi * ab) - np.sqrt(ab / beta)
    return GuduruCurve(abar=ab, m=np.ones_like(ab), P=P, Delta=Delta, alpha=alpha, beta=beta,
                       lam=np.inf)


def guduru_parameters(radius, amplitude, wavelength, dgamma, E_star, z0=None):
    """Dimensionless (alpha, beta, lam) of Paper A Eq. 30 (lam is None without z0).

    alpha = A R/xi^2, beta = xi^3 E*/(2 pi dgamma R^2), lam = Maugis parameter of the sphere.

    Parameters
    ----------
    radius : float
        Sphere radius R (m).
    amplitude : float
        Waviness amplitude A (m).
    wavelength : float
        Waviness wavelength xi (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    z0 : float, optional
        Equilibrium distance (m); needed for lam only.

    Returns
    -------
    alpha, beta : float
        Paper A Eq. 30 parameters (dimensionless).
    lam : float or None
        Maugis parameter of the sphere (:func:`~tribobem.analytic.adhesion.maugis_parameter`);
        None without ``z0``.
    """
    R, A, xi, g, E = (float(v) for v in (radius, amplitude, wavelength, dgamma, E_star))
    alpha = A * R / xi**2
    beta = xi**3 * E / (2.0 * np.pi * g * R**2)
    lam = None if z0 is None else float(maugis_parameter(R, g, E, z0))
    return alpha, beta, lam


@dataclass(frozen=True)
class GuduruSolution:
    """Dimensional Maugis-Dugdale state of a rigid sphere on a wavy elastic half-space.

    Attributes
    ----------
    contact_radius : float or ndarray
        a (m).
    cohesive_radius : float or ndarray
        c = m a (m).
    force : float or ndarray
        F (N), compressive positive.
    approach : float or ndarray
        delta (m).
    m : float or ndarray
        c/a.
    alpha, beta, lam : float
        Paper A Eq. 30 parameters and the Maugis parameter.
    """

    contact_radius: float | np.ndarray
    cohesive_radius: float | np.ndarray
    force: float | np.ndarray
    approach: float | np.ndarray
    m: float | np.ndarray
    alpha: float
    beta: float
    lam: float


def guduru(radius, amplitude, wavelength, dgamma, E_star, z0, a) -> GuduruSolution:
    """Sphere (radius R) on h = r^2/(2R) + A (1 - cos(2 pi r/xi)), Maugis-Dugdale adhesion.

    Parameters
    ----------
    radius : float
        Sphere radius R (m).
    amplitude : float
        Waviness amplitude A (m).
    wavelength : float
        Waviness wavelength xi (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa) (E/(1 - nu^2) for a rigid sphere on an elastic half-space).
    z0 : float
        Equilibrium distance (m).
    a : float or array_like
        Contact radii (m), > 0.

    Returns
    -------
    GuduruSolution
        Force F = P pi dgamma R, approach delta = Delta xi^2/R, cohesive radius c = m a.
    """
    for nm, v in (("radius", radius), ("wavelength", wavelength), ("dgamma", dgamma),
                  ("E_star", E_star), ("z0", z0)):
        if not np.isfinite(v) or v <= 0:
            raise InputError(nm, f"must be finite and > 0, got {v!r}")
    if not np.isfinite(amplitude) or amplitude < 0:
        raise InputError("amplitude", f"must be finite and >= 0, got {amplitude!r}")
    alpha, beta, lam = guduru_parameters(radius, amplitude, wavelength, dgamma, E_star, z0)
    a_arr = np.asarray(a, float)
    cur = guduru_curve(alpha, beta, lam, a_arr / wavelength)

    def o(x):
        x = np.asarray(x, float)
        return float(x) if x.ndim == 0 else x

    return GuduruSolution(
        contact_radius=o(a_arr), cohesive_radius=o(cur.m * a_arr),
        force=o(cur.P * np.pi * dgamma * radius), approach=o(cur.Delta * wavelength**2 / radius),
        m=o(cur.m), alpha=alpha, beta=beta, lam=lam)
