"""Where does a CG iteration of ``solve_normal`` spend its time?

For one periodic rough-contact problem per size (the one of normal_vs_tamaas.py, or the
adhesive one of adhesion_vs_tamaas.py with ``--problem adhesion``) this script measures

* the time of one ``op.apply`` (rfft2, multiply by the kernel, irfft2) and of its parts,
  and the time of one elementwise NumPy pass over the grid, for scale;
* the time per iteration of ``solve_normal`` (total / iterations, minimum of the repeats,
  interleaved with the apply timings) and the ratio  t_iter / (2 t_apply)  (target <= 1.5:
  an iteration performs two convolutions, K p and K t);
* a line profile of one solve: a small ``sys.settrace`` profiler charges the wall time
  between two line events to the line that was running, exclusively per function, over
  the files of tribobem's solver, operator, backend and interactions (NumPy and scipy.fft
  calls are charged to the tribobem line that made them).  Tracing adds a few
  microseconds per line, small against the milliseconds of a full-grid line at >= 512^2;
* peak memory: tracemalloc peak of the NumPy allocations during the solve and, in a fresh
  subprocess, the peak resident-set increase.

    python benchmarks/profile_iteration.py                    # 512 and 1024
    python benchmarks/profile_iteration.py --sizes 2048 --repeats 2
    python benchmarks/profile_iteration.py --problem adhesion --sizes 512
"""

from __future__ import annotations

import linecache
import math
import os
import sys
import time
import tracemalloc
import warnings
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import E_STAR, L, markdown_table  # noqa: E402


class LineProfiler:
    """Exclusive wall time per source line of the traced files (a minimal line_profiler)."""

    def __init__(self, filenames):
        self.files = {os.path.realpath(f) for f in filenames}
        self._known: dict = {}
        self.stats = defaultdict(lambda: [0, 0.0])  # (file, func, line) -> [hits, seconds]
        self.stack: list = []
        self.last = 0.0

    def _traced(self, code) -> bool:
        fn = code.co_filename
        r = self._known.get(fn)
        if r is None:
            r = self._known[fn] = os.path.realpath(fn) in self.files
        return r

    def _charge(self, now: float) -> None:
        if self.stack and self.stack[-1] is not None:
            self.stats[self.stack[-1]][1] += now - self.last

    def _global(self, frame, event, arg):
        if event == "call" and self._traced(frame.f_code):
            self._charge(time.perf_counter())
            self.stack.append(None)
            self.last = time.perf_counter()
            return self._local
        return None

    def _local(self, frame, event, arg):
        self._charge(time.perf_counter())
        if event == "line":
            key = (frame.f_code.co_filename, frame.f_code.co_name, frame.f_lineno)
            self.stack[-1] = key
            self.stats[key][0] += 1
        elif event == "return":
            self.stack.pop()
        self.last = time.perf_counter()
        return self._local

    def run(self, fn, *args, **kw):
        self.last = time.perf_counter()
        sys.settrace(self._global)
        try:
            return fn(*args, **kw)
        finally:
            sys.settrace(None)

    def table(self, iterations: int, top: int = 30) -> tuple[str, float]:
        total = sum(v[1] for v in self.stats.values())
        rows = []
        for (fn, func, line), (hits, sec) in sorted(self.stats.items(), key=lambda kv: -kv[1][1])[:top]:
            src = linecache.getline(fn, line).strip().replace("|", "\\|")
            if len(src) > 70:
                src = src[:67] + "..."
            rows.append([f"{os.path.basename(fn)}:{line}", func, hits, 1e3 * sec / iterations,
                         100.0 * sec / total if total else math.nan, f"`{src}`"])
        return markdown_table(["line", "function", "hits", "ms / iteration", "% of solve", "source"], rows), total

    def apply_calls(self) -> int:
        """Number of convolutions performed (hits of the kernel-multiply lines: op.apply in
        operators.py and the solver's convolve in columns.py)."""
        return sum(h for (fn, func, line), (h, sec) in self.stats.items()
                   if os.path.basename(fn) in ("operators.py", "columns.py") and "*= spec" in linecache.getline(fn, line))

    def grouped(self) -> dict:
        """Seconds per coarse category (by source text of the line)."""
        cats = defaultdict(float)
        for (fn, func, line), (hits, sec) in self.stats.items():
            src = linecache.getline(fn, line)
            base = os.path.basename(fn)
            if base == "columns.py" and func in ("add", "_add_periodic"):
                cats["sparse kernel columns (real space)"] += sec
            elif base == "columns.py" and "*= spec" in src:
                cats["kernel multiply"] += sec
            elif base == "columns.py" and any(k in src for k in ("rfft2(", ".r2c(", "True, 0, T")):
                cats["forward FFT (rfft2 or r2c along y + c2c along x)"] += sec
            elif base == "columns.py" and any(k in src for k in ("fft.ifft(", "fft.irfft(", ".c2r(", "False, 2, T")):
                cats["inverse FFT (c2c along x + c2r along y)"] += sec
            elif base == "backend.py" and "rfft2(" in src and "irfft2" not in src:
                cats["rfft2"] += sec
            elif base == "backend.py" and "irfft2(" in src:
                cats["irfft2"] += sec
            elif base == "operators.py" and "*= spec" in src:
                cats["kernel multiply"] += sec
            elif base in ("operators.py", "backend.py", "columns.py"):
                cats["operator overhead (python, slicing)"] += sec
            else:
                cats["solver (everything else)"] += sec
        return dict(cats)


