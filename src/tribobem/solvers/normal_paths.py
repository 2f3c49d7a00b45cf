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

import math
import warnings
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..errors import ConvergenceWarning, InputError
from ..results import NormalResult
from .normal import solve_normal

#: A jump: the contact area changes between two steps by more than this fraction of the
#: larger of the two, and by more than ``JUMP_MIN_FRACTION`` of the branch's largest area
#: (rough contacts change area in many small bursts that are not instabilities of the curve).
JUMP_THRESHOLD = 0.25
JUMP_MIN_FRACTION = 0.05


@dataclass
class LoadCurve:
    """A force-approach curve with its loading and unloading branches.

    Attributes
    ----------
    control : {"displacement", "force"}
    branch : ndarray of str
        "loading" or "unloading" for each point.
    approach, force : ndarray
        Rigid approach (m) and total normal force (N) of each point.
    contact_area, adhesive_area : ndarray
        m^2.
    repulsive_force, adhesive_force : ndarray
        F0+ and F0- (N).
    iterations : ndarray of int
    converged : ndarray of bool
    jumps : list of dict
        ``{"index", "branch", "kind" ("jump-in" | "jump-off"), "approach", "force"}``.
    results : list of NormalResult
        Full fields per point (only when ``keep_fields=True``; else empty).
    steps : list of dict
        The scalar summary of each point (:meth:`NormalResult.scalars` plus ``"branch"``; SI units).
    """

    control: str
    branch: np.ndarray
    approach: np.ndarray
    force: np.ndarray
    contact_area: np.ndarray
    adhesive_area: np.ndarray
    repulsive_force: np.ndarray
    adhesive_force: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    jumps: list = field(default_factory=list)
    results: list = field(default_factory=list)
    steps: list = field(default_factory=list)

    @property
    def pull_off_force(self) -> float:
        """Most negative force on the curve (N); 0 if the curve has no tensile point."""
        ok = self.converged
        if not np.any(ok):
            return float("nan")
        return float(min(np.min(self.force[ok]), 0.0))

    @property
    def pull_off_approach(self) -> float:
        """Approach (m) of the converged point with the most negative force; NaN if no point converged.

        Unlike :attr:`pull_off_force` it is not clipped at zero: without a tensile point it is the
        approach of the smallest (compressive) force.
        """
        ok = np.where(self.converged)[0]
        if not len(ok):
            return float("nan")
        return float(self.approach[ok[np.argmin(self.force[ok])]])

    def branch_mask(self, name: str) -> np.ndarray:
        """Which points of the curve lie on a branch.

        Parameters
        ----------
        name : {"loading", "unloading"}
            The branch.

        Returns
        -------
        ndarray of bool
            True for each point of branch ``name`` (same length as :attr:`approach`; converged or not).
        """
        return self.branch == name

    @property
    def hysteresis_energy(self) -> float:
        """Energy (J) lost over the load cycle: the area between the loading and unloading
        force-approach branches, integral of (F_loading - F_unloading) d(delta) over the
        approaches both branches cover (displacement control)."""
        lo, un = self.branch_mask("loading") & self.converged, self.branch_mask("unloading") & self.converged
        if lo.sum() < 2 or un.sum() < 2:
            return float("nan")
        dl, fl = self.approach[lo], self.force[lo]
        du, fu = self.approach[un], self.force[un]
        order_l, order_u = np.argsort(dl), np.argsort(du)
        dl, fl, du, fu = dl[order_l], fl[order_l], du[order_u], fu[order_u]
        grid = np.union1d(dl, du)
        grid = grid[(grid >= max(dl[0], du[0])) & (grid <= min(dl[-1], du[-1]))]
        if len(grid) < 2:
            return float("nan")
        diff = np.interp(grid, dl, fl) - np.interp(grid, du, fu)
        return float(np.sum(0.5 * (diff[1:] + diff[:-1]) * np.diff(grid)))

    def scalars(self) -> list[dict]:
        """One summary.json step entry per point (file-contract keys)."""
        return self.steps


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
    force continuous, a branch ending makes the force jump.

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
            if neighbours and np.isfinite(slope[k]) and slope[k] <= slope_factor * max(neighbours):
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
                               max_iterations=max_iterations, initial_pressure=prev, method=method)
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
                               max_iterations=max_iterations, initial_pressure=prev, method=method)
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


