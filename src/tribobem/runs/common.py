"""Helpers shared by the runners of several kinds (rows, curves, progress offsets, load checks,
the translation of the solvers' error keys into scenario keys).  The solver settings a runner
passes to its solves are :class:`tribobem.runs.settings.SolverSettings`."""

from __future__ import annotations

import contextlib
import functools
import re
from typing import Mapping

import numpy as np

from ..errors import InputError
from ..solvers.normal import resolve_method
from ..solvers.normal_paths import LoadCurve, find_jumps

__all__ = ["normal_method", "step_row", "curve_from_rows", "offset_progress", "approach_below_full_contact",
           "SCENARIO_KEYS", "translate_error", "scenario_keys", "scenario_errors"]

#: The solvers' error keys (``"<function>.<argument>"``: the library function and its own
#: argument, e.g. ``solve_tangential.method``) -> the scenario key a scenario user sees for them.
#: The solvers know nothing of scenarios; the runners translate at their boundary
#: (:func:`scenario_errors`), so that a scenario's message is the one it always was.  Keys that
#: map onto one scenario key from several solvers (``solver.tolerance``) say which value was bad
#: no better than before: the translation keeps the message, it does not refine it.
SCENARIO_KEYS: dict[str, str] = {
    # solve_normal (and NormCG, reached through it)
    "solve_normal.method": "solver.method",
    "solve_normal.tol": "solver.tolerance",
    "solve_normal.max_iterations": "solver.max_iterations",
    "solve_normal.refresh": "solver.refresh",
    "solve_normal.force": "load.force",
    "solve_normal.approach": "load.approach",
    # solve_tangential
    "solve_tangential.friction_coefficient": "friction.coefficient",
    "solve_tangential.force": "friction.tangential_force",
    "solve_tangential.displacement": "friction.tangential_displacement",
    "solve_tangential.tol": "solver.tolerance",
    "solve_tangential.method": "solver.tangential_method",
    "solve_tangential.preconditioner": "solver.tangential_preconditioner",
    "solve_tangential.max_iterations": "solver.max_iterations",
    # solve_coupled, solve_capillary
    "solve_coupled.max_coupling": "solver.max_coupling",
    "solve_capillary.contribution": "humidity.contribution",
    # load paths
    "approach_curve.approaches": "load.approaches",
    "force_curve.forces": "load.forces",
    "pull_off.preload": "load.preload",
    "direction_vector.direction_deg": "friction.direction",
    "tangential_ramp.slip": "friction.slip",
    "normal_path.tangential_forces": "friction.tangential_forces",
    "cycle_path.peak": "friction.path",
    "cycle_path.cycles": "friction.path.cycles",
    "cycle_path.steps": "friction.path.steps",
    "hysteresis_loop.control": "friction.path.control",
    "hysteresis_loop.amplitude": "friction.path.amplitude",
    "hysteresis_loop.friction_coefficient": "friction.coefficient",
    "hysteresis_loop.stroke": "friction.path.stroke",
    # the films' levelling (interactions.films.film_thickness)
    "film_thickness.mode": "humidity.levelling",
    "film_thickness.water": "humidity",
    "film_thickness.rh": "humidity.rh",
    "film_thickness.system": "humidity.film_system",
    "film_thickness.tol": "solver.tolerance",
    "film_thickness.max_iterations": "solver.max_iterations",
    "film_thickness.time": "humidity.film_time",
}


def _key_pattern(keys: Mapping[str, str]) -> re.Pattern:
    """A key followed by ": " where it starts a message or follows a space (the form in which a
    solver quotes another's error: ``f"...: {exc}"``), longest keys first."""
    alts = "|".join(re.escape(k) for k in sorted(keys, key=len, reverse=True))
    return re.compile(rf"(?<![\w.])({alts}): ")


_SCENARIO_PATTERN = _key_pattern(SCENARIO_KEYS)


def translate_error(exc: InputError, keys: Mapping[str, str] = SCENARIO_KEYS) -> InputError:
    """Rename the solver keys of ``exc`` to scenario keys, in place.

    Parameters
    ----------
    exc : InputError
        An error raised by a solver (any subclass: it keeps its class and attributes).
    keys : mapping
        Solver key -> scenario key (default :data:`SCENARIO_KEYS`).

    Returns
    -------
    InputError
        ``exc`` itself, its ``field`` translated and, in ``reason``, every quoted error of
        another solver (``"<key>: "``) too; ``str(exc)`` follows.  Keys not in ``keys`` stay.
    """
    pattern = _SCENARIO_PATTERN if keys is SCENARIO_KEYS else _key_pattern(keys)
    field = keys.get(exc.field, exc.field)
    reason = exc.reason
    if isinstance(reason, str) and keys:
        reason = pattern.sub(lambda m: keys[m.group(1)] + ": ", reason)
    if field != exc.field or reason != exc.reason:
        exc.field, exc.reason = field, reason
        exc.args = (f"{field}: {reason}",)
    return exc