class MemoryPeakTracer(LineProfiler):
    """Which line reaches the peak of the NumPy allocations (tracemalloc) during a solve."""

    def __init__(self, filenames):
        super().__init__(filenames)
        self.peak = 0
        self.peak_line = None
        self.peaks_by_line = defaultdict(int)
        self.snapshot = None

    def _charge(self, now: float) -> None:
        if self.stack and self.stack[-1] is not None:
            cur, peak = tracemalloc.get_traced_memory()
            key = self.stack[-1]
            self.peaks_by_line[key] = max(self.peaks_by_line[key], peak)
            if peak > self.peak:
                self.peak, self.peak_line = peak, key
                # What is still alive just after the peak (the temporaries of the peak line are gone).
                self.snapshot = tracemalloc.take_snapshot()
            tracemalloc.reset_peak()

    def run(self, fn, *args, **kw):
        tracemalloc.start()
        tracemalloc.reset_peak()
        self.base = tracemalloc.get_traced_memory()[0]
        try:
            return super().run(fn, *args, **kw)
        finally:
            tracemalloc.stop()

    def table(self, grid_bytes: int, top: int = 8) -> str:
        rows = []
        for (fn, func, line), peak in sorted(self.peaks_by_line.items(), key=lambda kv: -kv[1])[:top]:
            src = linecache.getline(fn, line).strip().replace("|", "\\|")
            if len(src) > 70:
                src = src[:67] + "..."
            rows.append([f"{os.path.basename(fn)}:{line}", func, (peak - self.base) / grid_bytes, f"`{src}`"])
        return markdown_table(["line", "function", "NumPy memory at its peak (grid arrays, above the inputs)", "source"], rows)

    def alive_table(self, grid_bytes: int) -> str:
        """Allocation sites of the big blocks alive right after the peak."""
        if self.snapshot is None:
            return ""
        rows = []
        for st in self.snapshot.statistics("lineno"):
            if st.size < grid_bytes / 8:
                continue
            fr = st.traceback[0]
            src = linecache.getline(fr.filename, fr.lineno).strip().replace("|", "\\|")
            if len(src) > 70:
                src = src[:67] + "..."
            rows.append([f"{os.path.basename(fr.filename)}:{fr.lineno}", st.count, st.size / grid_bytes, f"`{src}`"])
        return markdown_table(["allocated at", "blocks", "grid arrays", "source"], rows)


