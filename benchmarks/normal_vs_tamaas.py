"""Non-adhesive periodic rough contact: tribobem vs Tamaas, in one process.

Problem (issue 7): periodic self-affine surface (Hurst 0.8, spectral rms slope 1,
see common.py), elastic half-space E = 1, nu = 0.3 against it, mean pressure 0.01 E*,
force control.  Tamaas: ``PolonskyKeerRey`` with pressure primal and constraint, tol 1e-10.
tribobem: ``solve_normal(op, h, force=0.01 E* L^2, tol=...)`` on the periodic spectral
operator, with h = max(s) - s.

Timing is interleaved (Tamaas, tribobem, tribobem, Tamaas, ...) and the minimum of the
repeats is reported, because the machine may be shared.  Equal accuracy: the contact
areas (node counts) must agree to 1e-6 relative; if they do not at tribobem tol 1e-10,
tighter tolerances are tried and the first one that agrees is the one timed.

    python benchmarks/normal_vs_tamaas.py                  # 256 .. 2048, 3 repeats
    python benchmarks/normal_vs_tamaas.py --quick          # 256, 512, 1 repeat
    python benchmarks/normal_vs_tamaas.py --sizes 1024 --repeats 5 --serial

Always exits 0 when it ran (without Tamaas it times tribobem alone).
"""

from __future__ import annotations

import json
import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import E_STAR, L, Samples, markdown_table, timed  # noqa: E402

MEAN_PRESSURE = 0.01 * E_STAR
TAMAAS_TOL = 1e-10
TRIBOBEM_TOLS = (1e-10, 1e-11, 1e-12, 1e-13, 1e-14)
AREA_RTOL = 1e-6
MAX_ITERATIONS = 10000
METHOD = "polonsky_keer"  # --method: solve_normal's method (polonsky_keer | normcg)


def run_tamaas(s: np.ndarray, n: int) -> tuple[float, float, dict]:
    tm = common.tm
    model = common.tamaas_model(n)
    solver = tm.PolonskyKeerRey(model, s, TAMAAS_TOL, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure)
    solver.max_iter = MAX_ITERATIONS
    with common.capture_fd1() as log:
        wall, cpu, err = timed(solver.solve, MEAN_PRESSURE)
    p = np.array(model.traction, dtype=float, copy=True).reshape(n, n)
    return wall, cpu, {
        "iterations": common.tamaas_iterations(log["text"]),
        "error": err,
        "pressure": p,
        "contact_nodes": int(np.count_nonzero(p > 0)),
        "mean_pressure": float(p.mean()),
    }


def run_tribobem(op, h: np.ndarray, tol: float) -> tuple[float, float, dict]:
    from tribobem.solvers.normal import solve_normal

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wall, cpu, res = timed(solve_normal, op, h, force=MEAN_PRESSURE * L * L, tol=tol,
                               max_iterations=MAX_ITERATIONS, method=METHOD)
    return wall, cpu, {
        "iterations": res.iterations,
        "converged": res.converged,
        "pressure": res.pressure,
        "contact_nodes": int(np.count_nonzero(res.contact)),
        "mean_pressure": res.force / (L * L),
        "solver_time": res.time,
    }


def rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b) if b else (0.0 if a == b else math.inf)


