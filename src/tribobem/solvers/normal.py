"""Normal contact: Polonsky-Keer constrained conjugate gradients, extended to Dugdale
adhesion as in Paper A (steps 1-6), with explicit masks instead of the "-1000 sigma0" trick.

The problem (Paper A Eq. 13; SPEC 4-5): find the pressure p on the grid such that

* p > floor on contact nodes (g = 0), where floor = -sigma0 with adhesion, 0 without;
* p = s(g) on non-contact nodes, where s is the interaction's outside stress
  (-sigma0 for 0 < g < h0 and 0 beyond, for Dugdale; 0 without adhesion);
* the total force equals F0 (force control) or the approach equals delta (displacement
  control),

with g = h + K p - delta.  The contact nodes are the CG unknowns; the non-contact nodes
follow the gap.  Each iteration costs two convolutions (K p and K t).

Differences from the printed algorithm (documented in the README):

* the force balance (Paper A Eq. 22) also subtracts the force carried by the cohesive zone
  *outside* the contact; the printed Eq. 22a omits it, which makes the total force differ
  from F0 by the adhesive force of that zone;
* nodes are classified with boolean masks; a non-contact node whose gap becomes negative
  (overlap) enters the contact with p = s(g) - tau g (Eq. 21 applied to its stress);
* convergence is measured by the relative change of the pressure,
  sum |p - p_old| / sum |p| (Eq. 23 made relative), and the solver reports non-convergence
  with a warning, the residual history and ``converged=False``.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..errors import ConvergenceError, ConvergenceWarning, InputError
from ..interactions.base import NoInteraction
from ..results import NormalResult


def _self_compliance(op: ConvolutionOperator) -> float:
    """Displacement (m/Pa) of a cell under its own unit pressure (diagonal of K)."""
    cache = op.__dict__.setdefault("_self_compliance", None)
    if cache is None:
        xp = op.xp
        e = xp.zeros(op.grid.shape)
        e[0, 0] = 1.0
        cache = float(op.backend.to_numpy(op.apply(e))[0, 0])
        op.__dict__["_self_compliance"] = cache
    return cache


def solve_normal(
    operator: ConvolutionOperator,
    gap,
    *,
    force: float | None = None,
    approach: float | None = None,
    interaction=None,
    tol: float = 1e-10,
    max_iterations: int = 10000,
    initial_pressure=None,
    initial_contact=None,
    strict: bool = False,
) -> NormalResult:
    """Solve a normal contact problem, with or without adhesion.

    Parameters
    ----------
    operator : ConvolutionOperator
        Elastic operator (its normal block is used).
    gap : array_like
        Initial (undeformed) gap h(x, y) in m, shape ``grid.shape``; its minimum is
        usually 0 (first point of contact).
    force : float, optional
        Total normal force F0 in N (force control).  Positive = compressive; it may be
        negative (pulling) with adhesion.
    approach : float, optional
        Rigid approach delta in m (displacement control).  Give exactly one of ``force``
        and ``approach``.
    interaction : Interaction, optional
        Stress law outside contact, e.g. :class:`~tribobem.interactions.DugdaleAdhesion`.
        None: non-adhesive contact.
    tol : float
        Tolerance on the relative pressure change per iteration.
    max_iterations : int
    initial_pressure : array_like or NormalResult, optional
        Warm start (Pa), e.g. the pressure of the previous load step (a
        :class:`NormalResult` gives both its pressure and its contact mask).
    initial_contact : array_like of bool, optional
        Contact mask that goes with ``initial_pressure``; by default the nodes with
        p > floor (with adhesion, pass it: a node at p = 0 outside the cohesive zone is
        otherwise taken as in contact for the first iteration).
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning when the solver
        does not converge.

    Returns
    -------
    NormalResult
    """
    t_start = time.perf_counter()
    op = operator.normal
    xp, grid = op.xp, op.grid
    inter = interaction if interaction is not None else NoInteraction()
    floor = float(inter.floor)

    if (force is None) == (approach is None):
        raise InputError("load", "give exactly one of force (force control) or approach (displacement control)")
    h = xp.asarray(gap, dtype=float)
    if h.shape != grid.shape:
        raise InputError("gap", f"shape {tuple(h.shape)} does not match the grid {grid.shape}")
    if not bool(xp.all(xp.isfinite(h))):
        bad = int(xp.count_nonzero(~xp.isfinite(h)))
        raise InputError("gap", f"{bad} points are NaN or infinite; fill or crop the topography first")
    if not (tol > 0 and math.isfinite(tol)):
        raise InputError("solver.tolerance", f"must be a finite value > 0, got {tol!r}")
    if max_iterations < 1:
        raise InputError("solver.max_iterations", f"must be >= 1, got {max_iterations!r}")

    cell = grid.cell_area
    force_control = force is not None
    if force_control:
        if not math.isfinite(force):
            raise InputError("load.force", f"must be finite, got {force!r}")
        if floor == 0.0 and force <= 0.0:
            raise InputError("load.force", f"must be > 0 N without adhesion, got {force!r}")
        target = force / cell  # target sum of p
        h_eff = h
    else:
        if not math.isfinite(approach):
            raise InputError("load.approach", f"must be finite, got {approach!r}")
        h_eff = h - approach

    # Step 1: initial pressure.
    if isinstance(initial_pressure, NormalResult):
        initial_contact = initial_pressure.contact if initial_contact is None else initial_contact
        initial_pressure = initial_pressure.pressure
    if initial_pressure is not None:
        p = xp.array(initial_pressure, dtype=float)
        if p.shape != grid.shape:
            raise InputError("initial_pressure", f"shape {tuple(p.shape)} does not match the grid {grid.shape}")
        p = xp.maximum(p, floor)
    elif force_control:
        p = xp.full(grid.shape, target / h.size)
    else:
        p = xp.zeros(grid.shape)
    if initial_contact is not None:
        contact = xp.asarray(initial_contact, dtype=bool) & (p > floor)
    elif force_control or initial_pressure is not None:
        contact = p > floor
    else:
        contact = xp.zeros(grid.shape, dtype=bool)

    tau0 = 1.0 / _self_compliance(op)
    t = xp.zeros(grid.shape)
    G_old = 1.0
    conjugate = False
    history: list[float] = []
    converged = False
    message = ""
    tau = tau0
    delta = float("nan") if force_control else float(approach)

    for it in range(1, max_iterations + 1):
        # Step 2: gap from the current pressure; under force control the approach is the
        # mean of h + u over the contact nodes (Polonsky-Keer), so g has zero mean there.
        g = op.apply(p)
        g += h_eff
        n_c = int(xp.count_nonzero(contact))
        if force_control:
            if n_c == 0:
                message = "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"
                break
            delta = float(xp.sum(xp.where(contact, g, 0.0))) / n_c
            g -= delta

        # Step 3: conjugate direction on the contact nodes.
        g_c = xp.where(contact, g, 0.0)
        G = float(xp.vdot(g_c, g_c))
        if conjugate and G_old > 0:
            t = xp.where(contact, g_c + (G / G_old) * t, 0.0)
        else:
            t = g_c
        G_old = G

        # Step 4: step length.
        if n_c > 0 and G > 0:
            r = op.apply(t)
            rt = float(xp.vdot(r, t))
            if force_control:
                rt -= float(xp.sum(xp.where(contact, r, 0.0))) / n_c * float(xp.sum(t))
            tau = float(xp.vdot(g_c, t)) / rt if rt > 0 else tau0

        # Step 5: update, project, move nodes between the sets.
        p_new = p - tau * t
        stays = contact & (p_new > floor)
        outside = inter.outside_stress(g, xp)
        overlap = ~stays & (g < 0)
        p_new = xp.where(stays, p_new, outside)
        p_new = xp.where(overlap, outside - tau * g, p_new)
        new_contact = stays | overlap
        conjugate = not bool(xp.any(overlap))

        # Step 6: force balance, scaling p - floor on the contact nodes.
        if force_control:
            n_new = int(xp.count_nonzero(new_contact))
            if n_new == 0:
                message = "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"
                p, contact = p_new, new_contact
                break
            fixed = float(xp.sum(xp.where(new_contact, 0.0, p_new)))
            free = float(xp.sum(xp.where(new_contact, p_new - floor, 0.0)))
            scale = (target - fixed - floor * n_new) / free if free > 0 else -1.0
            if scale <= 0:
                message = ("the contact cannot carry the requested force: the load is beyond "
                           "pull-off (no equilibrium under force control)")
                p, contact = p_new, new_contact
                break
            p_new = xp.where(new_contact, scale * (p_new - floor) + floor, p_new)

        err = float(xp.sum(xp.abs(p_new - p)))
        norm = float(xp.sum(xp.abs(p_new)))
        err = err / norm if norm > 0 else err
        history.append(err)
        p, contact = p_new, new_contact
        if err < tol:
            converged = True
            message = f"converged in {it} iterations"
            break
    else:
        message = f"not converged after {max_iterations} iterations (residual {history[-1]:.3e}, tolerance {tol:.1e})"

    # Final fields, consistent with the returned pressure.
    u = op.apply(p)
    g = u + h
    n_c = int(xp.count_nonzero(contact))
    if force_control:
        delta = float(xp.sum(xp.where(contact, g, 0.0))) / n_c if n_c else float("nan")
    g = g - delta if n_c or not force_control else g - float(xp.min(g))
    gap_field = xp.where(contact, 0.0, xp.maximum(g, 0.0))
    penetration = float(-xp.min(xp.where(contact, 0.0, g))) if n_c < g.size else 0.0
    adhesive = (~contact) & (p < 0)
    be = op.backend
    total = float(xp.sum(p)) * cell
    if not converged:
        if strict:
            raise ConvergenceError(message)
        warnings.warn(message, ConvergenceWarning, stacklevel=2)
    return NormalResult(
        grid=grid,
        pressure=be.to_numpy(p),
        gap=be.to_numpy(gap_field),
        displacement=be.to_numpy(u),
        contact=be.to_numpy(contact),
        adhesive=be.to_numpy(adhesive),
        force=total,
        approach=delta,
        iterations=len(history),
        residual_history=np.asarray(history),
        converged=converged,
        time=time.perf_counter() - t_start,
        message=message,
        control="force" if force_control else "displacement",
        info={"max_penetration": max(penetration, 0.0), "interaction": repr(inter), "operator": op.kind},
    )
