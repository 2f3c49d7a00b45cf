"""Benchmark: capillary adhesion speed targets (issue 8 item 8).

1. The equilibrium water film on 256^2 (target: at most 5 s): the SiO2 film levelled on the
   Paper B rough surface (Gaussian, rms 5 nm, L_ac/L = 0.02, 10 um periodic cell) at RH 0.5
   and 0.9, open system (:func:`tribobem.interactions.films.film_thickness`), timed by the
   films' own benchmark ``benchmarks/capillary_films.py`` (its ``main``; a local copy of the
   same measurement when that file is absent).
2. A 10-value RH sweep of the Paper B rough interface at 256^2 (target: within 2 minutes):
   the ``capillary`` run of :func:`studies.paper_b.base_scenario` (elastic SiO2 on a
   rigid dry flat, 500 uN, Dugdale 88 mJ/m^2 / 0.3 nm, equilibrium films) at RH 0.1, 0.2, ...,
   0.9, 0.95, through :func:`tribobem.scenario.run_scenario` (no files written).

Prints wall and CPU time (``time.process_time``: the machine may be shared, CPU time is the
steadier number; it counts every FFT thread), Newton iterations of the films, and per RH the
outer (island) iterations, the normal solver's iterations and the capillary force.  Not a test:
nothing is asserted.  ``python benchmarks/capillary.py [--n 256] [--json out.json]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))

RH_SWEEP = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
FILM_TARGET = 5.0
SWEEP_TARGET = 120.0


def film_benchmark(n: int = 256, rh_values=(0.5, 0.9)) -> list[dict]:
    """Time the equilibrium film of the Paper B surface on ``n`` x ``n`` cells (open system)."""
    import importlib.util

    films_bench = Path(__file__).resolve().parent / "capillary_films.py"
    if films_bench.exists():  # the films' own benchmark: same surface, its table printed
        spec = importlib.util.spec_from_file_location("capillary_films", films_bench)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        rows = mod.main(["--n", str(n), "--rh", *[str(r) for r in rh_values], "--systems", "open"])
        return [{"n": n, "rh": r["rh"], "wall": r["wall_s"], "cpu": r["cpu_s"], "newton": r["iterations"],
                 "converged": r["converged"], "relative_ptp": r["max"] - r["min"], "message": r["message"]}
                for r in rows]
    return _film_benchmark_local(n, rh_values)


def _film_benchmark_local(n: int, rh_values) -> list[dict]:
    import numpy as np

    from tribobem.geometry import gaussian_surface
    from tribobem.grid import Grid
    from tribobem.interactions.films import film_thickness
    from studies.paper_b import LAC_RATIOS, RMS, SIZE

    grid = Grid(n, n, SIZE, SIZE, True)
    h = gaussian_surface(grid, RMS, LAC_RATIOS[0] * SIZE, seed=1)
    out = []
    for rh in rh_values:
        w0, c0 = time.perf_counter(), time.process_time()
        res = film_thickness(h, grid, "SiO2", rh, mode="equilibrium", system="open")
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        out.append({"n": n, "rh": rh, "wall": wall, "cpu": cpu, "newton": res.iterations, "converged": res.converged,
                    "relative_ptp": float(np.ptp(res.thickness)) / res.mean_thickness, "message": res.message})
    return out


def sweep_benchmark(n: int = 256, rh_values=RH_SWEEP) -> dict:
    """Time the RH sweep of the Paper B rough interface (one ``capillary`` run)."""
    from tribobem.scenario import run_scenario
    from studies.paper_b import base_scenario

    scn = base_scenario()
    scn["grid"]["n"] = n
    scn["humidity"]["rh"] = list(rh_values)
    scn["output"] = {"fields": "none", "figures": False, "report": False}
    w0, c0 = time.perf_counter(), time.process_time()
    r = run_scenario(scn, progress=False, quiet=True)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    steps = [{k: st.get(k) for k in ("rh", "capillary_force", "solid_solid_force", "water_solid_force", "wetted_area",
                                     "island_count", "outer_iterations", "iterations", "inner_iterations",
                                     "film_iterations_1", "converged")} for st in r.steps]
    return {"n": n, "wall": wall, "cpu": cpu, "timings": r.summary["timings"], "steps": steps,
            "converged": r.converged}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--no-sweep", action="store_true", help="only the film benchmark")
    ap.add_argument("--json", type=Path, default=None, help="also write the numbers to this file")
    args = ap.parse_args(argv)

    films = film_benchmark(args.n)
    print(f"## Equilibrium film on {args.n}^2 (target <= {FILM_TARGET:g} s)\n")
    print("| RH | wall (s) | CPU (s) | Newton | converged | (e_max - e_min) / e_iso |")
    print("|---|---|---|---|---|---|")
    for f in films:
        print(f"| {f['rh']:g} | {f['wall']:.2f} | {f['cpu']:.2f} | {f['newton']} | {f['converged']} | "
              f"{f['relative_ptp']:.3g} |")
    out = {"films": films}
    if not args.no_sweep:
        sw = sweep_benchmark(args.n)
        out["sweep"] = sw
        print(f"\n## {len(sw['steps'])}-value RH sweep of the Paper B interface on {args.n}^2 "
              f"(target <= {SWEEP_TARGET:g} s)\n")
        print(f"wall {sw['wall']:.1f} s, CPU {sw['cpu']:.1f} s (build {sw['timings']['build']:.1f} s, solve "
              f"{sw['timings']['solve']:.1f} s); all converged: {sw['converged']}\n")
        print("| RH | F_cap (uN) | F_ss (uN) | F_ws (uN) | meniscus (um^2) | islands | outer it. "
              "| last normal solve it. | film Newton |")
        print("|---|---|---|---|---|---|---|---|---|")
        for s in sw["steps"]:
            inner = s.get("inner_iterations") if s.get("inner_iterations") is not None else s.get("iterations")
            print(f"| {s['rh']:g} | {s['capillary_force'] * 1e6:.4g} | {s['solid_solid_force'] * 1e6:.4g} | "
                  f"{s['water_solid_force'] * 1e6:.4g} | {s['wetted_area'] * 1e12:.4g} | {s['island_count']} | "
                  f"{s['outer_iterations']} | {inner} | {s['film_iterations_1']} |")
    if args.json:
        args.json.write_text(json.dumps(out, indent=1, default=str) + "\n", encoding="utf-8")
    return out


if __name__ == "__main__":
    main()
    sys.exit(0)
