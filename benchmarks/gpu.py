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
* ``hysteresis``: the loop of ``examples/hysteresis_mindlin.toml``;
* ``burl_ramp``: the partial-slip ramp of ``burl_whole.py --ramp`` (the whole burl to gross slip,
  82 um free-boundary window), 2048^2;
* ``hertz``: a rigid 10 um ball on Si (free boundary, 1.2 um window) at 128^2 - 1024^2, where
  the GPU's fixed costs meet the CPU's time (the small-grid limit ``CUPY_MIN_NODES``).

The first CuPy call of a process compiles kernels; a small warm-up solve runs first and its time is
reported separately (``warm-up``).  CPU references above ``--cpu-max-n`` are skipped (a 8192^2
CPU solve takes tens of minutes and ~11 GB); the table then shows "-".

    python benchmarks/gpu.py                         # every case, default sizes (needs CuPy + a GPU)
    python benchmarks/gpu.py --cases burl --sizes 4096 8192 --cpu-max-n 4096
    python benchmarks/gpu.py --dry-run               # check the script on the CPU: "cupy" -> numpy, small sizes
    python benchmarks/gpu.py --cases normal_normcg burl --precision single   # single-precision NormCG on the GPU

Without CuPy and a CUDA device it says so and exits 0 (``--dry-run`` works anywhere).

The two sides can also run on different machines (a GPU lent for minutes, the CPU reference on
the machine the CPU targets are set for):

    python benchmarks/gpu.py --save DIR ...          # GPU side only: DIR/gpu_rows.json, DIR/gpu_contacts.npz
    python benchmarks/gpu.py --against DIR ...       # CPU side only, compared with DIR's GPU runs

``--save`` writes after every case (a run cut short keeps what it finished), records a case that
fails with its error and goes on, and gives the memory CuPy's pool holds after each case (the
operator caches of earlier cases included).
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
                 "burl": [4096, 8192], "adhesion": [None], "partial_slip": [None], "hysteresis": [None],
                 "burl_ramp": [2048], "hertz": [128, 256, 512, 1024]}
DRY_SIZES = {"normal_pk": [128], "normal_normcg": [128], "burl": [256], "adhesion": [None],
             "partial_slip": [None], "hysteresis": [None], "burl_ramp": [128], "hertz": [64]}


#: ``--precision``: ``[solver] precision`` of the non-adhesive normal cases (None: the default,
#: "auto", which is double precision on CuPy; "single" runs NormCG's direction images in float32
#: on the device, the convergence test in double).
PRECISION: list = [None]


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
    if case == "hertz":
        return {"kind": "normal", "name": f"Hertz ball {n}^2",
                "grid": {"n": n, "size": "1.2 um", "periodic": False},
                "body1": {"E": "130 GPa", "nu": 0.28},
                "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
                "load": {"force": "200 uN"}, "solver": {"tolerance": 1e-10}, "output": quiet_out}
    if case == "burl_ramp":
        from burl_whole import scenario as burl_scenario

        sc = burl_scenario(n, ramp=True)
        if n < 1024:  # the dry run: coarser cells, the cutoff at 4 of them
            sc["body1"]["roughness"]["short_cutoff"] = f"{4 * 82e-6 / n * 1e9:g} nm"
        sc["output"] = quiet_out
        return sc
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


_SOLVER_KEYS = ("time", "iterations", "residual", "tangential_iterations", "tangential_residual",
                "coupling_iterations")


def _scalars(summary: dict) -> dict:
    """The run's scalar results: run-level numbers and the last state's (solver counters left out)."""
    def num(v):
        return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_))

    out = {k: float(v) for k, v in summary.items() if num(v)}
    last = summary["steps"][-1] if summary["steps"] else {}
    out.update({f"last.{k}": float(v) for k, v in last.items() if num(v) and k not in _SOLVER_KEYS})
    return out


def _counts(summary: dict) -> dict:
    """Solver work of the run: the last state's normal iterations and the totals over the states."""
    steps = summary["steps"]
    total = sum(int(s.get("iterations") or 0) for s in steps)
    tang = sum(int(s.get("tangential_iterations") or 0) for s in steps)
    return {"states": len(steps), "iterations_last": int(steps[-1].get("iterations") or 0) if steps else 0,
            "iterations_total": total, "tangential_iterations_total": tang,
            "converged": bool(summary.get("converged", True))}


def run(sc: dict, backend: str, base_dir: Path):
    from tribobem.scenario import run_scenario

    sc = copy.deepcopy(sc)
    sc.setdefault("solver", {})["backend"] = backend
    if PRECISION[0] is not None and sc.get("kind") == "normal" and "adhesion" not in sc:
        sc["solver"]["precision"] = PRECISION[0]
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


