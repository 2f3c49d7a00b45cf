"""Colloidal-probe pull-off on measured substrates, five spots per file (thesis Paper C, Fig. 5).

A smooth SiO2 sphere (R = 2.5 um) on Si with Dugdale adhesion (dgamma = 88 mJ/m^2, z0 = 0.3 nm,
vacuum: no water), unloaded from a 100 nN preload on five non-overlapping windows ("spots")
of each measured scan shipped with tribobem (``tribobem.data``):

* Park AFM ``example_ps.tiff`` (1 um, 512^2, rms 3.9 nm): windows of 1/3 um at the scan's
  own pixel (1.95 nm);
* Asylum AFM ``spot_1-1000nm.ibw`` (20 um, 256^2, pixel 78 nm): windows of 6 pixels
  (0.47 um) spread over the scan, resampled (bilinear) to 256^2 so that dx = 1.8 nm resolves
  the probe's cohesive zone (at pull-off a = 26 nm, c - a = 17 nm: at dx = 7.7 nm, i.e. 2 um
  windows on 256^2, the smooth probe's pull-off is 22 % above Maugis-Dugdale), each with its
  best plane removed ("height"), and once more with the tilt kept (mean removed only,
  "center"): the 89 nm rms of the file is almost all tilt (9.5 nm without the plane), which
  moves the probe's first touch by slope x R but does not change the mean pull-off beyond its
  spread.  The scan's 78 nm pixel is larger than the contact: below it the window is a
  bilinear interpolation, so these spots measure the scan's long-wavelength shape, not its
  (unmeasured) nanometre roughness.

    python examples/studies/afm_pulloff.py             # full (~2-4 min of one core) -> results/afm_pulloff/
    python examples/studies/afm_pulloff.py --publish   # ... and the published docs/ copies
    python examples/studies/afm_pulloff.py --quick     # small windows, coarse grids (< 20 s)

Writes ``<out>/data/afm_pulloff.csv`` (one row per spot), ``<out>/data/afm_pulloff_summary.csv``
(mean, std and references per case) and ``<out>/figures/afm_pulloff.png`` (``<out>`` =
``--out``, default ``results/afm_pulloff``; ``--quick`` adds ``_quick``).  The repository's
published files (``docs/data/afm_pulloff*.csv``, ``docs/figures/afm_pulloff.png``) are written
only with ``--publish`` (not with ``--quick``).  The data folder is
:func:`tribobem.data.topography_dir` (the files shipped with the package; ``TRIBOBEM_DATA_DIR``
replaces it), or ``--data``.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))

from studies.afm_pulloff import afm_pull_off_spots
from tribobem.data import topography_dir
from tribobem.errors import ConvergenceWarning


def data_dir() -> Path:
    """The folder of the measured files: tribobem's data folder (``TRIBOBEM_DATA_DIR`` replaces it)."""
    return topography_dir()


def cases(quick: bool) -> list[dict]:
    """(label, file, options) of each bar of the figure."""
    if quick:
        return [
            {"label": "Park .tiff", "file": "example_ps.tiff", "window": 0.125e-6, "n": 32},
            {"label": "Asylum .ibw", "file": "spot_1-1000nm.ibw", "window": 0.5e-6, "n": 32},
        ]
    return [
        {"label": "Park .tiff\n(1/3 um, native 1.95 nm)", "file": "example_ps.tiff", "window": None, "n": None},
        {"label": "Asylum .ibw\n(0.47 um -> 256$^2$, plane removed)", "file": "spot_1-1000nm.ibw", "window": 0.5e-6,
         "n": 256},
        {"label": "Asylum .ibw\n(0.47 um -> 256$^2$, tilt kept)", "file": "spot_1-1000nm.ibw", "window": 0.5e-6,
         "n": 256, "window_detrend": "center"},
    ]


