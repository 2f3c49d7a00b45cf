"""Tangential contact at a given pressure: partial slip with Coulomb friction (Paper D).

The problem (Paper D Eqs. 7, 12-13): on the compressive contact C+ (contact nodes with
p > 0; no shear in the adhesive zone, Paper D) find the shear q = (q_x, q_y) acting on body 1
such that, with the slip

    s = K_tt q + K_tz p - s_ref - delta,

* stick nodes: |q| < mu p and s = 0;
* slip nodes:  |q| = mu p and q opposes the slip, q = -mu p s/|s|;

and either the tangential force sum(q) dx dy = (F_x, F_y) (force control; the rigid shift
delta = (delta_x, delta_y) is an unknown) or delta given (displacement control).  ``s_ref`` is
zero in the "total" mode (slip measured from the undeformed state, Paper D: normal and
tangential loads applied in one step) and the relative displacement u1 - u2 - delta of the
previous step in the "incremental" mode (Paper E Eq. 5: the slip increment), which carries the
load history.  Classical, non-associated Coulomb friction: the normal gap is not affected by
slip (no dilatancy).

Method (ours; the thesis cites its tangential CGM without describing it).  The problem is the
minimisation of the convex energy 1/2 q.K_tt q + q.(K_tz p - s_ref) over the set C of tractions
with |q_i| <= mu p_i (the friction discs) and, under force control, sum(q) = F / (dx dy); the
rigid shift delta is the multiplier of that constraint.  Two solvers:

* ``method="tangcg"`` (default; the idea of Vollebregt's TangCG in CONTACT, written anew): a
  conjugate gradient over the stick nodes and the slip nodes, the slip tractions moving along
  their rim only, with the rim curvature |s.n| / (mu p) in their Jacobian (the linearised
  rotation of a traction that must oppose its slip: this is what keeps rotating slip directions
  stable), the tractions put back on the rim after each step, and every 2 steps (4 with the
  diagonal preconditioner) an exact slip and an update of the element division (stick tractions
  beyond their disc slip, slip nodes whose slip runs along their traction stick again; restart).
  Under force control the search direction carries no net force and delta is the mean slip of
  the stick nodes (Polonsky-Keer's mean gap).  When no node sticks (a state at or beyond the
  gross-slip onset, below mu F0+: the slip tractions turn away from the load), every node moves
  along its rim, the direction is projected onto the rim moves that keep the force, delta is the
  least-squares fit of the rim components of the slip (the force balance's multiplier), and at
  the checks the force is restored by turning the tractions, q_i = mu p_i (q_i + lambda)/|q_i +
  lambda|; nodes whose slip runs along their traction stick again as usual.  (Before, these
  states fell to the projected gradient: 5-10x the iterations, half of a rough burl's ramp.)
  Preconditioner (``preconditioner=``):

  - ``"fft"`` (default): on the stick nodes z = P_S M P_S r, M the convolution whose 2x2 symbol
    is the inverse, wavevector by wavevector, of the symbol of K_tt (as NormCG's M for the
    normal block, :mod:`.normal_cg`); slip nodes keep the diagonal one (they move along their
    rim only, with the curvature term).  M acts on the bounding box of the contact (a periodic
    box of m1 x m2 cells): its symbol is that of Strang's circulant approximation of K_tt on the
    box (the kernels cut to offsets |d| <= m/2 and wrapped), not the operator's own (padded)
    spectrum: the box transform is much smaller than the padded one, and the preconditioner
    better.  Slip nodes in M as well (scaled by K_ii/(K_ii + curvature)) was tried and needs
    more iterations on larger loops.  The iteration count barely grows with the grid; the
    stick nodes and tractions are those of the diagonal preconditioner to the tolerance;
  - ``"diagonal"``: K_ii (and K_ii + curvature on slip nodes): fewer convolutions per iteration
    (no preconditioner convolution) but an iteration count that grows with the grid.

  Either needs several times fewer iterations than the projected gradient.  On a free-boundary
  grid the product K_tt v of an iteration is a cyclic convolution on the contact's bounding box
  (m1 x m2 cells, N >= 2m - 1 points per axis: exact, since the shear vanishes outside the
  contact and the slip is needed on it only), not on the padded 2nx x 2ny grid;
* ``method="fista"``, and the fallback when TangCG stalls: an accelerated projected gradient
  (FISTA, Beck and Teboulle 2009) with adaptive restart (O'Donoghue and Candes 2015): a gradient
  step of length 1/L (L the largest eigenvalue of the 2x2 symbol of K_tt) and the exact
  projection onto C (q_i = P_disc_i(z_i + lambda), the 2-D multiplier lambda found by
  safeguarded Newton steps on the monotone force balance; delta = L lambda at the fixed point).
  Every iteration is a descent step of a convex problem, so it converges from any start,
  including the all-slip states of gross sliding.

Convergence needs both the relative traction change sum|dq| / sum mu p and the stick-slip
complementarity residual to fall below ``tol``: the rms over C+ of |s| on stick nodes and of
the part of s that does not oppose q on slip nodes, relative to the slip scale
max|K_tt (mu p e_x)| (the displacement that full slip along x would produce).  The solver never
stops silently short of the tolerance: non-convergence gives ``converged=False``, the
residual history and a :class:`~tribobem.errors.ConvergenceWarning` (or an error with
``strict=True``).

The elasticity (K_tt, K_tz, K_zt, the box convolutions and the FFT preconditioner) is
:class:`~tribobem.elasticity.tangential.TangentialOperator`; the iteration loop (checks, stall
detection, history, messages) is :func:`.iteration.run_iterations`, which runs TangCG
(:class:`_TangCG`) and the projected gradient (:class:`_ProjectedGradient`).  Measured
iteration counts: benchmarks/README.md (the TangCG section, and "Solver notes moved from
docstrings").
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..elasticity.tangential import TangentialOperator, tangential_operator  # noqa: F401 (benchmarks' conv_timer)
from ..errors import InputError
from ..results import TangentialResult
from .iteration import IterativeSolver, dot, report_failure, run_iterations

__all__ = ["GrossSlipError", "solve_tangential"]


#: Preconditioner of TangCG when ``solve_tangential(preconditioner=None)`` (also the one the
#: coupling loop and the load paths use).
DEFAULT_PRECONDITIONER = "fft"
# Single-precision search directions: TangCG's images K v of its search directions and its FFT
# preconditioner are transformed in single precision where the backend supports it
# (``Backend.single_precision``: free boundary, the NumPy backend; a backend without it runs
# them in double precision).  Their error, ~1e-7 of the step, does not reach the solution or the
# convergence test: every check of the element division recomputes K q exactly in double
# precision and measures the residual from it (``_TangCG._exact``).
#: With single-precision search directions, the exact K q of a check as the last one plus K of
#: the change of q in single precision, while that change is at most this fraction of |q| (L1;
#: see ``_TangCG._exact``),
#: at a tolerance of at most ``INCREMENTAL_TOL``; above it the fraction grows with the tolerance,
#: to at most 100x (the loose solves of the coupling loop's predictor and early passes).
INCREMENTAL_EXACT = 1e-3
INCREMENTAL_TOL = 1e-7
#: ... for at most this many checks in a row (then one in double precision: the single-precision
#: errors of a long solve do not add up).
INCREMENTAL_CHECKS = 20


class GrossSlipError(InputError):
    """The tangential force exceeds what the contact can carry (gross sliding).

    Parameters
    ----------
    field : str
        The input the error is about (as for :class:`~tribobem.errors.InputError`).
    message : str
        What went wrong.
    max_force : float
        The largest tangential force magnitude with an equilibrium (N).

    Attributes
    ----------
    max_force : float
        The largest tangential force magnitude with an equilibrium, mu F0+ (N).
    """

    def __init__(self, field: str, message: str, max_force: float):
        self.max_force = max_force
        super().__init__(field, message)


def beyond_capacity_error(force: float, capacity: float, mu: float) -> GrossSlipError:
    """The GrossSlipError of a tangential force |F_t| = ``force`` (N) at or beyond mu F0+ =
    ``capacity`` (N)."""
    why = ("the friction coefficient is 0 (frictionless): any tangential force is gross sliding"
           if mu == 0 else f"it reaches mu F0+ = {capacity:.6g} N, the most the contact can carry")
    return GrossSlipError("friction.tangential_force",
                          f"gross sliding: |F_t| = {force:.6g} N has no equilibrium; {why}", capacity)


def _as_pair(value, name: str):
    """(x, y) from a pair or a scalar (taken along x); InputError naming ``name`` otherwise."""
    if value is None:
        return None
    try:
        if np.ndim(value) == 0:
            a, b = float(value), 0.0
        else:
            vals = [float(v) for v in np.asarray(value, dtype=float).ravel()]
            if len(vals) != 2:
                raise InputError(name, f"must be a number or an (x, y) pair, got {len(vals)} components: {value!r}")
            a, b = vals
    except (TypeError, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError(name, f"must be a number or an (x, y) pair of numbers, got {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise InputError(name, f"must be finite, got {value!r}")
    return np.array([a, b])


class _TangentialProblem(NamedTuple):
    """Checked inputs and start of a tangential solve (see :func:`_tangential_problem`).

    The node arrays are on the compressive contact C+ (``contact``), in the order of ``idx``.
    """

    mu: float
    """Friction coefficient (>= 0)."""
    preconditioner: str
    """Preconditioner of TangCG, ``"fft"`` or ``"diagonal"`` (the default resolved)."""
    pressure: object
    """Normal traction p (Pa), a backend array of ``grid.shape``."""
    contact: object
    """Compressive contact C+: the given contact mask & (p > 0)."""
    idx: object
    """Flat grid indices of the nodes of C+."""
    bound: object
    """Friction-disc radii mu p (Pa) on C+."""
    capacity: float
    """mu F0+ (N), the largest tangential force with an equilibrium."""
    pressure_displacement: tuple
    """(K_xz p, K_yz p) (m) on the full grid, or (None, None) without normal-tangential coupling."""
    reference: object
    """Incremental mode: the reference relative displacement (m), shape (2, nx, ny); else None."""
    v0: object
    """Fixed part of the slip K_tz p - s_ref (m), shape (2, n_c)."""
    force_control: bool
    """True when the force is given, False when the displacement is."""
    target: object
    """Force control: the target sum of q (Pa), F / cell area; else None."""
    delta: object
    """Initial rigid shift (m): 0 under force control, the given displacement otherwise."""
    displacement: object
    """Displacement control: the given (delta_x, delta_y) (m); else None."""
    shear: object
    """Initial shear q (Pa), shape (2, n_c), inside the friction discs."""


def solve_tangential(
    operator: ConvolutionOperator,
    pressure,
    contact,
    *,
    friction_coefficient: float,
    force=None,
    displacement=None,
    reference=None,
    initial_shear=None,
    initial_stick=None,
    pressure_displacement=None,
    tol: float = 1e-8,
    max_iterations: int = 5000,
    strict: bool = False,
    stall: int = 1000,
    method: str = "tangcg",
    preconditioner: str | None = None,
    slip_scale: float | None = None,
    full_fields: bool = True,
) -> TangentialResult:
    """Solve the partial-slip problem at a given pressure.

    Parameters
    ----------
    operator : ConvolutionOperator
        Coupled operator with components ("x", "y", "z").
    pressure : array_like
        Normal traction p (Pa) of the solved normal problem.
    contact : array_like of bool
        Its contact mask; shear acts on ``contact & (p > 0)`` only.
    friction_coefficient : float
        mu >= 0 (0: frictionless, any tangential force is gross sliding).
    force : (float, float) or float, optional
        Tangential force (F_x, F_y) on body 2 in N (force control).
    displacement : (float, float) or float, optional
        Rigid tangential displacement (delta_x, delta_y) of body 2 relative to body 1 in m
        (displacement control).  Give exactly one of ``force`` and ``displacement``.
    reference : array_like, shape (2, nx, ny), optional
        Relative displacement u1 - u2 - delta of the previous step (incremental mode, Paper E
        Eq. 5): the slip is measured from it.  None: total mode (from the undeformed state).
    initial_shear : array_like, shape (2, nx, ny), optional
        Warm start (Pa), e.g. the shear of the previous step or coupling iteration.
    initial_stick : array_like of bool, optional
        The stick mask that goes with ``initial_shear``.  Its slip nodes start on the rim of
        their (new) friction disc, in the direction of their warm-start traction: without it a
        slip node whose bound mu p grew would start inside its disc, as a stick node, and the
        first iterations would undo the warm start.
    pressure_displacement : array_like, shape (2, nx, ny), optional
        K_tz p if already known (saves a convolution).
    tol : float
        Tolerance on the relative traction change and the complementarity residual.
    max_iterations : int
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` instead of warning.
    stall : int
        Stop (not converged) after this many iterations without improving the residual.
    method : {"tangcg", "fista"}
        "tangcg" (default): conjugate gradients on the stick and slip nodes with the rim
        curvature term (see the module docstring; also for states in which no node sticks),
        falling back to "fista" when it does not converge; "fista": the accelerated projected
        gradient only.
    preconditioner : {"fft", "diagonal"}, optional
        Preconditioner of "tangcg" (see the module docstring): "fft", the inverse symbol of
        K_tt on the contact's bounding box applied to the stick nodes, or "diagonal", the
        self-compliances.  None: :data:`DEFAULT_PRECONDITIONER`.  Either gives the solution to
        ``tol``; only the iteration path differs.
    slip_scale : float, optional
        The slip scale (m) that makes the complementarity residual relative (see the module
        docstring), if known: the coupling loop passes the value of its first tangential solve to
        the later ones of the same step, whose pressures differ by < 1e-2 relative (saves one
        tangential convolution, 4 FFTs, per call).  None: computed from this pressure.
    full_fields : bool
        False: skip the final tangential convolution (4 FFTs); ``slip`` and
        ``relative_displacement`` of the result are then NaN (for the intermediate passes of the
        coupling loop, which use only the shear and the stick mask).

    Returns
    -------
    TangentialResult

    Raises
    ------
    GrossSlipError
        Under force control when |F| >= mu F0+ (no equilibrium: gross sliding), or mu = 0
        with a nonzero force.
    InputError
        Bad friction coefficient, load, shapes or non-finite values.
    """
    t_start = time.perf_counter()
    top = tangential_operator(operator)
    prob = _tangential_problem(
        top, pressure, contact, friction_coefficient=friction_coefficient, force=force,
        displacement=displacement, reference=reference, initial_shear=initial_shear,
        initial_stick=initial_stick, pressure_displacement=pressure_displacement, tol=tol,
        method=method, preconditioner=preconditioner, max_iterations=max_iterations)
    kii = np.array(top.self_compliance)
    st = _Tangential(top, prob.idx, prob.bound, prob.v0, prob.shear, prob.delta, prob.force_control,
                     prob.target, kii, top.lipschitz)
    # Slip scale (m): displacement of full slip along x.
    s_scale = float(slip_scale) if slip_scale is not None and slip_scale > 0 else st.slip_scale()
    converged, message, history = _run_solvers(st, prob.mu, s_scale, tol=tol, max_iterations=max_iterations,
                                               stall=stall, method=method, preconditioner=prob.preconditioner)
    return _tangential_result(top, prob, st, converged, message, history, s_scale=s_scale, method=method,
                              strict=strict, full_fields=full_fields, t_start=t_start)


def _check_options(friction_coefficient, force, displacement, tol, method, preconditioner, max_iterations):
    """Check the scalar arguments of :func:`solve_tangential`.

    Parameters
    ----------
    friction_coefficient, force, displacement, tol, method, preconditioner, max_iterations
        As for :func:`solve_tangential`.

    Returns
    -------
    mu : float
        The friction coefficient.
    force, displacement : ndarray, shape (2,), or None
        (x, y) of the given load (N, resp. m); the other one None.
    preconditioner : str
        The preconditioner, :data:`DEFAULT_PRECONDITIONER` for None.

    Raises
    ------
    InputError
        Bad friction coefficient, load, tolerance, method, preconditioner or iteration limit.
    """
    mu = friction_coefficient
    if isinstance(mu, (bool, np.bool_)) or not isinstance(mu, (int, float, np.integer, np.floating)) \
            or not math.isfinite(mu) or mu < 0:
        raise InputError("solve_tangential.friction_coefficient", f"must be a finite number >= 0, got {mu!r}")
    mu = float(mu)
    if (force is None) == (displacement is None):
        raise InputError("friction", "give exactly one of force (force control) or displacement (displacement control)")
    F = _as_pair(force, "solve_tangential.force")
    D = _as_pair(displacement, "solve_tangential.displacement")
    if not (tol > 0 and math.isfinite(tol)):
        raise InputError("solve_tangential.tol", f"must be a finite value > 0, got {tol!r}")
    if method not in ("tangcg", "fista"):
        raise InputError("solve_tangential.method", f"must be 'tangcg' or 'fista', got {method!r}")
    if preconditioner is None:
        preconditioner = DEFAULT_PRECONDITIONER
    if preconditioner not in ("diagonal", "fft"):
        raise InputError("solve_tangential.preconditioner",
                         f"must be 'diagonal' or 'fft', got {preconditioner!r}")
    if not isinstance(max_iterations, (int, np.integer)) or max_iterations < 1:
        raise InputError("solve_tangential.max_iterations", f"must be an integer >= 1, got {max_iterations!r}")
    return mu, F, D, preconditioner


def _tangential_problem(top, pressure, contact, *, friction_coefficient, force, displacement, reference,
                        initial_shear, initial_stick, pressure_displacement, tol, method, preconditioner,
                        max_iterations) -> _TangentialProblem:
    """Check the inputs of :func:`solve_tangential` and build its start.

    Parameters
    ----------
    top : TangentialOperator
        The elasticity of the tangential problem.
    pressure, contact, friction_coefficient, force, displacement, reference, initial_shear, ...
        As for :func:`solve_tangential` (all its arguments but ``operator``, ``strict``, ``stall``,
        ``slip_scale`` and ``full_fields``).

    Returns
    -------
    _TangentialProblem

    Raises
    ------
    GrossSlipError
        Under force control when |F| >= mu F0+, or a nonzero force without compressive contact.
    InputError
        Bad friction coefficient, load, shapes or non-finite values.
    """
    xp, grid = top.xp, top.grid
    mu, F, D, preconditioner = _check_options(friction_coefficient, force, displacement, tol, method,
                                              preconditioner, max_iterations)
    p = xp.asarray(pressure, dtype=float)
    if p.shape != grid.shape:
        raise InputError("pressure", f"shape {tuple(p.shape)} does not match the grid {grid.shape}")
    if not bool(xp.all(xp.isfinite(p))):
        raise InputError("pressure", "contains NaN or infinite values")
    # The compressive contact C+ carries the shear (none in the adhesive zone, Paper D).
    cmask = xp.asarray(contact, dtype=bool) & (p > 0)
    idx = xp.flatnonzero(cmask.ravel())
    bound = mu * p.ravel()[idx]  # friction-disc radii (Pa)
    capacity = float(bound.sum()) * grid.cell_area  # mu F0+ (N)
    (wx, wy), ref_full, v0 = _fixed_slip(top, p, idx, reference, pressure_displacement)
    force_control, target, delta = _load(F, D, int(idx.size), capacity, mu, grid.cell_area)
    q = _initial_shear(xp, grid, idx, bound, initial_shear, initial_stick, F, capacity)
    return _TangentialProblem(mu, preconditioner, p, cmask, idx, bound, capacity, (wx, wy), ref_full, v0,
                              force_control, target, delta, D, q)


def _fixed_slip(top, p, idx, reference, pressure_displacement):
    """The fixed part of the slip, K_tz p - s_ref, on the contact nodes.

    Parameters
    ----------
    top : TangentialOperator
        The elasticity of the tangential problem.
    p : array
        Normal traction (Pa), ``grid.shape``.
    idx : array of int
        Flat grid indices of the contact nodes.
    reference, pressure_displacement
        As for :func:`solve_tangential`.

    Returns
    -------
    pressure_displacement : (array, array) or (None, None)
        K_xz p, K_yz p (m) on the full grid; (None, None) without normal-tangential coupling
        and none given.
    reference : array or None
        The reference relative displacement (m), shape (2, nx, ny), in the incremental mode.
    v0 : array, shape (2, n_c)
        K_tz p - s_ref (m) on the contact nodes.

    Raises
    ------
    InputError
        ``reference`` of the wrong shape.
    """
    xp, grid = top.xp, top.grid
    if pressure_displacement is None:
        wx, wy = top.from_pressure(p) if top.coupled else (None, None)
    else:
        wx, wy = (xp.asarray(a, dtype=float) for a in pressure_displacement)
    v0 = xp.zeros((2, int(idx.size)))
    if wx is not None:
        v0[0] = wx.ravel()[idx]
        v0[1] = wy.ravel()[idx]
    ref_full = None
    if reference is not None:
        # Incremental mode (Paper E Eq. 5): the slip is measured from the previous step.
        ref_full = xp.asarray(reference, dtype=float)
        if ref_full.shape != (2,) + grid.shape:
            raise InputError("reference", f"shape {tuple(ref_full.shape)} must be (2, {grid.nx}, {grid.ny})")
        v0[0] -= ref_full[0].ravel()[idx]
        v0[1] -= ref_full[1].ravel()[idx]
    return (wx, wy), ref_full, v0


def _load(F, D, n_c: int, capacity: float, mu: float, cell: float):
    """The load of the solve: force control with its target, or the given rigid shift.

    Parameters
    ----------
    F, D : ndarray, shape (2,), or None
        The given force (N) or displacement (m), exactly one not None.
    n_c : int
        Number of compressive contact nodes.
    capacity : float
        mu F0+ (N).
    mu : float
        Friction coefficient.
    cell : float
        Cell area (m^2).

    Returns
    -------
    force_control : bool
    target : ndarray, shape (2,), or None
        Force control: the target sum of q (Pa); else None.
    delta : ndarray, shape (2,)
        Initial rigid shift (m): zero under force control, a copy of ``D`` otherwise.

    Raises
    ------
    GrossSlipError
        A force at or beyond mu F0+ (gross sliding: no equilibrium).
    """
    force_control = F is not None
    if force_control:
        Fmag = float(np.hypot(*F))
        if n_c == 0 and Fmag > 0:
            raise GrossSlipError("friction.tangential_force",
                                 f"a tangential force of {Fmag:.4g} N with no compressive contact: nothing can carry it "
                                 "(gross sliding)", 0.0)
        if Fmag >= capacity * (1.0 - 1e-12) and Fmag > 0:
            raise beyond_capacity_error(Fmag, capacity, mu)
        target = F / cell  # target sum of q (Pa)
        delta = np.zeros(2)
    else:
        target = None
        delta = D.copy()
    return force_control, target, delta


def _initial_shear(xp, grid, idx, bound, initial_shear, initial_stick, F, capacity: float):
    """The initial shear: the warm start projected onto the discs, else zero (all nodes stick).

    Parameters
    ----------
    xp : module
        The backend's array module.
    grid : Grid
        The grid.
    idx : array of int
        Flat grid indices of the contact nodes.
    bound : array
        Friction-disc radii mu p (Pa) of the contact nodes.
    initial_shear, initial_stick
        As for :func:`solve_tangential`.
    F : ndarray, shape (2,), or None
        The given force (N) under force control, else None.
    capacity : float
        mu F0+ (N).

    Returns
    -------
    array, shape (2, n_c)
        The shear q (Pa) on the contact nodes, inside (or on the rim of) the friction discs.

    Raises
    ------
    InputError
        ``initial_shear`` or ``initial_stick`` of the wrong shape.
    """
    q = xp.zeros((2, int(idx.size)))
    if initial_shear is not None:
        q0 = xp.asarray(initial_shear, dtype=float)
        if q0.shape != (2,) + grid.shape:
            raise InputError("initial_shear", f"shape {tuple(q0.shape)} must be (2, {grid.nx}, {grid.ny})")
        q[0] = q0[0].ravel()[idx]
        q[1] = q0[1].ravel()[idx]
        if initial_stick is not None:
            st0 = xp.asarray(initial_stick, dtype=bool)
            if st0.shape != grid.shape:
                raise InputError("initial_stick", f"shape {tuple(st0.shape)} must be ({grid.nx}, {grid.ny})")
            # Warm-start slip nodes onto the rim of their (new) disc, in their traction's direction.
            slip0 = ~st0.ravel()[idx]
            mag0 = xp.sqrt(q[0] ** 2 + q[1] ** 2)
            on_rim = slip0 & (mag0 > 0)
            f = xp.where(on_rim, bound / xp.where(mag0 > 0, mag0, 1.0), 1.0)
            q *= f
        _project(xp, q, bound)
    elif F is not None and capacity > 0:
        # Admissible start with the right force: q = (F / mu F0+) mu p, all nodes stick.
        cell = grid.cell_area
        q[0] = bound * (F[0] * cell / capacity)
        q[1] = bound * (F[1] * cell / capacity)
    return q


def _run_solvers(st, mu: float, s_scale: float, *, tol, max_iterations, stall, method, preconditioner):
    """Iterate to the tolerance: TangCG, then (or only) the accelerated projected gradient.

    Parameters
    ----------
    st : _Tangential
        The working state, updated in place (its ``cg_iterations`` set after TangCG).
    mu : float
        Friction coefficient.
    s_scale : float
        Slip scale (m) of the complementarity residual.
    tol, max_iterations, stall, method, preconditioner
        As for :func:`solve_tangential` (``preconditioner`` resolved).

    Returns
    -------
    converged : bool
    message : str
    history : list of float
        The residual history of both solvers.
    """
    history: list[float] = []
    converged, message = False, ""
    if st.n == 0:
        converged, message = True, "no compressive contact: no shear"
    elif mu == 0.0:
        converged, message = True, "frictionless (mu = 0): no shear"
        st.finish_frictionless()
    else:
        used = 0
        if method == "tangcg":
            cg = _TangCG(st, s_scale, tol, preconditioner)
            out = run_iterations(cg, tol=tol, max_iterations=max_iterations, stall=min(stall, 400), history=history)
            converged, used, message = out.converged, out.iterations, out.message
            st.cg_iterations = used
            if not converged:
                # Fall back to the accelerated projected gradient from the best (admissible) state.
                cg.restore_best()
                st.reset_momentum()
                message = f"TangCG: {message}; continued by the projected gradient"
        # (when TangCG used up the iteration limit, its message stands)
        if not converged and (used < max_iterations or not history):
            out = run_iterations(_ProjectedGradient(st, s_scale, message), tol=tol, max_iterations=max_iterations,
                                 stall=stall, history=history, first=used + 1)
            converged, message = out.converged, out.message
    return converged, message, history


def _final_fields(top, prob: _TangentialProblem, st, full_fields: bool):
    """The full-grid fields of the result, consistent with the final shear.

    Parameters
    ----------
    top : TangentialOperator
        The elasticity of the tangential problem.
    prob : _TangentialProblem
        The checked inputs.
    st : _Tangential
        The final working state.
    full_fields : bool
        As for :func:`solve_tangential` (False: slip and relative displacement NaN).

    Returns
    -------
    shear : (array, array)
        q_x, q_y (Pa), ``grid.shape``.
    slip, relative : (array, array)
        The slip and the relative displacement u1 - u2 - delta (m), ``grid.shape`` each.
    delta : ndarray, shape (2,)
        The rigid shift (m).
    stick : array of bool
        The stick mask, ``grid.shape``.
    """
    xp, grid, idx = top.xp, top.grid, prob.idx
    qx = xp.zeros(grid.size if hasattr(grid, "size") else grid.nx * grid.ny)
    qy = xp.zeros_like(qx)
    qx[idx] = st.q[0]
    qy[idx] = st.q[1]
    qx, qy = qx.reshape(grid.shape), qy.reshape(grid.shape)
    delta = st.delta if prob.force_control else prob.displacement
    if full_fields:
        wx, wy = prob.pressure_displacement
        ux, uy = top.shear_displacement(qx, qy)
        relx, rely = ux - delta[0], uy - delta[1]
        if wx is not None:
            relx = relx + wx
            rely = rely + wy
        slipx, slipy = relx, rely
        if prob.reference is not None:
            slipx = relx - prob.reference[0]
            slipy = rely - prob.reference[1]
    else:
        relx = rely = slipx = slipy = xp.full(grid.shape, np.nan)
    stick = xp.zeros(grid.nx * grid.ny, dtype=bool)
    stick[idx] = st.stick
    stick = stick.reshape(grid.shape)
    return (qx, qy), (slipx, slipy), (relx, rely), delta, stick


def _tangential_result(top, prob: _TangentialProblem, st, converged: bool, message: str, history, *,
                       s_scale: float, method: str, strict: bool, full_fields: bool,
                       t_start: float) -> TangentialResult:
    """Assemble the result of :func:`solve_tangential`; warn (or raise) when not converged.

    Parameters
    ----------
    top : TangentialOperator
        The elasticity of the tangential problem.
    prob : _TangentialProblem
        The checked inputs.
    st : _Tangential
        The final working state.
    converged, message, history
        The outcome of :func:`_run_solvers`.
    s_scale : float
        Slip scale (m) of the complementarity residual.
    method, strict, full_fields
        As for :func:`solve_tangential`.
    t_start : float
        ``time.perf_counter()`` at the start of the solve.

    Returns
    -------
    TangentialResult
        Host (NumPy) arrays.

    Raises
    ------
    ConvergenceError
        With ``strict``, when the solve did not converge.
    """
    (qx, qy), (slipx, slipy), (relx, rely), delta, stick = _final_fields(top, prob, st, full_fields)
    cell, n_c = top.grid.cell_area, st.n
    fx = float(st.q[0].sum()) * cell
    fy = float(st.q[1].sum()) * cell
    gross = n_c > 0 and not bool(st.stick.any())
    if not converged:
        # stacklevel 3: this function <- solve_tangential <- its caller
        report_failure(message, strict=strict, prefix="tangential solver: ", stacklevel=3)
    tn = top.be.to_numpy
    return TangentialResult(
        grid=top.grid,
        shear=np.stack([tn(qx), tn(qy)]),
        slip=np.stack([tn(slipx), tn(slipy)]),
        relative_displacement=np.stack([tn(relx), tn(rely)]),
        contact=tn(prob.contact),
        stick=tn(stick),
        force_x=fx,
        force_y=fy,
        displacement_x=float(delta[0]),
        displacement_y=float(delta[1]),
        friction_coefficient=float(prob.mu),
        mode="total" if prob.reference is None else "incremental",
        control="force" if prob.force_control else "displacement",
        iterations=len(history),
        residual_history=np.asarray(history),
        converged=converged,
        gross_slip=gross,
        time=time.perf_counter() - t_start,
        message=message,
        info={"capacity": prob.capacity, "slip_scale": s_scale, "convolutions": st.n_apply,
              "preconditioner_convolutions": st.n_precondition, "preconditioner": prob.preconditioner,
              "restarts": st.restarts, "method": method,
              "convolution_box": (st._apply_box() or (None,))[0] if n_c else None,
              "tangcg_iterations": getattr(st, "cg_iterations", 0)},
    )


def _project(xp, q, bound):
    """Project the tractions q (2, n) onto the discs |q| <= bound, in place; returns the mask
    of the nodes that were on or beyond the rim."""
    mag = xp.sqrt(q[0] * q[0] + q[1] * q[1])
    over = mag >= bound
    if bool(over.any()):
        with np.errstate(invalid="ignore", divide="ignore"):
            f = xp.where(over, bound / xp.where(mag > 0, mag, 1.0), 1.0)
        q *= f
    return over


def _less_delta(s, delta):
    """``s - delta[:, None]``, in place on the fresh (2, n) array ``s``: the host 2-vector
    ``delta`` (the rigid shift) enters as two scalars, not as an array copied to the device
    every iteration."""
    s[0] -= delta[0]
    s[1] -= delta[1]
    return s


def _force_multiplier(xp, z, bound, target, lam, rim=False):
    """The tractions q_i = P_i(z_i + lam) whose sum is ``target``, and the 2-D multiplier lam.

    P_i projects onto the disc |q| <= bound_i (``rim=True``: onto its rim, every node slipping).
    lam by damped Newton steps on the force balance, the gradient of a convex function of lam
    (sum of the discs' Moreau envelopes, or of b_i |z_i + lam| on the rims), from ``lam``.
    Returns (q_x, q_y, lam).
    """
    b, F = bound, target
    lam = np.array(lam, dtype=float)
    fscale = float(b.sum()) + float(np.abs(F).max()) + 1e-300

    def evaluate(lam):
        wx, wy = z[0] + lam[0], z[1] + lam[1]
        mag = xp.sqrt(wx * wx + wy * wy)
        out = xp.ones(mag.shape, dtype=bool) if rim else mag > b
        f = xp.where(out, b / xp.where(mag > 0, mag, 1e-300 if rim else 1.0), 1.0)
        qx, qy = wx * f, wy * f
        res = np.array([float(qx.sum()) - F[0], float(qy.sum()) - F[1]])
        return qx, qy, mag, out, f, res

    qx, qy, mag, out, f, res = evaluate(lam)
    for _ in range(60):
        nr = float(np.hypot(*res))
        if nr <= 1e-13 * fscale:
            break
        # Jacobian: I on interior nodes, (b/|w|)(I - e e^T) on rim nodes.
        n_in = float((~out).sum())
        ex = xp.where(out, (z[0] + lam[0]) / xp.where(mag > 0, mag, 1.0), 0.0)
        ey = xp.where(out, (z[1] + lam[1]) / xp.where(mag > 0, mag, 1.0), 0.0)
        fo = xp.where(out, f, 0.0)
        jxx = n_in + float((fo * (1 - ex * ex)).sum())
        jyy = n_in + float((fo * (1 - ey * ey)).sum())
        jxy = -float((fo * ex * ey).sum())
        J = np.array([[jxx, jxy], [jxy, jyy]])
        J += 1e-12 * (jxx + jyy + 1.0) * np.eye(2)
        try:
            step = np.linalg.solve(J, res)
        except np.linalg.LinAlgError:
            step = res / max(jxx + jyy, 1.0)
        a = 1.0
        for _ in range(40):
            cand = lam - a * step
            c = evaluate(cand)
            if float(np.hypot(*c[5])) < nr:
                break
            a *= 0.5
        lam = cand
        qx, qy, mag, out, f, res = c
    return qx, qy, lam


class _Tangential:
    """Working state of the accelerated projected-gradient iteration on the contact set."""

    # A stick node is strictly inside its disc; slip nodes sit on the rim.
    RIM = 1.0 - 1e-9

    def __init__(self, top, idx, bound, v0, q, delta, force_control, target, kii, lipschitz):
        self.top, self.xp = top, top.xp
        self.idx, self.bound, self.v0 = idx, bound, v0
        self.force_control, self.target = force_control, target
        self.kii = kii
        self.L = lipschitz
        self.n = int(idx.size)
        # row stride -> gather indices of the contact nodes in the box transform (_gather_index)
        self._gather_cache = {}
        size = top.grid.nx * top.grid.ny
        self.full = (self.xp.zeros(size), self.xp.zeros(size))
        self.delta = np.array(delta, dtype=float)
        self.lam = np.zeros(2)
        self.q = q
        self.Kq = self._apply(q)
        self.y, self.Ky = q.copy(), self.Kq.copy()
        self.t_mom = 1.0
        self.stick = self._stick_mask()
        self.change = float("inf")
        self.complementarity = float("inf")
        self.n_apply = 2
        self.n_precondition = 0
        self._box_data = None
        self.restarts = 0

    def _stick_mask(self):
        xp = self.xp
        mag = xp.sqrt(self.q[0] ** 2 + self.q[1] ** 2)
        return mag < self.bound * self.RIM

    def _apply(self, t, single: bool = False):
        """K_tt t on the contact nodes, for t (2, n) given on them (one tangential convolution).

        Free boundary: the convolution on the contact's bounding box only
        (:meth:`TangentialOperator.box_shear_displacement`, exact: the tractions vanish outside
        it and the slip is needed on the contact nodes only), when its transform is smaller than
        0.8 x the padded grid's; the contact of a ball over +-2a fills about half of each axis,
        so the box transform is about a third of the padded one.  Else the padded operator.

        ``single``: the box convolution in single precision where the backend supports it (the
        images of TangCG's search directions, see the single-precision note at
        :data:`INCREMENTAL_EXACT`); the result is
        float64 either way."""
        boxed = self._apply_box()
        if boxed is not None:
            box, local, bx, by = boxed
            bx[local] = t[0]
            by[local] = t[1]
            ux, uy = self.top.box_shear_displacement(bx.reshape(box), by.reshape(box), single=single, scratch=True)
            bx[local] = 0.0
            by[local] = 0.0
            if self.xp is np and ux.ndim == 2 and ux.strides[1] == ux.itemsize == uy.itemsize \
                    and ux.strides == uy.strides:
                # NumPy: gather straight from the transform's rows (ux, uy are column slices of
                # them) into the float64 result: no raveled copy of the box, no stack, no cast
                u = np.empty((2, self.n))
                rs = ux.strides[0] // ux.itemsize
                at = self._gather_index(local, box, rs)
                for k, a in enumerate((ux, uy)):
                    flat = np.lib.stride_tricks.as_strided(a, shape=((a.shape[0] - 1) * rs + a.shape[1],),
                                                           strides=(a.itemsize,), writeable=False)
                    u[k] = np.take(flat, at)
                return u
            u = self.xp.stack([ux.ravel()[local], uy.ravel()[local]])
            return u if u.dtype == np.float64 else u.astype(np.float64)
        fx, fy = self.full
        fx[self.idx] = t[0]
        fy[self.idx] = t[1]
        shape = self.top.shape
        ux, uy = self.top.shear_displacement(fx.reshape(shape), fy.reshape(shape))
        fx[self.idx] = 0.0
        fy[self.idx] = 0.0
        return self.xp.stack([ux.ravel()[self.idx], uy.ravel()[self.idx]])

    def _gather_index(self, local, box, row_stride: int):
        """The flat indices ``local`` of the contact nodes in a ``box`` laid out with rows of
        ``row_stride`` elements (cached per stride: ``local`` and ``box`` are this state's, fixed
        by its contact set)."""
        cache = self._gather_cache
        at = cache.get(row_stride)
        if at is None:
            at = cache[row_stride] = (local // box[1]) * row_stride + local % box[1]
        return at

    def _box(self):
        """The preconditioner's box: the bounding box of the contact nodes (the whole axis where
        a periodic contact wraps around), sized up to a fast FFT length; the nodes' flat indices
        in it and a scatter buffer (cached)."""
        if getattr(self, "_box_data", None) is None:
            import scipy.fft

            top = self.top
            nx, ny = top.shape
            ii, jj = self._rows_cols()

            def axis(c, n):
                lo, hi = int(c.min()), int(c.max())
                if top.periodic:
                    # a contact across the cell edge: take the whole axis
                    occ = np.zeros(n, dtype=bool)
                    occ[c] = True
                    if occ[0] and occ[-1]:
                        return 0, n
                ext = hi - lo + 1
                # a multiple of 16 (few distinct shapes along a load path: FFT plans are made per
                # shape), then a fast FFT length
                m = min(scipy.fft.next_fast_len(-(-ext // 16) * 16, real=True), n)
                return lo, max(m, ext)

            i0, m1 = axis(ii, nx)
            j0, m2 = axis(jj, ny)
            local = ((ii - i0) % m1) * m2 + (jj - j0) % m2
            # single-precision residuals where the backend transforms them so (a preconditioner
            # needs no double precision; see the single-precision note at INCREMENTAL_EXACT)
            real = np.float32 if top.be.single_precision else np.float64
            self._box_data = ((m1, m2), self.xp.asarray(local), self.xp.zeros(m1 * m2, dtype=real),
                              self.xp.zeros(m1 * m2, dtype=real))
        return self._box_data

    def _rows_cols(self):
        """Row and column indices (NumPy) of the contact nodes on the grid."""
        ny = self.top.shape[1]
        idx = self.top.be.to_numpy(self.idx)
        return idx // ny, idx % ny

    def _apply_box(self):
        """(box, local indices, scatter buffers) of the box convolution of :meth:`_apply`, or
        None (periodic grid, no contact, or a box transform not clearly smaller; cached)."""
        if not hasattr(self, "_apply_box_data"):
            data = None
            top = self.top
            if not top.periodic and self.n > 0:
                # the contact's exact bounding box (not the preconditioner's, rounded up to a
                # fast length: its transform would be up to 1.2x larger per axis)
                ii, jj = self._rows_cols()
                i0, j0 = int(ii.min()), int(jj.min())
                box = (int(ii.max()) - i0 + 1, int(jj.max()) - j0 + 1)
                N, _ = top.box_spectra(box)
                if N[0] * N[1] < 0.8 * top.fft_shape[0] * top.fft_shape[1]:
                    local = self.xp.asarray((ii - i0) * box[1] + (jj - j0))
                    data = (box, local, self.xp.zeros(box[0] * box[1]), self.xp.zeros(box[0] * box[1]))
            self._apply_box_data = data
        return self._apply_box_data

    def _precondition(self, t, nodes):
        """M t on ``nodes`` (a mask of the contact nodes), for t (2, n) restricted to them: the
        inverse-symbol convolution on the contact's box (:meth:`TangentialOperator.precondition`)."""
        box, local, bx, by = self._box()
        sel = local[nodes]
        bx[sel] = t[0, nodes]
        by[sel] = t[1, nodes]
        zx, zy = self.top.precondition(bx.reshape(box), by.reshape(box))
        bx[sel] = 0.0
        by[sel] = 0.0
        return zx.ravel()[sel], zy.ravel()[sel]

    def slip_scale(self) -> float:
        """max |K_tt (mu p e_x)| (m): the displacement scale of full slip."""
        if self.n == 0:
            return 1.0
        t = self.xp.zeros((2, self.n))
        t[0] = self.bound
        u = self._apply(t)
        return max(float(self.xp.abs(u).max()), 1e-300)

    def reset_momentum(self):
        """Restart the projected gradient from the current state (after another method)."""
        self.Kq = self._apply(self.q)
        self.n_apply += 1
        self.y, self.Ky = self.q.copy(), self.Kq.copy()
        self.t_mom = 1.0
        self.stick = self._stick_mask()
        if self.force_control:
            self._update_delta()

    def finish_frictionless(self):
        self.q[...] = 0.0
        self.stick = self.xp.zeros(self.n, dtype=bool)

    # ------------------------------------------------------------------ projection
    def _project_force(self, z):
        """P_C(z): the discs intersected with sum q = target.  q_i = P_i(z_i + lam), with the
        2-D multiplier lam found by Newton steps on the (monotone) force balance."""
        qx, qy, self.lam = _force_multiplier(self.xp, z, self.bound, self.target, self.lam)
        return self.xp.stack([qx, qy])

    # ------------------------------------------------------------------ one iteration
    def iterate(self):
        xp, bound = self.xp, self.bound
        L = self.L
        grad = self.Ky + self.v0
        if not self.force_control:
            _less_delta(grad, self.delta)
        z = self.y - grad / L
        if self.force_control:
            q_new = self._project_force(z)
        else:
            q_new = z
            _project(xp, q_new, bound)
        Kq_new = self._apply(q_new)
        self.n_apply += 1
        dq = q_new - self.q
        # Adaptive restart (O'Donoghue and Candes 2015): drop the momentum when it points uphill.
        if dot(self.y - q_new, dq) > 0.0:
            self.t_mom = 1.0
            self.y, self.Ky = q_new.copy(), Kq_new.copy()
            self.restarts += 1
        else:
            t_new = 0.5 * (1.0 + math.sqrt(1.0 + 4.0 * self.t_mom**2))
            beta = (self.t_mom - 1.0) / t_new
            self.t_mom = t_new
            self.y = q_new + beta * dq
            self.Ky = Kq_new + beta * (Kq_new - self.Kq)
        self.q, self.Kq = q_new, Kq_new
        self.stick = self._stick_mask()
        norm = float(bound.sum()) * 2.0
        self.change = float(xp.abs(dq).sum()) / norm if norm > 0 else 0.0
        if self.force_control:
            self._update_delta()
        self._complementarity()

    def _update_delta(self):
        """Rigid shift under force control: the mean of K q + K_tz p - s_ref over the stick nodes
        (their slip vanishes), or the projection multiplier times L without stick nodes."""
        stick = self.stick
        if bool(stick.any()):
            s_raw = self.Kq + self.v0
            self.delta = np.array([float(s_raw[0][stick].mean()), float(s_raw[1][stick].mean())])
        else:
            self.delta = self.lam * self.L

    def _complementarity(self):
        """rms over C+ of the violated part of the stick/slip conditions (m)."""
        xp = self.xp
        s = _less_delta(self.Kq + self.v0, self.delta)
        stick = self.stick
        # Whole-array arithmetic on the contact nodes (no boolean gathers): stick nodes violate
        # by |s|, slip nodes by |s + |s| d| (s should equal -|s| d, d = q / (mu p) the unit
        # direction of the traction).
        smag = xp.sqrt(s[0] * s[0] + s[1] * s[1])
        b = xp.where(self.bound > 0, self.bound, 1.0)
        ex = s[0] + smag * (self.q[0] / b)
        ey = s[1] + smag * (self.q[1] / b)
        viol = xp.where(stick, smag, xp.sqrt(ex * ex + ey * ey))
        self.complementarity = float(xp.sqrt((viol * viol).mean())) if self.n else 0.0



class _TangCG(IterativeSolver):
    """Conjugate gradients over the stick AND slip nodes (the idea of Vollebregt's TangCG in
    CONTACT; our own implementation, with the force constraint handled as in Polonsky-Keer).

    Stick nodes move freely (residual -s); slip nodes move only along their rim (residual: the
    part of -s along the rim tangent t, perpendicular to the traction direction n), and their
    Jacobian carries the rim curvature |s.n| / g (the linearised rotation of a traction that must
    stay opposite to its slip), which keeps the slip directions stable.  Preconditioning: on the
    slip nodes diagonal (K_ii + |s.n|/g), on the stick nodes diagonal (K_ii) or, with
    ``preconditioner="fft"``, P_S M P_S (M the inverse symbol of K_tt on the contact's box,
    :meth:`TangentialOperator.preconditioner_spectra`; SPD, so the block-diagonal whole is a valid
    CG preconditioner).  After each step the slip tractions are put back on the rim.  Every
    ``INNER`` steps (``INNER_FFT`` with the FFT preconditioner, whose steps are worth more; both
    the measured best, see benchmarks/README.md), or earlier when the update is small, the slip
    is recomputed exactly and the element division is updated (:meth:`_check`): stick tractions
    beyond their disc start to slip, slip nodes whose slip runs along their traction return to
    stick (the conjugate direction then restarts).  Under force control the direction is made
    force-free (sum v = 0 on the stick nodes) and delta is the mean of K q + K_tz p - s_ref over
    the stick nodes; the mean of K v over the stick nodes is removed from the Jacobian-vector
    product (delta follows the step).

    Run by :func:`.iteration.run_iterations`: the residual is measured at the checks only
    (``residual()`` is None between them), and convergence needs an unchanged element division.
    """

    INNER = 4
    INNER_FFT = 2

    def __init__(self, st, s_scale, tol, preconditioner="diagonal"):
        self.st, self.xp = st, st.xp
        self.preconditioner = preconditioner
        self.inner = self.INNER if preconditioner == "diagonal" else self.INNER_FFT
        self.s_scale, self.tol = s_scale, tol
        # largest change of q (fraction of |q|_1) for an incremental exact K q (see _exact)
        self.incremental_limit = INCREMENTAL_EXACT * min(100.0, max(1.0, tol / INCREMENTAL_TOL))
        self.best = (float("inf"), None, None, None)
        self.stick = st._stick_mask()
        self.res = None
        self.changed = False
        self.exact_ref = None  # (q, K q, |q|_1, single-precision updates since double) (_exact)

    def restore_best(self):
        """Back to the best checked state, or (before any check) to an admissible one: the
        tractions projected onto their discs with the force restored on the stick nodes."""
        st = self.st
        _, q, Kq, delta = self.best
        self.exact_ref = None
        if q is not None:
            st.q[...] = q
            st.Kq = Kq
            st.delta = delta
            return
        _project(self.xp, st.q, st.bound)
        if st.force_control:
            inside = st._stick_mask()
            n_in = int(inside.sum())
            if n_in:
                deficit = st.target - np.array([float(st.q[0].sum()), float(st.q[1].sum())])
                st.q[0, inside] += deficit[0] / n_in
                st.q[1, inside] += deficit[1] / n_in
                _project(self.xp, st.q, st.bound)

    def _exact(self, recompute: bool = True):
        """Exact K q (``recompute=False``: the state's K q is already exact), delta and slip s.

        With single-precision directions, K q is the last exact one plus K of the change of q
        since then in single precision, while that change is at most ``INCREMENTAL_EXACT`` of
        |q| (L1): its error, ~1e-7 of K of the change, is then ~1e-10 of K q per check.  At a
        tolerance above ``INCREMENTAL_TOL`` the fraction is INCREMENTAL_EXACT x tol /
        INCREMENTAL_TOL (at most 100x): the error per check stays ~1e-3 of the tolerance."""
        st = self.st
        if recompute:
            ref = self.exact_ref
            d = None
            if ref is not None and ref[3] < INCREMENTAL_CHECKS and st.top.be.single_precision:
                d = st.q - ref[0]
                if float(self.xp.abs(d).sum()) > self.incremental_limit * ref[2]:
                    d = None
            st.Kq = st._apply(st.q) if d is None else ref[1] + st._apply(d, single=True)
            st.n_apply += 1
            chain = 0 if d is None else ref[3] + 1
        else:
            chain = 0
        self.exact_ref = (st.q.copy(), st.Kq, float(self.xp.abs(st.q).sum()), chain)
        s_raw = st.Kq + st.v0
        if st.force_control:
            if bool(self.stick.any()):
                st.delta = np.array([float(s_raw[0][self.stick].mean()), float(s_raw[1][self.stick].mean())])
            else:
                st.delta = self._slip_fit(s_raw, self._tangents())
        return _less_delta(s_raw, st.delta)

    # -- no stick node under force control: every node slips on its rim, the rigid shift delta is
    #    the multiplier of the force balance (as in the projected gradient), and a node returns to
    #    stick at a check when its slip runs along its traction.  Without this the solve of a state
    #    beyond (or near) the gross-slip onset fell to the projected gradient, 5-10x the iterations.
    def _tangents(self):
        """Unit rim tangents t (2, n) of the tractions (perpendicular to q)."""
        xp, q = self.xp, self.st.q
        mag = xp.sqrt(q[0] ** 2 + q[1] ** 2)
        mag = xp.where(mag > 0, mag, 1.0)
        return xp.stack([-q[1] / mag, q[0] / mag])

    @staticmethod
    def _rim_system(t):
        """The 2x2 matrix A = sum_i t_i t_i^T of the force balance along the rims."""
        axx, ayy, axy = float((t[0] * t[0]).sum()), float((t[1] * t[1]).sum()), float((t[0] * t[1]).sum())
        return np.array([[axx, axy], [axy, ayy]])

    def _rim_solve(self, t, rhs):
        """c with A c = rhs (least squares when the tangents are nearly parallel: then a force
        change along the tractions cannot be made by rotating them, to first order)."""
        return np.linalg.lstsq(self._rim_system(t), np.asarray(rhs, dtype=float), rcond=1e-10)[0]

    def _slip_fit(self, s_raw, t):
        """delta that makes the rim components of the slip force-free: A delta = sum t (t . s_raw)
        (at the solution t . (s_raw - delta) = 0 on every slip node)."""
        ts = t[0] * s_raw[0] + t[1] * s_raw[1]
        return self._rim_solve(t, [float((t[0] * ts).sum()), float((t[1] * ts).sum())])

    def _rim_free(self, x, t):
        """Remove from x (2, n), given along the tangents, the part that changes the force:
        x - t (t . c) with A c = sum x, so that sum x = 0 (the constraint's orthogonal projection)."""
        c = self._rim_solve(t, [float(x[0].sum()), float(x[1].sum())])
        tc = t[0] * c[0] + t[1] * c[1]
        return x - tc * t, c

    def _rotate_to_force(self):
        """Restore sum q = target with no stick node: q_i = b_i (q_i + lam) / |q_i + lam| (every
        node on its rim; a solution exists because |target| < sum b_i, checked on entry)."""
        st = self.st
        st.q[0], st.q[1], _ = _force_multiplier(self.xp, st.q.copy(), st.bound, st.target, np.zeros(2), rim=True)

    # -- the steps run by iteration.run_iterations
    def start(self):
        """Slip of the starting tractions (the projected-gradient state computed their K q)."""
        st, xp = self.st, self.xp
        self.s = self._exact(recompute=False)
        self.steps = 0  # CG steps since the last check
        self.v = self.qv_prev = None
        self.q_outer = st.q.copy()
        self.r = None  # residual; None: rebuild it and the masks of the element division
        self.division = None
        self.restart = True
        # Masks as 0/1 floats and where(): whole-array arithmetic on the contact nodes instead of
        # boolean gathers and scatters.  The masks change only at a check of the element division,
        # which also resets r.
        self.bsafe = xp.where(st.bound > 0, st.bound, 1.0)
        return None

    def residual(self):
        """max(relative traction change, complementarity / slip scale) at a check, else None."""
        return self.res

    def settled(self) -> bool:
        """Whether the last check left the element division unchanged."""
        return not self.changed

    def improved(self, residual: float) -> None:
        """Keep the best checked state for the projected-gradient fallback."""
        st = self.st
        self.best = (residual, st.q.copy(), st.Kq.copy(), np.array(st.delta))

    def stalled_message(self, residual, best, stall, tol) -> str:
        return f"stalled at residual {residual:.3e} (best {best:.3e})"

    def converged_message(self, iteration: int) -> str:
        return f"converged in {iteration} iterations (TangCG)"

    def exhausted_message(self, max_iterations, history, tol) -> str:
        return f"not converged after {max_iterations} iterations"

    def iterate(self):
        """One CG step; every ``inner`` steps, or when the step is small, a check (:meth:`_check`)."""
        st, xp = self.st, self.xp
        b, kii, q = st.bound, st.kii, st.q
        self.res = None
        stick = self.stick
        s, r = self.s, self.r
        if r is None:
            slip = ~stick
            any_slip = bool(slip.any())
            n_st = int(stick.sum())
            stickf = stick.astype(float)
            # Directions of the slip tractions and the residual.
            t = self._tangents()
            n = xp.stack([t[1], -t[0]])
            r = -s
            if any_slip:
                rt = t[0] * r[0] + t[1] * r[1]
                r = xp.where(slip, rt * t, r)
            self.division = (slip, any_slip, n_st, stickf, n, t)
        else:
            slip, any_slip, n_st, stickf, n, t = self.division
        # Curvature of the rim: |s.n| / g on slip nodes (s.n < 0 for a proper slip).
        if any_slip:
            sn = xp.where(slip, xp.maximum(-(s[0] * n[0] + s[1] * n[1]), 0.0) / self.bsafe, 0.0)
        else:
            sn = xp.zeros(st.n)
        z = xp.empty_like(r)
        z[0] = r[0] / (kii[0] + sn)
        z[1] = r[1] / (kii[1] + sn)
        if self.preconditioner == "fft" and n_st:
            # stick nodes: z = P_S M P_S r (M: the inverse symbol of K_tt on the contact's box)
            z[0, stick], z[1, stick] = st._precondition(r, stick)
            st.n_precondition += 1
        if any_slip:
            zt = t[0] * z[0] + t[1] * z[1]
            z = xp.where(slip, zt * t, z)
        v = self.v
        if self.restart or v is None:
            v = z
        else:
            qv_prev = self.qv_prev
            zq = dot(z, qv_prev)
            vq = dot(v, qv_prev)
            beta = 0.0 if (abs(zq) < 1e-300 or abs(vq) < 1e-6 * abs(zq)) else -zq / vq
            v = z + beta * v
        self.restart = False
        rim_only = st.force_control and not n_st
        if st.force_control and n_st:
            v = v - stickf * (v.sum(axis=1) / n_st)[:, None]
        elif rim_only:
            v = self._rim_free(v, t)[0]
        Kv = st._apply(v, single=True)
        st.n_apply += 1
        if st.force_control and n_st:
            Kv = Kv - ((Kv * stickf).sum(axis=1) / n_st)[:, None]
        if rim_only:
            # Every node slips: J v is the force-free part of the rim operator, and delta follows
            # the step (the slip fit of K v).
            jt = t[0] * Kv[0] + t[1] * Kv[1]
            Jv = self._rim_free(jt * t + sn * v, t)[0]
            Kv = Kv - xp.asarray(self._slip_fit(Kv, t))[:, None]
        elif any_slip:
            jt = t[0] * Kv[0] + t[1] * Kv[1]
            Jv = xp.where(slip, jt * t + sn * v, Kv)
        else:
            Jv = Kv.copy()
        rv, vq = dot(r, v), dot(v, Jv)
        alpha = 0.0 if abs(rv) < 1e-300 else (rv / vq if abs(vq) > 1e-6 * abs(rv) else 1.0)
        q += alpha * v
        if any_slip:
            mag = xp.sqrt(q[0] ** 2 + q[1] ** 2)
            q *= xp.where(slip, b / xp.where(mag > 0, mag, 1.0), 1.0)
        st.Kq = st.Kq + alpha * Kv  # linear part only; made exact at the next check
        self.s = s + alpha * Kv
        self.r = r - alpha * Jv
        self.v = v
        self.qv_prev = Jv
        dif = abs(alpha) * float(xp.sqrt((v * v).sum(axis=0).mean()))
        self.steps += 1
        if self.steps >= self.inner or dif <= 1e-3 * self.tol * float(b.mean()):
            return self._check()
        return None

    def _check(self):
        """Check the element division with the exact slip and measure the residual."""
        st, xp = self.st, self.xp
        b, q = st.bound, st.q
        self.steps = 0
        mag = xp.sqrt(q[0] ** 2 + q[1] ** 2)
        over = self.stick & (mag > b)
        changed = bool(over.any())
        if changed:
            f = xp.where(over, b / xp.where(mag > 0, mag, 1.0), 1.0)
            q *= f
            self.stick = self.stick & ~over
        if st.force_control:
            # Restore the force on the stick nodes; a node pushed beyond its disc slips.
            for _ in range(8):
                n_st = int(self.stick.sum())
                if n_st == 0:
                    self._rotate_to_force()
                    break
                deficit = st.target - np.array([float(q[0].sum()), float(q[1].sum())])
                q[0, self.stick] += deficit[0] / n_st
                q[1, self.stick] += deficit[1] / n_st
                mag = xp.sqrt(q[0] ** 2 + q[1] ** 2)
                over = self.stick & (mag > b)
                if not bool(over.any()):
                    break
                q *= xp.where(over, b / xp.where(mag > 0, mag, 1.0), 1.0)
                self.stick = self.stick & ~over
                changed = True
        s = self._exact()
        self.s = s
        slipm = ~self.stick
        back = slipm & ((s[0] * q[0] + s[1] * q[1]) > 0)
        if bool(back.any()):
            self.stick = self.stick | back
            # leave them just inside the rim
            q[:, back] *= 1.0 - 1e-6
            changed = True
        # Convergence measures (as for the projected gradient).
        st.stick = self.stick.copy()
        st.change = float(xp.abs(q - self.q_outer).sum()) / max(2.0 * float(b.sum()), 1e-300)
        self.q_outer = q.copy()
        st._complementarity()
        self.res = max(st.change, st.complementarity / self.s_scale)
        self.changed = changed
        # The next step rebuilds the residual and the masks of the (possibly new) division.
        self.r = None
        self.restart = self.restart or changed
        if changed:
            self.v = None
        return None


class _ProjectedGradient(IterativeSolver):
    """The steps of the accelerated projected gradient (:meth:`_Tangential.iterate`), alone or as
    the fallback of TangCG, whose message ``prefix`` it continues."""

    stall_hint = ""

    def __init__(self, st, s_scale, prefix=""):
        self.st, self.s_scale, self.prefix = st, s_scale, prefix

    def iterate(self):
        """One FISTA step (always possible: the problem is convex)."""
        self.st.iterate()

    def residual(self) -> float:
        """max(relative traction change, complementarity / slip scale)."""
        st = self.st
        return max(st.change, st.complementarity / self.s_scale)

    def converged_message(self, iteration: int) -> str:
        return (self.prefix + "; " if self.prefix else "") + f"converged in {iteration} iterations"

    def exhausted_message(self, max_iterations, history, tol) -> str:
        return (f"not converged after {max_iterations} iterations (residual "
                f"{history[-1] if history else float('nan'):.3e}, tolerance {tol:.1e})")