def _scale(key: str, values: dict) -> float:
    """The magnitude a value is compared on: a vector component's is its vector's (a y force of
    1e-24 N beside an x force of 2e-6 N is zero, not a relative difference of 1)."""
    for a, b in (("_x", "_y"), ("_y", "_x")):
        if key.endswith(a):
            return max(abs(values[key]), abs(values.get(key[: -len(a)] + b, 0.0)))
    return abs(values[key])


def agreement(ca, sa: dict, cb, sb: dict) -> dict:
    """Contact-node and scalar agreement of two runs of one scenario (contact masks, scalars)."""
    nodes = None if ca is None or cb is None else int(np.count_nonzero(ca != cb))
    worst, key = 0.0, None
    for k, va in sa.items():
        vb = sb.get(k)
        if vb is None or not np.isfinite(va) or not np.isfinite(vb):
            continue
        d = abs(va - vb) / max(_scale(k, sa), 1e-300)
        if d > worst:
            worst, key = d, k
    return {"contact_nodes": int(np.count_nonzero(ca)) if ca is not None else None,
            "contact_nodes_differ": nodes, "max_rel_diff": worst, "max_rel_diff_key": key}


def compare(a, b) -> dict:
    """Contact-node and scalar agreement of two runs (run results) of one scenario."""
    return agreement(_contact(a), _scalars(a.summary), _contact(b), _scalars(b.summary))


def _sizes(a, case: str) -> list:
    if a.sizes and DEFAULT_SIZES[case] != [None]:
        return a.sizes
    return (DRY_SIZES if a.dry_run else DEFAULT_SIZES)[case]


def _pool_peak_reset():
    """Free CuPy's unused pool blocks before a case, so that the pool's size after it is what the
    case used plus what earlier cases still hold (their cached operators); None without CuPy."""
    try:
        import cupy
    except ImportError:
        return None
    pool = cupy.get_default_memory_pool()
    pool.free_all_blocks()
    return pool


HEADER = ("| case | n | GPU wall s | CPU s (wall s) | CPU / GPU wall | iterations (last; total, tangential) "
          "| GPU pool GB | contact nodes | nodes differ | max rel. diff (key) |\n"
          "|---|---|---|---|---|---|---|---|---|---|")


def _line(row: dict) -> str:
    if "error" in row:
        return f"| {row['case']} | {row['n']} | failed: {row['error'][:200]} |"
    has_cpu = "cpu_s" in row
    cpu = f"{row['cpu_s']:.2f} ({row['cpu_wall_s']:.2f})" if has_cpu else "-"
    ratio = f"{row['cpu_s'] / row['gpu_wall_s']:.1f}" if has_cpu else "-"
    diff = f"{row['max_rel_diff']:.1e} ({row['max_rel_diff_key']})" if has_cpu else "-"
    it = f"{row.get('iterations_last', '-')}; {row.get('iterations_total', '-')}, {row.get('tangential_iterations_total', '-')}"
    pool = f"{row['gpu_pool_gb']:.2f}" if row.get("gpu_pool_gb") is not None else "-"
    return (f"| {row['case']} | {row['n']} | {row['gpu_wall_s']:.2f} | {cpu} | {ratio} | {it} | {pool} | "
            f"{row.get('contact_nodes', '-')} | {row.get('contact_nodes_differ', '-')} | {diff} |")


def _save(outdir: Path, meta: dict, rows: list, masks: dict) -> None:
    outdir.mkdir(parents=True, exist_ok=True)
    (outdir / "gpu_rows.json").write_text(json.dumps(dict(meta, rows=rows), indent=1))
    # bit-packed contact masks (an 8192^2 mask: 8 MB before compression)
    np.savez_compressed(outdir / "gpu_contacts.npz",
                        **{k: np.packbits(m) for k, m in masks.items()},
                        **{f"{k}__shape": np.asarray(m.shape) for k, m in masks.items()})


def _load_masks(outdir: Path) -> dict:
    path = outdir / "gpu_contacts.npz"
    if not path.exists():
        return {}
    z = np.load(path)
    out = {}
    for k in z.files:
        if k.endswith("__shape"):
            continue
        shape = tuple(int(v) for v in z[f"{k}__shape"])
        out[k] = np.unpackbits(z[k], count=int(np.prod(shape))).astype(bool).reshape(shape)
    return out


