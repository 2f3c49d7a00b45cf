"""Whole burl at asperity resolution (issue 20 item 3, CPU part).

A rigid crowned burl (flat top of radius 30 um, edge radius 500 um, crown 0.5 m) pressed with
0.025 N on an elastic Si wafer (130 GPa, nu 0.28) whose surface carries a 2 nm rms self-affine
roughness (Hurst 0.8, roll-off 10 um, short cutoff 80 nm = 4 cells), on a free-boundary 82 um window
(n = 4096: 20 nm cells).  The burl's flat top carries the load: the crown drops 0.9 nm over the
top, against a punch approach of ~3 nm, and the rounded edge rises 3 nm within 1.7 um of it.

Each size runs in a fresh subprocess (so that the peak resident set, ``ru_maxrss``, is that
run's) and prints: iterations, FFT convolutions (and per iteration), CPU time of the solve
(``time.process_time``, all threads), its wall time, the CPU time of building the problem,
the process's peak RSS, contact nodes, the approach and the force balance.

    python benchmarks/burl_whole.py --n 1024 2048          # normal solves (NormCG)
    python benchmarks/burl_whole.py --n 4096               # the target: <= 5 min CPU, <= 3 GB
    python benchmarks/burl_whole.py --n 1024 --coarse 0    # cold start (no coarse-grid start)
    python benchmarks/burl_whole.py --n 1024 --tracemalloc # + tracemalloc peak of the solve
    python benchmarks/burl_whole.py --ramp                 # partial-slip ramp at 2048^2 (default method)
    python benchmarks/burl_whole.py --ramp --method polonsky_keer   # the same with Polonsky-Keer
    python benchmarks/burl_whole.py --ramp --onset-by force         # onset probes in force control
    python benchmarks/burl_whole.py --n 1024 --json out.json
    python benchmarks/burl_whole.py --n 4096 8192 --solver auto   # candidate-set solves (default)
    python benchmarks/burl_whole.py --n 4096 --solver whole       # the whole grid in double precision

``--coarse L`` passes ``coarse_levels=L`` to ``solve_normal_cg`` (default: its own choice);
``--compare`` also solves cold and reports the largest pressure difference and whether the
contact node sets are identical.  ``--threads T`` sets ``TRIBOBEM_FFT_WORKERS`` in the child.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import warnings


def scenario(n: int, ramp: bool = False) -> dict:
    """The burl scenario on an n x n free-boundary grid (82 um)."""
    sc = {
        "kind": "partial_slip" if ramp else "normal",
        "name": f"whole burl {n}^2",
        "grid": {"n": n, "size": "82 um", "periodic": False},
        "body1": {"name": "silicon wafer", "E": "130 GPa", "nu": 0.28,
                  "roughness": {"kind": "self_affine", "hurst": 0.8, "rms": "2 nm", "rolloff": "10 um",
                                "short_cutoff": "80 nm", "seed": 1}},
        "body2": {"rigid": True, "shape": {"kind": "burl", "radius": "30 um", "edge_radius": "500 um",
                                           "crown": "0.5 m"}},
        "load": {"force": "0.025 N"},
        "solver": {"method": "normcg", "tolerance": 1e-10},
    }
    if ramp:
        sc["friction"] = {"coefficient": 0.3,
                          "tangential_forces": {"start": "0 N", "stop": "0.0075 N", "num": 11}}
        sc["solver"] = {"tolerance": 1e-10}  # method: the caller's (default auto = normcg here)
    return sc


def _rss_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / 1e9  # Linux: kB


def _status_bytes(key: str) -> int:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _reset_peak() -> int:
    """Reset the peak resident set to the current one (Linux ``clear_refs``); the current RSS in
    bytes (0 where it cannot be read)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        return 0
    return _status_bytes("VmRSS")


def _vm_hwm() -> int:
    return _status_bytes("VmHWM")


def child_normal(n: int, coarse, compare: bool, trace: bool, solver: str = "auto") -> dict:
    import numpy as np

    from tribobem.scenario import build_problem, parse_scenario
    from tribobem.solvers.normal_cg import solve_normal_cg

    c0, w0 = time.process_time(), time.perf_counter()
    pb = build_problem(parse_scenario(scenario(n)))
    op = pb.operator.normal
    from tribobem.solvers.normal_cg import fft_preconditioner
    if solver == "whole":
        fft_preconditioner(op)  # (the whole-grid solve's spectra, built with the problem)
    build_cpu, build_wall = time.process_time() - c0, time.perf_counter() - w0
    rss_build = _rss_gb()
    rss_before_solve = _reset_peak()  # the solve's own peak is measured from here (Linux)
    force = pb.scenario.load.force
    kw = {} if coarse is None else {"coarse_levels": coarse}
    kw.update({"whole": {"candidates": False}, "auto": {"precision": "auto"},
               "single": {"precision": "single"}}[solver])
    if trace:
        import tracemalloc
        tracemalloc.start()
    c0, w0 = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = solve_normal_cg(op, pb.gap, force=force, tol=pb.scenario.solver.tolerance, **kw)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    out = {"n": n, "converged": bool(res.converged), "iterations": int(res.iterations),
           "convolutions": int(res.info["convolutions"]),
           "conv_per_iteration": res.info["convolutions"] / max(res.iterations, 1),
           "coarse": res.info.get("coarse"), "solver": solver, "precision": res.info.get("precision"),
           "candidates": res.info.get("candidates"),
           "cpu_s": cpu, "wall_s": wall, "build_cpu_s": build_cpu, "build_wall_s": build_wall,
           "rss_after_build_gb": rss_build, "peak_rss_gb": _rss_gb(),
           "solve_peak_bytes_per_node": (_vm_hwm() - rss_before_solve) / n**2 if rss_before_solve else None,
           "contact_nodes": int(np.count_nonzero(res.contact)),
           "approach_nm": float(res.approach) * 1e9,
           "force_error": abs(float(res.pressure.sum()) * pb.grid.dx * pb.grid.dy - force) / force,
           "max_pressure_MPa": float(res.pressure.max()) / 1e6}
    if trace:
        import tracemalloc
        out["tracemalloc_peak_gb"] = tracemalloc.get_traced_memory()[1] / 1e9
        tracemalloc.stop()
    if compare:
        c0 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cold = solve_normal_cg(op, pb.gap, force=force, tol=pb.scenario.solver.tolerance, coarse_levels=0)
        out["cold"] = {"iterations": int(cold.iterations), "convolutions": int(cold.info["convolutions"]),
                       "cpu_s": time.process_time() - c0}
        out["same_contact"] = bool(np.array_equal(cold.contact, res.contact))
        out["contact_nodes_differ"] = int(np.count_nonzero(cold.contact != res.contact))
        out["max_dp_rel"] = float(np.abs(cold.pressure - res.pressure).max() / np.abs(cold.pressure).max())
    return out


