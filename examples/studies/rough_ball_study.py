"""Smooth ball on a Gaussian rough flat: pull-off and adhesive force versus roughness rms
(thesis Paper A section 7, Figs. 9 and 11; Paper D section 3.2).

    python examples/studies/rough_ball_study.py             # full study (~10 min of one core) -> results/rough_ball/
    python examples/studies/rough_ball_study.py --publish   # ... and the published docs/ copies
    python examples/studies/rough_ball_study.py --quick     # tiny grid, 3 rms values (< 20 s)

Writes ``<out>/data/rough_ball.csv``, ``<out>/data/rough_ball.nc`` and
``<out>/figures/rough_ball_pulloff.png`` (``<out>`` = ``--out``, default ``results/rough_ball``;
``--quick`` adds the suffix ``_quick`` to the file names).  The repository's published files
(``docs/data/rough_ball<suffix>.csv``, ``docs/figures/rough_ball_pulloff<suffix>.png``) are
written only with ``--publish`` (not with ``--quick``); the NetCDF file stays in ``<out>``.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))

from studies.rough_ball import peak_summary, rough_ball_study, study_table

Z0 = 0.25e-9
FULL_RMS_OVER_Z0 = [0, 0.25, 0.5, 1, 2, 4, 10, 20, 50, 100]
QUICK_RMS_OVER_Z0 = [0, 2, 20]
#: The area ratio of contacts smaller than this many cells is not plotted (not resolved).
MIN_CONTACT_CELLS = 10


def plot(ds, path: Path) -> None:
    """Two panels: (a) |pull-off| vs rms/z0 (Paper A Fig. 9); (b) -F0-/F0 and the area
    ratio vs rms/z0 (Paper A Fig. 11)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = ds["rms_over_z0"].values
    xmin = x[x > 0].min() if np.any(x > 0) else 1.0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.9))
    colors = {1.0: "C0", 2.0: "C3"}
    cell = ds.attrs["dx"] ** 2
    for mu in ds["tabor"].values:
        c = colors.get(float(mu), None)
        sel = ds.sel(tabor=mu)
        ax1.plot(x, -sel["pull_off_force"].values * 1e6, "o-", color=c, label=rf"$\mu_T$ = {mu:g}")
        # grid floor: one cell at -sigma0 (the pull-off of a single-cell asperity)
        ax1.axhline(float(sel["sigma0"]) * cell * 1e6, color=c, ls="-", lw=3, alpha=0.15)
        ax1.axhline(-float(sel["md_pull_off"]) * 1e6, color=c, ls=":", lw=1)
        ax1.axhline(-float(sel["dmt_pull_off"]) * 1e6, color=c, ls="--", lw=0.8, alpha=0.6)
        ax1.axhline(-float(sel["jkr_pull_off"]) * 1e6, color=c, ls="-.", lw=0.8, alpha=0.6)
        ax2.plot(x, -sel["adhesive_force_ratio"].values, "o-", color=c, label=rf"$-F_0^-/F_0$, $\mu_T$ = {mu:g}")
    ax2b = ax2.twinx()
    for mu in ds["tabor"].values:
        c = colors.get(float(mu), None)
        ratio = ds["area_ratio"].sel(tabor=mu).values.copy()
        ratio[ds["contact_area"].sel(tabor=mu).values < MIN_CONTACT_CELLS * cell] = np.nan
        ax2b.plot(x, ratio, "s--", color=c, mfc="none", label=rf"area ratio, $\mu_T$ = {mu:g}")
    for ax in (ax1, ax2):
        ax.set_xscale("symlog", linthresh=xmin)
        ax.set_xlim(0, x.max() * 1.3)
        ax.set_xlabel(r"roughness rms / $z_0$  (0 = smooth ball)")
        ax.grid(alpha=0.3, which="both")
    ax1.set_yscale("log")
    ax1.set_ylabel(r"|pull-off force|  ($\mu$N)")
    ax1.set_title("(a) pull-off; smooth ball: MD ':', DMT '--', JKR '-.';\n"
                  r"wide pale line: one cell at $-\sigma_0$ (grid floor)", fontsize=9)
    ax1.legend(fontsize=8)
    ax2.set_ylabel(r"$-F_0^-/F_0$ (adhesive force at $F_0$ = 10 $\mu$N)")
    ax2b.set_ylabel(r"area ratio  $A(p<0)/A_c$")
    ax2.set_title(r"(b) adhesive force (filled) and area ratio (open squares) at $F_0$;" "\n"
                  f"area ratio shown where the contact has >= {MIN_CONTACT_CELLS} cells", fontsize=9)
    h1, l1 = ax2.get_legend_handles_labels()
    h2, l2 = ax2b.get_legend_handles_labels()
    ax2.legend(h1 + h2, l1 + l2, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
    a = ds.attrs
    fig.suptitle(f"Rigid ball R = {a['radius'] * 1e6:g} um on a Gaussian rough flat (E = {a['E'] / 1e9:g} GPa), "
                 f"{a['n']}x{a['n']} cells on {a.get('domain', a['size']) * 1e6:g} um (dx = {a['dx'] * 1e9:.1f} nm), "
                 f"beta = {a['correlation_length'] * 1e6:.2f} um, z0 = {a['z0'] * 1e9:g} nm", fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="tiny grid (64^2 on 2.5 um), rms/z0 = 0, 2, 20")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "rough_ball",
                    help="output folder (default results/rough_ball)")
    ap.add_argument("--publish", action="store_true",
                    help="also copy the table and the figure to docs/data/ and docs/figures/ (not with --quick)")
    ap.add_argument("--n", type=int, default=None, help="cells per side (default 256, quick 64)")
    ap.add_argument("--size", type=float, default=None, help="domain side in m (default 10e-6, quick 2.5e-6)")
    ap.add_argument("--surface-n", type=int, default=None, help="grid of the base surface (resolution checks)")
    ap.add_argument("--domain", type=float, default=None,
                    help="solve only the central domain x domain (m) of the surface (resolution checks)")
    ap.add_argument("--rms", type=float, nargs="+", default=None, help="rms values as multiples of z0")
    ap.add_argument("--tabor", type=float, nargs="+", default=[1.0, 2.0])
    ap.add_argument("--n-steps", type=int, default=None, help="unloading steps (default 30, quick 20)")
    ap.add_argument("--refine", type=int, default=None, help="refinements of the minimum (default 6, quick 4)")
    ap.add_argument("--suffix", default=None, help="file name suffix (default '' or '_quick')")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--replot", type=Path, default=None, help="only redraw the figure from a saved .nc")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the full study into docs/: not with --quick")
    if args.replot is not None:
        import xarray as xr

        with xr.open_dataset(args.replot) as ds:
            out = args.out / "figures" / (args.replot.stem.replace("rough_ball", "rough_ball_pulloff") + ".png")
            plot(ds.load(), out)
        print(f"wrote {out}")
        return 0

    n = args.n or (64 if args.quick else 256)
    size = args.size or (2.5e-6 if args.quick else 10e-6)
    rms = np.array(args.rms or (QUICK_RMS_OVER_Z0 if args.quick else FULL_RMS_OVER_Z0), dtype=float) * Z0
    n_steps = args.n_steps or (20 if args.quick else 30)
    refine = args.refine if args.refine is not None else (4 if args.quick else 6)
    suffix = args.suffix if args.suffix is not None else ("_quick" if args.quick else "")

    def progress(done, total):
        if not args.quiet:
            print(f"  case {done}/{total}  ({time.process_time():.0f} s CPU)", flush=True)

    t0, c0 = time.perf_counter(), time.process_time()
    ds = rough_ball_study(rms, tabor_values=args.tabor, n=n, size=size, z0=Z0, surface_n=args.surface_n, domain=args.domain,
                          n_steps=n_steps, refine=refine, progress=progress)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    ds.attrs.update({"wall_time": wall, "cpu_time": cpu})

    data = args.out / "data"
    figs = args.out / "figures"
    data.mkdir(parents=True, exist_ok=True)
    df = study_table(ds)
    df.to_csv(data / f"rough_ball{suffix}.csv", index=False)
    ds.to_netcdf(data / f"rough_ball{suffix}.nc")
    plot(ds, figs / f"rough_ball_pulloff{suffix}.png")
    published = publish(args.out, suffix) if args.publish else []

    if not args.quiet:
        cols = ["tabor", "rms_over_z0", "pull_off_force", "pull_off_over_piRdg", "adhesive_force_ratio",
                "repulsive_force", "contact_area", "adhesive_area", "area_ratio", "converged"]
        import pandas as pd

        with pd.option_context("display.width", 200, "display.max_columns", 20, "display.precision", 4):
            print(df[cols].to_string(index=False))
        for mu in ds["tabor"].values:
            s = ds.sel(tabor=mu)
            print(f"mu_T = {mu:g}: dgamma = {float(s.work_of_adhesion) * 1e3:.1f} mJ/m^2, sigma0 = "
                  f"{float(s.sigma0) / 1e6:.0f} MPa; smooth at F0: a = {float(s.smooth_contact_radius) * 1e9:.0f} nm "
                  f"(MD {float(s.md_contact_radius) * 1e9:.0f}), c = {float(s.smooth_cohesive_radius) * 1e9:.0f} nm "
                  f"(MD {float(s.md_cohesive_radius) * 1e9:.0f}), cohesive zone = {float(s.cohesive_zone_cells):.2f} cells; "
                  f"MD pull-off {float(s.md_pull_off) * 1e6:.2f} uN")
        for var in ("pull_off_force", "adhesive_force"):
            for row in peak_summary(ds, var):
                print(f"{var}: mu_T = {row['tabor']:g}: peak at rms/z0 = {row['peak_rms_over_z0']:g} "
                      f"({row['peak_value']:.3e} N, smooth {row['smooth_value']:.3e} N); "
                      f"rise then fall: {row['rise_then_fall']}")
        print(f"wall {wall:.1f} s, CPU {cpu:.1f} s; wrote {data / f'rough_ball{suffix}.csv'} and "
              f"{figs / f'rough_ball_pulloff{suffix}.png'}"
              + (f"; published {', '.join(map(str, published))}" if published else ""))
    return 0


def publish(out: Path, suffix: str) -> list[Path]:
    """Copy the study's table and figure from ``out`` into docs/ (the published files)."""
    copies = [(out / "data" / f"rough_ball{suffix}.csv", ROOT / "docs" / "data" / f"rough_ball{suffix}.csv"),
              (out / "figures" / f"rough_ball_pulloff{suffix}.png",
               ROOT / "docs" / "figures" / f"rough_ball_pulloff{suffix}.png")]
    for src, dest in copies:
        if src.resolve() != dest.resolve():  # --out docs --publish: already there
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(src, dest)
    return [dest for _, dest in copies]


if __name__ == "__main__":
    sys.exit(main())