def traced_files():
    import tribobem.elasticity.backend as be
    import tribobem.elasticity.columns as cols
    import tribobem.elasticity.operators as ops
    import tribobem.interactions.base as ib
    import tribobem.interactions.dugdale as dg
    import tribobem.solvers.normal as nm

    return [nm.__file__, ops.__file__, be.__file__, cols.__file__, dg.__file__, ib.__file__]


def problem_kwargs(problem: str, s: np.ndarray) -> dict:
    from tribobem.interactions.dugdale import DugdaleAdhesion

    if problem == "normal":
        return dict(force=0.01 * E_STAR * L * L, tol=1e-10)
    # The adhesive problem of adhesion_vs_tamaas.py.
    import adhesion_vs_tamaas as adh

    prm = adh.parameters(s)
    return dict(approach=prm["approach"], interaction=DugdaleAdhesion.from_stress(prm["sigma0"], prm["h0"]),
                tol=adh.TRIBOBEM_TOL)


def elementwise_pass(n: int, repeats: int = 5) -> dict:
    """Times (s) of single NumPy passes over an n x n float64 grid, for scale."""
    rng = np.random.default_rng(0)
    a, b = rng.random((n, n)), rng.random((n, n))
    m = a > 0.5
    out = np.empty_like(a)
    tests = {
        "a + b (new array)": lambda: a + b,
        "np.add(a, b, out=)": lambda: np.add(a, b, out=out),
        "np.where(m, a, 0.0)": lambda: np.where(m, a, 0.0),
        "np.count_nonzero(m)": lambda: np.count_nonzero(m),
        "np.vdot(a, b)": lambda: np.vdot(a, b),
        "np.sum(a)": lambda: np.sum(a),
        "a > 0.5 (mask)": lambda: a > 0.5,
        "np.flatnonzero(m)": lambda: np.flatnonzero(m),
    }
    res = {}
    for name, f in tests.items():
        f()
        best = math.inf
        for _ in range(repeats):
            t0 = time.perf_counter()
            f()
            best = min(best, time.perf_counter() - t0)
        res[name] = best
    return res


def apply_parts(op, repeats: int = 5) -> dict:
    """rfft2, kernel multiply, irfft2 of one apply, timed separately (s)."""
    be = op.backend
    rng = np.random.default_rng(1)
    p = rng.random(op.grid.shape)
    spec = op.spectra["zz"]
    res = {"rfft2": math.inf, "multiply": math.inf, "irfft2": math.inf, "apply": math.inf}
    for _ in range(repeats + 1):
        t0 = time.perf_counter()
        T = be.rfft2(p, s=op.fft_shape)
        t1 = time.perf_counter()
        T *= spec
        t2 = time.perf_counter()
        be.irfft2(T, s=op.fft_shape)
        t3 = time.perf_counter()
        op.apply(p)
        t4 = time.perf_counter()
        for k, v in (("rfft2", t1 - t0), ("multiply", t2 - t1), ("irfft2", t3 - t2), ("apply", t4 - t3)):
            res[k] = min(res[k], v)
    return res


def in_solve_apply(solve) -> dict:
    """CPU time per iteration of one solve against ``op.apply`` timed inside it.

    Every convolution the solver makes (``normal.convolve``) is preceded by an ``op.apply``
    of the same input, timed with ``time.process_time`` and subtracted from the solve's CPU
    time: both see the same load, caches and memory state.  Returns t_iter, t_apply (mean
    over the calls), t_conv (mean of the solver's own convolution) and the call count.
    """
    import tribobem.solvers.normal as nm

    orig = nm.convolve
    acc = {"apply": 0.0, "conv": 0.0, "n": 0}

    def timed_convolve(op, x, **kw):
        t0 = time.process_time()
        op.apply(x)
        t1 = time.process_time()
        out = orig(op, x, **kw)
        t2 = time.process_time()
        acc["apply"] += t1 - t0
        acc["conv"] += t2 - t1
        acc["n"] += 1
        return out

    nm.convolve = timed_convolve
    try:
        t0 = time.process_time()
        res = solve()
        total = time.process_time() - t0
    finally:
        nm.convolve = orig
    n = max(acc["n"], 1)
    cpu = total - acc["apply"]
    return {"t_iter": cpu / res.iterations, "t_apply": acc["apply"] / n, "t_conv": acc["conv"] / n,
            "convolutions": acc["n"], "iterations": res.iterations, "cpu": cpu}


