"""Load paths: force-approach curves (loading and unloading), jumps, pull-off, hysteresis.

Under displacement control the approach is stepped and every step is warm-started from the
previous one, so the solver follows a branch until it ends; the jump to another branch shows
as a discontinuity of the contact area (jump-in on loading, jump-off on unloading).
Displacement control traces the unstable force branch that force control cannot reach, so
the pull-off force (the most negative force on the curve, Papers A and C) is taken from it
by default.  Under force control the unloading stops at the last force with an
equilibrium: that force is the force-controlled pull-off (jump-off).

A state at a given force can also be reached the way an experiment reaches it, by loading
under displacement control from the first touch and interpolating the force-approach curve
(:func:`solve_at_force`): the pull-off starts there.  This path needs no force-controlled
solve from zero pressure, which on a periodic cell may settle in full contact (the mean
pressure of the periodic kernel is then undetermined) and which stalls for stiff Dugdale laws
on fine grids (Maugis lambda = 5 on 1248^2, see :func:`solve_at_force`).
"""

from __future__ import annotations

import functools
import math
import warnings
from typing import Callable, Sequence

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..errors import ConvergenceWarning, InputError
from ..interactions.hardness import unwrap_cap
from ..results import LoadCurve, NormalResult, PullOff
from .coupling import solve_coupled
from .normal import solve_normal
from .tangential_paths import direction_vector

#: A jump: the contact area changes between two steps by more than this fraction of the
#: larger of the two, and by more than ``JUMP_MIN_FRACTION`` of the branch's largest area
#: (rough contacts change area in many small bursts that are not instabilities of the curve).
JUMP_THRESHOLD = 0.25
JUMP_MIN_FRACTION = 0.05


def _record(curve_rows: list, res: NormalResult, branch: str, keep: bool, store: list):
    row = res.scalars()
    row["branch"] = branch
    curve_rows.append(row)
    if keep:
        store.append(res)


def _assemble(control: str, rows: list, store: list) -> LoadCurve:
    def col(k, dtype=float):
        return np.array([r[k] for r in rows], dtype=dtype)

    curve = LoadCurve(
        control=control,
        branch=np.array([r["branch"] for r in rows], dtype=object),
        approach=col("approach"),
        force=col("normal_force"),
        contact_area=col("contact_area"),
        adhesive_area=col("adhesive_area"),
        repulsive_force=col("repulsive_force"),
        adhesive_force=col("adhesive_force"),
        iterations=col("iterations", int),
        converged=col("converged", bool),
        results=store,
        steps=rows,
    )
    curve.jumps = find_jumps(curve)
    return curve


def find_jumps(curve: LoadCurve, threshold: float = JUMP_THRESHOLD,
               min_fraction: float = JUMP_MIN_FRACTION, slope_factor: float = 2.0) -> list[dict]:
    """Discontinuities of a force-approach curve (jump-in / jump-off) along each branch.

    A step is a jump when (i) the contact area changes by more than ``threshold`` of the
    larger area and by more than ``min_fraction`` of the branch's largest area, and (ii) its
    force-approach slope exceeds ``slope_factor`` times the slopes of both neighbouring
    steps: new asperities touching a rough surface change the area in bursts but leave the
    force continuous, a branch ending makes the force jump.  A step with no neighbouring step
    (a branch of two points) is never a jump: the slope test needs a neighbour.

    Only converged points are considered, each branch on its own.

    Parameters
    ----------
    curve : LoadCurve
        The force-approach curve (approach in m, force in N, contact area in m^2).
    threshold : float
        Relative change of the contact area (dimensionless, fraction of the larger of the two
        areas of the step) above which a step is a jump candidate.
    min_fraction : float
        Least change of the contact area (dimensionless, fraction of the branch's largest contact
        area) of a jump.
    slope_factor : float
        Least ratio (dimensionless) of the step's force-approach slope |dF/d(delta)| (N/m) to the
        larger slope of its neighbouring steps.

    Returns
    -------
    list of dict
        One ``{"index", "branch", "kind", "approach", "force"}`` per jump, loading branch first, in
        curve order: ``index`` (int) is the point just after the jump, ``branch`` "loading" or
        "unloading", ``kind`` "jump-in" (area grows) or "jump-off" (area shrinks), ``approach`` (m)
        and ``force`` (N) those of that point.  Empty if there is none.
    """
    jumps = []
    for name in ("loading", "unloading"):
        idx = np.where((curve.branch == name) & curve.converged)[0]
        if len(idx) < 2:
            continue
        a_max = float(np.max(curve.contact_area[idx]))
        d, f, area = curve.approach[idx], curve.force[idx], curve.contact_area[idx]
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.abs(np.diff(f) / np.diff(d))
        for k in range(len(idx) - 1):
            a0, a1 = area[k], area[k + 1]
            ref = max(a0, a1)
            if ref <= 0 or abs(a1 - a0) <= threshold * ref or abs(a1 - a0) <= min_fraction * a_max:
                continue
            neighbours = [slope[j] for j in (k - 1, k + 1) if 0 <= j < len(slope) and np.isfinite(slope[j])]
            # without a neighbouring step the slope test cannot be made: a branch of two points
            # (e.g. two loads of a Hertz contact, the area growing 4.6 times) shows no jump
            if not neighbours or (np.isfinite(slope[k]) and slope[k] <= slope_factor * max(neighbours)):
                continue
            i1 = int(idx[k + 1])
            kind = "jump-in" if a1 > a0 else "jump-off"
            jumps.append({"index": i1, "branch": name, "kind": kind,
                          "approach": float(curve.approach[i1]), "force": float(curve.force[i1])})
    return jumps


