"""Candidate-set solves of non-adhesive free-boundary normal contact.

On a free-boundary grid the elastic operator is a linear (zero-padded) convolution, so a
problem whose pressure vanishes outside a box is solved exactly on that box alone, with the
box's own free-boundary operator (:class:`~tribobem.solvers.boxes.Window`): the same influence
coefficients, the same unknowns, padded transforms of the box instead of the whole grid.

Which nodes can be in contact is known before the solve, and checked exactly after it.  The
half-space's influence coefficients are positive and a non-adhesive pressure is >= 0, so the
displacement K p is >= 0 everywhere and the gap h + K p - delta of a node is at least
h - delta: a node whose undeformed gap exceeds the rigid approach delta cannot touch.  The
candidates are therefore the nodes with h < delta_est, delta_est from a coarse solve of the
same problem (the gap's block mean on a grid of at most ``COARSE_NODES`` nodes, with a margin
``SAFETY`` on the approach above the lowest gap); the box around them is solved; and the
solution is verified on the whole grid: every node outside the box must have h > delta of
the box's solution.  A node that fails grows the box (to the nodes below the new approach plus
the margin ``GROWTH``) and the box is solved again from the last state, at most ``MAX_ROUNDS`` times,
then the whole grid is solved.  So the result is the whole grid's (the same contact nodes,
pressures within the solver tolerance), never a truncated one.  One whole-grid convolution of
the box's pressure gives the displacement and the gap outside the box (inside, the box's own).

Under displacement control delta is given: the candidate box is exact at once.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from ..errors import InputError
from ..interactions.base import NoInteraction
from ..results import NormalResult

__all__ = ["candidate_solve", "applies", "MIN_NODES"]

#: ``candidates=None`` (automatic) solves on a candidate box from this many grid nodes.
MIN_NODES = 512 * 512
#: The coarse estimate of the approach: the gap's block mean on at most this many nodes.
COARSE_NODES = 256 * 256
#: Margin on the estimated approach above the lowest gap (the fine grid's sharper asperities
#: deform more than the coarse grid's block means: the fine approach is the larger).
SAFETY = 0.25
#: A box that fails the check grows to the nodes below its approach plus this margin (relative
#: to the approach above the lowest gap).
GROWTH = 0.25
#: Box growths before the whole grid is solved.
MAX_ROUNDS = 4
#: The box is solved only when its padded transform is below this fraction of the grid's.
MAX_FRACTION = 0.7


def applies(op, interaction, initial_pressure=None, precondition: bool = True) -> str | None:
    """Why a candidate-set solve does not apply (None when it does).

    Parameters
    ----------
    op : ConvolutionOperator
        The whole grid's normal operator.
    interaction : Interaction or None
        The outside law: only non-adhesive contact (no law, no hardness cap) has K p >= 0.
    initial_pressure : array_like, optional
        A warm start (the candidate solve starts from its own coarse solve).
    precondition : bool
        The solve is the preconditioned NormCG.

    Returns
    -------
    str or None
        The reason, or None.
    """
    if op.periodic:
        return "periodic grid (the cyclic convolution couples every node)"
    if not isinstance(interaction if interaction is not None else NoInteraction(), NoInteraction):
        return "an outside stress law (the displacement need not be >= 0)"
    if initial_pressure is not None:
        return "a warm start"
    if not precondition:
        return "unpreconditioned CG"
    from ..elasticity.bodies import body_model_of

    if body_model_of(op.pair).name != "halfspace":
        return "a body model other than the half-space (positive influence coefficients are not known)"
    return None


def candidate_solve(solve, op, gap, candidates, *, force, approach, interaction, tol, max_iterations,
                    initial_pressure, strict, refresh, stall, precondition, precision, coarse_levels):
    """The candidate-set solve of ``solve_normal_cg`` when it applies, else None.

    Parameters
    ----------
    solve : callable
        :func:`~tribobem.solvers.normal_cg.solve_normal_cg` (passed in: the box and the coarse
        problem are its solves, and it calls this function).
    op : ConvolutionOperator
        The whole grid's normal operator.
    gap : array_like
        Undeformed gap h (m), ``op.grid.shape``.
    candidates : bool or None
        The caller's choice (``solve_normal_cg``).
    force, approach, interaction, tol, max_iterations, initial_pressure, strict, refresh, stall, \
