"""Iterations of the normal solvers: Polonsky-Keer (solve_normal) vs NormCG (solve_normal_cg).

Issue 9 item 8: Polonsky-Keer needs 150-200 iterations at 1024^2 on the benchmark surface and
the count grows with the grid; Vollebregt's bound-constrained CG with an FFT preconditioner
(solvers/normal_cg.py) should keep it nearly flat (target <= 60 at 1024^2 and 2048^2) with
identical contact areas.

Problems (one process, same operator and surface for both solvers):

* non-adhesive: the surface and load of normal_vs_tamaas.py (periodic self-affine, H = 0.8,
  spectral rms slope 1, E = 1, nu = 0.3, mean pressure 0.01 E*, force control), tol 1e-10;
  the contact node counts must be IDENTICAL (the script says so when they are not);
* adhesive (``--adhesive-sizes``, default 256-1024): the Dugdale problem of
  adhesion_vs_tamaas.py (z0 = rms/10, sigma0 = 0.1 E*, displacement control at a mean gap of
  2 rms), tol 1e-10.  This problem is not convex: the two solvers may stop at different valid
  equilibria; the table gives both forces, contact and cohesive-zone node counts, the
  violation of the Dugdale conditions and the total potential energy (lower = more stable).

Reported: iterations, FFT convolutions where counted, CPU time (``time.process_time``, the
minimum over ``--repeats`` interleaved runs) and its ratio NormCG / Polonsky-Keer.  Set
``TRIBOBEM_FFT_WORKERS=1`` for a one-thread A/B comparison; on a shared machine report CPU
times and ratios, not wall times.

    python benchmarks/normal_iterations.py                   # 256 .. 2048, adhesive 256 .. 1024
    python benchmarks/normal_iterations.py --quick           # 256, 512; adhesive 256
    python benchmarks/normal_iterations.py --sizes 1024 --adhesive-sizes --json out.json
"""

from __future__ import annotations

import json
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import adhesion_vs_tamaas as adh  # noqa: E402
import common  # noqa: E402
from common import E_STAR, L, Samples, markdown_table, timed  # noqa: E402

MEAN_PRESSURE = 0.01 * E_STAR
TOL = 1e-10
MAX_ITERATIONS = 20000
METHODS = ("polonsky_keer", "normcg")


def _solver(method):
    from tribobem.solvers.normal import solve_normal
    from tribobem.solvers.normal_cg import solve_normal_cg

    return solve_normal if method == "polonsky_keer" else solve_normal_cg


def warm_up(op):
    """Plan the FFTs and build the preconditioner before timing (kernel spectra are built
    with the operator too): both solvers are then timed on warm caches."""
    from tribobem.solvers.normal_cg import fft_preconditioner

    common.time_apply(op, repeats=1)
    fft_preconditioner(op).apply(np.zeros(op.grid.shape))