def approach_curve(
    operator: ConvolutionOperator,
    gap,
    approaches: Sequence[float],
    *,
    interaction=None,
    unload: bool = True,
    tol: float = 1e-10,
    max_iterations: int = 10000,
    keep_fields: bool = False,
    progress: Callable[[int, int], None] | None = None,
    method: str = "polonsky_keer",
    precision: str = "double",
) -> LoadCurve:
    """Force-approach curve under displacement control.

    Parameters
    ----------
    operator : ConvolutionOperator
    gap : array_like
        Initial gap h (m).
    approaches : sequence of float
        Approaches (m) of the loading branch, in loading order; the unloading branch runs
        through the same values in reverse.
    interaction : Interaction, optional
    unload : bool
        Also trace the unloading branch.
    tol, max_iterations
        Solver settings for each point.
    keep_fields : bool
        Keep every :class:`NormalResult` (memory: ~6 fields per point).
    progress : callable, optional
        Called as ``progress(done, total)`` after each point.
    method : {"polonsky_keer", "normcg"}
        The normal solver (:func:`~tribobem.solvers.normal.solve_normal`).
    precision : {"double", "single", "auto"}
        NormCG's arithmetic (:func:`~tribobem.solvers.normal_cg.solve_normal_cg`); with
        Polonsky-Keer, double.

    Returns
    -------
    LoadCurve
    """
    approaches = np.asarray(approaches, dtype=float)
    if approaches.ndim != 1 or len(approaches) < 1 or not np.all(np.isfinite(approaches)):
        raise InputError("approach_curve.approaches", "must be a non-empty list of finite approaches (m)")
    plan = [("loading", d) for d in approaches]
    if unload:
        plan += [("unloading", d) for d in approaches[::-1]]
    rows, store, prev = [], [], None
    for k, (branch, d) in enumerate(plan):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_normal(operator, gap, approach=float(d), interaction=interaction, tol=tol,
                               max_iterations=max_iterations, initial_pressure=prev, method=method,
                               precision=_precision(method, precision))
        if not res.converged:
            warnings.warn(f"{branch} point at approach {d:.4g} m: {res.message}", ConvergenceWarning, stacklevel=2)
        _record(rows, res, branch, keep_fields, store)
        prev = res
        if progress:
            progress(k + 1, len(plan))
    return _assemble("displacement", rows, store)


def force_curve(
    operator: ConvolutionOperator,
    gap,
    forces: Sequence[float],
    *,
    interaction=None,
    unload: bool = True,
    tol: float = 1e-10,
    max_iterations: int = 10000,
    keep_fields: bool = False,
    progress: Callable[[int, int], None] | None = None,
    method: str = "polonsky_keer",
    precision: str = "double",
) -> LoadCurve:
    """Force-approach curve under force control.

    The loading branch runs through ``forces`` in order, the unloading branch back in
    reverse.  Where no equilibrium exists (beyond pull-off) the point is recorded as not
    converged, a jump-off is reported at the previous point, and the branch stops.  Other
    parameters as for :func:`approach_curve`.

    Parameters
    ----------
    operator : ConvolutionOperator
        The elastic operator (grid and material).
    gap : array_like
        Initial gap h (m).
    forces : sequence of float
        Total normal forces (N, compressive > 0, tensile < 0 with adhesion) of the loading branch,
        in loading order; the unloading branch runs through the same values in reverse.
    interaction : Interaction, optional
        Adhesive interaction law; None: non-adhesive (hard) contact.
    unload : bool
        Also trace the unloading branch.
    tol : float
        Convergence tolerance of each solve (dimensionless, relative; see
        :func:`~tribobem.solvers.normal.solve_normal`).
    max_iterations : int
        Iteration limit of each solve.
    keep_fields : bool
        Keep every :class:`NormalResult` (memory: ~6 fields per point).
    progress : callable, optional
        Called as ``progress(done, total)`` after each converged point (``total``: number of
        planned points of both branches).
    method : {"polonsky_keer", "normcg"}
        The normal solver (:func:`~tribobem.solvers.normal.solve_normal`).

    Returns
    -------
    LoadCurve
        ``control == "force"``; only converged points are recorded, and ``jumps`` includes the
        force-controlled jump-offs (at the last point with an equilibrium of a branch).

    Raises
    ------
    InputError
        If ``forces`` is not a non-empty 1-D sequence of finite forces, or if no force of it has
        an equilibrium (all beyond pull-off).
    """
    forces = np.asarray(forces, dtype=float)
    if forces.ndim != 1 or len(forces) < 1 or not np.all(np.isfinite(forces)):
        raise InputError("force_curve.forces", "must be a non-empty list of finite forces (N)")
    plan = [("loading", f) for f in forces]
    if unload:
        plan += [("unloading", f) for f in forces[::-1]]
    rows, store, prev = [], [], None
    detached_branch = None
    jump_offs = []
    for k, (branch, f) in enumerate(plan):
        if branch == detached_branch:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_normal(operator, gap, force=float(f), interaction=interaction, tol=tol,
                               max_iterations=max_iterations, initial_pressure=prev, method=method,
                               precision=_precision(method, precision))
        if not res.converged:
            # No equilibrium at this force: the contact jumps off (force control).
            if rows:
                jump_offs.append({"index": len(rows) - 1, "branch": branch, "kind": "jump-off",
                                  "approach": rows[-1]["approach"], "force": rows[-1]["normal_force"]})
            detached_branch = branch
            prev = None
            continue
        _record(rows, res, branch, keep_fields, store)
        prev = res
        if progress:
            progress(k + 1, len(plan))
    if not rows:
        raise InputError("force_curve.forces", "no force of the list has an equilibrium (all beyond pull-off)")
    curve = _assemble("force", rows, store)
    curve.jumps = sorted(curve.jumps + jump_offs, key=lambda j: j["index"])
    return curve


