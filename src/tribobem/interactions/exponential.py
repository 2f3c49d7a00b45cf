"""Exponential adhesion with a hard wall: a smooth cohesive law of finite work.

Outside the contact a node with gap g > 0 carries the tension

    p(g) = -(w / rho) exp(-g / rho)

(w the work of adhesion, J/m^2, rho the range, m): the law of the Contact Mechanics
Challenge's adhesive case (Mueser et al., Tribol. Lett. 65:118, 2017) and of Tamaas's
``ExponentialAdhesionFunctional`` (its ``rho`` and ``surface_energy``).  The contact nodes
(g = 0) carry any p > -w / rho, the law's value at zero gap: the wall is hard, so the
repulsion is the contact pressure itself.

The law is smooth in g: the normal solvers treat changes of its tension as fixed-point updates
of the load (one piece of :meth:`outside_branch`).  A node's own equilibrium, g = g_ext + C
p(g) with C the cell's self-compliance, is single-valued when the law's largest slope w / rho^2
is below the cell stiffness 1 / C, i.e. when ``C w / rho^2 < 1`` (:meth:`cell_ratio`): the
exponential counterpart of Dugdale's sigma0 C criterion (:mod:`.dugdale`).  On coarser cells
the discrete problem may have several equilibria, as the step law has.

"Adhesive area": the nodes out of contact with g < rho, where the tension is above 1/e of its
peak (the range over which a Dugdale law of the same peak and work would act).  The adhesive
*force* counts every tensile node.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .base import require_positive

__all__ = ["ExponentialAdhesion"]

#: Separation (in units of rho) used as the law's ``range`` where a finite one is needed (the
#: separated start of a pull-off, the path's stepping): the tension there is e^-7 ~ 1e-3 of the peak.
RANGE_RHO = 7.0


@dataclass(frozen=True)
class ExponentialAdhesion:
    """Exponential adhesion law with a hard wall.

    Parameters
    ----------
    work_of_adhesion : float
        w in J/m^2 (> 0): the integral of the tension over the gap.
    rho : float
        Decay length rho in m (> 0).
    """

    work_of_adhesion: float
    rho: float

    #: The range is infinite (the tail beyond a window would be dropped): no window solves.
    windowable = False
    result_checks = frozenset()
    report_rows = (
        ("peak_stress", "exponential law's peak stress w/\u03c1", "pressure"),
        ("rho", "exponential law's range \u03c1", "length"),
        ("tabor_parameter", "Tabor parameter \u03bc_T (z0 = \u03c1)", "dimensionless"),
    )

    def __post_init__(self):
        require_positive(self, work_of_adhesion="J/m^2", rho="m")

    @classmethod
    def from_spec(cls, spec, context=None) -> "ExponentialAdhesion":
        """The law of an ``[adhesion] model = "exponential"`` table (its registry builder).

        Parameters
        ----------
        spec : ExponentialAdhesionSpec
            ``work_of_adhesion`` (J/m^2) and ``rho`` (m).
        context : LawContext, optional
            Unused: the law depends on its own keys alone.

        Returns
        -------
        ExponentialAdhesion
        """
        return cls(spec.work_of_adhesion, spec.rho)

    @property
    def peak_stress(self) -> float:
        """w / rho (Pa): the tension at zero gap."""
        return self.work_of_adhesion / self.rho

    @property
    def floor(self) -> float:
        """Lowest contact pressure (Pa): -w / rho, the law at zero gap."""
        return -self.peak_stress

    @property
    def range(self) -> float:
        """A finite range for stepping (m): 7 rho, where the tension is 1e-3 of its peak."""
        return RANGE_RHO * self.rho

    @property
    def path_step(self) -> float:
        """The approach step of load paths near the wall (m): rho / 4."""
        return 0.25 * self.rho

    def outside_stress(self, gap, xp):
        """-(w / rho) exp(-g / rho) (Pa) on the non-contact nodes.

        Parameters
        ----------
        gap : ndarray
            Gap (m), any shape.
        xp : module
            Array namespace of ``gap``.

        Returns
        -------
        ndarray
            Stress (Pa, negative = tensile), shape of ``gap``.
        """
        # an overlapping node (g < 0, about to enter the contact) takes the law's value at the wall
        return -self.peak_stress * xp.exp(-xp.maximum(gap, 0.0) / self.rho)

    def outside_slope(self, gap, xp):
        """ds/dg = (w / rho^2) exp(-g / rho) (Pa/m) for g > 0 (the solvers' relaxed update)."""
        return (self.peak_stress / self.rho) * xp.exp(-xp.maximum(gap, 0.0) / self.rho)

    def outside_branch(self, gap, xp):
        """One smooth piece: zeros (int8) of the shape of ``gap``."""
        return xp.zeros(gap.shape, dtype=xp.int8)

    def adhesive_mask(self, gap, xp):
        """The adhesive area's nodes among the non-contact ones: g < rho (module docstring)."""
        return gap < self.rho

    def cell_ratio(self, compliance: float) -> float:
        """C w / rho^2: below 1 a node's equilibrium is single-valued (module docstring).

        Parameters
        ----------
        compliance : float
            The cell's self-compliance C (m/Pa).

        Returns
        -------
        float
        """
        return float(compliance) * self.work_of_adhesion / self.rho**2

    def summary_info(self, radius: float | None = None, effective_modulus: float | None = None) -> dict:
        """peak stress (Pa), rho (m) and, for a sphere, the Tabor parameter with z0 = rho.

        Parameters
        ----------
        radius : float, optional
            Composite sphere radius R (m).
        effective_modulus : float, optional
            Composite modulus E* (Pa).

        Returns
        -------
        dict
        """
        info = {"peak_stress": self.peak_stress, "rho": self.rho}
        if radius is not None and effective_modulus is not None:
            info["tabor_parameter"] = self.tabor_parameter(radius, effective_modulus)
        return info

    def tabor_parameter(self, radius: float, effective_modulus: float) -> float:
        """mu = (R w^2 / (E*^2 rho^3))^(1/3), the sphere's Tabor parameter with z0 = rho.

        Parameters
        ----------
        radius : float
            Composite sphere radius R (m).
        effective_modulus : float
            Composite modulus E* (Pa).

        Returns
        -------
        float
        """
        return (radius * self.work_of_adhesion**2 / (effective_modulus**2 * self.rho**3)) ** (1.0 / 3.0)

    @classmethod
    def from_tabor(cls, tabor: float, radius: float, effective_modulus: float, rho: float) -> "ExponentialAdhesion":
        """The work of adhesion that gives Tabor parameter ``tabor`` (z0 = rho) for this sphere.

        Parameters
        ----------
        tabor : float
            mu (dimensionless).
        radius, effective_modulus, rho : float
            R (m), E* (Pa), rho (m).

        Returns
        -------
        ExponentialAdhesion
        """
        return cls(math.sqrt(tabor**3 * effective_modulus**2 * rho**3 / radius), rho)