def bench_size(n: int, args, use_tamaas: bool) -> dict:
    s, gen = common.make_surface(n)
    h = s.max() - s
    op = common.tribobem_operator(n, args.workers)
    op_serial = common.tribobem_operator(n, 1) if args.serial else None
    t_apply = common.time_apply(op)
    t_apply_serial = common.time_apply(op_serial) if op_serial is not None else math.nan

    tam, tri, tri1 = Samples(), Samples(), Samples()
    out = {"n": n, "generator": gen, "t_apply": t_apply, "t_apply_serial": t_apply_serial}

    # Round 0: accuracy (and first timing sample); find the tribobem tolerance that matches.
    tol = TRIBOBEM_TOLS[0]
    tri_at_1e10 = None
    if use_tamaas:
        tam.add(*run_tamaas(s, n))
        ref = tam.info
        for tol in TRIBOBEM_TOLS:
            wall, cpu, info = run_tribobem(op, h, tol)
            if tri_at_1e10 is None:
                tri_at_1e10 = info
            if rel(info["contact_nodes"], ref["contact_nodes"]) <= AREA_RTOL:
                break
        tri.add(wall, cpu, info)
    else:
        tri.add(*run_tribobem(op, h, tol))
        tri_at_1e10 = tri.info
    if op_serial is not None:
        tri1.add(*run_tribobem(op_serial, h, tol))

    # Further rounds, alternating the order.
    for r in range(1, args.repeats):
        order = ["tribobem", "serial", "tamaas"] if r % 2 else ["tamaas", "serial", "tribobem"]
        for who in order:
            if who == "tamaas" and use_tamaas:
                tam.add(*run_tamaas(s, n))
            elif who == "tribobem":
                tri.add(*run_tribobem(op, h, tol))
            elif who == "serial" and op_serial is not None:
                tri1.add(*run_tribobem(op_serial, h, tol))

    out.update(tol=tol, tribobem=tri, tribobem_serial=tri1, tamaas=tam if use_tamaas else None,
               tribobem_at_1e10=tri_at_1e10)
    if use_tamaas:
        pt, pb = tam.info["pressure"], tri.info["pressure"]
        out["area_rel_diff_1e10"] = rel(tri_at_1e10["contact_nodes"], tam.info["contact_nodes"])
        out["area_rel_diff"] = rel(tri.info["contact_nodes"], tam.info["contact_nodes"])
        out["pressure_max_diff"] = float(np.abs(pb - pt).max() / pt.max())
        out["mask_mismatch"] = int(np.count_nonzero((pb > 0) != (pt > 0)))
        out["force_rel_diff"] = rel(tri.info["mean_pressure"], tam.info["mean_pressure"])
    return out