def run(method, op, h, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wall, cpu, res = timed(_solver(method), op, h, tol=TOL, max_iterations=MAX_ITERATIONS, **kw)
    return wall, cpu, res


def bench_normal(n, args):
    s, gen = common.make_surface(n)
    h = s.max() - s
    op = common.tribobem_operator(n, args.workers)
    warm_up(op)
    samples = {m: Samples() for m in METHODS}
    results = {}
    for r in range(args.repeats):
        for m in (METHODS if r % 2 == 0 else METHODS[::-1]):
            wall, cpu, res = run(m, op, h, force=MEAN_PRESSURE * L * L)
            samples[m].add(wall, cpu, {})
            results[m] = res
    pk, cg = results["polonsky_keer"], results["normcg"]
    return {
        "n": n, "generator": gen,
        **{f"{m}_iterations": results[m].iterations for m in METHODS},
        **{f"{m}_converged": results[m].converged for m in METHODS},
        **{f"{m}_contact_nodes": int(np.count_nonzero(results[m].contact)) for m in METHODS},
        **{f"{m}_cpu": samples[m].cpu for m in METHODS},
        **{f"{m}_wall": samples[m].times for m in METHODS},
        "normcg_convolutions": cg.info.get("convolutions"),
        "normcg_set_changes": cg.info.get("set_changes"),
        "mask_mismatch": int(np.count_nonzero(pk.contact != cg.contact)),
        "pressure_max_diff": float(np.abs(pk.pressure - cg.pressure).max() / pk.pressure.max()),
        "approach_rel_diff": abs(cg.approach - pk.approach) / abs(pk.approach),
        "cpu_ratio": samples["normcg"].best_cpu / samples["polonsky_keer"].best_cpu,
    }


def bench_adhesive(n, args):
    from tribobem.interactions.dugdale import DugdaleAdhesion

    s, gen = common.make_surface(n)
    h = s.max() - s
    prm = adh.parameters(s)
    law = DugdaleAdhesion(prm["dgamma"], prm["z0"])
    op = common.tribobem_operator(n, args.workers)
    warm_up(op)
    samples = {m: Samples() for m in METHODS}
    results = {}
    for r in range(args.repeats):
        for m in (METHODS if r % 2 == 0 else METHODS[::-1]):
            wall, cpu, res = run(m, op, h, approach=prm["approach"], interaction=law)
            samples[m].add(wall, cpu, {})
            results[m] = res
    out = {"n": n, "generator": gen, "cpu_ratio": samples["normcg"].best_cpu / samples["polonsky_keer"].best_cpu}
    for m in METHODS:
        res = results[m]
        chk = adh.dugdale_check(op, h, res.pressure, prm)
        out[m] = {"iterations": res.iterations, "converged": res.converged, "cpu": samples[m].cpu,
                  "wall": samples[m].times, "force": res.force, "contact_nodes": int(np.count_nonzero(res.contact)),
                  "cohesive_nodes": int(np.count_nonzero(res.adhesive)), "energy": chk["energy"],
                  "violation": max(chk["cohesive_stress_err"], chk["outside_stress_err"],
                                   float(chk["contact_below_floor"]), max(0.0, -chk["min_gap_over_h0"])),
                  "convolutions": res.info.get("convolutions")}
    return out


def main(argv=None) -> int:
    parser = common.base_parser(__doc__.splitlines()[0], [256, 512, 1024, 2048])
    parser.add_argument("--adhesive-sizes", type=int, nargs="*", default=[256, 512, 1024],
                        help="grid sizes of the adhesive (Dugdale) problem; none to skip it")
    parser.add_argument("--json", help="write the measured numbers to this file")
    args = parser.parse_args(argv)
    if args.quick:
        args.sizes = [n for n in args.sizes if n <= 512] or [256]
        args.adhesive_sizes = [n for n in args.adhesive_sizes if n <= 256]
        args.repeats = 1
    print("## Normal solver iterations: Polonsky-Keer vs NormCG (preconditioned bound-constrained CG)\n")
    print(common.environment())
    from tribobem.elasticity.backend import default_fft

    print(f"FFT engine {default_fft()}; workers {args.workers or 'default'}; tol {TOL:g}; "
          f"repeats {args.repeats} (minimum CPU time reported; runs interleaved)\n", flush=True)

    normal = []
    for n in args.sizes:
        r = bench_normal(n, args)
        normal.append(r)
        print(f"n={n}: PK {r['polonsky_keer_iterations']} it, {min(r['polonsky_keer_cpu']):.2f} s CPU; "
              f"NormCG {r['normcg_iterations']} it, {min(r['normcg_cpu']):.2f} s CPU; contact nodes "
              f"{r['polonsky_keer_contact_nodes']} / {r['normcg_contact_nodes']}", flush=True)
    if normal:
        print("\n### Non-adhesive, force control (mean pressure 0.01 E*)\n")
        headers = ["n", "PK it", "NormCG it", "NormCG convolutions", "PK CPU s", "NormCG CPU s", "CPU ratio NormCG/PK",
                   "contact nodes PK", "contact nodes NormCG", "identical", "max |dp| / max p", "converged"]
        rows = [[r["n"], r["polonsky_keer_iterations"], r["normcg_iterations"], r["normcg_convolutions"],
                 min(r["polonsky_keer_cpu"]), min(r["normcg_cpu"]), r["cpu_ratio"],
                 r["polonsky_keer_contact_nodes"], r["normcg_contact_nodes"],
                 "yes" if r["mask_mismatch"] == 0 else f"NO ({r['mask_mismatch']} nodes differ)",
                 r["pressure_max_diff"], f"{r['polonsky_keer_converged']}/{r['normcg_converged']}"] for r in normal]
        print(markdown_table(headers, rows))

    adhesive = []
    for n in args.adhesive_sizes:
        r = bench_adhesive(n, args)
        adhesive.append(r)
        print(f"adhesive n={n}: PK {r['polonsky_keer']['iterations']} it, NormCG {r['normcg']['iterations']} it",
              flush=True)
    if adhesive:
        print("\n### Dugdale adhesion, displacement control (mean gap 2 rms)\n")
        headers = ["n", "PK it", "NormCG it", "PK CPU s", "NormCG CPU s", "CPU ratio", "force PK", "force NormCG",
                   "contact PK", "contact NormCG", "cohesive PK", "cohesive NormCG", "energy PK",
                   "(E_NormCG - E_PK) / |E_PK|",
                   "max violation PK / NormCG"]
        rows = []
        for r in adhesive:
            a, b = r["polonsky_keer"], r["normcg"]
            rows.append([r["n"], a["iterations"], b["iterations"], min(a["cpu"]), min(b["cpu"]), r["cpu_ratio"],
                         a["force"], b["force"], a["contact_nodes"], b["contact_nodes"], a["cohesive_nodes"],
                         b["cohesive_nodes"], a["energy"], (b["energy"] - a["energy"]) / abs(a["energy"]),
                         f"{a['violation']:.1e} / {b['violation']:.1e}"])
        print(markdown_table(headers, rows))

    bad = [r["n"] for r in normal if r["mask_mismatch"]]
    if bad:
        print(f"\nWARNING: contact node sets differ at n = {bad}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"normal": normal, "adhesive": adhesive}, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