precondition, precision, coarse_levels
        As ``solve_normal_cg``.

    Returns
    -------
    NormalResult or None
        The whole grid's result (``info["candidates"]``: rounds, boxes, coarse solve, the
        verification), or None when the candidate solve does not apply, would not pay
        (box above ``MAX_FRACTION``), or ``candidates`` is False.

    Raises
    ------
    InputError
        ``candidates=True`` where it cannot apply.
    """
    if candidates is False:
        return None
    if candidates not in (None, True):
        raise InputError("candidates", f"must be True, False or None, got {candidates!r}")
    why = applies(op, interaction, initial_pressure, precondition)
    if why is not None:
        if candidates is True:
            raise InputError("candidates", f"a candidate-set solve does not apply: {why}")
        return None
    grid = op.grid
    if candidates is None and grid.nx * grid.ny < MIN_NODES:
        return None
    if coarse_levels not in (None, 0) and candidates is None:
        return None  # the caller asked for the nested whole-grid start
    xp = op.xp
    h = xp.asarray(gap, dtype=float)
    if h.shape != grid.shape or not bool(xp.all(xp.isfinite(h))) or (force is None) == (approach is None):
        return None  # normal_problem reports it
    return _solve(solve, op, h, force, approach, tol, max_iterations, strict, refresh, stall, precision,
                  candidates is True)


def _coarse_estimate(solve_normal_cg, op, h, force, precision):
    """Approach (m, above the lowest gap) and pressure of the problem on a grid of at most
    ``COARSE_NODES`` nodes (block means of the gap); None when no coarse grid divides this one."""
    from ..elasticity.operators import free_boundary_operator
    from ..grid import Grid

    g = op.grid
    if g.nx % 2 or g.ny % 2 or g.nx < 16 or g.ny < 16:
        return None
    k = 2
    while g.nx % (2 * k) == 0 and g.ny % (2 * k) == 0 and (g.nx // k) * (g.ny // k) > COARSE_NODES:
        k *= 2
    cg = Grid(g.nx // k, g.ny // k, g.lx, g.ly, False)
    hc = h.reshape(cg.nx, k, cg.ny, k).mean(axis=(1, 3))
    cop = free_boundary_operator(cg, op.pair, ("z",), backend=op.backend)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a start only
        res = solve_normal_cg(cop, hc, force=force, tol=1e-4, precision=precision, candidates=False)
    if not math.isfinite(float(res.approach)):
        return None
    return float(res.approach) - float(hc.min()), res, k


def _box_of(mask, shape, be):
    """The box around the True nodes of ``mask`` (on the backend: only its row and column
    summaries come to the host), a fast FFT length, or None."""
    from .boxes import _window_of_extent

    return _window_of_extent(be.to_numpy(mask.any(axis=1)), be.to_numpy(mask.any(axis=0)), shape, margin=0.0)


def _solve(solve_normal_cg, op, h, force, approach, tol, max_iterations, strict, refresh, stall, precision, forced):
    t0, c0 = time.perf_counter(), time.process_time()
    xp, grid = op.xp, op.grid
    h_min = float(h.min())
    info = {"rounds": 0, "boxes": [], "coarse": None}
    start = None
    if approach is not None:
        level = float(approach)
    else:
        est = _coarse_estimate(solve_normal_cg, op, h, force, precision)
        if est is None:
            if forced:
                warnings.warn("candidate-set solve: no coarse grid for the approach estimate (odd or small grid); "
                              "solving the whole grid", stacklevel=3)
            return None
        rise, cres, k = est
        info["coarse"] = {"grid": [grid.nx // k, grid.ny // k], "iterations": int(cres.iterations),
                          "approach_above_min": rise}
        level = h_min + (1.0 + SAFETY) * rise
        start = (cres, k)
    win = None
    last = None  # (window, its result) of the last box solve
    for rnd in range(MAX_ROUNDS + 1):
        mask = h < level
        if win is not None:
            mask[win.i0:win.i1, win.j0:win.j1] = True
        new = _box_of(mask, grid.shape, op.backend)
        del mask
        if new is None:
            info["fallback"] = "no node lies below the approach"
            break
        if new.shape[0] * new.shape[1] > MAX_FRACTION * grid.nx * grid.ny:
            info["fallback"] = "the candidate box would cover most of the grid"
            break
        win = new
        wop = win.operator(op)
        hw = xp.ascontiguousarray(h[win.i0:win.i1, win.j0:win.j1])
        p0 = None
        if last is not None:
            p0 = _embed_pressure(last[1], last[0], win, xp)
        elif start is not None:  # the coarse pressure (a nested start of the box measured no faster)
            cres, k = start
            # the coarse pressure on the box's fine nodes (each coarse value on its k x k nodes)
            a0, b0 = win.i0 // k, win.j0 // k
            pc = np.asarray(op.backend.to_numpy(cres.pressure))[a0:-(-win.i1 // k), b0:-(-win.j1 // k)]
            pc = np.repeat(np.repeat(pc, k, axis=0), k, axis=1)
            p0 = xp.asarray(np.ascontiguousarray(pc[win.i0 - a0 * k:win.i1 - a0 * k, win.j0 - b0 * k:win.j1 - b0 * k]))
            del pc
            if not bool((p0 > 0).any()):
                p0 = None
        res_win = solve_normal_cg(wop, hw, force=force, approach=approach, tol=tol, max_iterations=max_iterations,
                                  initial_pressure=p0, strict=strict, refresh=refresh, stall=stall,
                                  precision=precision, candidates=False, coarse_levels=None if p0 is None else 0)
        last = (win, res_win)
        info["rounds"] = rnd + 1
        info["boxes"].append([win.i0, win.i1, win.j0, win.j1])
        delta = float(res_win.approach)
        if not math.isfinite(delta):
            info["fallback"] = "the box solve found no contact"
            break
        # the check: every node outside the box opens (h > delta, K p >= 0)
        outside_min = _outside_min(h, win)
        if outside_min > delta:
            return _embed(op, h, win, res_win, info, t0, c0, outside_min - delta, strict)
        level = delta + GROWTH * (delta - h_min)
    if forced:
        warnings.warn(f"candidate-set solve fell back to the whole grid ({info.get('fallback', 'box kept growing')})",
                      stacklevel=3)
    return None


def _embed_pressure(res, prev, win, xp):
    """The previous box's pressure on the new box (which contains it)."""
    p = xp.zeros(win.shape)
    p[prev.i0 - win.i0:prev.i1 - win.i0, prev.j0 - win.j0:prev.j1 - win.j0] = xp.asarray(res.pressure)
    return p


