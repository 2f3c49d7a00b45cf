"""Flat punches and burls: the rounded and the sharp flat punch, Kendall's pull-off and the
full-stick tangential stiffness.

Conventions: SI units, ``E*`` the composite modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``,
force ``P > 0`` compressive, approach ``delta > 0`` when the bodies are pushed together
(measured from the first touch of the flat top), pull-off forces NEGATIVE (as in
:mod:`tribobem.analytic.adhesion`).

Sneddon (1965): an axisymmetric frictionless punch of profile ``f(r)`` (``f(0) = 0``, the gap
it leaves at zero approach) in contact over ``r < a`` with a pressure that is bounded at
``r = a`` has::

    delta = a int_0^a f'(r) / sqrt(a^2 - r^2) dr
    P     = 2 E* int_0^a r^2 f'(r) / sqrt(a^2 - r^2) dr

(Hertz, ``f = r^2/(2R)``: ``delta = a^2/R``, ``P = 4 E* a^3/(3R)``.)  Both are linear in ``f'``,
so the terms of a composite profile add.

Rounded flat punch (the burl of :func:`tribobem.geometry.shapes.burl`)
-----------------------------------------------------------------------
``f(r) = 0`` for ``r < b``, ``(r - b)^2 / (2 R)`` beyond; with ``theta = arccos(b/a)``
(``a >= b``: any load puts the whole flat in contact)::

    delta = (a / R) [sqrt(a^2 - b^2) - b theta]
    P     = (E* / (3 R)) [sqrt(a^2 - b^2) (4 a^2 - b^2) - 3 a^2 b theta]

derived here from Sneddon's integrals with ``int_b^a dr/sqrt(a^2 - r^2) = theta``,
``int_b^a r dr/sqrt(.) = s``, ``int_b^a r^2 dr/sqrt(.) = (a^2 theta + b s)/2`` and
``int_b^a r^3 dr/sqrt(.) = s (2 a^2 + b^2)/3`` (``s = sqrt(a^2 - b^2)``); the same relations as
Ciavarella, Hills and Monno (1998) for the axisymmetric rounded punch.  Limits (tested):
``b -> 0`` is Hertz; ``a -> b`` (``R -> 0`` at a fixed load) gives ``delta = a^2 theta^3/(3R)``,
``P = 2 E* a^3 theta^3/(3R)``, i.e. the flat punch ``P = 2 a E* delta``.

A spherical crown of radius ``R_c`` over the whole burl (``f += r^2/(2 R_c)``) adds the Hertz
terms ``a^2/R_c`` and ``4 E* a^3/(3 R_c)``; the contact then starts at the axis and is Hertzian
until it reaches ``a = b``.

Sharp flat punch (Boussinesq)::

    P = 2 b E* delta,     p(r) = P / (2 pi b sqrt(b^2 - r^2))  (r < b)

Kendall (1971): the flat punch of radius ``b`` adhering with work of adhesion ``dgamma``
detaches (under load or displacement control alike: the crack at its edge runs unstably) at::

    F_pull-off = -sqrt(8 pi E* dgamma b^3)

the Griffith condition ``K_I^2/(2 E*) = dgamma`` on the edge singularity
``K_I = P/(2 b sqrt(pi b))`` of the Boussinesq pressure.  It is the JKR-like limit: a Dugdale
(cohesive) zone of length ``d ~ pi E* dgamma/(4 sigma0^2)`` small against ``b``.

Full-stick tangential stiffness
-------------------------------
A tangential traction ``q(r) = Q / (2 pi a sqrt(a^2 - r^2))`` on a circle of radius ``a`` moves
every point of it by the same ``Q k / (8 a)`` (Mindlin 1949; Johnson 1985, 3.6), with
``k = sum_i (2 - nu_i)/G_i`` (a rigid body adds 0): the initial tangential stiffness of a
contact of radius ``a`` in full stick is::

    K = dQ/d delta_t = 8 a / k        (= 8 G* a with Mindlin's 1/G* = k)

For a flat punch this traction has the same shape as the pressure, ``q/p = Q/P`` everywhere,
so the contact sticks fully for any ``Q < mu P``; for the rounded punch and the sphere the
pressure vanishes at the edge and a slip annulus opens at once, ``K -> 8 a/k`` as ``Q -> 0``.
The relation neglects the normal-tangential coupling: it is exact when Dundurs' ``beta = 0``
(identical bodies, or an incompressible body, ``nu = 0.5``, against a rigid one).  With
coupling, the full-stick (bonded) stiffness differs: for a rigid punch bonded to a half-space
it is ``32 G a (1 - nu)/(7 - 8 nu)`` (Mossakovskii; 4.57 G a at nu = 0 against Mindlin's
4 G a), which equals ``8 a/k`` only at ``nu = 0.5``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError

__all__ = [
    "RoundedPunchSolution", "rounded_punch", "rounded_punch_force", "rounded_punch_approach",
    "FlatPunchSolution", "flat_punch", "flat_punch_pressure", "kendall_pull_off", "kendall_pull_off_magnitude",
    "full_stick_stiffness", "bonded_punch_stiffness",
]


def _pos(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a finite number > 0, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(name, f"must be a finite number > 0, got {value!r}")
    return v


def _nonneg(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a finite number >= 0, got {value!r}") from None
    if not (math.isfinite(v) and v >= 0):
        raise InputError(name, f"must be a finite number >= 0, got {value!r}")
    return v


def rounded_punch_approach(a: float, b: float, R: float, crown: float | None = None) -> float:
    """Approach (m) of the rounded flat punch at contact radius ``a`` (Sneddon; module docstring).

    Parameters
    ----------
    a : float
        Contact radius (m), >= 0; without a crown, ``a >= b``.
    b : float
        Radius of the flat top (m), >= 0.
    R : float
        Edge radius (m), > 0.
    crown : float, optional
        Radius of a spherical crown over the whole punch (m); None: flat top.

    Returns
    -------
    float
        ``delta`` (m).
    """
    d = 0.0
    if a > b:
        s = math.sqrt(a * a - b * b)
        d += (a / R) * (s - b * math.acos(b / a))
    if crown is not None:
        d += a * a / crown
    return d


def rounded_punch_force(a: float, b: float, R: float, E_star: float, crown: float | None = None) -> float:
    """Normal force (N) of the rounded flat punch at contact radius ``a`` (Sneddon; module docstring).

    Parameters
    ----------
    a, b, R, crown
        As for :func:`rounded_punch_approach` (m).
    E_star : float
        Composite modulus (Pa).

    Returns
    -------
    float
        ``P`` (N), compressive positive.
    """
    P = 0.0
    if a > b:
        s = math.sqrt(a * a - b * b)
        P += E_star / (3.0 * R) * (s * (4 * a * a - b * b) - 3 * a * a * b * math.acos(b / a))
    if crown is not None:
        P += 4.0 * E_star * a**3 / (3.0 * crown)
    return P


@dataclass(frozen=True)
class RoundedPunchSolution:
    """State of a rounded flat punch (a burl) pressed on an elastic half-space.

    Attributes
    ----------
    contact_radius : float
        ``a`` (m).
    approach : float
        ``delta`` (m), from the first touch of the top.
    force : float
        ``P`` (N).
    flat_punch_approach : float
        ``P / (2 a E*)`` (m): the approach of a sharp flat punch of radius ``a`` at the same
        load, the limit the rounded punch tends to as ``a -> b``.
    """

    contact_radius: float
    approach: float
    force: float
    flat_punch_approach: float


def rounded_punch(force=None, approach=None, contact_radius=None, *, flat_radius: float, edge_radius: float,
                  E_star: float, crown: float | None = None) -> RoundedPunchSolution:
    """The rounded flat punch (a burl with an optional crown) from its force, approach or contact radius.

    Parameters
    ----------
    force : float, optional
        Normal force ``P`` (N), >= 0.  Give exactly one of ``force``, ``approach``,
        ``contact_radius``.
    approach : float, optional
        Approach ``delta`` (m), >= 0.
    contact_radius : float, optional
        Contact radius ``a`` (m); without a crown, ``>= flat_radius``.
    flat_radius : float
        Radius ``b`` of the flat top (m), >= 0 (0: a sphere of radius ``edge_radius``).
    edge_radius : float
        Radius ``R`` of the rounded edge (m), > 0.
    E_star : float
        Composite modulus (Pa), > 0.
    crown : float, optional
        Radius ``R_c`` of a spherical crown over the whole punch (m), > 0.

    Returns
    -------
    RoundedPunchSolution

    Raises
    ------
    InputError
        Naming the argument that is missing, out of range or inconsistent.

    Notes
    -----
    ``P(a)`` and ``delta(a)`` increase with ``a``; a force or an approach is inverted by
    Brent's method on ``a`` to a relative 1e-13.
    """
    given = [k for k, v in (("force", force), ("approach", approach), ("contact_radius", contact_radius))
             if v is not None]
    if len(given) != 1:
        raise InputError("rounded_punch", "give exactly one of force=, approach=, contact_radius=")
    b = _nonneg("flat_radius", flat_radius)
    R = _pos("edge_radius", edge_radius)
    Es = _pos("E_star", E_star)
    Rc = None if crown is None else _pos("crown", crown)
    a_min = 0.0 if Rc is not None else b

    if contact_radius is not None:
        a = _nonneg("contact_radius", contact_radius)
        if a < a_min:
            raise InputError("contact_radius", f"a flat top of radius {b:g} m is in contact as a whole: a >= {b:g} m, "
                                               f"got {a:g} m")
    else:
        fn = (lambda x: rounded_punch_force(x, b, R, Es, Rc)) if force is not None else \
             (lambda x: rounded_punch_approach(x, b, R, Rc))
        target = _nonneg(given[0], force if force is not None else approach)
        if target == 0.0:
            a = a_min
        else:
            hi = max(2.0 * a_min, b + R, 1e-300)
            while fn(hi) < target:
                hi *= 2.0
            a = brentq(lambda x: fn(x) - target, a_min, hi, xtol=1e-300, rtol=1e-13, maxiter=500)
    P = rounded_punch_force(a, b, R, Es, Rc)
    d = rounded_punch_approach(a, b, R, Rc)
    return RoundedPunchSolution(contact_radius=float(a), approach=float(d), force=float(P),
                                flat_punch_approach=float(P / (2.0 * a * Es)) if a > 0 else 0.0)


@dataclass(frozen=True)
class FlatPunchSolution:
    """A sharp flat punch of radius ``b`` in full contact (Boussinesq).

    Attributes
    ----------
    radius : float
        ``b`` (m), the contact radius at every load.
    force : float
        ``P = 2 b E* delta`` (N).
    approach : float
        ``delta`` (m).
    stiffness : float
        Normal stiffness ``dP/d delta = 2 b E*`` (N/m).
    mean_pressure : float
        ``P / (pi b^2)`` (Pa); the pressure at the centre is half of it.
    """

    radius: float
    force: float
    approach: float
    stiffness: float
    mean_pressure: float


def flat_punch(force=None, approach=None, *, radius: float, E_star: float) -> FlatPunchSolution:
    """The sharp flat punch: ``P = 2 b E* delta`` (adhesive tension allowed: any sign).

    Parameters
    ----------
    force : float, optional
        Normal force (N).  Give exactly one of ``force`` and ``approach``.
    approach : float, optional
        Approach (m).
    radius : float
        Punch radius ``b`` (m), > 0.
    E_star : float
        Composite modulus (Pa), > 0.

    Returns
    -------
    FlatPunchSolution
    """
    if (force is None) == (approach is None):
        raise InputError("flat_punch", "give exactly one of force= and approach=")
    b = _pos("radius", radius)
    Es = _pos("E_star", E_star)
    k = 2.0 * b * Es
    if force is not None:
        P = float(force)
        d = P / k
    else:
        d = float(approach)
        P = k * d
    if not (math.isfinite(P) and math.isfinite(d)):
        raise InputError("flat_punch", f"force and approach must be finite, got {force!r}, {approach!r}")
    return FlatPunchSolution(radius=b, force=P, approach=d, stiffness=k, mean_pressure=P / (math.pi * b * b))


def flat_punch_pressure(r, force: float, radius: float):
    """Boussinesq pressure ``P / (2 pi b sqrt(b^2 - r^2))`` under a flat punch (Pa; 0 outside,
    infinite at ``r = b``).

    Parameters
    ----------
    r : array_like
        Radial distance(s) from the axis (m).
    force : float
        ``P`` (N).
    radius : float
        ``b`` (m), > 0.

    Returns
    -------
    ndarray or float
        Pressure (Pa), same shape as ``r``.
    """
    b = _pos("radius", radius)
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = np.where(r < b, float(force) / (2.0 * np.pi * b * np.sqrt(np.clip(b * b - r * r, 0.0, None))), 0.0)
    return float(p) if p.ndim == 0 else p


def kendall_pull_off(radius: float, work_of_adhesion: float, E_star: float) -> float:
    """Kendall's pull-off force of a flat punch, ``-sqrt(8 pi E* dgamma b^3)`` (N, negative).

    Parameters
    ----------
    radius : float
        Punch radius ``b`` (m), > 0.
    work_of_adhesion : float
        ``dgamma`` (J/m^2), > 0.
    E_star : float
        Composite modulus (Pa), > 0.

    Returns
    -------
    float
        Pull-off force (N), negative (tensile).
    """
    return -kendall_pull_off_magnitude(radius, work_of_adhesion, E_star)


def kendall_pull_off_magnitude(radius: float, work_of_adhesion: float, E_star: float) -> float:
    """``|F| = sqrt(8 pi E* dgamma b^3)`` (N), the magnitude of :func:`kendall_pull_off`."""
    b = _pos("radius", radius)
    w = _pos("work_of_adhesion", work_of_adhesion)
    Es = _pos("E_star", E_star)
    return math.sqrt(8.0 * math.pi * Es * w * b**3)


def full_stick_stiffness(contact_radius: float, E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Initial tangential stiffness ``8 a / k`` of a circular contact in full stick (N/m).

    Parameters
    ----------
    contact_radius : float
        ``a`` (m), > 0: the punch radius ``b`` for a sharp flat punch, the contact radius of
        :func:`rounded_punch` for a burl.
    E1, nu1, E2, nu2 : float
        Young's moduli (Pa; ``inf`` for a rigid body) and Poisson's ratios of the bodies.

    Returns
    -------
    float
        ``K = 8 a / k``, ``k = sum (2 - nu_i)/G_i``, ``G_i = E_i/(2 (1 + nu_i))`` (N/m).

    Notes
    -----
    Uncoupled (Dundurs' beta = 0): see the module docstring for when that holds and for the
    bonded punch with coupling (:func:`bonded_punch_stiffness`).
    """
    from .mindlin import mindlin_compliance_k

    a = _pos("contact_radius", contact_radius)
    return 8.0 * a / mindlin_compliance_k(E1, nu1, E2, nu2)


def bonded_punch_stiffness(radius: float, E: float, nu: float) -> float:
    """Tangential stiffness of a rigid circular punch bonded to a half-space (coupling included),
    ``32 G b (1 - nu)/(7 - 8 nu)`` (N/m), ``G = E/(2 (1 + nu))``.

    Equal to :func:`full_stick_stiffness` against a rigid body only at ``nu = 0.5``; at
    ``nu = 0`` it is 14 % stiffer (4.57 G b against 4 G b).

    Parameters
    ----------
    radius : float
        ``b`` (m), > 0.
    E : float
        Young's modulus of the half-space (Pa), > 0.
    nu : float
        Its Poisson's ratio, in (-1, 0.5].

    Returns
    -------
    float
        ``K`` (N/m).
    """
    b = _pos("radius", radius)
    E = _pos("E", E)
    if not (-1.0 < float(nu) <= 0.5):
        raise InputError("nu", f"must be in (-1, 0.5], got {nu!r}")
    G = E / (2.0 * (1.0 + nu))
    return 32.0 * G * b * (1.0 - nu) / (7.0 - 8.0 * nu)
