"""Self-consistent normal contact with capillary menisci and water films (Paper B Fig. 6).

The meniscus islands depend on the gap and the gap on the pressure the islands carry.
:func:`solve_capillary` iterates on the set of ACTIVE islands (an outer fixed point):

1. an estimate of the gap (the previous state, or the undeformed bodies) gives the islands
   (:func:`~tribobem.interactions.menisci.meniscus_islands`);
2. the normal solver (:func:`~tribobem.solvers.normal.solve_normal`) solves the contact with the
   stress law of those islands (:class:`~tribobem.interactions.capillary.CapillaryInteraction`:
   Dugdale, else capillary pressure and water-filled van der Waals in the islands, else the
   air-gap van der Waals term), warm-started from the previous outer iteration; its force
   balance subtracts every prescribed stress;
3. the solved gap gives new islands; stop when the active mask repeats.  A mask seen before
   but not the last one is a CYCLE: the solve stops with a ConvergenceWarning, ``converged =
   False`` and a message (as does reaching ``max_outer``).

Rigid bodies: with ``operator=None`` (and the ``grid``) both bodies are rigid; only a
prescribed approach is meaningful.  The gap is h - delta, nothing deforms, the islands are
found once, and the stresses outside the contact follow from the law.  The reaction of the
contact nodes (g <= 0) is then indeterminate: the contact and total forces are NaN when a node
touches (the capillary, solid-solid and water-solid forces are exact), and the total force is the
outside force when none does.  This is Paper B 4.1's check (rigid sphere on a flat): it needs
no elastic solve.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from ..errors import ConvergenceError, ConvergenceWarning, InputError
from ..grid import Grid
from ..interactions.base import NoInteraction
from ..interactions.hardness import HardnessCap, unwrap_cap
from ..interactions.capillary import CapillaryInteraction, ForceSplit
from ..interactions.dugdale import DugdaleAdhesion
from ..interactions.menisci import CRITICAL_DISTANCE, Islands, meniscus_islands
from ..interactions.van_der_waals import DEFAULT_CUTOFF, HAMAKER_SIO2, HAMAKER_WATER, VanDerWaals
from ..results import CapillaryResult, NormalResult
from .normal import solve_normal

__all__ = ["CapillaryModel", "solve_capillary", "island_fixed_point"]


@dataclass(frozen=True)
class CapillaryModel:
    """The capillary model of one RH, for solvers that call the normal solve themselves.

    A plain stress law (:class:`~tribobem.interactions.base.Interaction`) depends on the local
    gap only; the capillary law also depends on the meniscus islands, which depend on the whole
    gap.  The coupling loop (:func:`~tribobem.solvers.coupling.solve_coupled`) therefore calls
    :meth:`solve_state` (the island fixed point of :func:`solve_capillary`) where it calls the
    normal solver for a plain law: the islands are recomputed at every pass of every step.

    Attributes
    ----------
    film1, film2 : ndarray
        Film thicknesses of bodies 1 and 2 on the grid (m), each on its body's undeformed
        topography.
    options : dict
        The remaining keyword arguments of :func:`solve_capillary` (Kelvin radius in m,
        capillary pressure in Pa, contribution, adhesion, Hamaker constants in J, contact angles
        in rad, critical distance and cutoff in m, periodicity, ...).
    grid : Grid
        The grid of the films (for :meth:`moved`).
    offset : (float, float)
        Rigid displacement of body 2's film from its initial place (m).
    film2_origin : ndarray or None
        Body 2's film at zero offset (None: ``film2`` is); every :meth:`moved` starts from it, so
        interpolation errors do not accumulate along a path.
    """

    film1: np.ndarray
    film2: np.ndarray
    options: dict
    grid: Grid
    offset: tuple = (0.0, 0.0)
    film2_origin: np.ndarray | None = field(default=None, repr=False)

    #: Solvers recognise a self-consistent law by this attribute (see solvers.coupling).
    self_consistent = True

    @property
    def h0(self) -> float:
        """Range of the Dugdale law (m) the model contains; 0 without one."""
        adh = self.options.get("adhesion")
        return float(adh.h0) if adh is not None and hasattr(adh, "h0") else 0.0

    def solve_state(self, operator, gap, *, tol: float, max_iterations: int, initial=None,
                    normal_force: float | None = None, approach: float | None = None) -> CapillaryResult:
        """The self-consistent capillary state on ``gap`` (:func:`solve_capillary`, not strict: a
        cycling island fixed point comes back with ``converged=False``).

        Parameters
        ----------
        operator : ConvolutionOperator
            The elastic operator (3x3 in the coupling loop: its z block is used).
        gap : array_like
            The gap (m), with the shear-induced normal displacement in it.
        tol, max_iterations : float, int
            Normal solver settings.
        initial : CapillaryResult or NormalResult, optional
            Warm start: its pressure and its gap (the first islands).
        normal_force, approach : float
            Exactly one: N or m.

        Returns
        -------
        CapillaryResult
        """
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            return solve_capillary(operator, gap, normal_force=normal_force, approach=approach, film1=self.film1,
                                   film2=self.film2, tol=tol, max_iterations=max_iterations, initial=initial,
                                   **self.options)

    @property
    def windowable(self) -> bool:
        """Whether a step may be solved on a window of a free-boundary grid: without the van der
        Waals terms every stress outside the contact has a finite support (the active menisci
        and the Dugdale zone), which :meth:`stress_support` tells; with them the air-gap term
        reaches every node."""
        return not bool(self.options.get("van_der_waals", True))

    def restricted(self, slicer, grid: Grid) -> "CapillaryModel":
        """The model on a window of the grid (free boundary): films sliced by ``slicer``.

        Parameters
        ----------
        slicer : callable
            Maps a grid-shaped array to the window's part.
        grid : Grid
            The window's grid.

        Returns
        -------
        CapillaryModel
        """
        return replace(self, film1=slicer(self.film1), film2=slicer(self.film2), grid=grid,
                       options={**self.options, "periodic": False}, film2_origin=None)

    def islands_of(self, gap, contact) -> Islands:
        """The meniscus islands of a whole-grid state (gap in m, contact mask).

        Parameters
        ----------
        gap : ndarray
            Gap (m) on this model's grid.
        contact : ndarray of bool
            Contact nodes.

        Returns
        -------
        Islands
        """
        o = self.options
        return meniscus_islands(np.maximum(gap, 0.0), self.film1, self.film2, o["kelvin_radius"], contact,
                                contact_angles=o.get("contact_angles", (0.0, 0.0)),
                                critical_distance=o.get("critical_distance", CRITICAL_DISTANCE),
                                periodic=bool(o.get("periodic", self.grid.periodic)),
                                connectivity=o.get("connectivity", 4))

    def law(self, active) -> CapillaryInteraction:
        """The stress law of an island state on this model's grid, as :func:`solve_capillary`
        builds it (the applied capillary pressure includes the contribution coefficient).

        Parameters
        ----------
        active : ndarray of bool
            Active meniscus nodes (grid-shaped).

        Returns
        -------
        CapillaryInteraction
        """
        o = self.options
        adhesion = o.get("adhesion")
        if isinstance(adhesion, NoInteraction):
            adhesion = None
        vdw = None
        if o.get("van_der_waals", True):
            cutoff = o.get("cutoff")
            if cutoff is None:
                cutoff = adhesion.h0 if adhesion is not None else DEFAULT_CUTOFF
            h1, h2 = _hamaker_pair(o.get("hamaker", (HAMAKER_SIO2, HAMAKER_SIO2)))
            vdw = VanDerWaals(h1, h2, o.get("water_hamaker", HAMAKER_WATER), cutoff)
        dp_eff = float(o.get("contribution", 1.0)) * float(o["capillary_pressure"])
        return CapillaryInteraction(np.asarray(active, dtype=bool), np.broadcast_to(self.film1, self.grid.shape),
                                    np.broadcast_to(self.film2, self.grid.shape), dp_eff, adhesion=adhesion,
                                    van_der_waals=vdw, edge_width=o.get("edge_width", 0.2))

    def stress_support(self, gap, contact) -> tuple[np.ndarray, Islands]:
        """Nodes that carry a prescribed stress in a whole-grid state (active menisci, the
        Dugdale zone 0 < g < h0), and the islands.

        Parameters
        ----------
        gap : ndarray
            Gap (m).
        contact : ndarray of bool
            Contact nodes.

        Returns
        -------
        (ndarray of bool, Islands)
        """
        isl = self.islands_of(gap, contact)
        support = np.asarray(isl.active, dtype=bool).copy()
        if self.h0 > 0:
            support |= (gap > 0) & (gap < self.h0)
        return support, isl

    def moved(self, offset) -> "CapillaryModel":
        """The model with body 2 (the counterface) moved rigidly by ``offset`` (m) from its
        initial place: its film moves with it (gross sliding), body 1's stays.

        Parameters
        ----------
        offset : (float, float)
            Total rigid displacement of body 2 (m).

        Returns
        -------
        CapillaryModel
        """
        origin = self.film2 if self.film2_origin is None else self.film2_origin
        film2 = np.maximum(self.grid.translate(origin, offset), 0.0)  # cubic interpolation may undershoot 0
        return replace(self, film2=film2, offset=(float(offset[0]), float(offset[1])), film2_origin=origin)


def island_fixed_point(islands: Islands, step: Callable[[Islands], tuple[object, Islands]], max_outer: int):
    """Iterate ``islands -> step(islands) = (state, new islands)`` until the active mask repeats.

    Returns ``(state, islands_used, outer_iterations, status, history)`` with ``status`` one of
    ``"converged"``, ``"cycle"`` (a mask seen earlier, not the last one, came back) and
    ``"max_outer"``; ``islands_used`` are the islands whose law produced ``state``.

    A cycle stops the loop rather than iterating on: the active mask takes a finite set of
    values, so a repeat that is not the last mask means the iteration would oscillate forever.

    Parameters
    ----------
    islands : Islands
        The starting islands (water menisci and their active mask).
    step : callable
        ``step(islands) -> (state, new_islands)``: one solve with the islands' stress law and
        the islands it implies.
    max_outer : int
        Most outer iterations (solves).

    Returns
    -------
    tuple
        ``(state, islands_used, outer_iterations, status, history)``; ``history`` is the count
        of active nodes after each iteration.
    """
    seen = {islands.key: 0}
    history = []
    state = None
    for k in range(1, max_outer + 1):
        state, new = step(islands)
        history.append(int(np.count_nonzero(new.active)))
        if new.key == islands.key:
            return state, new, k, "converged", history
        if new.key in seen:
            return state, islands, k, "cycle", history
        seen[new.key] = k
        islands = new
    return state, islands, max_outer, "max_outer", history


def _film(e, shape, name):
    a = np.asarray(e, dtype=float)
    try:
        return np.broadcast_to(a, shape)
    except ValueError:
        raise InputError(name, f"shape {a.shape} does not match the gap {shape}") from None


def _hamaker_pair(hamaker):
    try:
        h1, h2 = (float(v) for v in hamaker)
    except (TypeError, ValueError):
        raise InputError("hamaker", f"give the two bodies' own Hamaker constants (A1, A2) in J, got {hamaker!r}") from None
    return h1, h2


def solve_capillary(operator, gap, *, normal_force: float | None = None, approach: float | None = None,
                    film1, film2, kelvin_radius: float, capillary_pressure: float,
                    adhesion: DugdaleAdhesion | None = None, hamaker=(HAMAKER_SIO2, HAMAKER_SIO2),
                    water_hamaker: float = HAMAKER_WATER, van_der_waals: bool = True,
                    contact_angles=(0.0, 0.0), critical_distance: float = CRITICAL_DISTANCE,
                    cutoff: float | None = None, contribution: float = 1.0, periodic: bool | None = None,
                    connectivity: int = 4, grid: Grid | None = None, tol: float = 1e-10, max_outer: int = 50,
                    max_iterations: int = 10000, initial=None, edge_width: float = 0.2,
                    normal_method: str = "polonsky_keer", strict: bool = False) -> CapillaryResult:
    """Normal contact with meniscus islands, self-consistent in the islands (Paper B Fig. 6).

    Parameters
    ----------
    operator : ConvolutionOperator or None
        Elastic operator; None: both bodies rigid (give ``grid`` and ``approach``).
    gap : array_like
        Undeformed gap h (m), grid-shaped.
    normal_force, approach : float
        Exactly one: the applied normal force (N, may be negative: pulling) or the rigid
        approach (m).
    film1, film2 : float or array_like
        Film thicknesses on bodies 1 and 2 (m), e.g. from :mod:`tribobem.interactions.films`.
    kelvin_radius : float
        r_k (m, < 0; ``-inf`` at RH = 1).
    capillary_pressure : float
        dP_cap = R_g T ln(RH)/V (Pa, <= 0), before the contribution coefficient.
    adhesion : DugdaleAdhesion, optional
        Solid-solid Dugdale law (wins below h0).
    hamaker : (float, float)
        Own Hamaker constants of bodies 1 and 2 in vacuum (J).
    water_hamaker : float
        Water's own constant (J).
    van_der_waals : bool
        Water-solid terms on (water-filled in the menisci, air-gap elsewhere) or off.
    contact_angles : (float, float)
        Radians.
    critical_distance : float
        d_cr (m).
    cutoff : float, optional
        Short-range cut-off of the 1/D^3 terms (m); default h0 with adhesion, else
        :data:`~tribobem.interactions.van_der_waals.DEFAULT_CUTOFF`.
    contribution : float
        Factor in [0, 1] on the capillary pressure (Paper C's coefficient,
        :func:`~tribobem.interactions.menisci.contribution_coefficient`).
    periodic : bool, optional
        Islands wrap around; default: the operator's (grid's) periodicity.
    connectivity : {4, 8}
    grid : Grid, optional
        Needed for rigid bodies (``operator=None``).
    tol, max_iterations : float, int
        Normal-solver tolerance and iteration limit.
    max_outer : int
        Outer (island) iterations at most.
    initial : CapillaryResult or NormalResult, optional
        Warm start (e.g. the previous RH or approach step): its pressure starts the first
        normal solve and its displacement the first gap estimate.
    edge_width : float
        Width of the Dugdale-edge ramp as a fraction of h0 (see
        :class:`~tribobem.interactions.capillary.CapillaryInteraction`).
    normal_method : {"polonsky_keer", "normcg"}
        The solver of each normal solve of the island fixed point
        (:func:`~tribobem.solvers.normal.solve_normal`'s ``method``).  Both reach equilibria of
        the same discrete problem; with a Dugdale zone they may settle on different ones (the
        adhesive problem is not unique), so forces differ at the level of the grid.
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning.

    Returns
    -------
    CapillaryResult
    """
    t0 = time.perf_counter()
    if (normal_force is None) == (approach is None):
        raise InputError("load", "give exactly one of normal_force or approach")
    rigid = operator is None
    if rigid:
        if grid is None:
            raise InputError("grid", "two rigid bodies (operator=None) need the grid")
        if approach is None:
            raise InputError("load", "two rigid bodies: the normal force does not fix the state; give the approach")
    else:
        grid = operator.grid
    h = np.asarray(gap, dtype=float)
    if h.shape != grid.shape:
        raise InputError("gap", f"shape {h.shape} does not match the grid {grid.shape}")
    if not np.all(np.isfinite(h)):
        raise InputError("gap", "contains NaN or infinite values")
    e1, e2 = _film(film1, h.shape, "film1"), _film(film2, h.shape, "film2")
    rk, dp = float(kelvin_radius), float(capillary_pressure)
    if not (math.isfinite(dp) and dp <= 0):
        raise InputError("capillary_pressure", f"must be finite and <= 0 Pa, got {capillary_pressure!r}")
    if (rk == -math.inf) != (dp == 0.0):
        raise InputError("capillary_pressure", "r_k = -inf (RH = 1) goes with dP_cap = 0 and only with it")
    c = float(contribution)
    if not (0.0 <= c <= 1.0):
        raise InputError("solve_capillary.contribution", f"coefficient must be in [0, 1], got {contribution!r}")
    adhesion, cap = unwrap_cap(adhesion)  # a hardness cap goes around the capillary law of each step
    if isinstance(adhesion, NoInteraction):
        adhesion = None
    if adhesion is not None and not isinstance(adhesion, DugdaleAdhesion):
        raise InputError("adhesion", f"must be a DugdaleAdhesion or None, got {type(adhesion).__name__}")
    if max_outer < 1:
        raise InputError("max_outer", f"must be >= 1, got {max_outer!r}")
    if cutoff is None:
        cutoff = adhesion.h0 if adhesion is not None else DEFAULT_CUTOFF
    h1, h2 = _hamaker_pair(hamaker)
    vdw = VanDerWaals(h1, h2, water_hamaker, cutoff) if van_der_waals else None
    periodic = grid.periodic if periodic is None else bool(periodic)
    dp_eff = c * dp
    island_kw = dict(contact_angles=contact_angles, critical_distance=critical_distance, periodic=periodic,
                     connectivity=connectivity)

    def islands_of(g, contact):
        return meniscus_islands(g, e1, e2, rk, contact, **island_kw)

    def law(isl):
        return CapillaryInteraction(isl.active, e1, e2, dp_eff, adhesion=adhesion, van_der_waals=vdw,
                                    edge_width=edge_width)

    if rigid:
        return _rigid(grid, h, float(approach), islands_of, law, rk, dp_eff, t0)

    # First gap estimate: the warm start moved to this load, or the undeformed bodies.
    warm = initial.normal if isinstance(initial, CapillaryResult) else initial
    if warm is not None and not isinstance(warm, NormalResult):
        raise InputError("initial", f"must be a CapillaryResult or NormalResult, got {type(initial).__name__}")
    if warm is not None:
        if approach is not None:
            g_est = h + warm.displacement - float(approach)
            contact_est = g_est <= 0
        else:
            g_est, contact_est = warm.gap, warm.contact
    else:
        g_est = h - (float(approach) if approach is not None else float(h.min()))
        contact_est = g_est <= 0
    islands = islands_of(np.maximum(g_est, 0.0), contact_est)
    load = {"force": normal_force} if normal_force is not None else {"approach": approach}
    box = {"warm": warm}
    base = cap.plastic if cap is not None else None

    def step(isl):
        inter = law(isl)
        # with a hardness cap every outer iteration loads from the plastic state before the
        # solve (the islands change the load, not the history); the body keeps the last one's
        capped = HardnessCap(cap.hardness, inter, plastic=base) if cap is not None else inter
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_normal(operator, h, interaction=capped, tol=tol, max_iterations=max_iterations,
                               initial_pressure=box["warm"], method=normal_method, **load)
        if cap is not None:
            cap.plastic = capped.plastic
        box["warm"] = res
        return (res, inter), islands_of(res.gap, res.contact)

    (res, inter), used, outer, status, history = island_fixed_point(islands, step, max_outer)
    split = inter.split_force(res.pressure, res.gap, res.contact, grid.cell_area)
    if status == "converged":
        converged = bool(res.converged)
        message = (f"islands self-consistent after {outer} outer iterations; " + res.message if converged
                   else f"islands self-consistent after {outer} outer iterations but the last normal solve did not "
                        f"converge: {res.message}")
    elif status == "cycle":
        converged = False
        message = (f"the island fixed point cycles (an active-island mask of an earlier outer iteration came back "
                   f"at outer iteration {outer}); the state is that of the last solve")
    else:
        converged = False
        message = f"the islands did not settle in {max_outer} outer iterations (max_outer); the state is that of the last solve"
    if not converged:
        if strict:
            raise ConvergenceError(message)
        warnings.warn(message, ConvergenceWarning, stacklevel=2)
    return _result(res, used, split, outer, converged, message, rk, dp_eff, inter, history, t0)


def _result(res, isl, split: ForceSplit, outer, converged, message, rk, dp_eff, inter, history, t0):
    return CapillaryResult(
        normal=res, islands=isl, capillary_force=split.capillary, solid_solid_force=split.solid_solid,
        water_solid_force=split.water_solid, contact_force=split.contact, repulsive_force=split.repulsive,
        total_force=split.total, contact_area=res.contact_area, wetted_area=split.wetted_area,
        island_count=isl.active_count, outer_iterations=outer, converged=converged, message=message,
        kelvin_radius=rk, capillary_pressure=dp_eff, interaction=inter, history=history,
        time=time.perf_counter() - t0)


def _rigid(grid, h, approach, islands_of, law, rk, dp_eff, t0):
    """Two rigid bodies at a prescribed approach (module docstring)."""
    g = h - approach
    contact = g <= 0
    gap = np.maximum(g, 0.0)
    isl = islands_of(gap, contact)
    inter = law(isl)
    p = np.where(contact, 0.0, inter.outside_stress(gap))
    split = inter.split_force(p, gap, contact, grid.cell_area)
    touching = bool(contact.any())
    nan = math.nan
    if touching:
        split.contact = split.repulsive = split.total = nan
        message = ("rigid bodies at a prescribed approach: the contact reaction is indeterminate (contact and "
                   "total forces NaN); the capillary, solid-solid and water-solid forces are exact")
    else:
        message = "rigid bodies at a prescribed approach, not touching: every stress follows from the law"
    normal = NormalResult(
        grid=grid, pressure=p, gap=gap, displacement=np.zeros_like(h), contact=contact,
        adhesive=(~contact) & (p < 0), force=split.total, approach=approach, iterations=0,
        residual_history=np.zeros(0), converged=True, time=time.perf_counter() - t0, message=message,
        control="displacement", info={"rigid": True, "interaction": repr(inter), "operator": "none (rigid bodies)"})
    return _result(normal, isl, split, 1, True, message, rk, dp_eff, inter,
                   [int(np.count_nonzero(isl.active))], t0)
