"""Lennard-Jones 9-3 adhesion with a hard wall at its zero-force separation.

Two half-spaces whose atoms interact by a 6-12 Lennard-Jones potential exert on each other the
9-3 stress (Paper A's origin of the Dugdale law; Greenwood 1997)

    p(D) = -(8 dgamma / (3 z0)) [ (z0 / D)^3 - (z0 / D)^9 ],

D the separation, z0 the equilibrium separation (p = 0 at D = z0), dgamma the work of adhesion
(the integral of the tension from z0 to infinity).  Its largest tension, at D = 3^(1/6) z0, is
16 dgamma / (9 sqrt3 z0): Dugdale's sigma0 of the same dgamma and z0, which is how the Dugdale
law is fitted to it.

**Gap datum.** The solvers' gap g is zero in contact.  Here g = D - z0: contact is the
equilibrium separation, and the 9-3 law's own repulsion (D < z0) is replaced by the hard wall
of the contact constraint, which carries any p > 0 there (``floor`` 0: the law's value at
g = 0).  The work of the tensile branch, dgamma, is unchanged.

"Adhesive area": the nodes out of contact with g < h0 = 9 sqrt3 z0 / 16, the range of the
Dugdale law of the same dgamma and z0 (the tension there is above 0.44 of its peak).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .base import require_positive

__all__ = ["LennardJonesAdhesion"]

#: Separation (in units of z0, beyond contact) used as the law's finite ``range``: the tension
#: at g = 9 z0 is 1.4e-3 of its peak.
RANGE_Z0 = 9.0


@dataclass(frozen=True)
class LennardJonesAdhesion:
    """The 9-3 Lennard-Jones stress with a hard wall at D = z0 (module docstring).

    Parameters
    ----------
    work_of_adhesion : float
        dgamma in J/m^2 (> 0).
    z0 : float
        Equilibrium separation in m (> 0).
    """

    work_of_adhesion: float
    z0: float

    windowable = False
    result_checks = frozenset()
    report_rows = (
        ("peak_stress", "Lennard-Jones peak stress", "pressure"),
        ("tabor_parameter", "Tabor parameter \u03bc_T", "dimensionless"),
    )

    def __post_init__(self):
        require_positive(self, work_of_adhesion="J/m^2", z0="m")

    @classmethod
    def from_spec(cls, spec, context=None) -> "LennardJonesAdhesion":
        """The law of an ``[adhesion] model = "lennard_jones"`` table (its registry builder)."""
        return cls(spec.work_of_adhesion, spec.z0)

    @property
    def peak_stress(self) -> float:
        """16 dgamma / (9 sqrt3 z0) (Pa), at g = (3^(1/6) - 1) z0."""
        return 16.0 * self.work_of_adhesion / (9.0 * math.sqrt(3.0) * self.z0)

    @property
    def h0(self) -> float:
        """The Dugdale range of the same dgamma and z0, 9 sqrt3 z0 / 16 (m): the adhesive area's edge."""
        return 9.0 * math.sqrt(3.0) * self.z0 / 16.0

    floor = 0.0

    @property
    def tension_limit(self) -> float:
        """The most tensile stress of the law (Pa): -peak_stress (the floor, the law at g = 0, is 0)."""
        return -self.peak_stress

    @property
    def range(self) -> float:
        """A finite range for stepping (m): 9 z0."""
        return RANGE_Z0 * self.z0

    @property
    def path_step(self) -> float:
        """The approach step of load paths near the wall (m): z0 / 8."""
        return 0.125 * self.z0

    def _s(self, gap, xp):
        return self.z0 / (xp.maximum(gap, 0.0) + self.z0)

    def outside_stress(self, gap, xp):
        """-(8 dgamma / (3 z0)) (s^3 - s^9), s = z0 / (g + z0) (Pa); 0 at g = 0."""
        s3 = self._s(gap, xp) ** 3
        return -(8.0 * self.work_of_adhesion / (3.0 * self.z0)) * (s3 - s3**3)

    def outside_slope(self, gap, xp):
        """ds/dg (Pa/m) of :meth:`outside_stress` (the solvers' relaxed update)."""
        s = self._s(gap, xp)
        return (8.0 * self.work_of_adhesion / (3.0 * self.z0**2)) * (3.0 * s**4 - 9.0 * s**10)

    def outside_branch(self, gap, xp):
        """One smooth piece: zeros (int8)."""
        return xp.zeros(gap.shape, dtype=xp.int8)

    def adhesive_mask(self, gap, xp):
        """The adhesive area's nodes among the non-contact ones: g < h0 (module docstring)."""
        return gap < self.h0

    def summary_info(self, radius: float | None = None, effective_modulus: float | None = None) -> dict:
        """peak stress (Pa) and, for a sphere, the Tabor parameter."""
        info = {"peak_stress": self.peak_stress}
        if radius is not None and effective_modulus is not None:
            info["tabor_parameter"] = (radius * self.work_of_adhesion**2
                                       / (effective_modulus**2 * self.z0**3)) ** (1.0 / 3.0)
        return info
