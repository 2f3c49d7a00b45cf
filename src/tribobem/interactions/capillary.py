"""Capillary interaction: the stress law outside the contact with water films (Papers B, C).

One law per non-contact node, in this order:

1. Dugdale solid-solid adhesion, ``-sigma0`` where 0 < g < h0, when an adhesion law is given
   (solid-solid wins: h0 is below a water-molecule diameter, no water fits there; Paper B
   L1658, Paper C);
2. else, in an *active meniscus island* (:func:`~tribobem.interactions.menisci.meniscus_islands`),
   the capillary pressure dP_cap (negative, times Paper C's contribution coefficient if used)
   plus the water-filled van der Waals term -A_1w2 / (6 pi g^3) (Paper B Eq. 11);
3. else the air-gap term between the two films (Paper B Eq. 12 with its signs corrected,
   :func:`~tribobem.interactions.van_der_waals.air_gap_stress`), e_a = g - e1 - e2.

The law depends on the POSITION through the island mask and the local films, which the
interaction holds: it is the law of one state of the islands.  The self-consistent solve
(:func:`tribobem.solvers.capillary.solve_capillary`) rebuilds it when the islands change.

Dugdale edge (a regularisation of ours, not in the thesis): where the law just beyond h0 is
MORE tensile than -sigma0 (|dP_cap + water-filled term| > sigma0: low RH, strong Hamaker
constants), the precedence rule makes the stress jump to more tension as the gap opens past
h0.  The discrete problem then has no equilibrium at the zone's edge (the gap of an edge node
is pushed out of the zone by -sigma0 and pulled back by the meniscus) and the normal solver
cycles.  The equilibrium of the set-valued law sits AT g = h0 with an intermediate stress;
the law approaches it with a linear ramp from -sigma0 at h0 to the meniscus law at
h0 (1 + edge_width) on those nodes, which makes it continuous there.  ``edge_width`` = 0.2
(0.06 nm for z0 = 0.3 nm) converged in every case measured (sphere R = 1 um, 128^2 and 256^2,
RH 0.1-0.3, SiO2 and Si Hamaker constants, force and approach control: 26-440 iterations);
0.05 and 0.1 left some of them cycling.  Where the step is monotone (|law| < sigma0 beyond
h0) the thesis' step is kept.

Floor (the lowest pressure a contact node carries, the stress of the law at g = 0+): -sigma0
with Dugdale adhesion; without it the island law at zero gap, dP_cap + the water-filled term at
the cut-off (every contact node seeds an active island).  The law's only discontinuity within
one island state is the Dugdale edge g = h0; :meth:`CapillaryInteraction.outside_branch` tells
the normal solver which side of it each node is on, so it restarts its conjugate directions
only there and treats the smooth van der Waals terms as a fixed-point update.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .dugdale import DugdaleAdhesion
from .van_der_waals import VanDerWaals

__all__ = ["CapillaryInteraction", "ForceSplit"]


@dataclass
class ForceSplit:
    """The normal force of a solved state split by origin (N; negative = tensile).

    Attributes
    ----------
    capillary : float
        dP_cap times the wetted area, F_cap.
    solid_solid : float
        Dugdale zone outside the contact, F_ss.
    water_solid : float
        Water-filled and air-gap van der Waals terms, F_ws.
    contact : float
        Pressure on the contact nodes (compressive part and, with adhesion or capillarity, a
        tensile part down to the floor).
    repulsive : float
        F0+: the compressive part of the contact pressure (Paper D Eq. 16b).
    total : float
        contact + capillary + solid_solid + water_solid.
    wetted_area : float
        Meniscus area outside the contact that carries dP_cap (m^2).
    dugdale_area : float
        Area of the Dugdale zone outside the contact (m^2).
    """

    capillary: float
    solid_solid: float
    water_solid: float
    contact: float
    repulsive: float
    total: float
    wetted_area: float
    dugdale_area: float


@dataclass(eq=False)
class CapillaryInteraction:
    """The stress law outside the contact for one state of the meniscus islands.

    Parameters
    ----------
    active : ndarray of bool, shape (nx, ny)
        Nodes of the active meniscus islands.
    film1, film2 : float or ndarray
        Film thicknesses e1, e2 on bodies 1 and 2 (m, >= 0).
    capillary_pressure : float
        Applied capillary pressure (Pa, <= 0): R_g T ln(RH) / V times the contribution
        coefficient.
    adhesion : DugdaleAdhesion, optional
        Solid-solid Dugdale law; None: no Dugdale zone.
    van_der_waals : VanDerWaals, optional
        Water-solid terms (Hamaker constants, cut-off); None: switched off.
    edge_width : float
        Width of the Dugdale-edge ramp as a fraction of h0 (module docstring), > 0.

    Notes
    -----
    ``outside_stress`` accepts a gap of the grid's shape or its flat (C-order) ravel, the form
    the normal solver passes.
    """

    active: np.ndarray
    film1: object
    film2: object
    capillary_pressure: float
    adhesion: DugdaleAdhesion | None = None
    van_der_waals: VanDerWaals | None = None
    edge_width: float = 0.2
    _cache: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        self.active = np.asarray(self.active, dtype=bool)
        if self.active.ndim != 2:
            raise InputError("active", f"must be a 2-D mask, got shape {self.active.shape}")
        shape = self.active.shape
        films = []
        for name, e in (("film1", self.film1), ("film2", self.film2)):
            a = np.asarray(e, dtype=float)
            try:
                a = np.broadcast_to(a, shape).copy()
            except ValueError:
                raise InputError(name, f"shape {a.shape} does not match the grid {shape}") from None
            if not np.all(np.isfinite(a)) or np.any(a < 0):
                raise InputError(name, "film thickness must be finite and >= 0 m everywhere")
            films.append(a)
        self.film1, self.film2 = films
        dp = float(self.capillary_pressure)
        if not (math.isfinite(dp) and dp <= 0):
            raise InputError("capillary_pressure", f"must be finite and <= 0 Pa (tensile), got {self.capillary_pressure!r}")
        self.capillary_pressure = dp
        if self.adhesion is not None and not isinstance(self.adhesion, DugdaleAdhesion):
            raise InputError("adhesion", f"must be a DugdaleAdhesion or None, got {type(self.adhesion).__name__}")
        if self.van_der_waals is not None and not isinstance(self.van_der_waals, VanDerWaals):
            raise InputError("van_der_waals", f"must be a VanDerWaals or None, got {type(self.van_der_waals).__name__}")
        if not (math.isfinite(self.edge_width) and self.edge_width > 0):
            raise InputError("edge_width", f"must be a finite value > 0 (a fraction of h0), got {self.edge_width!r}")

    # -- the interaction protocol ----------------------------------------------------------

    @property
    def shape(self) -> tuple[int, int]:
        """Grid shape (nx, ny) of the island mask and the films."""
        return self.active.shape

    @property
    def floor(self) -> float:
        """Lowest contact pressure (Pa): -sigma0, or the island law at zero gap without Dugdale."""
        if self.adhesion is not None:
            return -self.adhesion.sigma0
        s = self.capillary_pressure
        if self.van_der_waals is not None:
            s += float(self.van_der_waals.water_filled_stress(0.0))
        return s

    @property
    def range(self) -> float:
        """Range of the Dugdale zone h0 (m); 0 without adhesion (the other terms have no range)."""
        return self.adhesion.h0 if self.adhesion is not None else 0.0

    def _arrays(self, xp):
        key = xp.__name__
        if key not in self._cache:
            self._cache[key] = tuple(xp.asarray(a.ravel()) for a in (self.active, self.film1, self.film2))
        return self._cache[key]

    def _flat(self, gap):
        n = self.active.size
        if gap.size != n:
            raise InputError("gap", f"has {gap.size} nodes, the island mask {n} ({self.shape})")
        return gap.reshape(-1)

    def _beyond(self, g, xp):
        """The law without the Dugdale zone: meniscus (dP_cap + water-filled term) in active
        islands, the air-gap term elsewhere (flat arrays)."""
        active, e1, e2 = self._arrays(xp)
        dp = self.capillary_pressure
        vdw = self.van_der_waals
        if vdw is not None:
            return xp.where(active, dp + vdw.water_filled_stress(g, xp), vdw.air_gap_stress(g, e1, e2, xp))
        return xp.where(active, dp, 0.0)

    def _edge(self, xp):
        """Where the law beyond the Dugdale zone starts more tensile than -sigma0 (flat mask),
        and its value at the end of the edge ramp, h0 (1 + edge_width)."""
        key = ("edge", xp.__name__)
        if key not in self._cache:
            ad = self.adhesion
            s0 = self._beyond(xp.full(self.active.size, ad.h0), xp)
            s1 = self._beyond(xp.full(self.active.size, ad.h0 * (1.0 + self.edge_width)), xp)
            self._cache[key] = (s0 < -ad.sigma0, s1)
        return self._cache[key]

    def outside_stress(self, gap, xp=np):
        """Traction (Pa, negative = tensile) on non-contact nodes with gap ``gap`` (m).

        Parameters
        ----------
        gap : ndarray
            Gap of every node (m), grid-shaped or its flat C-order ravel (the law depends on
            the position, so all nodes are needed).
        xp : module
            Array namespace of ``gap`` (``numpy`` or ``cupy``).

        Returns
        -------
        ndarray
            Stress (Pa), shape of ``gap``.

        Raises
        ------
        InputError
            ``gap`` does not have the island mask's number of nodes.
        """
        g = self._flat(xp.asarray(gap, dtype=float))
        s = self._beyond(g, xp)
        ad = self.adhesion
        if ad is not None:
            ramped, s1 = self._edge(xp)
            zone = g < ad.h0
            s = xp.where(zone, -ad.sigma0, s)
            if bool(ramped.any()):
                w = ad.h0 * self.edge_width
                on_ramp = ramped & ~zone & (g < ad.h0 + w)
                s = xp.where(on_ramp, -ad.sigma0 + (g - ad.h0) * ((s1 + ad.sigma0) / w), s)
        return s.reshape(gap.shape)

    def outside_branch(self, gap, xp=np):
        """Which piece of the law a node is on (True: Dugdale zone behind a step).

        The law is continuous in g within a piece, so the normal solver needs no restart while
        no node changes piece.  Nodes with an edge ramp have a continuous law: one piece.

        Parameters
        ----------
        gap : ndarray
            Gap of every node (m), grid-shaped or its flat C-order ravel.
        xp : module
            Array namespace of ``gap`` (``numpy`` or ``cupy``).

        Returns
        -------
        ndarray of bool
            Shape of ``gap``; all False without adhesion.
        """
        g = self._flat(xp.asarray(gap, dtype=float))
        if self.adhesion is None:
            return xp.zeros(gap.shape, dtype=bool)
        ramped, _ = self._edge(xp)
        return ((g < self.adhesion.h0) & ~ramped).reshape(gap.shape)

    # -- post-processing -----------------------------------------------------------------

    def split_force(self, pressure, gap, contact, cell_area: float) -> ForceSplit:
        """Split the force of a solved state into capillary, solid-solid and water-solid parts.

        Parameters
        ----------
        pressure, gap : ndarray
            Solved pressure (Pa) and gap (m), grid-shaped.
        contact : ndarray of bool
            Contact nodes.
        cell_area : float
            Area of one cell (m^2).

        Returns
        -------
        ForceSplit
            The parts sum to the total force of ``pressure``; on the meniscus nodes the
            capillary part is dP_cap and the rest of their pressure is water-solid.
        """
        p = np.asarray(pressure, dtype=float)
        g = np.asarray(gap, dtype=float)
        c = np.asarray(contact, dtype=bool)
        if p.shape != self.shape or g.shape != self.shape or c.shape != self.shape:
            raise InputError("pressure", f"pressure, gap and contact must have the grid's shape {self.shape}")
        free = ~c
        dug = free & (g < self.adhesion.h0) if self.adhesion is not None else np.zeros(self.shape, bool)
        wet = free & ~dug & self.active
        rest = free & ~dug
        n_wet = int(np.count_nonzero(wet))
        capillary = self.capillary_pressure * n_wet * cell_area
        solid_solid = float(p[dug].sum()) * cell_area
        # Water-solid: the meniscus nodes' pressure beyond dP_cap, and every other free node's.
        water_solid = (float((p[wet] - self.capillary_pressure).sum()) + float(p[rest & ~wet].sum())) * cell_area
        contact_force = float(p[c].sum()) * cell_area
        repulsive = float(p[c & (p > 0)].sum()) * cell_area
        return ForceSplit(capillary=capillary, solid_solid=solid_solid, water_solid=water_solid,
                          contact=contact_force, repulsive=repulsive,
                          total=contact_force + capillary + solid_solid + water_solid,
                          wetted_area=n_wet * cell_area, dugdale_area=int(np.count_nonzero(dug)) * cell_area)

    def __repr__(self) -> str:
        return (f"CapillaryInteraction(dP_cap={self.capillary_pressure:.4g} Pa, "
                f"active={int(np.count_nonzero(self.active))}/{self.active.size} nodes, "
                f"adhesion={self.adhesion!r}, van_der_waals={self.van_der_waals!r})")
