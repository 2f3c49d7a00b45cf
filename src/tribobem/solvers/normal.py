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
    refresh: int = 50,
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
    refresh : int
        Recompute the displacement exactly at least every ``refresh`` iterations (between
        refreshes it is updated incrementally while the contact set does not change).

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
        target = None
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

    state = _CGState(op, inter, floor, h_eff, p, contact, force_control, target, refresh)
    history: list[float] = []
    converged = False
    message = ""
    for it in range(1, max_iterations + 1):
        status = state.iterate()
        if status is not None:
            message = status
            break
        history.append(state.error)
        if state.error < tol:
            if state.started_exact:
                converged = True
                message = f"converged in {it} iterations"
                break
            # The displacement was updated incrementally: confirm with an exact one.
            state.make_exact()
    else:
        message = f"not converged after {max_iterations} iterations (residual {history[-1]:.3e}, tolerance {tol:.1e})"
    p, contact = state.full_pressure(), state.cmask
    delta = state.delta if force_control else float(approach)

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


class _CGState:
    """Working state of the constrained CG (Paper A steps 2-6) on the compressed contact set.

    ``idx`` are the flat indices of the contact nodes; ``p_c`` and ``t_c`` the pressure and
    search direction there; ``p_out`` the stress of the non-contact nodes (full array, zero
    on contact nodes; ``None`` when the interaction has no outside stress).
    """

    def __init__(self, op, inter, floor, h_eff, p, contact, force_control, target, refresh):
        xp = op.xp
        self.op, self.xp, self.inter, self.floor = op, xp, inter, floor
        self.h = h_eff.ravel()
        self.force_control, self.target, self.refresh = force_control, target, refresh
        self.has_outside = not isinstance(inter, NoInteraction)
        self.shape = h_eff.shape
        self.size = h_eff.size
        self.tau0 = 1.0 / _self_compliance(op)
        self.tau = self.tau0
        self.delta = 0.0
        self.error = float("inf")
        self.conjugate = False
        self.G_old = 1.0
        self._set_pressure(p.ravel(), contact.ravel())
        self.t_full = xp.zeros(self.size)
        self.t_c = xp.zeros(len(self.idx))
        self.make_exact()

    # -- state helpers -------------------------------------------------------------
    def _set_pressure(self, p_flat, cmask_flat):
        xp = self.xp
        self.cmask = cmask_flat.reshape(self.shape)
        self.cflat = cmask_flat
        self.idx = xp.flatnonzero(cmask_flat)
        self.p_c = p_flat[self.idx].copy()
        if self.has_outside:
            self.p_out = xp.where(cmask_flat, 0.0, p_flat)
        else:
            self.p_out = None
        self.W = None  # K(p_out + floor 1_C), valid while no node changes status

    def full_pressure(self):
        p = self.p_out.copy() if self.p_out is not None else self.xp.zeros(self.size)
        p[self.idx] = self.p_c
        return p.reshape(self.shape)

    def make_exact(self):
        self.u = self.op.apply(self.full_pressure()).ravel()
        self.u_exact = True
        self.since_exact = 0

    def _W(self):
        if self.W is None:
            if not self.has_outside and self.floor == 0.0:
                self.W = 0.0
            else:
                w = self.p_out.copy() if self.p_out is not None else self.xp.zeros(self.size)
                w[self.idx] = self.floor
                self.W = self.op.apply(w.reshape(self.shape)).ravel()
        return self.W

    # -- one iteration ---------------------------------------------------------------
    def iterate(self):
        """One CG iteration; returns an error message when no equilibrium exists."""
        xp, op, floor = self.xp, self.op, self.floor
        self.started_exact = self.u_exact
        idx = self.idx
        n_c = len(idx)
        if self.force_control and n_c == 0:
            return "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"

        # Step 2: gap on the contact nodes; under force control the approach is the mean
        # of h + u there (Polonsky-Keer), so the contact gap has zero mean.
        g_c = self.u[idx] + self.h[idx]
        if self.force_control:
            self.delta = float(g_c.mean())
            g_c -= self.delta

        # Step 3: conjugate direction.
        G = float(g_c @ g_c)
        if self.conjugate and self.G_old > 0:
            t_c = g_c + (G / self.G_old) * self.t_c
        else:
            t_c = g_c
        self.G_old = G

        # Step 4: step length from r = K t (mean-free on the contact under force control).
        r = None
        if n_c > 0 and G > 0:
            self.t_full.fill(0.0)
            self.t_full[idx] = t_c
            r = op.apply(self.t_full.reshape(self.shape)).ravel()
            r_c = r[idx]
            rt = float(r_c @ t_c)
            if self.force_control:
                rt -= float(r_c.mean()) * float(t_c.sum())
            self.tau = float(g_c @ t_c) / rt if rt > 0 else self.tau0
        self.t_c = t_c
        tau = self.tau

        # Step 5: update on the contact, then check every node's status with the full gap.
        p_c_new = self.p_c - tau * t_c
        stays = p_c_new > floor
        g = self.u + self.h
        if self.force_control:
            g -= self.delta
        g[idx] = 0.0
        overlap = g < 0  # non-contact nodes that penetrate (contact nodes have g = 0 here)
        any_overlap = bool(overlap.any())
        self.conjugate = not any_overlap
        if self.has_outside:
            out_new = self.inter.outside_stress(g, xp)
            out_new[idx] = 0.0
            out_changed = bool(xp.any(out_new != self.p_out))
        else:
            out_new, out_changed = None, False
        all_stay = bool(stays.all())
        changed = any_overlap or out_changed or not all_stay

        p_c_old, idx_old, p_out_old = self.p_c, idx, self.p_out
        if not changed:
            self.p_c = p_c_new
        else:
            # Rebuild the sets: leavers take the outside stress of their gap, overlapping
            # nodes enter with p = s(g) - tau g (Paper A Eq. 21).
            p_full = out_new if out_new is not None else xp.zeros(self.size)
            leavers = idx[~stays]
            if len(leavers):
                p_full[leavers] = (self.inter.outside_stress(g[leavers], xp) if self.has_outside else 0.0)
            p_full[idx[stays]] = p_c_new[stays]
            cm = xp.zeros(self.size, dtype=bool)
            cm[idx[stays]] = True
            if any_overlap:
                ov = xp.flatnonzero(overlap)
                base = out_new[ov] if out_new is not None else 0.0
                p_full[ov] = base - tau * g[ov]
                cm[ov] = True
            # Keep the search direction of the nodes that stay (for the next conjugate step).
            self.t_full.fill(0.0)
            self.t_full[idx] = t_c
            self._set_pressure(p_full, cm)
            self.t_c = self.t_full[self.idx]

        # Step 6: force balance by scaling p - floor on the contact nodes.
        scale = 1.0
        if self.force_control:
            n_new = len(self.idx)
            if n_new == 0:
                return "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"
            fixed = float(self.p_out.sum()) if self.p_out is not None else 0.0
            free = float(self.p_c.sum()) - floor * n_new
            scale = (self.target - fixed - floor * n_new) / free if free > 0 else -1.0
            if scale <= 0:
                return ("the contact cannot carry the requested force: the load is beyond "
                        "pull-off (no equilibrium under force control)")
            if floor == 0.0:
                self.p_c *= scale
            else:
                self.p_c = scale * (self.p_c - floor) + floor

        # Relative pressure change (Paper A Eq. 23, made relative).
        if not changed:
            diff = float(xp.abs(self.p_c - p_c_old).sum())
        else:
            old = p_out_old.copy() if p_out_old is not None else xp.zeros(self.size)
            old[idx_old] = p_c_old
            diff = float(xp.abs(self.full_pressure().ravel() - old).sum())
        norm = float(xp.abs(self.p_c).sum()) + (float(xp.abs(self.p_out).sum()) if self.p_out is not None else 0.0)
        self.error = diff / norm if norm > 0 else diff

        # New displacement: incremental while nothing changed status, else exact.
        self.since_exact += 1
        if not changed and r is not None and self.since_exact < self.refresh:
            W = self._W()
            u = self.u
            u -= tau * r
            if scale != 1.0:
                u *= scale
                if not isinstance(W, float):
                    u += (1.0 - scale) * W
            self.u_exact = False
        elif not changed and r is None:
            pass  # nothing moved (no contact node, no status change)
        else:
            self.make_exact()
        return None
