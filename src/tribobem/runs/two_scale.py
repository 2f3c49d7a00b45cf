"""The two-scale path of a run kind (``[two_scale]``): micro windows, then the macro solve.

Not a kind of its own: the kinds that accept ``[two_scale]`` (``normal``) call
:func:`run_normal` when the built problem carries micro windows (``pb.two_scale``).

1. The pressure range of the table: the smooth macro contact (the shapes without the
   roughness, hard contact) is solved at the largest load; the table runs from 1e-3 of its mean
   contact pressure to twice its largest pressure, ``[two_scale] pressures`` values spaced
   evenly in ln p (or between ``min_pressure`` and ``max_pressure``).
2. The micro windows give the interface law (:func:`tribobem.two_scale.micro.interface_law`:
   cached, through Dask).
3. Each load is solved at macro scale with the law (:func:`tribobem.two_scale.macro.
   solve_interface_normal`).

summary.json: the steps carry the run-level keys of a whole-grid run, with ``contact_area``
the real contact area (the law's contact fraction summed over the macro cells) and
``max_pressure`` the largest asperity pressure of the windows at the cells' nominal
pressures; ``nominal_contact_area`` and ``max_nominal_pressure`` are the macro ones, and
``approach`` is the approach of the mean planes (0: the mean planes of the undeformed
roughness touch where the macro gap is 0).  ``two_scale`` holds the table and how it was made.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..results import NormalResult
from ..solvers.normal import solve_normal
from ..two_scale.macro import pressure_length, solve_interface_normal
from ..two_scale.micro import interface_law
from .common import step_row
from .kind import RunOutput
from .settings import SolverSettings

__all__ = ["run_normal", "table_pressures"]

#: A window's largest contact patch must span at least this many cells (equivalent diameter) at
#: the macro mean pressure, or the run warns (as a whole-grid run's contact_cells check does).
MIN_PATCH_CELLS = 3.0
#: The automatic table: from this fraction of the smooth contact's mean pressure ...
LOW_FRACTION = 1e-3
#: ... to this multiple of its largest pressure.
HIGH_FACTOR = 2.0


def table_pressures(pb, settings: SolverSettings, force: float) -> tuple[np.ndarray, dict]:
    """The nominal pressures of the micro table (Pa) and how they were chosen.

    Parameters
    ----------
    pb : Problem
        The built two-scale problem (its macro operator and gap).
    settings : SolverSettings
        The run's solver settings (for the smooth solve).
    force : float
        The largest load of the run (N).

    Returns
    -------
    (ndarray, dict)
        The pressures, and ``{"smooth_mean_pressure", "smooth_max_pressure"}`` (Pa) when the
        range was automatic.
    """
    ts = pb.scenario.two_scale
    info: dict = {}
    lo, hi = ts.min_pressure, ts.max_pressure
    if lo is None or hi is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            smooth = solve_normal(pb.operator, pb.gap, force=force, **settings.normal_kw())
        mean_p = force / max(smooth.contact_area, pb.grid.dx * pb.grid.dy)
        info = {"smooth_mean_pressure": float(mean_p), "smooth_max_pressure": float(smooth.max_pressure)}
        lo = LOW_FRACTION * mean_p if lo is None else lo
        hi = HIGH_FACTOR * float(smooth.max_pressure) if hi is None else hi
        hi = max(hi, 10.0 * lo)
    return np.geomspace(lo, hi, int(ts.pressures)), info


def _macro_result(pb, res) -> NormalResult:
    """The macro state as a NormalResult for fields.nc: nominal pressure, mean-plane separation."""
    contact = res.pressure > 0
    return NormalResult(grid=pb.grid, pressure=res.pressure, gap=res.separation, displacement=res.displacement,
                        contact=contact, adhesive=np.zeros_like(contact), force=res.force, approach=res.approach,
                        iterations=res.newton_iterations, residual_history=np.array([res.residual]),
                        converged=res.converged, time=res.time, control="force",
                        info={"two_scale": True})


def _row(pb, state: NormalResult, res) -> dict:
    row = step_row(state, "loading")
    row.update({
        "contact_area": res.real_contact_area, "contact_area_compressive": res.real_contact_area,
        "nominal_contact_area": res.nominal_area, "max_pressure": res.max_pressure,
        "max_nominal_pressure": res.max_nominal_pressure, "mean_gap": float(np.mean(res.separation)),
        "cg_iterations": res.cg_iterations, "residual": res.residual,
    })
    return row


def run_normal(pb, bar, settings: SolverSettings) -> RunOutput:
    """Kind ``normal`` with ``[two_scale]``: the loads of ``[load]`` (``force`` or ``forces``).

    Parameters
    ----------
    pb : Problem
        The built problem: the macro gap and operator, and ``pb.two_scale`` (the windows).
    bar : progress handler
        ``bar.phase(description, total)`` and ``bar(done, total)``.
    settings : SolverSettings
        The run's solver settings (the tolerance of the micro and macro solves).

    Returns
    -------
    RunOutput
    """
    sc = pb.scenario
    ts = sc.two_scale
    forces = [sc.load.force] if sc.load.force is not None else list(sc.load.forces)
    pressures, range_info = table_pressures(pb, settings, max(forces))
    bar.phase("micro windows", 1)
    law = interface_law(pb.two_scale, pressures, tol=settings.tolerance, max_iterations=settings.max_iterations,
                        scheduler=ts.scheduler, cache=ts.cache)
    bar(1, 1)
    bar.phase("macro solves", len(forces))
    rows, results, messages = [], [], []
    beyond = False
    for k, force in enumerate(forces):
        res = solve_interface_normal(pb.operator, pb.gap, law, float(force), tol=max(settings.tolerance, 1e-9))
        state = _macro_result(pb, res)
        rows.append(_row(pb, state, res))
        results.append(state)
        beyond = beyond or res.beyond_table
        bar(k + 1, len(forces))
    info = law.info
    if info.get("not_converged"):
        messages.append(f"two_scale: {info['not_converged']} of {info['solves']} micro window solves did not converge "
                        f"(tolerance {settings.tolerance:g}); the interface law averages them as they are")
    if not law.converged and not info.get("not_converged"):
        messages.append("two_scale: a micro window solve did not converge")
    if beyond:
        messages.append(f"two_scale.max_pressure: a macro cell's nominal pressure exceeds the table's largest "
                        f"({law.pressures[-1]:.4g} Pa); the law was extrapolated there: give a larger max_pressure")
    # the windows' asperity contacts at the largest load's mean nominal pressure: resolved when the
    # largest patch spans >= 3 cells (the result check contact_cells of a whole-grid run)
    last = rows[-1]
    mean_p = float(last["normal_force"]) / max(float(last["nominal_contact_area"]), pb.grid.dx * pb.grid.dy)
    patch = law.patch_cells_at(mean_p)
    if patch is not None and patch < MIN_PATCH_CELLS:
        messages.append(f"two_scale.window_n: at the mean nominal pressure ({mean_p:.3g} Pa) the windows' largest "
                        f"contact patch is {patch:.1f} cell(s) across (< {MIN_PATCH_CELLS:g}): the asperity contacts "
                        "are not resolved, so the real contact area and the peak pressure are set by the window's "
                        "cells; refine two_scale.window_n")
    # the scale separation at the largest load: the window against the length over which the
    # nominal pressure changes (median over the contact and its edge's 5th percentile)
    lengths = pressure_length(results[-1].pressure, pb.grid.dx, pb.grid.dy)
    separation = {"pressure_length_median": lengths["median"], "pressure_length_edge": lengths["p05"],
                  "window_over_pressure_length": float(ts.window / lengths["median"])}
    run = {"two_scale": {**range_info, **separation, "mean_nominal_pressure": mean_p, "window_patch_cells": patch,
                         "law": law.as_dict(), "gap_spread_max": float(np.max(law.gap_spread))}}
    labels = [f"loading {k}" for k in range(len(rows))]
    return RunOutput(rows=rows, results=results, labels=labels, indices=list(range(len(rows))), run=run,
                     warnings=messages)
