"""Paper B section 4.2: capillary force of a rough SiO2 surface against a rigid dry flat,
against relative humidity (L_ac, rms, realisations, 5000 uN, uniform vs levelled films).

    python examples/studies/paper_b.py                  # run (resumable) and gather
    python examples/studies/paper_b.py --no-run         # gather what is there
    python examples/studies/paper_b.py --quick          # 32^2 cells on 1.25 um, 5 cases x 3 RH (~1 min)
    python examples/studies/paper_b.py --publish        # ... and write docs/data, docs/figures

1. runs the sweep ``examples/studies/paper_b.toml`` (the same as
   ``studies.paper_b.sweep_spec()``; 14 cases, each a ``capillary`` run over 12 RH on
   256^2 cells) into ``--out`` (default ``results/paper_b``; resumable: finished cases are kept,
   ``--max-points`` runs at most that many of the missing ones).  The same as
   ``tribobem sweep examples/studies/paper_b.toml --out results/paper_b``;
2. gathers ``<out>/paper_b.csv`` (one row per case and RH), ``<out>/paper_b_findings.csv``
   (Paper B's findings beside ours, with a verdict) and ``<out>/paper_b.png``; with
   ``--publish`` (full study only) also ``docs/data/paper_b.csv``,
   ``docs/data/paper_b_findings.csv`` and ``docs/figures/paper_b.png``.

The choices Paper B leaves open (dgamma, z0, Hamaker constants, the flat's material) are listed
in :mod:`studies.paper_b`.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))
SWEEP = ROOT / "examples" / "studies" / "paper_b.toml"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=None,
                    help="results folder (default results/paper_b, or results/paper_b_quick with --quick)")
    ap.add_argument("--quick", action="store_true", help="small cell and few RH (a test of the machinery)")
    ap.add_argument("--no-run", action="store_true", help="only gather the cases already computed")
    ap.add_argument("--max-points", type=int, default=None, help="run at most this many missing cases")
    ap.add_argument("--publish", action="store_true",
                    help="also write docs/data/paper_b*.csv and docs/figures/paper_b.png (full study only)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the repository's published data: not from a --quick run")
    out = args.out or ROOT / "results" / ("paper_b_quick" if args.quick else "paper_b")

    from studies.paper_b import findings, gather, plot_study, sweep_spec
    from tribobem.sweep import run_sweep

    spec = sweep_spec(quick=True) if args.quick else SWEEP
    t0 = time.perf_counter()
    if not args.no_run:
        res = run_sweep(spec, out, scheduler="synchronous", progress=not args.quiet, max_points=args.max_points)
        if not args.quiet:
            print(f"sweep: {res.n_ok} of {res.n_points} cases ok, {res.n_failed} failed "
                  f"({time.perf_counter() - t0:.0f} s)")
    curves = gather(spec, out)
    table = findings(curves)
    out.mkdir(parents=True, exist_ok=True)
    import pandas as pd

    curves.to_csv(out / "paper_b.csv", index=False)
    pd.DataFrame(table).to_csv(out / "paper_b_findings.csv", index=False)
    label = "quick: 32^2 cells on 1.25 um" if args.quick else "256^2 cells on 10 um, 500 uN"
    plot_study(curves, out / "paper_b.png", title=f"Paper B 4.2 with tribobem ({label})")
    if args.publish:
        (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
        (ROOT / "docs" / "figures").mkdir(parents=True, exist_ok=True)
        shutil.copyfile(out / "paper_b.csv", ROOT / "docs" / "data" / "paper_b.csv")
        shutil.copyfile(out / "paper_b_findings.csv", ROOT / "docs" / "data" / "paper_b_findings.csv")
        shutil.copyfile(out / "paper_b.png", ROOT / "docs" / "figures" / "paper_b.png")
    if not args.quiet:
        for row in table:
            print(f"[{row['verdict']}] {row['paper']}\n    ours: {row['ours']}")
        print(f"wrote {out / 'paper_b.csv'}, {out / 'paper_b_findings.csv'} and {out / 'paper_b.png'}"
              + (" (and the docs/ copies)" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
