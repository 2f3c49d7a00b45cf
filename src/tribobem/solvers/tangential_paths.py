"""Load paths of the partial-slip kind: tangential ramps to gross slip, normal loading with friction.

* :func:`tangential_ramp`: a tangential force (or displacement) ramp at a fixed normal load,
  each step solved by the coupling loop (Paper D).  The ramp ends at gross slip (no stick node
  left, or a force beyond mu F0+): that is a result, not an error.  The gross-slip onset is
  then bracketed between the last step with stick and the first without, to ``refine_tol`` x
  mu F0+ (not the first listed step whose stick area is zero): an extrapolation of the
  friction still unused in the stick zone (:func:`unused_friction`) to zero, with a bisection
  safeguard, probing displacement-controlled states (:func:`_locate_onset_displacement`, for a
  force ramp in total slip on grids from ``DISPLACEMENT_ONSET_NODES`` on) or force-controlled
  ones (:func:`_locate_onset`).
* :func:`normal_path`: a normal-load path with friction and the incremental slip criterion
  (Paper E Eq. 5): the relative displacement of each step is the reference of the next, so
  the history of the tangential state is carried (Spence's self-similar stick zone under
  monotonic loading of dissimilar bodies).

Slip modes: ``"total"`` measures the slip from the undeformed state (each step is the one-shot
problem of Paper D, warm-started only for speed); ``"incremental"`` carries the history.
"""

from __future__ import annotations

import math
import warnings
from typing import Callable, Sequence

import numpy as np

from ..errors import ConvergenceWarning, InputError
from ..results import CoupledResult, SlipRamp
from .coupling import solve_coupled
from .tangential import GrossSlipError

#: Extrapolate the warm start of ramp steps from the last two (Paper D ramp at 64^2: 28 % fewer
#: tangential and 22 % fewer normal iterations per state, same onset).
EXTRAPOLATE = True

__all__ = ["tangential_ramp", "stick_radius_ratio", "direction_vector"]


def direction_vector(direction_deg: float) -> np.ndarray:
    """Unit vector of a tangential load ``direction_deg`` degrees from the x axis.

    Parameters
    ----------
    direction_deg : float
        Angle of the load from the x axis (degrees, counter-clockwise).

    Returns
    -------
    ndarray, shape (2,)
        (cos, sin) of the angle.

    Raises
    ------
    InputError
        For a non-finite angle.
    """
    if not math.isfinite(direction_deg):
        raise InputError("direction_vector.direction_deg", f"must be a finite angle in degrees, got {direction_deg!r}")
    t = math.radians(direction_deg)
    return np.array([math.cos(t), math.sin(t)])


def stick_radius_ratio(res: CoupledResult) -> float:
    """Equivalent stick radius over equivalent contact radius, sqrt(A_stick / A_contact).

    Parameters
    ----------
    res : CoupledResult
        A solved step (its tangential stick ratio A_stick / A_contact is used).

    Returns
    -------
    float
        c/a (dimensionless), the quantity of the Cattaneo-Mindlin law c/a = (1 - Q/(mu P))^(1/3)
        for circular contacts; 0 without stick.
    """
    return math.sqrt(max(res.tangential.stick_ratio, 0.0))


def _along(res: CoupledResult, e: np.ndarray, what: str) -> float:
    t = res.tangential
    if what == "force":
        return float(t.force_x * e[0] + t.force_y * e[1])
    return float(t.displacement_x * e[0] + t.displacement_y * e[1])


