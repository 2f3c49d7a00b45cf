"""Normal contact: Polonsky-Keer constrained conjugate gradients, extended to Dugdale
adhesion as in Paper A (steps 1-6), with explicit masks instead of the "-1000 sigma0" trick.

The problem (Paper A Eq. 13): find the pressure p on the grid such that

* p > floor on contact nodes (g = 0), where floor = -sigma0 with adhesion, 0 without;
* p = s(g) on non-contact nodes, where s is the interaction's outside stress
  (-sigma0 for 0 < g < h0 and 0 beyond, for Dugdale; 0 without adhesion);
* the total force equals F0 (force control) or the approach equals delta (displacement
  control),

with g = h + K p - delta.  The contact nodes are the CG unknowns; the non-contact nodes
follow the gap.  Each iteration costs one convolution (K t) and updates u = K p from it
incrementally; when nodes change status, their few columns of K are added in real space
(at most ``_SPARSE_MAX_NODES``, elasticity/columns.py), else K p is recomputed (a second
convolution), which saves convolutions without changing the iterations or the contact nodes;
u is recomputed exactly every ``refresh`` iterations and before convergence is declared.

Differences from the printed algorithm (documented in the README):

* the force balance (Paper A Eq. 22) also subtracts the force carried by the cohesive zone
  *outside* the contact; the printed Eq. 22a omits it, which makes the total force differ
  from F0 by the adhesive force of that zone;
* nodes are classified with boolean masks; a non-contact node whose gap becomes negative
  (overlap) enters the contact with p = s(g) - tau g (Eq. 21 applied to its stress);
* convergence needs both the relative change of the pressure,
  sum |p - p_old| / sum |p| (Eq. 23 made relative), and the rms gap on the contact nodes
  relative to the range of the initial gap, to fall below ``tol``: the pressure change alone
  can stall while gaps stay open.  The solver reports non-convergence with a warning, the
  residual history and ``converged=False``;
* the conjugate direction restarts from steepest descent whenever a node changes status
  (Polonsky-Keer restart only on overlap), after a force rescale, and when it is not a
  descent direction: warm starts then need fewer iterations than cold starts, and adhesive
  solves need fewer, at a small cost on non-adhesive rough contacts;
* once the contact set and the outside stresses have not changed for ``PRECONDITION_AFTER``
  iterations, the CG is preconditioned with the half-space's stiffness |q| on the contact's
  box (``_stiffness_box``; a few FFTs of the box per iteration, used where they cost at most
  half the operator's transform: always on the free boundary): the settled phase, where the
  plain iteration spends most of its iterations (87 % of them on the adhesive loop of
  benchmarks/adhesive_loop.py), converges several times faster, and every change of the sets
  is still made by the plain steps, which decide on which of the equilibria of an adhesive
  problem the solve ends.  A change of the sets returns to the plain steps.  Preconditioning
  from the first settled iteration put a few edge nodes of warm-started Maugis-Dugdale steps
  on another equilibrium; from the second it reached the plain iteration's in every case
  measured (tests/solvers/test_normal_preconditioned.py);
* smooth outside laws (an interaction with ``outside_branch``, see interactions.base, e.g.
  the capillary law with its van der Waals 1/g^3 terms): their stresses change at every
  iteration, which restarted the CG at every iteration.  A change that keeps every node on
  the same piece of the law is deferred: the CG runs on the frozen outside load until its
  relative pressure change falls below 10 x the relative mismatch of the outside stresses,
  then the outside stresses are applied (one restart) -- an inexact fixed point on the
  outside load.  Convergence also requires that mismatch below ``tol``.  Applying the smooth
  change at every iteration while keeping the conjugate directions stalls them.  Dugdale and
  non-adhesive solves are unaffected by the deferral.

Measured iteration counts and timings of these choices: benchmarks/README.md ("Solver notes
moved from docstrings").  The iteration loop (stall detection, convergence test with an exact
recompute, history, messages) is :func:`.iteration.run_iterations`, shared with
:mod:`.normal_cg` and :mod:`.tangential`; the input checks and the result assembly are those of
:mod:`.normal_problem`, shared with :mod:`.normal_cg`; this module supplies the Polonsky-Keer
step (:class:`_CGState`).

:func:`solve_normal` is also the entry to both normal solvers: its default ``method="auto"``
(:func:`resolve_method`, the rule of a scenario's ``[solver] method = "auto"``) solves
non-adhesive contact with NormCG (:mod:`.normal_cg`) and contact with an outside stress law
(adhesion, menisci) with Polonsky-Keer.
"""

from __future__ import annotations

import math
import time

from ..elasticity.backend import work_array
from ..elasticity.columns import KernelColumns, convolve, convolve_buffers
from ..elasticity.operators import ConvolutionOperator
from ..errors import InputError
from ..interactions.base import NoInteraction
from ..interactions.hardness import HardnessCap
from ..results import NormalResult
from .iteration import DEFER_RATIO, IterativeSolver, dot, relaxed_outside_update, run_iterations
from .normal_problem import _self_compliance, normal_problem, normal_result

#: Largest number of nodes whose pressure may change outside the CG step (leavers, entering
#: overlaps, changed outside stresses) for the displacement to be corrected with columns of
#: K in real space rather than recomputed with a convolution (see _CGState).
_SPARSE_MAX_NODES = 10

#: Precondition the CG once the contact set and the outside stresses have not changed for this
#: many iterations (None: never).  See ``_CGState._precondition``.
PRECONDITION_AFTER = 2
#: ... and only where the preconditioner's box transform is at most this fraction of the
#: operator's transform (see ``_stiffness_box``).
BOX_FRACTION = 0.5


