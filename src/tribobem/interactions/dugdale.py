"""Dugdale (Maugis) cohesive-zone approximation of the Lennard-Jones adhesion.

A constant tensile stress ``-sigma0`` acts where 0 < g < h0, nothing beyond (Paper A
Eq. 13), with ``sigma0 = 16 dgamma / (9 sqrt(3) z0)`` and ``h0 = dgamma / sigma0 =
9 sqrt(3) z0 / 16 = 0.974 z0`` (Paper D misprints h0 as 9 sqrt(3) z0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError


@dataclass(frozen=True)
class DugdaleAdhesion:
    """Dugdale adhesion law.

    Parameters
    ----------
    work_of_adhesion : float
        Delta gamma in J/m^2 (> 0).
    z0 : float
        Equilibrium separation of the Lennard-Jones potential in m (> 0), typically
        0.2-0.4 nm.
    """

    work_of_adhesion: float
    z0: float

    #: A step law of finite range h0 that depends on the gap alone: a window solve is exact
    #: (the check after each step grows the window when the zone reaches its edge).
    windowable = True
    #: The cohesive-zone resolution checks of :mod:`tribobem.output.checks` (they read
    #: ``sigma0`` and ``h0``).
    result_checks = frozenset({"cohesive_zone", "cohesive_range", "cohesive_edge"})
    #: The rows of :meth:`summary_info` in the HTML report: (key, label, dimension).
    report_rows = (
        ("sigma0", "Dugdale stress \u03c3\u2080", "pressure"),
        ("h0", "Dugdale range h\u2080", "length"),
        ("tabor_parameter", "Tabor parameter \u03bc_T", "dimensionless"),
        ("maugis_parameter", "Maugis parameter \u03bb", "dimensionless"),
    )

    def __post_init__(self):
        if not (math.isfinite(self.work_of_adhesion) and self.work_of_adhesion > 0):
            raise InputError("adhesion.work_of_adhesion", f"must be > 0 J/m^2, got {self.work_of_adhesion!r}")
        if not (math.isfinite(self.z0) and self.z0 > 0):
            raise InputError("adhesion.z0", f"must be > 0 m, got {self.z0!r}")

    @classmethod
    def from_spec(cls, spec, context=None) -> "DugdaleAdhesion":
        """The law of an ``[adhesion]`` table with ``model = "dugdale"`` (its registry builder).

        Parameters
        ----------
        spec : DugdaleAdhesionSpec
            The validated table: ``work_of_adhesion`` (J/m^2) and ``z0`` (m).
        context : LawContext, optional
            The problem (unused: the law depends on its own keys alone).

        Returns
        -------
        DugdaleAdhesion
        """
        return cls(spec.work_of_adhesion, spec.z0)

    def summary_info(self, radius: float | None = None, effective_modulus: float | None = None) -> dict:
        """sigma0 (Pa) and h0 (m), and for a sphere the Tabor and Maugis parameters.

        Parameters
        ----------
        radius : float, optional
            Composite sphere radius R (m); None: no sphere, no Tabor or Maugis parameter.
        effective_modulus : float, optional
            Composite modulus E* (Pa); None (both bodies rigid): no Tabor or Maugis parameter.

        Returns
        -------
        dict
            ``sigma0``, ``h0`` and, with both arguments, ``tabor_parameter`` and
            ``maugis_parameter`` (summary.json ``problem``).
        """
        info = {"sigma0": self.sigma0, "h0": self.h0}
        if radius is not None and effective_modulus is not None:
            info["tabor_parameter"] = self.tabor_parameter(radius, effective_modulus)
            info["maugis_parameter"] = self.maugis_parameter(radius, effective_modulus)
        return info

    @classmethod
    def from_stress(cls, sigma0: float, h0: float) -> "DugdaleAdhesion":
        """Build from the Dugdale stress (Pa) and range (m) directly.

        Parameters
        ----------
        sigma0 : float
            Dugdale stress (Pa, > 0).
        h0 : float
            Range of the cohesive zone (m, > 0).

        Returns
        -------
        DugdaleAdhesion
            dgamma = sigma0 h0 and z0 = 16 h0 / (9 sqrt3).
        """
        return cls(sigma0 * h0, h0 * 16.0 / (9.0 * math.sqrt(3.0)))

    @property
    def sigma0(self) -> float:
        """Dugdale stress sigma0 = 16 dgamma / (9 sqrt3 z0), Pa."""
        return 16.0 * self.work_of_adhesion / (9.0 * math.sqrt(3.0) * self.z0)

    @property
    def h0(self) -> float:
        """Range of the cohesive zone h0 = dgamma / sigma0 = 9 sqrt3 z0 / 16, m."""
        return self.work_of_adhesion / self.sigma0

    @property
    def range(self) -> float:
        """Range of the law (m): h0, beyond which the stress is 0."""
        return self.h0

    @property
    def floor(self) -> float:
        """Lowest contact pressure (Pa): -sigma0, the law's limit at zero gap."""
        return -self.sigma0

    def outside_stress(self, gap, xp):
        """-sigma0 where gap < h0, else 0 (Pa).

        Parameters
        ----------
        gap : ndarray
            Gap of the non-contact nodes (m), any shape.
        xp : module
            Array namespace of ``gap`` (``numpy`` or ``cupy``).

        Returns
        -------
        ndarray
            Stress (Pa, negative = tensile), shape of ``gap``.
        """
        return xp.where(gap < self.h0, -self.sigma0, 0.0)

    def tabor_parameter(self, radius: float, effective_modulus: float) -> float:
        """mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3) (the square on dgamma that Paper A Eq. 1 omits).

        Parameters
        ----------
        radius : float
            Composite sphere radius R (m).
        effective_modulus : float
            Composite modulus E* (Pa).

        Returns
        -------
        float
            Tabor parameter (dimensionless).
        """
        return (radius * self.work_of_adhesion**2 / (effective_modulus**2 * self.z0**3)) ** (1.0 / 3.0)

    def maugis_parameter(self, radius: float, effective_modulus: float) -> float:
        """lambda = 2 sigma0 (9 R / (16 pi dgamma E*^2))^(1/3) (about 1.16 mu_T).

        Parameters
        ----------
        radius : float
            Composite sphere radius R (m).
        effective_modulus : float
            Composite modulus E* (Pa).

        Returns
        -------
        float
            Maugis parameter (dimensionless).
        """
        return 2.0 * self.sigma0 * (9.0 * radius / (16.0 * math.pi * self.work_of_adhesion * effective_modulus**2)) ** (1.0 / 3.0)

    @classmethod
    def from_tabor(cls, tabor: float, radius: float, effective_modulus: float, z0: float) -> "DugdaleAdhesion":
        """The work of adhesion that gives Tabor parameter ``tabor`` for this sphere.

        Parameters
        ----------
        tabor : float
            Target Tabor parameter mu_T (dimensionless).
        radius : float
            Composite sphere radius R (m).
        effective_modulus : float
            Composite modulus E* (Pa).
        z0 : float
            Equilibrium separation (m).

        Returns
        -------
        DugdaleAdhesion
            dgamma = sqrt(mu_T^3 E*^2 z0^3 / R) (J/m^2) and ``z0``.
        """
        dgamma = math.sqrt(tabor**3 * effective_modulus**2 * z0**3 / radius)
        return cls(dgamma, z0)

    @classmethod
    def from_maugis(cls, lam: float, radius: float, effective_modulus: float, z0: float) -> "DugdaleAdhesion":
        """The work of adhesion that gives Maugis parameter ``lam`` for this sphere.

        lambda = 2 (16/(9 sqrt3)) (dgamma/z0) (9R/(16 pi dgamma E*^2))^(1/3) is
        proportional to dgamma^(2/3), so dgamma follows in closed form.

        Parameters
        ----------
        lam : float
            Target Maugis parameter lambda (dimensionless).
        radius : float
            Composite sphere radius R (m).
        effective_modulus : float
            Composite modulus E* (Pa).
        z0 : float
            Equilibrium separation (m).

        Returns
        -------
        DugdaleAdhesion
            The law with that dgamma (J/m^2) and ``z0``.
        """
        k = 2.0 * 16.0 / (9.0 * math.sqrt(3.0) * z0) * (9.0 * radius / (16.0 * math.pi * effective_modulus**2)) ** (1.0 / 3.0)
        return cls((lam / k) ** 1.5, z0)
