"""Normal contact: bound-constrained, FFT-preconditioned conjugate gradients (Vollebregt's NormCG).

Same problem, same arguments and the same :class:`~tribobem.results.NormalResult` as
:func:`tribobem.solvers.normal.solve_normal` (Polonsky-Keer); the two are interchangeable.
Find the pressure p (Pa) with

* p > floor on the contact nodes C (g = 0), floor = -sigma0 with Dugdale adhesion, else 0;
* p = s(g) on the other nodes, s the interaction's outside stress (0 without adhesion);
* total force = F0 (force control) or approach = delta (displacement control),

where g = h + K p - delta.

Method (Vollebregt, J. Comput. Phys. 257 (2014) 333-351, "BCCG+" as in CONTACT's
``normcg``, m_solvpn.f90; written from the method, not translated):

* **FFT-based preconditioner.**  The residual (the contact gap) is multiplied by M, the
  convolution whose spectrum is the reciprocal of the operator's spectrum, restricted to the
  contact: z = P_C M P_C g.  K is a smoothing operator of order -1 (2/(E* |q|) in Fourier
  space), M of order +1, so M K is close to the identity at all wavelengths and the iteration
  count no longer grows with the grid (Polonsky-Keer's does).  The periodic spectrum has no
  q = 0 mode; M takes the value of its smallest nonzero wavevector there (the mean of a
  residual on a partial contact is not in K's null space).  On the free-boundary (DC-FFT)
  operator M is the reciprocal of the zero-padded kernel's spectrum (positive for the Love
  coefficients; a non-positive mode, were there one, gets the smallest positive value).
* **Force constraint by projection.**  Under force control z, the search direction d and K d
  are made mean-free on the contact, so a step keeps the total force; the rigid approach is
  the mean contact gap (as in Polonsky-Keer).  After nodes leave the contact the pressure is
  rescaled to the force (the force balance of :mod:`.normal`: p - floor scaled on C).
* **Bound constraints without restarts.**  Polak-Ribiere conjugation, beta = max(0, (r.z -
  r_old.z)/r_old.z_old), continued across changes of the contact set (the direction is set
  to 0 on nodes that leave), so that the many small changes of a rough contact do not throw
  away the Krylov information -- Polonsky-Keer as implemented in :mod:`.normal` restarts from
  steepest descent at every change.  Nodes whose pressure falls to the floor leave the
  contact; non-contact nodes that overlap (g < 0) enter with their current pressure.
* **Dugdale adhesion** (any interaction with a step law): the non-contact nodes carry
  s(g), re-evaluated from the exact gap after every step (a fixed-point update of the outside
  load, as in Polonsky-Keer); the CG acts on the contact nodes with that load frozen.  The
  adhesive problem is not convex: from the same start the two solvers may stop at different,
  equally valid equilibria (measured: benchmarks/normal_iterations.py).
* **Smooth laws** (a law whose ``outside_branch`` says which piece a node is on, e.g. the
  capillary law with its edge ramps): a change of the outside stresses that moves no node to
  another piece is deferred while the CG on the frozen load still makes progress (the relative
  pressure change above ``iteration.DEFER_RATIO`` times the relative mismatch), as Polonsky-Keer does;
  convergence needs the mismatch below ``tol``.  Applied at every iteration, on a rough burl
  with menisci on hundreds of spots, the updates never settled (every solve unconverged).

Convergence: the measures of :func:`.normal.solve_normal`, so that results at the same
``tol`` are equally accurate -- the relative pressure change sum |p - p_old| / sum |p| and
the rms gap on the contact nodes relative to the range of the initial gap must both fall
below ``tol``, with no change of the contact set or outside stresses in that iteration and
an exactly recomputed displacement.  Failure: ``ConvergenceWarning`` (or ``ConvergenceError``
with ``strict``), ``converged=False``, the residual history.

Cost per iteration: two convolutions (K d and M r), a third after an iteration in which nodes
left the contact or outside stresses changed (the displacement is then recomputed exactly;
otherwise it is updated incrementally and refreshed every ``refresh`` iterations).  Skipping
that exact recompute (updating u incrementally and ignoring the truncation of the leavers)
needs several times more iterations, so it is not done.

The iteration loop (stall detection, convergence test with an exact recompute, history,
messages) is :func:`.iteration.run_iterations`; the input checks and the result assembly are
those of :mod:`.normal_problem` (shared with :mod:`.normal`); this module supplies the NormCG
step (:class:`_NormCG`).  Measured iteration counts and CPU times against Polonsky-Keer:
benchmarks/README.md (the NormCG section, and "Solver notes moved from docstrings").
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..errors import InputError
from ..interactions.base import NoInteraction
from ..interactions.hardness import unwrap_cap
from ..results import NormalResult
from .iteration import DEFER_RATIO, IterativeSolver, dot, relaxed_outside_update, run_iterations
from .normal_problem import _self_compliance, normal_problem, normal_result

__all__ = ["solve_normal_cg", "fft_preconditioner", "resolve_precision"]

#: Coarse-grid start (``coarse_levels=None``): halve the grid while the coarser one keeps at
#: least this many nodes, at most ``_COARSE_MAX_LEVELS`` times; its tolerance.
_COARSE_MIN_NODES = 256 * 256
_COARSE_MAX_LEVELS = 3
_COARSE_TOL = 1e-4
#: precision="auto" runs single precision from this many nodes (below, a transform costs little)
SINGLE_MIN_NODES = 512 * 512


def fft_preconditioner(operator: ConvolutionOperator) -> ConvolutionOperator:
    """The FFT-based approximate inverse M of the normal operator (cached on the operator).

    Parameters
    ----------
    operator : ConvolutionOperator
        Elastic operator; its normal block K (m/Pa) is inverted.

    Returns
    -------
    ConvolutionOperator
        Convolution with spectrum 1/K(q) (Pa/m) on the same FFT grid (zero-padded for the
        free boundary).  Modes where K(q) <= 0 (the q = 0 mode of a periodic operator) get
        the smallest of the other values, i.e. the stiffness of the longest wavelength.
    """
    op = operator.normal
    cached = op.cache.normcg_preconditioner
    if cached is not None:
        return cached
    spec = op.spectrum()
    if spec is None:
        raise InputError("operator", "has no normal (zz) block: the normal solvers need one")
    xp = op.xp
    if not xp.iscomplexobj(spec) and bool((spec > 0).all()):
        # Every mode positive (the free-boundary Love kernel): divide by K's own array instead
        # of storing 1/K -- two grid fields less (a 4096^2 burl's memory bound).
        pre = ConvolutionOperator(op.grid, op.pair, ("z",), {"zz": spec}, op.fft_shape, op.backend,
                                  f"NormCG preconditioner of {op.kind}", reciprocal=True)
        op.cache.normcg_preconditioner = pre
        return pre
    K = np.real(np.asarray(op.backend.to_numpy(spec)))
    M = np.empty(K.shape)
    positive = K > 0
    if bool(positive.all()):
        np.divide(1.0, K, out=M)  # (no masked copies of the spectrum)
    else:
        M[positive] = 1.0 / K[positive]
        # K(q) -> 0 only at q = 0 (periodic): continue 1/K with its longest-wavelength value.
        M[~positive] = M[positive].min()
    del positive
    pre = ConvolutionOperator(op.grid, op.pair, ("z",), {"zz": op.backend.asarray(M)}, op.fft_shape, op.backend,
                              f"NormCG preconditioner of {op.kind}")
    op.cache.normcg_preconditioner = pre
    return pre


def solve_normal_cg(
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
    initial_displacement=None,
    strict: bool = False,
    refresh: int = 50,
    stall: int = 2000,
    precondition: bool = True,
    coarse_levels: int | None = None,
    coarse_tol: float = _COARSE_TOL,
    coarse_restrict: str = "mean",
    coarse_prolong: str = "constant",
    precision: str = "double",
    candidates: bool | None = None,
) -> NormalResult:
    """Solve a normal contact problem (with or without adhesion) by NormCG.

    Parameters
    ----------
    operator : ConvolutionOperator
        Elastic operator (its normal block is used), periodic or free boundary.
    gap : array_like
        Initial (undeformed) gap h(x, y) in m, shape ``grid.shape``.
    force : float, optional
        Total normal force F0 in N (force control); positive = compressive, may be negative
        with adhesion.
    approach : float, optional
        Rigid approach delta in m (displacement control).  Give exactly one of ``force`` and
        ``approach``.
    interaction : Interaction, optional
        Outside stress law, e.g. :class:`~tribobem.interactions.DugdaleAdhesion`; None:
        non-adhesive contact.
    tol : float
        Tolerance on the relative pressure change per iteration and on the rms contact gap
        relative to the range of ``gap`` (both must be below it), as in ``solve_normal``.
    max_iterations : int
        Iteration limit; each iteration costs two or three convolutions.
    initial_pressure : array_like or NormalResult, optional
        Warm start (Pa); a :class:`NormalResult` gives its pressure and contact mask.
    initial_contact : array_like of bool, optional
        Contact mask that goes with ``initial_pressure`` (default: p > floor).
    initial_displacement : array_like, optional
        The displacement K p (m) of ``initial_pressure`` on this operator, when the caller has
        it (e.g. the ``displacement`` of the :class:`NormalResult` passed as
        ``initial_pressure``): it replaces the first convolution (``info["convolutions"]`` one
        less).  Used only when the warm start is that pressure unchanged by the start (none of
        it raised to the floor, and under force control either no rescale to the force or one
        without an outside stress law, where K of the rescaled pressure is the rescaled
        ``initial_displacement``); ignored without ``initial_pressure``.
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning on failure.
    refresh : int
        Recompute the displacement exactly at least every ``refresh`` iterations.
    stall : int
        Stop (not converged) when the residual has not improved for this many iterations.
    precondition : bool
        Use the FFT preconditioner (default).  False gives the unpreconditioned
        bound-constrained CG (for comparison).
    coarse_levels : int, optional
        Coarse-grid start: first solve the same problem on a grid with cells 2x larger (the
        gap's 2 x 2 block mean; recursively ``coarse_levels`` deep) to ``coarse_tol`` and
        start from its pressure on the 2 x 2 fine nodes.  The converged result is that of the
        cold start (same contact nodes, pressures within the tolerance).  None (default):
        automatic -- non-adhesive cold starts halve the grid while the coarse one keeps
        >= 256^2 nodes, at most 3 times (fewer fine iterations: benchmarks/README.md, whole
        burl); 0: off.  Excludes ``initial_pressure``; each level needs even grid sizes.
    coarse_tol : float
        Tolerance of the coarse solves (a start only).
    coarse_restrict, coarse_prolong : str
        Coarse gap: "mean" (default) or "min" of each 2 x 2 block; fine start: "constant"
        (default, each coarse value on its 4 nodes) or "linear" (bilinear).
    precision : {"double", "single", "auto"}
        "single": the images of the search directions and the preconditioner are transformed
        in single precision (float32 / complex64, a float32 copy of the spectrum), while the
        displacement of the pressure is recomputed in double precision every ``refresh``
        iterations and at every convergence check, so that the converged state satisfies the
        double-precision tests at ``tol`` (certified: ``info["certificate"]``).  "auto": single
        where the backend transforms in single precision and the problem is non-adhesive
        (see :func:`resolve_precision`); "double" (default): double throughout.
    candidates : bool, optional
        Candidate-set solve of a non-adhesive free-boundary problem
        (:mod:`.candidates`): solve on the box of nodes that can touch (gap below the
        approach), verify every node outside, grow the box when the check fails, then one
        whole-grid convolution for the displacement.  None (default): where it applies and
        the grid has at least ``candidates.MIN_NODES`` nodes; True: wherever it applies;
        False: never.

    Returns
    -------
    NormalResult
        As :func:`~tribobem.solvers.normal.solve_normal`; ``info`` adds ``method``
        ("normcg"), ``set_changes`` (iterations in which the contact set or an outside
        stress changed), ``convolutions`` (number of FFT convolutions on this grid) and
        ``coarse`` (None, or the coarse start's levels, grid, iterations and convolutions per
        level, converged, cpu_s).

    Raises
    ------
    InputError
        Bad load, gap, tolerance, iteration limit, ``refresh`` or warm start.
    ConvergenceError
        With ``strict``, when the solver does not converge.
    """
    t_start = time.perf_counter()
    op = operator.normal
    xp, grid = op.xp, op.grid
    single = resolve_precision(precision, op, interaction)
    from .candidates import candidate_solve

    box = candidate_solve(solve_normal_cg, op, gap, candidates, force=force, approach=approach, interaction=interaction, tol=tol,
                          max_iterations=max_iterations, initial_pressure=initial_pressure, strict=strict,
                          refresh=refresh, stall=stall, precondition=precondition, precision=precision,
                          coarse_levels=coarse_levels)
    if box is not None:
        return box
    law, cap = unwrap_cap(interaction)
    if cap is not None:
        # the capped problem: p <= H on the gap raised by the plastic displacement so far; the
        # coarse start (an uncapped solve) is not a start for it
        interaction, coarse_levels = law, 0
        offset = cap.offset(grid.shape, xp)
        if offset is not None:
            gap = xp.asarray(gap, dtype=float) + offset
        del offset
    levels = _coarse_levels(coarse_levels, op, gap, interaction, initial_pressure, precondition)
    coarse_info = None
    if levels:
        start = _coarse_start(op, gap, force, approach, levels, coarse_tol, max_iterations, stall,
                              coarse_restrict, coarse_prolong, precision)
        if start is not None:
            initial_pressure, initial_contact, coarse_info = start
    h, inter, floor, force_control, target, _, p, contact = normal_problem(
        op, gap, force, approach, interaction, tol, max_iterations, initial_pressure, initial_contact, refresh)
    h_eff = h if force_control else h - approach
    u0 = None
    if initial_displacement is not None and initial_pressure is not None:
        # only for the warm start's own pressure (normal_problem raises it to the floor)
        p_given = initial_pressure.pressure if isinstance(initial_pressure, NormalResult) else initial_pressure
        u0 = xp.asarray(initial_displacement, dtype=float)
        if u0.shape != p.shape or not bool(xp.array_equal(p, xp.asarray(p_given))):
            u0 = None
        del p_given
    if force_control and not bool(contact.any()):
        # A warm start without contact cannot be rescaled to the force: start cold.
        p = xp.full(grid.shape, target / h.size)
        contact = p > floor
        u0 = None

    # The solver works on p and contact in place (normal_problem made them; no copies), and
    # the warm start's own array is no longer needed: one grid field less at the peak.
    del initial_pressure, initial_contact
    ceiling = cap.hardness if cap is not None else math.inf
    if ceiling <= max(floor, 0.0):
        raise InputError("hardness", f"must exceed the law's floor {floor!r} Pa and 0, got {ceiling!r}")
    if cap is not None and force_control and target > ceiling * h.size:
        raise InputError("solve_normal.force", f"{force!r} N exceeds the hardness times the nominal area "
                         f"({ceiling * grid.area!r} N): no capped contact carries it")
    solver = _NormCG(op, inter, floor, h_eff, p, contact, target, refresh,
                     fft_preconditioner(op) if precondition else None, u0, ceiling, tol, single)
    del p, contact, u0
    outcome = run_iterations(solver, tol=tol, max_iterations=max_iterations, stall=stall)
    p = solver.p.reshape(grid.shape)
    plastic = solver.pm.reshape(grid.shape) if solver.pm is not None else None
    contact = solver.cm.reshape(grid.shape)
    if plastic is not None:
        contact = contact | plastic
    # the exact K p of the last (converged) iterate, else recomputed
    u = solver.u.reshape(grid.shape) if solver.exact else op.apply(p)
    counts = {"set_changes": solver.set_changes, "convolutions": solver.convolutions,
              "precision": "single" if single else "double"}
    del solver
    res = normal_result(op, h, p, contact, u, approach, inter, outcome, strict, t_start,
                        {"method": "normcg" if precondition else "bccg", **counts, "coarse": coarse_info},
                        plastic=plastic)
    if cap is not None:
        # the plastic nodes' overlap becomes permanent once the solve has converged (a failed
        # solve leaves the body as it was)
        if res.converged and res.plastic_increment is not None:
            cap.commit(res.plastic_increment)
        res.plastic_displacement = cap.plastic
        res.info["hardness"] = cap.hardness
        res.info["interaction"] = repr(cap)
    return res


def resolve_precision(precision: str, op, interaction) -> bool:
    """Whether a NormCG solve runs its direction images in single precision.

    Parameters
    ----------
    precision : {"double", "single", "auto"}
        The caller's choice; "auto" is single on backends that transform float32 in single
        precision (``Backend.single_precision``) for non-adhesive problems without a hardness
        cap on grids of at least ``SINGLE_MIN_NODES`` nodes (the convergence test is in double
        precision either way; an outside stress law's fixed point is kept in double).
    op : ConvolutionOperator
        The normal operator.
    interaction : Interaction or None
        The outside law.

    Returns
    -------
    bool

    Raises
    ------
    InputError
        An unknown precision.
    """
    if precision not in ("double", "single", "auto"):
        raise InputError("precision", f"must be 'double', 'single' or 'auto', got {precision!r}")
    if precision == "double":
        return False
    if precision == "single":
        return True
    plain = isinstance(interaction if interaction is not None else NoInteraction(), NoInteraction)
    return plain and op.backend.single_precision and op.grid.nx * op.grid.ny >= SINGLE_MIN_NODES


def _coarse_levels(levels, op, gap, interaction, initial_pressure, precondition) -> int:
    """The number of coarse-grid levels to solve first (see ``solve_normal_cg``)."""
    if levels is None:
        # Automatic: non-adhesive cold starts on large grids only (the adhesive problem is not
        # convex: another start may find another equilibrium).
        if (initial_pressure is not None or not precondition
                or not isinstance(interaction if interaction is not None else NoInteraction(), NoInteraction)):
            return 0
        levels, nx, ny = 0, op.grid.nx, op.grid.ny
        while nx % 2 == 0 and ny % 2 == 0 and nx * ny >= 4 * _COARSE_MIN_NODES and levels < _COARSE_MAX_LEVELS:
            nx, ny, levels = nx // 2, ny // 2, levels + 1
        return levels
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or levels < 0:
        raise InputError("coarse_levels", f"must be an integer >= 0 or None, got {levels!r}")
    if levels and initial_pressure is not None:
        raise InputError("coarse_levels", "a coarse-grid start and initial_pressure exclude each other")
    nx, ny = op.grid.nx, op.grid.ny
    for _ in range(int(levels)):
        if nx % 2 or ny % 2 or nx < 8 or ny < 8:
            raise InputError("coarse_levels", f"{levels} levels need a grid divisible by 2^{levels} with at "
                             f"least 4 x 4 coarse nodes, got {op.grid.nx} x {op.grid.ny}")
        nx, ny = nx // 2, ny // 2
    return int(levels)


def _restrict(xp, a, how: str):
    """2 x 2 block mean (or minimum) of ``a``: the field on the grid with cells twice as large."""
    nx, ny = a.shape
    blocks = a.reshape(nx // 2, 2, ny // 2, 2)
    if how == "min":
        return blocks.min(axis=(1, 3))
    return blocks.mean(axis=(1, 3))


def _prolong(xp, a, how: str):
    """``a`` on the grid with cells half as large: each coarse value on its 2 x 2 fine nodes
    ("constant"), or bilinear between the coarse cell centres ("linear", edges held)."""
    if how == "linear":
        # fine node 2I sits dx_f/2 before coarse centre I, 2I + 1 as far after it
        lo = xp.concatenate([a[:1], a[:-1]], axis=0)
        hi = xp.concatenate([a[1:], a[-1:]], axis=0)
        rows = xp.empty((2 * a.shape[0], a.shape[1]))
        rows[0::2] = 0.75 * a + 0.25 * lo
        rows[1::2] = 0.75 * a + 0.25 * hi
        lo = xp.concatenate([rows[:, :1], rows[:, :-1]], axis=1)
        hi = xp.concatenate([rows[:, 1:], rows[:, -1:]], axis=1)
        out = xp.empty((rows.shape[0], 2 * a.shape[1]))
        out[:, 0::2] = 0.75 * rows + 0.25 * lo
        out[:, 1::2] = 0.75 * rows + 0.25 * hi
        return out
    return xp.repeat(xp.repeat(a, 2, axis=0), 2, axis=1)


def _coarse_operator(op):
    """The normal operator of the same domain with cells twice as large (same materials,
    boundary condition and backend)."""
    from ..elasticity.operators import free_boundary_operator, periodic_operator
    from ..grid import Grid

    g = op.grid
    cg = Grid(g.nx // 2, g.ny // 2, g.lx, g.ly, g.periodic)
    if op.periodic:
        kernel = "influence" if "influence" in op.kind else "spectral"
        return periodic_operator(cg, op.pair, ("z",), kernel=kernel, backend=op.backend)
    return free_boundary_operator(cg, op.pair, ("z",), backend=op.backend)


def _coarse_start(op, gap, force, approach, levels, tol, max_iterations, stall, restrict, prolong, precision="double"):
    """Solve the problem on the grid 2x coarser (recursively ``levels`` deep, to ``tol``) and
    return its pressure and contact on this grid, with a summary; None when it gives no start."""
    import warnings

    xp = op.xp
    t0 = time.process_time()
    h = xp.asarray(gap, dtype=float)
    if h.shape != op.grid.shape or not bool(xp.all(xp.isfinite(h))):
        return None  # normal_problem reports it
    cop = _coarse_operator(op)
    hc = _restrict(xp, h, restrict)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # an unconverged coarse solve is still a start
        res = solve_normal_cg(cop, hc, force=force, approach=approach, tol=tol, max_iterations=max_iterations,
                              stall=stall, coarse_levels=levels - 1, coarse_tol=tol, coarse_restrict=restrict,
                              coarse_prolong=prolong, precision=precision, candidates=False)
    del hc
    pc = xp.asarray(res.pressure)
    if not bool(xp.all(xp.isfinite(pc))) or not bool((pc > 0).any()):
        return None
    p = _prolong(xp, pc, prolong)
    xp.maximum(p, 0.0, out=p)
    inner = res.info.get("coarse") or {}
    info = {"levels": levels, "grid": [cop.grid.nx, cop.grid.ny], "tol": tol,
            "iterations": [int(res.iterations)] + list(inner.get("iterations", [])),
            "convolutions": [int(res.info["convolutions"])] + list(inner.get("convolutions", [])),
            "converged": bool(res.converged), "cpu_s": time.process_time() - t0}
    return p, p > 0, info


class _NormCG(IterativeSolver):
    """Working state of the bound-constrained preconditioned CG (flat arrays).

    ``p`` full pressure (Pa), ``cm`` contact mask, ``idx`` its flat indices, ``u`` = K p (m),
    exact or incrementally updated, ``r`` the contact gap (m) on ``idx`` (mean-free under
    force control), ``d`` the search direction on the full grid (0 off the contact).
    """

    def __init__(self, op, inter, floor, h_eff, p, contact, target, refresh, pre, u0=None, ceiling=math.inf, tol=0.0,
                 single=False):
        xp = op.xp
        self.single = bool(single)  # single-precision direction images (precision="single")
        self.u0 = u0  # K p of the start, when the caller knew it (see solve_normal_cg)
        self.scale = 1.0  # the last force-balance scale (_balance)
        self.op, self.xp, self.inter, self.floor, self.pre = op, xp, inter, floor, pre
        self.shape = h_eff.shape
        self.h = h_eff.ravel()
        self.target, self.refresh = target, refresh
        self.force_control = target is not None
        self.has_outside = not isinstance(inter, NoInteraction)
        self.h_scale = max(float(self.h.max() - self.h.min()), 1e-300)
        self.p = xp.asarray(p, dtype=float).ravel()  # owned: made by normal_problem
        self.cm = xp.asarray(contact, dtype=bool).ravel()
        # the hardness cap: plastic nodes (p = ceiling, overlap allowed) leave the contact set as
        # nodes at the floor do; None without a cap (no extra grid field)
        self.ceiling = float(ceiling)
        self.pm = None
        self.tol = tol
        if math.isfinite(self.ceiling):
            self.pm = self.p >= self.ceiling
            xp.minimum(self.p, self.ceiling, out=self.p)
            self.cm &= ~self.pm
        self.idx = xp.flatnonzero(self.cm)
        n = self.p.size
        self.d = xp.zeros(n)        # search direction, 0 off the contact
        self.r_old = xp.zeros(n)    # previous residual (Polak-Ribiere), 0 off the contact
        self.work = xp.zeros(n)     # scatter buffer for the preconditioner
        # p_old shares the preconditioner's buffer: their uses never overlap within an
        # iteration (one grid field less: the memory bound of a 4096^2 whole burl)
        self.p_old = self.work
        self.rz_old = 0.0
        self.delta = 0.0
        self.changed = False
        self.exact = False
        self.since_exact = 0
        self.set_changes = 0
        self.convolutions = 0
        self.pressure_change = float("inf")
        self.gap_residual = float("inf")
        self.branch_fn = getattr(inter, "outside_branch", None) if self.has_outside else None
        self.branch = None
        self.out_error = 0.0
        self.self_c = None  # the cell's self-compliance (m/Pa), on first use (_relaxed)
        self.relaxable = self.branch_fn is not None and getattr(inter, "outside_slope", None) is not None

    # -- the steps run by iteration.run_iterations (start and iterate below)
    def residual(self) -> float:
        """Largest of the relative pressure change, the relative rms contact gap and the
        mismatch of a deferred outside stress."""
        return max(self.pressure_change, self.gap_residual, self.out_error)

    def settled(self) -> bool:
        """No change of the contact set or of an outside stress in the last iteration."""
        return not self.changed

    def is_exact(self) -> bool:
        """Whether the displacement is exact (recomputed, not updated incrementally)."""
        return self.exact

    def confirm(self, tol: float) -> bool:
        """Recompute the displacement exactly; converged if the gap residual stays below ``tol``
        and nothing changes."""
        self.make_exact()
        return self.gap_residual < tol and not self.changed

    # ---------------------------------------------------------------------------------
    def K(self, v, single: bool = False):
        """K v on the whole grid (m); ``single``: in single precision where the solver runs so
        (the images of search directions only, never the exact recompute of u)."""
        self.convolutions += 1
        return self.op.apply(v.reshape(self.shape), single=single and self.single).ravel()

    def make_exact(self):
        """Recompute u = K p and the contact residual exactly (changed: set/load changes)."""
        self.u = self.K(self.p)
        self.exact = True
        self.since_exact = 0
        self._classify()

    def _balance(self) -> bool:
        """Force control: scale p - floor on the contact to the target force.  False when
        the contact cannot carry it (beyond pull-off).  The scale applied is ``self.scale``."""
        if self.pm is not None:
            return self._balance_capped()
        idx, floor = self.idx, self.floor
        if len(idx) == 0:
            return False
        p_c = self.p[idx]
        sum_c = float(p_c.sum())
        fixed = float(self.p.sum()) - sum_c if self.has_outside else 0.0
        free = sum_c - floor * len(idx)
        scale = (self.target - fixed - floor * len(idx)) / free if free > 0 else -1.0
        if scale <= 0:
            return False
        self.scale = scale
        self.p[idx] = scale * (p_c - floor) + floor if floor != 0.0 else scale * p_c
        return True

    def _balance_capped(self) -> bool:
        """:meth:`_balance` with the hardness cap: the plastic nodes carry H each; nodes the
        rescale lifts above H become plastic, and when the plastic nodes alone carry more than
        their share, they return to the contact set and the whole contact is rescaled."""
        xp, floor, ceil = self.xp, self.floor, self.ceiling
        for _ in range(1000):
            idx = self.idx
            n_pl = int(xp.count_nonzero(self.pm))
            p_c = self.p[idx]
            sum_c = float(p_c.sum())
            carried = float(self.p.sum()) - sum_c  # outside stresses and the plastic nodes' H
            need = self.target - carried - floor * len(idx)
            if need <= 0 and n_pl:
                back = xp.flatnonzero(self.pm)
                self.pm[back] = False
                self.cm[back] = True
                self.idx = xp.flatnonzero(self.cm)
                self.changed = True
                continue
            free = sum_c - floor * len(idx)
            if need > 0 and (len(idx) == 0 or free <= 0):
                return self._touch_next(need)
            if need <= 0:
                return False
            scale = need / free
            self.scale = scale
            p_c = scale * (p_c - floor) + floor if floor != 0.0 else scale * p_c
            self.p[idx] = p_c
            over = p_c > ceil
            if not bool(over.any()):
                return True
            self._to_plastic(idx[over])
        return False

    def _touch_next(self, need: float) -> bool:
        """Every loaded node is plastic and they carry less than the force: the bodies approach
        until the next nodes touch.  The ceil(need / H) + 1 free nodes of smallest gap enter the
        contact sharing ``need`` (sum of p, Pa), each below H; the CG takes it from there."""
        xp = self.xp
        free_nodes = xp.flatnonzero(~self.cm & ~self.pm)
        m = min(int(math.ceil(need / self.ceiling)) + 1, len(free_nodes))
        if m == 0 or need / m >= self.ceiling:
            return False
        g = (self.h + self.u)[free_nodes] if getattr(self, "u", None) is not None else self.h[free_nodes]
        nodes = free_nodes[xp.argpartition(g, m - 1)[:m]] if m < len(free_nodes) else free_nodes
        self.p[nodes] = need / m
        self.cm[nodes] = True
        self.idx = xp.flatnonzero(self.cm)
        self.changed = True
        self.scale = 1.0
        return True

    def _to_plastic(self, nodes):
        """Contact nodes that reach the cap: p = ceiling, off the contact set (overlap allowed)."""
        self.p[nodes] = self.ceiling
        self.pm[nodes] = True
        self.cm[nodes] = False
        self.d[nodes] = 0.0
        self.idx = self.xp.flatnonzero(self.cm)
        self.changed = True

    def _classify(self):
        """Update the approach, let overlapping nodes enter, re-evaluate the outside stresses,
        and form the contact residual.  Sets ``self.changed`` when anything changed."""
        xp = self.xp
        g = self.h + self.u
        idx = self.idx
        if self.force_control and len(idx):
            self.delta = float(g[idx].mean())
            g -= self.delta
        # Non-contact nodes that overlap enter with their current pressure (the outside
        # stress at g -> 0, i.e. the floor for a Dugdale law, 0 without adhesion).
        overlap = (g < 0) & ~self.cm
        if self.pm is not None:
            # plastic nodes stay plastic while they overlap; one whose gap opens unloads
            # elastically: it enters the contact set at p = H, where the CG lowers it
            # (beyond the gap tolerance: a flattened node sits at p = H with g = 0, and round-off
            # would otherwise move it in and out of the plastic set at every iteration)
            back = self.pm & (g > self.tol * self.h_scale)
            overlap &= ~self.pm
            overlap |= back
            self.pm &= ~back
        entered = bool(overlap.any())
        if entered:
            self.cm |= overlap
            self.idx = idx = xp.flatnonzero(self.cm)
            self.changed = True
        self.out_error = 0.0
        if self.has_outside:
            out = self._relaxed(self.inter.outside_stress(g, xp), g)
            out = xp.where(self.cm if self.pm is None else self.cm | self.pm, self.p, out)
            defer = False
            smooth = False
            if self.branch_fn is not None and not entered:
                # A smooth change (no node changes piece of the law) is deferred while the CG on
                # the frozen outside load still makes progress (as Polonsky-Keer does): applying
                # it every iteration turns the CG into a fixed point that need not settle.
                branch = self.branch_fn(g, xp)
                smooth = self.branch is not None and not bool(xp.any((branch != self.branch) & ~self.cm))
                self.branch = branch
                if smooth:
                    norm = float(xp.abs(self.p).sum())
                    self.out_error = float(xp.abs(out - self.p).sum()) / norm if norm > 0 else 0.0
                    defer = self.pressure_change > DEFER_RATIO * self.out_error
            if not defer and not bool(xp.array_equal(out, self.p)):
                # A relaxed smooth update (a law with outside_slope) keeps its mismatch as the
                # residual instead of counting as a change: the solve is settled once that
                # mismatch is below tol (a change would need it to vanish to round-off).
                keep = smooth and self.relaxable
                self.out_error = self.out_error if keep else 0.0
                # The outside load changed (fixed-point step): rebalance and recompute.
                self.p = out
                self.changed = self.changed or not keep
                if self.force_control and not self._balance():
                    return ("the contact cannot carry the requested force: the load is beyond "
                            "pull-off (no equilibrium under force control)")
                idx = self.idx  # (the balance of a capped contact may move nodes to or from the cap)
                self.u = self.K(self.p)
                self.exact, self.since_exact = True, 0
                g = self.h + self.u
                if self.force_control and len(idx):
                    self.delta = float(g[idx].mean())
                    g -= self.delta
                # The new outside load may close nodes (the adhesive pull): they enter too;
                # without this a state with no contact node stopped at once with overlaps.
                overlap = (g < 0) & ~self.cm
                if self.pm is not None:
                    overlap &= ~self.pm
                if bool(overlap.any()):
                    self.cm |= overlap
                    self.idx = idx = xp.flatnonzero(self.cm)
        self.r = g[idx]
        n_c = len(idx)
        self.gap_residual = math.sqrt(dot(self.r, self.r) / n_c) / self.h_scale if n_c else 0.0
        return None

    def _relaxed(self, out, g):
        """The outside load's update relaxed by each node's own response
        (:func:`~.iteration.relaxed_outside_update`; a law with ``outside_slope``)."""
        slope_fn = getattr(self.inter, "outside_slope", None)
        if slope_fn is None:
            return out
        if self.self_c is None:
            self.self_c = _self_compliance(self.op)
        return relaxed_outside_update(self.p, out, slope_fn(g, self.xp), self.self_c,
                                      getattr(self.inter, "tension_limit", self.floor), self.xp)

    def start(self):
        """Force balance of the initial pressure, exact displacement, first classification."""
        if self.force_control:
            if len(self.idx) == 0 or not self._balance():
                return "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"
        # (_classify sets the non-contact nodes to the outside stress of their initial gap.)
        u0, self.u0 = self.u0, None
        scale = self.scale if self.force_control else 1.0
        if u0 is not None and scale != 1.0:
            # K is linear: the rescaled pressure's displacement is the rescaled one when the
            # whole pressure was scaled (no outside law, floor 0, no pressure off the contact).
            xp = self.xp
            whole = (not self.has_outside and self.floor == 0.0
                     and int(xp.count_nonzero(self.p)) == int(xp.count_nonzero(self.p[self.idx])))
            u0 = u0 if whole else None
        if u0 is not None:
            # the caller's K p of the start (the last solve's convolution); a copy: u is updated in place
            self.u = self.xp.array(u0, dtype=float).ravel()
            if scale != 1.0:
                self.u *= scale
        else:
            self.u = self.K(self.p)
        del u0
        self.exact, self.since_exact = True, 0
        return self._classify()

    def iterate(self):
        """One NormCG iteration; returns an error message when no equilibrium exists."""
        xp, idx, floor = self.xp, self.idx, self.floor
        n_c = len(idx)
        if n_c == 0:
            if self.force_control:
                return "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"
            # Displacement control without contact: no CG, but the outside load's fixed point
            # (a smooth law's tension settles over several updates; a step law's in one).
            self.changed = False
            self.gap_residual = 0.0
            self.p_old[...] = self.p
            self.make_exact()  # recomputes u and re-evaluates the outside stresses (_classify)
            diff = self.p_old
            xp.subtract(self.p, diff, out=diff)
            norm = float(xp.abs(self.p).sum())
            self.pressure_change = float(xp.abs(diff).sum()) / norm if norm > 0 else 0.0
            return None
        self.changed = False
        r = self.r

        # Preconditioned residual z = P_C M P_C r (mean-free on C under force control).
        if self.pre is not None:
            w = self.work
            w.fill(0.0)
            w[idx] = r
            self.convolutions += 1
            wf = w.reshape(self.shape)
            z = self.pre.apply(wf, out=wf, single=self.single).ravel()[idx]  # in place: no further grid field
        else:
            z = r.copy()
        if self.force_control:
            z -= z.mean()

        # Polak-Ribiere direction, kept across changes of the contact set (d = 0 off C).
        rz = dot(r, z)
        d_c = self.d[idx]
        if self.rz_old > 0 and rz > 0:
            beta = max(0.0, (rz - dot(z, self.r_old[idx])) / self.rz_old)
            d_c *= beta
            d_c += z
        else:
            d_c = z
        if self.force_control:
            d_c -= d_c.mean()
        self.rz_old = rz
        self.r_old.fill(0.0)
        self.r_old[idx] = r
        self.d.fill(0.0)
        self.d[idx] = d_c

        # Step length (exact line search on the contact, force-constrained).
        q = self.K(self.d, single=True)
        q_c = q[idx]
        if self.force_control:
            q_c = q_c - q_c.mean()
        dq = dot(d_c, q_c)
        rd = dot(r, d_c)
        if not (dq > 0 and rd > 0):
            # Not a descent direction (round-off near convergence): restart next time.
            self.rz_old = 0.0
            alpha = 0.0
        else:
            alpha = rd / dq

        # Update on the contact; nodes that reach the floor leave it.
        self.p_old[...] = self.p
        p_c = self.p[idx] - alpha * d_c
        leave = p_c <= floor
        any_leave = bool(leave.any())
        self.p[idx] = xp.maximum(p_c, floor)
        if any_leave:
            leavers = idx[leave]
            self.cm[leavers] = False
            self.d[leavers] = 0.0
            self.idx = xp.flatnonzero(self.cm)
            self.changed = True
        if self.pm is not None:
            up = p_c >= self.ceiling
            if bool(up.any()):
                self._to_plastic(idx[up])  # (the old idx: up is indexed as p_c)
                any_leave = True
        idx = self.idx
        if any_leave:
            if self.force_control and not self._balance():
                return ("the contact cannot carry the requested force: the load is beyond "
                        "pull-off (no equilibrium under force control)")
            self.u = self.K(self.p)
            self.exact, self.since_exact = True, 0
        else:
            q *= q.dtype.type(alpha)
            self.u -= q
            self.since_exact += 1
            self.exact = False
            if self.since_exact >= self.refresh:
                self.u = self.K(self.p)
                self.exact, self.since_exact = True, 0
        del q, q_c
        status = self._classify()
        if status is not None:
            return status
        if self.changed:
            self.set_changes += 1

        # Relative pressure change (as solve_normal).
        w = self.p_old
        xp.subtract(self.p, w, out=w)
        xp.abs(w, out=w)
        norm = float(xp.abs(self.p).sum())
        diff = float(w.sum())
        self.pressure_change = diff / norm if norm > 0 else diff
        return None
