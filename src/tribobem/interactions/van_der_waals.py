"""Van der Waals stresses between solids with adsorbed water films (Paper B 2.3, Paper C).

Sign convention: a stress is negative when tensile, so an attraction is NEGATIVE
here.  Paper C prints the water-filled term with a plus sign (Eq. 8); Paper B (Eq. 11) and
this module write it with a minus.

Hamaker constants
-----------------
The thesis gives none.  Each body's own constant in vacuum (A_11, A_22) and water's (A_ww)
are inputs; the constants across a medium follow from the combining rule (Israelachvili,
*Intermolecular and Surface Forces*, ch. 13)::

    A_132 = (sqrt A_11 - sqrt A_33)(sqrt A_22 - sqrt A_33)

Defaults (APPROXIMATE, typical literature values): SiO2 6.5e-20 J, Si 19e-20 J, water
3.7e-20 J.  A combined constant may be negative (a repulsion across the medium); a body's own
constant in vacuum may not.

Water-filled gap (Paper B Eq. 11): p = -A_1w2 / (6 pi g^3).

Air gap between the two films (Paper B Eq. 12, signs corrected)
---------------------------------------------------------------
Body 1 (solid 1 under a film e1) and body 2 (solid 2 under a film e2) face each other across
an air gap e_a = g - e1 - e2.  Pairwise summation with the combining rule (write each body as
a sum of half-spaces of "strength" sqrt A: a water half-space ending at the film surface plus
a (sqrt A_i - sqrt A_w) half-space ending at the solid surface) gives four terms::

    p = -(1/(6 pi)) [ A_waw / e_a^3
                      + sqrt(A_ww) (sqrt A_11 - sqrt A_ww) / (e_a + e1)^3
                      + sqrt(A_ww) (sqrt A_22 - sqrt A_ww) / (e_a + e2)^3
                      + (sqrt A_11 - sqrt A_ww)(sqrt A_22 - sqrt A_ww) / (e_a + e1 + e2)^3 ]

with A_waw = A_ww (water across air, air taken as vacuum) and the last coefficient A_1w2.
Paper B prints the two middle terms as ``- sqrt(A_1w1 A_waw) / (e_a + e1)^3`` and
``- sqrt(A_2w2 A_waw) / (e_a + e2)^3``.  With A_1w1 = (sqrt A_11 - sqrt A_ww)^2 and positive
square roots that sign is wrong for solids with A_11 > A_ww (SiO2, Si): as e1, e2 -> 0 the
bracket must become the solid/air/solid constant sqrt(A_11 A_22) = A_12, which the form above
gives and the printed one does not (it gives (sqrt A_11 - 2 sqrt A_ww)(sqrt A_22 - 2 sqrt A_ww),
1.7e-20 J instead of 6.5e-20 J for SiO2 on SiO2).  The middle coefficients are -A_1wa and
-A_2wa of the combining rule (solid across water against air), which is how the layered-body
formula of Israelachvili (ch. 13) reads.  Other limits (tested): with thick films only the
water/air/water term is left; as e_a -> 0 it dominates (the films attract each other, the
reason for Paper B's critical distance d_cr) and the last term tends to the water-filled
value at g = e1 + e2.

Short-range cut-off: the 1/D^3 terms diverge at contact.  With a Dugdale zone the solid-solid
stress takes over below h0, so the water-filled term is never evaluated below h0; without it
every separation D in these terms is replaced by max(D, cutoff) (default: a typical z0,
:data:`DEFAULT_CUTOFF`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = [
    "HAMAKER_SIO2", "HAMAKER_SI", "HAMAKER_WATER", "DEFAULT_CUTOFF", "combine_hamaker",
    "water_filled_stress", "air_gap_stress", "VanDerWaals",
]

#: Hamaker constant of silica (SiO2) in vacuum, J (approximate).
HAMAKER_SIO2 = 6.5e-20
#: Hamaker constant of silicon in vacuum, J (approximate).
HAMAKER_SI = 19e-20
#: Hamaker constant of water in vacuum, J (approximate).
HAMAKER_WATER = 3.7e-20
#: Default short-range cut-off of the 1/D^3 terms without a Dugdale zone, m (a typical z0).
DEFAULT_CUTOFF = 0.3e-9


def _hamaker(value, field: str) -> float:
    try:
        a = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"Hamaker constant must be a number in J, got {value!r}") from None
    if not (math.isfinite(a) and a >= 0.0):
        raise InputError(field, f"a Hamaker constant in vacuum must be finite and >= 0 J, got {value!r}")
    return a


def combine_hamaker(a11: float, a22: float, a33: float = 0.0) -> float:
    """Hamaker constant A_132 of bodies 1 and 2 across medium 3 (combining rule), J.

    Parameters
    ----------
    a11, a22, a33 : float
        The three materials' own constants in vacuum (J, >= 0); ``a33 = 0`` is vacuum/air.

    Returns
    -------
    float
        A_132 = (sqrt A_11 - sqrt A_33)(sqrt A_22 - sqrt A_33); negative (repulsive) when the
        medium's constant lies between the two bodies'.

    Raises
    ------
    InputError
        A negative or non-finite constant.
    """
    s1 = math.sqrt(_hamaker(a11, "hamaker.a11"))
    s2 = math.sqrt(_hamaker(a22, "hamaker.a22"))
    s3 = math.sqrt(_hamaker(a33, "hamaker.a33"))
    return (s1 - s3) * (s2 - s3)


def _cutoff(cutoff) -> float:
    c = float(cutoff)
    if not (math.isfinite(c) and c >= 0.0):
        raise InputError("cutoff", f"must be a finite value >= 0 m, got {cutoff!r}")
    return c


def water_filled_stress(gap, a1w2: float, cutoff: float = 0.0, xp=np):
    """Van der Waals stress across a water-filled gap, -A_1w2 / (6 pi max(g, cutoff)^3) (Pa).

    Parameters
    ----------
    gap : array_like
        Gap g (m); > 0 where ``cutoff`` is 0.
    a1w2 : float
        Hamaker constant of body 1 and body 2 across water (J), from :func:`combine_hamaker`.
    cutoff : float
        Smallest separation used (m).
    xp : module
        Array module.

    Returns
    -------
    ndarray
        Stress (Pa; tensile, i.e. negative, for A_1w2 > 0), shape of ``gap``.

    Raises
    ------
    InputError
        A negative or non-finite ``cutoff``.
    """
    d = xp.maximum(gap, _cutoff(cutoff))
    return (-a1w2 / (6.0 * math.pi)) / (d * d * d)


def _air_coefficients(a11: float, a22: float, aww: float) -> tuple[float, float, float, float]:
    s1, s2, sw = math.sqrt(a11), math.sqrt(a22), math.sqrt(aww)
    return aww, sw * (s1 - sw), sw * (s2 - sw), (s1 - sw) * (s2 - sw)


def air_gap_stress(gap, film1, film2, hamaker1: float, hamaker2: float, water_hamaker: float = HAMAKER_WATER,
                   cutoff: float = 0.0, xp=np):
    """Van der Waals stress between two film-covered solids across an air gap (Pa).

    Paper B Eq. 12 with the signs of its middle terms corrected (module docstring), with the
    air gap e_a = max(g - e1 - e2, cutoff).

    Parameters
    ----------
    gap : array_like
        Gap g between the solid surfaces (m).
    film1, film2 : float or array_like
        Film thicknesses e1, e2 (m).
    hamaker1, hamaker2, water_hamaker : float
        Own constants of body 1, body 2 and water in vacuum (J, >= 0).
    cutoff : float
        Smallest air gap used (m); with 0 the air gap must be positive.
    xp : module
        Array module.

    Returns
    -------
    ndarray
        Stress (Pa, negative = tensile), broadcast shape of ``gap`` and the films.

    Raises
    ------
    InputError
        A negative or non-finite Hamaker constant or ``cutoff``.
    """
    c_ww, c_1w, c_w2, c_12 = _air_coefficients(_hamaker(hamaker1, "hamaker1"), _hamaker(hamaker2, "hamaker2"),
                                               _hamaker(water_hamaker, "water_hamaker"))
    e1 = xp.asarray(film1, dtype=float)
    e2 = xp.asarray(film2, dtype=float)
    ea = xp.maximum(gap - e1 - e2, _cutoff(cutoff))
    d1, d2, d12 = ea + e1, ea + e2, ea + e1 + e2
    return (-1.0 / (6.0 * math.pi)) * (c_ww / ea**3 + c_1w / d1**3 + c_w2 / d2**3 + c_12 / d12**3)


@dataclass(frozen=True)
class VanDerWaals:
    """The water-solid van der Waals terms of one body pair.

    Parameters
    ----------
    hamaker1, hamaker2 : float
        Own Hamaker constants of bodies 1 and 2 in vacuum (J, >= 0); defaults: SiO2.
    water_hamaker : float
        Water's own constant in vacuum (J, >= 0).
    cutoff : float
        Smallest separation in the 1/D^3 terms (m, > 0).
    """

    hamaker1: float = HAMAKER_SIO2
    hamaker2: float = HAMAKER_SIO2
    water_hamaker: float = HAMAKER_WATER
    cutoff: float = DEFAULT_CUTOFF

    def __post_init__(self):
        _hamaker(self.hamaker1, "hamaker1")
        _hamaker(self.hamaker2, "hamaker2")
        _hamaker(self.water_hamaker, "water_hamaker")
        if not (math.isfinite(self.cutoff) and self.cutoff > 0):
            raise InputError("cutoff", f"must be a finite value > 0 m, got {self.cutoff!r}")

    @property
    def solid_solid(self) -> float:
        """A_12 across air/vacuum, sqrt(A_11 A_22) (J)."""
        return combine_hamaker(self.hamaker1, self.hamaker2)

    @property
    def water_filled(self) -> float:
        """A_1w2 across water (J)."""
        return combine_hamaker(self.hamaker1, self.hamaker2, self.water_hamaker)

    def water_filled_stress(self, gap, xp=np):
        """-A_1w2 / (6 pi max(g, cutoff)^3) (Pa), with this pair's constants.

        Parameters
        ----------
        gap : array_like
            Gap g (m).
        xp : module
            Array module.

        Returns
        -------
        ndarray
            Stress (Pa), shape of ``gap``; see :func:`water_filled_stress`.
        """
        return water_filled_stress(gap, self.water_filled, self.cutoff, xp)

    def air_gap_stress(self, gap, film1, film2, xp=np):
        """Paper B Eq. 12 (signs corrected) with e_a = max(g - e1 - e2, cutoff) (Pa).

        Parameters
        ----------
        gap : array_like
            Gap g between the solid surfaces (m).
        film1, film2 : float or array_like
            Film thicknesses e1, e2 (m).
        xp : module
            Array module.

        Returns
        -------
        ndarray
            Stress (Pa), see :func:`air_gap_stress`.
        """
        return air_gap_stress(gap, film1, film2, self.hamaker1, self.hamaker2, self.water_hamaker, self.cutoff, xp)
