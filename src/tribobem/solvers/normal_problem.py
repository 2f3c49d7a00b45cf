"""Inputs and result of a normal solve, shared by the two normal solvers.

:func:`normal_problem` checks the arguments of :func:`~tribobem.solvers.normal.solve_normal`
and :func:`~tribobem.solvers.normal_cg.solve_normal_cg` (the same) and builds the start (Paper
A step 1); :func:`normal_result` assembles the :class:`~tribobem.results.NormalResult` from the
final pressure and displacement and the :class:`~.iteration.IterationOutcome` of the loop.  The
solvers supply only their iteration (Polonsky-Keer: ``normal._CGState``, NormCG:
``normal_cg._NormCG``).
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from ..errors import InputError
from ..interactions.base import NoInteraction
from ..results import NormalResult
from .iteration import IterationOutcome, report_failure

__all__ = ["NormalProblem", "normal_problem", "normal_result"]


class NormalProblem(NamedTuple):
    """Checked inputs and start of a normal solve (see :func:`normal_problem`).

    Attributes
    ----------
    h : array
        Initial gap (m), a backend array of ``grid.shape``.
    interaction : Interaction
        The outside stress law (``NoInteraction`` without adhesion).
    floor : float
        Lowest contact pressure (Pa): -sigma0 with Dugdale adhesion, else 0.
    force_control : bool
        True when the normal force is given, False when the approach is.
    target : float or None
        Force control: the target sum of p (Pa), F0 / cell area; else None.
    shift : float
        Displacement control: the approach (m); 0 under force control.
    pressure : array
        Initial pressure (Pa), a fresh C-contiguous array the solver may own.
    contact : array of bool
        Initial contact mask.
    """

    h: object
    """Initial gap (m), a backend array of ``grid.shape``."""
    interaction: object
    """The outside stress law (:class:`~tribobem.interactions.base.NoInteraction` without adhesion)."""
    floor: float
    """Lowest contact pressure (Pa): -sigma0 with Dugdale adhesion, else 0."""
    force_control: bool
    target: float | None
    """Force control: the target sum of p (Pa), F0 / cell area; else None."""
    shift: float
    """Displacement control: the approach (m); 0 under force control."""
    pressure: object
    """Initial pressure (Pa), a fresh C-contiguous array the solver may own."""
    contact: object
    """Initial contact mask."""


def normal_problem(op, gap, force, approach, interaction, tol, max_iterations, initial_pressure,
                   initial_contact, refresh: int | None = None) -> NormalProblem:
    """Check the inputs of a normal solve and build its start (Paper A step 1).

    Parameters
    ----------
    op : ConvolutionOperator
        The normal block of the elastic operator (m/Pa).
    gap, force, approach, interaction, tol, max_iterations, initial_pressure, initial_contact
        As for :func:`~tribobem.solvers.normal.solve_normal`.
    refresh : int, optional
        Checked (>= 1) when given.

    Returns
    -------
    NormalProblem
        The initial pressure is the warm start raised to the floor, else uniform (force
        control) or zero; the contact is ``initial_contact & (p > floor)``, else ``p > floor``
        (force control or a warm start), else empty.

    Raises
    ------
    InputError
        Bad load, gap, tolerance, iteration limit, ``refresh`` or warm start.
    """
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
        raise InputError("solve_normal.tol", f"must be a finite value > 0, got {tol!r}")
    if max_iterations < 1:
        raise InputError("solve_normal.max_iterations", f"must be >= 1, got {max_iterations!r}")
    if refresh is not None and refresh < 1:
        raise InputError("solve_normal.refresh", f"must be >= 1, got {refresh!r}")

    force_control = force is not None
    if force_control:
        if not math.isfinite(force):
            raise InputError("solve_normal.force", f"must be finite, got {force!r}")
        if floor == 0.0 and force <= 0.0:
            raise InputError("solve_normal.force", f"must be > 0 N without adhesion, got {force!r}")
        target = force / grid.cell_area  # target sum of p
        shift = 0.0
    else:
        target = None
        if not math.isfinite(approach):
            raise InputError("solve_normal.approach", f"must be finite, got {approach!r}")
        shift = float(approach)  # the Polonsky-Keer solver works on h - approach without storing it

    # Step 1: initial pressure (one array, owned by the solver state).
    if isinstance(initial_pressure, NormalResult):
        initial_contact = initial_pressure.contact if initial_contact is None else initial_contact
        initial_pressure = initial_pressure.pressure
    if initial_pressure is not None:
        p = xp.array(initial_pressure, dtype=float, order="C")
        if p.shape != grid.shape:
            raise InputError("initial_pressure", f"shape {tuple(p.shape)} does not match the grid {grid.shape}")
        xp.maximum(p, floor, out=p)
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
    return NormalProblem(h, inter, floor, force_control, target, shift, p, contact)


def normal_result(op, h, p, contact, u, approach, interaction, outcome: IterationOutcome, strict: bool,
                  t_start: float, info: dict, plastic=None) -> NormalResult:
    """Assemble the result of a normal solve, its fields consistent with the final pressure.

    Parameters
    ----------
    op : ConvolutionOperator
        The normal block of the elastic operator.
    h : array
        Initial gap (m), ``grid.shape``.
    p : array
        Final pressure (Pa), ``grid.shape``.
    contact : array of bool
        Final contact mask.
    u : array
        K p (m), exact for ``p``; ``h`` and ``u`` may be reused by the caller afterwards (the
        gap is a new array).
    approach : float or None
        The approach (m) under displacement control; None under force control, where the
        approach is the mean of h + u on the contact nodes (NaN without contact).
    interaction : Interaction
        The outside stress law (its repr goes to ``info``).
    outcome : IterationOutcome
        How the iteration ended (converged, message, residual history).
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning when the loop did
        not converge.  The warning points at the caller of the public solver.
    t_start : float
        ``time.perf_counter()`` at the start of the solve.
    info : dict
        The solver's entries of ``result.info``, after ``max_penetration`` (m),
        ``interaction`` and ``operator``.
    plastic : array of bool, optional
        The nodes at the hardness cap (part of ``contact``; their gap is an overlap taken up
        plastically): the approach is measured on the other contact nodes, and the result's
        ``plastic_increment`` is their overlap (m).

    Returns
    -------
    NormalResult
        Host (NumPy) arrays.

    Raises
    ------
    ConvergenceError
        With ``strict``, when the loop did not converge.
    """
    xp, grid = op.xp, op.grid
    force_control = approach is None
    g = u + h
    elastic = contact if plastic is None else contact & ~plastic
    n_c = int(xp.count_nonzero(elastic))
    if force_control:
        delta = float(xp.sum(xp.where(elastic, g, 0.0))) / n_c if n_c else float("nan")
    else:
        delta = float(approach)
    g -= delta if n_c or not force_control else float(xp.min(g))
    increment = None
    if plastic is not None and bool(xp.any(plastic)):
        increment = op.backend.to_numpy(xp.where(plastic, xp.maximum(-g, 0.0), 0.0))
    gap_field = xp.where(contact, 0.0, g)
    penetration = float(-xp.min(gap_field)) if n_c < g.size else 0.0
    del g
    xp.maximum(gap_field, 0.0, out=gap_field)
    # the law's own adhesive area where it defines one (a smooth law pulls everywhere), else p < 0
    mask_fn = getattr(interaction, "adhesive_mask", None)
    adhesive = (~contact) & (p < 0) & (mask_fn(gap_field, xp) if mask_fn is not None else True)
    be = op.backend
    total = float(xp.sum(p)) * grid.cell_area
    if not outcome.converged:
        # stacklevel 3: this function <- the public solver <- its caller
        report_failure(outcome.message, strict=strict, stacklevel=3)
    return NormalResult(
        grid=grid,
        pressure=be.to_numpy(p),
        gap=be.to_numpy(gap_field),
        displacement=be.to_numpy(u),
        contact=be.to_numpy(contact),
        adhesive=be.to_numpy(adhesive),
        force=total,
        approach=delta,
        iterations=len(outcome.history),
        residual_history=np.asarray(outcome.history),
        converged=outcome.converged,
        time=time.perf_counter() - t_start,
        message=outcome.message,
        control="force" if force_control else "displacement",
        info={"max_penetration": max(penetration, 0.0), "interaction": repr(interaction), "operator": op.kind,
              **info},
        plastic=be.to_numpy(plastic) if plastic is not None else None,
        plastic_increment=increment,
    )


def _self_compliance(op) -> float:
    """Displacement (m/Pa) of a cell under its own unit pressure (diagonal of K)."""
    c = op.cache.self_compliance
    if c is None:
        xp = op.xp
        e = xp.zeros(op.grid.shape)
        e[0, 0] = 1.0
        c = op.cache.self_compliance = float(op.backend.to_numpy(op.apply(e))[0, 0])
    return c
