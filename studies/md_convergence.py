"""Grid convergence of the two Dugdale discretisations on the Maugis-Dugdale sphere.

For lambda in (0.3, 1, 2, 5) and grids with 2-16 cells across the cohesive zone c - a (the grid
rule of :func:`tribobem.validation.adhesion.maugis_dugdale_problem`), the sphere is solved under
displacement control at the analytic approach of F = 0 (the state between loading and
pull-off), from zero pressure, by Polonsky-Keer and by NormCG, with the softened law (the
default, a ramp of width 3 sigma0 C at h0) and with the thesis' step.  Reported per state: the
errors of the contact radius a, the cohesive radius c and the force F (in units of pi R dgamma)
against Maugis-Dugdale (Johnson-Greenwood form), and the force spread between the two solvers.
The observed order is the slope of log |error| against log dx between the two finest grids.

    python studies/md_convergence.py [--lambdas 0.3 1 2 5] [--cells 2 4 8 16] [--csv docs/data/md_convergence.csv]
"""

from __future__ import annotations

import argparse
import csv
import math
import time
import warnings

from tribobem.solvers.normal import solve_normal
from tribobem.validation.adhesion import maugis_dugdale_problem

#: Cells across the cohesive zone of each level; lambda = 5 stops at 8 (1248^2).
CELLS = (2, 4, 8, 16)
LAMBDAS = (0.3, 1.0, 2.0, 5.0)
MAX_N = 1300


def states(lam: float, cells: float, discretisation: str) -> dict:
    """The two solvers' states of one (lambda, grid, discretisation) and their errors."""
    prob = maugis_dugdale_problem(lam, cells_cohesive=cells, cells_contact=2.5 * cells,
                                  discretisation=discretisation)
    ref = prob.reference(force=0.0)
    d = float(ref.approach)
    out = {"lambda": lam, "cells": cells, "n": prob.grid.nx, "dx": prob.grid.dx, "discretisation": discretisation}
    forces = {}
    for method in ("polonsky_keer", "normcg"):
        t = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = solve_normal(prob.operator, prob.gap, approach=d, interaction=prob.law, tol=1e-10, method=method,
                             max_iterations=20000)
        forces[method] = r.force if r.converged else math.nan
        if method == "polonsky_keer":
            out.update({
                "a_err": r.contact_radius() / float(ref.contact_radius) - 1,
                "c_err": r.cohesive_radius() / float(ref.cohesive_radius) - 1,
                "F_err": r.force / prob.F_scale,  # the reference force is 0: error in pi R dgamma
                "converged": r.converged,
            })
        out[f"cpu_{method}"] = time.process_time() - t
    out["spread"] = (forces["polonsky_keer"] - forces["normcg"]) / prob.F_scale
    return out


def order(rows: list[dict], key: str) -> float:
    """Observed order between the two finest grids of ``rows`` (one lambda, one discretisation)."""
    fine = sorted(rows, key=lambda r: r["dx"])[:2]
    if len(fine) < 2 or not all(abs(r[key]) > 0 for r in fine):
        return math.nan
    return math.log(abs(fine[1][key]) / abs(fine[0][key])) / math.log(fine[1]["dx"] / fine[0]["dx"])


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lambdas", type=float, nargs="+", default=list(LAMBDAS))
    ap.add_argument("--cells", type=float, nargs="+", default=list(CELLS))
    ap.add_argument("--csv", default=None)
    args = ap.parse_args(argv)
    rows = []
    print("| lambda | cells in c - a | n | law | a error | c error | F error (pi R dgamma) "
          "| PK - NormCG (pi R dgamma) | CPU PK / NormCG (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for lam in args.lambdas:
        for cells in args.cells:
            for how in ("softened", "step"):
                n = maugis_dugdale_problem(lam, cells_cohesive=cells, cells_contact=2.5 * cells).grid.nx
                if n > MAX_N:
                    continue
                r = states(lam, cells, how)
                rows.append(r)
                print(f"| {lam:g} | {cells:g} | {r['n']} | {how} | {100 * r['a_err']:+.2f} % | {100 * r['c_err']:+.2f} % "
                      f"| {r['F_err']:+.4f} | {r['spread']:+.1e} | {r['cpu_polonsky_keer']:.1f} / {r['cpu_normcg']:.1f} |",
                      flush=True)
    for lam in args.lambdas:
        for how in ("softened", "step"):
            sel = [r for r in rows if r["lambda"] == lam and r["discretisation"] == how]
            print(f"lambda {lam:g} {how}: observed order a {order(sel, 'a_err'):.2f}, c {order(sel, 'c_err'):.2f}, "
                  f"F {order(sel, 'F_err'):.2f}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    return rows


if __name__ == "__main__":
    main()
