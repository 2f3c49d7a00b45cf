"""The Contact Mechanics Challenge's adhesive case, scaled to fit one machine.

The challenge (Mueser et al., Tribol. Lett. 65:118, 2017) presses a periodic self-affine surface
(Hurst 0.8, rms gradient 1, roll-off at lambda_r and a short-wavelength cut at lambda_s) onto
an elastic half-space of contact modulus E* = 25 MPa at a mean pressure of 0.01 E*, with an
exponential adhesion of work w = 50 mJ/m^2 and range rho = 2.071 nm and a hard wall
(tribobem's ``[adhesion] model = "exponential"``).  Its surface spans L / lambda_s = 1000 and
needs 32768^2 points.  Here the physical groups that set the contact at the small scales are
kept: the Hurst exponent, the rms gradient, lambda_s (0.1 um), w, rho, E* and the pressure
0.01 E*; the band of wavelengths is cut to L / lambda_s = 8 (lambda_r = L / 2), so that the grid
can resolve lambda_s and rho.  The grid study refines the cell from lambda_s / 16 to lambda_s /
64 on the same surface (the same random phases, interpolated spectrally: one surface, three
samplings).

Reported per grid: relative contact area (nodes with g = 0), adhesive force (sum of p < 0) over
the load, adhesive area (g < rho) and the cell ratio C w / rho^2 (one equilibrium per node
below 1).  A scaled band is not the challenge's surface: the numbers are this problem's, to
be compared between grids, not with the challenge's published areas.

    python studies/cmc_adhesive.py [--refinements 16 32 64] [--csv docs/data/cmc_adhesive.csv]
"""

from __future__ import annotations

import argparse
import csv
import time
import warnings

import numpy as np

from tribobem.elasticity import periodic_operator
from tribobem.elasticity.bodies.halfspace import halfspace_self_compliance
from tribobem.grid import Grid
from tribobem.interactions.exponential import ExponentialAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers.normal import solve_normal

E_STAR = 25e6
W = 0.05
RHO = 2.071e-9
LAMBDA_S = 0.1e-6
BAND = 8  # L / lambda_s
HURST = 0.8
PRESSURE = 0.01 * E_STAR
SEED = 11


def surface(n: int) -> np.ndarray:
    """The scaled challenge surface on n^2 points: one set of random phases for every n (the
    coarser grids sample the same spectrum), rms gradient 1 (m)."""
    L = BAND * LAMBDA_S
    rng = np.random.default_rng(SEED)
    m = 8 * BAND  # the modes kept: |k| <= L / lambda_s, drawn on a fixed 2m x 2m lattice
    kx = np.fft.fftfreq(2 * m, 1.0 / (2 * m))
    KX, KY = np.meshgrid(kx, kx, indexing="ij")
    k = np.hypot(KX, KY)
    amp = np.where((k > 0) & (k <= BAND), np.maximum(k, 2.0) ** (-(1.0 + HURST)), 0.0)
    spec_small = amp * np.exp(2j * np.pi * rng.random(k.shape))
    spec = np.zeros((n, n), complex)
    idx = np.fft.fftfreq(n, 1.0 / n).astype(int)
    sel = np.abs(idx) < m
    ii = idx[sel] % (2 * m)
    spec[np.ix_(sel, sel)] = spec_small[np.ix_(ii, ii)]
    z = np.fft.ifft2(spec).real
    # scale to rms gradient 1 on the spectrum
    q = 2 * np.pi * np.fft.fftfreq(n, L / n)
    QX, QY = np.meshgrid(q, q, indexing="ij")
    zf = np.fft.fft2(z) / n**2
    g_rms = float(np.sqrt(np.sum((QX**2 + QY**2) * np.abs(zf) ** 2)))
    return z / g_rms


def solve(refinement: int, method: str = "normcg") -> dict:
    n = BAND * refinement
    L = BAND * LAMBDA_S
    grid = Grid.square(n, L, periodic=True)
    pair = ContactPair(Material(E_STAR, 0.0), Material.rigid())
    op = periodic_operator(grid, pair)
    z = surface(n)
    law = ExponentialAdhesion(W, RHO)
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = solve_normal(op, z.max() - z, force=PRESSURE * L * L, interaction=law, tol=1e-8, method=method,
                         max_iterations=20000)
    cpu = time.process_time() - t
    c = halfspace_self_compliance(grid.dx, grid.dy, E_STAR)
    return {"refinement": refinement, "n": n, "dx": grid.dx, "cell_ratio": law.cell_ratio(c), "method": method,
            "converged": r.converged, "iterations": r.iterations, "cpu": cpu,
            "contact_fraction": r.contact_fraction, "adhesive_over_load": r.adhesive_force / (PRESSURE * L * L),
            "adhesive_fraction": r.adhesive_area / grid.area, "mean_gap_over_rho": r.mean_gap / RHO}


def main(argv=None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--refinements", type=int, nargs="+", default=[16, 32, 64])
    ap.add_argument("--csv", default=None)
    args = ap.parse_args(argv)
    rows = []
    print("| lambda_s / dx | n | C w / rho^2 | solver | converged (iterations) | contact area | adhesive force / load "
          "| adhesive area | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k in args.refinements:
        for method in ("polonsky_keer", "normcg"):
            r = solve(k, method)
            rows.append(r)
            print(f"| {k} | {r['n']} | {r['cell_ratio']:.2f} | {method} | {r['converged']} ({r['iterations']}) "
                  f"| {100 * r['contact_fraction']:.3f} % | {r['adhesive_over_load']:+.4f} "
                  f"| {100 * r['adhesive_fraction']:.3f} % | {r['cpu']:.1f} |", flush=True)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    return rows


if __name__ == "__main__":
    main()