def _precision(method: str, precision: str) -> str:
    """The precision passed to ``solve_normal``: Polonsky-Keer's is double ("auto" there)."""
    return precision if method in ("normcg", "auto") or precision == "double" else "auto"


def _solve_quiet(operator, gap, interaction, tol, max_iterations, initial, method="polonsky_keer", **load):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_normal(operator, gap, interaction=interaction, tol=tol,
                            max_iterations=max_iterations, initial_pressure=initial, method=method, **load)


def _path_step(interaction, rng: float) -> float:
    """The approach step near the law's range (m): the law's ``path_step`` (a smooth law whose
    ``range`` is a far cut), else a quarter of the range."""
    step = getattr(interaction, "path_step", None)
    return float(step) if step else rng / 4.0


def _separated(res: NormalResult) -> bool:
    return not np.any(res.contact) and not np.any(res.adhesive)


def _check_force_target(force, rtol: float) -> float:
    """The target force (N) as a float, after checking it and ``rtol`` (dimensionless)."""
    force = float(force)
    if not math.isfinite(force):
        raise InputError("force", f"must be a finite force (N), got {force!r}")
    if not (0 < rtol < 1):
        raise InputError("rtol", f"must be in (0, 1), got {rtol!r}")
    return force


def _first_step(gap, interaction) -> tuple[np.ndarray, float, float]:
    """The gap and the lengths that set the approach steps of :func:`solve_at_force`.

    Parameters
    ----------
    gap : array_like
        Initial gap (m).
    interaction : optional
        The interaction law; its ``range`` (m), if any, sets the steps.

    Returns
    -------
    h : ndarray
        The gap as a float array (m).
    rng : float
        Interaction range (m), 0 without one.
    first : float
        First approach step (m), > 0.
    """
    rng = float(getattr(interaction, "range", 0.0) or 0.0)
    h = np.asarray(gap, dtype=float)
    # First step: a quarter of the interaction range, or a thousandth of the gap's relief.
    first = _path_step(interaction, rng) if rng > 0 else 1e-3 * float(np.ptp(h))
    if not first > 0:
        first = 1e-12
    return h, rng, first


class _ForcePath:
    """The displacement-controlled solves of one :func:`solve_at_force` path and their counts.

    Parameters
    ----------
    operator, h, interaction, tol, max_iterations
        As for :func:`~tribobem.solvers.normal.solve_normal` (``h``: the gap, m).
    force : float
        Target total force (N).
    rtol : float
        Tolerance on the force, relative to ``scale`` (dimensionless).
    max_solves : int
        Upper bound on the solves.
    progress : callable or None
        ``progress(solves, max_solves)`` after each step.

    Attributes
    ----------
    scale : float
        What ``rtol`` is relative to (N): ``|force|`` until the start of the path is known.
    solves : int
        Solves so far.
    fallbacks : int
        States of the path that only NormCG completed.
    """

    def __init__(self, operator, h, force, *, interaction, rtol, tol, max_iterations, max_solves, progress):
        self.operator, self.h, self.interaction = operator, h, interaction
        self.force, self.rtol, self.tol, self.max_iterations = force, rtol, tol, max_iterations
        self.max_solves, self.progress = max_solves, progress
        self.scale = abs(force)
        self.solves = 0
        self.cold_up = False  # set once a warm-started loading step has failed where a cold one converged
        self.fallbacks = 0
        self.cold_failed = set()  # approaches (m) where a cold solve did not converge
        # a hardness cap: every trial of the search loads from the plastic state of the path's
        # start (monotone loading), so that a trial beyond the target leaves no flattening behind
        self.cap = unwrap_cap(interaction)[1]
        self.base = self.cap.plastic if self.cap is not None else None

    def _solve(self, warm, method="polonsky_keer", **load):
        if self.cap is not None:
            self.cap.plastic = self.base
        return _solve_quiet(self.operator, self.h, self.interaction, self.tol, self.max_iterations, warm,
                            method=method, **load)

    def report(self):
        """Tell ``progress`` how many solves have run."""
        if self.progress:
            self.progress(self.solves, self.max_solves)

    def within(self, res: NormalResult) -> bool:
        """Whether the force (N) of ``res`` is within the tolerance of the target."""
        return abs(res.force - self.force) <= self.rtol * self.scale

    def normcg(self, d, warm):
        """NormCG at approach ``d`` (m) from the state ``warm``.

        Last resort, where Polonsky-Keer failed the step warm and cold (and, on the stepping,
        at every shorter step).  Polonsky-Keer restarts its CG at every change of the contact
        set; with a stiff step law on a fine grid the ring of edge nodes can change at every
        iteration and the iteration stalls (Maugis lambda = 5 on 1248^2, 'no progress in 2000
        iterations' warm and cold).  NormCG keeps its conjugate directions across the changes
        (187 iterations on a loading step there).  Only where the path would otherwise end, so
        that every path Polonsky-Keer completes keeps its equilibria.  The caller counts the
        states it takes from it.
        """
        self.solves += 1
        return self._solve(warm, method="normcg", approach=float(d))

    def solve(self, d, warm, fallback=False):
        """Polonsky-Keer at approach ``d`` (m) from ``warm`` (None: cold), cold if that fails.

        With ``fallback``, NormCG from ``warm`` where both fail.
        """
        loading = warm is not None and d > warm.approach
        res = self._solve(None if (self.cold_up and loading) else warm, approach=float(d))
        self.solves += 1
        if not res.converged and warm is not None and not (self.cold_up and loading) and d > 0 \
                and d not in self.cold_failed:
            # A warm start from a smaller contact can stall where a cold solve at a compressive
            # approach converges (Maugis lambda = 5 on 1248^2: 2500-4500 iterations warm, 1500
            # cold); a cold start at a positive approach lands on the contact branch.  A cold
            # solve is the same at the same approach: one that failed is not tried again.
            cold = self._solve(None, approach=float(d))
            self.solves += 1
            if cold.converged:
                res, self.cold_up = cold, self.cold_up or loading
            else:
                self.cold_failed.add(d)
        if not res.converged and warm is not None and fallback:
            res = self.normcg(d, warm)
            self.fallbacks += int(res.converged)
        self.report()
        return res

    def finish(self, res: NormalResult, full: bool = False) -> NormalResult:
        """``res`` with the path's entries added to its ``info`` (see :func:`solve_at_force`)."""
        res.info = dict(res.info or {}, target_force=self.force, force_scale=self.scale, solves=self.solves,
                        full_contact=bool(full), normcg_fallbacks=self.fallbacks)
        if self.cap is not None:
            # the body keeps the flattening of the state the path ends on
            self.cap.plastic = res.plastic_displacement if res.plastic_displacement is not None else self.base
        return res