def tangential_ramp(
    operator,
    gap,
    *,
    normal_force: float,
    friction_coefficient: float,
    forces: Sequence[float] | None = None,
    displacements: Sequence[float] | None = None,
    direction: float = 0.0,
    interaction=None,
    slip: str = "total",
    refine_tol: float = 1e-3,
    max_refine: int = 40,
    progress: Callable[[int, int], None] | None = None,
    initial: CoupledResult | None = None,
    onset_by: str = "auto",
    **solver_kw,
) -> SlipRamp:
    """Ramp the tangential load at a fixed normal force until gross slip.

    Parameters
    ----------
    operator : ConvolutionOperator
        3x3 operator.
    gap : array_like
        Initial gap (m).
    normal_force : float
        Normal force held during the ramp (N).
    friction_coefficient : float
    forces, displacements : sequence of float
        Ramp values along ``direction``: forces (N) or rigid displacements (m); one of them.
    direction : float
        Degrees from the x axis.
    interaction : Interaction, optional
    slip : {"total", "incremental"}
    refine_tol : float
        Refine the bracket of the gross-slip onset until it is below refine_tol x mu F0+ (force
        control) or refine_tol x the last step's displacement (displacement control).
    max_refine : int
        At most this many refinement solves.
    progress : callable, optional
        ``progress(done, total)``.
    initial : CoupledResult, optional
        Warm start of the first solve (e.g. the F_t = 0 state of the previous RH); only the
        iterations start from it, never the slip reference.
    onset_by : {"auto", "displacement", "force"}
        How a force ramp (total slip) brackets its onset: with displacement-controlled probes
        (:func:`_locate_onset_displacement`) or force-controlled ones (:func:`_locate_onset`);
        "auto" (default): displacement-controlled on grids of at least ``DISPLACEMENT_ONSET_NODES``
        nodes, force-controlled below.  Both bracket the same onset in force.  The
        displacement-controlled states stay well posed when only a few nodes stick, where a
        force-controlled solve, whose rigid displacement is the multiplier of the force, needs
        several times the iterations of a ramp step (a rough burl at 2048^2: 300-400 TangCG
        iterations per probe against 18-54).  The force search probes a dyadic grid of forces,
        so two runs that differ by round-off (mirrored bodies, a humid law equal to the dry one)
        give the same bracket to the last digit; the ends of a displacement-controlled bracket
        are solved forces, equal to the solvers' tolerance.  An incremental-slip ramp always
        probes in force (its reference is the ramp's).
    **solver_kw
        Passed to :func:`~tribobem.solvers.coupling.solve_coupled` (tol, tangential_tol, ...).

    Returns
    -------
    SlipRamp
    """
    if (forces is None) == (displacements is None):
        raise InputError("friction", "give exactly one of tangential_forces or tangential_displacements")
    if slip not in ("total", "incremental"):
        raise InputError("tangential_ramp.slip", f"must be 'total' or 'incremental', got {slip!r}")
    if onset_by not in ("auto", "displacement", "force"):
        raise InputError("onset_by", f"must be 'auto', 'displacement' or 'force', got {onset_by!r}")
    if not (isinstance(refine_tol, float) and 0 < refine_tol < 1):
        raise InputError("refine_tol", f"must be in (0, 1), got {refine_tol!r}")
    e = direction_vector(direction)
    control = "force" if forces is not None else "displacement"
    values = [float(v) for v in (forces if forces is not None else displacements)]
    mu = friction_coefficient
    ramp = SlipRamp(steps=[], values=[], control=control, direction=e)

    def solve(value, prev, reference, extrapolate=None, how=control):
        load = {"tangential_force": tuple(value * e)} if how == "force" else {"tangential_displacement": tuple(value * e)}
        return solve_coupled(operator, gap, friction_coefficient=mu, normal_force=normal_force,
                             interaction=interaction, reference=reference, initial=prev, extrapolate=extrapolate,
                             **load, **solver_kw)

    def ref_of(res):
        return res.tangential.relative_displacement if (slip == "incremental" and res is not None) else None

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        # The F_t = 0 state: the origin of the pre-sliding displacement.
        zero = None
        if not values or values[0] != 0.0:
            zero = solve(0.0, initial, None)
        prev = None
        last_stick = None
        failed_value = None
        total = len(values)
        older = None
        for k, v in enumerate(values):
            # Warm start extrapolated linearly from the last two steps while the ramp keeps its
            # direction (see solve_coupled).
            extra = None
            if EXTRAPOLATE and older is not None and prev is not None:
                v1, v0 = ramp.values[-1], ramp.values[-2]
                if (v - v1) * (v1 - v0) > 0:
                    extra = (older, min((v - v1) / (v1 - v0), 2.0))
            try:
                res = solve(v, prev if prev is not None else (zero or initial), ref_of(prev), extra)
            except GrossSlipError as exc:
                ramp.max_force = exc.max_force
                failed_value = v
                ramp.gross_slip = True
                ramp.message = f"gross slip at step {k}: {exc}"
                break
            ramp.steps.append(res)
            ramp.values.append(v)
            if progress:
                progress(k + 1, total)
            if res.tangential.gross_slip and mu > 0:
                ramp.gross_slip = True
                failed_value = v
                ramp.message = f"gross slip at step {k} ({control} {v:.6g}): no stick node left"
                break
            last_stick = (v, res, prev, ramp.values[-2] if len(ramp.values) >= 2 else None)
            older, prev = prev, res
        ramp.zero_state = zero if zero is not None else (ramp.steps[0] if ramp.steps else None)
        if ramp.gross_slip and last_stick is not None and failed_value is not None:
            lo, lo_res, lo_prev, prev_value = last_stick
            hi = failed_value
            base = lo_res if slip == "total" else lo_prev

            def probe(value, start, extra=None, how=control):
                # warm start: the nearest state with stick below the probe (the bracket's lower
                # end), extrapolated from the one before it; the reference of an incremental
                # step stays the ramp's.  how = "displacement": a displacement-controlled state,
                # the same equilibria as the force ramp's (total slip), well posed when only a
                # few nodes stick
                try:
                    res = solve(value, start, ref_of(base) if slip == "incremental" else None,
                                extra if EXTRAPOLATE else None, how)
                except GrossSlipError:
                    return True, None
                return bool(res.tangential.gross_slip), res

            scale = (mu * lo_res.normal.repulsive_force) if control == "force" else max(abs(hi), 1e-300)
            before = (prev_value, lo_prev) if prev_value is not None and lo_prev is not None else None
            origin = ramp.zero_state if ramp.zero_state is not None else lo_res
            # displacement-controlled probes need a state with stick that carries a force and has
            # moved from the origin (the scale of the first probe); else the force search
            wants = onset_by == "displacement" or (onset_by == "auto" and _large_grid(operator))
            by_displacement = (control == "force" and slip == "total" and wants
                               and _along(lo_res, e, "force") > 0
                               and _along(lo_res, e, "displacement") > _along(origin, e, "displacement"))
            if by_displacement:
                lo, hi, lo_res, n_ref = _locate_onset_displacement(
                    lambda value, start, extra=None: probe(value, start, extra, "displacement"), lo_res,
                    lo_prev if prev_value is not None else None, hi, refine_tol, mu, max_refine,
                    lambda r: _along(r, e, "displacement"), lambda r: _along(r, e, "force"),
                    _along(origin, e, "displacement"))
            else:
                lo, hi, lo_res, n_ref = _locate_onset(probe, lo, hi, lo_res, before, refine_tol, scale, max_refine,
                                                      control == "force", mu)
            ramp.refine_steps = n_ref
            ramp.onset_bracket = (lo, hi)
            ramp.onset_state = lo_res
            f_lo = _along(lo_res, e, "force")
            if control == "force":
                ramp.onset = 0.5 * (lo + hi)
            else:
                ramp.onset = f_lo
            ramp.onset_ratio = ramp.onset / (mu * lo_res.normal.repulsive_force) if mu > 0 else float("nan")
            if ramp.zero_state is not None:
                ramp.presliding_displacement = _along(lo_res, e, "displacement") - _along(ramp.zero_state, e, "displacement")
            how = " (displacement-controlled probes)" if by_displacement else ""
            ramp.message += f"; onset located to {abs(hi - lo):.3g} after {n_ref} refinement solves{how}"
        elif ramp.gross_slip and failed_value is not None and not ramp.steps:
            ramp.message += " (the first step already slips grossly: no onset bracket)"
    return ramp


