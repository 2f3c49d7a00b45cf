"""The tensile branch of a rough interface and the macro pull-off with it.

Micro: each periodic window is moved through a ladder of mean separations s of its mean planes
under displacement control (the window's approach is mean(h) - s: a periodic cell carries no
q = 0 displacement, so the mean of its gap is the mean of its undeformed gap less the approach),
warm-started step to step, with the adhesion of the run: a Dugdale zone
(:func:`tribobem.solvers.normal.solve_normal` with the interaction) or menisci at one RH
(:func:`tribobem.solvers.capillary.solve_capillary`).  The ladder is the same for every
realisation, so that their nominal (mean) pressures average at a common separation, as the
windows under one macro cell share its separation:

* the loading branch (index 0): from separated (every window's first touch plus the attraction's
  range) down to the separation of the deepest preload;
* unloading branches (index j >= 1): from the state at the nominal preload pressure p_j back up
  the ladder until every window has separated, or the ladder's top (a note says so).

An adhesive contact is history dependent: a cell's law depends on the largest pressure p_max
it carried.  :class:`TensileInterfaceLaw` interpolates the net nominal pressure P(s; p_max)
linearly in p_max between the branches whose preloads bracket it (p_0 = 0: a cell that never
carried a compressive pressure follows the loading branch); below its start a branch is the
loading branch.  Each branch is a monotone cubic in s, so P has a continuous slope.  With
menisci the equilibrium menisci of the capillary model depend on the state alone, so the
branches coincide except where the elastic contact itself is not unique; with a Dugdale zone the
unloading branches lie below the loading one (the necks that the preload made).

Macro: under a rigid approach delta the nominal pressure p of the macro cells solves

    p = P(h + G p - delta; p_max)

(no sign constraint: a cell pulls where the law is tensile).  It is solved by Newton's method:
with D = dP/ds on the cells where the law varies (the others take p = P(s)), the step solves the
symmetric system (G + C) dp = -C r, C = -1/D, by MINRES (C < 0 where the law softens beyond
the interface's tensile strength: the system is indefinite there; Jacobi-preconditioned), with a backtracking line
search on max |r|.  A cell whose softening is steeper than its own elastic stiffness (C > -c_0,
c_0 the cell's self-compliance) has no unique state: the macro cells are then too coarse for the
law and the solve says so.  :func:`interface_pull_off` loads to the preload force, then unloads
in steps that adapt to the force (from the law's separation step) until the burl has separated; the pull-off force is the
most tensile force of that curve, refined between its neighbours (as the whole-grid pull-off).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.sparse.linalg import LinearOperator, minres

from ..elasticity.operators import periodic_operator
from ..errors import ConvergenceWarning, InputError
from .laws import NormalInterfaceLaw
from .macro import _self_compliance
from .micro import MicroWindows, compute_tables, table_key

__all__ = ["TensileInterfaceLaw", "tensile_interface_law", "window_path_table", "solve_interface_at_approach",
           "interface_pull_off", "InterfacePullOff", "separation_ladder"]

#: Separation steps per attraction range in the tensile part of the ladder.
STEPS_PER_RANGE = 16
#: The ladder reaches this many attraction ranges above the highest window's first touch
#: (the necks and menisci of an unloading window outlast the loading's range).
TOP_RANGES = 3.0
#: A window counts as separated once its force is within this fraction of its most tensile one.
SEPARATED = 1e-3
#: A macro Newton solve stops once its residual has not halved in this many iterations.
STALL = 8
#: Bisections that locate the approach where the burl jumps off (no equilibrium beyond it).
JUMP_BISECTIONS = 4
#: Columns every branch carries besides the net pressure.
COLUMNS = ("contact_fractions", "repulsive_pressures", "capillary_pressures", "wetted_fractions")


def attraction_range(interaction, capillary) -> float:
    """The largest local gap (m) at which a window's attraction acts: the Dugdale range h0, or
    with menisci the meniscus cut height |r_k| (cos t1 + cos t2) + e1 + e2 plus the critical
    distance (as the whole-grid humid pull-off)."""
    rng = float(getattr(interaction, "h0", 0.0) or 0.0)
    if capillary is not None:
        opts = capillary["options"]
        rk = abs(float(opts["kelvin_radius"]))
        if math.isfinite(rk):
            t1, t2 = opts.get("contact_angles", (0.0, 0.0))
            s = rk * (math.cos(t1) + math.cos(t2)) + float(np.max(capillary["film1"])) + float(np.max(capillary["film2"]))
            rng = max(rng, s + float(opts.get("critical_distance", 0.0)))
        adh = opts.get("adhesion")
        if adh is not None:
            rng = max(rng, float(adh.h0))
    if not rng > 0:
        raise InputError("adhesion.model", "a two-scale pull-off needs an attraction: [adhesion] (Dugdale) or "
                                           "[humidity] with menisci")
    return rng


def separation_ladder(windows: MicroWindows, law: NormalInterfaceLaw, top_pressure: float) -> tuple[np.ndarray, float]:
    """The common ladder of mean separations (m, increasing) and its tensile step (m).

    From the normal table's largest pressure it takes the table's separations up to the smaller
    of the lowest first touch and the table's separation at its smallest pressure (with menisci
    the windows sit in contact at zero net pressure, well below their first touch); above it,
    steps of 1/:data:`STEPS_PER_RANGE` of the attraction range up to :data:`TOP_RANGES` ranges
    above the highest first touch.
    """
    rng = max(attraction_range(windows.interaction, windows.capillary_of(k)) for k in range(len(windows.gaps)))
    touch = [float(np.mean(g)) for g in windows.gaps]
    step = rng / STEPS_PER_RANGE
    lo, hi = min(min(touch), float(law.gaps[0])), max(touch) + TOP_RANGES * rng
    tensile = lo + step * np.arange(int(math.ceil((hi - lo) / step)) + 1)
    # to twice the deepest preload: cells next to the most loaded one may exceed it
    top = 2.0 * top_pressure
    keep = law.pressures <= top * (1 + 1e-12)
    comp = law.gaps[keep]
    if comp.size == 0 or comp[-1] > law.gap(np.array([top]))[0]:
        comp = np.append(comp, law.gap(np.array([top])))
    comp = np.sort(comp[comp < lo - 0.25 * step])
    return np.concatenate([comp, tensile]), float(step)


def _window_solver(op, gap, interaction, capillary, tol, max_iterations):
    """A function (s, warm start) -> (state, row) solving the window at mean separation s."""
    area = op.grid.lx * op.grid.ly
    mean_h = float(np.mean(gap))
    if capillary is None:
        from ..solvers.normal import solve_normal

        def solve(s, prev):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                r = solve_normal(op, gap, approach=mean_h - s, interaction=interaction, tol=tol,
                                 max_iterations=max_iterations,
                                 initial_pressure=None if prev is None else prev.pressure)
            contact = float(np.sum(r.pressure[r.contact])) * op.grid.dx * op.grid.dy
            return r, {"pressure": r.force / area, "contact_fractions": r.contact_area / area,
                       "repulsive_pressures": contact / area, "capillary_pressures": 0.0, "wetted_fractions": 0.0,
                       "converged": bool(r.converged), "separated": not (np.any(r.contact) or np.any(r.adhesive))}
        return solve
    from ..solvers.capillary import solve_capillary

    def solve(s, prev):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            r = solve_capillary(op, gap, approach=mean_h - s, film1=capillary["film1"], film2=capillary["film2"],
                                tol=tol, max_iterations=max_iterations, initial=prev, **capillary["options"])
        return r, {"pressure": r.total_force / area, "contact_fractions": r.normal.contact_area / area,
                   "repulsive_pressures": r.repulsive_force / area, "capillary_pressures": r.capillary_force / area,
                   "wetted_fractions": r.wetted_area / area, "converged": bool(r.converged),
                   "separated": not np.any(r.normal.contact) and r.island_count == 0}
    return solve


def window_path_table(grid, pair, gap: np.ndarray, separations, starts, *, interaction=None, capillary=None,
                      tol: float = 1e-8, max_iterations: int = 10000) -> dict:
    """One window's loading and unloading branches on a ladder of mean separations.

    Parameters
    ----------
    grid : Grid
        Periodic window grid (m).
    pair : ContactPair
        The materials.
    gap : ndarray
        The window's undeformed gap (m, minimum 0).
    separations : sequence of float
        The ladder of mean separations (m), increasing.
    starts : sequence of int
        Ladder indices where the unloading branches start (the preloads' separations).
    interaction : Interaction, optional
        The Dugdale law.
    capillary : dict, optional
        Menisci at one RH (``film1``, ``film2``, ``options``: :func:`~tribobem.two_scale.micro.
        window_table`).
    tol, max_iterations : float, int
        Normal solver settings.

    Returns
    -------
    dict
        ``pressure`` and every :data:`COLUMNS` entry as lists of branches (loading first), each
        a list over the ladder (NaN where the branch did not go: below an unloading branch's
        start), ``converged`` (all solves), ``solves``, ``separated`` (per unloading branch:
        whether the window separated within the ladder).
    """
    s_all = np.asarray(separations, dtype=float)
    op = periodic_operator(grid, pair)
    solve = _window_solver(op, gap, interaction, capillary, tol, max_iterations)
    touch = float(np.mean(gap))
    rng = attraction_range(interaction, capillary)
    n = s_all.size
    blank = {k: [np.nan] * n for k in ("pressure", *COLUMNS)}
    out = {k: [] for k in ("pressure", *COLUMNS)}
    converged, solves, separated_all = True, 0, []
    states: dict[int, object] = {}
    # loading: from the top down; nothing acts while every local gap exceeds the range
    load = {k: list(v) for k, v in blank.items()}
    prev = None
    for i in range(n - 1, -1, -1):
        if s_all[i] > touch + rng:
            for k in load:
                load[k][i] = 0.0
            continue
        prev, row = solve(float(s_all[i]), prev)
        solves += 1
        converged &= row["converged"]
        if i in starts:
            states[i] = prev
        for k in load:
            load[k][i] = float(row[k])
    for k in out:
        out[k].append(load[k])
    for j in starts:
        br = {k: list(v) for k, v in blank.items()}
        for k in br:
            br[k][j] = load[k][j]
        prev, fmin, sep = states.get(j), min(0.0, load["pressure"][j]), False
        for i in range(j + 1, n):
            prev, row = solve(float(s_all[i]), prev)
            solves += 1
            converged &= row["converged"]
            for k in br:
                br[k][i] = float(row[k])
            fmin = min(fmin, row["pressure"])
            if row["separated"] and abs(row["pressure"]) <= SEPARATED * abs(fmin):
                for k in br:  # separated: nothing acts further up
                    for m in range(i + 1, n):
                        br[k][m] = 0.0
                sep = True
                break
        separated_all.append(sep)
        for k in out:
            out[k].append(br[k])
    out.update(converged=bool(converged), solves=solves, separated=separated_all)
    return out


@dataclass
class TensileInterfaceLaw:
    """The net nominal pressure of a rough adhesive interface against mean separation and history.

    Attributes
    ----------
    separations : ndarray, shape (n,)
        The ladder of mean separations (m), increasing.
    preloads : ndarray, shape (m + 1,)
        Nominal preload pressure of each branch (Pa): 0 for the loading branch, then the
        unloading branches' preloads, increasing.
    pressure : ndarray, shape (m + 1, n)
        Net nominal pressure (Pa, negative in tension), mean over the realisations; an
        unloading branch below its start is the loading branch.
    columns : dict
        :data:`COLUMNS` arrays of the same shape (contact fraction, repulsive and meniscus
        pressures in Pa, wetted fraction).
    step : float
        The ladder's tensile step (m).
    realisations : int
    converged : bool
        Every micro solve converged.
    separated : bool
        Every unloading window separated within the ladder.
    info : dict
    """

    separations: np.ndarray
    preloads: np.ndarray
    pressure: np.ndarray
    columns: dict
    step: float
    realisations: int = 1
    converged: bool = True
    separated: bool = True
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        self.separations = np.asarray(self.separations, float)
        self.preloads = np.asarray(self.preloads, float)
        self.pressure = np.asarray(self.pressure, float)
        if self.pressure.shape != (self.preloads.size, self.separations.size):
            raise ValueError("one branch of pressures per preload, one value per separation")
        self._spline = PchipInterpolator(self.separations, self.pressure, axis=1, extrapolate=True)
        self._slope = self._spline.derivative()
        self._columns = {k: PchipInterpolator(self.separations, np.asarray(v, float), axis=1, extrapolate=True)
                         for k, v in self.columns.items()}

    @property
    def strength(self) -> float:
        """The interface's tensile strength (Pa, > 0): the most tensile pressure of any branch."""
        return float(max(-np.min(self.pressure), 0.0))

    def _weights(self, pmax):
        """Branch indices (j, j + 1) and the weight of j + 1 for each cell's largest pressure."""
        pre = self.preloads
        pm = np.maximum(np.asarray(pmax, float), 0.0)
        j = np.clip(np.searchsorted(pre, pm, side="right") - 1, 0, pre.size - 2)
        w = np.clip((pm - pre[j]) / (pre[j + 1] - pre[j]), 0.0, 1.0)
        return j, w

    def _combine(self, spline, s, pmax):
        s = np.asarray(s, float)
        flat = s.ravel()
        vals = spline(flat)  # (branches, cells)
        j, w = self._weights(np.broadcast_to(pmax, s.shape).ravel())
        cells = np.arange(flat.size)
        out = (1.0 - w) * vals[j, cells] + w * vals[j + 1, cells]
        return out.reshape(s.shape)

    def evaluate(self, s, pmax):
        """Net nominal pressure P (Pa) and its slope dP/ds (Pa/m) at separations ``s`` (m) of
        cells whose largest pressure was ``pmax`` (Pa); 0 above the ladder, and below it the
        first segment continued linearly (a cubic's extrapolation can turn back)."""
        s = np.asarray(s, float)
        s0 = self.separations[0]
        inside = np.maximum(s, s0)
        p = self._combine(self._spline, inside, pmax)
        d = self._combine(self._slope, inside, pmax)
        p = p + d * (s - inside)
        above = s >= self.separations[-1]
        return np.where(above, 0.0, p), np.where(above, 0.0, d)

    def column(self, key: str, s, pmax):
        """A :data:`COLUMNS` quantity at separations ``s`` and histories ``pmax``: held at the
        ladder's ends (0 above it; the fractions clipped to [0, 1])."""
        s = np.asarray(s, float)
        inside = np.clip(s, self.separations[0], self.separations[-1])
        out = np.where(s >= self.separations[-1], 0.0, self._combine(self._columns[key], inside, pmax))
        return np.clip(out, 0.0, 1.0) if key.endswith("fractions") else out

    def beyond_table(self, s) -> bool:
        """Whether a separation lies below the ladder (a cell more compressed than the table)."""
        return bool(np.any(np.asarray(s) < self.separations[0]))

    def as_dict(self) -> dict:
        """The law as plain lists (SI), for summary.json."""
        return {"separations": self.separations.tolist(), "preloads": self.preloads.tolist(),
                "pressure": self.pressure.tolist(), "step": self.step, "strength": self.strength,
                "realisations": self.realisations, "converged": self.converged, "separated": self.separated,
                "info": dict(self.info)}


def tensile_interface_law(windows: MicroWindows, law: NormalInterfaceLaw, preloads, *, tol: float = 1e-8,
                          max_iterations: int = 10000, scheduler: str = "synchronous", cache: bool = True,
                          cache_dir=None) -> TensileInterfaceLaw:
    """The tensile interface law of ``windows``, unloading from the nominal ``preloads``.

    Parameters
    ----------
    windows : MicroWindows
        The windows with their adhesion (``interaction``: Dugdale; or ``capillary``: menisci).
    law : NormalInterfaceLaw
        Their normal (loading) table: the compressive part of the ladder.
    preloads : sequence of float
        Nominal pressures (Pa, > 0, increasing) the unloading branches start from.
    tol, max_iterations, scheduler, cache, cache_dir
        As :func:`~tribobem.two_scale.micro.interface_law`.

    Returns
    -------
    TensileInterfaceLaw
    """
    preloads = np.asarray(preloads, float)
    if preloads.ndim != 1 or preloads.size < 1 or preloads[0] <= 0 or np.any(np.diff(preloads) <= 0):
        raise InputError("load.preload", "the unloading branches need increasing positive preload pressures")
    ladder, step = separation_ladder(windows, law, float(preloads[-1]))
    g_pre = law.gap(preloads)
    starts = [int(np.argmin(np.abs(ladder - g))) for g in g_pre]
    tasks = [(window_path_table, {"grid": windows.grid, "pair": windows.pair, "gap": g, "separations": ladder,
                                  "starts": starts, "interaction": windows.interaction,
                                  "capillary": windows.capillary_of(k), "tol": tol, "max_iterations": max_iterations},
              table_key(windows.grid, windows.pair, g, windows.interaction, preloads, tol, max_iterations,
                        kind="tensile", separations=ladder, starts=[float(i) for i in starts],
                        **windows.capillary_key(k)))
             for k, g in enumerate(windows.gaps)]
    tables = compute_tables(tasks, cache, cache_dir, scheduler)
    p = np.array([t["pressure"] for t in tables], float)  # (realisations, branches, n)
    cols = {k: np.array([t[k] for t in tables], float) for k in COLUMNS}
    # below its start an unloading branch is the loading branch (p_max is then the current pressure)
    for arr in (p, *cols.values()):
        for b in range(1, arr.shape[1]):
            below = np.isnan(arr[:, b, :])
            arr[:, b, :] = np.where(below, arr[:, 0, :], arr[:, b, :])
    if np.isnan(p).any():
        raise InputError("two_scale", "a window's loading branch did not reach the deepest preload")
    info = {"solves": int(sum(t["solves"] for t in tables)), "cached": int(sum(t.get("cached", False) for t in tables)),
            "ladder": int(ladder.size), "starts": starts, "step": step}
    # the preload pressures of the branches: the loading branch's pressure at each start (the
    # ladder's nearest separation to the nominal preload's)
    pre = np.concatenate([[0.0], p[:, 0, starts].mean(axis=0)])
    return TensileInterfaceLaw(separations=ladder, preloads=pre, pressure=p.mean(axis=0),
                               columns={k: v.mean(axis=0) for k, v in cols.items()}, step=step,
                               realisations=len(tables), converged=all(t["converged"] for t in tables),
                               separated=all(all(t["separated"]) for t in tables), info=info)


@dataclass
class ApproachState:
    """A macro state at a prescribed approach with the tensile law."""

    pressure: np.ndarray
    separation: np.ndarray
    displacement: np.ndarray
    approach: float
    force: float
    newton_iterations: int
    linear_iterations: int
    residual: float
    converged: bool
    unstable_cells: int = 0


def solve_interface_at_approach(op, h, law: TensileInterfaceLaw, approach: float, pmax, *, initial=None,
                                tol: float = 1e-8, max_newton: int = 60, c0: float | None = None) -> ApproachState:
    """The macro state p = P(h + G p - delta; p_max) at the rigid approach ``approach`` (module
    docstring).

    Parameters
    ----------
    op : ConvolutionOperator
        The macro normal operator.
    h : ndarray
        Undeformed macro gap (m).
    law : TensileInterfaceLaw
    approach : float
        Rigid approach delta (m), on the mean-plane datum of the normal interface law.
    pmax : ndarray or None
        Each cell's largest nominal pressure so far (Pa); None: every cell on the loading branch.
    initial : ndarray, optional
        Warm start pressure (Pa).
    tol : float
        max |p - P(s)| over the larger of the interface's strength and max |P|.
    max_newton : int
    c0 : float, optional
        The cells' self-compliance (m/Pa), from the operator when not given.

    Returns
    -------
    ApproachState
    """
    c0 = _self_compliance(op) if c0 is None else c0
    pm = np.zeros_like(h) if pmax is None else np.asarray(pmax, float)
    p = np.zeros_like(h) if initial is None else np.array(initial, float)
    n = h.size
    total_linear, residual, converged, unstable = 0, np.inf, False, 0

    def state(p):
        u = op.apply(p)
        s = h + u - approach
        P, D = law.evaluate(s, pm)
        return u, s, P, D

    u, s, P, D = state(p)
    scale = max(law.strength, float(np.max(np.abs(P))), 1.0)
    r = p - P
    residual = float(np.max(np.abs(r))) / scale
    best, since, it = residual, 0, 0
    for it in range(1, max_newton + 1):
        if residual <= tol:
            converged = True
            break
        # stagnation: no halving of the residual in STALL iterations (no equilibrium near here)
        if residual < 0.5 * best:
            best, since = residual, 0
        else:
            since += 1
            if since >= STALL:
                break
        active = np.abs(D) * c0 > 1e-12
        C = np.where(active, -1.0 / np.where(active, D, 1.0), 0.0)
        unstable = int(np.count_nonzero(active & (C < 0) & (C > -c0)))
        dp = np.where(active, 0.0, -r)
        rhs = np.where(active, -C * r - op.apply(dp), 0.0)
        mask = active.astype(float)

        # symmetric Jacobi scaling S (G + C) S, S = |c0 + C|^-1/2: the cells' compliances span
        # many decades (C -> infinity where the law is flat), and MINRES's stopping test is
        # relative to |A|
        S = np.where(active, 1.0 / np.sqrt(np.abs(c0 + C)), 1.0)

        def matvec(y, mask=mask, C=C, S=S):
            x = S * y.reshape(h.shape)
            return (S * (mask * op.apply(mask * x) + C * x) + (1.0 - mask) * x).ravel()

        A = LinearOperator((n, n), matvec=matvec, dtype=float)
        # inexact Newton: the linear solve is only as tight as the outer residual needs
        y, k = _symmetric_solve(A, (S * rhs).ravel(), float(np.clip(0.1 * residual, 1e-10, 1e-3)))
        x = S.ravel() * y
        total_linear += k
        dp = np.where(active, x.reshape(h.shape), dp)
        alpha = 1.0
        for _ in range(12):
            p_try = p + alpha * dp
            u_t, s_t, P_t, D_t = state(p_try)
            r_t = p_try - P_t
            res_t = float(np.max(np.abs(r_t))) / scale
            if res_t < residual or alpha < 1e-3:
                break
            alpha *= 0.5
        p, u, s, P, D, r, residual = p_try, u_t, s_t, P_t, D_t, r_t, res_t
    else:
        converged = residual <= tol
    dA = op.grid.dx * op.grid.dy
    return ApproachState(pressure=p, separation=s, displacement=u, approach=float(approach), force=float(p.sum() * dA),
                         newton_iterations=it, linear_iterations=total_linear, residual=residual, converged=converged,
                         unstable_cells=unstable)


def _symmetric_solve(A, b, rtol: float, rounds: int = 6, maxiter: int = 1000):
    """x with |A x - b| <= rtol |b| for a symmetric (possibly indefinite) A: MINRES (the short
    recurrence for such systems), restarted on the true residual, since SciPy's MINRES stops on a
    residual scaled by |A| |x|.  Returns (x, iterations)."""
    x = np.zeros_like(b)
    bnorm = float(np.linalg.norm(b)) or 1.0
    total = 0
    for _ in range(rounds):
        r = b - A.matvec(x)
        if float(np.linalg.norm(r)) <= rtol * bnorm:
            break
        count = [0]
        dx, _ = minres(A, r, rtol=rtol, maxiter=maxiter, callback=lambda xk: count.__setitem__(0, count[0] + 1))
        total += count[0]
        x += dx
    return x, total


def _locate_jump(op, h, law, pmax, last, bad: float, tol: float, c0: float, states: list) -> float:
    """Bisect between the last equilibrium ``last`` and the approach ``bad`` (m) where none was
    found, appending the equilibria found to ``states``; returns the first approach without one."""
    good = last
    for _ in range(JUMP_BISECTIONS):
        mid = 0.5 * (good.approach + bad)
        st = solve_interface_at_approach(op, h, law, mid, pmax, initial=good.pressure, tol=tol, c0=c0)
        if st.converged:
            states.append(st)
            good = st
        else:
            bad = mid
    return float(bad)


@dataclass
class InterfacePullOff:
    """The macro pull-off with a tensile interface law.

    Attributes
    ----------
    preload_state, pull_off_state : ApproachState
        The state at the preload and at the most tensile force.
    pmax : ndarray
        Each cell's largest nominal pressure (Pa): the preload state's, where it is compressive.
    curve : dict
        Lists per state from the preload outward: ``approach`` (m), ``force`` (N),
        ``capillary_force`` (N), ``contact_area`` (real, m^2), ``wetted_area`` (m^2), ``converged``.
    force, approach : float
        Pull-off force (N, negative) and its approach (m).
    converged : bool
        Every macro state converged and the burl separated.
    notes : list of str
    states : list of ApproachState
        Every macro state, in the order of ``curve``.
    time : float
    """

    preload_state: ApproachState
    pull_off_state: ApproachState
    pmax: np.ndarray
    curve: dict
    force: float
    approach: float
    converged: bool
    notes: list
    states: list = field(default_factory=list)
    time: float = 0.0


def _curve_row(law, st: ApproachState, pmax, dA: float) -> dict:
    col = {k: law.column(k, st.separation, pmax) for k in COLUMNS}
    return {"approach": st.approach, "force": st.force,
            "capillary_force": float(col["capillary_pressures"].sum() * dA),
            "repulsive_force": float(col["repulsive_pressures"].sum() * dA),
            "contact_area": float(col["contact_fractions"].sum() * dA),
            "wetted_area": float(col["wetted_fractions"].sum() * dA), "converged": st.converged}


def _preload(op, h, law, force: float, approach0: float, tol: float, c0: float, rtol: float = 1e-6):
    """The loading-branch state at the preload force (to ``rtol``): the force grows with the
    approach; a secant search, kept inside the bracket once it has one."""
    def at(d, init):
        return solve_interface_at_approach(op, h, law, d, None, initial=init, tol=tol, c0=c0)

    a = at(approach0, None)
    step = max(law.step, 1e-3 * abs(approach0))
    b = at(approach0 + (step if a.force < force else -step), a.pressure)
    lo = hi = None
    for _ in range(40):
        for st in (a, b):
            if st.force < force and (lo is None or st.approach > lo.approach):
                lo = st
            if st.force >= force and (hi is None or st.approach < hi.approach):
                hi = st
        if abs(b.force - force) <= rtol * abs(force):
            return b
        slope = (b.force - a.force) / (b.approach - a.approach) if b.approach != a.approach else 0.0
        d = b.approach + (force - b.force) / slope if slope > 0 else b.approach + (step if b.force < force else -step)
        if lo is not None and hi is not None and not lo.approach < d < hi.approach:
            d = 0.5 * (lo.approach + hi.approach)
        a, b = b, at(d, b.pressure)
    return b


def interface_pull_off(op, h, law: TensileInterfaceLaw, preload: float, approach0: float, *, n_steps: int = 40,
                       refine: int = 4, tol: float = 1e-8, max_steps: int = 400, progress=None) -> InterfacePullOff:
    """Load to ``preload`` (N) on the loading branch, then unload under displacement control until
    the burl has separated (module docstring): the approach steps start at the law's separation
    step and adapt so that the force changes by about its expected range over ``n_steps``.

    Parameters
    ----------
    op : ConvolutionOperator
        Macro normal operator.
    h : ndarray
        Undeformed macro gap (m).
    law : TensileInterfaceLaw
    preload : float
        The preload force (N, > 0).
    approach0 : float
        A first guess of the preload's approach (m; the normal interface law's).
    n_steps : int
        About how many unloading steps the force's range should take.
    refine : int
        ``2 refine - 1`` finer steps between the most tensile state's neighbours.
    tol : float
        Each state's tolerance (:func:`solve_interface_at_approach`).
    max_steps : int
        Most unloading steps.
    progress : callable, optional
        ``progress(step)`` after each unloading step.

    Returns
    -------
    InterfacePullOff
    """
    t0 = time.perf_counter()
    c0 = _self_compliance(op)
    dA = op.grid.dx * op.grid.dy
    notes: list[str] = []
    start = _preload(op, h, law, float(preload), float(approach0), tol, c0)
    pmax = np.maximum(start.pressure, 0.0)
    states = [start]
    # the approach steps adapt to the force: about n_steps steps over the force's expected range
    # (the preload down to the windows' strength over the loaded area); a large burl's elastic
    # displacement spans many of the law's separation steps
    target = (abs(float(preload)) + law.strength * float(np.count_nonzero(start.pressure)) * dA) / max(n_steps, 2)
    step, smallest, largest = law.step, law.step, 4096.0 * law.step
    prev, fmin, separated, k = start, start.force, False, 0
    while k < max_steps:
        # a secant predictor from the last two states (the first step starts from the preload's)
        if len(states) < 2:
            guess = prev.pressure
        else:
            ratio = step / max(states[-2].approach - prev.approach, smallest)
            guess = prev.pressure + ratio * (prev.pressure - states[-2].pressure)
        st = solve_interface_at_approach(op, h, law, prev.approach - step, pmax, initial=guess, tol=tol, c0=c0)
        if not st.converged and step > smallest:
            step = max(0.5 * step, smallest)  # too far for Newton from here: a shorter step
            continue
        if not st.converged and fmin < 0:
            # no equilibrium next to the last one, past the force's turn: the interface softens
            # faster than the burl's elasticity can follow, and the burl jumps off (as a JKR
            # contact does); locate the jump between the last state and this approach
            jump = _locate_jump(op, h, law, pmax, prev, st.approach, tol, c0, states)
            notes.append(f"two_scale: the burl jumps off at an approach of {jump:.4g} m (no equilibrium beyond it "
                         "under displacement control: the interface softens faster than the burl's elastic "
                         "stiffness); the pull-off force is the most tensile state before the jump")
            separated = True
            break
        change = abs(st.force - prev.force)
        if change > 2.0 * target and step > smallest:
            step = max(0.5 * step, smallest)  # the force moved too much: redo it shorter
            continue
        states.append(st)
        k += 1
        fmin = min(fmin, st.force)
        prev = st
        if progress is not None:
            progress(k)
        if change < 0.5 * target:
            step = min(2.0 * step, largest)
        if fmin < 0 and abs(st.force) <= SEPARATED * abs(fmin):
            separated = True
            break
    if not separated:
        notes.append(f"two_scale: the burl had not separated after {max_steps} unloading steps "
                     f"(force {prev.force:.4g} N, most tensile {fmin:.4g} N)")
    # refine about the most tensile state until its neighbours are within two separation steps
    for _ in range(4 if refine > 0 else 0):
        i = int(np.argmin([s.force for s in states]))
        if not 0 < i < len(states) - 1:
            break
        lo, hi = states[i + 1].approach, states[i - 1].approach
        for d in np.linspace(hi, lo, 2 * refine + 1)[1:-1]:
            near = min(states, key=lambda s: abs(s.approach - d))
            if abs(near.approach - d) <= 1e-6 * law.step:
                continue  # the most tensile state itself
            states.append(solve_interface_at_approach(op, h, law, float(d), pmax, initial=near.pressure, tol=tol, c0=c0))
        states.sort(key=lambda s: -s.approach)
        if hi - lo <= 2.0 * law.step:
            break
    at = min(states, key=lambda s: s.force)
    unstable = max(s.unstable_cells for s in states)
    if unstable:
        notes.append(f"grid.n: in {unstable} macro cell(s) the interface law softens faster than the cell's "
                     "own elastic stiffness (dP/ds > 1/c0): the state there is not unique; refine the macro cells")
    bad = sum(not s.converged for s in states)
    if bad:
        notes.append(f"two_scale: {bad} of {len(states)} macro pull-off states did not converge (tolerance {tol:g})")
    rows = [_curve_row(law, s, pmax, dA) for s in states]
    curve = {k: [r[k] for r in rows] for k in rows[0]}
    return InterfacePullOff(preload_state=start, pull_off_state=at, pmax=pmax, curve=curve, force=float(at.force),
                            approach=float(at.approach), converged=bool(separated and not bad), notes=notes,
                            states=states, time=time.perf_counter() - t0)