@contextlib.contextmanager
def scenario_keys(keys: Mapping[str, str] = SCENARIO_KEYS):
    """A context in which an :class:`~tribobem.errors.InputError` leaves with scenario keys.

    Parameters
    ----------
    keys : mapping
        Solver key -> scenario key (default :data:`SCENARIO_KEYS`).

    Raises
    ------
    InputError
        The error raised inside, the same object, translated by :func:`translate_error`.
    """
    try:
        yield
    except InputError as exc:
        translate_error(exc, keys)
        raise


def scenario_errors(run):
    """Decorate a kind's runner ``run(pb, bar, settings=None)`` so that the solvers' errors reach the scenario
    user under scenario keys (:func:`scenario_keys`).

    Parameters
    ----------
    run : callable
        The runner.

    Returns
    -------
    callable
        The same runner, its :class:`~tribobem.errors.InputError` translated.
    """
    @functools.wraps(run)
    def runner(*args, **kwargs):
        with scenario_keys():
            return run(*args, **kwargs)

    return runner


def normal_method(sc) -> str:
    """The normal solver a scenario's ``[solver] method`` stands for.

    ``auto`` (the default) is NormCG for contact without adhesion and without ``[humidity]``
    (same equilibrium as Polonsky-Keer, 2-4x fewer iterations on rough contacts, see
    benchmarks/README.md), and Polonsky-Keer with adhesion: the adhesive problem is not convex and
    the load paths and validation of the adhesive kinds were made with it.  The rule is
    :func:`tribobem.solvers.normal.resolve_method`, the same as ``solve_normal``'s default.

    Parameters
    ----------
    sc : Scenario
        The validated scenario.

    Returns
    -------
    str
        ``"normcg"`` or ``"polonsky_keer"``.
    """
    return resolve_method(sc.solver.method, sc.adhesion.enabled or sc.humidity is not None)


def step_row(res, branch: str) -> dict:
    """A summary.json step (the result's scalars) on ``branch``.

    Parameters
    ----------
    res : NormalResult or CoupledResult
        A solved step.
    branch : str
        Its branch of the load path (e.g. ``"loading"``, ``"unloading"``).

    Returns
    -------
    dict
        ``res.scalars()`` (forces in N, approach in m, areas in m^2, ...) plus ``branch``.
    """
    row = res.scalars()
    row["branch"] = branch
    return row


def curve_from_rows(rows: list, control: str):
    """A LoadCurve (with jumps) from step rows.

    Parameters
    ----------
    rows : list of dict
        Step rows of :func:`step_row` (with ``approach``, ``normal_force``, areas, forces,
        ``iterations``, ``converged``, ``branch``).
    control : {"force", "displacement"}
        How the path was driven (it decides what counts as a jump).

    Returns
    -------
    LoadCurve
        The curve (approach in m, forces in N, areas in m^2) with its jumps found.
    """
    def col(k, dtype=float):
        return np.array([r[k] for r in rows], dtype=dtype)

    curve = LoadCurve(control=control, branch=np.array([r["branch"] for r in rows], dtype=object),
                      approach=col("approach"), force=col("normal_force"), contact_area=col("contact_area"),
                      adhesive_area=col("adhesive_area"), repulsive_force=col("repulsive_force"),
                      adhesive_force=col("adhesive_force"), iterations=col("iterations", int),
                      converged=col("converged", bool), steps=rows)
    curve.jumps = find_jumps(curve)
    return curve


def offset_progress(cb, offset: int, total: int):
    """A ``progress(done, total)`` callback that reports ``offset + done`` of ``total`` to ``cb``.

    Used where one phase is made of several solver paths, so the bar advances over the whole
    phase instead of restarting per path.

    Parameters
    ----------
    cb : callable
        ``cb(done, total)``, the phase's progress handler.
    offset : int
        Steps done before this path.
    total : int
        Steps of the whole phase.

    Returns
    -------
    callable
        ``progress(done, _total)``; the path's own total is ignored.
    """
    return lambda done, _t: cb(offset + done, total)


def approach_below_full_contact(pb) -> None:
    """A periodic cell's mean displacement is fixed (the q = 0 mode carries no compliance), so in
    full contact (gap 0 everywhere) the approach equals the mean initial gap: an approach at or
    beyond it has no equilibrium (an unbounded force), which the solver could only report as a
    stalled step.  Refused naming the key, with the limit.

    Parameters
    ----------
    pb : Problem
        The built scenario; its ``load.approach`` or ``load.approaches`` (m) are checked on a
        periodic grid against the mean initial gap (m).

    Raises
    ------
    InputError
        On ``load.approach`` / ``load.approaches`` at or beyond full contact.
    """
    load = pb.scenario.load
    approaches = [load.approach] if load.approach is not None else list(load.approaches or [])
    if not approaches or not pb.grid.periodic or pb.operator is None:  # (two rigid bodies: no elasticity)
        return
    mean_gap = float(np.mean(pb.gap))
    worst = max(approaches)
    if worst >= mean_gap:
        key = "load.approach" if load.approach is not None else "load.approaches"
        raise InputError(key, f"{worst:.4g} m reaches full contact of the periodic cell: its mean initial gap is "
                              f"{mean_gap:.4g} m, and a periodic cell in full contact sits at approach = the mean gap "
                              f"for any mean pressure; give approaches below {mean_gap:.4g} m, or load.force")
