"""Paper C: pull-off of a SiO2 colloidal probe (R = 2.5 um, the "5 um probe" read as a
diameter) on Si and SiO2 flats at 35 % RH (with Paper C's contribution coefficient) and in
vacuum (no water), on five spots of the Park AFM scan scaled to Paper C's rms (0.46 nm Si,
0.74 nm SiO2): mean and spread per substrate and state, like Paper C Fig. 5.

    python examples/studies/paper_c.py                 # run (resumable) and gather
    python examples/studies/paper_c.py --no-run        # gather what is there
    python examples/studies/paper_c.py --quick         # two spots resampled to 48^2 (a test)
    python examples/studies/paper_c.py --publish       # ... and write docs/data, docs/figures

Writes ``<out>/paper_c.csv`` (one row per spot, substrate and state),
``<out>/paper_c_summary.csv`` (mean and spread) and ``<out>/paper_c.png`` into ``--out``
(default ``results/paper_c``); with ``--publish`` (full study only) also
``docs/data/paper_c.csv``, ``docs/data/paper_c_summary.csv`` and ``docs/figures/paper_c.png``.
Uses the measured scan ``example_ps.tiff`` shipped with tribobem (``tribobem.data``; another one
with ``--scan``).  The
set-up and what stands in for what is in :mod:`studies.paper_c`.
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


def main(argv=None) -> int:
    from studies.paper_c import PARK_SCAN

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=None,
                    help="results folder (default results/paper_c, or results/paper_c_quick with --quick)")
    ap.add_argument("--scan", type=Path, default=PARK_SCAN, help="the stand-in topography (Park .tiff)")
    ap.add_argument("--quick", action="store_true", help="two spots on 48^2 cells (a test of the machinery)")
    ap.add_argument("--no-run", action="store_true", help="only gather the points already computed")
    ap.add_argument("--max-points", type=int, default=None, help="run at most this many missing points")
    ap.add_argument("--publish", action="store_true",
                    help="also write docs/data/paper_c*.csv and docs/figures/paper_c.png (full study only)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the repository's published data: not from a --quick run")
    if not args.scan.is_file():
        ap.error(f"the measured scan {args.scan} is not there (tribobem.data.topography_path; "
                 f"TRIBOBEM_DATA_DIR replaces the shipped folder)")
    out = args.out or ROOT / "results" / ("paper_c_quick" if args.quick else "paper_c")

    from studies.paper_c import gather, plot_study, summary_table, sweep_spec
    from tribobem.sweep import run_sweep

    spec = sweep_spec(args.scan, quick=args.quick)
    t0 = time.perf_counter()
    if not args.no_run:
        res = run_sweep(spec, out, scheduler="synchronous", progress=not args.quiet, max_points=args.max_points)
        if not args.quiet:
            print(f"sweep: {res.n_ok} of {res.n_points} points ok, {res.n_failed} failed "
                  f"({time.perf_counter() - t0:.0f} s)")
    table = gather(spec, out)
    summ = summary_table(table)
    out.mkdir(parents=True, exist_ok=True)
    table.to_csv(out / "paper_c.csv", index=False)
    summ.to_csv(out / "paper_c_summary.csv", index=False)
    if not summ.empty:
        plot_study(table, out / "paper_c.png")
    if args.publish:
        for name, folder in (("paper_c.csv", "data"), ("paper_c_summary.csv", "data"), ("paper_c.png", "figures")):
            if (out / name).exists():
                (ROOT / "docs" / folder).mkdir(parents=True, exist_ok=True)
                shutil.copyfile(out / name, ROOT / "docs" / folder / name)
    if not args.quiet:
        for r in summ.itertuples():
            print(f"{r.substrate:5s} {r.state:8s}: pull-off {r.mean * 1e9:8.2f} +- {r.std * 1e9:6.2f} nN over "
                  f"{r.n_spots} spots (rms {r.mean_rms * 1e9:.3g} nm; smooth DMT {r.dmt * 1e9:.0f} nN)")
        s = {(r.substrate, r.state): r.mean for r in summ.itertuples()}
        for state in ("35 % RH", "vacuum"):
            if ("Si", state) in s and ("SiO2", state) in s:
                verdict = "above" if abs(s[("Si", state)]) > abs(s[("SiO2", state)]) else "NOT above"
                print(f"{state}: Si comes out {verdict} SiO2 (Paper C predicts above)")
        print(f"wrote {out / 'paper_c.csv'}, {out / 'paper_c_summary.csv'} and {out / 'paper_c.png'}"
              + (" (and the docs/ copies)" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
