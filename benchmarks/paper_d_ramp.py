"""Benchmark: the tangential force ramp of Paper D section 3.1 (issue 6 item 7).

A rigid ball (R = 10 um) on an elastic half-space (E = 130 GPa, nu = 0.3: dissimilar bodies, the
coupling loop is active), F0 = 10 uN, mu = 0.2, free boundary over +-2a (padded FFT grid),
``--steps`` tangential forces from 0 to mu F0 (the ramp ends at gross slip; the onset is then
bisected to 1e-3 mu F0+), total slip, the tolerances of the partial_slip run kind.  Optional
Dugdale adhesion through the Tabor parameter ``--mu-t`` (z0 = 0.2 nm, as Paper D's Table 1).

Prints wall and CPU time, solved states (ramp steps + bisection steps), coupling passes per
state and inner iterations per state, and the onset F_x/(mu F0+).  Not a test: nothing here is
asserted; ``python benchmarks/paper_d_ramp.py [--n 256 --steps 40]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--mu-t", type=float, default=0.0, help="Tabor parameter of the Dugdale adhesion (0: none)")
    ap.add_argument("--no-extrapolate", action="store_true", help="warm start from the last step only")
    ap.add_argument("--keep-freed-memory", action="store_true",
                    help="glibc mallopt, as in benchmarks/hysteresis.py (measures the page-fault cost)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.keep_freed_memory:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from hysteresis import keep_freed_memory

        keep_freed_memory()

    import tribobem as tb
    from tribobem.analytic.hertz import hertz
    from tribobem.geometry import sphere
    from tribobem.runs.settings import COUPLING_TOLERANCE, TANGENTIAL_TOLERANCE
    from tribobem.solvers import coupling as C
    from tribobem.solvers import tangential_paths as S

    counts = {"tangential_iterations": 0, "normal_iterations": 0, "states": 0}
    orig_t, orig_n, orig_c = C.solve_tangential, C.solve_normal, S.solve_coupled

    def t_solve(*a, **kw):
        r = orig_t(*a, **kw)
        counts["tangential_iterations"] += r.iterations
        return r

    def n_solve(*a, **kw):
        r = orig_n(*a, **kw)
        counts["normal_iterations"] += r.iterations
        return r

    passes = []

    def c_solve(*a, **kw):
        if args.no_extrapolate:
            kw["extrapolate"] = None
        r = orig_c(*a, **kw)
        counts["states"] += 1
        passes.append(r.coupling_iterations)
        return r

    C.solve_tangential, C.solve_normal, S.solve_coupled = t_solve, n_solve, c_solve

    pair = tb.ContactPair(tb.Material(130e9, 0.3, "flat"), tb.Material.rigid("ball"))
    R, F0, mu, z0 = 10e-6, 10e-6, 0.2, 0.2e-9
    Es = pair.effective_modulus
    interaction = None
    if args.mu_t > 0:
        # Tabor parameter mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3)
        dgamma = float(np.sqrt(args.mu_t**3 * Es**2 * z0**3 / R))
        interaction = tb.DugdaleAdhesion(dgamma, z0)
    a = float(hertz(force=F0, radius=R, E_star=Es).contact_radius)
    grid = tb.Grid.square(args.n, 4.0 * a * (1.3 if args.mu_t > 0 else 1.0))
    op = tb.make_operator(grid, pair, ("x", "y", "z"))
    gap = sphere(grid, radius=R)
    forces = np.linspace(0.0, mu * F0 * (1 + 0.5 * args.mu_t), args.steps)
    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ramp = S.tangential_ramp(op, gap, normal_force=F0, friction_coefficient=mu, forces=forces,
                                 interaction=interaction, tangential_tol=TANGENTIAL_TOLERANCE,
                                 coupling_tol=COUPLING_TOLERANCE)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    n = max(counts["states"], 1)
    out = {
        "grid": f"{args.n}^2 free boundary (padded {2 * args.n}^2)",
        "ramp_steps": len(ramp.steps), "bisection_steps": ramp.refine_steps, "solved_states": counts["states"],
        "wall_s": wall, "cpu_s": cpu,
        "coupling_passes_per_state": float(np.mean(passes)) if passes else float("nan"),
        "tangential_iterations_per_state": counts["tangential_iterations"] / n,
        "normal_iterations_per_state": counts["normal_iterations"] / n,
        "onset_ratio": ramp.onset_ratio, "keep_freed_memory": args.keep_freed_memory,
        "tolerances": {"tangential": TANGENTIAL_TOLERANCE, "coupling": COUPLING_TOLERANCE},
    }
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        for k, v in out.items():
            print(f"{k:34s} {v}")
    return out


if __name__ == "__main__":
    main(sys.argv[1:])