def profile_size(n: int, args) -> dict:
    from tribobem.solvers.normal import solve_normal

    s, _ = common.make_surface(n)
    h = s.max() - s
    op = common.tribobem_operator(n, args.workers)
    kw = problem_kwargs(args.problem, s)

    def solve():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return solve_normal(op, h, max_iterations=20000, **kw)

    # Interleave: apply timings and solves (minimum of each).
    t_apply, t_solve, res = math.inf, math.inf, None
    parts = None
    for _ in range(args.repeats):
        parts_now = apply_parts(op)
        if parts is None:
            parts = parts_now
        else:
            parts = {k: min(parts[k], parts_now[k]) for k in parts}
        t_apply = min(t_apply, parts["apply"])
        wall, _, res = common.timed(solve)
        t_solve = min(t_solve, wall)
    it = res.iterations
    counters = res.info.get("counters", {})

    insitu = in_solve_apply(solve)

    # Line profile of one more solve.
    prof = LineProfiler(traced_files())
    t0 = time.perf_counter()
    prof.run(solve)
    t_traced = time.perf_counter() - t0
    table, total = prof.table(it, top=args.top)

    # Memory: NumPy allocations during one solve, and the lines where they peak.
    mtr = MemoryPeakTracer(traced_files())
    mtr.run(solve)
    traced_peak = mtr.peak - mtr.base
    mem_table = mtr.table(8 * n * n)
    alive_table = mtr.alive_table(8 * n * n)
    mem = None
    if not args.no_memory:
        params = dict(kw_to_params(args.problem, s, kw), workers=args.workers)
        mem = common.run_memory_probe("tribobem", args.problem, n, params)

    return dict(n=n, iterations=it, converged=res.converged, insitu=insitu, t_solve=t_solve, t_apply=t_apply, parts=parts,
                t_traced=t_traced, table=table, grouped=prof.grouped(), traced_total=total,
                applies=prof.apply_calls(), mem_table=mem_table, alive_table=alive_table,
                elementwise=elementwise_pass(n), traced_peak=traced_peak, mem=mem, counters=counters)


def kw_to_params(problem: str, s, kw) -> dict:
    if problem == "normal":
        return {"mean_pressure": kw["force"] / (L * L), "tol": kw["tol"]}
    inter = kw["interaction"]
    return {"approach": kw["approach"], "sigma0": inter.sigma0, "h0": inter.h0, "tol": kw["tol"]}


