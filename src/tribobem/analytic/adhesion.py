"""Adhesive sphere-on-flat contact: Bradley, JKR, DMT and Maugis-Dugdale (thesis Appendix A.2).

Conventions
-----------
SI units.  ``E_star`` is the composite modulus 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,
``dgamma`` the work of adhesion (J/m^2), ``z0`` the equilibrium distance (m), ``radius`` the
composite sphere radius R (m).  Forces are positive when compressive; every *pull-off force*
returned by a function named ``*_pull_off*`` is NEGATIVE (the most tensile force); the
``*_pull_off_magnitude`` helpers return its absolute value.  Approach delta > 0 pushes the bodies
together.

Dugdale (Maugis) cohesive law (Paper A Eq. 2)::

    sigma0 = 16 dgamma / (9 sqrt(3) z0),     h0 = dgamma / sigma0 = 9 sqrt(3) z0 / 16 = 0.974 z0

Tabor and Maugis parameters (Paper A Eq. 1 and Paper D Eq. 14 misprint mu_T)::

    mu_T   = (R dgamma^2 / (E*^2 z0^3))^(1/3)
    lambda = 2 sigma0 (9 R / (16 pi dgamma E*^2))^(1/3)  (= 1.157 mu_T)

Maugis-Dugdale in the Johnson-Greenwood (1997) form, thesis Eqs. A.18-A.24, with m = c/a the
ratio of cohesive to contact radius::

    A_M = a (4 E* / (3 pi dgamma R^2))^(1/3),   F_M = F / (pi R dgamma),
    F_M = A^3 - lambda A^2 (sqrt(m^2-1) + m^2 arctan sqrt(m^2-1))                      (A.21)
    lambda A^2/2 [sqrt(m^2-1) + (m^2-2) arctan sqrt(m^2-1)]
        + 4 lambda^2 A/3 [sqrt(m^2-1) arctan sqrt(m^2-1) - m + 1] = 1                  (A.22)
    Delta_M = delta (16 E*^2 / (9 pi^2 dgamma^2 R))^(1/3) = A^2 - 4/3 A lambda sqrt(m^2-1)   (A.24)

(the thesis prints E_s instead of E_s^2 in A.24: corrected here).  Numerically the
unknown is s = sqrt(m^2 - 1) >= 0, so that the JKR-like limit (m -> 1) keeps full relative
accuracy.  At fixed A the left side of A.22 is strictly increasing in m (both brackets have
positive derivative 2 sqrt(m^2-1)/m + 2 m arctan sqrt(m^2-1) and
m arctan(sqrt(m^2-1))/sqrt(m^2-1) + 1/m - 1 > 0) and is 0 at m = 1, so the root is unique.

The curve parametrised by A includes its A -> 0 end point (c = m a stays finite): with
C = lim A m, pi lambda C^2/4 + (4 lambda^2/3)(pi/2 - 1) C = 1, F_M = -pi lambda C^2/2,
Delta_M = -4 lambda C/3.  For small lambda the force-controlled pull-off is this end point
(the classical DMT value -2 pi R dgamma as lambda -> 0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..errors import InputError

__all__ = [
    "dugdale_stress", "dugdale_range", "tabor_parameter", "maugis_parameter",
    "maugis_from_tabor", "tabor_from_maugis",
    "bradley_pull_off", "bradley_pull_off_magnitude",
    "JKRSolution", "jkr", "jkr_pressure", "jkr_pull_off", "jkr_pull_off_magnitude",
    "DMTSolution", "dmt", "dmt_pull_off", "dmt_pull_off_magnitude",
    "johnson_greenwood_pull_off_fit",
    "MaugisDugdaleCurve", "MaugisDugdaleSolution", "MaugisDugdalePullOff",
    "maugis_dugdale_curve", "maugis_dugdale", "maugis_dugdale_pressure",
    "maugis_dugdale_pull_off", "maugis_dugdale_pull_off_point",
    "maugis_dugdale_pull_off_force", "maugis_dugdale_pull_off_magnitude",
    "maugis_dugdale_scales",
]

_SQRT3 = np.sqrt(3.0)
#: lambda / mu_T = (32 / (9 sqrt 3)) (9 / (16 pi))^(1/3) = 1.1570...
MAUGIS_PER_TABOR = (32.0 / (9.0 * _SQRT3)) * (9.0 / (16.0 * np.pi)) ** (1.0 / 3.0)


# ----------------------------------------------------------------------------------------------
# small helpers
# ----------------------------------------------------------------------------------------------

def _pos(name, value):
    arr = np.asarray(value, dtype=float)
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise InputError(name, f"must be finite and > 0, got {value!r}")
    return float(arr) if arr.ndim == 0 else arr


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def _check_control(control):
    if control not in ("force", "displacement"):
        raise InputError("control", f"must be 'force' or 'displacement', got {control!r}")


def _bracketed_root(f, lo, hi, flo, fhi, rtol=1e-15, atol=0.0, maxiter=400):
    """Vectorised Illinois (modified regula falsi) root search with a bisection safeguard.

    ``f(x, idx)`` evaluates the function for the elements ``idx`` (integer index array) at the
    abscissae ``x`` (same length).  ``flo`` and ``fhi`` must have opposite signs (or be 0).
    An element whose bracket did not halve over the last two steps is bisected, so the bracket
    shrinks at least geometrically; smooth functions converge superlinearly.
    """
    a = np.array(lo, dtype=float, copy=True)
    b = np.array(hi, dtype=float, copy=True)
    fa = np.array(flo, dtype=float, copy=True)
    fb = np.array(fhi, dtype=float, copy=True)
    if np.any(fa * fb > 0):
        raise RuntimeError("root not bracketed")
    x = np.where(np.abs(fa) <= np.abs(fb), a, b)
    side = np.zeros(a.shape, dtype=np.int8)
    w1 = np.abs(b - a)          # width one step ago
    w2 = np.full(a.shape, np.inf)  # width two steps ago
    active = (fa != 0) & (fb != 0)
    for _ in range(maxiter):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        ai, bi, fai, fbi = a[idx], b[idx], fa[idx], fb[idx]
        mid = 0.5 * (ai + bi)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            c = (ai * fbi - bi * fai) / (fbi - fai)
        lo_i, hi_i = np.minimum(ai, bi), np.maximum(ai, bi)
        bad = ~((c > lo_i) & (c < hi_i)) | (np.abs(bi - ai) > 0.5 * w2[idx])
        c = np.where(bad, mid, c)
        fc = np.asarray(f(c, idx), dtype=float)
        x[idx] = c
        same_b = fc * fbi > 0
        same_a = fc * fai > 0
        # c replaces b (Illinois: halve the retained end value if it was retained before)
        jb = idx[same_b]
        fa[idx[same_b & (side[idx] == -1)]] *= 0.5
        b[jb] = c[same_b]
        fb[jb] = fc[same_b]
        side[jb] = -1
        # c replaces a
        ja = idx[same_a]
        fb[idx[same_a & (side[idx] == 1)]] *= 0.5
        a[ja] = c[same_a]
        fa[ja] = fc[same_a]
        side[ja] = 1
        width = np.abs(b[idx] - a[idx])
        w2[idx] = w1[idx]
        w1[idx] = width
        conv = (fc == 0) | (width <= atol + rtol * np.abs(c))
        active[idx[conv]] = False
    return x


# ----------------------------------------------------------------------------------------------
# parameters
# ----------------------------------------------------------------------------------------------

def dugdale_stress(dgamma, z0):
    """Dugdale stress sigma0 = 16 dgamma / (9 sqrt(3) z0) (Pa): the peak Lennard-Jones tension.

    Parameters
    ----------
    dgamma : float or array_like
        Work of adhesion (J/m^2).
    z0 : float or array_like
        Equilibrium distance (m).

    Returns
    -------
    float or ndarray
        sigma0 (Pa), broadcast over the inputs.
    """
    return _out(16.0 * np.asarray(dgamma, float) / (9.0 * _SQRT3 * np.asarray(z0, float)))


def dugdale_range(z0):
    """Dugdale range h0 = dgamma/sigma0 = 9 sqrt(3) z0 / 16 = 0.974 z0 (m).

    The range follows from equal work of adhesion, sigma0 h0 = dgamma, with the Dugdale stress
    of :func:`dugdale_stress`.  (Paper D prints "9 sqrt(3) z0": wrong.)

    Parameters
    ----------
    z0 : float or array_like
        Equilibrium distance (m).

    Returns
    -------
    float or ndarray
        h0 (m), shape of ``z0``.
    """
    return _out(9.0 * _SQRT3 * np.asarray(z0, float) / 16.0)


def tabor_parameter(radius, dgamma, E_star, z0):
    """Tabor parameter mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3) (dimensionless, Eq. A.15).

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    z0 : float
        Equilibrium distance (m).

    Returns
    -------
    float or ndarray
        mu_T (dimensionless), broadcast over the inputs.
    """
    R, g, E, z = (np.asarray(v, float) for v in (radius, dgamma, E_star, z0))
    return _out(np.cbrt(R * g**2 / (E**2 * z**3)))


def maugis_parameter(radius, dgamma, E_star, z0):
    """Maugis parameter lambda = 2 sigma0 (9 R / (16 pi dgamma E*^2))^(1/3) (Eq. A.20).

    With sigma0 = 16 dgamma/(9 sqrt 3 z0), lambda = 1.1570 mu_T (:data:`MAUGIS_PER_TABOR`).

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    z0 : float
        Equilibrium distance (m).

    Returns
    -------
    float or ndarray
        lambda (dimensionless), broadcast over the inputs.
    """
    R, g, E = (np.asarray(v, float) for v in (radius, dgamma, E_star))
    s0 = dugdale_stress(dgamma, z0)
    return _out(2.0 * s0 * np.cbrt(9.0 * R / (16.0 * np.pi * g * E**2)))


def maugis_from_tabor(mu_T):
    """Maugis parameter from the Tabor parameter: lambda = 1.1570 mu_T.

    The factor :data:`MAUGIS_PER_TABOR` is exact for the Dugdale stress of Paper A Eq. 2.

    Parameters
    ----------
    mu_T : float or array_like
        Tabor parameter (dimensionless).

    Returns
    -------
    float or ndarray
        lambda (dimensionless), shape of ``mu_T``.
    """
    return _out(MAUGIS_PER_TABOR * np.asarray(mu_T, float))


def tabor_from_maugis(lam):
    """Tabor parameter from the Maugis parameter: mu_T = lambda / 1.1570.

    Inverse of :func:`maugis_from_tabor`.

    Parameters
    ----------
    lam : float or array_like
        Maugis parameter lambda (dimensionless).

    Returns
    -------
    float or ndarray
        mu_T (dimensionless), shape of ``lam``.
    """
    return _out(np.asarray(lam, float) / MAUGIS_PER_TABOR)


# ----------------------------------------------------------------------------------------------
# Bradley, JKR, DMT
# ----------------------------------------------------------------------------------------------

def bradley_pull_off(radius, dgamma):
    """Bradley (rigid spheres) pull-off force -2 pi R dgamma (N, negative).

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).

    Returns
    -------
    float or ndarray
        Pull-off force (N, negative), broadcast over the inputs.
    """
    return _out(-2.0 * np.pi * np.asarray(radius, float) * np.asarray(dgamma, float))


def bradley_pull_off_magnitude(radius, dgamma):
    """|Bradley pull-off force| = 2 pi R dgamma (N, positive).

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force (N, positive).
    """
    return _out(-np.asarray(bradley_pull_off(radius, dgamma)))


@dataclass(frozen=True)
class JKRSolution:
    """JKR sphere-on-flat state.

    Attributes
    ----------
    contact_radius : float or ndarray
        a (m).
    force : float or ndarray
        F = 4 E* a^3/(3R) - sqrt(8 pi a^3 E* dgamma) (N).
    approach : float or ndarray
        delta = a^2/R - sqrt(2 pi a dgamma / E*) (m).
    """

    contact_radius: float | np.ndarray
    force: float | np.ndarray
    approach: float | np.ndarray


def _jkr_from_a(a, R, g, E):
    F = 4.0 * E * a**3 / (3.0 * R) - np.sqrt(8.0 * np.pi * a**3 * E * g)
    d = a**2 / R - np.sqrt(2.0 * np.pi * a * g / E)
    return F, d


def jkr(radius, dgamma, E_star, *, force=None, contact_radius=None, approach=None) -> JKRSolution:
    """JKR contact of a sphere on a flat (thesis Eqs. A.9-A.12).

    Give exactly one of ``force``, ``contact_radius`` or ``approach``.  From a force the
    stable (largest-a) branch is returned, Eq. A.10::

        a^3 = 3R/(4E*) (F + 3 pi R dgamma + sqrt(6 pi R dgamma F + (3 pi R dgamma)^2));

    from an approach the largest a solving delta = a^2/R - sqrt(2 pi a dgamma/E*).

    Parameters
    ----------
    radius, dgamma, E_star : float
        R (m), work of adhesion (J/m^2), composite modulus (Pa).
    force : float or array_like, optional
        F >= -1.5 pi R dgamma (N).
    contact_radius : float or array_like, optional
        a >= 0 (m).
    approach : float or array_like, optional
        delta (m), >= the fixed-grip minimum -(3/4)(pi^2 dgamma^2 R / E*^2)^(1/3) (m).

    Returns
    -------
    JKRSolution
    """
    R, g, E = _pos("radius", radius), _pos("dgamma", dgamma), _pos("E_star", E_star)
    if sum(v is not None for v in (force, contact_radius, approach)) != 1:
        raise InputError("jkr", "give exactly one of force=, contact_radius=, approach=")
    if contact_radius is not None:
        a = np.asarray(contact_radius, float)
        if np.any(a < 0):
            raise InputError("contact_radius", "must be >= 0")
    elif force is not None:
        F = np.asarray(force, float)
        P = 3.0 * np.pi * R * g
        if np.any(F < -P / 2.0 * (1 + 1e-12)):
            raise InputError("force", f"below the JKR pull-off force {-P / 2:.6g} N: no equilibrium")
        a = np.cbrt(3.0 * R / (4.0 * E) * (F + P + np.sqrt(np.clip(2.0 * P * F + P**2, 0.0, None))))
    else:
        dd = np.atleast_1d(np.asarray(approach, float))
        k = np.sqrt(2.0 * np.pi * g / E)
        x_min = np.cbrt(k * R / 4.0)   # x = sqrt(a); d(delta)/dx = 4x^3/R - k = 0
        d_min = x_min**4 / R - k * x_min
        if np.any(dd < d_min * (1 + 1e-12)):
            raise InputError("approach", f"below the JKR fixed-grip minimum {d_min:.6g} m: no equilibrium")
        xs = []
        for d in dd:
            hi = max(2.0 * x_min, 1e-300)
            while hi**4 / R - k * hi - d <= 0:
                hi *= 2.0
            xs.append(brentq(lambda x: x**4 / R - k * x - d, x_min, hi, xtol=1e-300, rtol=1e-15))
        a = np.asarray(xs) ** 2
        a = a.reshape(np.shape(approach))
    F, d = _jkr_from_a(a, R, g, E)
    return JKRSolution(contact_radius=_out(a), force=_out(F), approach=_out(d))


def jkr_pressure(r, contact_radius, radius, dgamma, E_star):
    """JKR pressure (Eq. A.9), Pa; -inf-like singular at r = a, 0 outside.

    p(r) = 2 a E*/(pi R) sqrt(1 - r^2/a^2) - sqrt(2 dgamma E*/(pi a)) / sqrt(1 - r^2/a^2).

    Parameters
    ----------
    r : array_like
        Radial positions (m).
    contact_radius : float
        Contact radius a (m), > 0.
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).

    Returns
    -------
    float or ndarray
        Pressure (Pa, compressive positive), shape of ``r``; -inf at r = a (the JKR crack-tip
        singularity) and 0 for r >= a.
    """
    r = np.asarray(r, float)
    a = float(contact_radius)
    rho2 = np.clip(1.0 - (r / a) ** 2, 0.0, None)
    with np.errstate(divide="ignore"):
        p = 2.0 * a * E_star / (np.pi * radius) * np.sqrt(rho2) - np.sqrt(
            2.0 * dgamma * E_star / (np.pi * a)) / np.sqrt(rho2)
    p = np.where(r < a, p, 0.0)
    return _out(p)


def jkr_pull_off(radius, dgamma, control="force"):
    """JKR pull-off force (N, negative).

    ``control="force"``: -3/2 pi R dgamma (Eq. A.12); ``control="displacement"`` (fixed grips,
    jump-off at the minimum of the approach): -5/6 pi R dgamma.

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).
    control : {"force", "displacement"}
        Loading control: force control (the pull-off is the minimum of the force) or fixed
        grips (the jump-off at the minimum of the approach).

    Returns
    -------
    float or ndarray
        Pull-off force (N, negative), broadcast over ``radius`` and ``dgamma``.

    Raises
    ------
    InputError
        ``control`` is neither ``"force"`` nor ``"displacement"``.
    """
    _check_control(control)
    f = 1.5 if control == "force" else 5.0 / 6.0
    return _out(-f * np.pi * np.asarray(radius, float) * np.asarray(dgamma, float))


def jkr_pull_off_magnitude(radius, dgamma, control="force"):
    """|JKR pull-off force| (N, positive); see :func:`jkr_pull_off`.

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).
    control : {"force", "displacement"}
        Loading control: force control (the pull-off is the minimum of the force) or fixed
        grips (the jump-off at the minimum of the approach).

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force (N, positive).
    """
    return _out(-np.asarray(jkr_pull_off(radius, dgamma, control)))


@dataclass(frozen=True)
class DMTSolution:
    """DMT sphere-on-flat state (Eq. A.13): a^3 = 3R (F + 2 pi R dgamma)/(4E*), delta = a^2/R.

    Attributes
    ----------
    contact_radius : float or ndarray
        a (m).
    force : float or ndarray
        F (N).
    approach : float or ndarray
        delta (m).
    """

    contact_radius: float | np.ndarray
    force: float | np.ndarray
    approach: float | np.ndarray


def dmt(radius, dgamma, E_star, *, force=None, contact_radius=None, approach=None) -> DMTSolution:
    """DMT contact of a sphere on a flat (Eqs. A.13-A.14): Hertz shifted by the adhesive load.

    Give exactly one of ``force``, ``contact_radius`` or ``approach``.

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    force : float or array_like, optional
        Normal force F >= -2 pi R dgamma (N, compressive positive).
    contact_radius : float or array_like, optional
        Contact radius a >= 0 (m).
    approach : float or array_like, optional
        Approach delta >= 0 (m).

    Returns
    -------
    DMTSolution
        Contact radius, force and approach (vectorised).

    Raises
    ------
    InputError
        Not exactly one of ``force``, ``contact_radius``, ``approach``; a non-positive
        ``radius``, ``dgamma`` or ``E_star``; a force below the DMT pull-off or a negative
        approach.
    """
    R, g, E = _pos("radius", radius), _pos("dgamma", dgamma), _pos("E_star", E_star)
    if sum(v is not None for v in (force, contact_radius, approach)) != 1:
        raise InputError("dmt", "give exactly one of force=, contact_radius=, approach=")
    Fa = 2.0 * np.pi * R * g
    if force is not None:
        F = np.asarray(force, float)
        if np.any(F < -Fa * (1 + 1e-12)):
            raise InputError("force", f"below the DMT pull-off force {-Fa:.6g} N")
        a = np.cbrt(3.0 * R * np.clip(F + Fa, 0.0, None) / (4.0 * E))
    elif contact_radius is not None:
        a = np.asarray(contact_radius, float)
    else:
        d = np.asarray(approach, float)
        if np.any(d < 0):
            raise InputError("approach", "must be >= 0 in the DMT model")
        a = np.sqrt(R * d)
    F = 4.0 * E * a**3 / (3.0 * R) - Fa
    return DMTSolution(contact_radius=_out(a), force=_out(F), approach=_out(a**2 / R))


def dmt_pull_off(radius, dgamma):
    """DMT pull-off force -2 pi R dgamma (N, negative; Eq. A.14).

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).

    Returns
    -------
    float or ndarray
        Pull-off force (N, negative), broadcast over the inputs.
    """
    return _out(-2.0 * np.pi * np.asarray(radius, float) * np.asarray(dgamma, float))


def dmt_pull_off_magnitude(radius, dgamma):
    """|DMT pull-off force| = 2 pi R dgamma (N, positive).

    Parameters
    ----------
    radius : float or array_like
        Composite sphere radius R (m).
    dgamma : float or array_like
        Work of adhesion (J/m^2).

    Returns
    -------
    float or ndarray
        Magnitude of the pull-off force (N, positive).
    """
    return _out(-np.asarray(dmt_pull_off(radius, dgamma)))


def johnson_greenwood_pull_off_fit(lam):
    """Johnson & Greenwood (1997) approximation of the MD pull-off force, F/(pi R dgamma).

    F_M = -7/4 + (1/4) (4.04 lambda^1.4 - 1) / (4.04 lambda^1.4 + 1): -2 at lambda = 0
    (DMT), -1.5 as lambda -> inf (JKR).  An empirical fit (Johnson & Greenwood, J. Colloid
    Interface Sci. 192, 326 (1997)); it agrees with the exact value of
    :func:`maugis_dugdale_pull_off` to within 1.7 % for every lambda (checked in the tests).

    Parameters
    ----------
    lam : float or array_like
        Maugis parameter lambda (dimensionless, >= 0).

    Returns
    -------
    float or ndarray
        F_M = F_pull-off / (pi R dgamma) (dimensionless, negative), shape of ``lam``.
    """
    x = 4.04 * np.asarray(lam, float) ** 1.4
    return _out(-1.75 + 0.25 * (x - 1.0) / (x + 1.0))


# ----------------------------------------------------------------------------------------------
# Maugis-Dugdale
# ----------------------------------------------------------------------------------------------

def _s_minus_atan(s):
    """s - arctan(s) without cancellation for small s."""
    s = np.asarray(s, dtype=float)
    out = s - np.arctan(s)
    small = np.abs(s) < 0.1
    if np.any(small):
        x = s[small]
        x2 = x * x
        ser = 1.0 / 17.0
        for k in (15, 13, 11, 9, 7, 5, 3):
            ser = 1.0 / k - x2 * ser
        out[small] = x * x2 * ser
    return out


def _md_brackets(s):
    """Return (T, bracket of A.22 first term, of A.22 second term, of A.21) at s = sqrt(m^2-1)."""
    s = np.asarray(s, dtype=float)
    T = np.arctan(s)
    m = np.sqrt(1.0 + s * s)
    b1 = _s_minus_atan(s) + s * s * T           # sqrt(m^2-1) + (m^2-2) atan sqrt(m^2-1)
    b2 = s * T - s * s / (1.0 + m)              # sqrt(m^2-1) atan sqrt(m^2-1) - m + 1
    bf = s + (1.0 + s * s) * T                  # sqrt(m^2-1) + m^2 atan sqrt(m^2-1)
    return T, b1, b2, bf


def _md_lhs(s, A, lam):
    _, b1, b2, _ = _md_brackets(s)
    return 0.5 * lam * A * A * b1 + (4.0 / 3.0) * lam * lam * A * b2


def _md_C0(lam):
    """C = lim_{A->0} A m: root of pi lam C^2/4 + (4 lam^2/3)(pi/2 - 1) C - 1 = 0."""
    qa = np.pi * lam / 4.0
    qb = 4.0 * lam * lam / 3.0 * (np.pi / 2.0 - 1.0)
    return 2.0 / (qb + np.sqrt(qb * qb + 4.0 * qa))


def _md_solve_s(A, lam):
    """Solve A.22 for s = sqrt(m^2-1) at each A > 0 (vectorised)."""
    A = np.atleast_1d(np.asarray(A, dtype=float))
    lo = np.zeros_like(A)
    flo = -np.ones_like(A)
    # initial upper bracket from the two leading terms, then doubling
    C = _md_C0(lam)
    hi = np.maximum(1.0, 2.0 * C / np.maximum(A, 1e-300))
    fhi = _md_lhs(hi, A, lam) - 1.0
    for _ in range(2000):
        bad = fhi <= 0
        if not np.any(bad):
            break
        hi[bad] *= 2.0
        fhi[bad] = _md_lhs(hi[bad], A[bad], lam) - 1.0

    def f(x, idx):
        return _md_lhs(x, A[idx], lam) - 1.0

    return _bracketed_root(f, lo, hi, flo, fhi)


def _check_lam(lam):
    lam = float(lam)
    if not np.isfinite(lam) or lam <= 0:
        raise InputError("lam", f"Maugis parameter must be finite and > 0, got {lam!r}")
    return lam


@dataclass(frozen=True)
class MaugisDugdaleCurve:
    """Dimensionless Maugis-Dugdale curve (Johnson-Greenwood units, Eqs. A.18-A.24).

    Attributes
    ----------
    lam : float
        Maugis parameter lambda.
    A : ndarray
        Contact radius A_M = a (4E*/(3 pi dgamma R^2))^(1/3).
    m : ndarray
        c/a (inf where A = 0).
    F : ndarray
        Force F_M = F/(pi R dgamma) (compressive positive).
    Delta : ndarray
        Approach Delta_M = delta (16 E*^2/(9 pi^2 dgamma^2 R))^(1/3).
    C : ndarray
        Cohesive radius in the units of A (C = m A, finite at A = 0).
    """

    lam: float
    A: np.ndarray
    m: np.ndarray
    F: np.ndarray
    Delta: np.ndarray
    C: np.ndarray


def _md_curve_arrays(lam, A):
    A = np.atleast_1d(np.asarray(A, dtype=float))
    if np.any(A < 0) or not np.all(np.isfinite(A)):
        raise InputError("A", "contact radii must be finite and >= 0")
    s = np.full_like(A, np.inf)
    pos = A > 0
    if np.any(pos):
        s[pos] = _md_solve_s(A[pos], lam)
    F = np.empty_like(A)
    D = np.empty_like(A)
    Cc = np.empty_like(A)
    if np.any(pos):
        _, _, _, bf = _md_brackets(s[pos])
        Ap = A[pos]
        F[pos] = Ap**3 - lam * Ap**2 * bf
        D[pos] = Ap**2 - (4.0 / 3.0) * Ap * lam * s[pos]
        Cc[pos] = Ap * np.sqrt(1.0 + s[pos] ** 2)
    if np.any(~pos):
        C0 = _md_C0(lam)
        F[~pos] = -np.pi * lam * C0**2 / 2.0
        D[~pos] = -4.0 * lam * C0 / 3.0
        Cc[~pos] = C0
    m = np.sqrt(1.0 + s**2)
    return A, m, F, D, Cc


def maugis_dugdale_curve(lam, A=None, m=None, n=400, A_max=3.0) -> MaugisDugdaleCurve:
    """Full dimensionless Maugis-Dugdale curve, parametrised by the contact radius A_M.

    Parameters
    ----------
    lam : float
        Maugis parameter lambda (> 0).
    A : array_like, optional
        Contact radii A_M >= 0 at which to evaluate (A = 0 gives the A -> 0 end point).
    m : array_like, optional
        Alternatively c/a >= 1 values; then A.22 is a quadratic in A, solved explicitly.
    n : int
        Number of points of the default grid ``A = linspace(0, A_max, n)``.
    A_max : float
        Largest A_M of the default grid.

    Returns
    -------
    MaugisDugdaleCurve
        Arrays A, m, F (= F_M), Delta (= Delta_M), C (= m A).

    Notes
    -----
    Solves A.22 for m at every A with a bracketed, vectorised Illinois iteration in
    s = sqrt(m^2 - 1) (relative tolerance 1e-15); the root is unique (module docstring).
    """
    lam = _check_lam(lam)
    if A is not None and m is not None:
        raise InputError("maugis_dugdale_curve", "give A= or m=, not both")
    if m is not None:
        mm = np.atleast_1d(np.asarray(m, dtype=float))
        if np.any(mm < 1):
            raise InputError("m", "c/a must be >= 1")
        s = np.sqrt(mm**2 - 1.0)
        _, b1, b2, bf = _md_brackets(s)
        qa = 0.5 * lam * b1
        qb = (4.0 / 3.0) * lam * lam * b2
        with np.errstate(divide="ignore", invalid="ignore"):
            Av = 2.0 / (qb + np.sqrt(qb * qb + 4.0 * qa))
        F = Av**3 - lam * Av**2 * bf
        D = Av**2 - (4.0 / 3.0) * Av * lam * s
        return MaugisDugdaleCurve(lam, Av, mm, F, D, mm * Av)
    if A is None:
        A = np.linspace(0.0, A_max, int(n))
    Av, mv, F, D, Cc = _md_curve_arrays(lam, A)
    return MaugisDugdaleCurve(lam, Av, mv, F, D, Cc)


def _md_point(lam, A):
    _, m, F, D, _ = _md_curve_arrays(lam, np.array([A]))
    return m[0], F[0], D[0]


def _md_argmin(lam, which, A_max=3.0, n=301):
    """Location A >= 0 of the minimum of F_M (which=2) or Delta_M (which=3) on the curve."""
    A = np.linspace(0.0, A_max, n)
    arrs = _md_curve_arrays(lam, A)
    y = arrs[which]
    i = int(np.argmin(y))
    if i == n - 1:
        raise RuntimeError("minimum not bracketed on the A grid")
    lo = A[max(i - 1, 0)]
    hi = A[i + 1]
    res = minimize_scalar(lambda x: _md_curve_arrays(lam, np.array([x]))[which][0],
                          bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-12 * max(hi, 1.0), "maxiter": 500})
    Ab = float(res.x)
    yb = float(res.fun)
    # the minimum may sit exactly at the A = 0 end point
    y0 = float(arrs[which][0])
    if y0 <= yb + 1e-13 * max(1.0, abs(yb)):
        Ab, yb = 0.0, y0
    return Ab, yb


@dataclass(frozen=True)
class MaugisDugdalePullOff:
    """Maugis-Dugdale pull-off point (dimensionless, Johnson-Greenwood units).

    Attributes
    ----------
    lam : float
        Maugis parameter.
    control : str
        ``"force"`` (minimum of F_M along the curve) or ``"displacement"`` (the jump-off point,
        minimum of Delta_M along the curve).
    force : float
        F_M at pull-off (negative).
    contact_radius : float
        A_M at pull-off (0 when it happens at the A -> 0 end point).
    approach : float
        Delta_M at pull-off.
    m : float
        c/a at pull-off (inf at A = 0).
    """

    lam: float
    control: str
    force: float
    contact_radius: float
    approach: float
    m: float


def maugis_dugdale_pull_off_point(lam, control="force") -> MaugisDugdalePullOff:
    """Maugis-Dugdale pull-off point for a given lambda.

    Parameters
    ----------
    lam : float
        Maugis parameter.
    control : {"force", "displacement"}
        Force control: pull-off at the minimum of F_M over the curve (JKR -1.5, DMT -2).
        Displacement control (fixed grips): the contact jumps off where Delta_M is minimal
        (dDelta/dA = 0); the reported force is F_M there (JKR -5/6, DMT -2).  Where that
        minimum is the A -> 0 end point (small lambda) there is no jump: the separated branch
        continues smoothly and F_M(A = 0) is the most tensile force of the path.

    Returns
    -------
    MaugisDugdalePullOff
    """
    lam = _check_lam(lam)
    _check_control(control)
    which = 2 if control == "force" else 3
    A, _ = _md_argmin(lam, which)
    m, F, D = _md_point(lam, A)
    return MaugisDugdalePullOff(lam=lam, control=control, force=float(F), contact_radius=float(A),
                                approach=float(D), m=float(m))


def maugis_dugdale_pull_off(lam, control="force"):
    """Dimensionless MD pull-off force F_M = F_pull-off/(pi R dgamma) (negative).

    Parameters
    ----------
    lam : float or array_like
        Maugis parameter(s) lambda (> 0); vectorised.
    control : {"force", "displacement"}
        See :func:`maugis_dugdale_pull_off_point`.

    Returns
    -------
    float or ndarray
        F_M at pull-off (dimensionless, negative), shape of ``lam``.
    """
    lams = np.asarray(lam, dtype=float)
    out = np.array([maugis_dugdale_pull_off_point(x, control).force for x in lams.ravel()])
    return _out(out.reshape(lams.shape))


def maugis_dugdale_scales(radius, dgamma, E_star):
    """Length/force scales of the Johnson-Greenwood units.

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).

    Returns
    -------
    a_scale : float
        a = A_M a_scale, a_scale = (3 pi dgamma R^2 / (4 E*))^(1/3) (m).
    F_scale : float
        F = F_M F_scale, F_scale = pi R dgamma (N).
    d_scale : float
        delta = Delta_M d_scale, d_scale = (9 pi^2 dgamma^2 R / (16 E*^2))^(1/3) (m)
        (thesis A.24 with E_s^2).
    """
    R, g, E = float(radius), float(dgamma), float(E_star)
    return (np.cbrt(3.0 * np.pi * g * R**2 / (4.0 * E)), np.pi * R * g,
            np.cbrt(9.0 * np.pi**2 * g**2 * R / (16.0 * E**2)))


def maugis_dugdale_pull_off_force(radius, dgamma, E_star, z0, control="force"):
    """Dimensional Maugis-Dugdale pull-off force (N, negative) of a sphere on a flat.

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    z0 : float
        Equilibrium distance (m); with ``dgamma`` it sets the Dugdale stress and so lambda.
    control : {"force", "displacement"}
        See :func:`maugis_dugdale_pull_off_point`.

    Returns
    -------
    float
        Pull-off force F_M pi R dgamma (N, negative).
    """
    lam = maugis_parameter(radius, dgamma, E_star, z0)
    return float(maugis_dugdale_pull_off(lam, control)) * np.pi * float(radius) * float(dgamma)


def maugis_dugdale_pull_off_magnitude(radius, dgamma, E_star, z0, control="force"):
    """|Maugis-Dugdale pull-off force| (N, positive).

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    dgamma : float
        Work of adhesion (J/m^2).
    E_star : float
        Composite modulus (Pa).
    z0 : float
        Equilibrium distance (m); with ``dgamma`` it sets the Dugdale stress and so lambda.
    control : {"force", "displacement"}
        See :func:`maugis_dugdale_pull_off_point`.

    Returns
    -------
    float
        Magnitude of :func:`maugis_dugdale_pull_off_force` (N, positive).
    """
    return -maugis_dugdale_pull_off_force(radius, dgamma, E_star, z0, control)


@dataclass(frozen=True)
class MaugisDugdaleSolution:
    """Dimensional Maugis-Dugdale sphere-on-flat state.

    Attributes
    ----------
    contact_radius : float or ndarray
        a (m).
    cohesive_radius : float or ndarray
        c = m a (m): outer radius of the -sigma0 annulus.
    force : float or ndarray
        F (N), compressive positive.
    approach : float or ndarray
        delta (m).
    m : float or ndarray
        c/a.
    lam : float
        Maugis parameter.
    A_M, F_M, Delta_M : float or ndarray
        The same state in Johnson-Greenwood units.
    sigma0 : float
        Dugdale stress (Pa).
    """

    contact_radius: float | np.ndarray
    cohesive_radius: float | np.ndarray
    force: float | np.ndarray
    approach: float | np.ndarray
    m: float | np.ndarray
    lam: float
    A_M: float | np.ndarray
    F_M: float | np.ndarray
    Delta_M: float | np.ndarray
    sigma0: float


def _largest_root_above(lam, which, target, A_start):
    """Largest A >= A_start with curve[which](A) = target (curve increasing beyond A_start)."""
    def g(x):
        return _md_curve_arrays(lam, np.array([x]))[which][0] - target
    g0 = g(A_start)
    if g0 >= 0:
        return A_start
    hi = max(2.0 * A_start, 1.0)
    while g(hi) <= 0:
        hi *= 2.0
    return brentq(g, A_start, hi, xtol=1e-14, rtol=1e-14, maxiter=500)


def maugis_dugdale(radius, dgamma, E_star, z0, a=None, force=None, approach=None) -> MaugisDugdaleSolution:
    """Dimensional Maugis-Dugdale solution of a sphere on a flat (Eqs. A.18-A.24).

    Give exactly one of ``a``, ``force`` or ``approach`` (each may be an array).

    Parameters
    ----------
    radius, dgamma, E_star, z0 : float
        R (m), work of adhesion (J/m^2), composite modulus (Pa), equilibrium distance (m).
    a : float or array_like, optional
        Contact radius (m); the state is unique.
    force : float or array_like, optional
        Normal force (N).  Where several states share the force the STABLE one (largest a) is
        returned.  Forces below the (force-control) pull-off raise :class:`InputError`.
    approach : float or array_like, optional
        Approach (m), displacement control.  The branch with the largest a is returned too (the
        one followed on unloading from contact until the jump-off at the minimum of delta);
        approaches below that minimum raise :class:`InputError` (the separated, a = 0 branch of
        Maugis is not implemented).

    Returns
    -------
    MaugisDugdaleSolution
    """
    R, g, E, z = (_pos(nm, v) for nm, v in (("radius", radius), ("dgamma", dgamma),
                                            ("E_star", E_star), ("z0", z0)))
    if sum(v is not None for v in (a, force, approach)) != 1:
        raise InputError("maugis_dugdale", "give exactly one of a=, force=, approach=")
    lam = float(maugis_parameter(R, g, E, z))
    a_s, F_s, d_s = maugis_dugdale_scales(R, g, E)
    if a is not None:
        shape = np.shape(a)
        A = np.atleast_1d(np.asarray(a, float)).ravel() / a_s
    elif force is not None:
        shape = np.shape(force)
        FM = np.atleast_1d(np.asarray(force, float)).ravel() / F_s
        A_min, F_min = _md_argmin(lam, 2)
        if np.any(FM < F_min * (1 + 1e-10) - 1e-14):
            raise InputError("force", f"below the Maugis-Dugdale pull-off force {F_min * F_s:.6g} N")
        A = np.array([_largest_root_above(lam, 2, f, A_min) for f in FM])
    else:
        shape = np.shape(approach)
        DM = np.atleast_1d(np.asarray(approach, float)).ravel() / d_s
        A_min, D_min = _md_argmin(lam, 3)
        if np.any(DM < D_min - 1e-12 * max(1.0, abs(D_min))):
            raise InputError("approach", f"below the jump-off approach {D_min * d_s:.6g} m of the "
                             "contact branch (separated branch not implemented)")
        A = np.array([_largest_root_above(lam, 3, d, A_min) for d in DM])
    Av, mv, F, D, _ = _md_curve_arrays(lam, A)

    def rs(x):
        return _out(np.reshape(x, shape))

    return MaugisDugdaleSolution(
        contact_radius=rs(Av * a_s), cohesive_radius=rs(Av * mv * a_s), force=rs(F * F_s),
        approach=rs(D * d_s), m=rs(mv), lam=lam, A_M=rs(Av), F_M=rs(F), Delta_M=rs(D),
        sigma0=float(dugdale_stress(g, z)))


def maugis_dugdale_pressure(r, radius, dgamma, E_star, z0, a=None, force=None, approach=None):
    """Maugis-Dugdale pressure profile p(r) (Pa), thesis Eq. A.23.

    p(r) = 2 E* a/(pi R) sqrt(1 - r^2/a^2) - (2 sigma0/pi) arctan sqrt((m^2-1)/(1 - r^2/a^2))
    for r <= a, -sigma0 for a < r <= c and 0 beyond.  The state is given by exactly one of
    ``a``, ``force`` or ``approach`` (scalars; see :func:`maugis_dugdale`).

    Parameters
    ----------
    r : array_like
        Radial positions (m).
    radius, dgamma, E_star, z0 : float
        R (m), work of adhesion (J/m^2), composite modulus (Pa), equilibrium distance (m).
    a : float, optional
        Contact radius (m).
    force : float, optional
        Normal force (N); the stable (largest-a) state is used.
    approach : float, optional
        Approach (m); the contact branch (largest a) is used.

    Returns
    -------
    float or ndarray
        Pressure (Pa, compressive positive), shape of ``r``.

    Raises
    ------
    InputError
        As :func:`maugis_dugdale`, or a state given as an array.
    """
    sol = maugis_dugdale(radius, dgamma, E_star, z0, a=a, force=force, approach=approach)
    if np.ndim(sol.contact_radius) != 0:
        raise InputError("maugis_dugdale_pressure", "give a scalar state (a, force or approach)")
    aa, c, m, s0 = sol.contact_radius, sol.cohesive_radius, sol.m, sol.sigma0
    s = np.sqrt(max(m * m - 1.0, 0.0))
    r = np.asarray(r, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.clip(1.0 - (r / aa) ** 2, 0.0, None) if aa > 0 else np.zeros_like(r)
        inner = (2.0 * E_star * aa / (np.pi * radius) * np.sqrt(q)
                 - 2.0 * s0 / np.pi * np.arctan2(s, np.sqrt(q)))
    p = np.where(r <= aa, inner, np.where(r <= c, -s0, 0.0))
    return _out(p)
