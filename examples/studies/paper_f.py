"""Paper F: pre-sliding of a rough polymer ball (HDPE, POM) on a silicon wafer: friction loops,
pressure and stick/slip maps, and the lateral stiffness K_L at A, B, C for F0 = 25, 50, 75 mN.

    python examples/studies/paper_f.py                 # 6 cases, 96^2, 96 steps/cycle, 4 cycles
    python examples/studies/paper_f.py --publish       # also docs/data/paper_f_stiffness.csv and
                                                       #   docs/figures/paper_f_loops.png
    python examples/studies/paper_f.py --quick         # 2 cases at 32^2, one cycle (< 1 min)

Every case is a ``hysteresis`` scenario (displacement control, Paper F Table 1 stroke and mu)
run into ``<out>/<material>_<F0>mN/`` (summary.json, fields.nc, figures, report.html; compare
it with a measured loop by ``tribobem compare-loop <out>/pom_50mN loop.csv``).  Finished cases
are read back when the command is repeated with the same parameters (``--force`` recomputes).
``<out>`` (default ``results/paper_f``) receives ``paper_f_stiffness.csv``, ``paper_f_cases.json``,
``paper_f_loops.png`` and ``paper_f_maps.png``.

The measured roughness: ``plu-1.plu``, shipped with tribobem (``tribobem.data``; Sensofar
confocal, 1.27 x 0.96 mm) stands in for the ball scans.  Its rms after removing the mean only (2.83 um) is a tilt
and the ball's form; with the best quadratic removed it is 18.2 nm.  The whole flattened scan is
scaled to Paper F Table 2's rms (3.17 um HDPE, 0.67 um POM) and its central window (320 um HDPE,
240 um POM: every contact of a 600 um normal-contact check lies inside) is resampled onto the
grid.  The grid and step count fit the compute budget of a 2-core machine (about 3 min per case
at 96^2); see :mod:`studies.paper_f` for every choice.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))

from studies import paper_f as pf


def _fmt(v, scale=1.0, spec=".4g"):
    try:
        v = float(v)
    except (TypeError, ValueError):
        return "-"
    return "-" if not math.isfinite(v) else format(v / scale, spec)


def print_table(records) -> None:
    print(f"{'case':14s} {'pt':2s} {'K_L fit':>9s} {'K_MD br.':>9s} {'Eq. 6':>9s} {'fit/MD':>7s}   "
          f"{'F_slide':>8s} {'/muF0':>6s} {'W_loop':>8s} {'W_MD':>8s} {'time':>6s}")
    print(f"{'':14s} {'':2s} {'kN/m':>9s} {'kN/m':>9s} {'kN/m':>9s} {'':>7s}   {'mN':>8s} {'':>6s} {'nJ':>8s} "
          f"{'nJ':>8s} {'s':>6s}")
    for r in records:
        for i, s in enumerate(r["stiffness"]):
            tail = (f"   {_fmt(r['sliding_force'], 1e-3):>8s} {_fmt(r['sliding_ratio'], 1, '.4f'):>6s} "
                    f"{_fmt(r['loop_energy'], 1e-9):>8s} {_fmt(r['mindlin_loop_energy'], 1e-9):>8s} "
                    f"{_fmt(r['wall_time'], 1, '.0f'):>6s}") if i == 0 else ""
            name = f"{r['material']} {r['load_mN']} mN" if i == 0 else ""
            print(f"{name:14s} {s['point']:2s} {_fmt(s['stiffness'], 1e3):>9s} {_fmt(s['mindlin_stiffness'], 1e3):>9s} "
                  f"{_fmt(s['eq6_stiffness'], 1e3):>9s} {_fmt(s['ratio_to_mindlin'], 1, '.3f'):>7s}{tail}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("results/paper_f"), help="output folder (default results/paper_f)")
    ap.add_argument("--publish", action="store_true",
                    help="also write docs/data/paper_f_stiffness.csv and docs/figures/paper_f_loops.png")
    ap.add_argument("--quick", action="store_true", help="HDPE and POM at 50 mN, 32^2, 80 steps, 1 cycle")
    ap.add_argument("--materials", nargs="+", default=None, choices=list(pf.MATERIALS))
    ap.add_argument("--loads", nargs="+", type=int, default=None, choices=list(pf.LOADS), help="F0 in mN")
    ap.add_argument("--n", type=int, default=None, help=f"cells per side (default {pf.N_DEFAULT})")
    ap.add_argument("--steps", type=int, default=None, help=f"steps per cycle (default {pf.STEPS_DEFAULT})")
    ap.add_argument("--cycles", type=int, default=None, help=f"displacement cycles (default {pf.CYCLES_DEFAULT})")
    ap.add_argument("--size", type=float, default=None, help="domain side in m (default: 320 um HDPE, 240 um POM)")
    ap.add_argument("--topography", type=Path, default=None, help="ball topography (default: plu-1.plu shipped with tribobem)")
    ap.add_argument("--force", action="store_true", help="recompute finished cases")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)

    quick = args.quick
    materials = args.materials or list(pf.MATERIALS)
    loads = args.loads or ([50] if quick else list(pf.LOADS))
    n = args.n or (32 if quick else pf.N_DEFAULT)
    steps = args.steps or (80 if quick else pf.STEPS_DEFAULT)
    cycles = args.cycles or (1 if quick else pf.CYCLES_DEFAULT)
    try:
        topo = args.topography or pf.default_topography()
    except FileNotFoundError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2

    def progress(done, total, rec):
        if not args.quiet:
            k = ", ".join(f"{s['point']} {_fmt(s['stiffness'], 1e3)}" for s in rec["stiffness"])
            print(f"[{done}/{total}] {rec['material']} {rec['load_mN']} mN: K_L (kN/m) {k}; "
                  f"{rec['wall_time']:.0f} s", flush=True)

    t0 = time.perf_counter()
    records = pf.paper_f_study(args.out, materials=materials, loads=loads, n=n, steps=steps, cycles=cycles,
                               size=args.size, topography=topo, force=args.force, progress=progress)
    rows = pf.stiffness_table(records)
    out = args.out
    pf.write_csv(rows, out / "paper_f_stiffness.csv")
    (out / "paper_f_cases.json").write_text(json.dumps(records, indent=1) + "\n", encoding="utf-8")
    pf.plot_loops(records, out / "paper_f_loops.png")
    maps = pf.plot_maps(records, out / "paper_f_maps.png")
    found = pf.findings(records)
    if args.publish:
        pf.write_csv(rows, ROOT / "docs" / "data" / "paper_f_stiffness.csv")
        pf.plot_loops(records, ROOT / "docs" / "figures" / "paper_f_loops.png")
    if not args.quiet:
        print_table(records)
        for r in records:
            print(f"{r['material']} {r['load_mN']} mN: Hertz a = {r['hertz_radius'] * 1e6:.1f} um, contact "
                  f"{_fmt(r['contact_area'], 1e-12, '.0f')} um^2 in {r['contact_cells']} cells (max r "
                  f"{_fmt(r['contact_radius_max'], 1e-6, '.0f')} um, {r['edge_margin_cells']} cells from the edge), "
                  f"p_max {_fmt(r['max_pressure'], 1e6, '.0f')} MPa; loop change between the last two cycles "
                  f"{_fmt(r['loop_change'], 1, '.1e')} mu F0; converged {r['converged']}"
                  + (f"; fit: {r['fit_error']}" if r.get("fit_error") else ""))
        print(f"K_L falls from A to C: {found['K_falls_A_to_C']}")
        print(f"POM stiffer than HDPE: {found['POM_stiffer_than_HDPE']}")
        print(f"wall {time.perf_counter() - t0:.0f} s; wrote {out / 'paper_f_stiffness.csv'}, "
              f"{out / 'paper_f_loops.png'}" + (f", {maps}" if maps else "")
              + ("; published docs/data/paper_f_stiffness.csv, docs/figures/paper_f_loops.png" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