def _outside_min(h, win) -> float:
    """Lowest undeformed gap outside the window (inf when it covers the grid)."""
    parts = [h[:win.i0], h[win.i1:], h[win.i0:win.i1, :win.j0], h[win.i0:win.i1, win.j1:]]
    vals = [float(a.min()) for a in parts if a.size]
    return min(vals) if vals else math.inf


def _embed(op, h, win, rw: NormalResult, info, t0, c0, margin, strict) -> NormalResult:
    """The whole grid's result: the box's pressure and contact, the displacement of one
    whole-grid convolution, the box's own displacement and gap inside it."""
    import dataclasses

    from ..elasticity.embedding import box_to_grid

    # a result's fields live on the host (normal_result), as the box's do
    sl = (slice(win.i0, win.i1), slice(win.j0, win.j1))
    u = box_to_grid(op, win.i0, win.j0, rw.pressure)  # (not the operator's own 2nx x 2ny spectrum)
    u[sl] = rw.displacement
    p = np.zeros(op.grid.shape)
    p[sl] = rw.pressure
    g = op.backend.to_numpy(h) + u
    g -= rw.approach
    g[sl] = rw.gap
    contact = np.zeros(op.grid.shape, dtype=bool)
    contact[sl] = rw.contact
    adhesive = np.zeros(op.grid.shape, dtype=bool)
    info = {**info, "verified_margin": float(margin), "box_fraction": win.shape[0] * win.shape[1] / (op.grid.nx * op.grid.ny),
            "cpu_s": time.process_time() - c0}
    out = dataclasses.replace(
        rw, grid=op.grid, pressure=p, gap=g, displacement=u, contact=contact, adhesive=adhesive,
        info={**rw.info, "operator": op.kind, "candidates": info, "convolutions": rw.info.get("convolutions", 0) + 1},
        time=time.perf_counter() - t0)
    return out