def plot(results, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    ref = results[0][1]
    for i, (case, res) in enumerate(results):
        f = -res.table["pull_off_force"].to_numpy() * 1e9
        ax.errorbar([i], [-res.mean * 1e9], yerr=[res.std * 1e9], fmt="o", color="C3", ms=8, capsize=6,
                    label="mean $\\pm$ std over spots" if i == 0 else None)
        ax.plot(i + 0.12 + np.zeros_like(f), f, "x", color="C0", label="single spots" if i == 0 else None)
        ax.plot([i - 0.3, i + 0.3], [-res.smooth * 1e9] * 2, color="k", lw=2,
                label="smooth sphere, same grid" if i == 0 else None)
        ax.annotate(f"{-res.mean * 1e9:.3g} $\\pm$ {res.std * 1e9:.2g} nN", (i - 0.08, -res.mean * 1e9),
                    ha="right", va="center", fontsize=7)
    ax.axhline(-ref.dmt * 1e9, color="C2", ls="--", label=r"DMT $2\pi R\Delta\gamma$")
    ax.axhline(-ref.jkr * 1e9, color="C1", ls="-.", label=r"JKR $1.5\pi R\Delta\gamma$")
    ax.axhline(-ref.maugis_dugdale * 1e9, color="C4", ls=":",
               label=f"Maugis-Dugdale ($\\lambda$ = {ref.info['maugis']:.2f})")
    ax.set_xticks(range(len(results)), [c["label"] for c, _ in results], fontsize=8)
    ax.set_yscale("log")
    ax.set_ylim(bottom=min(3.0, 0.3 * min(-r.table["pull_off_force"].max() * 1e9 for _, r in results)))
    ax.set_ylabel("|pull-off force| (nN)")
    ax.set_xlim(-0.6, len(results) - 0.4)
    ax.grid(alpha=0.3, which="both", axis="y")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_title(r"SiO$_2$ probe R = 2.5 $\mu$m on Si, $\Delta\gamma$ = 88 mJ/m$^2$, $z_0$ = 0.3 nm, "
                 "preload 100 nN (vacuum, Paper C)", fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="small windows on coarse grids")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "afm_pulloff",
                    help="output folder (default results/afm_pulloff)")
    ap.add_argument("--publish", action="store_true",
                    help="also copy the tables and the figure to docs/data/ and docs/figures/ (full study only)")
    ap.add_argument("--data", type=Path, default=None, help="folder of the measured files")
    ap.add_argument("--spots", type=int, default=5)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the full study into docs/: not with --quick")
    folder = args.data or data_dir()
    if not folder.is_dir():
        print(f"data folder {folder} not found (set TRIBOBEM_DATA_DIR)", file=sys.stderr)
        return 2
    suffix = "_quick" if args.quick else ""
    import pandas as pd

    results, rows, summary = [], [], []
    t0, c0 = time.perf_counter(), time.process_time()
    for case in cases(args.quick):
        c1 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = afm_pull_off_spots(folder / case["file"], n_spots=args.spots, window=case["window"], n=case["n"],
                                     window_detrend=case.get("window_detrend", "height"))
        label = case["label"].replace("\n", " ").replace("$^2$", "^2")
        results.append((case, res))
        t = res.table.copy()
        t.insert(0, "case", label)
        t.insert(1, "file", case["file"])
        rows.append(t)
        s = res.summary()
        s.update({"case": label, "window_detrend": res.info["window_detrend"], "n": res.info["solver_grid"].nx,
                  "dx": res.info["solver_grid"].dx, "scan_rms": res.info["scan_rms"],
                  "scan_rms_plane_removed": res.info["scan_rms_plane_removed"], "tabor": res.info["tabor"],
                  "maugis": res.info["maugis"], "cpu_time": time.process_time() - c1})
        summary.append(s)
        if not args.quiet:
            print(f"{label}: mean {res.mean * 1e9:.2f} nN, std {res.std * 1e9:.2f} nN over {len(t)} spots; smooth "
                  f"same grid {res.smooth * 1e9:.1f} nN, MD {res.maugis_dugdale * 1e9:.1f}, DMT {res.dmt * 1e9:.1f}, "
                  f"JKR {res.jkr * 1e9:.1f} nN  ({s['cpu_time']:.1f} s CPU)", flush=True)
    data = args.out / "data"
    data.mkdir(parents=True, exist_ok=True)
    table = pd.concat(rows, ignore_index=True)
    table.to_csv(data / f"afm_pulloff{suffix}.csv", index=False)
    first = ["case", "file", "n_spots", "window", "n", "dx", "window_detrend", "mean", "std", "min", "max",
             "smooth", "maugis_dugdale", "dmt", "jkr", "mean_over_smooth", "mean_rms", "scan_rms",
             "scan_rms_plane_removed", "tabor", "maugis", "cpu_time"]
    pd.DataFrame(summary)[first].to_csv(data / f"afm_pulloff_summary{suffix}.csv", index=False)
    plot(results, args.out / "figures" / f"afm_pulloff{suffix}.png")
    published = publish(args.out) if args.publish else []
    if not args.quiet:
        with pd.option_context("display.width", 220, "display.max_columns", 30, "display.precision", 4):
            print(table[["case", "spot", "x0", "y0", "rms", "rms_slope", "pull_off_force", "pull_off_over_dmt",
                         "contact_area", "edge_contact", "converged"]].to_string(index=False))
        print(f"wall {time.perf_counter() - t0:.1f} s, CPU {time.process_time() - c0:.1f} s; wrote "
              f"{data / f'afm_pulloff{suffix}.csv'} and {args.out / 'figures' / f'afm_pulloff{suffix}.png'}"
              + (f"; published {', '.join(map(str, published))}" if published else ""))
    return 0


def publish(out: Path) -> list[Path]:
    """Copy the full study's tables and figure from ``out`` into docs/ (the published files)."""
    copies = [(out / "data" / "afm_pulloff.csv", ROOT / "docs" / "data" / "afm_pulloff.csv"),
              (out / "data" / "afm_pulloff_summary.csv", ROOT / "docs" / "data" / "afm_pulloff_summary.csv"),
              (out / "figures" / "afm_pulloff.png", ROOT / "docs" / "figures" / "afm_pulloff.png")]
    for src, dest in copies:
        if src.resolve() != dest.resolve():  # --out docs --publish: already there
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, dest)
    return [dest for _, dest in copies]


if __name__ == "__main__":
    sys.exit(main())
