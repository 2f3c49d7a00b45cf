"""Dugdale (Maugis) cohesive-zone approximation of the Lennard-Jones adhesion.

A constant tensile stress ``-sigma0`` acts where 0 < g < h0, nothing beyond (Paper A
Eq. 13), with ``sigma0 = 16 dgamma / (9 sqrt(3) z0)`` and ``h0 = dgamma / sigma0 =
9 sqrt(3) z0 / 16 = 0.974 z0`` (Paper D misprints h0 as 9 sqrt(3) z0).

Two discretisations of the law on the grid:

* :class:`DugdaleAdhesion`, the step (the thesis' discretisation): a node carries -sigma0
  while its gap is below h0.  A node whose gap lies within sigma0 C of h0 (C the cell's
  self-compliance, 1.12 dx / E* for a square cell) is consistent both in and out of the zone:
  its own tension closes its gap by sigma0 C.  The discrete problem then has many equilibria,
  which differ by such edge nodes, and each solver (and each start) stops on one of them.
* :class:`SoftenedDugdale` (the default of ``[adhesion] model = "dugdale"`` where its ramp is
  at most h0 / 5 wide, :data:`AUTO_MAX_WIDTH`): the step is
  replaced by a linear ramp of width w centred on h0, -sigma0 below h0 - w/2, 0 above h0 + w/2.
  It keeps the work of adhesion (the area under the law, sigma0 h0) and, read as a sub-cell
  model, gives each cell the tension sigma0 times the part of the cell inside the zone, for a
  gap that varies by w across the cell.  The criterion for one equilibrium per node: a node
  under a fixed load from the others solves g = g_ext + C s(g), whose left side minus the right
  is strictly increasing when the law's slope sigma0 / w is below the cell's own stiffness
  1 / C, i.e. w > sigma0 C.  The ramp's nodes form a ring around the zone, one or two cells
  wide, whose collective modes are more compliant than one cell: measured on a sphere, the
  solvers' fixed point over the ring contracts as it would for a compliance of 1.9 C.  tribobem
  takes w = 3 sigma0 C (:data:`SOFTENING`), so that the ring too is single-valued with a margin,
  and Polonsky-Keer and NormCG stop on the same state.  As the cell shrinks w -> 0 and the law
  becomes Dugdale's.  Where w would exceed 2 h0 (a cell so coarse that sigma0 C > 2 h0 / 3) the
  law becomes a triangle from g = 0 with the same slope and work, sigma0' = 2 dgamma / w' below
  sigma0, w' = sqrt(2 h0 w).

Where the ramp is wide against h0 (a cell coarse against the cohesive length E* h0 / sigma0:
the Maugis-Dugdale sphere at lambda = 5 with 4 cells across its zone has w = 0.62 h0, a flat
punch's edge 0.88 h0) the ramp spans several cells, its ring softens faster than the ring's own
elastic response, and the softened solves did not converge or lost accuracy.  The default
``discretisation = "auto"`` (:func:`build_dugdale`) therefore softens only where w <= h0 / 5
(:data:`AUTO_MAX_WIDTH`) and keeps the step elsewhere.

What the softening cannot remove is a physical instability: a flat top under displacement
control at a separation near h0, or the jump-in and jump-off of a sphere under force control,
are many-valued in the continuous problem too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from .base import require_positive

#: Widest ramp (in units of h0) that ``discretisation = "auto"`` (the default) softens: beyond it the
#: ramp is no longer a small change of Dugdale's law (a cell coarse against the cohesive length
#: E* h0 / sigma0, as at lambda = 5 on 624^2 or a flat punch's edge), the softened solves failed to
#: converge or lost accuracy there (docs: theory, adhesion), and the step law is kept.
AUTO_MAX_WIDTH = 0.2

#: Width of the softened law's ramp in units of sigma0 x the cell's self-compliance: three times
#: the least width (sigma0 C) at which a lone node's equilibrium is single-valued (module docstring).
SOFTENING = 3.0


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
        require_positive(self, work_of_adhesion="J/m^2", z0="m")

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

    def softened(self, grid, effective_modulus: float | None, softening: float = SOFTENING) -> "DugdaleAdhesion":
        """This law softened for a grid (:class:`SoftenedDugdale`, the default of scenarios).

        Parameters
        ----------
        grid : Grid
            The solver grid (its cell dx x dy, m).
        effective_modulus : float or None
            Composite modulus E* (Pa); None (rigid bodies): the step law itself.
        softening : float
            w / (sigma0 C), > 1.

        Returns
        -------
        SoftenedDugdale or DugdaleAdhesion
        """
        if effective_modulus is None:
            return DugdaleAdhesion(self.work_of_adhesion, self.z0)
        from ..elasticity.bodies.halfspace import halfspace_self_compliance

        c = halfspace_self_compliance(grid.dx, grid.dy, effective_modulus)
        return SoftenedDugdale.for_cell(self.work_of_adhesion, self.z0, c, softening)

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


@dataclass(frozen=True)
class SoftenedDugdale(DugdaleAdhesion):
    """Dugdale adhesion with the step at h0 softened to a ramp of width ``width`` (module docstring).

    Parameters
    ----------
    work_of_adhesion : float
        Delta gamma in J/m^2 (> 0).
    z0 : float
        Equilibrium separation of the Lennard-Jones potential in m (> 0).
    width : float
        Width w of the ramp (m, >= 0); 0 is the step law.  :meth:`for_cell` takes it from the
        cell's self-compliance.

    Notes
    -----
    ``sigma0`` and ``h0`` stay Dugdale's (the checks, the Tabor and Maugis parameters and the
    reports read them); ``floor`` and ``range`` are the softened law's.
    """

    width: float = 0.0

    #: Without two-way edge nodes the cohesive-edge band is empty by construction.
    result_checks = frozenset({"cohesive_zone", "cohesive_range"})
    report_rows = DugdaleAdhesion.report_rows + (("softening_width", "Dugdale softening width w", "length"),)

    def __post_init__(self):
        super().__post_init__()
        if not (math.isfinite(self.width) and self.width >= 0):
            raise InputError("adhesion.width", f"must be >= 0 m, got {self.width!r}")

    @classmethod
    def for_cell(cls, work_of_adhesion: float, z0: float, compliance: float,
                 softening: float = SOFTENING) -> "SoftenedDugdale":
        """The softened law of a grid whose cell has self-compliance ``compliance``.

        Parameters
        ----------
        work_of_adhesion, z0 : float
            Dugdale's dgamma (J/m^2) and z0 (m).
        compliance : float
            The cell's self-compliance C (m/Pa), e.g.
            :func:`~tribobem.elasticity.bodies.halfspace.halfspace_self_compliance`; 0 for
            rigid bodies (the step law: nothing deforms, the problem is single-valued).
        softening : float
            w / (sigma0 C); must exceed 1 for one equilibrium per node.

        Returns
        -------
        SoftenedDugdale
            ``width = softening x sigma0 x compliance``.
        """
        if not softening > 1.0:
            raise InputError("softening", f"must be > 1 (w > sigma0 C), got {softening!r}")
        law = DugdaleAdhesion(work_of_adhesion, z0)
        return cls(work_of_adhesion, z0, softening * law.sigma0 * float(compliance))

    @property
    def _ramp(self) -> tuple[float, float, float]:
        """(lo, hi, peak): the ramp runs from -peak at g = lo to 0 at g = hi (m, m, Pa)."""
        s0, h0, w = self.sigma0, self.h0, self.width
        if w <= 2.0 * h0:
            return h0 - 0.5 * w, h0 + 0.5 * w, s0
        hi = math.sqrt(2.0 * h0 * w)  # the triangle of the same slope sigma0 / w and work sigma0 h0
        return 0.0, hi, 2.0 * s0 * h0 / hi

    @property
    def range(self) -> float:
        """Range of the law (m): h0 + w/2, beyond which the stress is 0."""
        return self._ramp[1]

    @property
    def floor(self) -> float:
        """Lowest contact pressure (Pa): the law at zero gap, -sigma0 (or the triangle's peak)."""
        return -self._ramp[2]

    def outside_stress(self, gap, xp):
        """-sigma0 below h0 - w/2, 0 above h0 + w/2, linear between (Pa).

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
        lo, hi, peak = self._ramp
        if hi <= lo:  # no ramp: Dugdale's step
            return super().outside_stress(gap, xp)
        return -peak * xp.clip((hi - gap) / (hi - lo), 0.0, 1.0)

    def outside_branch(self, gap, xp):
        """The piece of the law a node is on: 0 the plateau, 1 the ramp, 2 beyond the range.

        The law is continuous in the gap on each piece, so the normal solvers treat a change of
        tension on the ramp as a fixed-point update of the load (:mod:`tribobem.interactions.base`).

        Parameters
        ----------
        gap : ndarray
            Gap (m), any shape.
        xp : module
            Array namespace of ``gap``.

        Returns
        -------
        ndarray of int8
        """
        lo, hi, _ = self._ramp
        return (gap > lo).astype(xp.int8) + (gap >= hi).astype(xp.int8)

    def outside_slope(self, gap, xp):
        """ds/dg (Pa/m): sigma0 / w on the ramp, 0 elsewhere (the solvers' relaxed update).

        Parameters
        ----------
        gap : ndarray
            Gap (m), any shape.
        xp : module
            Array namespace of ``gap``.

        Returns
        -------
        ndarray
        """
        lo, hi, peak = self._ramp
        if hi <= lo:
            return xp.zeros(gap.shape)
        return xp.where((gap > lo) & (gap < hi), peak / (hi - lo), 0.0)

    def adhesive_mask(self, gap, xp):
        """The cohesive zone's nodes among the non-contact ones: g < h0 (the ramp's centre, so
        that the zone's area is the nearest-node estimate of the region inside Dugdale's range)."""
        return gap < self.h0

    def summary_info(self, radius: float | None = None, effective_modulus: float | None = None) -> dict:
        """Dugdale's scalars (:meth:`DugdaleAdhesion.summary_info`) and the softening width (m)."""
        info = super().summary_info(radius, effective_modulus)
        info["softening_width"] = self.width
        return info


def build_dugdale(spec, context=None):
    """The law of an ``[adhesion] model = "dugdale"`` table (its registry builder).

    ``discretisation = "softened"`` gives :class:`SoftenedDugdale` with the width of the problem
    grid's cell (w = 3 sigma0 C); ``"step"`` gives the thesis' step law, :class:`DugdaleAdhesion`;
    ``"auto"`` (the default) the softened law where its ramp is at most :data:`AUTO_MAX_WIDTH` h0
    wide, else the step.  Rigid bodies (no E*) always get the step law.

    Parameters
    ----------
    spec : DugdaleAdhesionSpec
        The validated table.
    context : LawContext, optional
        The problem grid (m) and E* (Pa); without it the step law.

    Returns
    -------
    DugdaleAdhesion or SoftenedDugdale
    """
    step = DugdaleAdhesion(spec.work_of_adhesion, spec.z0)
    how = getattr(spec, "discretisation", "auto")
    if how == "step" or context is None:
        return step
    soft = step.softened(context.grid, context.effective_modulus)
    if how == "auto" and getattr(soft, "width", 0.0) > AUTO_MAX_WIDTH * step.h0:
        return step
    return soft