def child_ramp(n: int, method: str, onset_by: str = "auto") -> dict:
    from tribobem.scenario import run_scenario

    if onset_by != "auto":
        # the A/B switch: the onset probes in force (before) or in displacement control, whatever
        # the grid (auto: displacement from tangential_paths.DISPLACEMENT_ONSET_NODES on)
        import functools

        from tribobem.runs import partial_slip
        from tribobem.solvers import tangential_paths
        partial_slip.tangential_ramp = functools.partial(tangential_paths.tangential_ramp, onset_by=onset_by)

    sc = scenario(n, ramp=True)
    sc["solver"]["method"] = method
    c0, w0 = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rr = run_scenario(sc, outdir=None, progress=False, quiet=True)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    summ = rr.summary  # run-level values are top-level keys of summary.json
    steps = summ["steps"]
    return {"n": n, "method": method, "onset_by": onset_by,
            "cpu_s": cpu, "wall_s": wall, "peak_rss_gb": _rss_gb(), "steps": len(steps),
            "converged": bool(summ["converged"]),
            "iterations": [s.get("iterations") for s in steps],
            "coupling_iterations": [s.get("coupling_iterations") for s in steps],
            "static_friction_ratio": summ.get("static_friction_ratio"),
            "onset_refinement_steps": summ.get("onset_refinement_steps"),
            "ramp_message": summ.get("ramp_message"),
            "presliding_displacement_nm": (summ.get("presliding_displacement") or float("nan")) * 1e9,
            "contact_nodes": [s.get("contact_nodes") for s in steps][:1],
            "warnings": summ.get("warnings", [])}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, nargs="+", default=[1024, 2048])
    ap.add_argument("--coarse", type=int, default=None, help="coarse_levels (default: the solver's choice)")
    ap.add_argument("--compare", action="store_true", help="also solve cold and compare")
    ap.add_argument("--tracemalloc", action="store_true")
    ap.add_argument("--ramp", action="store_true", help="the partial-slip ramp at 2048^2 (or --n)")
    ap.add_argument("--method", default="auto", help="[solver] method of the ramp (auto, normcg, polonsky_keer)")
    ap.add_argument("--onset-by", default="auto", choices=["auto", "displacement", "force"],
                    help="ramp: control of the onset probes (tangential_ramp's onset_by)")
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--solver", default="auto", choices=["auto", "whole", "single"],
                    help="normal solves: auto (the scenario default: candidate-set solve, precision auto), "
                         "whole (the whole grid in double precision, as before the candidate-set solve), single")
    ap.add_argument("--json", default=None)
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)

    if a.child is not None:
        n = int(a.child)
        if a.ramp:
            out = child_ramp(n, a.method, a.onset_by)
        else:
            out = child_normal(n, a.coarse, a.compare, a.tracemalloc, a.solver)
        print("RESULT " + json.dumps(out))
        return 0

    env = dict(os.environ)
    if a.threads:
        env["TRIBOBEM_FFT_WORKERS"] = str(a.threads)
    sizes = a.n if not (a.ramp and a.n == [1024, 2048]) else [2048]
    results = []
    for n in sizes:
        cmd = [sys.executable, os.path.abspath(__file__), "--child", str(n)]
        if a.coarse is not None:
            cmd += ["--coarse", str(a.coarse)]
        cmd += ["--compare"] * a.compare + ["--tracemalloc"] * a.tracemalloc + ["--ramp"] * a.ramp
        cmd += ["--method", a.method, "--onset-by", a.onset_by, "--solver", a.solver]
        load0 = os.getloadavg()[0]
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        line = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT ")]
        if proc.returncode != 0 or not line:
            print(proc.stdout[-3000:], proc.stderr[-3000:], file=sys.stderr)
            return 1
        r = json.loads(line[-1][7:])
        r["load_avg_start"] = load0
        r["load_avg_end"] = os.getloadavg()[0]
        results.append(r)
        print(json.dumps(r), flush=True)
    if not a.ramp:
        print("\n| n | iterations | convolutions | conv/it | CPU s | wall s | build CPU s | peak RSS GB | contact nodes |")
        print("|---|---|---|---|---|---|---|---|---|")
        for r in results:
            print(f"| {r['n']} | {r['iterations']} | {r['convolutions']} | {r['conv_per_iteration']:.2f} | "
                  f"{r['cpu_s']:.1f} | {r['wall_s']:.1f} | {r['build_cpu_s']:.1f} | {r['peak_rss_gb']:.2f} | "
                  f"{r['contact_nodes']} |")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