#: ``tangential_ramp(onset_by="auto")`` probes the onset in displacement control on grids of at
#: least this many nodes.  Measured on the whole-burl ramp (benchmarks/README.md): the ramp's CPU
#: time 0.85x at 512^2, 0.87x at 1024^2, 0.62x at 2048^2; on small grids the probes cost little
#: either way and the force search's bracket is reproducible to the last digit.
DISPLACEMENT_ONSET_NODES = 512 * 512


def _large_grid(operator) -> bool:
    grid = getattr(operator, "grid", None)
    if grid is None:
        return False
    nx, ny = grid.shape
    return nx * ny >= DISPLACEMENT_ONSET_NODES


def unused_friction(res: CoupledResult) -> float:
    """The friction still unused in the stick zone, as a fraction of mu F0+ (dimensionless).

    sum over the stick nodes of (mu p - |q|), over the sum of mu p on the compressive contact
    nodes; 0 without stick.  It falls to 0 continuously as the last stick node reaches its
    friction disc, i.e. at the gross-slip onset.  For Cattaneo-Mindlin it is exactly 1 - Q/(mu P)
    (the slip annulus carries mu p and every traction points along the load), linear in the
    force, which is what :func:`_locate_onset` extrapolates; on a rough burl (256^2-2048^2) it
    falls more slowly over the last few stick nodes (a power law with exponent up to ~1.5).
    """
    t = res.tangential
    if not bool(np.any(t.stick)):
        return 0.0
    p = np.asarray(res.normal.pressure)
    mu = t.friction_coefficient
    c = np.asarray(t.contact) & (p > 0)
    st = np.asarray(t.stick)
    q = np.hypot(t.shear[0][st], t.shear[1][st])
    return float(np.sum(mu * p[st] - q)) / max(float(mu * np.sum(p[c])), 1e-300)


