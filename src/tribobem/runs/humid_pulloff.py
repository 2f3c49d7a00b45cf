"""Run kind ``pulloff`` with ``[humidity]``: the humid pull-off, one per RH (Papers B and C).

For every RH of ``[humidity] rh`` (in the order given):

1. both bodies' films are levelled on their undeformed topographies (as in
   :mod:`tribobem.runs.capillary`);
2. the start: the self-consistent capillary state at ``load.preload`` (force control), or at
   zero external load without a preload (the bodies brought into contact and let go);
3. quasi-static unloading under displacement control: the approach steps down from the start,
   every state solved self-consistently with the meniscus islands recomputed from its own gap
   (:func:`~tribobem.solvers.capillary.solve_capillary`, warm-started from the previous
   step), in about ``load.steps / 2`` steps down to zero approach (the first touch of the
   undeformed bodies), then in steps of an eighth of the interaction range (the Dugdale range
   h0 or the meniscus cut height, whichever is larger) until the bodies have separated: no
   contact, no active meniscus and a force within 1e-3 of the most tensile one;
4. the most tensile force is refined by ``2 load.refine - 1`` finer continuation steps between
   its two neighbours.  The pull-off force is the most tensile force of that unloading curve
   (Papers A, C: the most negative force on the force-approach curve; under displacement
   control the unstable branch is followed, so this is the force-controlled jump-off force
   where the curve has one minimum).

Each RH is one summary.json step: the file-contract capillary keys of the state at pull-off
(:func:`tribobem.runs.capillary.capillary_row`) plus ``pull_off_force``, ``pull_off_approach``,
``preload`` and ``unloading_steps``; its ``converged`` also requires every state of the
unloading to have converged.  Run level: ``pull_off_force`` and ``pull_off_approach`` (lists in
RH order, file-contract), ``preload``, ``preload_source`` and ``unloading_curves`` (per RH: approach,
force, capillary force, contact and meniscus areas, converged, per unloading state).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import ConvergenceWarning, InputError
from ..solvers.capillary import solve_capillary
from ..two_scale.tensile import attraction_range
from .capillary import capillary_options, capillary_row, films_at, step_fields, step_maps
from .kind import RunOutput
from .settings import SolverSettings

__all__ = ["run", "humid_pull_off"]

#: How summary.json names the start of the unloading without a preload (as runs.pulloff).
ZERO_LOAD = "zero external load (adhesive equilibrium at F = 0)"
#: The bodies count as separated once the force is within this fraction of the most tensile one.
SEPARATED = 1e-3


def _interaction_range(pb, opts: dict, f1, f2) -> float:
    """Largest gap (m) at which an attraction can still switch on or off: the Dugdale range h0
    or the meniscus cut height (:func:`tribobem.two_scale.tensile.attraction_range`, which the
    two-scale windows use too); the short-range cut-off when nothing attracts."""
    try:
        return attraction_range(pb.interaction, {"film1": f1.thickness, "film2": f2.thickness, "options": opts})
    except InputError:
        return float(opts["cutoff"])


def humid_pull_off(pb, rh: float, f1, f2, *, preload: float | None, n_steps: int, refine: int, tol: float,
                   max_iterations: int, max_steps: int = 400, settings: SolverSettings | None = None):
    """The pull-off at one RH (module docstring, steps 2-4) on films ``f1``, ``f2``.

    Parameters
    ----------
    pb : Problem
        The built scenario with ``[humidity]``.
    rh : float
        Relative humidity (0..1).
    f1, f2 : FilmResult
        The films of body 1 and body 2 at ``rh`` (:func:`~tribobem.runs.capillary.films_at`).
    preload : float or None
        Normal force (N) of the start; None: zero external load.
    n_steps : int
        About twice the number of unloading steps down to zero approach (``load.steps``).
    refine : int
        Finer continuation steps around the most tensile state: ``2 refine - 1`` (0: none).
    tol : float
        Solver tolerance.
    max_iterations : int
        Iterations per solve.
    max_steps : int
        Most unloading steps beyond zero approach before giving up on separation (a note then
        says so).
    settings : SolverSettings, optional
        The run's solver settings: the normal solver of the islands' solves (default: built
        from ``pb.scenario``).

    Returns
    -------
    dict
        ``state`` (the CapillaryResult at pull-off), ``start`` (at the preload), ``curve``
        (lists: approach, force, capillary_force, contact_area, wetted_area, converged, sorted
        from the start outward), ``force``, ``approach``, ``opts`` and ``notes``.
    """
    opts = capillary_options(pb, rh, settings)
    common = dict(film1=f1.thickness, film2=f2.thickness, tol=tol, max_iterations=max_iterations, **opts)
    notes: list[str] = []
    target = 0.0 if preload is None else float(preload)
    try:
        start = solve_capillary(pb.operator, pb.gap, normal_force=target, **common)
    except InputError as exc:
        if exc.field != "solve_normal.force" or preload is not None:  # (solver key: runs.common.SCENARIO_KEYS)
            raise
        # No attraction at all at this RH (no Dugdale zone, a zero capillary contribution, van der
        # Waals off): no adhesive equilibrium at zero load and no pull-off to compute.
        raise InputError("humidity.rh", f"at RH {rh:g} nothing attracts the bodies (no [adhesion], no capillary "
                         "pressure, no van der Waals term): there is no adhesive equilibrium at zero load and no "
                         "pull-off; give load.preload, [adhesion] or van_der_waals = true") from None
    if not start.converged:
        notes.append(f"RH {rh:g}: the start at F = {target:.4g} N did not converge ({start.message})")
    d0 = float(start.normal.approach)
    states = [start]

    def step(d, prev):
        s = solve_capillary(pb.operator, pb.gap, approach=float(d), initial=prev, **common)
        states.append(s)
        return s

    rng = _interaction_range(pb, opts, f1, f2)
    # down to zero approach (the first touch of the undeformed bodies) in about n_steps / 2 steps
    n_down = max(n_steps // 2, 2)
    prev = start
    if math.isfinite(d0) and d0 > 0:
        for d in np.linspace(d0, 0.0, n_down + 1)[1:]:
            prev = step(d, prev)
    d = min(float(prev.normal.approach), 0.0) if math.isfinite(prev.normal.approach) else 0.0
    dd = rng / 8.0
    fmin = min(s.total_force for s in states)
    for _ in range(max_steps):
        d -= dd
        prev = step(d, prev)
        fmin = min(fmin, prev.total_force)
        separated = (not np.any(prev.normal.contact) and prev.island_count == 0
                     and abs(prev.total_force) <= SEPARATED * abs(fmin))
        if separated:
            break
    else:
        notes.append(f"RH {rh:g}: the unloading did not separate the bodies within {max_steps} steps of {dd:.3g} m")
    # refine around the most tensile converged state by finer continuation from its predecessor
    ok = [i for i, s in enumerate(states) if s.converged]
    if ok and refine > 0:
        order = sorted(range(len(states)),
                       key=lambda i: -states[i].normal.approach if math.isfinite(states[i].normal.approach) else 0)
        i = min(ok, key=lambda k: states[k].total_force)
        pos = order.index(i)
        if 0 < pos < len(order) - 1:
            a, b = states[order[pos - 1]], states[order[pos + 1]]
            done = np.array([s.normal.approach for s in states])
            prev = a
            for d in np.linspace(a.normal.approach, b.normal.approach, 2 * refine + 1)[1:-1]:
                if np.any(np.abs(done - d) <= 1e-9 * abs(dd)):
                    continue  # already solved there (the minimum itself)
                prev = step(d, prev)
    ok = [s for s in states if s.converged] or states
    at = min(ok, key=lambda s: s.total_force)
    path = sorted(states, key=lambda s: -s.normal.approach if math.isfinite(s.normal.approach) else math.inf)
    curve = {
        "rh": float(rh),
        "approach": [float(s.normal.approach) for s in path],
        "force": [float(s.total_force) for s in path],
        "capillary_force": [float(s.capillary_force) for s in path],
        "contact_area": [float(s.contact_area) for s in path],
        "wetted_area": [float(s.wetted_area) for s in path],
        "converged": [bool(s.converged) for s in path],
    }
    bad = sum(1 for s in states if not s.converged)
    if bad:
        notes.append(f"RH {rh:g}: {bad} of {len(states)} unloading states did not converge (the pull-off is taken "
                     "over the converged ones)")
    return {"state": at, "start": start, "curve": curve, "force": float(min(at.total_force, 0.0)),
            "approach": float(at.normal.approach), "opts": opts, "notes": notes, "n_states": len(states),
            "all_converged": bad == 0}


def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``pulloff`` scenario with ``[humidity]`` on its built Problem (module docstring).

    Returns its :class:`~tribobem.runs.kind.RunOutput` (with ``step_fields``, ``step_coords`` and
    the ``representative`` RH: the most tensile pull-off).

    Parameters
    ----------
    pb : Problem
        The built scenario (grid, elastic operator, gap in m, loads in N or m, interaction,
        solver settings).
    bar : progress handler
        ``bar.phase(description, total)`` starts a phase, ``bar(done, total)`` reports its
        progress (the CLI's progress bar, or a no-op).
    settings : SolverSettings, optional
        The run's solver settings (:mod:`tribobem.runs.settings`; default: built from
        ``pb.scenario``).

    Returns
    -------
    RunOutput
    """
    sc, load, hs = pb.scenario, pb.scenario.load, pb.humidity
    if settings is None:
        settings = SolverSettings.from_scenario(sc)
    kw = settings.path_kw()
    relief = float(np.ptp(pb.gap))
    n = len(hs.rh)
    bar.phase("humid pull-off (RH)", n)
    rows, results, labels, notes, curves = [], [], [], [], []
    maps: dict[str, list] = {}
    for k, rh in enumerate(hs.rh):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            f1, f2 = films_at(pb, rh, settings.film_tolerance)
            po = humid_pull_off(pb, rh, f1, f2, preload=load.preload, n_steps=load.steps, refine=load.refine,
                                settings=settings, **kw)
        state = po["state"]
        row = capillary_row(state, rh, f1, f2, po["opts"], relief)
        row.update({"branch": "pull-off", "pull_off_force": po["force"], "pull_off_approach": po["approach"],
                    "preload": float(po["start"].total_force), "unloading_steps": po["n_states"],
                    "converged": bool(row["converged"] and po["all_converged"])})
        rows.append(row)
        results.append(state.normal)
        labels.append(f"pull-off RH {rh:g}")
        for name, m in step_maps(state, f1, f2).items():
            maps.setdefault(name, []).append(m)
        curves.append(po["curve"])
        notes += po["notes"]
        notes += [f"RH {rh:g}, film on body{i}: {f.message}" for i, f in ((1, f1), (2, f2)) if not f.converged]
        bar(k + 1, n)
    forces = [r["pull_off_force"] for r in rows]
    run_level = {"pull_off_force": forces, "pull_off_approach": [r["pull_off_approach"] for r in rows],
                 "pull_off_control": "displacement", "preload": load.preload if load.preload is not None else 0.0,
                 "preload_source": "load.preload" if load.preload is not None else ZERO_LOAD,
                 "unloading_curves": curves}
    ipk = int(np.argmin(forces)) if forces else 0
    return RunOutput(rows=rows, results=results, labels=labels, indices=list(range(n)), run=run_level,
                     warnings=notes, representative=ipk,
                     step_fields=step_fields(maps),
                     step_coords={"rh": ([r["rh"] for r in rows], {"units": "1", "long_name": "relative humidity"})})