def main(argv=None) -> int:
    parser = common.base_parser(__doc__.splitlines()[0], [256, 512, 1024, 2048])
    parser.add_argument("--json", help="write the measured numbers to this file")
    parser.add_argument("--method", default="polonsky_keer", choices=["polonsky_keer", "normcg"],
                        help="tribobem's normal solver (solve_normal method)")
    args = parser.parse_args(argv)
    global METHOD
    METHOD = args.method
    if args.quick:
        args.sizes = [n for n in args.sizes if n <= 512] or [256]
        args.repeats = 1
        args.no_memory = True
    use_tamaas = common.HAVE_TAMAAS and not args.no_tamaas
    if not common.HAVE_TAMAAS:
        print("NOTICE: tamaas is not installed (pip install tamaas); timing tribobem only, "
              "on a NumPy-generated surface with the same PSD.")
    print("## Normal contact, periodic self-affine surface: tribobem vs Tamaas\n")
    print(common.environment())
    print(f"Problem: H = {common.HURST}, q0 = q1 = {common.Q0}, q2 = n/4, spectral rms slope "
          f"{common.RMS_SLOPE}, E = {common.E}, nu = {common.NU}, mean pressure 0.01 E*; "
          f"Tamaas tol {TAMAAS_TOL:g}; tribobem method {METHOD}; repeats {args.repeats} (min reported)\n", flush=True)

    results = []
    for n in args.sizes:
        r = bench_size(n, args, use_tamaas)
        results.append(r)
        tri, tam = r["tribobem"], r["tamaas"]
        t_iter = tri.best / tri.info["iterations"]
        line = (f"n={n}: tribobem {tri.best:.3f} s ({tri.info['iterations']} it, tol {r['tol']:g})"
                f", t_iter/(2 t_apply) = {t_iter / (2 * r['t_apply']):.2f}")
        if tam is not None:
            line += (f"; Tamaas {tam.best:.3f} s ({tam.info['iterations']} it); ratio {tri.best / tam.best:.3f}"
                     f"; contact nodes {tri.info['contact_nodes']} vs {tam.info['contact_nodes']}")
        print(line, flush=True)

    mem = {}
    if not args.no_memory:
        for r in results:
            n = r["n"]
            params = {"mean_pressure": MEAN_PRESSURE, "tol": r["tol"], "workers": args.workers}
            mem[("tribobem", n)] = common.run_memory_probe("tribobem", "normal", n, params)
            if use_tamaas:
                mem[("tamaas", n)] = common.run_memory_probe("tamaas", "normal", n, dict(params, tol=TAMAAS_TOL))

    # ---- tables -------------------------------------------------------------------
    print("\n### Time (minimum over repeats)\n")
    headers = ["n", "contact fraction", "Tamaas s", "Tamaas it", "tribobem s", "tribobem it", "tribobem tol",
               "ratio tribobem/Tamaas"]
    if args.serial:
        headers += ["tribobem 1 worker s", "ratio (1 worker)"]
    headers += ["CPU s Tamaas", "CPU s tribobem", "CPU ratio", "tribobem ms/it", "apply ms", "ms/it / (2 apply)",
                "CPU/wall tribobem", "CPU/wall Tamaas"]
    rows = []
    for r in results:
        tri, tam, tri1 = r["tribobem"], r["tamaas"], r["tribobem_serial"]
        it = tri.info["iterations"]
        row = [r["n"], tri.info["contact_nodes"] / r["n"] ** 2,
               tam.best if tam else math.nan, tam.info["iterations"] if tam else None,
               tri.best, it, f"{r['tol']:g}", tri.best / tam.best if tam else math.nan]
        if args.serial:
            row += [tri1.best, tri1.best / tam.best if tam else math.nan]
        row += [tam.best_cpu if tam else math.nan, tri.best_cpu, tri.best_cpu / tam.best_cpu if tam else math.nan,
                1e3 * tri.best / it, 1e3 * r["t_apply"], tri.best / it / (2 * r["t_apply"]),
                tri.cpu_per_wall, tam.cpu_per_wall if tam else math.nan]
        rows.append(row)
    print(markdown_table(headers, rows))

    if use_tamaas:
        print("\n### Accuracy (contact area = contact node count)\n")
        headers = ["n", "Tamaas nodes", "tribobem nodes @1e-10", "rel. diff @1e-10", "tribobem tol used",
                   "rel. diff @tol used", "max |p_tri - p_tam| / max p", "nodes differing", "mean p rel. diff"]
        rows = [[r["n"], r["tamaas"].info["contact_nodes"], r["tribobem_at_1e10"]["contact_nodes"],
                 r["area_rel_diff_1e10"], f"{r['tol']:g}", r["area_rel_diff"], r["pressure_max_diff"],
                 r["mask_mismatch"], r["force_rel_diff"]] for r in results]
        print(markdown_table(headers, rows))

    if mem:
        print("\n### Peak memory of one solve (fresh process; MiB and in n^2 float64 arrays)\n")
        headers = ["n", "one grid array MiB", "Tamaas peak RSS increase MiB", "(arrays)",
                   "tribobem peak RSS increase MiB", "(arrays)", "tribobem NumPy peak (tracemalloc) MiB", "(arrays)"]
        rows = []
        for r in results:
            n = r["n"]
            mt, mb = mem.get(("tamaas", n)), mem.get(("tribobem", n))
            rows.append([n, n * n * 8 / 2**20,
                         mt["rss_delta_mib"] if mt else math.nan, mt["rss_delta_grids"] if mt else math.nan,
                         mb["rss_delta_mib"] if mb else math.nan, mb["rss_delta_grids"] if mb else math.nan,
                         mb["traced_peak_mib"] if mb else math.nan, mb["traced_peak_grids"] if mb else math.nan])
        print(markdown_table(headers, rows))

    if args.json:
        dump = []
        for r in results:
            d = {k: v for k, v in r.items() if k not in ("tribobem", "tribobem_serial", "tamaas", "tribobem_at_1e10")}
            for k in ("tribobem", "tribobem_serial", "tamaas"):
                smp = r[k]
                if smp is not None and smp.times:
                    d[k] = {"times": smp.times, "cpu": smp.cpu,
                            **{kk: vv for kk, vv in smp.info.items() if kk != "pressure"}}
            d["memory"] = {c: mem.get((c, r["n"])) for c in ("tribobem", "tamaas")}
            dump.append(d)
        with open(args.json, "w") as f:
            json.dump(dump, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