def _stiffness_box(op: ConvolutionOperator, idx):
    """The preconditioner of the CG's settled phase on the contact nodes ``idx`` (flat).

    M = the body model's stiffness shape 1/K(q) up to a constant
    (:meth:`~tribobem.elasticity.bodies.BodyModel.preconditioner_stiffness`; for the half-space
    |q|, its 1/K(q) = E* |q| / 2 up to the constant, which a preconditioner does not need, so one
    M serves every material pair), applied on the
    contact's bounding box taken periodic (two cells larger, to a fast FFT length): FFTs of the
    box instead of the padded grid (a ball contact across 181 of 256 free-boundary cells: 192^2
    against 512^2).  A box 1.25x or 2x larger per axis, with less wrap-around, gave the same
    iteration counts on the adhesive loop of benchmarks/adhesive_loop.py.  On a periodic grid an
    axis that the contact spans for more than half is taken whole, where the periodic M is
    exact.  Returns ((rows, columns) of the nodes in the box, the box's FFT shape, the rfft2
    spectrum of M on it, a zeroed work array of the box's shape); None when the box's transform
    exceeds ``BOX_FRACTION`` of the operator's (e.g. the islands of a rough periodic contact
    spread over the cell: there the preconditioner cost as much as the operator, and the
    iterations it saved did not pay for it: 0.99-1.29x the plain iteration's CPU on the adhesive
    rough contact of benchmarks/adhesion_vs_tamaas.py, 256^2-1024^2).
    """
    import scipy.fft

    g = op.grid
    i, j = idx // g.ny, idx % g.ny

    def axis(c, n):
        lo, m = int(c.min()), int(c.max()) - int(c.min()) + 1
        if g.periodic and 2 * m > n:
            return 0, n
        return lo, scipy.fft.next_fast_len(m + 2, real=True)

    (i0, n1), (j0, n2) = axis(i, g.nx), axis(j, g.ny)
    if n1 * n2 > BOX_FRACTION * op.fft_shape[0] * op.fft_shape[1]:
        return None
    # M per box shape, cached on the operator (the box of a load path changes shape rarely)
    cache = op.cache.stiffness_box_spectra
    q = cache.get((n1, n2))
    if q is None:
        q = op.body_model.preconditioner_stiffness(op.pair, (n1, n2), g.lx / g.nx, g.ly / g.ny)
        # complex with zero imaginary parts: the same products, faster in NumPy than by a real array
        q = cache[(n1, n2)] = op.backend.asarray(q.astype(complex))
    return (i - i0, j - j0), (n1, n2), q, op.xp.zeros((n1, n2))


#: The normal solvers ``solve_normal`` (and a scenario's ``[solver] method``) can be asked for;
#: ``"auto"`` stands for one of the two others (:func:`resolve_method`).
METHODS = ("auto", "polonsky_keer", "normcg")