def main(argv=None) -> int:
    p = common.base_parser(__doc__.splitlines()[0], [512, 1024])
    p.add_argument("--problem", choices=("normal", "adhesion"), default="normal")
    p.add_argument("--top", type=int, default=25, help="lines shown in the line profile")
    args = p.parse_args(argv)
    if args.quick:
        args.sizes, args.repeats, args.no_memory = [256], 1, True
    print(f"## Cost of one CG iteration of solve_normal ({args.problem} problem)\n")
    print(common.environment(), "\n", flush=True)

    results = []
    for n in args.sizes:
        r = profile_size(n, args)
        results.append(r)
        t_it = r["t_solve"] / r["iterations"]
        print(f"### n = {n}: {r['iterations']} iterations (converged {r['converged']}), solve {r['t_solve']:.3f} s, "
              f"{1e3 * t_it:.2f} ms/iteration, apply {1e3 * r['t_apply']:.2f} ms, "
              f"t_iter / (2 t_apply) = {t_it / (2 * r['t_apply']):.2f}\n")
        ins = r["insitu"]
        print(f"In one untraced solve (CPU time): {1e3 * ins['t_iter']:.2f} ms/iteration, op.apply timed inside it "
              f"{1e3 * ins['t_apply']:.2f} ms, the solver's convolution {1e3 * ins['t_conv']:.2f} ms; "
              f"t_iter / t_apply = {ins['t_iter'] / ins['t_apply']:.2f} (target <= 1.5), "
              f"{ins['convolutions'] / ins['iterations']:.2f} convolutions per iteration\n")
        pa = r["parts"]
        ew = r["elementwise"]
        print("One apply: " + ", ".join(f"{k} {1e3 * v:.2f} ms" for k, v in pa.items()))
        print("One NumPy pass over the grid: " + ", ".join(f"{k} {1e3 * v:.2f} ms" for k, v in ew.items()) + "\n")
        g = r["grouped"]
        tot = sum(g.values())
        conv = sum(v for k, v in g.items() if k not in ("solver (everything else)", "sparse kernel columns (real space)"))
        if r["applies"]:
            t_conv = conv / r["applies"]
            r["t_apply_in_situ"] = t_conv
            print(f"In the traced solve: {r['applies']} convolutions ({r['applies'] / r['iterations']:.2f} per iteration), "
                  f"{1e3 * t_conv:.2f} ms each; traced time per iteration / (2 x that) = "
                  f"{tot / r['iterations'] / (2 * t_conv):.2f}; time per iteration / one such convolution = "
                  f"{tot / r['iterations'] / t_conv:.2f}; convolutions take {100 * conv / tot:.0f} % of the solve\n")
        if r.get("counters"):
            print(f"Solver counters (last solve): {r['counters']}\n")
        print(f"Line profile (one traced solve: {r['t_traced']:.3f} s wall, {r['traced_total']:.3f} s charged "
              "to lines; tracer overhead excluded from the charges):\n")
        print(markdown_table(["category", "ms / iteration", "% of solve"],
                             [[k, 1e3 * v / r["iterations"], 100 * v / tot]
                              for k, v in sorted(g.items(), key=lambda kv: -kv[1])]))
        print()
        print(r["table"])
        print()
        m = r["mem"]
        grid_mib = n * n * 8 / 2**20
        line = (f"Memory: NumPy peak during the solve (tracemalloc) {r['traced_peak'] / 2**20:.1f} MiB = "
                f"{r['traced_peak'] / 2**20 / grid_mib:.1f} grid arrays")
        if m:
            line += (f"; peak RSS increase (fresh process, incl. kernel) {m['rss_delta_mib']:.1f} MiB = "
                     f"{m['rss_delta_grids']:.1f} grid arrays")
        print(line + "\n")
        print("Lines at which the NumPy allocations peak (the memory held while the line runs):\n")
        print(r["mem_table"] + "\n")
        print("Arrays (>= 1/8 grid array) alive right after the peak, by the line that allocated them "
              "(the inputs h and the surface are included):\n")
        print(r["alive_table"] + "\n", flush=True)

    print("### Summary\n")
    rows = []
    for r in results:
        t_it = r["t_solve"] / r["iterations"]
        m = r["mem"]
        tc = r.get("t_apply_in_situ", math.nan)
        tot = sum(r["grouped"].values())
        rows.append([r["n"], r["iterations"], r["applies"] / r["iterations"], r["t_solve"], 1e3 * t_it,
                     1e3 * r["t_apply"], t_it / (2 * r["t_apply"]),
                     r["insitu"]["t_iter"] / r["insitu"]["t_apply"], tot / r["iterations"] / tc,
                     r["traced_peak"] / 2**20, r["traced_peak"] / (8 * r["n"] ** 2),
                     m["rss_delta_mib"] if m else math.nan])
    print(markdown_table(["n", "iterations", "convolutions / iteration", "solve s", "ms / iteration", "apply ms",
                          "t_iter / (2 t_apply)", "t_iter / t_apply, CPU, apply timed in the solve",
                          "t_iter / one solver convolution, in the traced solve",
                          "NumPy peak MiB", "(grid arrays)",
                          "peak RSS increase MiB"], rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
