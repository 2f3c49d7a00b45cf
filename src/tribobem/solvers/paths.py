"""Load paths: force-approach curves (loading and unloading), jumps, pull-off, hysteresis.

Under displacement control the approach is stepped and every step is warm-started from the
previous one, so the solver follows a branch until it ends; the jump to another branch shows
as a discontinuity of the contact area (jump-in on loading, jump-off on unloading).
Displacement control traces the unstable force branch that force control cannot reach, so
the pull-off force (the most negative force on the curve, Papers A and C) is taken from it
by default.  Under force control the unloading stops at the last force with an
equilibrium: that force is the force-controlled pull-off (jump-off).
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
        ok = np.where(self.converged)[0]
        if not len(ok):
            return float("nan")
        return float(self.approach[ok[np.argmin(self.force[ok])]])

    def branch_mask(self, name: str) -> np.ndarray:
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
        """One summary.json step entry per point (SPEC 9.1 keys)."""
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

    Returns
    -------
    LoadCurve
    """
    approaches = np.asarray(approaches, dtype=float)
    if approaches.ndim != 1 or len(approaches) < 1 or not np.all(np.isfinite(approaches)):
        raise InputError("load.approaches", "must be a non-empty list of finite approaches (m)")
    plan = [("loading", d) for d in approaches]
    if unload:
        plan += [("unloading", d) for d in approaches[::-1]]
    rows, store, prev = [], [], None
    for k, (branch, d) in enumerate(plan):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_normal(operator, gap, approach=float(d), interaction=interaction, tol=tol,
                               max_iterations=max_iterations, initial_pressure=prev)
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
) -> LoadCurve:
    """Force-approach curve under force control.

    The loading branch runs through ``forces`` in order, the unloading branch back in
    reverse.  Where no equilibrium exists (beyond pull-off) the point is recorded as not
    converged, a jump-off is reported at the previous point, and the branch stops.
    """
    forces = np.asarray(forces, dtype=float)
    if forces.ndim != 1 or len(forces) < 1 or not np.all(np.isfinite(forces)):
        raise InputError("load.forces", "must be a non-empty list of finite forces (N)")
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
                               max_iterations=max_iterations, initial_pressure=prev)
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
        raise InputError("load.forces", "no force of the list has an equilibrium (all beyond pull-off)")
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
    """

    force: float
    approach: float
    curve: LoadCurve
    state: NormalResult | None = None


def _solve_quiet(operator, gap, interaction, tol, max_iterations, initial, **load):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_normal(operator, gap, interaction=interaction, tol=tol,
                            max_iterations=max_iterations, initial_pressure=initial, **load)


def pull_off(
    operator: ConvolutionOperator,
    gap,
    interaction,
    *,
    preload: float,
    control: str = "displacement",
    n_steps: int = 40,
    refine: int = 8,
    tol: float = 1e-9,
    max_iterations: int = 10000,
    max_steps: int = 400,
    keep_fields: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> PullOff:
    """Pull-off force of an adhesive contact, by unloading from a compressive preload.

    Displacement control (default): solve the preload under force control, then unload by
    continuation: about ``n_steps / 2`` steps down to zero approach, then steps of h0 / 4
    (a quarter of the interaction range) once the force is tensile, until the bodies have
    separated; every solve is warm-started from the previous one, so the curve follows the
    branch being unloaded.  The minimum is refined by ``2 refine - 1`` finer continuation
    steps between its neighbours.

    Force control: step the force down from the preload; at the first force without
    equilibrium, bisect (``refine`` times) between it and the last force with one.  The last
    force with an equilibrium is the force-controlled pull-off (jump-off).

    Parameters
    ----------
    operator, gap, interaction
        As for :func:`solve_normal` (``interaction`` is required).
    preload : float
        Compressive force (N, > 0) from which the unloading starts.
    control : {"displacement", "force"}
    n_steps : int
        Unloading steps (force control), twice the number of coarse steps (displacement).
    refine : int
        Refinement of the minimum (finer continuation) or bisections (force control).
    max_steps : int
        Upper bound on the unloading steps under displacement control.
    keep_fields : bool
        Keep every :class:`NormalResult` in ``curve.results``.
    """
    if interaction is None:
        raise InputError("adhesion", "pull-off needs an adhesive interaction")
    if not preload > 0:
        raise InputError("load.preload", f"must be > 0 N, got {preload!r}")
    if control not in ("displacement", "force"):
        raise InputError("control", f"must be 'displacement' or 'force', got {control!r}")
    start = _solve_quiet(operator, gap, interaction, tol, max_iterations, None, force=preload)
    if not start.converged:
        raise InputError("load.preload", f"the preload has no converged solution: {start.message}")
    total = (n_steps if control == "force" else max_steps) + 2 * refine
    rows, store = [], []

    if control == "force":
        # Lower bound of any tensile force: sigma0 over the whole domain.
        f_min = interaction.floor * operator.grid.area
        forces = np.linspace(preload, f_min, n_steps + 1)[1:]
        prev, f_ok, f_fail = start, preload, None
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
                    progress(n_steps + k + 1, total)
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
        return PullOff(prev.force, prev.approach, curve, prev)

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
    return PullOff(result_force, result_approach, curve, state)
