"""Capillary force of a sphere on a flat with adsorbed water films (thesis A.2.2, Paper B 4.1).

Thesis Eqs. A.27-A.29 (Paper B Eqs. 17-19): a toroidal meniscus between a sphere of radius R
carrying a film t_ball and a flat carrying a film t_flat, with contact radius a (a^2/R is the
indentation) and filling angle phi (measured at the sphere's centre from the axis)::

    r1 = [R (1 - cos phi) - a^2/R - (t_ball cos phi + t_flat)] / (1 + cos phi)   (meridian, A.27a)
    r2 = R sin phi                                                              (neck, A.27b)
    1/r2 - 1/r1 = 1/r_k = R_g T ln(RH) / (gamma V)                               (Kelvin, A.28)
    F_cap = pi (R^2 sin^2 phi - a^2) dP_cap                                      (A.29)

Signs: r_k < 0 and dP_cap < 0 below saturation, so the concave meniscus has
1/r1 - 1/r2 = 1/|r_k| and F_cap < 0 (tensile).  The thesis writes A.25 as
(1/r1 - 1/r2)^-1 = r_k, which contradicts A.28 by a sign; A.28 (with r_k negative) is what is
solved here.  r1 follows from the circle of radius r1 tangent to the film surfaces of both
bodies (a film on the sphere counts t_ball cos phi vertically).  The wetted radius is R sin phi
(the thesis' approximation: the film thickness on the sphere is not added to it).

:func:`sphere_flat_island_force` gives what Paper B's island rule (cut height
S = |r_k| (cos theta1 + cos theta2) + e1 + e2) gives for the same rigid sphere: the wetted
disk g < S.  The two differ by the neck curvature 1/r2 (the island rule drops it) and the
cos phi factors, both small while |r_k| << sqrt(R S): about 1 % at RH 0.7 for R = 1 um, more
towards saturation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from ..errors import InputError

__all__ = ["SphereFlatCapillary", "sphere_flat_capillary", "sphere_flat_island_force"]


@dataclass(frozen=True)
class SphereFlatCapillary:
    """Toroidal meniscus of a sphere on a flat (thesis A.27-A.29).

    Attributes
    ----------
    filling_angle : float
        phi (rad); NaN at RH = 1 (no Laplace pressure, no finite meniscus).
    wetted_radius : float
        R sin phi (m).
    meridional_radius : float
        r1 (m, > 0).
    neck_radius : float
        r2 = R sin phi (m).
    force : float
        F_cap = pi (R^2 sin^2 phi - a^2) dP_cap (N, negative = tensile); 0 at RH = 1.
    """

    filling_angle: float
    wetted_radius: float
    meridional_radius: float
    neck_radius: float
    force: float


def _check(radius, kelvin_radius, capillary_pressure, film_ball, film_flat, contact_radius):
    R = float(radius)
    if not (math.isfinite(R) and R > 0):
        raise InputError("radius", f"must be a finite value > 0 m, got {radius!r}")
    rk = float(kelvin_radius)
    if math.isnan(rk) or rk >= 0:
        raise InputError("kelvin_radius", f"must be < 0 m (RH < 1) or -inf (RH = 1), got {kelvin_radius!r}")
    dp = float(capillary_pressure)
    if not (math.isfinite(dp) and dp <= 0):
        raise InputError("capillary_pressure", f"must be finite and <= 0 Pa, got {capillary_pressure!r}")
    if math.isinf(rk) != (dp == 0.0):
        raise InputError("capillary_pressure", "r_k = -inf (RH = 1) goes with dP_cap = 0 and only with it")
    for name, t in (("film_ball", film_ball), ("film_flat", film_flat), ("contact_radius", contact_radius)):
        if not (math.isfinite(float(t)) and float(t) >= 0):
            raise InputError(name, f"must be finite and >= 0 m, got {t!r}")
    return R, rk, dp, float(film_ball), float(film_flat), float(contact_radius)


def sphere_flat_capillary(radius: float, kelvin_radius: float, capillary_pressure: float, *,
                          film_ball: float = 0.0, film_flat: float = 0.0,
                          contact_radius: float = 0.0) -> SphereFlatCapillary:
    """Capillary force of a sphere on a flat with films, thesis Eqs. A.27-A.29.

    Parameters
    ----------
    radius : float
        Sphere radius R (m).
    kelvin_radius : float
        r_k (m, < 0; ``-inf`` at RH = 1).
    capillary_pressure : float
        dP_cap = gamma / r_k (Pa, <= 0).
    film_ball, film_flat : float
        Film thicknesses t1 (on the sphere) and t2 (on the flat), m.
    contact_radius : float
        a (m); 0 for rigid bodies touching at a point.

    Returns
    -------
    SphereFlatCapillary

    Raises
    ------
    InputError
        Invalid inputs, or a meniscus that would reach the sphere's equator (RH too close to
        1 for the toroidal approximation with these films).
    """
    R, rk, dp, t1, t2, a = _check(radius, kelvin_radius, capillary_pressure, film_ball, film_flat, contact_radius)
    if dp == 0.0:
        return SphereFlatCapillary(math.nan, math.nan, math.nan, math.nan, 0.0)
    inv_rk = 1.0 / rk

    def gap(phi):  # R (1 - cos phi) - a^2/R - (t1 cos phi + t2), with 1 - cos written stably
        c = math.cos(phi)
        return 2.0 * R * math.sin(0.5 * phi) ** 2 - a * a / R - (t1 * c + t2)

    def f(phi):
        return 1.0 / (R * math.sin(phi)) - (1.0 + math.cos(phi)) / gap(phi) - inv_rk

    # The meniscus needs r1 > 0: phi beyond the angle where the films (and indentation) close.
    c_lo = (R - a * a / R - t2) / (R + t1)
    if c_lo <= 0:
        raise InputError("film_ball", "films or indentation larger than the sphere: no meniscus")
    lo = math.acos(min(c_lo, 1.0))
    hi = 0.5 * math.pi
    if not f(hi) > 0:
        raise InputError("kelvin_radius", f"|r_k| = {abs(rk):.3g} m: the toroidal meniscus would pass the "
                                          "sphere's equator (RH too close to 1 for A.27-A.29)")
    # Just above lo, f -> -inf (r1 -> 0+): halve towards lo until f < 0 brackets the root.
    x = lo + 1e-6 * (hi - lo)
    for _ in range(80):
        if gap(x) > 0 and f(x) < 0:
            break
        x = lo + 0.5 * (x - lo)
    else:
        raise InputError("kelvin_radius", "no filling angle solves A.28 for these inputs")
    phi = brentq(f, x, hi, xtol=1e-15, rtol=1e-14, maxiter=200)
    r1 = gap(phi) / (1.0 + math.cos(phi))
    r2 = R * math.sin(phi)
    return SphereFlatCapillary(filling_angle=phi, wetted_radius=r2, meridional_radius=r1, neck_radius=r2,
                               force=math.pi * (r2 * r2 - a * a) * dp)


def sphere_flat_island_force(radius: float, kelvin_radius: float, capillary_pressure: float, *,
                             film_ball: float = 0.0, film_flat: float = 0.0, contact_angles=(0.0, 0.0),
                             exact: bool = True) -> float:
    """The capillary force Paper B's island rule gives for a rigid sphere touching a flat (N).

    The meniscus covers g(r) < S with S = |r_k| (cos theta1 + cos theta2) + t_ball + t_flat:
    r_w^2 = 2 R S - S^2 for the exact sphere g = R - sqrt(R^2 - r^2) (``exact``), 2 R S for the
    paraboloid r^2/(2R); F = pi r_w^2 dP_cap.  0 at RH = 1.

    This is the closed form of what the discrete island rule
    (:func:`~tribobem.interactions.menisci.meniscus_islands`) computes on a grid, so the
    validation can separate the discretisation error from the model difference to the toroidal
    meniscus of :func:`sphere_flat_capillary`.

    Parameters
    ----------
    radius : float
        Sphere radius R (m).
    kelvin_radius : float
        r_k (m, < 0; ``-inf`` at RH = 1); only ``|r_k|`` enters the cut height.
    capillary_pressure : float
        dP_cap = gamma / r_k (Pa, <= 0; 0 at RH = 1, which gives a zero force).
    film_ball, film_flat : float
        Adsorbed film thicknesses t_ball, t_flat on the sphere and the flat (m, >= 0).
    contact_angles : (float, float)
        theta1, theta2 (rad) of the meniscus on the two bodies.
    exact : bool
        True: the exact sphere gap ``R - sqrt(R^2 - r^2)`` (S capped at R); False: the
        paraboloid ``r^2/(2R)`` of the solvers' sphere geometry.

    Returns
    -------
    float
        Capillary force pi r_w^2 dP_cap (N, negative = tensile).

    Raises
    ------
    InputError
        Invalid radius, Kelvin radius, pressure or films.
    """
    R, rk, dp, t1, t2, _ = _check(radius, kelvin_radius, capillary_pressure, film_ball, film_flat, 0.0)
    if dp == 0.0:
        return 0.0
    c = math.cos(float(contact_angles[0])) + math.cos(float(contact_angles[1]))
    S = abs(rk) * c + t1 + t2
    if S <= 0:
        return 0.0
    S = min(S, R) if exact else S
    rw2 = 2.0 * R * S - S * S if exact else 2.0 * R * S
    return math.pi * rw2 * dp
