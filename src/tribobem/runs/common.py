"""Helpers shared by the runners of several kinds (rows, curves, progress offsets)."""

from __future__ import annotations

import numpy as np

from ..solvers.paths import LoadCurve, find_jumps

__all__ = ["solve_kw", "step_row", "curve_from_rows", "offset_progress"]


def solve_kw(sc) -> dict:
    """The solver keywords of a scenario's ``[solver]`` section."""
    return {"tol": sc.solver.tolerance, "max_iterations": sc.solver.max_iterations}


def step_row(res, branch: str) -> dict:
    """A summary.json step (the result's scalars) on ``branch``."""
    row = res.scalars()
    row["branch"] = branch
    return row


def curve_from_rows(rows: list, control: str):
    """A LoadCurve (with jumps) from step rows."""

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
    """A ``progress(done, total)`` callback that reports ``offset + done`` of ``total`` to ``cb``."""
    return lambda done, _t: cb(offset + done, total)
