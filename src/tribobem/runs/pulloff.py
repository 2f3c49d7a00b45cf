"""Run kind ``pulloff``: optional loading branch, then the pull-off.

The unloading starts from the state at ``load.preload`` (or, without a preload, from the
adhesive equilibrium at zero external load), reached by loading under displacement control
from the first touch (:func:`~tribobem.solvers.normal_paths.solve_at_force`); then
:func:`~tribobem.solvers.normal_paths.pull_off` unloads and refines the most negative force.  The
optional loading branch runs under displacement control from separation to the approach of
that start.  Run-level ``pull_off_force``, ``preload`` (the force the unloading started from),
``preload_source`` and ``cohesive_zone_cells`` (cells across the cohesive zone at pull-off).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..output.checks import cohesive_cells
from ..solvers.normal_paths import approach_curve, pull_off
from .common import curve_from_rows, offset_progress, scenario_errors
from .humid_pulloff import run as humid_run
from .two_scale import run_pulloff as run_two_scale
from .kind import (ALL, CAPILLARY_STEPS, RunKind, RunOutput, fail, refuse_normcg, require_elastic_body,
                   require_humidity)
from .kind import CAPILLARY_COLUMNS, NORMAL_COLUMNS
from .settings import SolverSettings

__all__ = ["run", "check", "KIND"]

#: How summary.json names the start of the unloading without a preload.
ZERO_LOAD = "zero external load (adhesive equilibrium at F = 0)"


@scenario_errors  # the solvers' error keys -> scenario keys (runs.common.SCENARIO_KEYS)
def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``pulloff`` scenario on its built :class:`~tribobem.scenario.build.Problem`.

    Returns its :class:`~tribobem.runs.kind.RunOutput`.

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
        The steps of the loading and unloading path, with the pull-off force (N) and approach (m)
        as run-level values.
    """
    if settings is None:
        settings = SolverSettings.from_scenario(pb.scenario)
    if pb.two_scale is not None:  # [two_scale]: the windows' tensile law, then the macro pull-off
        return run_two_scale(pb, bar, settings)
    if getattr(pb, "humidity", None) is not None:  # [humidity]: one pull-off per RH (runs.humid_pulloff)
        return humid_run(pb, bar, settings)
    load = pb.scenario.load
    kw = settings.path_kw()  # the pull-off path picks its normal solver itself (runs.settings.OWN_METHOD_KINDS)
    inter = pb.interaction
    n_load = max(load.steps // 2, 4) if load.loading else 0
    total = load.steps + load.refine + 1 + n_load
    bar.phase("pull-off", total)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        po = pull_off(pb.operator, pb.gap, inter, preload=load.preload, control=load.control, n_steps=load.steps,
                      refine=load.refine, progress=offset_progress(bar, 0, total), **kw)
        start = po.preload_state
        rows: list = []
        if load.loading and math.isfinite(start.approach):
            d0 = -2.0 * inter.range  # separated by twice the law's range
            approaches = np.linspace(d0, start.approach, n_load)
            loading = approach_curve(pb.operator, pb.gap, approaches, interaction=inter, unload=False,
                                     progress=offset_progress(bar, total - n_load, total), **kw)
            rows += [dict(r) for r in loading.steps]
        n_loading = len(rows)
        rows += [dict(r, branch="unloading") for r in po.curve.steps]  # force control labels them "loading"
        at = po.state  # the state at pull-off, on the branch the unloading followed
        bar(total, total)
    curve = curve_from_rows(rows, "displacement" if load.control == "displacement" else "force")
    if load.control == "force":  # the force-controlled jump-off (no equilibrium beyond it)
        seen = {(j["index"], j["kind"]) for j in curve.jumps}
        for j in po.curve.jumps:
            jj = dict(j, index=int(j["index"]) + n_loading, branch="unloading")
            if jj["kind"] == "jump-off" and (jj["index"], "jump-off") not in seen:
                curve.jumps.append(jj)
        curve.jumps.sort(key=lambda j: j["index"])

    run = {"pull_off_force": po.force, "pull_off_approach": po.approach, "pull_off_control": load.control,
           "preload": po.preload, "preload_source": "load.preload" if load.preload is not None else ZERO_LOAD}
    if at is not None:
        # cells across the cohesive zone at pull-off (the resolution of the number above)
        w = cohesive_cells(at)
        run["cohesive_zone_cells"] = w if math.isfinite(w) else None
    if load.loading:
        run["hysteresis_energy"] = curve.hysteresis_energy
    notes = list(po.notes)
    if load.grid_levels:
        run["grid_levels"] = levels = _grid_levels(pb, load, kw, po, bar)
        change = levels["change"]
        if change is not None and abs(change) > GRID_LEVEL_RTOL:
            notes.append(f"grid_levels: the pull-off moved by {100 * change:+.1f} % between the last two grid levels "
                         f"({levels['levels'][-2]['n']}^2 and {levels['levels'][-1]['n']}^2), more than "
                         f"{100 * GRID_LEVEL_RTOL:g} %: not converged in the grid; add load.grid_levels or refine grid.n")
    # index of the preload state in the steps: the first unloading row
    idx_pre = n_loading if len(rows) > n_loading else -1
    return RunOutput(rows=rows, results=[start, at], labels=["preload", "pull-off"], indices=[idx_pre, -1],
                     curve=curve, run=run, warnings=notes)


#: Largest change of the pull-off between the last two grid levels before a warning (load.grid_levels).
GRID_LEVEL_RTOL = 0.05


def _grid_levels(pb, load, kw, po, bar) -> dict:
    """The pull-off again on grids 2^k times finer over the same domain (``load.grid_levels``).

    Each level is the scenario with ``grid.n`` (or nx, ny) multiplied, built anew: a measured
    topography is interpolated bilinearly below its pixels (``Topography.resample``: the
    converged number is the interpolant's), and the Dugdale law is the level's own (softened
    where its ramp is narrow, ``discretisation = "auto"``).

    Returns
    -------
    dict
        ``levels``: per level ``n``, ``dx`` (m), ``pull_off_force`` (N), ``law``,
        ``cohesive_zone_cells``, ``preload_max_pressure`` (Pa) and, with a hardness,
        ``preload_plastic_area`` (m^2) and ``preload_max_plastic_displacement`` (m); ``change``: the
        relative change of the pull-off between the last two.
    """
    from ..interactions.dugdale import SoftenedDugdale
    from ..interactions.hardness import unwrap_cap

    def entry(p, po):
        res = po.state
        w = cohesive_cells(res) if res is not None else math.nan
        inner = unwrap_cap(p.interaction)[0]
        law = "softened" if isinstance(inner, SoftenedDugdale) else type(inner).__name__
        row = {"n": p.grid.nx, "dx": p.grid.dx, "pull_off_force": po.force, "law": law,
               "cohesive_zone_cells": w if math.isfinite(w) else None}
        pre = po.preload_state
        if pre is not None:
            row["preload_max_pressure"] = pre.max_pressure
            if pre.plastic is not None:  # a hardness cap: what the preload flattened on this level
                row["preload_plastic_area"] = pre.plastic_area
                row["preload_max_plastic_displacement"] = pre.scalars()["max_plastic_displacement"]
        return row

    out = [entry(pb, po)]
    for k in range(1, load.grid_levels + 1):
        pk = pb.refined(2**k)
        total = load.steps + load.refine + 1
        bar.phase(f"pull-off on {pk.grid.nx}x{pk.grid.ny} (grid level {k})", total)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            pok = pull_off(pk.operator, pk.gap, pk.interaction, preload=load.preload, control=load.control,
                           n_steps=load.steps, refine=load.refine, progress=offset_progress(bar, 0, total), **kw)
        out.append(entry(pk, pok))
    f0, f1 = out[-2]["pull_off_force"], out[-1]["pull_off_force"]
    change = (f1 - f0) / abs(f0) if f0 and math.isfinite(f0) and math.isfinite(f1) else None
    return {"levels": out, "change": change}


#: Load keys of the pull-off (the humid one honours control and loading only at their
#: displacement / no-loading values: check()).
_DRY_LOAD = ("preload", "control", "steps", "refine", "loading", "grid_levels")


def check(sc) -> None:
    """Kind ``pulloff``: Dugdale adhesion, or ``[humidity]`` (a humid pull-off, the films' keys
    ``film``/``hamaker`` then belong to it); a humid pull-off unloads under displacement control
    from its start with no separate loading branch.

    Parameters
    ----------
    sc : Scenario
        The validated scenario (called by the schema after the per-section checks).

    Raises
    ------
    InputError
        Through :func:`~tribobem.runs.kind.fail`, naming the offending scenario key.
    """
    require_elastic_body(sc)
    if sc.load.grid_levels and (sc.two_scale is not None or sc.humidity is not None):
        fail("load.grid_levels", "grid levels refine a whole-grid pull-off; a two-scale or humid pull-off has "
                                 "its own resolution keys (two_scale.window_n, grid.n)")
    if sc.two_scale is not None:
        _check_two_scale(sc)
    if sc.humidity is not None:
        require_humidity(sc)
        # What a humid pull-off does anyway may be stated; the other choice is refused.
        given, load = sc.load.model_fields_set, sc.load
        if "control" in given and load.control != "displacement":
            fail("load.control", "a humid pull-off (kind = 'pulloff' with [humidity]) unloads under "
                                 "displacement control only (leave control out or give 'displacement')")
        if "loading" in given and load.loading:
            fail("load.loading", "a humid pull-off (kind = 'pulloff' with [humidity]) has no separate "
                                 "loading branch (leave loading out or give false)")
        return
    for body in ("body1", "body2"):
        for key in ("film", "hamaker"):
            if key in getattr(sc, body).model_fields_set:
                fail(f"{body}.{key}", "used by a humid pull-off only (kind = 'pulloff' with a [humidity] "
                                      "section); this pull-off is dry")
    refuse_normcg(sc, "the dry pull-off path solves its Dugdale states with Polonsky-Keer (normcg applies to "
                      "the humid pull-off, kind = 'pulloff' with [humidity])")
    if not sc.adhesion.enabled:
        fail("adhesion.model", "kind = 'pulloff' needs adhesion: model = 'dugdale' with "
                               "work_of_adhesion and z0 (or a [humidity] section: a humid pull-off)")


def _check_two_scale(sc) -> None:
    """A two-scale pull-off: from a preload, under displacement control, at one RH."""
    load = sc.load
    if load.preload is None:
        fail("load.preload", "a two-scale pull-off unloads from a preload: give load.preload (a compressive force, N)")
    if "control" in load.model_fields_set and load.control != "displacement":
        fail("load.control", "a two-scale pull-off unloads under displacement control only")
    if "loading" in load.model_fields_set and load.loading:
        fail("load.loading", "a two-scale pull-off has no separate loading branch (it loads to the preload on the "
                             "windows' loading branch); leave loading out")
    if sc.humidity is not None and len(sc.humidity.rh or []) != 1:
        fail("humidity.rh", "a two-scale pull-off runs at one RH (its windows' menisci are tabulated at it): run one "
                            "scenario per RH (a sweep over humidity.rh)")
    if sc.humidity is not None and sc.adhesion.enabled:
        fail("adhesion.model", "a two-scale pull-off takes either Dugdale adhesion or menisci ([humidity]), not both")


KIND = RunKind(
    name="pulloff", run=run, check=check,
    summary="the pull-off force: unloading from a preload (Dugdale adhesion, or capillary with [humidity])",
    figures=("load_curve", "capillary", "maps"), report_sections=("capillary",),
    columns=NORMAL_COLUMNS, humid_columns=CAPILLARY_COLUMNS,
    results={"pull_off_force": "force", "pull_off_approach": "length", "preload": "force",
             "hysteresis_energy": "energy", **CAPILLARY_STEPS},
    uses={"load": _DRY_LOAD, "humidity": ALL, "body1": ("film", "hamaker", "hardness", "layer"),
          "body2": ("film", "hamaker", "hardness", "layer"),
          "solver": ("method",), "two_scale": ALL},
    hints={"friction": "a pull-off is frictionless; leave [friction] out",
           **{f"load.{k}": "a pull-off unloads from load.preload (a compressive force; left out: from the "
                           "adhesive equilibrium at zero external load)"
              for k in ("force", "approach", "forces", "approaches")}},
)
