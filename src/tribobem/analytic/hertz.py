"""Hertz contact of a sphere (paraboloid) on an elastic half-space (thesis Appendix A.1).

Conventions: SI units, E* the composite modulus 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,
force F > 0 compressive, approach delta > 0 when the bodies are pushed together.

Thesis Eqs. A.1-A.3::

    a = (3 R F / (4 E*))^(1/3),   p0 = 3 F / (2 pi a^2),   delta = a^2 / R,
    p(r) = p0 sqrt(1 - r^2/a^2)  (r <= a),  0 outside.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["HertzSolution", "hertz", "hertz_pressure"]


def _positive(name, value):
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
        raise InputError(name, f"must be finite and > 0, got {value!r}")
    return arr


def _scalar_or_array(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


@dataclass(frozen=True)
class HertzSolution:
    """Hertz solution of a sphere on a flat.

    Attributes
    ----------
    contact_radius : float or ndarray
        Contact radius a (m).
    max_pressure : float or ndarray
        Central pressure p0 = 3F/(2 pi a^2) (Pa).
    approach : float or ndarray
        Rigid approach delta = a^2/R (m).
    force : float or ndarray
        Normal force F (N), compressive positive.
    mean_pressure : float or ndarray
        F / (pi a^2) = 2 p0 / 3 (Pa); 0 where a = 0.
    """

    contact_radius: float | np.ndarray
    max_pressure: float | np.ndarray
    approach: float | np.ndarray
    force: float | np.ndarray
    mean_pressure: float | np.ndarray


def hertz(force=None, approach=None, *, radius, E_star) -> HertzSolution:
    """Hertz contact of a sphere of radius ``radius`` on a flat, from force or approach.

    Parameters
    ----------
    force : float or array_like, optional
        Normal force F >= 0 (N).  Give exactly one of ``force`` and ``approach``.
    approach : float or array_like, optional
        Rigid approach delta >= 0 (m).
    radius : float
        Sphere (composite) radius R (m).
    E_star : float
        Composite modulus E* (Pa).

    Returns
    -------
    HertzSolution
        Contact radius, central and mean pressure, approach and force (vectorised).

    Notes
    -----
    ``a = (3 R F/(4 E*))^(1/3)``, ``delta = a^2/R``, ``F = 4 E* a^3/(3 R)``,
    ``p0 = 3F/(2 pi a^2) = 2 E* a/(pi R)`` (thesis Eqs. A.1-A.3).
    """
    if (force is None) == (approach is None):
        raise InputError("hertz", "give exactly one of force= and approach=")
    R = float(_positive("radius", radius))
    Es = float(_positive("E_star", E_star))
    if force is not None:
        F = np.asarray(force, dtype=float)
        if np.any(~np.isfinite(F)) or np.any(F < 0):
            raise InputError("force", f"must be finite and >= 0 (no adhesion in Hertz), got {force!r}")
        a = np.cbrt(3.0 * R * F / (4.0 * Es))
        d = a**2 / R
    else:
        d = np.asarray(approach, dtype=float)
        if np.any(~np.isfinite(d)) or np.any(d < 0):
            raise InputError("approach", f"must be finite and >= 0, got {approach!r}")
        a = np.sqrt(R * d)
        F = 4.0 * Es * a**3 / (3.0 * R)
    p0 = 2.0 * Es * a / (np.pi * R)
    pm = 2.0 * p0 / 3.0
    return HertzSolution(
        contact_radius=_scalar_or_array(a),
        max_pressure=_scalar_or_array(p0),
        approach=_scalar_or_array(d),
        force=_scalar_or_array(F),
        mean_pressure=_scalar_or_array(pm),
    )


def hertz_pressure(r, a, p0):
    """Hertz pressure profile p(r) = p0 sqrt(1 - r^2/a^2) for r < a, 0 outside (Eq. A.2).

    Parameters
    ----------
    r : array_like
        Radial distance(s) from the contact centre (m).
    a : float
        Contact radius (m).
    p0 : float
        Central pressure (Pa).

    Returns
    -------
    ndarray or float
        Pressure (Pa), same shape as ``r``.
    """
    r = np.asarray(r, dtype=float)
    rho2 = (r / a) ** 2 if a > 0 else np.full_like(r, np.inf)
    p = p0 * np.sqrt(np.clip(1.0 - rho2, 0.0, None))
    return _scalar_or_array(p)