def gpu_side(a, gpu: str, device: str, warm: float) -> int:
    """--save: the GPU runs alone, written after every case."""
    outdir = Path(a.save)
    meta = {"device": device, "cpu_cores": os.cpu_count(), "warm_up_s": warm}
    w0 = time.perf_counter()
    rows, masks = [], {}
    print(HEADER)
    for case in a.cases:
        for n in _sizes(a, case):
            sc = scenario(case, n)
            row = {"case": case, "n": n or sc["grid"]["n"]}
            pool = _pool_peak_reset()
            try:
                g, _, g_wall = run(sc, gpu, EXAMPLES)
            except Exception as exc:  # recorded, and the table goes on
                import traceback

                traceback.print_exc()
                row["error"] = f"{type(exc).__name__}: {exc}"
            else:
                row.update(gpu_wall_s=g_wall, scalars=_scalars(g.summary), **_counts(g.summary),
                           timings=g.summary.get("timings", {}),
                           gpu_pool_gb=None if pool is None else pool.total_bytes() / 1e9,
                           backend=g.summary.get("problem", {}).get("backend"),
                           warnings=[str(w)[:300] for w in g.summary.get("warnings", [])])
                c = _contact(g)
                if c is not None:
                    masks[f"{case}_{row['n']}"] = c
                    row["contact_nodes"] = int(np.count_nonzero(c))
                del g
            rows.append(row)
            print(_line(row), flush=True)
            meta["elapsed_s"] = time.perf_counter() - w0
            _save(outdir, meta, rows, masks)
    return 0


def cpu_side(a) -> int:
    """--against: the CPU runs of the GPU rows saved in a directory, compared with them."""
    indir = Path(a.against)
    data = json.loads((indir / "gpu_rows.json").read_text())
    masks = _load_masks(indir)
    print(f"## GPU table: {data['device']} (saved runs); CPU: {os.cpu_count()} cores, here\n")
    print(f"warm-up on the GPU (128^2 NormCG solve, kernel compilation included): {data['warm_up_s']:.2f} s\n")
    run(scenario("normal_normcg", 128), "numpy", EXAMPLES)  # imports and first-call costs out of the table
    print(HEADER)
    rows = []
    for row in data["rows"]:
        skip = row["case"] not in a.cases or "error" in row or row["n"] > a.cpu_max_n \
            or (a.sizes and DEFAULT_SIZES[row["case"]] != [None] and row["n"] not in a.sizes)
        if not skip:
            n = None if DEFAULT_SIZES[row["case"]] == [None] else row["n"]
            c, c_cpu, c_wall = run(scenario(row["case"], n), "numpy", EXAMPLES)
            row = dict(row, cpu_s=c_cpu, cpu_wall_s=c_wall, cpu_counts=_counts(c.summary),
                       **agreement(_contact(c), _scalars(c.summary), masks.get(f"{row['case']}_{row['n']}"),
                                   row["scalars"]))
            del c
        rows.append(row)
        print(_line(row), flush=True)
        if a.json:  # after every row: a long table cut short keeps what it finished
            Path(a.json).write_text(json.dumps(dict(data, rows=rows, cpu_cores=os.cpu_count()), indent=1))
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", nargs="+", default=list(DEFAULT_SIZES), choices=list(DEFAULT_SIZES))
    ap.add_argument("--sizes", type=int, nargs="+", default=None, help="grid sizes (the cases that take one)")
    ap.add_argument("--cpu-max-n", type=int, default=4096, help="skip CPU references above this n")
    ap.add_argument("--dry-run", action="store_true",
                    help="no GPU: run the 'GPU' side on NumPy at small sizes (checks the script)")
    ap.add_argument("--save", default=None, help="GPU side only: write the runs to this directory")
    ap.add_argument("--against", default=None, help="CPU side only: compare with the GPU runs saved here")
    ap.add_argument("--precision", default=None, choices=["auto", "single", "double"],
                    help="[solver] precision of the non-adhesive normal cases (default: the scenario default)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    PRECISION[0] = a.precision

    if a.against:
        return cpu_side(a)

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
    if a.save:
        return gpu_side(a, gpu, device, warm)

    rows = []
    print(HEADER)
    for case in a.cases:
        for n in _sizes(a, case):
            sc = scenario(case, n)
            g, _, g_wall = run(sc, gpu, EXAMPLES)
            row = {"case": case, "n": n or sc["grid"]["n"], "gpu_wall_s": g_wall, **_counts(g.summary)}
            if n is None or n <= a.cpu_max_n:
                c, c_cpu, c_wall = run(sc, "numpy", EXAMPLES)
                row.update(cpu_s=c_cpu, cpu_wall_s=c_wall, **compare(c, g))
            rows.append(row)
            print(_line(row), flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps({"device": device, "warm_up_s": warm, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
