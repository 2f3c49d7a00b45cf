"""The CI gating tier of the validation: ``tribobem validate --ci`` (``level="ci"``).

The quick tier (``--quick``) checks every case on small grids; the full tier (``--full``) is
the complete set of accuracy bars (the costliest being lambda = 5 on 1248^2).  The gating tier
sits between them: every case that protects a published number runs at the resolution of that
number, or, where that resolution does not fit CI's time budget per physics, at a reduced
resolution that still fails a wrong implementation (run times of the tiers:
benchmarks/README.md); CI runs it one physics at a time (``--ci --physics NAME``) and fails on any
row (``.ci/run``).

What each case runs (:data:`GATE`):

``"full"``
    The case's full rows: Hertz at 512^2, Westergaard with both kernels, the bisinusoidal
    JGH asymptotes at 1024^2 (normal); Guduru's three waviness ratios at 192^2 (adhesion); every
    tangential case (Cattaneo-Mindlin, periodic, stiffness, coupling signs, Spence); the
    Mindlin-Deresiewicz loop (hysteresis); Paper E's hysteresis study at 256^2 (paper_e); the
    bisinusoidal resolution check with the published 625-case table (studies); the humid
    friction cases at 64^2 (humid_friction).
``maugis_dugdale``, ``md_pull_off``
    The Maugis-Dugdale table: lambda = 0.1, 0.3, 0.5, 1 and 2 at their full
    resolution (cohesive zone >= 12 cells, 15 rows each, 3 % / 5 %; pull-off 3 %), and
    lambda = 5 at :data:`MD_GATE_CELLS` cells across the cohesive zone (624^2) instead of 8
    (1248^2, where the force points need a displacement-controlled loading path: far more
    than CI's budget, even on 784^2).  The lambda = 5 rows of the
    gate: a, c and approach at F = 0 (a direct force-controlled solve, which converges on
    624^2), force, a and c at the two approaches of the full tier (cold displacement-controlled
    solves) and the pull-off (scan about the analytic pull-off approach), with the tolerances
    :data:`MD_GATE_TOL`.  Measured on 624^2: a, c 0.7-2.9 %, approach 5.7 %, force under
    displacement control 3.0 / 5.2 %, pull-off 2.8 %; the errors are first order in
    dx/(c - a) but not monotone (the discrete cohesive-zone edge: on 784^2 the pull-off is
    6.1 % off).
anything else (a new physics' cases)
    Its quick rows, until a gate entry is added here.
"""

from __future__ import annotations

from typing import Callable

from .adhesion import MD_LAMBDAS, maugis_dugdale_problem, maugis_dugdale_rows, md_pull_off_rows
from .common import ValidationRow

__all__ = ["GATE", "MD_GATE_CELLS", "MD_GATE_TOL", "gate_rows", "md_gate_rows", "md_pull_off_gate_rows"]

#: Cells across the cohesive zone c - a for lambda = 5 in the gate (the full tier uses 8).
MD_GATE_CELLS = 4.0
#: Tolerances of the lambda = 5 rows at :data:`MD_GATE_CELLS` cells: (a and c; approach and
#: force under displacement control; pull-off), about 1.5 x the errors measured on 624^2 (module
#: docstring); a missing cohesive-zone force or a wrong sigma0 moves the force and the
#: approach by 10-50 %.
MD_GATE_TOL = (0.05, 0.08, 0.05)


def _direct_force_control() -> dict:
    """Keyword asking :func:`maugis_dugdale_rows` for a direct force-controlled solve (its
    default for lambda >= 5 is the displacement-controlled loading path, made for 1248^2 and far
    costlier per point); empty where the function has no such choice (direct anyway)."""
    import inspect

    return {"force_path": "direct"} if "force_path" in inspect.signature(maugis_dugdale_rows).parameters else {}


_DIRECT = _direct_force_control()


