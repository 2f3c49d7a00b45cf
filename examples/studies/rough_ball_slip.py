"""Smooth ball on the Hu-Tonder rough flat under a tangential ramp (thesis Paper D section 3.2):
stick-ratio curves, static friction, pre-sliding displacement and F0+ against the rms, for a
non-adhesive contact and mu_T = 0.5, 1, 2.

    python examples/studies/rough_ball_slip.py                 # run (resumable) and gather
    python examples/studies/rough_ball_slip.py --no-run        # gather what is there
    python examples/studies/rough_ball_slip.py --publish       # ... and write docs/ outputs

1. writes the 10 um flat to ``results/rough_ball_slip_flat.npy`` (once; the base scenario
   reads it through a relative path, so it lives at that fixed place whatever ``--out`` is);
2. runs the sweep ``examples/studies/rough_ball_slip.toml`` into ``--out`` (default
   ``results/rough_ball_slip``; resumable: finished points are kept, ``--max-points`` runs at
   most that many of the missing ones).  The same as
   ``tribobem sweep examples/studies/rough_ball_slip.toml --out results/rough_ball_slip``;
3. gathers ``<out>/rough_ball_slip.csv`` (one row per point), ``<out>/rough_ball_slip_curves.csv``
   (the ramps) and ``<out>/rough_ball_slip.png``; with ``--publish`` also
   ``docs/data/rough_ball_slip.csv``, ``docs/data/rough_ball_slip_curves.csv`` and
   ``docs/figures/rough_ball_slip.png``;
4. scans F0+ against the rms with normal solves alone (denser rms, ~1-2 min):
   ``<out>/rough_ball_slip_f0_scan.csv`` (and ``docs/data/`` with ``--publish``; thin lines in panel d);
5. tracks the stick zone of the smooth ball along a ramp (non-adhesive and mu_T = 0.5; 128^2
   cells on the central 1.25 um, ~1 min): ``<out>/rough_ball_slip_stick_zone.csv`` (and
   ``docs/data/`` with ``--publish``), for Paper D's "dragged to the rear, shrinking" check.

The full sweep (29 points, 256^2 cells) takes about an hour of one core.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))
SWEEP = ROOT / "examples" / "studies" / "rough_ball_slip.toml"
FLAT = ROOT / "results" / "rough_ball_slip_flat.npy"
#: Stick-zone tracks (Paper D Fig. 3) on the smooth ball: 128^2 cells on the central 1.25 um
#: (the same 9.77 nm cells; the smooth contact and cohesive zone stay within +-0.34 um), ramps
#: below the onset.  label -> (work of adhesion or None, tangential forces).
TRACKS = {
    "smooth, non-adhesive": (None, ["0 uN", "0.4 uN", "0.8 uN", "1.2 uN", "1.5 uN", "1.7 uN", "1.8 uN"]),
    "smooth, mu_T = 0.5": ("14.2857 mJ/m^2", ["0 uN", "0.8 uN", "1.6 uN", "2.4 uN", "3.2 uN", "3.6 uN", "3.9 uN"]),
}


#: Flat rms (m) of the F0+ scan (normal solves alone, no friction; ~1-2 min).
SCAN_RMS = [0.0, 0.1e-9, 0.175e-9, 0.25e-9, 0.35e-9, 0.5e-9, 0.7e-9, 1e-9, 1.5e-9, 2.5e-9, 5e-9]
SCAN_TABOR = [0.5, 1.0, 2.0]


def stick_zone_tracks(quiet: bool = False) -> dict:
    """Run the TRACKS on the study's base scenario (smooth flat, 128^2 on 1.25 um)."""
    import tomllib

    from studies.rough_slip import stick_zone_track

    base_file = ROOT / "examples" / "studies" / "rough_ball_slip_base.toml"
    out = {}
    for label, (dgamma, forces) in TRACKS.items():
        scn = tomllib.loads(base_file.read_text(encoding="utf-8"))
        scn["grid"] = {"n": 128, "size": "1.25 um"}
        scn["body1"]["roughness"].update(rms="0 nm", crop={"x0": "4.375 um", "y0": "4.375 um",
                                                           "lx": "1.25 um", "ly": "1.25 um"})
        if dgamma is not None:
            scn["adhesion"].update(model="dugdale", work_of_adhesion=dgamma)
        scn["friction"]["tangential_forces"] = forces
        t0 = time.perf_counter()
        out[label] = stick_zone_track(scn, base_dir=base_file.parent)
        if not quiet:
            print(f"stick-zone track '{label}': {len(out[label])} steps ({time.perf_counter() - t0:.0f} s)")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "rough_ball_slip",
                    help="sweep results folder (default results/rough_ball_slip)")
    ap.add_argument("--sweep", type=Path, default=SWEEP, help="sweep file (default: the study's)")
    ap.add_argument("--no-run", action="store_true", help="only gather the points already computed")
    ap.add_argument("--max-points", type=int, default=None, help="run at most this many missing points")
    ap.add_argument("--publish", action="store_true",
                    help="also write docs/data/rough_ball_slip*.csv and docs/figures/rough_ball_slip.png")
    ap.add_argument("--no-track", action="store_true", help="skip the smooth-ball stick-zone tracks (~1 min)")
    ap.add_argument("--no-scan", action="store_true", help="skip the dense F0+ scan of normal solves (~1-2 min)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)

    from studies.rough_slip import (gather, paper_d_checks, plot_study, repulsive_force_scan,
                                             study_table, work_of_adhesion, write_flat)
    from tribobem.sweep import run_sweep

    if not FLAT.is_file():
        info = write_flat(FLAT)
        if not args.quiet:
            print(f"wrote {FLAT}: beta = {info['correlation_length'] * 1e6:.3f} um, rms slope "
                  f"{info['rms_slope']:.4f} at rms {info['rms'] * 1e9:g} nm")
    t0 = time.perf_counter()
    if not args.no_run:
        res = run_sweep(args.sweep, args.out, scheduler="synchronous", progress=not args.quiet,
                        max_points=args.max_points)
        if not args.quiet:
            print(f"sweep: {res.n_ok} of {res.n_points} points ok, {res.n_failed} failed "
                  f"({time.perf_counter() - t0:.0f} s)")
    table, curves = gather(args.sweep, args.out)
    tab = study_table(table)
    args.out.mkdir(parents=True, exist_ok=True)
    tab.to_csv(args.out / "rough_ball_slip.csv", index=False)
    curves.to_csv(args.out / "rough_ball_slip_curves.csv", index=False)
    tracks = {}
    if not args.no_track:
        import pandas as pd

        tracks = stick_zone_tracks(args.quiet)
        tr = pd.concat([df.assign(case=label) for label, df in tracks.items()], ignore_index=True)
        tr.to_csv(args.out / "rough_ball_slip_stick_zone.csv", index=False)
        if args.publish:
            (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
            tr.to_csv(ROOT / "docs" / "data" / "rough_ball_slip_stick_zone.csv", index=False)
    scan = None
    if not args.no_scan:
        import tomllib

        base_file = ROOT / "examples" / "studies" / "rough_ball_slip_base.toml"
        t1 = time.perf_counter()
        scan = repulsive_force_scan(tomllib.loads(base_file.read_text(encoding="utf-8")), SCAN_RMS,
                                    [work_of_adhesion(m) for m in SCAN_TABOR], base_dir=base_file.parent)
        scan.to_csv(args.out / "rough_ball_slip_f0_scan.csv", index=False)
        if not args.quiet:
            print(f"F0+ scan: {len(scan)} normal solves ({time.perf_counter() - t1:.0f} s)")
    plot_study(table, curves, args.out / "rough_ball_slip.png", scan=scan)
    if args.publish:
        (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
        tab.to_csv(ROOT / "docs" / "data" / "rough_ball_slip.csv", index=False)
        curves.to_csv(ROOT / "docs" / "data" / "rough_ball_slip_curves.csv", index=False)
        if scan is not None:
            scan.to_csv(ROOT / "docs" / "data" / "rough_ball_slip_f0_scan.csv", index=False)
        plot_study(table, curves, ROOT / "docs" / "figures" / "rough_ball_slip.png", scan=scan)

    if not args.quiet:
        import pandas as pd

        show = tab.copy()
        show["rms_nm"] = show["rms"] * 1e9
        show["F0+_uN"] = show["repulsive_force"] * 1e6
        show["F0-_uN"] = show["adhesive_force"] * 1e6
        show["delta_nm"] = show["presliding_displacement"] * 1e9
        show["a_nm"] = show["contact_radius"] * 1e9
        show["ext_nm"] = show["interaction_extent"] * 1e9
        cols = ["tabor", "rms_nm", "F0+_uN", "F0-_uN", "static_friction_ratio", "delta_nm",
                "zero_force_stick_ratio", "a_nm", "cohesive_zone_cells", "ext_nm", "edge_margin_cells",
                "status", "elapsed"]
        with pd.option_context("display.width", 220, "display.max_columns", 30, "display.precision", 4):
            print(show[cols].to_string(index=False))
        for c in paper_d_checks(table, curves, tracks, scan):
            print(f"[{c['verdict']}] {c['finding']}: {c['detail']}")
        print(f"wrote {args.out / 'rough_ball_slip.csv'} and {args.out / 'rough_ball_slip.png'}"
              + (" (and the docs/ copies)" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