def _start_state(path: _ForcePath, start: NormalResult | None) -> NormalResult:
    """The state the path starts from: ``start``, or the first touch (approach 0).

    Sets ``path.scale`` (N) to the larger of the target force and the start's force.
    """
    if start is not None:
        if not start.converged or not math.isfinite(start.approach):
            raise InputError("start", "must be a converged state with a finite approach")
        cur = start
    else:
        cur = path.solve(0.0, None)
        if not cur.converged:
            raise InputError("force", f"the first touch (approach 0) has no converged solution: {cur.message}")
    path.scale = max(abs(path.force), abs(cur.force))
    return cur


def _next_approach(cur, prev, step, force, up, rng, d_full):
    """The approach (m) of the next step of the bracketing, from ``cur`` by about ``step`` (m).

    ``prev`` is the state before ``cur`` (None at the start), ``force`` the target (N), ``up``
    whether the force must grow, ``rng`` the interaction range (m), ``d_full`` the approach
    of full contact (m, inf on a free boundary).
    """
    d = cur.approach + step
    if prev is not None and cur.force != prev.force:
        # secant extrapolation to the target, within [1, 4] times the last step
        d_sec = cur.approach + (force - cur.force) * (cur.approach - prev.approach) / (cur.force - prev.force)
        s = d_sec - cur.approach
        if s * step > 0:
            d = cur.approach + math.copysign(min(max(abs(s), abs(step)), 4 * abs(step)), step)
    if not up and rng > 0 and cur.force < 0:
        # towards a tensile target: small steps keep the state on its branch
        d = max(d, cur.approach - rng / 4.0)
    if up:
        d = min(d, d_full)
    return d


def _take_step(path: _ForcePath, cur, d, up, rng, first):
    """Solve the step from ``cur`` to approach ``d`` (m), shortened or by NormCG where it fails.

    Returns the approach (m) of the step taken and its state (unconverged, or separated on the
    unloading, where the branch ends).
    """
    nxt = path.solve(d, cur)
    d_step = d
    halvings = 0
    min_step = rng / 4.0 if rng > 0 else first
    while (not nxt.converged or (not up and _separated(nxt))) and halvings < 8 and path.solves < path.max_solves \
            and (up or abs(d - cur.approach) > min_step):
        # a step too long (for the solver, or past the end of the branch): shorten it; the
        # branch ends (no equilibrium) only where a step of h0/4 separates the bodies
        d = 0.5 * (cur.approach + d)
        nxt = path.solve(d, cur)
        halvings += 1
    if not nxt.converged and path.solves < path.max_solves:
        # Polonsky-Keer failed the step and every shortened one: NormCG, on the whole step
        # (a shortened one would leave the path crawling), else on the shortest
        d_short, d, nxt = d, d_step, path.normcg(d_step, cur)
        if (not nxt.converged or (not up and _separated(nxt))) and d_short != d_step \
                and path.solves < path.max_solves:
            d, nxt = d_short, path.normcg(d_short, cur)
        path.fallbacks += int(nxt.converged and (up or not _separated(nxt)))
        path.report()
    return d, nxt


def _short_of_full_contact(path: _ForcePath, cur, nxt) -> NormalResult:
    """The last state short of full contact, between ``cur`` and ``nxt`` (in full contact).

    Full contact (periodic cell): the force no longer follows the approach.  Bisect towards
    the threshold so that the state returned is the last one short of it.
    """
    d_in = nxt.approach
    for _ in range(6):
        if path.solves >= path.max_solves:
            break
        trial = path.solve(0.5 * (cur.approach + d_in), cur)
        if not trial.converged or np.all(trial.contact):
            d_in = trial.approach
        else:
            cur = trial
            if path.within(trial) or trial.force > path.force:
                return path.finish(trial)
    return path.finish(cur, full=True)


