"""Benchmark: a force-controlled friction hysteresis loop (issue 7 item 5).

The problem: a rigid ball (R = 50 um) on an elastic half-space (E = 70 GPa, nu = 0.3: dissimilar
bodies, so the coupling loop is active), Dugdale adhesion (50 mJ/m^2, z0 = 0.2 nm), F0 = 10 uN,
mu = 0.2, free boundary over +-2a (Paper E section 3.2), amplitude 0.98 mu F0+ (0.999 is unreachable:
the coupling lowers F0+ by ~1 % along the loading), ``--cycles``
cycles of ``--steps`` steps (target configuration: 256^2, 3 cycles, 80 steps: 260 steps).

Prints the wall and CPU time, coupled steps, tangential iterations per step (all coupling passes),
coupling passes per step, the share of the wall time spent in the FFTs (the backend's
rfft2/irfft2, timed by wrapping them), FFT pairs (one forward + one inverse) per step, and the
peak resident memory of the process.  Set TRIBOBEM_FFT_WORKERS=1 for comparable timings.  Not a test: nothing here
is asserted; run it with ``python benchmarks/hysteresis.py [--n 256 --cycles 3 --steps 80]``.
``--quick`` runs 96^2, 1 cycle, 16 steps (about a minute).
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
import warnings

import numpy as np


def keep_freed_memory(limit: int = 256 * 1024 * 1024) -> bool:
    """Raise glibc's mmap and trim thresholds to ``limit`` bytes (Linux/glibc only; False
    elsewhere).  By default a freed multi-MB array goes back to the OS, and the next one costs a
    page fault per 4 KiB page: measured on the padded 512^2 tangential convolution, 11.7 ms of
    CPU with the default and 5.1 ms with this setting (4 FFTs: ~4.3 ms)."""
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
        return bool(libc.mallopt(M_TRIM_THRESHOLD, limit)) and bool(libc.mallopt(M_MMAP_THRESHOLD, limit))
    except (OSError, AttributeError):
        return False


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=256)
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--steps", type=int, default=80)
    ap.add_argument("--amplitude", type=float, default=0.98,
                    help="F* / (mu F0+ at A); 0.999 is unreachable here: F0+ falls by ~1 %% along the loading")
    ap.add_argument("--quick", action="store_true", help="96^2, 1 cycle, 16 steps")
    ap.add_argument("--tol", type=float, default=1e-10, help="normal solver tolerance")
    ap.add_argument("--tangential-tol", type=float, default=1e-7)
    ap.add_argument("--coupling-tol", type=float, default=1e-6)
    ap.add_argument("--no-extrapolate", action="store_true", help="warm start from the last step only")
    ap.add_argument("--keep-freed-memory", action="store_true",
                    help="glibc mallopt: keep freed blocks below 256 MiB in the heap (no page faults on the "
                         "multi-MB FFT arrays); measures what a backend-level setting would give")
    ap.add_argument("--no-window", action="store_true",
                    help="solve every step on the whole grid (no window around the contact)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.keep_freed_memory:
        keep_freed_memory()
    if args.quick:
        args.n, args.cycles, args.steps = 96, 1, 16

    import tribobem as tb
    from tribobem.analytic.hertz import hertz
    from tribobem.elasticity.backend import Backend
    from tribobem.geometry import sphere
    from tribobem.solvers import coupling as C
    from tribobem.solvers import hysteresis as H
    from tribobem.solvers.hysteresis import hysteresis_loop, loop_energies

    H.EXTRAPOLATE = not args.no_extrapolate

    # Count tangential iterations and time the FFTs.
    counts = {"tangential_iterations": 0, "normal_iterations": 0, "fft_time": 0.0, "ffts": 0}
    # Count the iterations of every inner solve (all coupling passes, both tangential methods).
    orig_t, orig_n = C.solve_tangential, C.solve_normal

    def t_solve(*a, **kw):
        r = orig_t(*a, **kw)
        counts["tangential_iterations"] += r.iterations
        return r

    def n_solve(*a, **kw):
        r = orig_n(*a, **kw)
        counts["normal_iterations"] += r.iterations
        return r

    C.solve_tangential, C.solve_normal = t_solve, n_solve
    for name in ("rfft2", "irfft2"):
        fn = getattr(Backend, name)

        def timed(self, *a, _fn=fn, **kw):
            t0 = time.perf_counter()
            out = _fn(self, *a, **kw)
            counts["fft_time"] += time.perf_counter() - t0
            counts["ffts"] += 1
            return out

        setattr(Backend, name, timed)

    # The lean transforms (free boundary, scipy.fft) call pocketfft directly: time those too.
    from tribobem.elasticity import backend as B, columns as Cols

    class _TimedPocketfft:
        def __init__(self, mod):
            self._mod = mod

        def __getattr__(self, name):
            fn = getattr(self._mod, name)

            def timed(*a, **kw):
                t0 = time.perf_counter()
                out = fn(*a, **kw)
                counts["fft_time"] += time.perf_counter() - t0
                counts["ffts"] += 0.5  # a 1-D pass along one axis: half a 2-D transform
                return out

            return timed

    for mod in (B, Cols):
        if getattr(mod, "_pocketfft", None) is not None:
            mod._pocketfft = _TimedPocketfft(mod._pocketfft)

    pair = tb.ContactPair(tb.Material(70e9, 0.3, "flat"), tb.Material.rigid("ball"))
    R, F0, mu = 50e-6, 10e-6, 0.2
    adhesion = tb.DugdaleAdhesion(0.05, 0.2e-9)
    a = float(hertz(force=F0, radius=R, E_star=pair.effective_modulus).contact_radius) * 1.4  # adhesive contact is larger
    grid = tb.Grid.square(args.n, 4.0 * a)
    op = tb.make_operator(grid, pair, ("x", "y", "z"))
    gap = sphere(grid, radius=R)
    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = hysteresis_loop(op, gap, normal_force=F0, friction_coefficient=mu, amplitude=args.amplitude, cycles=args.cycles,
                              steps=args.steps, interaction=adhesion, tol=args.tol,
                              tangential_tol=args.tangential_tol, coupling_tol=args.coupling_tol,
                              window=not args.no_window)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    n_steps = len(run.steps) + 1
    F = [run.start.tangential.force_x] + [s.tangential.force_x for s in run.steps]
    D = [run.start.tangential.displacement_x] + [s.tangential.displacement_x for s in run.steps]
    cyc = [0] + list(run.path.cycle)
    out = {
        "grid": f"{args.n}^2 free boundary (padded {2 * args.n}^2)",
        "cycles": args.cycles, "steps_per_cycle": args.steps, "coupled_steps": n_steps,
        "wall_s": wall, "cpu_s": cpu,
        "tangential_iterations_per_step": counts["tangential_iterations"] / n_steps,
        "normal_iterations_per_step": counts["normal_iterations"] / n_steps,
        "coupling_passes_per_step": float(np.mean([s.coupling_iterations for s in run.steps])),
        "fft_share": counts["fft_time"] / wall, "ffts": counts["ffts"],
        "fft_pairs_per_step": counts["ffts"] / 2.0 / n_steps,
        "peak_rss_MiB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "repulsive_force_uN": run.start.normal.repulsive_force * 1e6,
        "keep_freed_memory": args.keep_freed_memory,
        "tolerances": {"normal": args.tol, "tangential": args.tangential_tol, "coupling": args.coupling_tol},
        "loop_energy_J": loop_energies(F, D, cyc), "failed_steps": run.failed,
        "window": run.steps[-1].normal.info.get("window") if run.steps else None,
    }
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        for k, v in out.items():
            print(f"{k:34s} {v}")
    return out


if __name__ == "__main__":
    main(sys.argv[1:])
