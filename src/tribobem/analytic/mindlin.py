"""Partial slip of a Hertz contact: Cattaneo-Mindlin, Mindlin-Deresiewicz and Spence.

Conventions
-----------
SI units.  A sphere (composite radius R) is pressed by a normal force ``P`` > 0 (N) onto a
flat; ``a`` is the contact radius (m) and the pressure is taken as Hertzian,
``p(r) = p0 sqrt(1 - r^2/a^2)`` with ``p0 = 3 P/(2 pi a^2)``; ``mu`` is the Coulomb friction
coefficient; ``Q`` the tangential force (N, signed); ``delta`` the tangential rigid shift of
the bodies (m, same sign as ``Q``).  Tangential tractions act on body 1.

The tangential compliance of the pair is ``k = sum_i (2 - nu_i)/G_i`` with
``G_i = E_i/(2 (1 + nu_i))`` (1/Pa), summed over BOTH bodies; a rigid body contributes 0
(:func:`mindlin_compliance_k`).  With this ``k`` every formula below holds for identical
bodies, for a rigid counterface and -- neglecting the normal-tangential coupling -- for
dissimilar bodies.  Note: the classical "G*" of Mindlin is 1/k, so ``K(0) = 8 G* a``.

Cattaneo-Mindlin (monotonic Q at constant P; thesis Eqs. 2.24-2.26)::

    c/a    = (1 - Q/(mu P))^(1/3)
    delta0 = 3 mu P k / (16 a)                         (the shift at gross slip, Q = mu P)
    delta  = delta0 [1 - (1 - Q/(mu P))^(2/3)]
    q(r)   = mu p0 sqrt(1 - r^2/a^2) - mu p0 (c/a) sqrt(1 - r^2/c^2) [r < c]
    K(Q)   = dQ/d delta = (8 a/k) (1 - Q/(mu P))^(1/3)
           = (3 mu P/(2 delta0)) (1 - delta/delta0)^(1/2)           (Paper F Eq. 6)
    K(0)   = 8 a/k                                                  (independent of mu)

The initial stiffness follows from differentiating the shift:
``d delta/dQ = delta0 (2/3) (1 - Q/(mu P))^(-1/3) / (mu P)``, i.e. ``k/(8 a)`` at Q = 0.
For two identical bodies ``k = 2 (2 - nu)/G`` and ``K(0) = 4 G a/(2 - nu)`` (thesis Eq. 2.26,
"factor 4" in terms of one body's G); for a rigid counterface ``k = (2 - nu)/G`` and
``K(0) = 8 G a/(2 - nu)`` (Paper F, "factor 8").  Both are ``8 a/k``.

Mindlin-Deresiewicz (oscillating Q between +Q* and -Q* after the virgin loading to +Q*;
r = Q*/(mu P))::

    unloading from +Q*:  delta =  delta0 [2 (1 - (Q* - Q)/(2 mu P))^(2/3) - (1 - r)^(2/3) - 1]
    reloading from -Q*:  delta = -delta0 [2 (1 - (Q* + Q)/(2 mu P))^(2/3) - (1 - r)^(2/3) - 1]
    stick radius:        c'/a  = (1 - (Q* - Q)/(2 mu P))^(1/3)   (unloading)
                         c''/a = (1 - (Q* + Q)/(2 mu P))^(1/3)   (reloading)
    branch stiffness:    K = (8 a/k) c'/a  and  (8 a/k) c''/a
    loop energy:         W = (9 mu^2 P^2 k/(10 a)) [1 - (1 - r)^(5/3) - (5 r/6)(1 + (1 - r)^(2/3))]

Thesis Eq. 2.27c prints ``(1 + Q*/(mu P))^(2/3)`` in the reloading branch; with it the loop
does not close (the reloading branch misses the turning point +Q* by
``delta0 [(1 + r)^(2/3) - (1 - r)^(2/3)]``).  The sign above is the correct one.

Spence (1975): normal loading with friction of dissimilar bodies
----------------------------------------------------------------
When a sphere is pressed monotonically into a dissimilar half-space (Dundurs' beta != 0,
``C_c = beta/(pi E*)``), the pressure draws the surface of the more compressible
body inward relative to the other; friction resists it in an outer slip annulus c < r < a,
the centre sticks.  The problem is self-similar (Spence 1975) and c/a depends on beta/mu
only.  We did not have Spence's paper to hand; the relation used here was derived for this
module, as follows, and checked against an independent incremental ring-element solution
(see ``tests/analytic/test_mindlin.py``):

* Goodman approximation: the shear does not change the pressure (Hertzian p).  This is what
  makes c/a a function of beta/mu alone; the coupled problem depends weakly on beta and mu
  separately.
* Self-similarity, ``q(r, a) = (E* a/R) f(r/a)``, with points stuck once r < c = b a, forces
  the relative radial displacement in the stick zone to be ``s(r) = C r^2`` (frozen as points
  stick).  With ``q = d Phi/dr`` (Phi = 0 for r >= a), ``s = (1/(pi E*)) d/dr [N(Phi) -
  beta U(p)]`` where N is the Boussinesq (1/rho) potential and U the logarithmic potential of
  the pressure.  In the slip annulus ``q = mu p`` (sign of beta).
* The stick disc is then a punch problem for Phi (Copson's solution) with two free constants
  (C and an additive constant).  Boundedness and continuity of q at r = c fix both; the
  admissibility inequalities (|q| <= mu p in the stick zone, slip opposing q in the annulus)
  exclude the remaining square-root term, because the stick zone ADVANCES over the slip zone
  (the Cattaneo signs are reversed).  That third condition fixes b = c/a.
* The Copson transforms of the two driving terms are elementary / elliptic
  (``G_N' = 2 pi p0 t [K - E](1 - t^2)``, ``G_U' = pi p0 [t + (1 - t^2) artanh t]``) and the
  condition ``d/dt [G'(t)/t^2] = 0`` at t = b reduces to the closed form::

      beta/mu = b K(sqrt(1 - b^2)) / artanh(b),      b = c/a,

  with K the complete elliptic integral of the first kind (modulus sqrt(1 - b^2)).
  Limits: c/a -> 1 as beta/mu -> 0, only logarithmically (1 - c/a ~ 2 exp(-pi mu/|beta|));
  c/a ~ 4 exp(-|beta|/mu) for large beta/mu.

:func:`spence_traction` gives the corresponding self-similar shear traction.

How good is the Goodman approximation?  An axisymmetric ring-element solution of the FULLY
coupled incremental problem (pressure changed by the shear, and vice versa; 200 rings,
2 % load steps; the same discretisation reproduces the closed form to -0.003..-0.005) gives a
smaller stick zone; the shear also raises the load at a given a (rigid ball, elastic flat)::

    beta    mu     beta/mu  c/a closed form  c/a ring, Goodman  c/a ring, coupled  F/F_Hertz
    0.286   0.5    0.571    0.9917           0.9864             0.9792             1.042
    0.286   0.286  1.0      0.9038           0.8997             0.8753             1.040
    0.286   0.2    1.43     0.7334           0.7303             0.6956             1.038
    0.286   0.190  1.5      0.7015           0.6982             0.6633             1.037
    0.5     0.5    1.0      0.9038           0.8997             0.8086             1.126
    0.5     0.333  1.5      0.7015           0.6982             0.5762             1.097

(beta = 0.286: rigid ball on nu = 0.3; 0.5: rigid ball on nu = 0.)  A solver that couples
normal and tangential tractions should therefore land 1-5 % (beta = 0.29) below the closed
form for beta/mu <= 1.5, more for larger beta; with the coupling of the shear into the
normal problem switched off it should reproduce the closed form.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk, ellipkm1, log_expit

from ..errors import InputError

__all__ = [
    "mindlin_compliance_k", "mindlin_delta0", "mindlin_initial_stiffness",
    "cattaneo_stick_ratio", "cattaneo_mindlin_displacement", "cattaneo_mindlin_traction",
    "mindlin_virgin_stiffness",
    "mindlin_unloading_displacement", "mindlin_reloading_displacement",
    "mindlin_unloading_stick_ratio", "mindlin_reloading_stick_ratio",
    "mindlin_unloading_stiffness", "mindlin_reloading_stiffness",
    "mindlin_loop_energy", "MindlinLoop", "mindlin_deresiewicz_loop",
    "spence_beta_over_mu", "spence_stick_ratio", "spence_traction",
]

_TOL = 1e-12     # relative slack on |Q| <= mu P and |Q| <= Q*


# ----------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------

def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def _pos(name, value):
    v = float(value)
    if not math.isfinite(v) or v <= 0:
        raise InputError(name, f"must be finite and > 0, got {value!r}")
    return v


def _common(P, a, mu, k=None):
    P = _pos("P", P)
    a = _pos("a", a)
    mu = _pos("mu", mu)
    if k is None:
        return P, a, mu
    return P, a, mu, _pos("k", k)


def _force_ratio(Q, P, mu, name="Q"):
    """x = Q/(mu P), checked |x| <= 1."""
    Q = np.asarray(Q, dtype=float)
    if not np.all(np.isfinite(Q)):
        raise InputError(name, f"must be finite, got {Q!r}")
    x = Q / (mu * P)
    if np.any(np.abs(x) > 1.0 + _TOL):
        raise InputError(name, f"|{name}| must not exceed mu P = {mu * P:g} N (gross sliding)")
    return np.clip(x, -1.0, 1.0)


def _amplitude(Q_star, P, mu):
    Qs = float(Q_star)
    if not math.isfinite(Qs) or Qs <= 0:
        raise InputError("Q_star", f"must be finite and > 0, got {Q_star!r}")
    r = Qs / (mu * P)
    if r > 1.0 + _TOL:
        raise InputError("Q_star", f"must not exceed mu P = {mu * P:g} N, got {Q_star!r}")
    return Qs, min(r, 1.0)


def _branch_force(Q, Qs, P, mu):
    Q = np.asarray(Q, dtype=float)
    if not np.all(np.isfinite(Q)) or np.any(np.abs(Q) > Qs * (1.0 + _TOL)):
        raise InputError("Q", f"must lie in [-Q*, Q*] = [{-Qs:g}, {Qs:g}] N")
    return np.clip(Q, -Qs, Qs) / (mu * P)


def _cbrt_pos(x):
    return np.cbrt(np.clip(x, 0.0, None))


# ----------------------------------------------------------------------------------------------
# compliance and Cattaneo-Mindlin
# ----------------------------------------------------------------------------------------------

def mindlin_compliance_k(E1, nu1, E2=math.inf, nu2=0.0) -> float:
    """Tangential compliance ``k = (2 - nu1)/G1 + (2 - nu2)/G2`` of a pair (1/Pa).

    Parameters
    ----------
    E1, nu1 : float
        Young's modulus (Pa; ``math.inf`` for rigid) and Poisson's ratio of body 1.
    E2, nu2 : float, optional
        The same for body 2; by default body 2 is rigid.

    Returns
    -------
    float
        ``k`` in 1/Pa, ``G_i = E_i/(2 (1 + nu_i))``; a rigid body contributes 0.  This is
        1/G* of Mindlin (``K(0) = 8 G* a = 8 a/k``).
    """
    total = 0.0
    rigid = 0
    for name, E, nu in (("1", E1, nu1), ("2", E2, nu2)):
        E = float(E)
        nu = float(nu)
        if math.isnan(E) or E <= 0:
            raise InputError(f"E{name}", f"must be > 0 Pa (or inf for rigid), got {E!r}")
        if not (-1.0 < nu <= 0.5):
            raise InputError(f"nu{name}", f"must lie in (-1, 0.5], got {nu!r}")
        if math.isinf(E):
            rigid += 1
            continue
        G = E / (2.0 * (1.0 + nu))
        total += (2.0 - nu) / G
    if rigid == 2:
        raise InputError("E1, E2", "both bodies are rigid; at least one must be elastic")
    return total


def mindlin_delta0(*, P, a, mu, k) -> float:
    """Shift at the onset of gross slip, ``delta0 = 3 mu P k/(16 a)`` (m).

    Parameters
    ----------
    P : float
        Normal force (N).
    a : float
        Contact radius (m).
    mu : float
        Friction coefficient.
    k : float
        Tangential compliance, :func:`mindlin_compliance_k` (1/Pa).

    Returns
    -------
    float
        delta0 (m).
    """
    P, a, mu, k = _common(P, a, mu, k)
    return 3.0 * mu * P * k / (16.0 * a)


def mindlin_initial_stiffness(a, k) -> float:
    """Initial tangential stiffness ``K(0) = dQ/d delta |_(Q=0) = 8 a/k`` (N/m).

    Parameters
    ----------
    a : float
        Contact radius (m).
    k : float
        ``sum_i (2 - nu_i)/G_i`` over both bodies (1/Pa), :func:`mindlin_compliance_k`.

    Returns
    -------
    float
        ``8 a/k``.

    Notes
    -----
    With ``delta = delta0 [1 - (1 - Q/(mu P))^(2/3)]`` and ``delta0 = 3 mu P k/(16 a)``::

        d delta/dQ = (3 mu P k/(16 a)) (2/3) (1 - Q/(mu P))^(-1/3) / (mu P)
                   = (k/(8 a)) (1 - Q/(mu P))^(-1/3)  ->  k/(8 a)  at Q = 0,

    so ``K(0) = 8 a/k``, independent of mu and P (except through a).  With ``k`` the SUM over
    both bodies this is Paper F's "8" for a rigid counterface (k = (2 - nu)/G) and the
    thesis' Eq. 2.26 "4" for two identical bodies (k = 2 (2 - nu)/G, K = 4 G a/(2 - nu)).
    """
    return 8.0 * _pos("a", a) / _pos("k", k)


def cattaneo_stick_ratio(Q, *, P, mu):
    """Stick radius ratio ``c/a = (1 - |Q|/(mu P))^(1/3)`` of Cattaneo-Mindlin.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N), ``|Q| <= mu P``.
    P : float
        Normal force (N).
    mu : float
        Friction coefficient.

    Returns
    -------
    float or ndarray
        c/a in [0, 1]; 0 at gross slip (|Q| = mu P).
    """
    P = _pos("P", P)
    mu = _pos("mu", mu)
    x = _force_ratio(Q, P, mu)
    return _out(_cbrt_pos(1.0 - np.abs(x)))


def cattaneo_mindlin_displacement(Q, *, P, a, mu, k):
    """Tangential shift on the virgin curve, ``delta = delta0 [1 - (1 - |Q|/(mu P))^(2/3)]``.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N), ``|Q| <= mu P``; delta has the sign of Q.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        delta (m); ``delta0 = 3 mu P k/(16 a)`` at ``|Q| = mu P``.
    """
    P, a, mu, k = _common(P, a, mu, k)
    x = _force_ratio(Q, P, mu)
    d0 = 3.0 * mu * P * k / (16.0 * a)
    return _out(np.sign(x) * d0 * (1.0 - _cbrt_pos(1.0 - np.abs(x)) ** 2))


def cattaneo_mindlin_traction(r, Q, *, P, a, mu):
    """Cattaneo-Mindlin shear traction ``q(r)`` (Pa) for a tangential force Q.

    Parameters
    ----------
    r : float or array_like
        Radial distance(s) from the contact centre (m).
    Q : float
        Tangential force (N), ``|Q| <= mu P``; q has its sign and direction.
    P, a, mu : float
        Normal force (N), contact radius (m), friction coefficient.

    Returns
    -------
    float or ndarray
        ``q = mu p0 sqrt(1 - r^2/a^2) - mu p0 (c/a) sqrt(1 - r^2/c^2)`` (second term for
        r < c only), ``p0 = 3 P/(2 pi a^2)``, ``c = a (1 - |Q|/(mu P))^(1/3)``; 0 for r >= a.
        It integrates to Q over the contact.
    """
    P, a, mu = _common(P, a, mu)
    x = float(_force_ratio(Q, P, mu))
    r = np.asarray(r, dtype=float)
    p0 = 3.0 * P / (2.0 * math.pi * a * a)
    c = a * float(_cbrt_pos(1.0 - abs(x)))
    q = mu * p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    if c > 0:
        q = q - mu * p0 * (c / a) * np.sqrt(np.clip(1.0 - (r / c) ** 2, 0.0, None))
    return _out(math.copysign(1.0, x) * q if x != 0 else np.zeros_like(q))


def mindlin_virgin_stiffness(Q=None, delta=None, *, P, a, mu, k):
    """Tangential (lateral) stiffness ``K_L = dQ/d delta`` on the virgin curve (N/m).

    Give exactly one of ``Q`` and ``delta``::

        K_L = (8 a/k) (1 - |Q|/(mu P))^(1/3) = (3 mu P/(2 delta0)) (1 - |delta|/delta0)^(1/2)

    (Paper F Eq. 6; the two forms are identical since 3 mu P/(2 delta0) = 8 a/k).

    Parameters
    ----------
    Q : float or array_like, optional
        Tangential force (N), ``|Q| <= mu P``.
    delta : float or array_like, optional
        Tangential shift (m), ``|delta| <= delta0``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        K_L (N/m); 8 a/k at zero load, 0 at gross slip.
    """
    if (Q is None) == (delta is None):
        raise InputError("mindlin_virgin_stiffness", "give exactly one of Q= and delta=")
    P, a, mu, k = _common(P, a, mu, k)
    K0 = 8.0 * a / k
    if Q is not None:
        x = _force_ratio(Q, P, mu)
        return _out(K0 * _cbrt_pos(1.0 - np.abs(x)))
    d0 = 3.0 * mu * P * k / (16.0 * a)
    d = np.asarray(delta, dtype=float)
    if not np.all(np.isfinite(d)) or np.any(np.abs(d) > d0 * (1.0 + _TOL)):
        raise InputError("delta", f"|delta| must not exceed delta0 = {d0:g} m")
    return _out(1.5 * mu * P / d0 * np.sqrt(np.clip(1.0 - np.abs(d) / d0, 0.0, None)))


# ----------------------------------------------------------------------------------------------
# Mindlin-Deresiewicz
# ----------------------------------------------------------------------------------------------

def mindlin_unloading_displacement(Q, Q_star, *, P, a, mu, k):
    """Shift on the branch unloading from +Q* (Q decreasing from Q* to -Q*) (m).

    ``delta = delta0 [2 (1 - (Q* - Q)/(2 mu P))^(2/3) - (1 - Q*/(mu P))^(2/3) - 1]``; it
    starts at the virgin-curve point ``delta(Q*)`` and ends at ``-delta(Q*)``.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Turning-point amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        Tangential shift delta (m), shape of ``Q``.
    """
    P, a, mu, k = _common(P, a, mu, k)
    Qs, r = _amplitude(Q_star, P, mu)
    x = _branch_force(Q, Qs, P, mu)
    d0 = mindlin_delta0(P=P, a=a, mu=mu, k=k)
    A = _cbrt_pos(1.0 - (r - x) / 2.0) ** 2
    return _out(d0 * (2.0 * A - np.cbrt(1.0 - r) ** 2 - 1.0))


def mindlin_reloading_displacement(Q, Q_star, *, P, a, mu, k):
    """Shift on the branch reloading from -Q* (Q increasing from -Q* to Q*) (m).

    ``delta = -delta0 [2 (1 - (Q* + Q)/(2 mu P))^(2/3) - (1 - Q*/(mu P))^(2/3) - 1]``
    (the thesis' Eq. 2.27c prints ``1 + Q*/(mu P)`` in the second term: a typo, the loop
    would not close).  It starts at ``-delta(Q*)`` and returns to ``delta(Q*)``.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Turning-point amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        Tangential shift delta (m), shape of ``Q``.
    """
    # Masing: the reloading branch is the unloading branch mirrored through the origin.
    return _out(-np.asarray(mindlin_unloading_displacement(-np.asarray(Q, dtype=float), Q_star, P=P, a=a, mu=mu, k=k)))


def mindlin_unloading_stick_ratio(Q, Q_star, *, P, mu):
    """Stick radius ``c'/a = (1 - (Q* - Q)/(2 mu P))^(1/3)`` while unloading from +Q*.

    The annulus c' < r < a slips back (counter-slip); r < c' does not slip.  c' = a at the
    turning point and shrinks to the virgin stick radius ``a (1 - Q*/(mu P))^(1/3)`` at -Q*.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Amplitude (N).
    P, mu : float
        Normal force (N), friction coefficient.

    Returns
    -------
    float or ndarray
        c'/a (dimensionless, in (0, 1]), shape of ``Q``.
    """
    P = _pos("P", P)
    mu = _pos("mu", mu)
    Qs, r = _amplitude(Q_star, P, mu)
    x = _branch_force(Q, Qs, P, mu)
    return _out(_cbrt_pos(1.0 - (r - x) / 2.0))


def mindlin_reloading_stick_ratio(Q, Q_star, *, P, mu):
    """Stick radius ``c''/a = (1 - (Q* + Q)/(2 mu P))^(1/3)`` while reloading from -Q*.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Amplitude (N).
    P, mu : float
        Normal force (N), friction coefficient.

    Returns
    -------
    float or ndarray
        c''/a (dimensionless, in (0, 1]), shape of ``Q``.
    """
    # Masing: the reloading branch is the unloading branch mirrored through the origin.
    return mindlin_unloading_stick_ratio(-np.asarray(Q, dtype=float), Q_star, P=P, mu=mu)


def mindlin_unloading_stiffness(Q, Q_star, *, P, a, mu, k):
    """Slope ``dQ/d delta = (8 a/k) (1 - (Q* - Q)/(2 mu P))^(1/3)`` of the unloading branch (N/m).

    The slope equals ``8 a/k`` (the virgin initial stiffness) at the turning point +Q*.

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Turning-point amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        Tangential stiffness dQ/d delta (N/m), shape of ``Q``.
    """
    P, a, mu, k = _common(P, a, mu, k)
    Qs, r = _amplitude(Q_star, P, mu)
    x = _branch_force(Q, Qs, P, mu)
    return _out(8.0 * a / k * _cbrt_pos(1.0 - (r - x) / 2.0))


def mindlin_reloading_stiffness(Q, Q_star, *, P, a, mu, k):
    """Slope ``dQ/d delta = (8 a/k) (1 - (Q* + Q)/(2 mu P))^(1/3)`` of the reloading branch (N/m).

    The slope equals ``8 a/k`` at the turning point -Q* (Masing: the unloading branch mirrored
    through the origin).

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N) in [-Q*, Q*].
    Q_star : float
        Turning-point amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float or ndarray
        Tangential stiffness dQ/d delta (N/m), shape of ``Q``.
    """
    # Masing: the reloading branch is the unloading branch mirrored through the origin.
    return mindlin_unloading_stiffness(-np.asarray(Q, dtype=float), Q_star, P=P, a=a, mu=mu, k=k)


def mindlin_loop_energy(Q_star, *, P, a, mu, k) -> float:
    """Energy dissipated per cycle +-Q* (J), the area of the Mindlin-Deresiewicz loop.

    ``W = (9 mu^2 P^2 k/(10 a)) [1 - (1 - r)^(5/3) - (5 r/6)(1 + (1 - r)^(2/3))]``,
    ``r = Q*/(mu P)``.  For small r, ``W ~ k Q*^3/(36 a mu P)`` (cubic in the amplitude).

    Parameters
    ----------
    Q_star : float
        Amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).

    Returns
    -------
    float
        Dissipated energy per cycle W (J).
    """
    P, a, mu, k = _common(P, a, mu, k)
    _, r = _amplitude(Q_star, P, mu)
    s = 1.0 - r
    bracket = 1.0 - s ** (5.0 / 3.0) - (5.0 * r / 6.0) * (1.0 + s ** (2.0 / 3.0))
    return 9.0 * mu**2 * P**2 * k / (10.0 * a) * bracket


@dataclass(frozen=True)
class MindlinLoop:
    """A closed Mindlin-Deresiewicz loop and the virgin curve leading to it.

    Attributes
    ----------
    Q : ndarray
        Tangential force (N): unloading +Q* -> -Q*, then reloading -Q* -> +Q*; the first and
        last points coincide.
    delta : ndarray
        Tangential shift (m) at each ``Q``.
    virgin_Q, virgin_delta : ndarray
        Virgin loading curve 0 -> +Q* (N, m).
    Q_star : float
        Amplitude (N).
    delta_star : float
        Shift at the turning point +Q* (m).
    energy : float
        Dissipated energy per cycle (J), :func:`mindlin_loop_energy`.
    """

    Q: np.ndarray
    delta: np.ndarray
    virgin_Q: np.ndarray
    virgin_delta: np.ndarray
    Q_star: float
    delta_star: float
    energy: float


def mindlin_deresiewicz_loop(Q_star, *, P, a, mu, k, n=201) -> MindlinLoop:
    """Arrays of a whole Mindlin-Deresiewicz loop at amplitude Q* (for plots and comparison).

    Parameters
    ----------
    Q_star : float
        Amplitude (N), ``0 < Q* <= mu P``.
    P, a, mu, k : float
        Normal force (N), contact radius (m), friction coefficient, compliance (1/Pa).
    n : int, optional
        Points per branch (>= 2).  The loop has ``2 n - 1`` points.

    Returns
    -------
    MindlinLoop
    """
    n = int(n)
    if n < 2:
        raise InputError("n", f"must be >= 2, got {n!r}")
    P, a, mu, k = _common(P, a, mu, k)
    Qs, _ = _amplitude(Q_star, P, mu)
    kw = dict(P=P, a=a, mu=mu, k=k)
    down = np.linspace(Qs, -Qs, n)
    up = np.linspace(-Qs, Qs, n)
    d_down = mindlin_unloading_displacement(down, Qs, **kw)
    d_up = mindlin_reloading_displacement(up, Qs, **kw)
    vQ = np.linspace(0.0, Qs, n)
    vd = cattaneo_mindlin_displacement(vQ, **kw)
    d_star = float(cattaneo_mindlin_displacement(Qs, **kw))
    # exact closure (the branches meet analytically; remove round-off)
    d_down[0] = d_star
    d_down[-1] = -d_star
    d_up[0] = -d_star
    d_up[-1] = d_star
    return MindlinLoop(
        Q=np.concatenate([down, up[1:]]),
        delta=np.concatenate([d_down, d_up[1:]]),
        virgin_Q=vQ,
        virgin_delta=np.asarray(vd, dtype=float),
        Q_star=Qs,
        delta_star=d_star,
        energy=mindlin_loop_energy(Qs, **kw),
    )


# ----------------------------------------------------------------------------------------------
# Spence (1975): incremental normal loading with friction, dissimilar bodies
# ----------------------------------------------------------------------------------------------

def _spence_logf_of_x(x):
    """ln(beta/mu) as a function of x = logit(b), stable for b -> 0 and b -> 1."""
    # b = expit(x), t = 1 - b = expit(-x); 1 - b^2 = t (1 + b); artanh b = (ln(1+b) - ln t)/2
    b = 1.0 / (1.0 + math.exp(-x)) if x > -700 else math.exp(x)
    ln_t = float(log_expit(-x))
    atanh_b = 0.5 * (math.log1p(b) - ln_t)
    if b < 0.5:
        Kp = float(ellipkm1(b * b))                      # K(1 - b^2) near the log singularity
    else:
        t = math.exp(ln_t)
        Kp = float(ellipk(t * (1.0 + b)))                # K(m = 1 - b^2)
    return math.log(b) + math.log(Kp) - math.log(atanh_b)


def spence_beta_over_mu(stick_ratio):
    """beta/mu for which a Hertz contact loaded normally with friction has stick ratio c/a.

    Closed form derived in the module docstring (Goodman approximation)::

        beta/mu = b K(sqrt(1 - b^2)) / artanh(b),     b = c/a

    (K: complete elliptic integral of the first kind, modulus sqrt(1 - b^2)).

    Parameters
    ----------
    stick_ratio : float or array_like
        c/a in [0, 1].

    Returns
    -------
    float or ndarray
        |beta|/mu >= 0: ``inf`` at c/a = 0, 0 at c/a = 1; strictly decreasing.
    """
    b = np.asarray(stick_ratio, dtype=float)
    if not np.all(np.isfinite(b)) or np.any((b < 0) | (b > 1)):
        raise InputError("stick_ratio", f"must lie in [0, 1], got {stick_ratio!r}")
    out = np.empty(b.shape)
    for i, bi in np.ndenumerate(b):
        if bi == 0.0:
            out[i] = math.inf
        elif bi == 1.0:
            out[i] = 0.0
        else:
            out[i] = bi * float(ellipkm1(bi * bi)) / math.atanh(bi)
    return _out(out)


def spence_stick_ratio(beta_over_mu):
    """Self-similar stick ratio c/a of a sphere pressed with friction into a dissimilar body.

    Solves ``|beta|/mu = b K(sqrt(1 - b^2))/artanh(b)`` for b = c/a (see the module
    docstring for the derivation and its assumptions: Hertz pressure unaffected by the shear
    (Goodman approximation), monotonically increasing load, Coulomb friction; ``beta`` is
    Dundurs' parameter with ``C_c = beta/(pi E*)``, ``ContactPair.dundurs_beta``).  The sign
    of beta only sets the direction of the shear (outward on the more compressible body).

    Parameters
    ----------
    beta_over_mu : float or array_like
        beta/mu (any sign; ``inf`` allowed, meaning mu -> 0).

    Returns
    -------
    float or ndarray
        c/a in [0, 1]: 1 at beta/mu = 0 (no slip), approaching 1 only logarithmically,
        ``1 - c/a ~ 2 exp(-pi mu/|beta|)``; ``c/a ~ 4 exp(-|beta|/mu)`` for large |beta|/mu.
        Values: 0.1 -> 1 - 4.6e-14, 0.5 -> 0.99623, 1 -> 0.90375, 1.5 -> 0.70150,
        2 -> 0.48513, 3 -> 0.19532.

    Notes
    -----
    Exact for the Goodman-approximated problem.  With the full normal-tangential coupling
    the stick zone is smaller: c/a lower by 0.7 %, 2.7 %, 4.8 % for beta = 0.286 and
    mu = 0.5, 0.286, 0.2 (numerical, see the module docstring).
    """
    y = np.asarray(beta_over_mu, dtype=float)
    if np.any(np.isnan(y)):
        raise InputError("beta_over_mu", f"must not be NaN, got {beta_over_mu!r}")
    y = np.abs(y)
    out = np.empty(y.shape)
    for i, yi in np.ndenumerate(y):
        if yi == 0.0:
            out[i] = 1.0
        elif math.isinf(yi):
            out[i] = 0.0
        else:
            target = math.log(yi)
            g = lambda x: _spence_logf_of_x(x) - target  # noqa: E731  (decreasing in x)
            lo, hi = -50.0, 50.0
            while g(lo) < 0 and lo > -1e6:
                lo *= 2.0
            while g(hi) > 0 and hi < 1e6:
                hi *= 2.0
            if g(lo) < 0:          # beta/mu astronomically large
                out[i] = 0.0
                continue
            if g(hi) > 0:          # beta/mu so small that c/a rounds to 1
                out[i] = 1.0
                continue
            x = brentq(g, lo, hi, xtol=1e-13, rtol=1e-15, maxiter=500)
            out[i] = 1.0 / (1.0 + math.exp(-x)) if x > -700 else math.exp(x)
    return _out(out)


def _spence_G1(t, bm):
    """Copson transform derivative G'(t)/(mu p0) of the stick-zone data (module docstring)."""
    m = 1.0 - t * t
    return bm * math.pi * (t + m * math.atanh(t)) - 2.0 * math.pi * t * (ellipk(m) - ellipe(m))


def _spence_G2(t, bm):
    """G''(t)/(mu p0)."""
    m = 1.0 - t * t
    return 2.0 * math.pi * (bm * (1.0 - t * math.atanh(t)) - (ellipk(m) - 2.0 * ellipe(m)))


def spence_traction(rho, beta_over_mu):
    """Self-similar shear traction of the Spence problem, ``q_r/(mu p0)`` against r/a.

    In the slip annulus ``q = mu p = mu p0 sqrt(1 - rho^2)``; in the stick disc rho < b
    (b = :func:`spence_stick_ratio`) ``q = mu p + d Phi_c/dr`` with the Copson correction::

        d Phi_c/dr = -(mu p0/(pi^2 r)) int_0^sqrt(b^2 - r^2) g''(sqrt(r^2 + s^2)) ds,
        g''(t) = G''(t) - 2 G'(b) t/b^2,
        G'(t)/(mu p0)  = (beta/mu) pi [t + (1 - t^2) artanh t] - 2 pi t [K - E](1 - t^2),
        G''(t)/(mu p0) = 2 pi (beta/mu) (1 - t artanh t) - 2 pi [K - 2 E](1 - t^2)

    (lengths in units of a; K, E complete elliptic integrals of parameter 1 - t^2).  q and its
    slope are continuous at rho = b, q = 0 at the centre, |q| <= mu p everywhere.

    Parameters
    ----------
    rho : float or array_like
        r/a (>= 0).
    beta_over_mu : float
        beta/mu (finite; sign sets the direction).

    Returns
    -------
    float or ndarray
        ``q_r/(mu p0)`` acting on body 1, positive radially outward when beta > 0
        (body 1 then the more compressible one, drawn inward by the pressure); 0 for rho >= 1.
    """
    bm_signed = float(beta_over_mu)
    if not math.isfinite(bm_signed):
        raise InputError("beta_over_mu", f"must be finite, got {beta_over_mu!r}")
    bm = abs(bm_signed)
    sign = 1.0 if bm_signed >= 0 else -1.0
    rho = np.asarray(rho, dtype=float)
    if not np.all(np.isfinite(rho)) or np.any(rho < 0):
        raise InputError("rho", "must be finite and >= 0")
    b = float(spence_stick_ratio(bm))
    out = np.array(np.sqrt(np.clip(1.0 - rho**2, 0.0, None)), dtype=float)
    if bm == 0.0 or b <= 0.0:
        return _out(sign * out) if b <= 0.0 else _out(np.zeros_like(out))
    if b >= 1.0 - 1e-12:
        raise InputError("beta_over_mu", "too small: the slip annulus is thinner than 1e-12 a")
    g1b = _spence_G1(b, bm)

    def gpp(t):
        return _spence_G2(t, bm) - 2.0 * g1b * t / (b * b)

    def corr(r):
        S = math.sqrt(b * b - r * r)
        I = quad(lambda s: gpp(math.sqrt(r * r + s * s)), 0.0, S, limit=200,
                 epsabs=1e-13, epsrel=1e-12)[0]
        return -I / (math.pi**2 * r)

    r_small = 1e-4 * b
    for i, r in np.ndenumerate(rho):
        if r >= b:
            continue
        if r < r_small:          # q is odd in r: linear near the centre
            out[i] = r / r_small * (math.sqrt(1.0 - r_small**2) + corr(r_small))
        else:
            out[i] = out[i] + corr(r)
    return _out(sign * out)
