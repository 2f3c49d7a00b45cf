"""Paper E section 3.2: the friction hysteresis study (thesis Paper E Figs. 6, 7, 9).

The model problem, one loop and its measures (:func:`md_state`, :func:`paper_e_problem`,
:func:`start_state`, :class:`PaperELoop`, :func:`paper_e_loop`, :func:`loop_metrics`, the
constants; every choice documented there) live in the package,
:mod:`tribobem.validation.paper_e_model`, because the ``paper_e`` validation case runs them; they
are re-exported here.  This module adds the study over every work of adhesion
(:func:`paper_e_study`) and its tables (:func:`summary_table`, :func:`loops_table`); the driver is
``examples/studies/paper_e.py``.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

from tribobem.errors import InputError
from tribobem.validation.paper_e_model import (  # noqa: F401 (re-exported)
    DEFAULT_SOLVER,
    E_FLAT,
    FORCE,
    FRICTION,
    MIN_COHESIVE_CELLS,
    NU_FLAT,
    RADIUS,
    RAMP_FRACTIONS,
    WORKS,
    Z0,
    PaperELoop,
    _points,
    loop_metrics,
    md_state,
    paper_e_loop,
    paper_e_problem,
    start_state,
)
from tribobem.validation.references import PAPER_E_SMOOTH_REPULSIVE_FORCE

__all__ = [
    "RADIUS", "E_FLAT", "NU_FLAT", "FORCE", "FRICTION", "Z0", "WORKS", "PAPER_E_SMOOTH_REPULSIVE_FORCE",
    "MIN_COHESIVE_CELLS", "DEFAULT_SOLVER", "RAMP_FRACTIONS",
    "md_state", "paper_e_problem", "start_state", "PaperELoop", "paper_e_loop", "loop_metrics", "paper_e_study",
    "summary_table", "loops_table",
]


def paper_e_study(works: Sequence[float] = WORKS, n: int = 96, *, progress: Callable[[PaperELoop], None] | None = None,
                  **loop_kw) -> list:
    """:func:`paper_e_loop` for every work of adhesion (same grid size n, domain +-2a each)."""
    if not len(works):
        raise InputError("works", "give at least one work of adhesion")
    out = []
    for w in works:
        lp = paper_e_loop(float(w), n, **loop_kw)
        out.append(lp)
        if progress:
            progress(lp)
    return out


def summary_table(loops: Sequence[PaperELoop]):
    """A pandas DataFrame, one row of :func:`loop_metrics` per loop, with Paper E's smooth F0+
    (``paper_e_repulsive_force``, only at dgamma = 50 mJ/m^2)."""
    import pandas as pd

    rows = []
    for lp in loops:
        r = loop_metrics(lp)
        r["paper_e_repulsive_force"] = (PAPER_E_SMOOTH_REPULSIVE_FORCE if math.isclose(lp.work_of_adhesion, 0.05)
                                        else float("nan"))
        rows.append(r)
    return pd.DataFrame(rows)


def loops_table(loops: Sequence[PaperELoop]):
    """A pandas DataFrame with every step of every loop: dgamma, n, step, point label, cycle,
    branch, F_x, F_x/(mu F0), F_x/(mu F0+), delta_x, stick ratio, F0+ of the step, converged."""
    import pandas as pd

    rows = []
    for lp in loops:
        label = {i: k for k, i in lp.points.items()}
        for k in range(len(lp.forces)):
            rows.append({"work_of_adhesion": lp.work_of_adhesion, "n": lp.n, "step": k, "point": label.get(k, ""),
                         "cycle": int(lp.cycles[k]), "branch": lp.branches[k], "turning": bool(lp.turning[k]),
                         "tangential_force_x": lp.forces[k],
                         "force_over_mu_f0": lp.forces[k] / (lp.friction_coefficient * lp.normal_force),
                         "force_over_mu_f0p": lp.forces[k] / (lp.friction_coefficient * lp.repulsive_force),
                         "displacement_x": lp.displacements[k], "stick_ratio": lp.stick_ratios[k],
                         "repulsive_force": lp.repulsive_forces[k], "converged": bool(lp.converged[k])})
    return pd.DataFrame(rows)