def _locate_onset(probe, lo, hi, lo_res, before, refine_tol, scale, max_refine, force_control, mu):
    """Shrink the bracket [lo, hi] of the gross-slip onset below ``refine_tol`` x ``scale``.

    ``probe(value, start, extra)`` solves a state warm-started from ``start`` (the bracket's
    lower end: the nearest state with stick), extrapolated linearly from the state with stick
    before it (``extra`` = (that state, w), as on the ramp), and returns (gross, result);
    ``before`` is (value, result) of the state before ``lo_res`` on the ramp, or None.  The
    onset is estimated by extrapolating :func:`unused_friction` to 0 from the nearest states
    with stick (:func:`_extrapolate_onset`), and the probe goes 0.45 of the required width
    beyond the estimate: above it after a state with stick, below it after one without, so that
    an estimate good to 0.45 of the width closes the bracket in two solves.  A bisection when
    there is no estimate inside the bracket, when a probe below the estimate had no stick (the
    estimate is too high), or when the last three probes did not halve the bracket.

    Returns (lo, hi, lo_res, number of probes).
    """
    pts = [(lo, unused_friction(lo_res))]
    below = None  # (value, state) of the state with stick before lo_res: the warm start's slope
    if before is not None and before[0] < lo and not before[1].tangential.gross_slip:
        pts.insert(0, (before[0], unused_friction(before[1])))
        below = before
    n_ref = 0
    widths = [hi - lo]
    side = 1.0  # the next probe: above (+1) or below (-1) the estimate
    overshot = False
    # Probes on a dyadic grid of the first bracket, 1/16 of the required width or finer: states
    # that differ by round-off (e.g. mirrored bodies) make the same probes, as a bisection does.
    lo0, w0 = lo, hi - lo
    cell = w0 / 2.0 ** max(math.ceil(math.log2(16.0 * w0 / max(refine_tol * scale, 1e-300))), 1)
    while True:
        if force_control:
            scale = mu * lo_res.normal.repulsive_force
        need = refine_tol * scale
        w = hi - lo
        if w <= need or n_ref >= max_refine:
            break
        est = _extrapolate_onset(pts)
        value = est + side * 0.45 * need if est is not None else float("nan")
        usable = lo < value < hi  # (False for NaN)
        stalled = len(widths) >= 4 and w > 0.5 * widths[-4]  # three probes without halving it
        is_below = usable and side < 0
        if not usable or stalled or overshot or w <= 2.0 * need:
            value, is_below = 0.5 * (lo + hi), False
        value = lo0 + round((value - lo0) / cell) * cell
        value = min(max(value, lo + cell), hi - cell)
        extra = (below[1], min((value - lo) / (lo - below[0]), 2.0)) if below is not None else None
        gross, res = probe(value, lo_res, extra)
        n_ref += 1
        # a probe below the estimate without stick: the estimate is too high, bisect next
        overshot = gross and is_below
        if gross:
            hi, side = value, -1.0
        else:
            below = (lo, lo_res)
            lo, lo_res, side = value, res, 1.0
            pts.append((value, unused_friction(res)))
        widths.append(hi - lo)
    return lo, hi, lo_res, n_ref


