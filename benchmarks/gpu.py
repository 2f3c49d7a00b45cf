"""The GPU table: every run kind with ``backend = "cupy"`` against the same problem on the CPU.

Each case is a scenario run through :func:`tribobem.scenario.run_scenario` twice, in one process:
once with ``[solver] backend = "cupy"`` (wall time; the results come back to the host, so the
device work is finished when the call returns) and once with ``"numpy"`` (CPU time,
``time.process_time``, and wall time).  The table gives both times, their ratio and the agreement:
the contact node sets of the last state (identical or the number of nodes that differ) and the
largest relative difference of the run's scalar results.

Cases (``--cases``; sizes with ``--sizes``):

* ``normal_pk``, ``normal_normcg``: the periodic self-affine surface of ``normal_vs_tamaas.py``
  (Hurst 0.8, spectral rms slope 1, mean pressure 0.01 E*), 1024^2 - 8192^2, each method;
* ``burl``: the whole burl of ``burl_whole.py`` (free boundary, 20 nm cells at 4096^2), 4096^2 and
  8192^2 (the window grows with n at fixed cells);
* ``adhesion``: the rough-ball pull-off of ``examples/pulloff_rough_ball.toml``;
* ``partial_slip``: the Paper D ramp of ``examples/partial_slip_paper_d.toml``;
* ``hysteresis``: the loop of ``examples/hysteresis_mindlin.toml``.

The first CuPy call of a process compiles kernels; a small warm-up solve runs first and its time is
reported separately (``warm-up``).  CPU references above ``--cpu-max-n`` are skipped (a 8192^2
CPU solve takes tens of minutes and ~11 GB); the table then shows "-".

    python benchmarks/gpu.py                         # every case, default sizes (needs CuPy + a GPU)
    python benchmarks/gpu.py --cases burl --sizes 4096 8192 --cpu-max-n 4096
    python benchmarks/gpu.py --dry-run               # check the script on the CPU: "cupy" -> numpy, small sizes

Without CuPy and a CUDA device it says so and exits 0 (``--dry-run`` works anywhere).
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import sys
import time
import tomllib
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"
sys.path.insert(0, str(HERE))

DEFAULT_SIZES = {"normal_pk": [1024, 2048, 4096, 8192], "normal_normcg": [1024, 2048, 4096, 8192],
                 "burl": [4096, 8192], "adhesion": [None], "partial_slip": [None], "hysteresis": [None]}
DRY_SIZES = {"normal_pk": [128], "normal_normcg": [128], "burl": [256], "adhesion": [None],
             "partial_slip": [None], "hysteresis": [None]}


def _example(name: str) -> dict:
    with open(EXAMPLES / f"{name}.toml", "rb") as f:
        return tomllib.load(f)


def scenario(case: str, n: int | None) -> dict:
    """The scenario of a case at size ``n`` (None: the example's own grid)."""
    quiet_out = {"fields": "last", "figures": False, "report": False}
    if case in ("normal_pk", "normal_normcg"):
        return {"kind": "normal", "name": f"periodic self-affine {n}^2",
                "grid": {"n": n, "size": 1.0, "periodic": True},
                "body1": {"E": 1.0, "nu": 0.3,
                          "roughness": {"kind": "self_affine", "hurst": 0.8, "rms_slope": 1.0,
                                        "rolloff": 0.25, "short_cutoff": 4.0 / n, "seed": 1}},
                "body2": {"rigid": True},
                "load": {"force": 0.01 / (1 - 0.3**2)},
                "solver": {"method": "polonsky_keer" if case == "normal_pk" else "normcg", "tolerance": 1e-10},
                "output": quiet_out}
    if case == "burl":
        from burl_whole import scenario as burl_scenario

        sc = burl_scenario(n)
        # 20 nm cells from 4096^2 on (82 um: the burl of burl_whole.py; 164 um at 8192^2), the
        # 82 um window below (coarser cells: the dry run)
        sc["grid"]["size"] = f"{max(n, 4096) * 20e-9 * 1e6:g} um"
        if n < 4096:
            sc["body1"]["roughness"]["short_cutoff"] = f"{4 * 82e-6 / n * 1e9:g} nm"
        sc["output"] = quiet_out
        return sc
    name = {"adhesion": "pulloff_rough_ball", "partial_slip": "partial_slip_paper_d",
            "hysteresis": "hysteresis_mindlin"}[case]
    sc = _example(name)
    sc.pop("expected", None)
    sc["output"] = quiet_out
    if n is not None:
        sc["grid"]["n"] = n
    return sc


def _scalars(summary: dict) -> dict:
    out = {k: v for k, v in summary.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    last = summary["steps"][-1] if summary["steps"] else {}
    out.update({f"last.{k}": v for k, v in last.items()
                if isinstance(v, (int, float)) and not isinstance(v, bool)
                and k not in ("time", "iterations", "residual", "tangential_iterations", "tangential_residual",
                              "coupling_iterations")})
    return out


def run(sc: dict, backend: str, base_dir: Path):
    from tribobem.scenario import run_scenario

    sc = copy.deepcopy(sc)
    sc.setdefault("solver", {})["backend"] = backend
    c0, w0 = time.process_time(), time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rr = run_scenario(sc, outdir=None, progress=False, quiet=True, base_dir=base_dir)
    return rr, time.process_time() - c0, time.perf_counter() - w0


def _contact(rr):
    if not rr.results:
        return None
    c = rr.results[-1].contact
    return np.asarray(c.get() if hasattr(c, "get") else c, dtype=bool)


def compare(a, b) -> dict:
    """Contact-node and scalar agreement of two runs of one scenario."""
    ca, cb = _contact(a), _contact(b)
    nodes = None if ca is None or cb is None else int(np.count_nonzero(ca != cb))
    sa, sb = _scalars(a.summary), _scalars(b.summary)
    worst, key = 0.0, None
    for k, va in sa.items():
        vb = sb.get(k)
        if vb is None or not np.isfinite(va) or not np.isfinite(vb):
            continue
        d = abs(va - vb) / max(abs(va), 1e-300)
        if d > worst:
            worst, key = d, k
    return {"contact_nodes": int(np.count_nonzero(ca)) if ca is not None else None,
            "contact_nodes_differ": nodes, "max_rel_diff": worst, "max_rel_diff_key": key}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", nargs="+", default=list(DEFAULT_SIZES), choices=list(DEFAULT_SIZES))
    ap.add_argument("--sizes", type=int, nargs="+", default=None, help="grid sizes (the cases that take one)")
    ap.add_argument("--cpu-max-n", type=int, default=4096, help="skip CPU references above this n")
    ap.add_argument("--dry-run", action="store_true",
                    help="no GPU: run the 'GPU' side on NumPy at small sizes (checks the script)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)

    from tribobem.elasticity import cupy_available

    # every size on the GPU: the table is where the small-grid limit of scenario runs
    # (TRIBOBEM_CUPY_MIN_NODES, below which they run on NumPy) is measured
    os.environ["TRIBOBEM_CUPY_MIN_NODES"] = "0"

    gpu = "numpy" if a.dry_run else "cupy"
    if not a.dry_run and not cupy_available():
        print("NOTICE: CuPy with a CUDA device is not available: nothing to measure "
              "(run where a GPU is at hand, or --dry-run to check the script).")
        return 0
    device = "dry run (NumPy on both sides)"
    if not a.dry_run:
        import cupy

        device = cupy.cuda.runtime.getDeviceProperties(cupy.cuda.Device().id)["name"].decode()
    print(f"## GPU table: {device}; CPU: {os.cpu_count()} cores\n")

    # warm-up: the first CuPy solve of a process compiles the kernels
    _, _, warm = run(scenario("normal_normcg", 128), gpu, EXAMPLES)
    print(f"warm-up (128^2 NormCG solve, kernel compilation included): {warm:.2f} s\n")

    rows = []
    print("| case | n | GPU wall s | CPU s (wall s) | CPU / GPU wall | contact nodes | nodes differ | max rel. diff (key) |")
    print("|---|---|---|---|---|---|---|---|")
    for case in a.cases:
        sizes = a.sizes if (a.sizes and DEFAULT_SIZES[case] != [None]) else \
            (DRY_SIZES if a.dry_run else DEFAULT_SIZES)[case]
        for n in sizes:
            sc = scenario(case, n)
            g, _, g_wall = run(sc, gpu, EXAMPLES)
            row = {"case": case, "n": n or sc["grid"]["n"], "gpu_wall_s": g_wall}
            if n is None or n <= a.cpu_max_n:
                c, c_cpu, c_wall = run(sc, "numpy", EXAMPLES)
                row.update(cpu_s=c_cpu, cpu_wall_s=c_wall, **compare(c, g))
            rows.append(row)
            cpu = f"{row['cpu_s']:.2f} ({row['cpu_wall_s']:.2f})" if "cpu_s" in row else "-"
            ratio = f"{row['cpu_s'] / g_wall:.1f}" if "cpu_s" in row else "-"
            diff = (f"{row['max_rel_diff']:.1e} ({row['max_rel_diff_key']})" if "cpu_s" in row else "-")
            print(f"| {case} | {row['n']} | {g_wall:.2f} | {cpu} | {ratio} | {row.get('contact_nodes', '-')} | "
                  f"{row.get('contact_nodes_differ', '-')} | {diff} |", flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps({"device": device, "warm_up_s": warm, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