def resolve_method(method: str, adhesive: bool) -> str:
    """The normal solver that ``method`` stands for: the one rule of ``"auto"``.

    Shared by :func:`solve_normal` (``adhesive``: an outside stress law is given) and the
    scenario runners (:func:`tribobem.runs.common.normal_method`; ``adhesive``: ``[adhesion]``
    is on or ``[humidity]`` is given), so that a script and a scenario solve the same problem
    with the same solver.

    ``"auto"`` is NormCG without an outside stress law: the non-adhesive problem is convex, both
    solvers reach the same equilibrium (identical contact nodes), and NormCG needs 2-4x fewer
    iterations on rough contacts, a count that does not grow with the grid (benchmarks/README.md,
    the NormCG sections).  With one (Dugdale adhesion, a capillary or any other interaction) it
    is Polonsky-Keer: the problem is not convex, NormCG may stop at another, equally valid
    equilibrium, and the adhesive load paths and their validation were made with Polonsky-Keer.

    Parameters
    ----------
    method : {"auto", "polonsky_keer", "normcg"}
        The solver asked for.
    adhesive : bool
        Whether the problem has an outside stress law (adhesion, menisci, ...).

    Returns
    -------
    str
        ``"polonsky_keer"`` or ``"normcg"``.

    Raises
    ------
    InputError
        ``method`` is none of :data:`METHODS` (key ``solve_normal.method``; a scenario reads
        ``solver.method``, :data:`tribobem.runs.common.SCENARIO_KEYS`).
    """
    if method == "auto":
        return "polonsky_keer" if adhesive else "normcg"
    if method not in METHODS:
        raise InputError("solve_normal.method", f"must be 'auto', 'polonsky_keer' or 'normcg', got {method!r}")
    return method


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
    initial_displacement=None,
    strict: bool = False,
    refresh: int = 50,
    stall: int = 2000,
    method: str = "auto",
    precondition: bool = True,
    precision: str = "double",
    candidates: bool | None = None,
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
        Tolerance on the relative pressure change per iteration and on the rms contact gap
        relative to the range of ``gap`` (both must be below it).
    max_iterations : int
        Iteration limit.
    initial_pressure : array_like or NormalResult, optional
        Warm start (Pa), e.g. the pressure of the previous load step (a
        :class:`NormalResult` gives both its pressure and its contact mask).
    initial_contact : array_like of bool, optional
        Contact mask that goes with ``initial_pressure``; by default the nodes with
        p > floor (with adhesion, pass it: a node at p = 0 outside the cohesive zone is
        otherwise taken as in contact for the first iteration).
    initial_displacement : array_like, optional
        The displacement K p (m) of ``initial_pressure`` on this operator, when the caller has it
        (e.g. the ``displacement`` of the :class:`NormalResult` passed as ``initial_pressure``,
        solved on the same operator): it replaces the first convolution, with either solver.
        Used only when the warm start is that pressure unchanged (none of it raised to the floor;
        NormCG: nor rescaled to the force with an outside stress law, where the rescaled
        pressure's K p needs a convolution anyway); ignored without ``initial_pressure``.
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning when the solver
        does not converge.
    refresh : int
        Recompute the displacement exactly at least every ``refresh`` iterations (between
        refreshes it is updated incrementally while the contact set does not change, and
        with kernel columns when at most ``_SPARSE_MAX_NODES`` nodes change status).
    stall : int
        Stop (not converged) when the residual has not improved on its best value for
        this many iterations, e.g. when no equilibrium exists near an instability.
    method : {"auto", "polonsky_keer", "normcg"}
        ``"auto"`` (default, the same rule as a scenario's ``[solver] method = "auto"``, see
        :func:`resolve_method`): NormCG when ``interaction`` is None (non-adhesive contact),
        Polonsky-Keer when an interaction is given (Dugdale adhesion, menisci, any outside stress
        law).  ``"polonsky_keer"``: this module's constrained CG.  ``"normcg"``: Vollebregt's
        FFT-preconditioned bound-constrained CG
        (:func:`tribobem.solvers.normal_cg.solve_normal_cg`, same arguments and result):
        fewer iterations, whose count does not grow with the grid, and identical contact
        nodes on non-adhesive problems; with Dugdale adhesion it may stop at another, equally
        valid equilibrium of the non-convex problem (benchmarks/normal_iterations.py).  The
        solver used is ``result.info["method"]`` (``"polonsky_keer"``, ``"normcg"``, or
        ``"bccg"`` for NormCG with ``precondition=False``).
    precondition : bool
        Use the solver's preconditioner (default).  Polonsky-Keer: once the contact set and the
        outside stresses have stopped changing (``PRECONDITION_AFTER`` iterations without a
        change), precondition the CG with the half-space's stiffness on the contact's box; the
        steps that change the sets are Polonsky-Keer's own, so it reaches the same equilibrium
        in fewer iterations.  NormCG: the FFT preconditioner of every iteration.  False: the
        plain iteration of either (for comparison; NormCG's is the unpreconditioned
        bound-constrained CG, far slower).
    precision : {"double", "single", "auto"}
        NormCG's arithmetic (:func:`~tribobem.solvers.normal_cg.solve_normal_cg`): "single"
        transforms the search directions and the preconditioner in single precision and keeps
        the convergence test in double; "auto" is single where that is safe
        (:func:`~tribobem.solvers.normal_cg.resolve_precision`).  Polonsky-Keer runs in double
        precision ("auto" means double there; "single" is refused).
    candidates : bool, optional
        NormCG's candidate-set solve of non-adhesive free-boundary contact
        (:mod:`tribobem.solvers.candidates`); None: where it applies on large grids.
        Polonsky-Keer: None or False.

    Returns
    -------
    NormalResult
        ``info`` holds ``method`` (the solver used), ``max_penetration`` (m), ``interaction``,
        ``operator`` and, for Polonsky-Keer, ``counters`` (convolutions of the iteration, see
        ``_CGState.stats``); NormCG's entries: :func:`~tribobem.solvers.normal_cg.solve_normal_cg`.

    Raises
    ------
    InputError
        Bad load, gap, tolerance, iteration limit, warm start or method.
    ConvergenceError
        With ``strict``, when the solver does not converge.
    """
    if isinstance(interaction, HardnessCap):
        # the hardness cap is a bound of NormCG's bound-constrained CG (Polonsky-Keer has none):
        # a capped solve is NormCG's, whatever the method asked for (info["method"] says so)
        method = "normcg"
    method = resolve_method(method, interaction is not None and not isinstance(interaction, NoInteraction))
    if method == "normcg":
        from .normal_cg import solve_normal_cg

        return solve_normal_cg(operator, gap, force=force, approach=approach, interaction=interaction, tol=tol,
                               max_iterations=max_iterations, initial_pressure=initial_pressure,
                               initial_contact=initial_contact, initial_displacement=initial_displacement,
                               strict=strict, refresh=refresh, stall=stall, precondition=precondition,
                               precision=precision, candidates=candidates)
    if precision not in ("double", "auto"):
        raise InputError("solve_normal.precision", f"single precision is NormCG's (method 'normcg'); Polonsky-Keer "
                         f"runs in double precision: give 'double' or 'auto', got {precision!r}")
    if candidates:
        raise InputError("solve_normal.candidates", "the candidate-set solve is NormCG's (method 'normcg')")
    t_start = time.perf_counter()
    op = operator.normal
    h, inter, floor, force_control, target, shift, p, contact = normal_problem(
        op, gap, force, approach, interaction, tol, max_iterations, initial_pressure, initial_contact)
    u0 = None
    if initial_displacement is not None and initial_pressure is not None:
        # only for the warm start's own pressure (normal_problem raises it to the floor)
        p_given = initial_pressure.pressure if isinstance(initial_pressure, NormalResult) else initial_pressure
        u0 = op.xp.asarray(initial_displacement, dtype=float)
        if u0.shape != p.shape or not bool(op.xp.array_equal(p, op.xp.asarray(p_given))):
            u0 = None
    state = _CGState(op, inter, floor, h, shift, p, contact, force_control, target, refresh,
                     PRECONDITION_AFTER if precondition else None, u0)
    del p, contact, u0  # the state owns the pressure, a copy of the mask and of the displacement
    outcome = run_iterations(state, tol=tol, max_iterations=max_iterations, stall=stall)
    p, contact = state.full_pressure(), state.cmask
    counters = state.stats()  # result.info["counters"] (benchmarks/profile_iteration.py, tests)
    # The solver's displacement when it is exact for this pressure, else one more convolution.
    u = state.u.reshape(op.grid.shape) if state.u_exact else None
    del state  # its work arrays go before the last convolution allocates
    if u is None:
        u = convolve(op, p)
    return normal_result(op, h, p, contact, u, approach, inter, outcome, strict, t_start,
                         {"method": "polonsky_keer", "counters": counters})


#: Why a force-controlled iteration stops when no node is in contact.
_NO_CONTACT = "no node is in contact: the load is beyond pull-off (no equilibrium under force control)"


class _Step:
    """What the steps of one CG iteration hand on to the later ones (:meth:`_CGState.iterate`).

    Large temporaries are kept here rather than in the callers' frames so that a step can
    free them before a later allocation, as the memory peak of a uniform start (every node
    in contact) requires.

    Attributes
    ----------
    r : array or None
        K t on the full (flat) grid (m per unit of t, step 4), overwritten by the
        displacement update; None without a step or once freed.
    p_c_old, p_c_new : array
        Pressure on the contact nodes at the iteration's start and after the CG update (Pa).
    stays : array of bool
        Which contact nodes stay (p_c_new > floor).
    out_new : array or None
        The outside stress of every node's gap (Pa), None without an outside law.
    changed : bool
        Whether a node changed status or the outside stresses were applied (step 5).
    diff : float or None
        sum |p_new - p_old| (Pa) without a status change.
    old_idx, moved_nodes, p_moved_old : array
        After a status change: the old contact nodes, the non-contact nodes whose pressure
        changed and their old pressure (Pa).
    sparse, w_change : tuple or None
        (nodes, pressure changes in Pa) whose columns of K update u and W (few nodes only).
    W_old : array or None
        W of the old sets (m), when ``w_change`` updates it.
    scale : float
        The force balance's scale of p - floor on the contact (step 6).
    """

    __slots__ = ("r", "p_c_old", "p_c_new", "stays", "out_new", "changed", "diff", "old_idx",
                 "moved_nodes", "p_moved_old", "sparse", "w_change", "W_old", "scale")

    def __init__(self, r):
        self.r = r
        self.p_c_old = self.p_c_new = self.stays = self.out_new = None
        self.changed = False
        self.diff = None
        self.old_idx = self.moved_nodes = self.p_moved_old = None
        self.sparse = self.w_change = self.W_old = None
        self.scale = 1.0


class _CGState(IterativeSolver):
    """Working state of the constrained CG (Paper A steps 2-6).

    ``p`` is the full (flat) pressure, ``idx`` the flat indices of the contact nodes, and
    ``t_c`` the search direction on them.  Work arrays are preallocated and updated in
    place: at 1024^2 a fresh array costs as much as a pass over it.  Full-grid arrays held:
    p, u and g (the gap; also the FFT input t and the scratch array), and during an
    iteration r = K t; plus, with an outside stress, s0 and (force control) W.

    The displacement u = K p is updated incrementally, u <- s (u - tau K t) + (1 - s) W,
    while no node changes status.  When a few nodes do (leavers set to their outside
    stress, overlapping nodes entering, outside stresses changing), the pressure differs
    from the incremental one on those nodes only, and their columns of K are added in real
    space (elasticity/columns.py) instead of recomputing K p with a convolution, as long as
    there are at most ``sparse_max`` of them and the force balance does not need W (no
    outside stress, or no rescale).  The exact recomputation every ``refresh`` iterations
    and before convergence is declared is kept.
    """

    def __init__(self, op, inter, floor, h, shift, p, contact, force_control, target, refresh,
                 precondition_after=None, u0=None):
        xp = op.xp
        self.op, self.xp, self.inter, self.floor = op, xp, inter, floor
        self.h = h.ravel()
        self.force_control, self.target, self.refresh = force_control, target, refresh
        self.has_outside = not isinstance(inter, NoInteraction)
        self.shape = h.shape
        self.size = h.size
        self.tau0 = 1.0 / _self_compliance(op)
        self.tau = self.tau0
        # Force control: the mean of h + u on the contact (updated every iteration).
        # Displacement control: the approach; the gap is (h - approach) + u.
        self.delta = 0.0 if force_control else shift
        self.shift = shift
        self.error = float("inf")
        self.conjugate = False
        self.G_old = 1.0
        # Scale of the gap residual: the range of the initial gap h - shift (m).
        self.h_scale = max(float(h.max() - shift) - float(h.min() - shift), 1e-300)
        self.gap_residual = float("inf")
        self.p = xp.ascontiguousarray(p, dtype=float).ravel()
        self.cflat = xp.array(contact, dtype=bool).ravel()
        self.idx = xp.flatnonzero(self.cflat)
        self.t_c = None  # search direction on the contact (set by the first iteration)
        self.g = xp.empty(self.size)
        self.ovmask = xp.empty(self.size, dtype=bool)
        self.W = None  # K(p_out + floor 1_C), valid while no node changes status
        self.u = None
        self.u0 = u0  # K p of the start, when the caller knew it (see solve_normal)
        # Stress of a node that just left the contact (its gap is ~0), per node: a law may
        # depend on the position (e.g. meniscus islands).
        self.s0 = inter.outside_stress(xp.zeros(self.size), xp) if self.has_outside else 0.0
        # Optional: which piece of a piecewise-smooth law each node is on (see
        # interactions.base).  Without it every change of an outside stress is a status change.
        self.branch_fn = getattr(inter, "outside_branch", None) if self.has_outside else None
        self.slope_fn = getattr(inter, "outside_slope", None) if self.has_outside else None
        self.branch = None
        self.out_error = 0.0  # relative mismatch of deferred smooth outside stresses
        # W = 0: no outside stress, floor 0 and no pressure outside the contact (a warm start
        # may bring some); then a rescale needs no W and status changes can be sparse.
        self.w_zero = (not self.has_outside and floor == 0.0
                       and int(xp.count_nonzero(self.p)) == int(xp.count_nonzero(self.p[self.idx])))
        self.sparse_max = _SPARSE_MAX_NODES
        self.columns = None
        # Work buffers of the convolutions (K t and the exact K p write into them), made once
        # the contact holds at most a quarter of the nodes: the first iterations of a uniform
        # start carry full-grid contact vectors, and the memory peak is there.
        self.r_buf = self.spec_buf = None
        self.buffered = convolve_buffers(op)[0] is not None
        # Counters (benchmarks): convolutions for K t, exact K p, W; sparse updates and their columns.
        self.n_kt = self.n_exact = self.n_w = self.n_sparse = self.n_columns = 0
        self.started_exact = False
        # Iterations since the last status change, whether the last direction was
        # preconditioned, and the preconditioner's box (per contact set).
        self.stable = 0
        self.precondition_after = precondition_after
        self.pre_active = False
        self.pre_box = None
        self.n_pre = 0

    def stats(self) -> dict:
        return {"kt": self.n_kt, "exact": self.n_exact, "w": self.n_w, "sparse_updates": self.n_sparse,
                "sparse_columns": self.n_columns, "preconditioned": self.n_pre}

    def _box(self):
        """The preconditioner's box for the current contact set (cached), or None where it
        would not be cheaper than the operator (:func:`_stiffness_box`)."""
        if self.pre_box is None or self.pre_box[0] is not self.idx:
            self.pre_box = (self.idx, _stiffness_box(self.op, self.idx))
        return self.pre_box[1]

    def _precondition(self, g_c):
        """z = P_C M P_C g_c on the contact's box (:func:`_stiffness_box`), mean-free under force
        control (the step then keeps the force)."""
        (bi, bj), N, q, w = self._box()
        be = self.op.backend
        w[bi, bj] = g_c
        if be._lean():
            # the same pocketfft transforms into reused work arrays (no fresh spectra per step)
            T = work_array(self.op, "box spectrum", (N[0], N[1] // 2 + 1), complex, limit=8)
            rows = work_array(self.op, "box field", N, float, limit=8)
            be.rfft2_into(w, T)
            T *= q
            z = be.irfft2_into(T, N, rows)[bi, bj]
        else:
            z = be.irfft2(be.rfft2(w) * q, s=N)[bi, bj]
        w[bi, bj] = 0.0  # the box buffer stays zero off the contact for the next call
        self.n_pre += 1
        if self.force_control:
            z -= z.mean()
        return z

    # -- the steps run by iteration.run_iterations
    def start(self):
        """Exact displacement of the initial pressure (the start always exists: None)."""
        if self.u0 is not None:
            # the caller's K p of this pressure (the same convolution, done by the last solve): a copy,
            # the state updates its displacement in place
            self.u = self.xp.array(self.u0, dtype=float).ravel()
            self.u0 = None
            self.u_exact = True
            self.since_exact = 0
            return
        self.make_exact()

    def residual(self) -> float:
        """Largest of the relative pressure change, the relative rms contact gap and the
        mismatch of deferred outside stresses."""
        return max(self.error, self.gap_residual, self.out_error)

    def is_exact(self) -> bool:
        """Whether the iteration started from an exact displacement."""
        return self.started_exact

    def confirm(self, tol: float) -> bool:
        """Recompute the displacement exactly; convergence is then tested on the next iteration."""
        self.make_exact()
        return False

    @property
    def cmask(self):
        return self.cflat.reshape(self.shape)

    def full_pressure(self):
        return self.p.reshape(self.shape)

    def _buffers(self):
        if self.r_buf is None and self.buffered and 4 * len(self.idx) <= self.size:
            self.r_buf, self.spec_buf = convolve_buffers(self.op)
        return self.r_buf, self.spec_buf

    def make_exact(self):
        r_buf, spec_buf = self._buffers()
        if spec_buf is not None and self.u is not None:
            # K p written over the old displacement
            self.u = convolve(self.op, self.p.reshape(self.shape), out=self.u.reshape(self.shape),
                              spectrum=spec_buf).ravel()
        else:
            self.u = None  # free the old displacement before the convolution allocates the new one
            self.u = convolve(self.op, self.p.reshape(self.shape)).ravel()
        self.n_exact += 1
        self.u_exact = True
        self.since_exact = 0

    def _W(self):
        """K applied to the pressure the force balance does not scale (cached)."""
        if self.W is None:
            if self.w_zero or (not self.has_outside and self.floor == 0.0):
                self.W = 0.0
            else:
                w = self.xp.where(self.cflat, self.floor, self.p)
                self.W = convolve(self.op, w.reshape(self.shape)).ravel()
                self.n_w += 1
        return self.W

    def iterate(self):
        """One CG iteration (Paper A steps 2-6); returns an error message when no equilibrium exists."""
        self.started_exact = self.u_exact
        if self.force_control and len(self.idx) == 0:
            return _NO_CONTACT
        g_c = self._contact_gap()
        t_c, G = self._search_direction(g_c)
        step = _Step(self._step_length(g_c, t_c, G))
        del g_c  # (t_c may be the same array)
        self._update_sets(t_c, step)
        del t_c  # kept as self.t_c
        message = self._balance_force(step)
        if message is not None:
            return message
        self._measure_change(step)
        # Free the contact-set temporaries before a convolution allocates its arrays (the
        # first iteration of a uniform start has every node in contact).
        step.p_c_old = step.p_c_new = step.stays = None
        self._update_displacement(step)
        return None

    def _contact_gap(self):
        """Step 2: the gap on the contact nodes.

        Under force control the approach ``self.delta`` (m) is set to the mean of h + u there
        (Polonsky-Keer), so the contact gap has zero mean.

        Returns
        -------
        array
            The gap g_c on the contact nodes ``self.idx`` (m), a new array.
        """
        idx = self.idx
        if self.force_control:
            g_c = self.u[idx] + self.h[idx]
            self.delta = float(g_c.mean())
            g_c -= self.delta
        else:
            g_c = self.u[idx] + (self.h[idx] - self.shift)
        return g_c

    def _search_direction(self, g_c):
        """Step 3: the conjugate direction; preconditioned once the sets have settled.

        Also sets ``self.G_old`` (the CG's scalar for the next iteration) and the relative rms
        contact gap ``self.gap_residual``.

        Parameters
        ----------
        g_c : array
            The contact gap of step 2 (m).

        Returns
        -------
        t_c : array
            The search direction on the contact nodes (m; Pa when preconditioned); may be
            ``g_c`` itself.
        G : float
            g_c . g_c (m^2).
        """
        n_c = len(self.idx)
        G = dot(g_c, g_c)
        after = self.precondition_after
        use_pre = after is not None and self.stable >= after and n_c > 1 and self._box() is not None
        conj = self.conjugate and use_pre == self.pre_active
        self.pre_active = use_pre
        z_c = self._precondition(g_c) if use_pre else g_c
        rz = dot(g_c, z_c) if use_pre else G  # the CG's scalar (g . M g; g . g unpreconditioned)
        t_c = z_c + (rz / self.G_old) * self.t_c if (conj and self.G_old > 0) else z_c
        if t_c is not z_c and dot(g_c, t_c) <= 0.0:
            t_c = z_c  # not a descent direction: restart from (preconditioned) steepest descent
        self.G_old = rz
        self.gap_residual = math.sqrt(G / n_c) / self.h_scale if n_c else 0.0
        return t_c, G

    def _step_length(self, g_c, t_c, G):
        """Step 4: the step length ``self.tau`` from r = K t (mean-free on the contact under
        force control).

        Parameters
        ----------
        g_c : array
            The contact gap (m).
        t_c : array
            The search direction on the contact nodes (step 3).
        G : float
            g_c . g_c (m^2).

        Returns
        -------
        array or None
            r = K t on the full (flat) grid (m per unit of t), None when no step is taken.
        """
        idx = self.idx
        n_c = len(idx)
        # A contact gap at round-off level (e.g. the first step of a warm start at a new
        # load) gives no usable step: tau would be a ratio of round-off; only the force
        # balance (step 6) acts.
        if n_c > 0 and G > (1e-13 * self.h_scale) ** 2 * n_c:
            t_full = self.g  # free until step 5
            t_full.fill(0.0)
            t_full[idx] = t_c
            r_buf, spec_buf = self._buffers()
            r = convolve(self.op, t_full.reshape(self.shape), out=r_buf, spectrum=spec_buf).ravel()
            self.n_kt += 1
            r_c = r[idx]
            rt = dot(r_c, t_c)
            if self.force_control:
                rt -= float(r_c.mean()) * float(t_c.sum())
            del r_c
            self.tau = dot(g_c, t_c) / rt if rt > 0 else self.tau0
            return r
        if n_c > 0:
            self.tau = 0.0
        else:
            self.tau = self.tau0  # no contact yet: penetrating nodes enter with p = -g / K_00
        return None

    def _update_sets(self, t_c, step):
        """Step 5: update the pressure on the contact; every node's status from the full gap.

        Sets ``step.changed`` (a node changed status or the outside stresses were applied),
        ``step.p_c_old`` and, without a change, ``step.diff``; keeps the next search direction
        in ``self.t_c``.

        Parameters
        ----------
        t_c : array
            The search direction on the contact nodes (step 3).
        step : _Step
            The iteration's record; holds r = K t (step 4).
        """
        xp, p, idx = self.xp, self.p, self.idx
        step.p_c_old = p_c_old = p[idx]
        p_c_new = t_c * -self.tau  # p_c_old - tau t_c with one temporary
        p_c_new += p_c_old
        step.p_c_new = p_c_new
        step.stays = p_c_new > self.floor
        del p_c_new  # (the record holds it: the rebuild frees it)
        all_stay = bool(step.stays.all())
        level, any_overlap = self._full_gap()
        self.conjugate = not any_overlap
        out_changed = self._outside_stresses(step)
        defer = self._defer_smooth_change(step.out_new, out_changed, not any_overlap and all_stay)
        changed = any_overlap or (out_changed and not defer) or not all_stay
        step.changed = changed
        if changed:
            self.out_error = 0.0  # the rebuild below applies every outside stress
            t_c = self._rebuild_sets(t_c, level, any_overlap, step)
        else:
            p[idx] = step.p_c_new
            step.out_new = None
            step.diff = float(xp.abs(self.tau * t_c).sum()) if not self.force_control else None
        self.stable = 0 if changed else self.stable + 1
        self.t_c = t_c

    def _full_gap(self):
        """Step 5: the gap of every node into ``self.g`` and the overlapping nodes (non-contact
        nodes with a negative gap) into ``self.ovmask``; g = h + u (- delta).

        Returns
        -------
        level : float
            What remains to subtract from ``self.g`` for the gap (m): the approach under force
            control without an outside law, else 0.
        any_overlap : bool
            Whether a node overlaps.
        """
        xp, g, idx = self.xp, self.g, self.idx
        if self.force_control:
            xp.add(self.u, self.h, out=g)
            level = self.delta
        else:
            xp.subtract(self.h, self.shift, out=g)
            g += self.u
            level = 0.0
        overlap = self.ovmask
        if self.has_outside:
            if level != 0.0:
                g -= level
                level = 0.0
            g[idx] = 0.0
            xp.less(g, 0.0, out=overlap)  # contact nodes have g = 0 here
        else:
            xp.less(g, level, out=overlap)  # g - level < 0
            overlap[idx] = False
        return level, bool(overlap.any())

    def _outside_stresses(self, step):
        """Step 5: the outside stress of every node's gap, into ``step.out_new`` (Pa; None
        without an outside law), with the contact's old pressure on the contact nodes.

        Returns
        -------
        bool
            Whether the outside stress of a non-contact node changed.
        """
        if not self.has_outside:
            step.out_new = None
            return False
        out_new = self.inter.outside_stress(self.g, self.xp)
        if self.slope_fn is not None:
            # relaxed by the node's own response: p + (s - p) / (1 - C s')
            relaxed_outside_update(self.p, out_new, self.slope_fn(self.g, self.xp), _self_compliance(self.op),
                                   getattr(self.inter, "tension_limit", self.floor), self.xp, out=out_new)
        out_new[self.idx] = step.p_c_old  # compare only the non-contact nodes below
        step.out_new = out_new
        return not bool(self.xp.array_equal(out_new, self.p))

    def _defer_smooth_change(self, out_new, out_changed, settled):
        """Step 5: whether to defer a smooth change of the outside stresses.

        A smooth change (no node changes piece of the law, see interactions.base) is deferred
        while the CG on the frozen outside load is still making progress, and applied (with a
        restart: the load changed) once the CG has converged to the level of the outside
        mismatch: applying it at every iteration restarts the CG every iteration (steepest
        descent), and applying it while keeping the conjugate directions stalled them.
        Convergence requires the mismatch ``self.out_error`` (set here) to vanish.

        Parameters
        ----------
        out_new : array or None
            The new outside stresses (Pa), :meth:`_outside_stresses`.
        out_changed : bool
            Whether an outside stress of a non-contact node changed.
        settled : bool
            No node overlaps and every contact node stays.

        Returns
        -------
        bool
        """
        xp, p, g = self.xp, self.p, self.g
        smooth = False
        self.out_error = 0.0
        if self.branch_fn is not None:
            branch = self.branch_fn(g, xp)
            if out_changed and self.branch is not None:
                smooth = not bool(xp.any((branch != self.branch) & ~self.cflat))
            self.branch = branch
        if not (smooth and settled):
            return False
        work = g  # the gap is not needed any more (no overlap)
        xp.subtract(out_new, p, out=work)
        xp.abs(work, out=work)
        norm = float(xp.abs(p).sum())
        self.out_error = float(work.sum()) / norm if norm > 0 else float(work.sum())
        return self.error > DEFER_RATIO * self.out_error

    def _rebuild_sets(self, t_c, level, any_overlap, step):
        """Step 5 after a status change: rebuild the sets and their pressures.

        Leavers take the outside stress of their gap, overlapping nodes enter with
        p = s(g) - tau g (Paper A Eq. 21).  Only these nodes, the contact and the non-contact
        nodes whose outside stress changed get a new pressure: ``step.moved_nodes`` lists the
        non-contact ones, ``step.p_moved_old`` their old pressure.  Sets ``step.old_idx``,
        ``step.sparse`` and ``step.w_change`` (few changed nodes: their columns of K) and
        restarts the CG.

        Parameters
        ----------
        t_c : array
            The search direction on the old contact nodes.
        level : float
            What remains to subtract from ``self.g`` for the gap (m), :meth:`_full_gap`.
        any_overlap : bool
            Whether a node overlaps.
        step : _Step
            The iteration's record.

        Returns
        -------
        array
            The search direction on the new contact nodes (0 on the entering ones).
        """
        xp, p, idx = self.xp, self.p, self.idx
        step.old_idx = idx
        ov = g_ov = None
        if any_overlap:
            ov = xp.flatnonzero(self.ovmask)
            g_ov = self.g[ov] - level if level != 0.0 else self.g[ov]
        step.moved_nodes = moved_nodes = self._moved_nodes(step.out_new, ov)
        step.p_moved_old = p[moved_nodes]
        # The new pressure differs from the incremental one p - tau t on the leavers and
        # the moved nodes only (before the force balance): few of them -> kernel columns.
        leave = ~step.stays
        use_sparse = int(xp.count_nonzero(leave)) + len(moved_nodes) <= self.sparse_max
        if use_sparse:
            leavers = idx[leave]
            p_leavers_inc = step.p_c_new[leave]
        else:
            step.r = None  # an exact recomputation follows: free K t now
        self._set_pressure(leave, ov, g_ov, step)
        del leave
        if use_sparse:
            step.sparse = (xp.concatenate((leavers, moved_nodes)),
                           xp.concatenate((p[leavers] - p_leavers_inc, p[moved_nodes] - step.p_moved_old)))
        t_c = self._carry_direction(t_c, step.old_idx)
        # W = K(p_out + floor 1_C) of the new sets: the old one plus the columns of the
        # changed nodes (leavers: floor -> outside stress; entering: outside stress ->
        # floor; moved: old -> new outside stress), when there are few and it was known
        W_old, self.W = self.W, None
        if use_sparse and W_old is not None and not isinstance(W_old, float):
            entering = self.cflat[moved_nodes]
            w_new = xp.where(entering, self.floor, p[moved_nodes])
            step.w_change = (xp.concatenate((leavers, moved_nodes)),
                             xp.concatenate((p[leavers] - self.floor, w_new - step.p_moved_old)))
            step.W_old = W_old
        self.conjugate = False  # the problem changed: restart from steepest descent
        return t_c

    def _moved_nodes(self, out_new, ov):
        """Step 5: the non-contact nodes whose pressure changes: the overlapping ones and those
        whose outside stress changed.

        Parameters
        ----------
        out_new : array or None
            The new outside stresses (Pa), :meth:`_outside_stresses`.
        ov : array or None
            Flat indices of the overlapping nodes (None: none overlaps).

        Returns
        -------
        array
            Their flat indices.
        """
        xp = self.xp
        if out_new is None:
            return ov if ov is not None else self.idx[:0]
        out_moved = out_new != self.p
        if ov is not None:
            out_moved |= self.ovmask
        return xp.flatnonzero(out_moved)

    def _set_pressure(self, leave, ov, g_ov, step):
        """Step 5 after a status change: the new pressures and contact mask.

        The moved nodes take their new outside stress, the leavers the stress s0 of a node
        that just left, the staying contact nodes their CG update and the overlapping nodes
        enter (Paper A Eq. 21).  Frees ``step.out_new`` and ``step.p_c_new``.

        Parameters
        ----------
        leave : array of bool
            The contact nodes that leave (on ``self.idx``).
        ov : array or None
            Flat indices of the overlapping nodes (None: none overlaps).
        g_ov : array or None
            Their gap (m).
        step : _Step
            The iteration's record.
        """
        xp, p, idx = self.xp, self.p, self.idx
        if step.out_new is not None:
            p[step.moved_nodes] = step.out_new[step.moved_nodes]  # elsewhere out_new equals p already
        step.out_new = None
        # leavers take the stress s0 (0 without an outside law); in place, no temporary
        xp.copyto(step.p_c_new, self.s0[idx] if self.has_outside else self.s0, where=leave)
        p[idx] = step.p_c_new
        step.p_c_new = None
        cm = self.cflat
        cm[idx] = step.stays
        if ov is not None:
            # Paper A Eq. 21 with the step length; with no step this iteration (a contact gap
            # at round-off level, tau = 0) with a node's own stiffness 1 / K_00, as before any
            # contact: else the node enters at its outside stress with its overlap left, the
            # pressure does not change and convergence is declared on a penetrating state
            p[ov] -= (self.tau if self.tau > 0.0 else self.tau0) * g_ov
            cm[ov] = True

    def _carry_direction(self, t_c, old_idx):
        """Step 5 after a status change: the new contact nodes ``self.idx`` from the mask, and
        the search direction of the nodes that stay (0 on the entering ones), for the next
        conjugate step; ``self.g`` is free now and serves as the scatter buffer.

        Parameters
        ----------
        t_c : array
            The search direction on the old contact nodes ``old_idx``.
        old_idx : array
            The old contact nodes (flat indices).

        Returns
        -------
        array
            The search direction on the new contact nodes.
        """
        g = self.g
        self.idx = idx = self.xp.flatnonzero(self.cflat)
        g[idx] = 0.0
        g[old_idx] = t_c
        return g[idx]

    def _balance_force(self, step):
        """Step 6: force balance by scaling p - floor on the contact nodes (force control).

        Sets ``step.scale`` and, without a status change, ``step.diff`` (the change includes
        the rescale).

        Returns
        -------
        str or None
            A message when the contact cannot carry the force (no equilibrium), else None.
        """
        if not self.force_control:
            return None
        xp, p, idx, floor = self.xp, self.p, self.idx, self.floor
        n_new = len(idx)
        if n_new == 0:
            self.u_exact = False
            return _NO_CONTACT
        p_c = p[idx]
        total = float(p.sum()) if self.has_outside else float(p_c.sum())
        free = float(p_c.sum()) - floor * n_new
        fixed = total - float(p_c.sum())
        scale = (self.target - fixed - floor * n_new) / free if free > 0 else -1.0
        if scale <= 0:
            self.u_exact = False
            return ("the contact cannot carry the requested force: the load is beyond "
                    "pull-off (no equilibrium under force control)")
        new_c = scale * (p_c - floor) + floor if floor != 0.0 else scale * p_c
        if abs(scale - 1.0) > 1e-6:
            # A rescale (e.g. the first step after a load change) moves every gap: the
            # old conjugate direction no longer belongs to this problem.
            self.conjugate = False
        if not step.changed:  # same nodes: the change includes the force-balance rescale
            step.diff = float(xp.abs(new_c - step.p_c_old).sum())
        p[idx] = new_c
        step.scale = scale
        return None

    def _measure_change(self, step):
        """Relative pressure change ``self.error`` (Paper A Eq. 23, made relative); after a
        status change the pressure changed on the old contact and the moved nodes only.
        Restarts the CG when the pressure stopped moving while gaps stay open."""
        xp, p = self.xp, self.p
        if step.changed:
            dp = p[step.old_idx]
            dp -= step.p_c_old
            xp.abs(dp, out=dp)
            diff = float(dp.sum()) + float(xp.abs(p[step.moved_nodes] - step.p_moved_old).sum())
            del dp
            step.old_idx = step.moved_nodes = step.p_moved_old = None
        else:
            diff = step.diff
        norm = float(xp.abs(p).sum()) if (self.has_outside or self.floor != 0.0) else float(p[self.idx].sum())
        self.error = diff / norm if norm > 0 else diff
        if self.error < 1e-3 * self.gap_residual:
            # The pressure has stopped moving while gaps stay open: the conjugate direction
            # has degenerated (e.g. parallel to the pressure, which the force balance
            # undoes); restart from steepest descent.
            self.conjugate = False

    def _update_displacement(self, step):
        """The new displacement u = K p: incremental while nothing changed status, else exact
        or, when few nodes changed, incremental plus their columns of K.

            u <- s (u - tau K t + K d) + (1 - s) W,  W = K(p_out + floor 1_C)
        """
        self.since_exact += 1
        r, step.r = step.r, None
        scale = step.scale
        moved = r is not None or scale != 1.0
        if not step.changed and self.since_exact < self.refresh:
            if moved:
                self._add_step(r)
                if scale != 1.0:
                    self._rescale_displacement(scale)
                self.u_exact = False
        elif step.changed and step.sparse is not None and self.since_exact < self.refresh:
            self._add_step(r)
            del r
            self._add_columns(step)
            if scale != 1.0:
                # u <- s K p + (1 - s) W of the new sets (W: updated above, or one convolution)
                self._rescale_displacement(scale, skip_w=self.w_zero)
            self.n_sparse += 1
            self.u_exact = False
        elif step.changed or moved:
            del r
            self.make_exact()

    def _add_step(self, r):
        """u <- u - tau K t in place (r = K t, overwritten; None: no step)."""
        if r is not None:
            r *= -self.tau
            self.u += r

    def _rescale_displacement(self, scale, skip_w=False):
        """u <- s u + (1 - s) W in place, W = K(p_out + floor 1_C) (m, :meth:`_W`).

        Parameters
        ----------
        scale : float
            The force balance's scale s (step 6).
        skip_w : bool
            Take W = 0 without consulting :meth:`_W` (W is known to vanish).
        """
        u = self.u
        u *= scale
        W = 0.0 if skip_w else self._W()
        if not isinstance(W, float):
            u += (1.0 - scale) * W

    def _add_columns(self, step):
        """Add the columns of K of the few nodes whose pressure changed to u (``step.sparse``)
        and, when known, to W of the old sets (``step.w_change``: W of the new sets)."""
        if self.columns is None:
            self.columns = KernelColumns.of(self.op, self.spec_buf)
        nodes, values = step.sparse
        self.columns.add(self.u.reshape(self.shape), nodes, values, self.g.reshape(self.shape))
        self.n_columns += len(nodes)
        if step.w_change is not None:
            # the unscaled part's displacement of the new sets, from the old one (few columns)
            nodes, values = step.w_change
            self.columns.add(step.W_old.reshape(self.shape), nodes, values, self.g.reshape(self.shape))
            self.W = step.W_old
            self.n_columns += len(nodes)