def _locate_onset_displacement(probe, lo_res, before, q_hi, refine_tol, mu, max_refine, along_d, along_f, origin):
    """Bracket the gross-slip onset of a force ramp with displacement-controlled probes.

    A force ramp in total slip has the same equilibria as a displacement ramp: a state with
    stick at rigid displacement delta carries the force Q(delta), which rises with delta up to
    the onset, where the last stick node slips, and keeps rising slowly beyond it (the slip
    directions align).  So a displacement-controlled probe with stick gives a lower end of the
    bracket in force, Q(delta), and one without stick an upper end; the search stops when
    ``q_hi - q_lo`` (N) is below ``refine_tol`` x mu F0+, as the force search does.

    The displacement of the onset is estimated by extrapolating :func:`unused_friction` to 0
    against delta (:func:`_extrapolate_onset`: G falls as (delta* - delta)^1.5 for
    Cattaneo-Mindlin), and each probe goes 0.35 of the required width (the force width over
    the slope of Q(delta)) above the estimate after a state with stick, below it after one
    without (0.35: a pair around a good estimate closes the bracket at ~0.7 of the width, clear
    of the stopping threshold); a bisection in delta when the estimate leaves the bracket,
    misleads, or the last three probes did not halve it.  Before any probe without stick the
    upper end is the force ramp's first value without stick (``q_hi``).

    Parameters
    ----------
    probe : callable
        ``probe(delta, start, extra) -> (gross, result)``: the state at rigid displacement
        delta (m along the ramp), warm-started from ``start`` and extrapolated with ``extra``
        = (older state, w) as the ramp's steps are (result None: no state, gross slip).
    lo_res, before : CoupledResult
        The ramp's last state with stick, and the one before it (or None).
    q_hi : float
        The ramp's first force without stick (N).
    along_d, along_f : callable
        A state's rigid displacement (m) and force (N) along the ramp.
    origin : float
        delta of the state at zero tangential force (m).

    Returns
    -------
    (q_lo, q_hi, lo_res, number of probes)
    """
    d_lo, q_lo = along_d(lo_res), along_f(lo_res)
    pts = [(d_lo, unused_friction(lo_res))]
    below = None  # the state with stick before lo_res: the slope and the warm start's extrapolation
    if before is not None and not before.tangential.gross_slip and along_d(before) < d_lo:
        pts.insert(0, (along_d(before), unused_friction(before)))
        below = before
    span = d_lo - origin  # the pre-sliding displacement so far (> 0 on a ramp with stick)
    if not (math.isfinite(span) and span > 0):
        span = max(abs(d_lo), 1e-300)
    # Probes on a grid of delta: a power-of-two fraction of the pre-sliding displacement so far,
    # at most 1/16 of the required width at the secant slope q_lo / span (steeper than near the
    # onset: finer than needed).  States that differ by round-off (mirrored bodies, a humid law
    # that is the dry one) then make the same probes unless an estimate falls within round-off
    # of a cell boundary.
    need0 = refine_tol * mu * lo_res.normal.repulsive_force
    width0 = need0 * span / q_lo if q_lo > 0 else span * 2.0 ** -20
    levels = min(max(math.ceil(math.log2(16.0 * span / max(width0, 1e-300))), 4), 40)
    d0, cell = d_lo, span * 2.0 ** -levels
    d_hi = None
    n_ref = 0
    side = 1.0
    overshot = False
    widths = []
    while True:
        need = refine_tol * mu * lo_res.normal.repulsive_force
        if q_hi - q_lo <= need or n_ref >= max_refine:
            break
        # slope of Q(delta) (N/m): across the bracket once it has a displacement-controlled upper
        # end, else the secant of the last two states with stick (larger than near the onset:
        # the margin errs small, the bracket closes in force all the same)
        if d_hi is not None:
            k = (q_hi - q_lo) / (d_hi - d_lo)
        elif below is not None and d_lo > along_d(below):
            k = (q_lo - along_f(below)) / (d_lo - along_d(below))
        else:
            k = q_lo / span
        k = k if (math.isfinite(k) and k > 0) else q_lo / span
        # 0.35 of the width on each side: a pair of probes around a good estimate closes the
        # bracket at ~0.7 of the required width, clear of the stopping test's threshold, so that
        # equal searches do not part over round-off in the forces
        margin = 0.35 * need / k
        est = _extrapolate_onset(pts)
        is_below = bisect = False
        if d_hi is None:
            # no upper end in delta yet: just above the estimate (or half the pre-sliding so far
            # beyond the last state with stick when there is none), at most that far
            reach = 0.5 * max(d_lo - origin, span)
            if est is None or not est > d_lo:
                value = d_lo + reach
            else:
                value = min(est + margin, d_lo + reach)
        else:
            w = d_hi - d_lo
            value = est + side * margin if est is not None else float("nan")
            usable = d_lo < value < d_hi
            stalled = len(widths) >= 4 and w > 0.5 * widths[-4]
            is_below = usable and side < 0
            if not usable or stalled or overshot or q_hi - q_lo <= 2.0 * need:
                value, is_below, bisect = 0.5 * (d_lo + d_hi), False, True
        # in whole cells from d0 (the bracket's ends are grid points after the first probe): a
        # bisection takes the lower middle cell, an estimate its nearest cell (ties up)
        i_lo = math.floor((d_lo - d0) / cell + 0.5)
        if bisect:
            i = (i_lo + math.floor((d_hi - d0) / cell + 0.5)) // 2
        else:
            i = math.floor((value - d0) / cell + 0.5 + 1e-6)
        i = max(i, i_lo + 1)
        if d_hi is not None:
            i = min(i, math.floor((d_hi - d0) / cell + 0.5) - 1)
            if i <= i_lo:  # the bracket is one grid cell wide in delta: it cannot shrink further
                break
        value = d0 + i * cell
        extra = (below, min((value - d_lo) / (d_lo - along_d(below)), 2.0)) if below is not None else None
        gross, res = probe(value, lo_res, extra)
        n_ref += 1
        overshot = gross and is_below
        if gross:
            d_hi, side = value, -1.0
            if res is not None:
                q_hi = min(q_hi, along_f(res))
        else:
            below = lo_res
            d_lo, q_lo, lo_res, side = value, along_f(res), res, 1.0
            pts.append((value, unused_friction(res)))
        widths.append((d_hi - d_lo) if d_hi is not None else float("inf"))
    return q_lo, q_hi, lo_res, n_ref


