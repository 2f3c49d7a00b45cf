"""Benchmark: the adhesive friction loop, with where its CPU time goes per kind of inner solve.

The problem: a rigid ball (R = 40 um) on an elastic half-space (E = 100 GPa, nu = 0.25: the pair
is dissimilar, so the normal-tangential coupling loop is active), Dugdale adhesion (40 mJ/m^2,
z0 = 0.2 nm), F = 8 uN, mu = 0.25, a free-boundary 0.6 um square of ``--n``^2 cells, a
force-controlled loop of ``--cycles`` x ``--steps`` steps at amplitude ``--amplitude`` x mu F0+
(0.95 by default: 0.98 is beyond what the contact carries at step 10 of the loading).  The
scenario runs through :func:`tribobem.scenario.run.run_scenario`, as ``tribobem run`` does, with
the run's default solver settings.

Prints the CPU time (``time.process_time``) of the whole run and of its phases (summary.json
``timings``), the coupling passes per step, and for each kind of inner solve (normal solves at the
inexact tolerance of an early coupling pass and at the run's tolerance; tangential predictor,
early-pass and final-pass solves) the number of solves, iterations and CPU seconds, counted by
wrapping the solvers the coupling loop calls.  The loop energies are printed to 7 digits, for
comparing variants.  ``--method`` sets ``[solver] method`` (auto: Polonsky-Keer with adhesion).
Not a test: nothing is asserted.

    python benchmarks/adhesive_loop.py [--n 256 --cycles 3 --steps 40] [--method auto] [--json]
"""

from __future__ import annotations

import argparse
import collections
import functools
import json
import sys
import tempfile
import time


def scenario(n: int, cycles: int, steps: int, amplitude: float, method: str, discretisation: str = "softened") -> dict:
    """The benchmark's hysteresis scenario (module docstring)."""
    return {
        "kind": "hysteresis",
        "name": "adhesive friction loop",
        "grid": {"n": n, "size": "0.6 um", "periodic": False},
        "body1": {"E": "100 GPa", "nu": 0.25},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "40 um"}},
        "adhesion": {"model": "dugdale", "work_of_adhesion": "40 mJ/m^2", "z0": "0.2 nm",
                     "discretisation": discretisation},
        "load": {"force": "8 uN"},
        "friction": {"coefficient": 0.25,
                     "path": {"control": "force", "cycles": cycles, "steps": steps, "amplitude": amplitude}},
        "solver": {"method": method},
        "output": {"fields": "none", "figures": False, "report": False},
    }


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--amplitude", type=float, default=0.95)
    ap.add_argument("--method", default="auto", choices=["auto", "polonsky_keer", "normcg"])
    ap.add_argument("--discretisation", default="softened", choices=["softened", "step"])
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)

    import tribobem.solvers.coupling as C
    from tribobem.scenario.run import run_scenario

    # Attribute every inner solve of the coupling loop to its kind (by its tolerance: see
    # solvers/coupling.py for the inexact early passes and the predictor).
    rows = collections.defaultdict(lambda: [0, 0, 0.0])

    def wrap(name, kind_of):
        f = getattr(C, name)

        @functools.wraps(f)
        def timed(*a, **k):
            t0 = time.process_time()
            r = f(*a, **k)
            row = rows[kind_of(k)]
            row[0] += 1
            row[1] += int(getattr(r, "iterations", 0))
            row[2] += time.process_time() - t0
            return r

        setattr(C, name, timed)
        return f

    def normal_kind(k):
        return "normal, run tolerance" if k.get("tol", 0.0) <= tol_run else "normal, inexact pass"

    def tangential_kind(k):
        tol = k.get("tol", 0.0)
        if tol <= tang_run:
            return "tangential, final pass"
        return "tangential, predictor" if tol == max(tang_run, C.PREDICTOR_TOL) else "tangential, inexact pass"

    from tribobem.runs.settings import TANGENTIAL_TOLERANCE

    sc = scenario(args.n, args.cycles, args.steps, args.amplitude, args.method, args.discretisation)
    tol_run = 1e-10  # the scenario default [solver] tolerance
    tang_run = max(tol_run, TANGENTIAL_TOLERANCE)
    originals = (wrap("solve_normal", normal_kind), wrap("solve_tangential", tangential_kind))
    try:
        with tempfile.TemporaryDirectory() as out:
            t0 = time.process_time()
            run_scenario(sc, outdir=out, quiet=True, progress=False)
            cpu = time.process_time() - t0
            with open(f"{out}/summary.json", encoding="utf-8") as fh:
                s = json.load(fh)
    finally:
        C.solve_normal, C.solve_tangential = originals
    steps = s["steps"]
    passes = sum(x["coupling_iterations"] for x in steps)
    result = {"n": args.n, "steps": len(steps), "cpu_s": cpu, "timings": s["timings"],
              "passes_per_step": passes / len(steps), "normal_method": s["problem"].get("normal_method"),
              "loop_energies_J": s["dissipated_energy"],
              "solves": {k: {"solves": v[0], "iterations": v[1], "cpu_s": v[2]} for k, v in sorted(rows.items())}}
    if args.json:
        print(json.dumps(result, indent=2))
        return result
    print(f"{args.n}^2, {len(steps)} steps, normal solver {result['normal_method']}: {cpu:.1f} s CPU "
          f"(solve phase {s['timings']['solve']:.1f} s wall), {result['passes_per_step']:.2f} coupling passes per step")
    print(f"{'inner solve':26s} {'solves':>7s} {'iterations':>10s} {'it/solve':>8s} {'CPU s':>7s}")
    for k, (n, its, t) in sorted(rows.items()):
        print(f"{k:26s} {n:7d} {its:10d} {its / max(n, 1):8.1f} {t:7.1f}")
    print("loop energies (J):", ", ".join(f"{e:.7e}" for e in s["dissipated_energy"]))
    return result


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
