"""Friction hysteresis (Papers E and F): tangential cycles with the load history carried.

The start is the one-shot ("total") solve at F_t = 0 (Paper E point A: for dissimilar bodies a
stick core in a slip annulus).  Every later step is an incremental step (Paper E Eq. 5): the slip
is measured from the previous step's relative displacement, so stick and slip depend on the
history; the coupling loop and the Dugdale adhesion act at every step.

Paths (:func:`cycle_path`):

* force control: 0 -> +F* -> -F* -> +F* -> ... (``cycles`` full cycles after the initial
  loading), F* = amplitude x mu F0+ of the F_t = 0 state;
* displacement control: 0 -> +d/2 -> -d/2 -> +d/2 ... (stroke d peak to peak).  When the
  stroke exceeds the pre-sliding range the whole compressive contact slips and the force
  saturates at mu F0+ (gross sliding), which the solver reaches without special handling.

Step law (Paper E Fig. 3 gives none; Paper E says "exponential" increments): each branch is
sampled at F = F_start + (F_end - F_start)(1 - cos(pi k/m))/2, k = 1..m (Chebyshev-cosine
spacing): the steps are densest right after a reversal (A', D', H') and right before a turning
point, where a small force change moves the contact most; m = steps/2 per branch (steps/4 for the
initial loading, at least 4).

Windows (``window=True``, the default): at a fixed normal force the contact and its cohesive
zone stay in one place, so on a free-boundary grid every step after the start is solved on a
window around them (:mod:`.window`: the same discrete problem on fewer cells, checked after each
step by one whole-grid convolution and grown when a node outside it closes or enters the adhesive
range; the stored states are whole-grid ones).  On the 256^2 loop of benchmarks/hysteresis.py the
window is 192^2 (padded transforms of 384^2 instead of 512^2); the adhesive loop of
benchmarks/adhesive_loop.py, whose cohesive zone spans 214 of its 256 rows, is solved on the
whole grid (a window would not pay, ``window.MAX_FRACTION``).

Gross sliding against a rough counterface (thesis recommendation 3): with ``moving_gap`` the
upper body's geometry moves with the sliding (after each step in gross slip, by that step's
displacement increment), so new contact pairs form; the elastic pre-sliding displacement does not
move the geometry (small-displacement theory).
"""

from __future__ import annotations

import math
import warnings
from typing import Callable

import numpy as np

from ..errors import ConvergenceWarning, InputError
from ..results import CyclePath, HysteresisRun
from .coupling import solve_coupled
from .tangential_paths import direction_vector
from .tangential import GrossSlipError
from .window import auto_window, solve_coupled_windowed

#: Extrapolate the warm start of each step linearly from the last two (see ``solve_coupled``).
EXTRAPOLATE = True

__all__ = ["cycle_path", "hysteresis_loop", "loop_energies"]


def _branch(start: float, end: float, m: int) -> np.ndarray:
    k = np.arange(1, m + 1)
    return start + (end - start) * 0.5 * (1.0 - np.cos(np.pi * k / m))


