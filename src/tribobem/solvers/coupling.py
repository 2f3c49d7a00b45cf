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
    if (normal_force is None) == (approach is None):
        raise InputError("load", "give exactly one of normal_force or approach")
    if tangential_force is not None and tangential_displacement is not None:
        raise InputError("friction", "give tangential_force or tangential_displacement, not both")
    if tangential_force is None and tangential_displacement is None:
        tangential_force = (0.0, 0.0)
    if max_coupling < 1:
        raise InputError("solve_coupled.max_coupling", f"must be >= 1, got {max_coupling!r}")
    top = tangential_operator(operator)
    xp = top.xp
    h = xp.asarray(gap, dtype=float)
    normal_load = {"force": normal_force} if normal_force is not None else {"approach": approach}
    _beyond_capacity(interaction, normal_force, friction_coefficient, tangential_force, tangential_displacement)

    # A self-consistent law (capillary islands) solves its own normal problem: the islands are
    # recomputed from the gap of every pass.
    humid = bool(getattr(interaction, "self_consistent", False))
    box = {"state": None}

    def normal_solve(h_k, n_tol, warm, contact0=None):
        if humid:
            if not isinstance(warm, NormalResult) and not hasattr(warm, "normal"):
                warm = initial.normal if initial is not None else None  # an extrapolated pressure: the last state
            box["state"] = interaction.solve_state(operator, h_k, tol=n_tol, max_iterations=max_iterations,
                                                   initial=warm, normal_force=normal_force, approach=approach)
            return box["state"].normal
        if contact0 is not None:
            return solve_normal(operator, h_k, interaction=interaction, tol=n_tol, max_iterations=max_iterations,
                                initial_pressure=warm, initial_contact=contact0, method=normal_method, **normal_load)
        # a NormalResult of an earlier pass (this operator): its displacement is K p of the warm start
        u_warm = warm.displacement if isinstance(warm, NormalResult) and normal_method == "polonsky_keer" else None
        return solve_normal(operator, h_k, interaction=interaction, tol=n_tol, max_iterations=max_iterations,
                            initial_pressure=warm, initial_displacement=u_warm, method=normal_method, **normal_load)

    shear = None
    stick = None
    predicted = None  # pressure at which the predictor solved the shear (a fixed-point iterate)
    s_scale = None  # slip scale of the first tangential solve of the step, reused by the later ones
    rho_hint = None
    uz = None
    p_init = None
    if initial is not None:
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
        if top.coupled and shear_on_pressure:
            if PREDICTOR:
                # Predictor: the tangential problem at the predicted pressure first.  The shear
                # of the last step (even extrapolated) misses this step's shear by 1-10 %, and its
                # normal displacement leaves the first pressure as far from the solution as the
                # predicted one (measured: 2e-3 relative); the shear solved at the predicted
                # pressure is one contraction (rho ~ 0.05) closer, so the first pass starts from
                # a pressure error ~1e-4 and the loop needs one pass fewer.
                p_pred = p_init[0] if isinstance(p_init, tuple) else initial.normal.pressure
                c_pred = p_init[1] if isinstance(p_init, tuple) else initial.normal.contact
                pre = None
                # Within 1e-3 of what the predicted pressure carries, the all-slip state there
                # degenerates (its tractions all but aligned) and costs many times a step, for a
                # pressure that is only a prediction: the passes solve it instead.
                near = tangential_displacement is None and _near_capacity(
                    operator, p_pred, c_pred, friction_coefficient, tangential_force)
                if not near:
                    try:
                        pre = solve_tangential(operator, p_pred, c_pred, friction_coefficient=friction_coefficient,
                                               force=tangential_force, displacement=tangential_displacement,
                                               reference=reference, initial_shear=shear, initial_stick=stick,
                                               tol=max(tangential_tol, PREDICTOR_TOL), max_iterations=max_iterations,
                                               full_fields=False)
                    except GrossSlipError:
                        pre = None  # the predicted pressure cannot carry the force: start from the warm start
                if pre is not None:
                    # on the host, as the pressures of the normal results it is compared with
                    shear, stick, predicted = pre.shear, pre.stick, operator.backend.to_numpy(p_pred)
                    s_scale = pre.info["slip_scale"]
            uz = top.normal_from_shear(xp.asarray(shear[0]), xp.asarray(shear[1]))
    history: list[float] = []
    first = 0 if predicted is not None else 1
    converged = False
    message = ""
    normal: NormalResult | None = None
    tang = None
    two_way = top.coupled and shear_on_pressure
    n_outer = max_coupling if two_way else 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        last_change = float("inf")
        prev_f = prev_g = None
        for k in range(1, n_outer + 1):
            h_k = h if uz is None else h + uz
            # Inexact inner solves while the outer loop is far from converged: the tolerances
            # follow the last pressure change.  The stopping test needs only the pressure, so it
            # is made right after the normal solve: the final pass's tangential solve is then
            # always at ``tangential_tol`` (and the only one that builds the full slip fields),
            # and its normal solve at ``tol``, the pass the error estimate will likely accept
            # being solved at ``tol`` from the start.
            rho = _contraction(history, rho_hint, first)
            likely_last = _likely_last(rho, rho_hint, len(history) >= first + 2, last_change, coupling_tol)
            n_tol = tol if (not two_way or likely_last or INEXACT_NORMAL is None) else \
                max(tol, min(INEXACT_NORMAL, 1e-2 * last_change))
            if isinstance(p_init, tuple):  # extrapolated pressure with the contact of the last step
                p0, c0 = p_init
                normal = normal_solve(h_k, n_tol, p0, c0)
                p_init = initial.normal  # the change of the first pass is measured from the last step
            else:
                normal = normal_solve(h_k, n_tol, p_init)
            if k == 1 and predicted is not None:
                # the predictor solved the shear at this pressure: a fixed-point difference
                p_prev = predicted
                change = float(np.abs(normal.pressure - p_prev).sum()) / max(float(np.abs(normal.pressure).sum()), 1e-300)
            elif p_init is not None and isinstance(p_init, NormalResult):
                p_prev = p_init.pressure
                change = float(np.abs(normal.pressure - p_prev).sum()) / max(float(np.abs(normal.pressure).sum()), 1e-300)
            else:
                change = float("inf") if two_way else 0.0
            history.append(change)
            # Stop on the a-posteriori estimate of the remaining pressure error of a linear
            # contraction, change x rho / (1 - rho) (rho measured from the last two changes),
            # or on the change itself; at least two normal solves (the last one from the shear
            # of a tangential solve at 1e-2 x the previous change, not the predictor's 1e-4).
            rho = _contraction(history, rho_hint, first)
            done = (not two_way) or (k > 1 and (change < coupling_tol
                                                or (rho is not None and _remaining(change, rho) < coupling_tol)))
            if done and n_tol > tol:
                # Accepted at an inexact normal tolerance (<= 1e-2 x the last change, below the
                # estimated error): finish the same normal problem at ``tol``.
                normal = normal_solve(h_k, tol, normal)
            final = done or k == n_outer
            t_tol = tangential_tol if final else max(tangential_tol, min(INEXACT_TANGENTIAL, 1e-2 * last_change))
            tang = solve_tangential(operator, normal.pressure, normal.contact,
                                    friction_coefficient=friction_coefficient, force=tangential_force,
                                    displacement=tangential_displacement, reference=reference,
                                    initial_shear=shear, initial_stick=stick, tol=t_tol,
                                    max_iterations=max_iterations, slip_scale=s_scale, full_fields=final)
            s_scale = tang.info["slip_scale"]
            p_init, shear, stick = normal, tang.shear, tang.stick
            if not two_way:
                converged = True
                message = ("uncoupled (identical materials): one pass" if not top.coupled
                           else "Goodman approximation (shear not acting on the pressure): one pass")
                break
            last_change = change
            if done:
                converged = True
                message = f"coupling converged in {k} iterations"
                break
            if final:
                break
            g_k = top.normal_from_shear(xp.asarray(tang.shear[0]), xp.asarray(tang.shear[1]))
            if ANDERSON and uz is not None:
                # Anderson(1) mixing of the fixed point uz -> G(uz) (shear-induced normal displacement).
                f_k = g_k - uz
                if prev_f is not None:
                    df = f_k - prev_f
                    dd = float((df * df).sum())
                    gamma = float((f_k * df).sum()) / dd if dd > 0 else 0.0
                    new_uz = g_k - gamma * (g_k - prev_g)
                else:
                    new_uz = g_k
                prev_f, prev_g = f_k, g_k
                uz = new_uz
            else:
                uz = g_k
        if not converged:
            message = (f"coupling loop not converged after {max_coupling} iterations (pressure change "
                       f"{history[-1]:.3e}, tolerance {coupling_tol:.1e})")
    cap = box["state"]
    islands_ok = cap is None or bool(cap.converged)
    ok = converged and normal.converged and tang.converged and islands_ok
    if not ok:
        parts = [message] if not converged else []
        if not islands_ok:
            parts.append(f"meniscus islands: {cap.message}")
        elif not normal.converged:
            parts.append(f"normal solver: {normal.message}")
        if not tang.converged:
            parts.append(f"tangential solver: {tang.message}")
        message = "; ".join(parts)
        warnings.warn(message, ConvergenceWarning, stacklevel=2)
    res = CoupledResult(normal=normal, tangential=tang, coupling_iterations=len(history),
                        coupling_history=np.asarray(history), converged=ok, message=message, capillary=cap)
    res._contraction = _contraction(history, None, first) if two_way else None
    return res
