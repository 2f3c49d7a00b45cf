"""Normal-tangential coupling of dissimilar bodies: the Panagiotopoulos loop (Paper D Fig. 2).

For dissimilar materials the pressure displaces the surfaces tangentially (K_tz p) and the
shear displaces them normally (K_zt q).  The loop alternates the two solvers, each warm-started
from the other's last state, and owns nothing else:

1. the (adhesive) normal problem with the gap h + K_zx q_x + K_zy q_y (the shear-induced
   normal displacement enters the gap);
2. the tangential problem at that pressure (with K_tz p in the slip);
3. until the relative pressure change sum|p - p_old| / sum|p| falls below ``coupling_tol``.

A warm-started step (``initial``) first solves the tangential problem at the predicted pressure
(the last step's, or its linear extrapolation): the shear-induced normal displacement of the
first pass is then one contraction of the fixed point closer to the solution than the one of the
old (or extrapolated) shear, and the first pass's pressure change, measured against the predicted
pressure, is a genuine fixed-point difference (one pass fewer per step, and the loop's forces and
displacements closer to a tightly converged reference).

The outer fixed point uz -> K_zt q(p(uz)) is accelerated by Anderson(1) mixing.  The inner
solves are inexact while the loop is far from converged (tangential: 1e-2 x the last pressure
change, at most ``INEXACT_TANGENTIAL``; normal: likewise, at most ``INEXACT_NORMAL``).  The
stopping test (the pressure change, or the remaining error change x rho / (1 - rho) estimated
from the measured contraction rho) needs only the pressure, so it is made right after the
normal solve: a normal solve accepted at an inexact tolerance is finished at ``tol`` (no extra
pass), and the final pass's tangential solve is always at ``tangential_tol`` and the only one
that builds the full slip fields (the intermediate ones use ``full_fields=False`` and the slip
scale of the step's first tangential solve).  Measured passes and iterations per step:
benchmarks/README.md ("Solver notes moved from docstrings").

Identical materials (or a zero coupling compliance) make one pass.  The loop never stops
silently: a non-converged outer loop gives ``converged=False``, the history of the pressure
change and a :class:`~tribobem.errors.ConvergenceWarning`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..elasticity.operators import ConvolutionOperator
from ..elasticity.tangential import tangential_operator
from ..errors import ConvergenceWarning, InputError
from ..results import CoupledResult, NormalResult
from .normal import solve_normal
from .tangential import GrossSlipError, _as_pair, beyond_capacity_error, solve_tangential

__all__ = ["solve_coupled"]

#: Anderson(1) mixing of the outer fixed point (the same results, less CPU; benchmarks/README.md).
ANDERSON = True
#: Loosest normal tolerance of the early coupling passes (None: every pass at full accuracy).
INEXACT_NORMAL = 1e-6
#: Loosest tangential tolerance of the early coupling passes.
INEXACT_TANGENTIAL = 1e-4
#: Solve the tangential problem at the predicted pressure before the first pass of a warm-started
#: step (see ``solve_coupled``).
PREDICTOR = True
#: Tolerance of the predictor's tangential solve (dimensionless; a loose one suffices: the first pass
#: starts as close, benchmarks/README.md).
PREDICTOR_TOL = 1e-3


def _contraction(history, hint: float | None = None, first: int = 1) -> float | None:
    """Contraction factor of the outer loop from its last two pressure changes (None while
    unknown or not clearly contracting).  Before two passes have been compared, ``hint`` (the
    factor measured on the previous step, doubled for safety) stands in for it.  ``first``: the
    number of leading changes that are not fixed-point differences (1: the first pass measured
    against the last step; 0: against the predictor's pressure, itself a fixed-point iterate)."""
    if len(history) < first + 2:
        if len(history) == first + 1 and hint is not None and hint > 0:
            return 2.0 * hint if 2.0 * hint < 0.5 else None
        return None
    a, b = history[-2], history[-1]
    # A pass with no pressure change at all (the loop at round-off) measures no contraction: a
    # rho of 0 taken on to the next step as its hint stopped that step after two passes
    # whatever their change.
    if not (math.isfinite(a) and math.isfinite(b)) or a <= 0 or b <= 0:
        return None
    rho = b / a
    return rho if rho < 0.5 else None


def _remaining(change: float, rho: float) -> float:
    """Estimated distance to the fixed point after a pass with this change (geometric tail)."""
    return change * rho / (1.0 - rho)


def _likely_last(rho, hint, measured: bool, last_change: float, coupling_tol: float) -> bool:
    """Whether the next pass is likely the last: its predicted change rho x ``last_change`` leaves
    an estimated remaining error below the tolerance.  Once this step has measured its own
    contraction (``measured``) the larger of it and the last step's (``hint``) is used: the
    contraction grows over a step's passes (0.04 -> 0.07 -> 0.1 on the adhesive loop of
    benchmarks/adhesive_loop.py), and a pass wrongly taken as the last costs a normal solve at the
    run's tolerance that the next pass repeats.  Before that, twice the hint with a 5x margin."""
    if rho is None:
        return False
    if measured:
        r = max(rho, min(hint, 0.5)) if hint is not None and hint > 0 else rho
        return _remaining(r * last_change, r) < coupling_tol
    return _remaining(rho * last_change, rho) < 5.0 * coupling_tol


def _beyond_capacity(interaction, normal_force, mu, tangential_force, tangential_displacement) -> None:
    """Raise GrossSlipError before any solve when the force is known to exceed mu F0+.

    Without an interaction (no adhesion) the compressive contact carries exactly the normal
    force, whatever the coupling does to the pressure, so mu F0+ = mu F_N.  The passes would
    find it too, but only after a predictor and a tangential solve at the capacity, where the
    all-slip state degenerates: the costliest solves of a ramp (a rough burl at 2048^2: ~300 s).
    Bad inputs are left to the solvers, which name them.
    """
    if interaction is not None or normal_force is None or tangential_displacement is not None:
        return
    try:
        F = _as_pair(tangential_force, "friction.tangential_force")
        fn, mu = float(normal_force), float(mu)
    except (InputError, TypeError, ValueError):
        return
    f_t = math.hypot(*F)
    if not (math.isfinite(f_t) and math.isfinite(fn) and math.isfinite(mu)) or fn <= 0 or mu <= 0 or f_t == 0:
        return
    cap = mu * fn
    if f_t >= cap * (1.0 - 1e-12):
        raise beyond_capacity_error(f_t, cap, mu)


def _near_capacity(operator, pressure, contact, mu, tangential_force, margin: float = 1e-3) -> bool:
    """Whether |F_t| >= (1 - margin) mu F0+ of ``pressure`` (on ``contact``)."""
    try:
        f_t = math.hypot(*_as_pair(tangential_force, "friction.tangential_force"))
        xp = operator.backend.xp
        p = xp.asarray(pressure, dtype=float)
        f0p = float(xp.where(xp.asarray(contact, dtype=bool) & (p > 0), p, 0.0).sum()) * operator.grid.cell_area
        return f_t > 0 and f_t >= (1.0 - margin) * float(mu) * f0p
    except (InputError, TypeError, ValueError, AttributeError):
        return False


def _checked_tangential_load(normal_force, approach, tangential_force, tangential_displacement, max_coupling):
    """Check the load arguments of :func:`solve_coupled` and return the tangential force.

    Parameters
    ----------
    normal_force, approach : float or None
        Normal load, force (N) or approach (m); exactly one must be given.
    tangential_force, tangential_displacement : (float, float) or None
        Tangential load, force (N) or displacement (m); at most one.
    max_coupling : int
        Outer iterations (>= 1).

    Returns
    -------
    tangential_force : (float, float) or None
        As given, or ``(0.0, 0.0)`` when neither tangential load is given.
    """
    if (normal_force is None) == (approach is None):
        raise InputError("load", "give exactly one of normal_force or approach")
    if tangential_force is not None and tangential_displacement is not None:
        raise InputError("friction", "give tangential_force or tangential_displacement, not both")
    if tangential_force is None and tangential_displacement is None:
        tangential_force = (0.0, 0.0)
    if max_coupling < 1:
        raise InputError("solve_coupled.max_coupling", f"must be >= 1, got {max_coupling!r}")
    return tangential_force


class _NormalSolve:
    """The normal solve of a coupling pass (step 1 of the loop), warm-started from the last state.

    A self-consistent law (capillary islands) solves its own normal problem: the islands are
    recomputed from the gap of every pass, and its last state is kept in ``capillary``.

    Parameters
    ----------
    operator : ConvolutionOperator
        3x3 operator of the step.
    interaction : Interaction or CapillaryModel or None
        Stress law outside contact, or a self-consistent law.
    initial : CoupledResult or None
        Warm start of the step (its normal state stands in for an extrapolated pressure).
    normal_force, approach : float or None
        Normal load, force (N) or approach (m).
    max_iterations : int
        Per solver call.
    normal_method : str
        ``method`` of :func:`~tribobem.solvers.normal.solve_normal`.
    """

    def __init__(self, operator, interaction, initial, normal_force, approach, max_iterations, normal_method):
        self.operator = operator
        self.interaction = interaction
        self.initial = initial
        self.normal_force = normal_force
        self.approach = approach
        self.max_iterations = max_iterations
        self.normal_method = normal_method
        self.normal_load = {"force": normal_force} if normal_force is not None else {"approach": approach}
        self.humid = bool(getattr(interaction, "self_consistent", False))
        #: The self-consistent law's state of the last solve (None without one).
        self.capillary = None

    def __call__(self, h_k, n_tol, warm, contact0=None) -> NormalResult:
        """Solve the normal problem on the gap ``h_k`` (m) to the tolerance ``n_tol``, warm-started
        from ``warm`` (a NormalResult, a pressure in Pa, or None) and, with it, ``contact0``."""
        operator, interaction, max_iterations = self.operator, self.interaction, self.max_iterations
        if self.humid:
            if not isinstance(warm, NormalResult) and not hasattr(warm, "normal"):
                # an extrapolated pressure: the last state
                warm = self.initial.normal if self.initial is not None else None
            self.capillary = interaction.solve_state(operator, h_k, tol=n_tol, max_iterations=max_iterations,
                                                     initial=warm, normal_force=self.normal_force,
                                                     approach=self.approach)
            return self.capillary.normal
        if contact0 is not None:
            return solve_normal(operator, h_k, interaction=interaction, tol=n_tol, max_iterations=max_iterations,
                                initial_pressure=warm, initial_contact=contact0, method=self.normal_method,
                                **self.normal_load)
        # a NormalResult of an earlier pass (this operator): its displacement is K p of the warm start
        u_warm = warm.displacement if isinstance(warm, NormalResult) and self.normal_method == "polonsky_keer" else None
        return solve_normal(operator, h_k, interaction=interaction, tol=n_tol, max_iterations=max_iterations,
                            initial_pressure=warm, initial_displacement=u_warm, method=self.normal_method,
                            **self.normal_load)


def _start_state(initial, extrapolate, xp):
    """Warm start of a step: the last step's state, or its linear extrapolation along the path.

    Parameters
    ----------
    initial : CoupledResult or None
        The previous step.
    extrapolate : (CoupledResult, float) or None
        ``(older, w)``: the step before ``initial`` and the ratio of the load increments.
    xp : module
        Array namespace of the operator's backend.

    Returns
    -------
    p_init : NormalResult or (ndarray, ndarray) or None
        Warm start of the first normal solve: the last normal state, or the extrapolated pressure
        (Pa) with the last contact.
    shear : ndarray or None
        Warm-start shear (2, nx, ny) in Pa.
    stick : ndarray or None
        Warm-start stick zone.
    rho_hint : float or None
        Contraction factor measured on the previous step.
    """
    if initial is None:
        return None, None, None, None
    p_init = initial.normal
    shear = initial.tangential.shear
    stick = initial.tangential.stick
    # the contraction measured on the previous step (kept on the result by this function)
    rho_hint = getattr(initial, "_contraction", None)
    if rho_hint is None:
        rho_hint = _contraction(list(initial.coupling_history))
    if extrapolate is not None:
        older, w = extrapolate
        w = float(w)
        if older is not None and math.isfinite(w) and w > 0:
            shear = (1.0 + w) * xp.asarray(shear) - w * xp.asarray(older.tangential.shear)
            p_x = (1.0 + w) * xp.asarray(initial.normal.pressure) - w * xp.asarray(older.normal.pressure)
            p_init = (p_x, initial.normal.contact)
    return p_init, shear, stick, rho_hint


def _predictor(operator, initial, p_init, shear, stick, tangential_kw, tangential_tol):
    """Predictor: the tangential problem at the predicted pressure, before the first pass.

    The shear of the last step (even extrapolated) misses this step's shear by 1-10 %, and its
    normal displacement leaves the first pressure as far from the solution as the predicted one
    (measured: 2e-3 relative); the shear solved at the predicted pressure is one contraction
    (rho ~ 0.05) closer, so the first pass starts from a pressure error ~1e-4 and the loop needs
    one pass fewer.

    Parameters
    ----------
    operator : ConvolutionOperator
        3x3 operator of the step.
    initial : CoupledResult
        The previous step.
    p_init : NormalResult or (ndarray, ndarray)
        Warm start of the step (see :func:`_start_state`).
    shear, stick : ndarray
        Warm-start shear (Pa) and stick zone.
    tangential_kw : dict
        Load and solver keywords of :func:`~tribobem.solvers.tangential.solve_tangential`.
    tangential_tol : float
        Tolerance of the run's tangential solves (the predictor's is at least ``PREDICTOR_TOL``).

    Returns
    -------
    shear, stick : ndarray
        The predictor's shear (Pa) and stick zone, or the warm start's when it was skipped.
    predicted : ndarray or None
        The predicted pressure (Pa, on the host) at which the shear was solved (None: skipped).
    slip_scale : float or None
        Slip scale of the predictor's tangential solve (None: skipped).
    """
    p_pred = p_init[0] if isinstance(p_init, tuple) else initial.normal.pressure
    c_pred = p_init[1] if isinstance(p_init, tuple) else initial.normal.contact
    # Within 1e-3 of what the predicted pressure carries, the all-slip state there degenerates
    # (its tractions all but aligned) and costs many times a step, for a pressure that is only a
    # prediction: the passes solve it instead.
    if tangential_kw["displacement"] is None and _near_capacity(
            operator, p_pred, c_pred, tangential_kw["friction_coefficient"], tangential_kw["force"]):
        return shear, stick, None, None
    try:
        pre = solve_tangential(operator, p_pred, c_pred, initial_shear=shear, initial_stick=stick,
                               tol=max(tangential_tol, PREDICTOR_TOL), full_fields=False, **tangential_kw)
    except GrossSlipError:
        return shear, stick, None, None  # the predicted pressure cannot carry the force: start from the warm start
    # on the host, as the pressures of the normal results it is compared with
    return pre.shear, pre.stick, operator.backend.to_numpy(p_pred), pre.info["slip_scale"]


@dataclass
class _Passes:
    """State of the outer loop, carried from pass to pass (pressures in Pa, shears in Pa,
    displacements in m)."""

    #: The shear acts on the normal problem (dissimilar materials, no Goodman approximation).
    two_way: bool
    #: Number of passes allowed.
    n_outer: int
    #: Warm start of the next normal solve (NormalResult, (pressure, contact) or None).
    p_init: Any
    #: Warm-start shear (2, nx, ny) and stick zone of the next tangential solve.
    shear: Any
    stick: Any
    #: Slip scale of the step's first tangential solve, reused by the later ones.
    s_scale: float | None
    #: Shear-induced normal displacement entering the gap of the next pass (None: none yet).
    uz: Any
    #: Contraction factor measured on the previous step.
    rho_hint: float | None
    #: Pressure at which the predictor solved the shear (a fixed-point iterate), or None.
    predicted: Any
    #: Number of leading pressure changes that are not fixed-point differences.
    first: int
    #: Relative pressure change of every pass.
    history: list[float] = field(default_factory=list)
    #: Pressure change of the last pass (sets the inexact tolerances of the next one).
    last_change: float = float("inf")
    #: Anderson(1) memory: the last residual G(uz) - uz and image G(uz).
    prev_f: Any = None
    prev_g: Any = None
    normal: NormalResult | None = None
    tang: Any = None
    converged: bool = False
    message: str = ""


def _start_passes(operator, top, initial, extrapolate, shear_on_pressure, max_coupling, tangential_kw,
                  tangential_tol) -> _Passes:
    """State of the loop before its first pass: the warm start, the predictor's shear and the
    shear-induced normal displacement of the first gap (see :func:`solve_coupled`)."""
    xp = top.xp
    p_init, shear, stick, rho_hint = _start_state(initial, extrapolate, xp)
    predicted = None
    s_scale = None
    uz = None
    if initial is not None and top.coupled and shear_on_pressure:
        if PREDICTOR:
            shear, stick, predicted, s_scale = _predictor(operator, initial, p_init, shear, stick, tangential_kw,
                                                          tangential_tol)
        uz = top.normal_from_shear(xp.asarray(shear[0]), xp.asarray(shear[1]))
    two_way = top.coupled and shear_on_pressure
    return _Passes(two_way=two_way, n_outer=max_coupling if two_way else 1, p_init=p_init, shear=shear,
                   stick=stick, s_scale=s_scale, uz=uz, rho_hint=rho_hint, predicted=predicted,
                   first=0 if predicted is not None else 1)


def _normal_tolerance(st: _Passes, tol: float, coupling_tol: float) -> float:
    """Tolerance of a pass's normal solve: inexact (1e-2 x the last pressure change, at most
    ``INEXACT_NORMAL``) while the loop is far from converged; ``tol`` on the pass the error
    estimate will likely accept, so that it is solved at ``tol`` from the start."""
    rho = _contraction(st.history, st.rho_hint, st.first)
    likely_last = _likely_last(rho, st.rho_hint, len(st.history) >= st.first + 2, st.last_change, coupling_tol)
    if not st.two_way or likely_last or INEXACT_NORMAL is None:
        return tol
    return max(tol, min(INEXACT_NORMAL, 1e-2 * st.last_change))


def _pressure_change(st: _Passes, k: int) -> float:
    """Relative pressure change sum|p - p_old| / sum|p| of pass ``k`` (step 3 of the loop)."""
    if k == 1 and st.predicted is not None:
        # the predictor solved the shear at this pressure: a fixed-point difference
        p_prev = st.predicted
    elif st.p_init is not None and isinstance(st.p_init, NormalResult):
        p_prev = st.p_init.pressure
    else:
        return float("inf") if st.two_way else 0.0
    return (float(np.abs(st.normal.pressure - p_prev).sum())
            / max(float(np.abs(st.normal.pressure).sum()), 1e-300))


def _normal_pass(st: _Passes, k: int, h, normal_solve: _NormalSolve, initial, tol: float,
                 coupling_tol: float):
    """Normal solve of pass ``k`` on the gap h + uz (m) and the stopping test it alone decides.

    Returns
    -------
    change : float
        Relative pressure change of the pass (also appended to ``st.history``).
    done : bool
        Whether the loop has converged with this pass (its normal state then solved at ``tol``).
    """
    h_k = h if st.uz is None else h + st.uz
    n_tol = _normal_tolerance(st, tol, coupling_tol)
    if isinstance(st.p_init, tuple):  # extrapolated pressure with the contact of the last step
        p0, c0 = st.p_init
        st.normal = normal_solve(h_k, n_tol, p0, c0)
        st.p_init = initial.normal  # the change of the first pass is measured from the last step
    else:
        st.normal = normal_solve(h_k, n_tol, st.p_init)
    change = _pressure_change(st, k)
    st.history.append(change)
    # Stop on the a-posteriori estimate of the remaining pressure error of a linear contraction,
    # change x rho / (1 - rho) (rho measured from the last two changes), or on the change itself;
    # at least two normal solves (the last one from the shear of a tangential solve at 1e-2 x the
    # previous change, not the predictor's 1e-4).
    rho = _contraction(st.history, st.rho_hint, st.first)
    done = (not st.two_way) or (k > 1 and (change < coupling_tol
                                           or (rho is not None and _remaining(change, rho) < coupling_tol)))
    if done and n_tol > tol:
        # Accepted at an inexact normal tolerance (<= 1e-2 x the last change, below the estimated
        # error): finish the same normal problem at ``tol``.
        st.normal = normal_solve(h_k, tol, st.normal)
    return change, done


def _tangential_pass(st: _Passes, operator, final: bool, tangential_kw: dict, tangential_tol: float) -> None:
    """Tangential solve of a pass at its pressure (step 2 of the loop): inexact (1e-2 x the last
    pressure change, at most ``INEXACT_TANGENTIAL``, no full slip fields) except on the final pass."""
    t_tol = tangential_tol if final else max(tangential_tol, min(INEXACT_TANGENTIAL, 1e-2 * st.last_change))
    st.tang = solve_tangential(operator, st.normal.pressure, st.normal.contact, initial_shear=st.shear,
                               initial_stick=st.stick, tol=t_tol, slip_scale=st.s_scale, full_fields=final,
                               **tangential_kw)
    st.s_scale = st.tang.info["slip_scale"]
    st.p_init, st.shear, st.stick = st.normal, st.tang.shear, st.tang.stick


def _pass_ends_loop(st: _Passes, top, k: int, change: float, done: bool, final: bool) -> bool:
    """Record the outcome of pass ``k`` and whether the loop stops after it."""
    if not st.two_way:
        st.converged = True
        st.message = ("uncoupled (identical materials): one pass" if not top.coupled
                      else "Goodman approximation (shear not acting on the pressure): one pass")
        return True
    st.last_change = change
    if done:
        st.converged = True
        st.message = f"coupling converged in {k} iterations"
        return True
    return final


def _next_normal_displacement(st: _Passes, top):
    """Shear-induced normal displacement K_zt q (m) of the next pass's gap, Anderson(1)-mixed.

    The outer fixed point is uz -> G(uz) = K_zt q(p(uz)); with ``ANDERSON`` and a previous
    iterate the new uz is G - gamma (G - G_prev), gamma minimising the mixed residual.
    """
    xp = top.xp
    g_k = top.normal_from_shear(xp.asarray(st.tang.shear[0]), xp.asarray(st.tang.shear[1]))
    if not (ANDERSON and st.uz is not None):
        return g_k
    f_k = g_k - st.uz
    if st.prev_f is not None:
        df = f_k - st.prev_f
        dd = float((df * df).sum())
        gamma = float((f_k * df).sum()) / dd if dd > 0 else 0.0
        new_uz = g_k - gamma * (g_k - st.prev_g)
    else:
        new_uz = g_k
    st.prev_f, st.prev_g = f_k, g_k
    return new_uz


def _corrector_passes(st: _Passes, operator, top, h, normal_solve: _NormalSolve, initial, *, tol: float,
                      tangential_tol: float, coupling_tol: float, max_coupling: int, tangential_kw: dict) -> None:
    """The coupling passes (normal solve, stopping test, tangential solve, mixing), in ``st``.

    The inner solves' ConvergenceWarnings are silenced: the loop reports their state once, on
    the result (:func:`_checked_convergence`).
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        for k in range(1, st.n_outer + 1):
            # Inexact inner solves while the outer loop is far from converged: the tolerances
            # follow the last pressure change.  The stopping test needs only the pressure, so it
            # is made right after the normal solve: the final pass's tangential solve is then
            # always at ``tangential_tol`` (and the only one that builds the full slip fields).
            change, done = _normal_pass(st, k, h, normal_solve, initial, tol, coupling_tol)
            final = done or k == st.n_outer
            _tangential_pass(st, operator, final, tangential_kw, tangential_tol)
            if _pass_ends_loop(st, top, k, change, done, final):
                break
            st.uz = _next_normal_displacement(st, top)
        if not st.converged:
            st.message = (f"coupling loop not converged after {max_coupling} iterations (pressure change "
                          f"{st.history[-1]:.3e}, tolerance {coupling_tol:.1e})")


def _checked_convergence(st: _Passes, capillary):
    """Whether the step converged (loop, last normal and tangential solves, meniscus islands),
    and its message; a ConvergenceWarning (at the caller of :func:`solve_coupled`) when not.

    Returns
    -------
    ok : bool
    message : str
    """
    islands_ok = capillary is None or bool(capillary.converged)
    ok = st.converged and st.normal.converged and st.tang.converged and islands_ok
    if ok:
        return ok, st.message
    parts = [st.message] if not st.converged else []
    if not islands_ok:
        parts.append(f"meniscus islands: {capillary.message}")
    elif not st.normal.converged:
        parts.append(f"normal solver: {st.normal.message}")
    if not st.tang.converged:
        parts.append(f"tangential solver: {st.tang.message}")
    message = "; ".join(parts)
    # stacklevel 3: this helper, solve_coupled, its caller
    warnings.warn(message, ConvergenceWarning, stacklevel=3)
    return ok, message


def _coupled_result(st: _Passes, capillary, ok: bool, message: str) -> CoupledResult:
    """The step's CoupledResult, with the measured contraction kept as the next step's hint."""
    res = CoupledResult(normal=st.normal, tangential=st.tang, coupling_iterations=len(st.history),
                        coupling_history=np.asarray(st.history), converged=ok, message=message,
                        capillary=capillary)
    res._contraction = _contraction(st.history, None, st.first) if st.two_way else None
    return res


def solve_coupled(
    operator: ConvolutionOperator,
    gap,
    *,
    friction_coefficient: float,
    normal_force: float | None = None,
    approach: float | None = None,
    tangential_force=None,
    tangential_displacement=None,
    interaction=None,
    reference=None,
    initial: CoupledResult | None = None,
    extrapolate: tuple | None = None,
    tol: float = 1e-10,
    tangential_tol: float = 1e-8,
    coupling_tol: float = 1e-7,
    max_iterations: int = 10000,
    max_coupling: int = 50,
    shear_on_pressure: bool = True,
    normal_method: str = "polonsky_keer",
) -> CoupledResult:
    """Solve one step of the coupled normal-tangential contact problem.

    Parameters
    ----------
    operator : ConvolutionOperator
        3x3 operator (components ("x", "y", "z")), free boundary or periodic.
    gap : array_like
        Initial gap h (m).
    friction_coefficient : float
        mu >= 0.
    normal_force, approach : float
        Normal load: force (N) or approach (m); exactly one.
    tangential_force : (float, float), optional
        (F_x, F_y) on body 2 (N); or ``tangential_displacement`` (delta_x, delta_y) in m.
        Neither: zero tangential force.
    interaction : Interaction or CapillaryModel, optional
        Stress law outside contact (e.g. Dugdale adhesion), or a self-consistent law (an object
        with ``self_consistent = True`` and a ``solve_state`` method, e.g.
        :class:`~tribobem.solvers.capillary.CapillaryModel`): its ``solve_state`` then replaces
        the normal solve of every pass (the meniscus islands recomputed each time) and its state
        is kept on the result (``capillary``).
    reference : array_like, shape (2, nx, ny), optional
        Previous step's relative displacement (incremental slip, Paper E Eq. 5); None: total.
    initial : CoupledResult, optional
        Warm start (previous step).
    extrapolate : (CoupledResult, float), optional
        ``(older, w)``: the step before ``initial`` and the ratio w of this step's load increment
        to the last one.  The warm start is then extrapolated linearly along the path,
        x0 = x_n + w (x_n - x_{n-1}) for the pressure, the shear and the shear-induced normal
        displacement (the first coupling pass then starts near the new state instead of the old
        one; paths pass it only while the load keeps its direction).
    tol, tangential_tol : float
        Tolerances of the normal and tangential solvers.
    coupling_tol : float
        Tolerance of the outer loop on the relative pressure error: the loop stops when the
        relative pressure change of a pass, or the remaining error estimated from it and the
        measured contraction rho (change x rho / (1 - rho), rho < 0.5), is below it.
    max_iterations : int
        Per solver call.
    max_coupling : int
        Outer iterations.
    shear_on_pressure : bool
        False: Goodman's approximation, the shear does not act on the normal problem (one pass;
        the pressure still displaces the surfaces tangentially).  Analytic solutions such as
        Spence's self-similar stick zone are derived under it.
    normal_method : {"polonsky_keer", "normcg"}
        The normal solver of every pass (:func:`~tribobem.solvers.normal.solve_normal`'s
        ``method``; ignored by a self-consistent law, which solves its own normal problem).
        Each pass is warm-started from the last pressure either way.

    Returns
    -------
    CoupledResult

    Raises
    ------
    GrossSlipError
        When the tangential force cannot be carried (see :func:`solve_tangential`).
    """
    tangential_force = _checked_tangential_load(normal_force, approach, tangential_force, tangential_displacement,
                                                max_coupling)
    top = tangential_operator(operator)
    h = top.xp.asarray(gap, dtype=float)
    _beyond_capacity(interaction, normal_force, friction_coefficient, tangential_force, tangential_displacement)
    normal_solve = _NormalSolve(operator, interaction, initial, normal_force, approach, max_iterations,
                                normal_method)
    tangential_kw = {"friction_coefficient": friction_coefficient, "force": tangential_force,
                     "displacement": tangential_displacement, "reference": reference,
                     "max_iterations": max_iterations}
    st = _start_passes(operator, top, initial, extrapolate, shear_on_pressure, max_coupling, tangential_kw,
                       tangential_tol)
    _corrector_passes(st, operator, top, h, normal_solve, initial, tol=tol, tangential_tol=tangential_tol,
                      coupling_tol=coupling_tol, max_coupling=max_coupling, tangential_kw=tangential_kw)
    ok, message = _checked_convergence(st, normal_solve.capillary)
    return _coupled_result(st, normal_solve.capillary, ok, message)