def cycle_path(peak: float, cycles: int, steps: int, control: str = "force") -> CyclePath:
    """The cyclic path 0 -> +peak -> -peak -> +peak ... with ``cycles`` full cycles.

    Parameters
    ----------
    peak : float
        F* (N) or d/2 (m), > 0.
    cycles : int
        Full cycles after the initial loading, >= 1.
    steps : int
        Steps per cycle (>= 4): steps/2 per branch, steps/4 (>= 4) for the initial loading.
    control : {"force", "displacement"}
        What ``peak`` is: a tangential force amplitude or a displacement half stroke.

    Returns
    -------
    CyclePath
        The values (N or m) of every step, cosine-spaced along each branch (steps crowd near
        the turning points, where stick and slip change fastest), with their cycle, branch and
        turning flags.

    Raises
    ------
    InputError
        For a non-positive peak, ``cycles`` < 1 or ``steps`` < 4.
    """
    if not (math.isfinite(peak) and peak > 0):
        raise InputError("cycle_path.peak", f"the amplitude (or half stroke) must be > 0, got {peak!r}")
    if not isinstance(cycles, (int, np.integer)) or cycles < 1:
        raise InputError("cycle_path.cycles", f"must be an integer >= 1, got {cycles!r}")
    if not isinstance(steps, (int, np.integer)) or steps < 4:
        raise InputError("cycle_path.steps", f"must be an integer >= 4, got {steps!r}")
    m = steps // 2
    m0 = max(steps // 4, 4)
    vals, cyc, br, turn = [], [], [], []

    def add(a, b, n, c, name):
        v = _branch(a, b, n)
        vals.extend(v)
        cyc.extend([c] * n)
        br.extend([name] * n)
        turn.extend([False] * (n - 1) + [True])

    add(0.0, peak, m0, 0, "loading")
    for c in range(1, cycles + 1):
        add(peak, -peak, m, c, "unloading")
        add(-peak, peak, m, c, "reloading")
    return CyclePath(np.array(vals), np.array(cyc), np.array(br, dtype=object), np.array(turn), control)


def hysteresis_loop(
    operator,
    gap,
    *,
    normal_force: float,
    friction_coefficient: float,
    control: str = "force",
    amplitude: float = 0.999,
    stroke: float | None = None,
    cycles: int = 1,
    steps: int = 40,
    direction: float = 0.0,
    interaction=None,
    moving_gap: Callable | None = None,
    progress: Callable[[int, int], None] | None = None,
    window: bool = True,
    initial=None,
    **solver_kw,
) -> HysteresisRun:
    """Run tangential force or displacement cycles at a fixed normal force.

    Parameters
    ----------
    operator : ConvolutionOperator
        3x3 operator.
    gap : array_like
        Initial gap (m).
    normal_force : float
        N.
    friction_coefficient : float
        mu > 0 for force control (the amplitude is a fraction of mu F0+).
    control : {"force", "displacement"}
    amplitude : float
        F* / (mu F0+) for force control, in (0, 1].
    stroke : float
        Peak-to-peak displacement (m) for displacement control.
    cycles, steps : int
        Full cycles after the initial loading; steps per cycle.
    direction : float
        Degrees from the x axis.
    moving_gap : callable, optional
        ``moving_gap(offset) -> gap`` with body 2 moved by ``offset`` (m, 2-vector).  Under
        displacement control the counterface then moves with the sliding: after every step in
        gross slip the offset grows by that step's rigid-displacement increment (thesis
        recommendation 3; new contact pairs form on a rough counterface).  None: the gap is fixed
        (exact for smooth bodies).
    window : bool
        Solve each step on a window of the grid around the contact and cohesive zone of the
        start (free boundary, Dugdale or no adhesion; :mod:`.window`): exact, checked after every
        step (the window grows, up to the whole grid, when a node outside it closes or comes
        within the adhesive range).  False: every step on the whole grid.
    initial : CoupledResult, optional
        Warm start of the start's solve (e.g. the previous RH's start); the iterations only.
    **solver_kw
        Passed to :func:`~tribobem.solvers.coupling.solve_coupled`.

    Returns
    -------
    HysteresisRun
    """
    mu = friction_coefficient
    e = direction_vector(direction)
    if control not in ("force", "displacement"):
        raise InputError("hysteresis_loop.control", f"must be 'force' or 'displacement', got {control!r}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        start = solve_coupled(operator, gap, friction_coefficient=mu, normal_force=normal_force,
                              interaction=interaction, initial=initial, **solver_kw)
        if control == "force":
            if not (0 < amplitude <= 1):
                raise InputError("hysteresis_loop.amplitude", f"must be in (0, 1], got {amplitude!r}")
            if mu <= 0:
                raise InputError("hysteresis_loop.friction_coefficient", "must be > 0 for a force-controlled loop (the amplitude "
                                                         "is a fraction of mu F0+)")
            peak = amplitude * mu * start.normal.repulsive_force
        else:
            if stroke is None or not (math.isfinite(stroke) and stroke > 0):
                raise InputError("hysteresis_loop.stroke", f"must be a length > 0, got {stroke!r}")
            peak = 0.5 * stroke
        path = cycle_path(peak, cycles, steps, control)
        run = HysteresisRun(start=start, steps=[], path=path, direction=e,
                            peak_force=peak if control == "force" else float("nan"))
        prev = older = start
        win = auto_window(start, operator, interaction) if window else None
        windowed = win is not None
        offset = np.zeros(2)
        gap_k = gap
        law_k = interaction
        n_cycles = int(path.cycle.max())
        diss = [None] * (n_cycles + 1)
        slip = [None] * (n_cycles + 1)
        for k, v in enumerate(path.values):
            load = ({"tangential_force": tuple(v * e)} if control == "force"
                    else {"tangential_displacement": tuple(v * e)})
            if moving_gap is not None and control == "displacement" and k > 0 and prev.tangential.gross_slip:
                d_prev = np.array([prev.tangential.displacement_x, prev.tangential.displacement_y])
                d_new = v * e
                offset = offset + (d_new - d_prev)
                gap_k = moving_gap(offset)
                if hasattr(interaction, "moved"):
                    law_k = interaction.moved(offset)  # the counterface's film moves with it
            # Linear extrapolation of the warm start while the load keeps its direction (not across a
            # turning point, where the state's history changes branch).
            extra = None
            if k >= 1 and EXTRAPOLATE:
                v1 = path.values[k - 1]
                v0 = path.values[k - 2] if k >= 2 else 0.0
                if (v - v1) * (v1 - v0) > 0 and gap_k is gap:
                    extra = (older, min((v - v1) / (v1 - v0), 2.0))
            try:
                if windowed:
                    res, win = solve_coupled_windowed(
                        win, operator, gap_k, friction_coefficient=mu, normal_force=normal_force,
                        interaction=law_k, reference=prev.tangential.relative_displacement,
                        initial=prev, extrapolate=extra, solver=solve_coupled, **load, **solver_kw)
                    windowed = win is not None  # grown to the whole grid: stay there
                else:
                    res = solve_coupled(operator, gap_k, friction_coefficient=mu, normal_force=normal_force,
                                        interaction=law_k, reference=prev.tangential.relative_displacement,
                                        initial=prev, extrapolate=extra, **load, **solver_kw)
            except GrossSlipError as exc:
                raise GrossSlipError(
                    "friction.path.amplitude",
                    f"the tangential force {abs(v):.6g} N of step {k + 1} ({path.branch[k]}, cycle {path.cycle[k]}) "
                    f"cannot be carried: the contact carries at most mu F0+ = {exc.max_force:.6g} N there, so the "
                    f"largest reachable amplitude is F* = {exc.max_force:.6g} N "
                    f"({exc.max_force / (mu * start.normal.repulsive_force):.4f} mu F0+ of the start)", exc.max_force) from None
            if not res.converged:
                run.failed.append(k)
            c = int(path.cycle[k])
            # Frictional work per area on this step: q . ds (the slip increment), >= 0 on slip nodes.
            ds = res.tangential.slip
            q = res.tangential.shear
            w = -(q[0] * ds[0] + q[1] * ds[1])
            dl = np.where(res.tangential.contact, np.hypot(ds[0], ds[1]), 0.0)  # slip only where in contact
            diss[c] = w if diss[c] is None else diss[c] + w
            slip[c] = dl if slip[c] is None else slip[c] + dl
            run.steps.append(res)
            run.offsets.append(offset.copy())
            older, prev = prev, res
            if progress:
                progress(k + 1, len(path.values))
        run.dissipation = [d for d in diss if d is not None]
        run.accumulated_slip = [s for s in slip if s is not None]
        if run.failed:
            run.message = f"{len(run.failed)} step(s) did not converge: {run.failed[:10]}"
    return run


def loop_energies(forces, displacements, cycles) -> list:
    """Work of the tangential force over each full cycle (J): |integral of F d(delta)| along the
    cycle's path from its start (the last point of cycle c - 1), trapezoid rule.

    Once the loop is stationary this is the loop area, the energy dissipated per cycle.  A cycle
    that does not end where it began (the first ones after the initial loading, a few per cent of
    the width) also changes the stored elastic energy; closing its polygon would not measure the
    dissipation either.  The traction work ``HysteresisRun.dissipation`` (sum of -q . ds) is the
    dissipation itself, for every cycle.

    Parameters
    ----------
    forces : array_like
        Tangential force (N) at each step.
    displacements : array_like
        Tangential displacement (m) at each step.
    cycles : array_like of int
        Cycle number of each step (0: the initial loading, not counted).

    Returns
    -------
    list of float
        The work (J) of each cycle 1.. that has steps.
    """
    F = np.asarray(forces, float)
    d = np.asarray(displacements, float)
    c = np.asarray(cycles, int)
    out = []
    for cyc in range(1, int(c.max()) + 1 if len(c) else 1):
        idx = np.flatnonzero(c == cyc)
        if len(idx) == 0:
            continue
        first = idx[0] - 1 if idx[0] > 0 else idx[0]
        sel = np.concatenate([[first], idx])
        Fx, dx = F[sel], d[sel]
        out.append(float(abs(np.sum(0.5 * (Fx[1:] + Fx[:-1]) * np.diff(dx)))))
    return out
