"""Benchmark: a humid force-controlled hysteresis loop against the same dry loop (issue 19).

Requirement: a humid loop (capillary menisci and films acting at every tangential step) costs
at most 2x the CPU time of the same dry loop (3 cycles x 40 steps at 256^2).

The problem: a rigid SiO2 sphere (R = 1 um, SiO2 film) on an elastic Si flat (E = 130 GPa,
nu = 0.28, Si film): dissimilar bodies, so the normal-tangential coupling is active; no Dugdale
adhesion (``adhesion.model = "none"`` in both runs), no van der Waals terms; F0 = 1 uN, mu = 0.3,
free boundary on a 0.3 um square; force control, amplitude 0.9 mu F0+, ``--cycles`` x ``--steps``.
The problem is built once from the scenario (:func:`tribobem.scenario.build.build_problem`) and
the solver-level loop :func:`tribobem.solvers.hysteresis.hysteresis_loop` is timed with the
run's solver settings (those of ``runs/hysteresis.py``), once with the dry law (``pb.interaction``,
the solve window on: the default) and once with the :class:`~tribobem.solvers.capillary.CapillaryModel`
of ``--rh`` (``tribobem.runs.humid_friction.capillary_model``; its film levelling is done before
the clock starts and timed apart).  A humid *run* also runs the dry reference loop by design:
that is not counted here.  A third row times the dry loop without its window
(``window=False``): the part of the ratio that is the window's.

Each variant runs ``--repeats`` times in this process, alternating; the table gives the minimum
CPU (``time.process_time``) and wall time of each.  Set TRIBOBEM_FFT_WORKERS=1 for comparable
CPU times.  ``--profile`` adds a cProfile of one humid loop (top functions by cumulative and own
time).  Not a test: nothing is asserted.  ``--quick``: 96^2, 1 cycle, 16 steps.

    python benchmarks/humid_loop.py [--n 256 --cycles 3 --steps 40 --rh 0.5 --repeats 2] [--profile] [--json]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings


def scenario(n: int, rh: float, cycles: int, steps: int) -> dict:
    """The benchmark's hysteresis scenario (module docstring)."""
    return {
        "kind": "hysteresis",
        "grid": {"n": n, "size": "0.3 um"},
        "body1": {"E": "130 GPa", "nu": 0.28, "film": {"isotherm": "Si"}},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}, "film": {"isotherm": "SiO2"}},
        "load": {"force": "1 uN"},
        "friction": {"coefficient": 0.3,
                     "path": {"control": "force", "amplitude": 0.9, "cycles": cycles, "steps": steps}},
        "humidity": {"rh": [rh], "van_der_waals": False},
        "output": {"fields": "none", "figures": False, "report": False},
    }


def loop_once(pb, interaction, window: bool = True):
    """One solver-level loop with the run's settings; returns (cpu s, wall s, HysteresisRun)."""
    from tribobem.errors import ConvergenceWarning
    from tribobem.runs.settings import SolverSettings
    from tribobem.solvers.hysteresis import hysteresis_loop

    sc = pb.scenario
    path = sc.friction.path
    # the run's tangential and coupling tolerances; the loop's default normal solver (Polonsky-Keer)
    solver_kw = {k: v for k, v in SolverSettings.from_scenario(sc).coupled_kw().items() if k != "normal_method"}
    c0, t0 = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        run = hysteresis_loop(pb.operator, pb.gap, normal_force=sc.load.force,
                              friction_coefficient=float(sc.friction.coefficient), control=path.control,
                              amplitude=path.amplitude, cycles=path.cycles, steps=path.steps,
                              direction=sc.friction.direction, interaction=interaction, window=window,
                              **solver_kw)
    return time.process_time() - c0, time.perf_counter() - t0, run


