"""Solving a free-boundary step on a window of the grid: the potential contact area.

On a free-boundary (non-periodic) grid the elastic operator is a linear convolution, so a
problem whose tractions vanish outside a box of m1 x m2 cells is solved exactly on that box
alone, with the operator of an m1 x m2 free-boundary grid of the same cell size (its padded
transforms are 2m1 x 2m2 instead of 2nx x 2ny): the same influence coefficients, the same
unknowns, the same solution.  This is CONTACT's "potential contact area" (Vollebregt), used here
for load paths whose contact stays in one place (the hysteresis loops of a ball at a fixed
normal force: the cohesive zone of the 256^2 benchmark over +-2a fills 60 % of each axis).

What makes it safe is the check after each step (:meth:`Window.embed`): the displacements of the
whole grid are computed from the window's tractions with the padded operator (one 3x3
convolution), and every node outside the window must be open (gap > 0) and beyond the range of
the stress law (no adhesive traction would act there).  When one is not, the window grows to
cover it (with the margin) and the step is solved again (:func:`solve_coupled_windowed`), up to
the whole grid; so the result is the whole grid's to the solvers' tolerances, never silently a
truncated one.  Interactions that depend on the gap alone and vanish beyond a finite range
(none, Dugdale: those that declare ``windowable``, :mod:`tribobem.interactions.base`) allow a
window; so does the capillary model without its van der Waals terms
(its stresses act on the active menisci and the Dugdale zone: the check after each step finds
the islands of the whole grid's gap and grows the window when an active meniscus reaches past
it).  A long-range law (van der Waals) is solved on the whole grid.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..interactions.base import law_windowable
from ..results import CoupledResult, NormalResult
from .boxes import MARGIN, MAX_FRACTION, MIN_MARGIN, Window, _fast_even, _window_around, _window_of_extent  # noqa: F401
from .coupling import solve_coupled

__all__ = ["Window", "auto_window", "windowable", "solve_coupled_windowed"]

#: With a capillary model, solve on a window around the contact and the Dugdale range only, the
#: menisci outside it entering as a prescribed traction (False: a window around every traction).
EXTERIOR = True


def _embed_exterior(window: Window, res: CoupledResult, operator: ConvolutionOperator, gap, reference, model,
                    p_ext, u_ext):
    """The whole-grid state of a step solved on ``window`` with the prescribed exterior traction
    ``p_ext`` (the menisci outside it; ``u_ext`` its three displacement components), and what the
    whole grid's islands say about it.

    Returns ``(result, violation, settled)``: the embedded CoupledResult (pressure = the window's
    plus ``p_ext``; displacements, gap, relative displacement from one whole-grid convolution;
    the capillary state rebuilt on the whole grid's islands), the nodes outside the window that
    close or enter the Dugdale range (the window must grow), and whether the whole grid's law
    gives the exterior exactly the traction ``p_ext`` that was assumed (else the islands moved
    and the step is solved again with the new exterior).  ``result`` is None when the window's
    own islands disagree with the whole grid's inside it (an island connected only through the
    exterior): the caller then solves without the split.
    """
    nr, tr = res.normal, res.tangential
    n_shape = operator.grid.shape
    sl = (slice(window.i0, window.i1), slice(window.j0, window.j1))
    xp = operator.xp
    be = operator.backend
    outside = np.ones(n_shape, dtype=bool)
    outside[sl] = False

    def pad(a, fill=0.0, dtype=float):
        a = np.asarray(be.to_numpy(a) if not isinstance(a, np.ndarray) else a)
        out = np.full(a.shape[:-2] + n_shape, fill, dtype=dtype)
        out[(...,) + sl] = a
        return out

    p_w = pad(nr.pressure)
    p = p_w + p_ext
    q = pad(tr.shear)
    # linearity: the exterior's displacements (u_ext, cached per exterior) plus the window's
    u = be.to_numpy(operator.apply(xp.asarray(np.stack([q[0], q[1], p_w])))) + u_ext
    uzz = be.to_numpy(operator.normal.apply(xp.asarray(p_w))) + u_ext[2]
    gap_full = np.asarray(gap, dtype=float) + u[2] - nr.approach
    gap_full[sl] = nr.gap  # the solver's own gap inside (exact zeros on its contact nodes)
    contact = pad(nr.contact, False, bool)
    support, islands = model.stress_support(gap_full, contact)
    cap_w = res.capillary
    if cap_w is not None and not np.array_equal(np.asarray(cap_w.islands.active, bool), islands.active[sl]):
        return None, None, False
    law = model.law(islands.active)
    stress = np.asarray(law.outside_stress(np.maximum(gap_full, 0.0), np))
    h0 = model.h0
    reach = h0 * (1.0 + float(model.options.get("edge_width", 0.2))) if h0 > 0 else 0.0
    violation = outside & ((gap_full <= 0.0) | (gap_full < reach))
    settled = bool(np.array_equal(stress[outside], p_ext[outside]))
    normal = dataclasses.replace(
        nr, grid=operator.grid, pressure=p, gap=gap_full, displacement=uzz, contact=contact,
        adhesive=pad(nr.adhesive, False, bool) | (outside & (p < 0)), force=float(nr.force) + float(p_ext.sum()) *
        operator.grid.cell_area, info={**nr.info, "window": (window.i0, window.i1, window.j0, window.j1),
                                       "exterior": "menisci outside the window as a prescribed traction"})
    rel = np.stack([u[0] - tr.displacement_x, u[1] - tr.displacement_y])
    slip = rel - np.asarray(reference) if reference is not None else rel.copy()
    slip[(...,) + sl] = tr.slip
    tang = dataclasses.replace(
        tr, grid=operator.grid, shear=q, slip=slip, relative_displacement=rel, contact=pad(tr.contact, False, bool),
        stick=pad(tr.stick, False, bool), mode="total" if reference is None else "incremental",
        info={**tr.info, "window": (window.i0, window.i1, window.j0, window.j1)})
    cap = None
    if cap_w is not None:
        split = law.split_force(p, gap_full, contact, operator.grid.cell_area)
        cap = dataclasses.replace(
            cap_w, normal=normal, islands=islands, capillary_force=split.capillary,
            solid_solid_force=split.solid_solid, water_solid_force=split.water_solid, contact_force=split.contact,
            repulsive_force=split.repulsive, total_force=split.total, wetted_area=split.wetted_area,
            island_count=islands.active_count, interaction=law)
    out = dataclasses.replace(res, normal=normal, tangential=tang, capillary=cap)
    out._contraction = getattr(res, "_contraction", None)
    return out, violation, settled


#: Rounds of the exterior menisci per step (the exterior traction updated to the islands the
#: step's solution gives, until they repeat).
EXTERIOR_ROUNDS = 4


def _exterior_displacement(operator: ConvolutionOperator, window: Window, p_ext) -> np.ndarray:
    """(u_x, u_y, u_z) of the exterior traction ``p_ext`` on the whole grid (m), cached on the
    operator per window and traction: a hysteresis step usually keeps the last step's menisci,
    so one whole-grid 3x3 convolution serves many steps."""
    cache = operator.cache.exterior_displacements
    key = (window.i0, window.i1, window.j0, window.j1, hash(p_ext.tobytes()))
    hit = cache.get(key)
    if hit is not None and np.array_equal(hit[0], p_ext):
        return hit[1]
    be = operator.backend
    zeros = np.zeros(p_ext.shape)
    u = be.to_numpy(operator.apply(operator.xp.asarray(np.stack([zeros, zeros, p_ext]))))
    if len(cache) >= 4:
        cache.pop(next(iter(cache)))
    cache[key] = (p_ext.copy(), u)
    return u


def _solve_exterior(window, operator, gap, *, initial, extrapolate, reference, model, solver, kw):
    """One step on ``window`` with the menisci outside it as a prescribed traction (see
    :func:`solve_coupled_windowed`).  Returns ``(result, violation)``; ``result`` None when the
    split does not apply (the caller falls back)."""
    be = operator.backend
    n_shape = operator.grid.shape
    outside = np.ones(n_shape, dtype=bool)
    outside[window.i0:window.i1, window.j0:window.j1] = False
    cell = operator.grid.cell_area
    cap0 = initial.capillary
    active = np.asarray(cap0.islands.active, dtype=bool)
    g_prev = np.asarray(be.to_numpy(initial.normal.gap) if not isinstance(initial.normal.gap, np.ndarray)
                        else initial.normal.gap, dtype=float)
    if np.any(outside & np.asarray(initial.normal.contact, bool)):
        return None, None
    if extrapolate is not None and extrapolate[0] is not None:
        # the menisci of the gap extrapolated along the path (the last step's would miss the
        # island edges that move with the load, and cost a second round)
        older, w = extrapolate
        g_old = np.asarray(be.to_numpy(older.normal.gap) if not isinstance(older.normal.gap, np.ndarray)
                           else older.normal.gap, dtype=float)
        g_prev = g_prev + float(w) * (g_prev - g_old)
        active = np.asarray(model.islands_of(g_prev, np.asarray(initial.normal.contact, bool)).active, dtype=bool)
    wop = window.operator(operator)
    law_w = model.restricted(window.slice, wop.grid)
    init_w = window.slice_result(initial, operator)
    extra_w = None
    if extrapolate is not None and extrapolate[0] is not None:
        extra_w = (window.slice_result(extrapolate[0], operator), extrapolate[1])
    res = None
    for _ in range(EXTERIOR_ROUNDS):
        stress = np.asarray(model.law(active).outside_stress(np.maximum(g_prev, 0.0), np))
        p_ext = np.where(outside, stress, 0.0)
        u_ext = _exterior_displacement(operator, window, p_ext)
        kw_w = dict(kw)
        if kw_w.get("normal_force") is not None:
            kw_w["normal_force"] = float(kw_w["normal_force"]) - float(p_ext.sum()) * cell
        # the exterior's tangential displacement (K_tz p_ext) enters the slip like a reference
        ref_w = -window.slice(u_ext[:2])
        if reference is not None:
            ref_w = ref_w + window.slice(reference)
        res_w = solver(wop, window.slice(np.asarray(gap, dtype=float) + u_ext[2]), initial=init_w,
                       extrapolate=extra_w, reference=ref_w, interaction=law_w, **kw_w)
        res, violation, settled = _embed_exterior(window, res_w, operator, gap, reference, model, p_ext, u_ext)
        if res is None or violation.any():
            return res, violation
        if settled:
            return res, violation
        active, g_prev = np.asarray(res.capillary.islands.active, bool), res.normal.gap
        init_w = window.slice_result(res, operator)
        extra_w = None
    res = dataclasses.replace(res, converged=False, message=(
        f"{res.message}; the menisci outside the solve window did not settle in {EXTERIOR_ROUNDS} rounds"))
    return res, np.zeros(n_shape, dtype=bool)


def windowable(operator: ConvolutionOperator, interaction) -> bool:
    """Whether a step on this operator with this law may be solved on a window (free boundary;
    no stress law, or one of finite range that depends on the gap alone).

    Parameters
    ----------
    operator : ConvolutionOperator
        The whole grid's operator; a periodic one never allows a window (its convolution is
        cyclic, so tractions in a box do not decouple from the rest).
    interaction : Interaction or None
        The stress law outside contact.

    Returns
    -------
    bool
    """
    if operator.periodic:
        return False
    # The law says (its ``windowable``): none and Dugdale do; a capillary model does without
    # its long-range van der Waals terms (finite support); a law that does not say does not.
    return law_windowable(interaction)


def auto_window(res: CoupledResult | NormalResult, operator: ConvolutionOperator, interaction) -> Window | None:
    """The window around the tractions of a solved state (contact and cohesive zone), or None
    when windows do not apply or would not pay (see :func:`windowable`, ``MAX_FRACTION``).

    Parameters
    ----------
    res : CoupledResult or NormalResult
        A solved state on the whole grid (its pressure, contact and adhesive masks give the
        tractions' support).
    operator : ConvolutionOperator
        The whole grid's operator.
    interaction : Interaction or None
        The stress law outside contact.

    Returns
    -------
    Window or None
        The box around the support plus ``MARGIN``, widened to a fast FFT length; None when
        :func:`windowable` says no or the box exceeds ``MAX_FRACTION`` of the grid.
    """
    if not windowable(operator, interaction):
        return None
    nr = res.normal if isinstance(res, CoupledResult) else res
    if getattr(interaction, "self_consistent", False) and EXTERIOR and isinstance(res, CoupledResult) \
            and res.capillary is not None:
        # the unknown tractions only: the contact and the Dugdale range; the menisci beyond are a
        # prescribed traction (solve_coupled_windowed)
        return _window_around(_unknown_support(nr, interaction), operator.grid.shape)
    return _window_around((nr.pressure != 0) | nr.contact | nr.adhesive, operator.grid.shape)


def _unknown_support(nr, model):
    """Nodes whose traction the step must solve for with a capillary model: the contact and the
    Dugdale range (with its edge ramp)."""
    gap = np.asarray(nr.gap, dtype=float)
    mask = np.asarray(nr.contact, dtype=bool).copy()
    h0 = model.h0
    if h0 > 0:
        mask |= (gap > 0) & (gap < h0 * (1.0 + float(model.options.get("edge_width", 0.2))))
    return mask


def solve_coupled_windowed(window: Window | None, operator: ConvolutionOperator, gap, *, initial=None,
                           extrapolate=None, reference=None, interaction=None, solver=None, **kw):
    """:func:`~tribobem.solvers.coupling.solve_coupled` on ``window``, checked and embedded.

    ``initial``, ``extrapolate`` and ``reference`` are whole-grid states (as returned).  When a
    node outside the window closes or comes within the law's range, the window grows around the
    tractions and those nodes and the step is solved again (up to the whole grid).

    ``solver``: the step solver (default :func:`~tribobem.solvers.coupling.solve_coupled`).

    Parameters
    ----------
    window : Window or None
        The window to try first (e.g. from :func:`auto_window` or the last step); None: solve
        on the whole grid.
    operator : ConvolutionOperator
        The whole grid's 3x3 free-boundary operator.
    gap : array_like
        Initial gap h (m) on the whole grid.
    initial : CoupledResult, optional
        Warm start on the whole grid (previous step).
    extrapolate : (CoupledResult, float), optional
        ``(older, w)`` as for :func:`~tribobem.solvers.coupling.solve_coupled`, on the whole grid.
    reference : array_like, shape (2, nx, ny), optional
        Previous step's relative displacement (m) (incremental slip); None: total.
    interaction : Interaction, optional
        Stress law outside contact (a windowable one, see :func:`windowable`).
    solver : callable, optional
        Step solver with the signature of :func:`~tribobem.solvers.coupling.solve_coupled`.
    **kw
        Passed to ``solver`` (friction coefficient, loads in N or m, tolerances, ...).

    Returns
    -------
    (CoupledResult, Window or None)
        The whole-grid result and the window it was solved on (for the next step).
    """
    solver = solve_coupled if solver is None else solver
    full_shape = operator.grid.shape
    exterior = (EXTERIOR and getattr(interaction, "self_consistent", False) and initial is not None
                and getattr(initial, "capillary", None) is not None)
    while window is not None and exterior:
        res, violation = _solve_exterior(window, operator, gap, initial=initial, extrapolate=extrapolate,
                                         reference=reference, model=interaction, solver=solver, kw=kw)
        if res is None:
            break  # the split does not apply: the window around every traction below
        if not violation.any():
            return res, window
        region = np.zeros(full_shape, dtype=bool)
        region[window.i0:window.i1, window.j0:window.j1] = True
        window = _window_around(region | violation | _unknown_support(res.normal, interaction), full_shape)
    if exterior and initial is not None:
        window = _window_around((initial.normal.pressure != 0) | initial.normal.contact, full_shape)
    while window is not None:
        wop = window.operator(operator)
        init_w = window.slice_result(initial, operator) if initial is not None else None
        extra_w = None
        if extrapolate is not None and extrapolate[0] is not None:
            extra_w = (window.slice_result(extrapolate[0], operator), extrapolate[1])
        law_w = interaction
        if getattr(interaction, "self_consistent", False):
            law_w = interaction.restricted(window.slice, wop.grid)
        res_w = solver(wop, window.slice(gap), initial=init_w, extrapolate=extra_w,
                       reference=window.slice(reference), interaction=law_w, **kw)
        res, violation = window.embed(res_w, operator, gap, reference, interaction)
        if not violation.any():
            return res, window
        # grow around the old window, the violating nodes and the tractions (strictly larger:
        # it covers the violating nodes, which lie outside the old one), or give up to the grid
        region = np.zeros(full_shape, dtype=bool)
        region[window.i0:window.i1, window.j0:window.j1] = True
        window = _window_around(region | violation | (res.normal.pressure != 0) | res.normal.contact, full_shape)
    res = solver(operator, gap, initial=initial, extrapolate=extrapolate, reference=reference,
                        interaction=interaction, **kw)
    return res, None
