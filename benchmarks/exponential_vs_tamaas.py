"""Exponential adhesion on a periodic rough surface: tribobem against Tamaas, in one process.

Problem: the periodic self-affine surface of normal_vs_tamaas.py (Hurst 0.8, spectral rms
slope 1, E = 1, nu = 0.3), the exponential law with a hard wall, p = -(w / rho) exp(-g / rho),
rho = 0.1 rms height and a peak stress w / rho = 0.05 E*, at a mean gap of 2 rms heights
(displacement control).

* Tamaas: ``PolonskyKeerRey(model, s, 1e-10, gap, gap)`` + ``ExponentialAdhesionFunctional``
  (``rho``, ``surface_energy`` = w); ``solve(mean_gap)``; contact = nodes with zero gap.
* tribobem: ``solve_normal(op, max(s) - s, approach=max(s) - mean(s) - mean_gap,
  interaction=ExponentialAdhesion(w, rho))``, Polonsky-Keer and NormCG at tol 1e-10.

Compared: total force and contact area (target 1e-3), CPU time.  Tamaas is optional
(``pip install tamaas``); without it tribobem runs alone.

    python benchmarks/exponential_vs_tamaas.py [--sizes 256 512]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import E_STAR, L  # noqa: E402

RHO_OVER_RMS = 0.1
PEAK_OVER_ESTAR = 0.05
MEAN_GAP_OVER_RMS = 2.0


def main(argv=None) -> list[dict]:
    from tribobem.interactions.exponential import ExponentialAdhesion
    from tribobem.solvers.normal import solve_normal

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    args = ap.parse_args(argv)
    print("| n | solver | CPU s | iterations | force | contact area | force vs Tamaas | area vs Tamaas |")
    print("|---|---|---|---|---|---|---|---|")
    out = []
    for n in args.sizes:
        s, _ = common.make_surface(n)
        rms = float(s.std())
        rho = RHO_OVER_RMS * rms
        w = PEAK_OVER_ESTAR * E_STAR * rho
        mean_gap = MEAN_GAP_OVER_RMS * rms
        cell = (L / n) ** 2
        ref = None
        if common.HAVE_TAMAAS:
            tm = common.tm
            model = common.tamaas_model(n)
            solver = tm.PolonskyKeerRey(model, s, 1e-10, tm.PolonskyKeerRey.gap, tm.PolonskyKeerRey.gap)
            functional = tm.ExponentialAdhesionFunctional(s)
            functional.parameters = {"rho": rho, "surface_energy": w}
            solver.addFunctionalTerm(functional)
            solver.max_iter = 20000
            t = time.process_time()
            with common.capture_fd1() as log:
                solver.solve(mean_gap)
            cpu = time.process_time() - t
            p = np.array(model.traction, dtype=float).reshape(n, n)
            g = np.array(model.displacement, dtype=float).reshape(n, n) - s
            ref = (float(p.sum()) * cell, float(np.count_nonzero(g <= 1e-8 * rho)) * cell)
            print(f"| {n} | Tamaas | {cpu:.2f} | {common.tamaas_iterations(log['text'])} | {ref[0]:.6e} | {ref[1]:.6e} | | |",
                  flush=True)
        op = common.tribobem_operator(n, 1)
        for method in ("polonsky_keer", "normcg"):
            t = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = solve_normal(op, s.max() - s, approach=float(s.max() - s.mean()) - mean_gap,
                                 interaction=ExponentialAdhesion(w, rho), tol=1e-10, method=method, max_iterations=20000)
            cpu = time.process_time() - t
            dF = f"{r.force / ref[0] - 1:+.1e}" if ref else ""
            dA = f"{r.contact_area / ref[1] - 1:+.1e}" if ref else ""
            print(f"| {n} | tribobem {method} | {cpu:.2f} | {r.iterations} | {r.force:.6e} | {r.contact_area:.6e} "
                  f"| {dF} | {dA} |", flush=True)
            out.append({"n": n, "method": method, "force": r.force, "area": r.contact_area, "reference": ref})
    return out


if __name__ == "__main__":
    main()
