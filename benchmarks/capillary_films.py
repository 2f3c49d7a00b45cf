"""Benchmark: the equilibrium water film on a Paper-B-like rough SiO2 surface (issue 8).

The problem (Paper B Sec. 4.2): a Gaussian rough surface (exponential ACF, Hu-Tonder filter,
``tribobem.geometry.gaussian_surface``), 10 x 10 um, 256^2 periodic, rms 5 nm, correlation
length L_ac = 0.02 L = 200 nm (``--lac`` changes the ratio), seed 1, carrying the shipped
(approximate) SiO2 isotherm; the equilibrium film (``film_thickness(mode="equilibrium")``) in
the open and the closed system at RH 0.3, 0.6 and 0.9.

Prints one row per (RH, system): wall time, CPU time (``time.process_time``: all threads of
the process, so on a shared machine it is the better number), Newton iterations, CG iterations,
the film's min / mean / max over the isotherm thickness, the mean of the film on the highest
and the lowest 5 % of the nodes, and the residual. Not a test: nothing is asserted. Run
``python benchmarks/capillary_films.py [--n 256 --lac 0.02 --mode equilibrium --json]``;
``--steep`` runs a much harder, unphysically steep surface (64 nm window, 0.5 nm cells,
rms 3 nm, L_ac 5 nm) to show the solver's behaviour when films are squeezed to the floor.

Thin-film row (issue 21 item 3): ``--mode thin_film --lac 0.05 --rh 0.5 0.9 --systems closed``
times the thin-film levelling (closed system, with the disjoining pressure so that it has a
steady state to stop at; "Newton" is then the number of accepted ROS2 steps) on Paper B's
surface; results in benchmarks/README.md.  Paper B's own form, without the disjoining pressure,
is not timed: on this surface it does not finish (``film_thickness`` Notes).
"""

from __future__ import annotations

import argparse
import json
import re
import time
import warnings

import numpy as np


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--size", type=float, default=10e-6, help="side length, m")
    ap.add_argument("--rms", type=float, default=5e-9, help="rms height, m")
    ap.add_argument("--lac", type=float, default=0.02, help="correlation length / side length")
    ap.add_argument("--rh", type=float, nargs="+", default=[0.3, 0.6, 0.9])
    ap.add_argument("--systems", nargs="+", default=["open", "closed"])
    ap.add_argument("--mode", default="equilibrium", choices=["equilibrium", "thin_film", "uniform"])
    ap.add_argument("--steep", action="store_true", help="64 nm window, 128^2, rms 3 nm, L_ac 5 nm")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.steep:
        args.n, args.size, args.rms, args.lac = 128, 64e-9, 3e-9, 5e-9 / 64e-9

    from tribobem.elasticity.backend import default_workers
    from tribobem.geometry import gaussian_surface
    from tribobem.grid import Grid
    from tribobem.interactions.films import film_thickness
    from tribobem.interactions.isotherms import SIO2

    grid = Grid.square(args.n, args.size, periodic=True)
    hs = gaussian_surface(grid, args.rms, args.lac * args.size, seed=args.seed)
    top = hs >= np.quantile(hs, 0.95)
    bottom = hs <= np.quantile(hs, 0.05)
    print(f"# {args.n}^2, {args.size * 1e6:g} um, rms {args.rms * 1e9:g} nm, L_ac {args.lac * args.size * 1e9:g} nm, "
          f"SiO2 isotherm, mode {args.mode}, {default_workers()} FFT workers (shared machine: CPU time is the fairer number)")
    print("| RH | system | wall s | CPU s | Newton | CG | e_min/e_iso | e_mean/e_iso | e_max/e_iso | "
          "e(top 5%)/e_iso | e(bottom 5%)/e_iso | residual | converged |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for rh in args.rh:
        for system in args.systems:
            if args.mode == "thin_film" and system == "open":
                continue
            e_iso = SIO2.thickness(rh)
            w0, c0 = time.perf_counter(), time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                # thin_film: with the disjoining pressure, so that it has a steady state to stop at
                extra = {"disjoining": True} if args.mode == "thin_film" else {}
                res = film_thickness(hs, grid, SIO2, rh, mode=args.mode, system=system, **extra)
            wall, cpu = time.perf_counter() - w0, time.process_time() - c0
            m = re.search(r"\((\d+) CG", res.message)
            row = {
                "rh": rh, "system": system, "wall_s": wall, "cpu_s": cpu, "iterations": res.iterations,
                "cg_iterations": int(m.group(1)) if m else None,
                "min": float(res.thickness.min() / e_iso), "mean": float(res.mean_thickness / e_iso),
                "max": float(res.thickness.max() / e_iso), "top": float(res.thickness[top].mean() / e_iso),
                "bottom": float(res.thickness[bottom].mean() / e_iso), "residual": res.residual,
                "converged": res.converged, "message": res.message,
            }
            rows.append(row)
            print(f"| {rh:g} | {system} | {wall:.2f} | {cpu:.2f} | {res.iterations} | {row['cg_iterations']} | "
                  f"{row['min']:.4f} | {row['mean']:.6f} | {row['max']:.4f} | {row['top']:.4f} | {row['bottom']:.4f} | "
                  f"{res.residual:.1e} | {res.converged} |")
    if args.json:
        print(json.dumps(rows, indent=1))
    return rows


if __name__ == "__main__":
    main()
