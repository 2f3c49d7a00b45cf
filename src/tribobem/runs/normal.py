"""Run kind ``normal``: one load or a list of loads, warm-started step to step.

One load (``force`` or ``approach``) or a list (``forces`` / ``approaches``); with
``load.unload = true`` a list is traced back down (the unloading branch).  With
``[adhesion]`` the Dugdale interaction acts outside contact.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..solvers.normal import solve_normal
from ..solvers.normal_paths import approach_curve, force_curve
from .common import approach_below_full_contact, scenario_errors, step_row
from .kind import ALL, RunKind, RunOutput, fail, positive_normal_load, require_elastic_body
from .kind import NORMAL_COLUMNS
from .settings import SolverSettings
from .two_scale import run_normal as run_two_scale

__all__ = ["run", "check", "KIND"]


@scenario_errors  # the solvers' error keys -> scenario keys (runs.common.SCENARIO_KEYS)
def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``normal`` scenario on its built :class:`~tribobem.scenario.build.Problem`.

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
        One step per load (and per unloading load), with the solved states for fields.nc.
    """
    sc, load = pb.scenario, pb.scenario.load
    if settings is None:
        settings = SolverSettings.from_scenario(sc)
    if pb.two_scale is not None:  # [two_scale]: micro windows, then the macro solve
        return run_two_scale(pb, bar, settings)
    kw = settings.normal_run_kw()
    inter = pb.interaction
    approach_below_full_contact(pb)
    run_level: dict = {}
    if load.force is not None or load.approach is not None:
        bar.phase("solving", 1)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            if load.force is not None:
                res = solve_normal(pb.operator, pb.gap, force=load.force, interaction=inter, **kw)
            else:
                res = solve_normal(pb.operator, pb.gap, approach=load.approach, interaction=inter, **kw)
        bar(1, 1)
        run_level["solve"] = solve_path(res)
        return RunOutput(rows=[step_row(res, "loading")], results=[res], labels=["loading 0"], indices=[0],
                         run=run_level)
    unload = bool(load.unload)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        if load.forces is not None:
            bar.phase("force steps", len(load.forces) * (2 if unload else 1))
            curve = force_curve(pb.operator, pb.gap, load.forces, interaction=inter, unload=unload,
                                keep_fields=True, progress=bar, **kw)
        else:
            bar.phase("approach steps", len(load.approaches) * (2 if unload else 1))
            curve = approach_curve(pb.operator, pb.gap, load.approaches, interaction=inter, unload=unload,
                                   keep_fields=True, progress=bar, **kw)
    rows = [dict(r) for r in curve.steps]
    counters: dict = {}
    labels = []
    for r in rows:
        k = counters.get(r["branch"], 0)
        counters[r["branch"]] = k + 1
        labels.append(f"{r['branch']} {k}")
    if inter is not None and np.any(curve.converged) and np.nanmin(curve.force) < 0:
        run_level["pull_off_force"] = curve.pull_off_force
        run_level["pull_off_approach"] = curve.pull_off_approach
    if unload:
        run_level["hysteresis_energy"] = curve.hysteresis_energy
    return RunOutput(rows=rows, results=list(curve.results), labels=labels, indices=list(range(len(rows))),
                     run=run_level, curve=curve)


def solve_path(res) -> dict:
    """summary.json ``solve`` of a single-load normal run: how the solve ran.

    Parameters
    ----------
    res : NormalResult
        The solved state.

    Returns
    -------
    dict
        ``method`` (the normal solver), ``precision`` (NormCG's arithmetic: "single" or
        "double"; absent for Polonsky-Keer) and, when the candidate-set solve ran,
        ``candidates``: its ``rounds``, ``box`` ([i0, i1, j0, j1], nodes), ``box_fraction`` (of the
        grid's nodes) and ``verified_margin`` (m: the smallest undeformed gap above the approach
        outside the box).
    """
    info = res.info
    out = {"method": info.get("method")}
    if "precision" in info:
        out["precision"] = info["precision"]
    cand = info.get("candidates")
    if cand:
        out["candidates"] = {"rounds": int(cand["rounds"]), "box": list(cand["boxes"][-1]),
                             "box_fraction": float(cand["box_fraction"]),
                             "verified_margin": float(cand["verified_margin"])}
    return out


def check(sc) -> None:
    """Kind ``normal``: exactly one of the four loads; compressive without adhesion; ``unload``
    traces a list back down (a single load has no unloading branch).

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
    load = sc.load
    given = load.given
    if len(given) != 1:
        fail("load.force" if not given else f"load.{given[1]}",
             "give exactly one of force, approach, forces or approaches"
             + (f" (got {', '.join(given)})" if given else ""))
    if "unload" in load.model_fields_set and given[0] in ("force", "approach"):
        fail("load.unload", f"traces a list of loads back down (load.forces or load.approaches); a single "
                            f"load.{given[0]} has no unloading branch")
    positive_normal_load(sc)
    if sc.two_scale is not None:
        if given[0] not in ("force", "forces"):
            fail(f"load.{given[0]}", "a two-scale run is force-controlled: give load.force or load.forces")
        if "unload" in load.model_fields_set and load.unload:
            fail("load.unload", "a two-scale run traces the loading branch (the normal interface law has no "
                                "unloading hysteresis without adhesion); leave unload out")
        if sc.adhesion.model != "none":
            fail("adhesion.model", "a two-scale normal run takes a non-adhesive interface (the windows' Dugdale "
                                   "tensile law serves the two-scale pull-off only, kind = 'pulloff'); run the whole "
                                   "grid")


KIND = RunKind(
    name="normal", run=run, check=check,
    summary="normal contact at one load or along a list of loads (with Dugdale adhesion if given)",
    figures=("load_curve", "two_scale", "maps"),
    columns=NORMAL_COLUMNS,
    results={"pull_off_force": "force", "pull_off_approach": "length", "hysteresis_energy": "energy"},
    uses={"load": ("force", "approach", "forces", "approaches", "unload"), "solver": ("method", "precision"),
          "two_scale": ALL,
          "body1": ("hardness", "layer"), "body2": ("hardness", "layer")},
)