def _bracket(path: _ForcePath, cur, up, first, rng, d_full):
    """Step the approach from ``cur`` until the force brackets the target.

    Returns ``(cur, nxt, None)``, the target force between those of the two states, or
    ``(None, None, state)`` where a state ends the search (within the tolerance, or the last
    one short of full contact).  ``first`` is the first step (m), ``rng`` the interaction
    range (m), ``d_full`` the approach of full contact (m).
    """
    force = path.force
    prev, step = None, (first if up else -first)
    while True:
        if path.solves >= path.max_solves:
            raise InputError("force", f"no bracket of {force:.4g} N within {path.max_solves} solves "
                                      f"(last: {cur.force:.4g} N at approach {cur.approach:.4g} m)")
        d = _next_approach(cur, prev, step, force, up, rng, d_full)
        d, nxt = _take_step(path, cur, d, up, rng, first)
        if not nxt.converged or (not up and _separated(nxt)):
            raise InputError("force", f"no equilibrium at {force:.4g} N on this branch: the contact "
                                      f"{'separates' if nxt.converged else 'has no converged state'} at approach "
                                      f"{d:.4g} m (force {cur.force:.4g} N just before)")
        if up and (np.all(nxt.contact) or d >= d_full):
            return None, None, _short_of_full_contact(path, cur, nxt)
        if path.within(nxt):
            return None, None, path.finish(nxt)
        if (nxt.force > force) == up:  # bracketed between cur and nxt
            return cur, nxt, None
        prev, cur, step = cur, nxt, d - cur.approach


def _regula_falsi(path: _ForcePath, cur, nxt, up) -> NormalResult:
    """Refine the bracket ``cur``, ``nxt`` by regula falsi (Illinois) on the approach.

    Returns the first state within the tolerance, else (with a :class:`ConvergenceWarning`)
    the nearest to the target of those found.
    """
    force = path.force
    # Regula falsi (Illinois) on [lo, hi] with F(lo) < force < F(hi).
    lo, hi = (cur, nxt) if up else (nxt, cur)
    f_lo, f_hi = lo.force - force, hi.force - force
    best = min((lo, hi), key=lambda r: abs(r.force - force))
    side = 0
    while path.solves < path.max_solves:
        d = (lo.approach * f_hi - hi.approach * f_lo) / (f_hi - f_lo)
        warm = lo if abs(d - lo.approach) < abs(d - hi.approach) else hi
        res = path.solve(d, warm, fallback=True)  # a failure here would end the refinement
        if not res.converged:
            break
        if abs(res.force - force) < abs(best.force - force):
            best = res
        if path.within(res):
            return path.finish(res)
        if res.force < force:
            lo, f_lo = res, res.force - force
            if side == -1:
                f_hi /= 2.0
            side = -1
        else:
            hi, f_hi = res, res.force - force
            if side == 1:
                f_lo /= 2.0
            side = 1
    # stacklevel 3: the warning points at the caller of solve_at_force
    warnings.warn(f"solve_at_force: {force:.4g} N reached to {abs(best.force - force):.3g} N after {path.solves} "
                  f"solves (tolerance {path.rtol * path.scale:.3g} N)", ConvergenceWarning, stacklevel=3)
    return path.finish(best)


