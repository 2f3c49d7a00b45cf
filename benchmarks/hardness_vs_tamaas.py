"""The hardness cap on a periodic rough surface: tribobem against Tamaas's ``KatoSaturated``.

Problem: the periodic self-affine surface of normal_vs_tamaas.py (Hurst 0.8, spectral rms
slope 1, E = 1, nu = 0.3) under a mean pressure of 0.05 E*, with the pressure capped at a
hardness H = 0.5, 1 and 2 E* (about half, 7 % and none of the contact plastic at 256^2).

* Tamaas: ``KatoSaturated(model, s, 1e-10, H)``; ``solve(mean pressure)``; contact = p > 0,
  plastic = p >= H (1 - 1e-9).
* tribobem: ``solve_normal(op, max(s) - s, force=..., interaction=HardnessCap(H), tol=1e-10)``
  (NormCG with the cap as its upper bound).

Compared: contact area, plastic area and total force (target 1e-3), CPU time.  Tamaas is
optional (``pip install tamaas``); without it tribobem runs alone.

    python benchmarks/hardness_vs_tamaas.py [--sizes 256 512]
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

MEAN_PRESSURE = 0.05  # x E*
HARDNESS = (0.5, 1.0, 2.0)  # x E*


def main(argv=None) -> list[dict]:
    from tribobem.interactions.hardness import HardnessCap
    from tribobem.solvers.normal import solve_normal

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512])
    args = ap.parse_args(argv)
    print("| n | H / E* | solver | CPU s | contact area | plastic area | force | area vs Tamaas | plastic vs Tamaas |")
    print("|---|---|---|---|---|---|---|---|---|")
    out = []
    for n in args.sizes:
        s, _ = common.make_surface(n)
        cell = (L / n) ** 2
        pbar = MEAN_PRESSURE * E_STAR
        op = common.tribobem_operator(n, 1)
        for h_rel in HARDNESS:
            H = h_rel * E_STAR
            ref = None
            if common.HAVE_TAMAAS:
                tm = common.tm
                model = common.tamaas_model(n)
                solver = tm.KatoSaturated(model, s, 1e-10, H)
                solver.max_iter = 50000
                t = time.process_time()
                with common.capture_fd1():
                    solver.solve(pbar)
                cpu = time.process_time() - t
                p = np.array(model.traction, dtype=float).reshape(n, n)
                ref = (float(np.count_nonzero(p > 0)) * cell, float(np.count_nonzero(p >= H * (1 - 1e-9))) * cell,
                       float(p.sum()) * cell)
                print(f"| {n} | {h_rel:g} | Tamaas KatoSaturated | {cpu:.2f} | {ref[0]:.6e} | {ref[1]:.6e} | {ref[2]:.6e} | | |",
                      flush=True)
            t = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = solve_normal(op, s.max() - s, force=pbar * L * L, interaction=HardnessCap(H), tol=1e-10,
                                 max_iterations=20000)
            cpu = time.process_time() - t
            dA = f"{r.contact_area / ref[0] - 1:+.1e}" if ref else ""
            dP = f"{r.plastic_area / ref[1] - 1:+.1e}" if ref and ref[1] > 0 else ""
            print(f"| {n} | {h_rel:g} | tribobem | {cpu:.2f} | {r.contact_area:.6e} | {r.plastic_area:.6e} | {r.force:.6e} "
                  f"| {dA} | {dP} |", flush=True)
            out.append({"n": n, "hardness": H, "area": r.contact_area, "plastic_area": r.plastic_area,
                        "converged": r.converged, "reference": ref})
    return out


if __name__ == "__main__":
    main()
