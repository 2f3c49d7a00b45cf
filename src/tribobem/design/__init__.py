"""Design studies: rank design variants (burls, textures, roughness, RH, clamp load) against targets.

``tribobem design DESIGN.toml`` runs, for every point of a grid of design parameters, a fixed
chain of run kinds on the same geometry (:mod:`~tribobem.design.chain`): normal contact at
the clamp load, the pull-off from it, a tangential ramp to gross slip and optionally a
hysteresis loop; it then ranks the points against the design's targets and writes

* ``design.nc`` / ``design.csv``: one row per point (the varied parameters, static friction
  force and ratio, pre-sliding displacement, lateral stiffness at A/B/C, pull-off force, real
  contact area, max and peak pressure, ``exceeds_hardness``, warnings, status and message,
  the score and the rank; SI units);
* ``design_report.html``: the ranking, Pareto plots (static friction against pull-off, lateral
  stiffness against real contact area) and every warning of every point.

The points run on the sweep machinery (:func:`tribobem.sweep.run_sweep`: Dask, local by
default; resumable: a finished point is cached under ``points/<hash>.json`` and never
recomputed; a failed point is recorded with its message and retried on the next run).  The
hash covers the base scenario, the point, the chain options and the solver, not the targets:
changing a target re-ranks without recomputing.

Modules: :mod:`~tribobem.design.spec` (the design file), :mod:`~tribobem.design.chain` (one
point), :mod:`~tribobem.design.table` (table, score, rank), :mod:`~tribobem.design.report`
(HTML, Pareto fronts), :mod:`~tribobem.design.command` (:func:`run_design`, the command).
"""

from .chain import DesignPointError, point_scenario, run_chain, stage_scenario
from .command import DesignResult, run_design
from .report import pareto_front, render_design_report, write_design_report
from .spec import ChainOptions, DesignSpec, DesignSweep, Target, load_design
from .table import rank_rows

__all__ = [
    # the design file
    "DesignSpec", "DesignSweep", "ChainOptions", "Target", "load_design",
    # running it
    "run_design", "DesignResult", "DesignPointError", "run_chain", "stage_scenario", "point_scenario",
    # table and report
    "rank_rows", "pareto_front", "render_design_report", "write_design_report",
]