def solve_at_force(
    operator: ConvolutionOperator,
    gap,
    force: float,
    *,
    interaction=None,
    rtol: float = 1e-3,
    tol: float = 1e-10,
    max_iterations: int = 10000,
    max_solves: int = 60,
    start: NormalResult | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> NormalResult:
    """The state at a total force, reached by loading under displacement control.

    The way an experiment reaches a load: the bodies touch (approach 0, the minimum of the
    gap), then the approach is stepped, every solve warm-started from the previous one, until
    the force brackets ``force``; the approach is then refined by regula falsi (Illinois) on the
    force-approach curve, each solve warm-started from the nearer end of the bracket, until
    the force is within ``rtol`` of the target.  Steps grow by secant extrapolation of the curve
    (at most 4 times the previous step); towards a tensile target they are kept to a quarter of
    the interaction range, so the state stays on the branch it started on.

    Use it where a cold force-controlled solve fails:

    * a periodic cell may settle in full contact from zero pressure, where the force is not
      determined by the approach; here the loading stops at the last state short of full
      contact (``info["full_contact"]`` is True when the target lies beyond it);
    * for stiff Dugdale laws on fine grids the cold force-controlled Polonsky-Keer iteration
      can stall (Maugis lambda = 5, 1248^2: 'no progress in 2000 iterations' at
      F = pi R dgamma).

    Each step is a Polonsky-Keer solve warm-started from the last state; if it fails, a cold
    one at a compressive approach, then shorter steps.  Where all of these fail (the path would
    end there), NormCG from the same warm start completes the step (``info["normcg_fallbacks"]``
    counts these steps).  Polonsky-Keer restarts its CG at every change of the contact set, and
    with a stiff step law on a fine grid the ring of edge nodes can change at every iteration
    (lambda = 5 on 1248^2: steps of the loading and of the unloading towards F = 0 stall);
    NormCG keeps its directions across such changes.

    Parameters
    ----------
    operator, gap, interaction
        As for :func:`~tribobem.solvers.normal.solve_normal`.
    force : float
        Target total force (N); may be tensile with adhesion.
    rtol : float
        Tolerance on the force, relative to max(|force|, |force at the first touch|) (the
        latter for a target near zero).
    tol, max_iterations
        Settings of each solve.
    max_solves : int
        Upper bound on the solves.
    start : NormalResult, optional
        A converged state to continue from instead of the first touch (e.g. the previous target
        of a series of forces along one branch).
    progress : callable, optional
        ``progress(solves, max_solves)`` after each solve.

    Returns
    -------
    NormalResult
        Displacement-controlled (``control == "displacement"``); ``info`` gains ``"target_force"``,
        ``"force_scale"`` (what ``rtol`` is relative to), ``"solves"``, ``"full_contact"`` and
        ``"normcg_fallbacks"``.

    Raises
    ------
    InputError
        If no state of the branch reaches the force (a tensile force beyond the pull-off, or
        the bracket not found within ``max_solves``).
    """
    force = _check_force_target(force, rtol)
    h, rng, first = _first_step(gap, interaction)
    # A periodic cell is in full contact at the approach of its mean gap (the periodic kernel
    # keeps the mean displacement at zero): no state lies beyond it.
    d_full = float(np.mean(h)) if operator.grid.periodic else math.inf
    path = _ForcePath(operator, h, force, interaction=interaction, rtol=rtol, tol=tol,
                      max_iterations=max_iterations, max_solves=max_solves, progress=progress)
    cur = _start_state(path, start)
    if path.within(cur):
        return path.finish(cur)
    up = cur.force < force
    cur, nxt, final = _bracket(path, cur, up, first, rng, d_full)
    if final is not None:
        return final
    return _regula_falsi(path, cur, nxt, up)


def _check_pull_off_args(interaction, preload, control: str, start: str) -> None:
    """Check the arguments of :func:`pull_off` (``preload`` in N)."""
    if interaction is None:
        raise InputError("adhesion", "pull-off needs an adhesive interaction")
    if preload is not None and not preload > 0:
        raise InputError("pull_off.preload", f"must be > 0 N (or left out: zero external load), got {preload!r}")
    if control not in ("displacement", "force"):
        raise InputError("control", f"must be 'displacement' or 'force', got {control!r}")
    if start not in ("approach", "force"):
        raise InputError("start", f"must be 'approach' or 'force', got {start!r}")


def _preload_notes(operator, interaction, target: float, state0: NormalResult) -> list[str]:
    """What the loading to the preload ``target`` (N) had to give way to, for the run's warnings.

    ``state0`` is the state :func:`solve_at_force` reached.
    """
    notes = []
    if state0.info.get("full_contact"):
        notes.append(f"preload: the periodic cell reaches full contact below the preload {target:.4g} N; the "
                     f"unloading starts from the last state short of full contact ({state0.force:.4g} N at "
                     f"approach {state0.approach:.4g} m)")
    elif abs(state0.force - target) > 1e-3 * max(state0.info.get("force_scale", abs(target)),
                                                 abs(interaction.floor) * operator.grid.cell_area):
        # solve_at_force missed its tolerance (rtol 1e-3: a jump of the force-approach curve
        # or a solve that did not converge next to the target; at zero load relative to the
        # force of one cell at the floor): say so, not only in a warning
        notes.append(f"preload: the loading reached {state0.force:.4g} N, not {target:.4g} N (no converged "
                     f"state within 0.1 % of it on the force-approach curve); the unloading starts there")
    if state0.info.get("normcg_fallbacks"):
        # the path mixes two solvers of a multistable problem: say so
        notes.append(f"preload: the loading needed NormCG on {state0.info['normcg_fallbacks']} step(s) where "
                     "Polonsky-Keer did not converge; the preload state may be another of the discrete Dugdale "
                     "equilibria than Polonsky-Keer's (compare on a finer grid)")
    return notes


def _preload_state(operator, gap, interaction, target: float, start: str, tol: float,
                   max_iterations: int) -> tuple[NormalResult, list[str]]:
    """The state the unloading of :func:`pull_off` starts from, at the force ``target`` (N).

    Reached as ``start`` says (``"force"``: force-controlled from zero pressure; ``"approach"``:
    :func:`solve_at_force`).  Returns it and the notes on what the start had to give way to.
    """
    if start == "force":
        state0 = _solve_quiet(operator, gap, interaction, tol, max_iterations, None, force=target)
        if not state0.converged:
            raise InputError("pull_off.preload", f"the preload has no converged solution: {state0.message}")
        return state0, []
    try:
        state0 = solve_at_force(operator, gap, target, interaction=interaction, tol=tol,
                                max_iterations=max_iterations)
    except InputError as exc:
        raise InputError("pull_off.preload", f"the preload cannot be reached: {exc}") from None
    return state0, _preload_notes(operator, interaction, target, state0)


def _unloading_forces(start_force: float, f_min: float, n_steps: int) -> np.ndarray:
    """The forces (N) of the force-controlled unloading from ``start_force`` down to ``f_min``."""
    forces = np.linspace(start_force, f_min, n_steps + 1)[1:]
    if start_force > 0.0 and 0.0 not in forces:
        # Zero load is an equilibrium of an adhesive contact (the start without a preload):
        # step through it, so that a first tensile step beyond the pull-off (coarse steps, few
        # bisections) cannot leave a compressive force as the pull-off force.
        forces = np.sort(np.append(forces, 0.0))[::-1]
    return forces


def _pull_off_by_force(solve, operator, interaction, state0, notes, n_steps, refine, progress) -> PullOff:
    """Force-controlled pull-off: step the force down, then bisect at the first failure.

    ``solve(initial, force=...)`` is a force-controlled solve (N); the other arguments are
    those of :func:`pull_off` (``state0``: the start, ``notes``: the start's notes).
    """
    # Lower bound of any tensile force: sigma0 over the whole domain.
    f_min = interaction.floor * operator.grid.area
    forces = _unloading_forces(state0.force, f_min, n_steps)
    total = len(forces) + 2 * refine
    rows, store = [], []
    prev, f_ok, f_fail = state0, state0.force, None
    _record(rows, state0, "unloading", False, store)
    for k, f in enumerate(forces):
        res = solve(prev, force=float(f))
        if progress:
            progress(k + 1, total)
        if not res.converged:
            f_fail = float(f)
            break
        _record(rows, res, "unloading", False, store)
        prev, f_ok = res, float(f)
    if f_fail is not None:
        # bisect between the last force with an equilibrium and the first without
        for k in range(refine):
            f = 0.5 * (f_ok + f_fail)
            res = solve(prev, force=f)
            if progress:
                progress(len(forces) + k + 1, total)
            if res.converged:
                _record(rows, res, "unloading", False, store)
                prev, f_ok = res, f
            else:
                f_fail = f
    rows.sort(key=lambda r: -r["normal_force"])
    curve = _assemble("force", rows, store)
    if f_fail is not None:
        curve.jumps.append({"index": len(rows) - 1, "branch": "unloading", "kind": "jump-off",
                            "approach": prev.approach, "force": prev.force})
    return PullOff(prev.force, prev.approach, curve, prev, state0, notes)


def _unload_by_approach(solve, interaction, state0, n_steps, max_steps, keep_fields, total, progress):
    """Unload by a quasi-static continuation on the approach from ``state0`` until separation.

    Coarse steps while the contact is compressive, then steps of a quarter of the interaction
    range once the force turns tensile (a larger step can jump to another metastable branch of
    a rough contact), until the bodies have separated.  ``solve(initial, approach=...)`` is a
    displacement-controlled solve (m).

    Returns
    -------
    rows, store : list
        The curve's rows and (with ``keep_fields``) states.
    best : tuple
        (force (N), row index, state just above that point) of the most negative force; the
        index is None where no state converged.
    best_state : NormalResult or None
        The state at that point.
    """
    rng = float(getattr(interaction, "range", 0.0)) or 1e-3 * max(abs(state0.approach), 1e-12)
    d_hi = state0.approach
    fine = _path_step(interaction, rng)
    coarse = max((d_hi - 0.0) / max(n_steps // 2, 1), fine)
    rows, store = [], []
    prev, d = state0, d_hi
    best_state = None
    best = (np.inf, None, None)  # (force, row index, result just above that point)
    _record(rows, state0, "unloading", keep_fields, store)  # the curve starts at the preload
    k = 0
    while k < max_steps:
        step = fine if (prev.force < 0.0 or d - coarse < 0.0) else coarse
        d -= step
        res = solve(prev, approach=float(d))
        _record(rows, res, "unloading", keep_fields, store)
        if res.converged and res.force < best[0]:
            best = (res.force, len(rows) - 1, prev)
            best_state = res
        prev = res
        k += 1
        if progress:
            progress(k, total)
        if res.contact_area == 0 and res.adhesive_area == 0:
            break
    else:
        # stacklevel 3: the warning points at the caller of pull_off
        warnings.warn(f"pull-off: the bodies had not separated after {max_steps} steps", ConvergenceWarning, stacklevel=3)
    return rows, store, best, best_state


def _refine_minimum(solve, rows, store, i, above, state, *, refine, keep_fields, max_steps, total, progress):
    """Refine the minimum of the force at row ``i`` by a finer continuation from ``above``.

    ``2 refine - 1`` steps between the approaches of rows ``i - 1`` and ``i + 1``, from the
    state just above the minimum; ``state`` is the state at row ``i``.  Returns the rows and
    states (sorted by decreasing approach) and the pull-off force (N), approach (m) and state.
    """
    result_force, result_approach = float(rows[i]["normal_force"]), float(rows[i]["approach"])
    if refine > 0 and 0 < i < len(rows) - 1:
        d0, d1 = float(rows[i - 1]["approach"]), float(rows[i + 1]["approach"])
        prev = above
        for k, d in enumerate(np.linspace(d0, d1, 2 * refine + 1)[1:-1]):
            res = solve(prev, approach=float(d))
            prev = res
            if progress:
                progress(max_steps + k, total)
            if res.converged and res.force < result_force:
                result_force, result_approach, state = res.force, res.approach, res
                _record(rows, res, "unloading", keep_fields, store)
        order = np.argsort([-r["approach"] for r in rows], kind="stable")
        rows = [rows[j] for j in order]
        if keep_fields:
            store = [store[j] for j in order]
    return rows, store, result_force, result_approach, state


def pull_off(
    operator: ConvolutionOperator,
    gap,
    interaction,
    *,
    preload: float | None = None,
    control: str = "displacement",
    n_steps: int = 40,
    refine: int = 8,
    tol: float = 1e-9,
    max_iterations: int = 10000,
    max_steps: int = 400,
    keep_fields: bool = False,
    start: str = "approach",
    progress: Callable[[int, int], None] | None = None,
) -> PullOff:
    """Pull-off force of an adhesive contact, by unloading from a preload.

    The start: the state at the preload, reached by loading under displacement control from
    the first touch (:func:`solve_at_force`, ``start="approach"``, the default; the force within
    0.1 %), or by a force-controlled solve from zero pressure (``start="force"``, the method
    before solver version 2).  Without a preload the unloading starts from the adhesive
    equilibrium at zero external load (F = 0 on the contact branch).  A periodic cell that
    reaches full contact below the preload starts from its last state short of full contact (the
    unloading of a fully bonded cell has no contact edge to follow); ``notes`` says so.

    Displacement control (default): unload by continuation from the start: about
    ``n_steps / 2`` steps down to zero approach, then steps of h0 / 4 (a quarter of the
    interaction range) once the force is tensile, until the bodies have separated; every solve
    is warm-started from the previous one, so the curve follows the branch being unloaded.  The
    minimum is refined by ``2 refine - 1`` finer continuation steps between its neighbours.

    Force control: step the force down from the preload; at the first force without
    equilibrium, bisect (``refine`` times) between it and the last force with one.  The last
    force with an equilibrium is the force-controlled pull-off (jump-off).

    Parameters
    ----------
    operator, gap, interaction
        As for :func:`solve_normal` (``interaction`` is required).
    preload : float, optional
        Compressive force (N, > 0) from which the unloading starts; None: zero external load.
    control : {"displacement", "force"}
    n_steps : int
        Unloading steps (force control), twice the number of coarse steps (displacement).
    refine : int
        Refinement of the minimum (finer continuation) or bisections (force control).
    max_steps : int
        Upper bound on the unloading steps under displacement control.
    keep_fields : bool
        Keep every :class:`NormalResult` in ``curve.results``.
    tol : float
        Convergence tolerance of each solve (dimensionless).
    max_iterations : int
        Iteration limit of each solve.
    start : {"approach", "force"}
        How the preload state is reached (see above).
    progress : callable, optional
        Called as ``progress(done, total)`` after each solve.

    Returns
    -------
    PullOff
        ``force`` (N, the pull-off force: the most negative force of the unloading curve under
        displacement control, the last force with an equilibrium under force control),
        ``approach`` (m) at it, the unloading ``curve`` (:class:`LoadCurve`, approach in m, force
        in N), the ``state`` at pull-off, the ``preload_state`` the unloading started from, and
        ``notes`` on what the start had to give way to.

    Raises
    ------
    InputError
        If ``interaction`` is None, ``preload`` is not > 0 N, ``control`` or ``start`` is not one
        of the values above, the preload state cannot be reached (no converged solution), or no
        point of the unloading curve converged (displacement control).
    """
    _check_pull_off_args(interaction, preload, control, start)
    target = 0.0 if preload is None else float(preload)
    state0, notes = _preload_state(operator, gap, interaction, target, start, tol, max_iterations)
    solve = functools.partial(_solve_quiet, operator, gap, interaction, tol, max_iterations)
    if control == "force":
        return _pull_off_by_force(solve, operator, interaction, state0, notes, n_steps, refine, progress)
    total = max_steps + 2 * refine
    rows, store, best, best_state = _unload_by_approach(solve, interaction, state0, n_steps, max_steps,
                                                        keep_fields, total, progress)
    _, i, above = best
    if i is None:
        raise InputError("adhesion", "no point of the unloading curve converged")
    rows, store, result_force, result_approach, state = _refine_minimum(
        solve, rows, store, i, above, best_state, refine=refine, keep_fields=keep_fields, max_steps=max_steps,
        total=total, progress=progress)
    curve = _assemble("displacement", rows, store)
    return PullOff(result_force, result_approach, curve, state, state0, notes)


def normal_path(
    operator,
    gap,
    *,
    normal_forces: Sequence[float],
    friction_coefficient: float,
    tangential_forces: Sequence[float] | None = None,
    direction: float = 0.0,
    interaction=None,
    slip: str = "incremental",
    progress: Callable[[int, int], None] | None = None,
    **solver_kw,
) -> list:
    """A normal-load path with friction, the tangential state carried step to step.

    Parameters
    ----------
    normal_forces : sequence of float
        Normal force of each step (N).
    tangential_forces : sequence of float, optional
        Tangential force along ``direction`` of each step (N), paired with ``normal_forces``;
        default 0.
    slip : {"incremental", "total"}
        "incremental" (default) carries the history (the reference of a step is the previous
        step's relative displacement; a node entering the contact takes it as well).

    Returns
    -------
    list of CoupledResult
        One per step.  A step with a force beyond mu F0+ raises GrossSlipError.
    """
    e = direction_vector(direction)
    forces = [float(f) for f in normal_forces]
    if tangential_forces is None:
        tangential_forces = [0.0] * len(forces)
    if len(tangential_forces) != len(forces):
        raise InputError("normal_path.tangential_forces", f"must pair with load.forces: {len(tangential_forces)} "
                                                       f"values for {len(forces)} normal forces")
    out: list = []
    prev = None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        for k, (fn, ft) in enumerate(zip(forces, tangential_forces)):
            ref = prev.tangential.relative_displacement if (prev is not None and slip == "incremental") else None
            res = solve_coupled(operator, gap, friction_coefficient=friction_coefficient, normal_force=fn,
                                tangential_force=tuple(float(ft) * e), interaction=interaction, reference=ref,
                                initial=prev, **solver_kw)
            out.append(res)
            prev = res
            if progress:
                progress(k + 1, len(forces))
    return out