def md_gate_rows() -> list[ValidationRow]:
    """The Maugis-Dugdale table of the gate: every lambda of the table.

    Returns
    -------
    list of ValidationRow
        The full-tier rows (15 each) for lambda < 5; for lambda = 5 the reduced set of the
        module docstring at :data:`MD_GATE_CELLS` with :data:`MD_GATE_TOL`.
    """
    rows: list[ValidationRow] = []
    for lam in MD_LAMBDAS:
        if lam >= 5:
            tol, tol_force, _ = MD_GATE_TOL
            prob = maugis_dugdale_problem(lam, cells_cohesive=MD_GATE_CELLS)
            fc = maugis_dugdale_rows(prob, forces=[0.0], approaches=[], tol=tol, **_DIRECT)
            for r in fc:  # the approach gets the looser bar (5.7 % measured)
                if r.quantity.startswith("approach"):
                    r.tolerance = tol_force
                    r.passed = bool(r.rel_error <= tol_force)
            rows += fc + maugis_dugdale_rows(prob, forces=[], tol=tol, tol_dc_force=tol_force)
        else:
            rows += maugis_dugdale_rows(maugis_dugdale_problem(lam))
    return rows


def md_pull_off_gate_rows() -> list[ValidationRow]:
    """The Maugis-Dugdale pull-off of the gate: every lambda of the table.

    Returns
    -------
    list of ValidationRow
        One pull-off row per lambda; lambda = 5 at :data:`MD_GATE_CELLS` with the pull-off
        tolerance of :data:`MD_GATE_TOL`.
    """
    rows: list[ValidationRow] = []
    for lam in MD_LAMBDAS:
        if lam >= 5:
            rows += md_pull_off_rows(maugis_dugdale_problem(lam, cells_cohesive=MD_GATE_CELLS), tol=MD_GATE_TOL[2])
        else:
            rows += md_pull_off_rows(maugis_dugdale_problem(lam))
    return rows


#: case name -> ``"full"``, ``"quick"`` or a function returning the gate's rows.
GATE: dict[str, str | Callable[[], list[ValidationRow]]] = {
    # normal
    "hertz": "full", "westergaard": "full", "bisinusoidal_small_load": "full", "bisinusoidal_near_full": "full",
    "force_balance": "full", "periodic_vs_free": "full",
    # adhesion
    "maugis_dugdale": md_gate_rows, "md_pull_off": md_pull_off_gate_rows, "md_grid_band": "full",
    "md_step": "quick", "md_solver_agreement": "full", "exponential": "full", "guduru": "full",
    # tangential
    "cattaneo_mindlin": "full", "cattaneo_periodic": "full", "mindlin_stiffness": "full", "coupling_sign": "full",
    "spence": "full",
    # hysteresis
    "mindlin_deresiewicz": "full",
    # paper_e
    "paper_e": "full",
    # studies
    "bisinusoidal_resolution": "full",
    # humid_friction (64^2, about 30 s on 2 cores)
    "humid_dry_limit": "full", "humid_uncoupled_onset": "full", "humid_coupled_onset": "full",
    "humid_force_balance": "full", "humid_loop_energy": "full",
    # burl (about 25 s on 2 cores, the kendall pull-off on 264^2 most of it)
    "rounded_punch": "full", "flat_punch": "full", "burl_stiffness": "full", "kendall": "full", "texture_cell": "full",
    # two_scale (seconds: the whole burls' numbers are committed, only the two-scale side runs)
    "two_scale_smooth": "full", "two_scale_layer": "full", "two_scale_whole_burl": "full",
    "two_scale_partial_slip": "full", "two_scale_hysteresis": "full", "two_scale_humid": "full",
    "two_scale_pulloff": "full",
    # materials (seconds)
    "hardness_hertz": "full", "hardness_sphere": "full", "hardness_rigid_plastic": "full", "hardness_pulloff": "full",
    "subsurface_hertz": "full", "subsurface_sliding": "full", "subsurface_equilibrium": "full",
    "layer_limits": "full", "layer_fem": "full", "layer_sphere": "full",
}


def gate_rows(name: str, case: Callable[[bool], list[ValidationRow]]) -> list[ValidationRow]:
    """The gate's rows of case ``name`` whose tier function (``rows(quick)``) is ``case``.

    Parameters
    ----------
    name : str
        Case name; its entry in :data:`GATE` decides what runs (a case without one runs its
        quick rows).
    case : callable
        The case's ``rows(quick)`` function.

    Returns
    -------
    list of ValidationRow
    """
    how = GATE.get(name, "quick")
    if how == "full":
        return case(False)
    if how == "quick":
        return case(True)
    return how()