def _stats(run) -> dict:
    steps = run.steps
    n = len(steps) + 1
    return {"coupled_steps": n,
            "coupling_passes_per_step": sum(s.coupling_iterations for s in steps) / max(len(steps), 1),
            "repulsive_force_uN": run.start.normal.repulsive_force * 1e6,
            "failed_steps": run.failed,
            "window": steps[-1].normal.info.get("window") if steps else None}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--rh", type=float, default=0.5)
    ap.add_argument("--repeats", type=int, default=2, help="runs of each variant (minimum reported)")
    ap.add_argument("--no-unwindowed", action="store_true", help="skip the dry loop without its window")
    ap.add_argument("--profile", action="store_true", help="cProfile one humid loop (after the timings)")
    ap.add_argument("--quick", action="store_true", help="96^2, 1 cycle, 16 steps")
    ap.add_argument("--json", action="store_true", help="print only one JSON line")
    args = ap.parse_args(argv)
    if args.quick:
        args.n, args.cycles, args.steps = 96, 1, 16

    from tribobem.errors import ConvergenceWarning
    from tribobem.runs.humid_friction import capillary_model
    from tribobem.runs.settings import SolverSettings
    from tribobem.scenario.build import build_problem
    from tribobem.scenario.schema import parse_scenario

    pb = build_problem(parse_scenario(scenario(args.n, args.rh, args.cycles, args.steps)))
    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        model, f1, f2 = capillary_model(pb, args.rh, SolverSettings.from_scenario(pb.scenario).film_tolerance)
    film_cpu = time.process_time() - c0
    variants = {"dry": (pb.interaction, True), "humid": (model, True)}
    if not args.no_unwindowed:
        variants["dry, no window"] = (pb.interaction, False)
    best = {k: {"cpu_s": float("inf"), "wall_s": float("inf")} for k in variants}
    for _ in range(max(1, args.repeats)):
        for name, (law, win) in variants.items():
            cpu, wall, run = loop_once(pb, law, win)
            b = best[name]
            if cpu < b["cpu_s"]:
                b.update(cpu_s=cpu, **_stats(run))
            b["wall_s"] = min(b["wall_s"], wall)
    out = {"grid": f"{args.n}^2 free boundary", "cycles": args.cycles, "steps_per_cycle": args.steps, "rh": args.rh,
           "repeats": args.repeats, "film_levelling_cpu_s": film_cpu, "variants": best,
           "ratio_cpu_humid_over_dry": best["humid"]["cpu_s"] / best["dry"]["cpu_s"],
           "ratio_wall_humid_over_dry": best["humid"]["wall_s"] / best["dry"]["wall_s"]}
    if "dry, no window" in best:
        out["ratio_cpu_humid_over_dry_no_window"] = best["humid"]["cpu_s"] / best["dry, no window"]["cpu_s"]
    if args.json:
        print(json.dumps(out))
    else:
        print(f"humid vs dry hysteresis loop: {out['grid']}, {args.cycles} cycles x {args.steps} steps, RH {args.rh:g}, "
              f"min of {args.repeats}")
        print(f"{'variant':16s} {'CPU s':>8s} {'wall s':>8s} {'steps':>6s} {'passes/step':>11s} {'F0+ uN':>8s} window")
        for name, b in best.items():
            print(f"{name:16s} {b['cpu_s']:8.2f} {b['wall_s']:8.2f} {b['coupled_steps']:6d} "
                  f"{b['coupling_passes_per_step']:11.2f} {b['repulsive_force_uN']:8.4f} {b['window']}")
        print(f"CPU ratio humid / dry: {out['ratio_cpu_humid_over_dry']:.2f} (requirement <= 2)"
              + (f"; humid / dry without window: {out['ratio_cpu_humid_over_dry_no_window']:.2f}"
                 if "ratio_cpu_humid_over_dry_no_window" in out else ""))
        print(f"film levelling (once per RH, not in the loop): {film_cpu:.2f} s CPU")
        print(json.dumps(out))
    if args.profile:
        import cProfile
        import io
        import pstats

        prof = cProfile.Profile()
        prof.enable()
        loop_once(pb, model, True)
        prof.disable()
        for key in ("cumulative", "tottime"):
            s = io.StringIO()
            pstats.Stats(prof, stream=s).sort_stats(key).print_stats(25)
            print(f"--- humid loop, top 25 by {key} ---")
            print(s.getvalue())
    return out


if __name__ == "__main__":
    main(sys.argv[1:])