@dataclass
class PullOff:
    """Pull-off of an adhesive contact.

    Attributes
    ----------
    force : float
        Pull-off force (N), the most negative force on the unloading curve (negative).
    approach : float
        Approach at pull-off (m).
    curve : LoadCurve
        The unloading curve it was taken from.
    state : NormalResult
        The solution at pull-off (pressure, gap, contact and cohesive zone).
    preload_state : NormalResult
        The state the unloading started from (its ``force`` is the preload actually applied).
    notes : list of str
        What the start had to give way to (e.g. a periodic cell in full contact below the
        requested preload), for the run's warnings.
    """

    force: float
    approach: float
    curve: LoadCurve
    state: NormalResult | None = None
    preload_state: NormalResult | None = None
    notes: list = field(default_factory=list)

    @property
    def preload(self) -> float:
        """The force (N) of the state the unloading started from."""
        return float(self.preload_state.force) if self.preload_state is not None else math.nan


def _solve_quiet(operator, gap, interaction, tol, max_iterations, initial, method="polonsky_keer", **load):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_normal(operator, gap, interaction=interaction, tol=tol,
                            max_iterations=max_iterations, initial_pressure=initial, method=method, **load)


def _separated(res: NormalResult) -> bool:
    return not np.any(res.contact) and not np.any(res.adhesive)


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
    force = float(force)
    if not math.isfinite(force):
        raise InputError("force", f"must be a finite force (N), got {force!r}")
    if not (0 < rtol < 1):
        raise InputError("rtol", f"must be in (0, 1), got {rtol!r}")
    rng = float(getattr(interaction, "range", 0.0) or 0.0)
    h = np.asarray(gap, dtype=float)
    # First step: a quarter of the interaction range, or a thousandth of the gap's relief.
    first = rng / 4.0 if rng > 0 else 1e-3 * float(np.ptp(h))
    if not first > 0:
        first = 1e-12
    # A periodic cell is in full contact at the approach of its mean gap (the periodic kernel
    # keeps the mean displacement at zero): no state lies beyond it.
    d_full = float(np.mean(h)) if operator.grid.periodic else math.inf
    solves = 0
    scale = abs(force)

    cold_up = False  # set once a warm-started loading step has failed where a cold one converged
    fallbacks = 0  # states of the path that only NormCG completed
    cold_failed = set()  # approaches (m) where a cold solve did not converge

    def normcg(d, warm):
        # Last resort, where Polonsky-Keer failed the step warm and cold (and, on the stepping,
        # at every shorter step): NormCG from the same warm start.  Polonsky-Keer restarts its
        # CG at every change of the contact set; with a stiff step law on a fine grid the ring
        # of edge nodes can change at every iteration and the iteration stalls (Maugis
        # lambda = 5 on 1248^2, 'no progress in 2000 iterations' warm and cold).  NormCG keeps
        # its conjugate directions across the changes (187 iterations on a loading step there).
        # Only where the path would otherwise end, so that every path Polonsky-Keer completes
        # keeps its equilibria.  The caller counts the states it takes from it.
        nonlocal solves
        solves += 1
        return _solve_quiet(operator, h, interaction, tol, max_iterations, warm, method="normcg", approach=float(d))

    def solve(d, warm, fallback=False):
        nonlocal solves, cold_up, fallbacks
        loading = warm is not None and d > warm.approach
        res = _solve_quiet(operator, h, interaction, tol, max_iterations, None if (cold_up and loading) else warm,
                           approach=float(d))
        solves += 1
        if not res.converged and warm is not None and not (cold_up and loading) and d > 0 and d not in cold_failed:
            # A warm start from a smaller contact can stall where a cold solve at a compressive
            # approach converges (Maugis lambda = 5 on 1248^2: 2500-4500 iterations warm, 1500
            # cold); a cold start at a positive approach lands on the contact branch.  A cold
            # solve is the same at the same approach: one that failed is not tried again.
            cold = _solve_quiet(operator, h, interaction, tol, max_iterations, None, approach=float(d))
            solves += 1
            if cold.converged:
                res, cold_up = cold, cold_up or loading
            else:
                cold_failed.add(d)
        if not res.converged and warm is not None and fallback:
            res = normcg(d, warm)
            fallbacks += int(res.converged)
        if progress:
            progress(solves, max_solves)
        return res

    def done(res, full=False):
        res.info = dict(res.info or {}, target_force=force, force_scale=scale, solves=solves, full_contact=bool(full),
                        normcg_fallbacks=fallbacks)
        return res

    if start is not None:
        if not start.converged or not math.isfinite(start.approach):
            raise InputError("start", "must be a converged state with a finite approach")
        cur = start
    else:
        cur = solve(0.0, None)
        if not cur.converged:
            raise InputError("force", f"the first touch (approach 0) has no converged solution: {cur.message}")
    scale = max(abs(force), abs(cur.force))
    if abs(cur.force - force) <= rtol * scale:
        return done(cur)
    up = cur.force < force
    prev, step = None, (first if up else -first)
    while True:
        if solves >= max_solves:
            raise InputError("force", f"no bracket of {force:.4g} N within {max_solves} solves "
                                      f"(last: {cur.force:.4g} N at approach {cur.approach:.4g} m)")
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
        nxt = solve(d, cur)
        d_step = d
        halvings = 0
        min_step = rng / 4.0 if rng > 0 else first
        while (not nxt.converged or (not up and _separated(nxt))) and halvings < 8 and solves < max_solves \
                and (up or abs(d - cur.approach) > min_step):
            # a step too long (for the solver, or past the end of the branch): shorten it; the
            # branch ends (no equilibrium) only where a step of h0/4 separates the bodies
            d = 0.5 * (cur.approach + d)
            nxt = solve(d, cur)
            halvings += 1
        if not nxt.converged and solves < max_solves:
            # Polonsky-Keer failed the step and every shortened one: NormCG, on the whole step
            # (a shortened one would leave the path crawling), else on the shortest
            d_short, d, nxt = d, d_step, normcg(d_step, cur)
            if (not nxt.converged or (not up and _separated(nxt))) and d_short != d_step and solves < max_solves:
                d, nxt = d_short, normcg(d_short, cur)
            fallbacks += int(nxt.converged and (up or not _separated(nxt)))
            if progress:
                progress(solves, max_solves)
        if not nxt.converged or (not up and _separated(nxt)):
            raise InputError("force", f"no equilibrium at {force:.4g} N on this branch: the contact "
                                      f"{'separates' if nxt.converged else 'has no converged state'} at approach "
                                      f"{d:.4g} m (force {cur.force:.4g} N just before)")
        if up and (np.all(nxt.contact) or d >= d_full):
            # Full contact (periodic cell): the force no longer follows the approach.  Bisect
            # towards the threshold so that the state returned is the last one short of it.
            d_in = nxt.approach
            for _ in range(6):
                if solves >= max_solves:
                    break
                trial = solve(0.5 * (cur.approach + d_in), cur)
                if not trial.converged or np.all(trial.contact):
                    d_in = trial.approach
                else:
                    cur = trial
                    if abs(trial.force - force) <= rtol * scale or trial.force > force:
                        return done(trial)
            return done(cur, full=True)
        if abs(nxt.force - force) <= rtol * scale:
            return done(nxt)
        if (nxt.force > force) == up:  # bracketed between cur and nxt
            break
        prev, cur, step = cur, nxt, d - cur.approach
    # Regula falsi (Illinois) on [lo, hi] with F(lo) < force < F(hi).
    lo, hi = (cur, nxt) if up else (nxt, cur)
    f_lo, f_hi = lo.force - force, hi.force - force
    best = min((lo, hi), key=lambda r: abs(r.force - force))
    side = 0
    while solves < max_solves:
        d = (lo.approach * f_hi - hi.approach * f_lo) / (f_hi - f_lo)
        warm = lo if abs(d - lo.approach) < abs(d - hi.approach) else hi
        res = solve(d, warm, fallback=True)  # a failure here would end the refinement
        if not res.converged:
            break
        if abs(res.force - force) < abs(best.force - force):
            best = res
        if abs(res.force - force) <= rtol * scale:
            return done(res)
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
    warnings.warn(f"solve_at_force: {force:.4g} N reached to {abs(best.force - force):.3g} N after {solves} solves "
                  f"(tolerance {rtol * scale:.3g} N)", ConvergenceWarning, stacklevel=2)
    return done(best)


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
    if interaction is None:
        raise InputError("adhesion", "pull-off needs an adhesive interaction")
    if preload is not None and not preload > 0:
        raise InputError("pull_off.preload", f"must be > 0 N (or left out: zero external load), got {preload!r}")
    if control not in ("displacement", "force"):
        raise InputError("control", f"must be 'displacement' or 'force', got {control!r}")
    if start not in ("approach", "force"):
        raise InputError("start", f"must be 'approach' or 'force', got {start!r}")
    target = 0.0 if preload is None else float(preload)
    notes: list[str] = []
    if start == "force":
        state0 = _solve_quiet(operator, gap, interaction, tol, max_iterations, None, force=target)
        if not state0.converged:
            raise InputError("pull_off.preload", f"the preload has no converged solution: {state0.message}")
    else:
        try:
            state0 = solve_at_force(operator, gap, target, interaction=interaction, tol=tol,
                                    max_iterations=max_iterations)
        except InputError as exc:
            raise InputError("pull_off.preload", f"the preload cannot be reached: {exc}") from None
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
    start = state0
    total = (n_steps if control == "force" else max_steps) + 2 * refine
    rows, store = [], []

    if control == "force":
        # Lower bound of any tensile force: sigma0 over the whole domain.
        f_min = interaction.floor * operator.grid.area
        forces = np.linspace(start.force, f_min, n_steps + 1)[1:]
        if start.force > 0.0 and 0.0 not in forces:
            # Zero load is an equilibrium of an adhesive contact (the start without a preload):
            # step through it, so that a first tensile step beyond the pull-off (coarse steps, few
            # bisections) cannot leave a compressive force as the pull-off force.
            forces = np.sort(np.append(forces, 0.0))[::-1]
        total = len(forces) + 2 * refine
        prev, f_ok, f_fail = start, start.force, None
        _record(rows, start, "unloading", False, store)
        for k, f in enumerate(forces):
            res = _solve_quiet(operator, gap, interaction, tol, max_iterations, prev, force=float(f))
            if progress:
                progress(k + 1, total)
            if not res.converged:
                f_fail = float(f)
                break
            _record(rows, res, "unloading", False, store)
            prev, f_ok = res, float(f)
        if f_fail is not None:
            for k in range(refine):
                f = 0.5 * (f_ok + f_fail)
                res = _solve_quiet(operator, gap, interaction, tol, max_iterations, prev, force=f)
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
        return PullOff(prev.force, prev.approach, curve, prev, start, notes)

    # Displacement control: a quasi-static continuation.  Coarse steps while the contact is
    # compressive, then steps of a quarter of the interaction range once the force turns
    # tensile (a larger step can jump to another metastable branch of a rough contact),
    # until the bodies have separated.
    rng = float(getattr(interaction, "range", 0.0)) or 1e-3 * max(abs(start.approach), 1e-12)
    d_hi = start.approach
    coarse = max((d_hi - 0.0) / max(n_steps // 2, 1), rng / 4.0)
    fine = rng / 4.0
    prev, d = start, d_hi
    best_state = None
    best = (np.inf, None, None)  # (force, row index, result just above that point)
    _record(rows, start, "unloading", keep_fields, store)  # the curve starts at the preload
    k = 0
    while k < max_steps:
        step = fine if (prev.force < 0.0 or d - coarse < 0.0) else coarse
        d -= step
        res = _solve_quiet(operator, gap, interaction, tol, max_iterations, prev, approach=float(d))
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
        warnings.warn(f"pull-off: the bodies had not separated after {max_steps} steps", ConvergenceWarning, stacklevel=2)
    f_best, i, above = best
    if i is None:
        raise InputError("adhesion", "no point of the unloading curve converged")
    result_force, result_approach = float(rows[i]["normal_force"]), float(rows[i]["approach"])
    state = best_state
    # Refine around the minimum by a finer continuation from the point just above it.
    if refine > 0 and 0 < i < len(rows) - 1:
        d0, d1 = float(rows[i - 1]["approach"]), float(rows[i + 1]["approach"])
        prev = above
        for k, d in enumerate(np.linspace(d0, d1, 2 * refine + 1)[1:-1]):
            res = _solve_quiet(operator, gap, interaction, tol, max_iterations, prev, approach=float(d))
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
    curve = _assemble("displacement", rows, store)
    return PullOff(result_force, result_approach, curve, state, start, notes)