def _extrapolate_onset(pts):
    """The force at which the unused friction G reaches 0, from the last states with stick.

    G = C (F* - F)^p through the last three points (p = 1 for Cattaneo-Mindlin; the last stick
    nodes of a rough contact give p up to ~1.5: G falls more slowly near the onset), else the
    straight line (p = 1) through the last two (also when the three points ask for p < 1, as far
    from the onset).  None without two usable points.
    """
    if len(pts) < 2:
        return None
    (x1, y1), (x2, y2) = pts[-2], pts[-1]
    if not (x2 > x1 and y1 > y2 > 0):
        return None

    def onset(pw):
        # F* of the power law pw through the last two points
        return x2 + (x2 - x1) / ((y1 / y2) ** (1.0 / pw) - 1.0)

    if len(pts) >= 3:
        x0, y0 = pts[-3]
        if x1 > x0 and y0 > y1:
            def mismatch(pw):  # log G0 predicted by the law through the last two, minus measured
                f = onset(pw)
                return math.log(y2) + pw * math.log((f - x0) / (f - x2)) - math.log(y0)

            lo_p, hi_p = 1.0, 3.0
            m_lo, m_hi = mismatch(lo_p), mismatch(hi_p)
            if m_lo * m_hi < 0:
                for _ in range(50):  # bisection on the exponent (cheap: no solve)
                    mid = 0.5 * (lo_p + hi_p)
                    m = mismatch(mid)
                    if m * m_lo > 0:
                        lo_p, m_lo = mid, m
                    else:
                        hi_p = mid
                return onset(0.5 * (lo_p + hi_p))
    return onset(1.0)


