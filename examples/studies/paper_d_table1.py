"""Paper D Table 1: gross-slip onset of a smooth rigid ball on an elastic flat with Dugdale
adhesion, mu_T = 0, 0.5, 1, 2, with a resolution study (thesis Paper D section 3.1).

    python examples/studies/paper_d_table1.py --out results/paper_d            # full study
    python examples/studies/paper_d_table1.py --out results/paper_d --quick    # one small grid (s)
    python examples/studies/paper_d_table1.py --publish                        # also into docs/
    python examples/studies/paper_d_table1.py --replot [--publish]             # figure from the CSVs

Full study: tangential ramps to gross slip on n = 64, 96, 128, 192 cells per side over
-2 c0 < x, y < 2 c0 for every mu_T (the onset ratio's resolution study), and the F_x = 0 state
alone on n = 256 and 512 for mu_T > 0 (the adhesive force F0- against Maugis-Dugdale, whose
cohesive zone c - a spans only 2-3 cells on the ramps' grids at mu_T = 2).  About 15 min of
CPU (two cores); longer on a loaded machine.

Writes ``<out>/paper_d_table1.csv`` (one row per ramp, ``ramp`` True, and per F_x = 0 state,
``ramp`` False; SI units; Paper D's and the Maugis-Dugdale values beside),
``<out>/paper_d_table1_curves.csv`` (the ramps: stick ratio and displacement against
F_x/(mu F0+)) and ``<out>/paper_d_table1.png`` (``<out>`` defaults to ``results/paper_d``;
``--quick`` adds ``_quick``).  ``--publish`` copies the table and the figure to
``docs/data/paper_d_table1.csv`` and ``docs/figures/paper_d_table1.png``; nothing is written
into ``docs/`` without it.
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

from studies.paper_d import PAPER_D_TABLE1, paper_d_table1, resolution_summary, study_table, zero_state

TABOR = [0.0, 0.5, 1.0, 2.0]
FULL_GRIDS = [64, 96, 128, 192]
#: F_x = 0 states alone (F0- and the cohesive zone against Maugis-Dugdale) on finer grids than
#: the ramps can afford; only for mu_T > 0 (without adhesion F0+ = F0 on every grid).
FULL_ZERO_GRIDS = [256, 512]
QUICK_GRIDS = [48]
QUICK_ZERO_GRIDS = [64]
QUICK_TABOR = [1.0]


def curves_table(cases):
    import pandas as pd

    rows = []
    for c in cases:
        for k, (f, fr, st, d) in enumerate(zip(c.forces, c.force_ratios, c.stick_ratios, c.displacements)):
            rows.append({"tabor": c.tabor, "n": c.n, "dx": c.dx, "step": k, "tangential_force": f,
                         "force_ratio": fr, "stick_ratio": st, "displacement_x": d,
                         "onset_state": k == len(c.forces) - 1 and c.gross_slip})
    return pd.DataFrame(rows)


def plot(table, curves, path: Path) -> None:
    """(a) stick ratio against F_x/(mu F0+), finest ramp grid; (b) onset ratio against dx per
    mu_T; (c) F0- over the Maugis-Dugdale value against dx; (d) the table (finest grids).

    ``table`` and ``curves`` are the two CSV tables (DataFrames) the study writes.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ramps = table[table["ramp"].astype(bool)]
    zeros = table[~table["ramp"].astype(bool)]
    tabors = sorted(ramps["tabor"].unique())
    fig = plt.figure(figsize=(15, 7.4))
    gs = fig.add_gridspec(2, 3, height_ratios=[3, 1.35], width_ratios=[1.2, 1, 1])
    ax1 = fig.add_subplot(gs[0, 0])
    ax2 = fig.add_subplot(gs[0, 1])
    ax4 = fig.add_subplot(gs[0, 2])
    ax3 = fig.add_subplot(gs[1, :])
    colors = {0.0: "k", 0.5: "C0", 1.0: "C2", 2.0: "C3"}
    rows = []
    for t in tabors:
        cs = ramps[ramps["tabor"] == t].sort_values("n")
        fin = cs.iloc[-1]
        col = colors.get(float(t))
        cv = curves[(curves["tabor"] == t) & (curves["n"] == fin["n"])].sort_values("step")
        x, y = cv["force_ratio"].to_numpy(), cv["stick_ratio"].to_numpy()
        if bool(fin["gross_slip"]):
            x, y = np.append(x, fin["onset_ratio"]), np.append(y, 0.0)
        ax1.plot(x, y, "o-", ms=3, color=col,
                 label=rf"$\mu_T$ = {t:g} (n = {fin['n']}, a/dx = {fin['cells_across_contact']:.0f})")
        ax2.plot(cs["dx"] * 1e9, cs["onset_ratio"], "o-", color=col, label=rf"$\mu_T$ = {t:g}")
        ref = PAPER_D_TABLE1.get(float(t))
        if ref:
            ax1.axvline(ref[3], color=col, ls=":", lw=0.8)
        zs = zeros[zeros["tabor"] == t].sort_values("n")
        if t > 0:
            pts = table[table["tabor"] == t].sort_values("dx")
            ratio = pts["adhesive_force"] / pts["md_adhesive_force"]
            ax4.plot(pts["dx"] * 1e9, ratio, "s-", color=col, mfc="none", label=rf"$\mu_T$ = {t:g}")
            for (_, p), r in zip(pts.iterrows(), ratio):
                ax4.annotate(f"{p['cells_across_cohesive_zone']:.1f}", (p["dx"] * 1e9, r), textcoords="offset points",
                             xytext=(3, 3), fontsize=6.5, color=col)
            if ref:
                ax4.plot([0], [ref[0] * 1e-6 / fin["md_adhesive_force"]], marker="*", ms=10, color=col, ls="none",
                         clip_on=False)
        zf = zs.iloc[-1] if len(zs) else None
        ref = ref or (np.nan,) * 4
        rows.append([f"{t:g}", f"{fin['n']}", f"{fin['dx'] * 1e9:.2f}", f"{fin['cells_across_contact']:.1f}",
                     f"{fin['cells_across_cohesive_zone']:.1f}", f"{fin['adhesive_force'] * 1e6:.3f}",
                     f"{zf['adhesive_force'] * 1e6:.2f} ({zf['n']})" if zf is not None else "-",
                     f"{fin['md_adhesive_force'] * 1e6:.3f}", f"{ref[0]:.3f}", f"{fin['repulsive_force'] * 1e6:.3f}",
                     f"{ref[1]:.3f}", f"{fin['zero_stick_ratio']:.3f}", f"{fin['onset_ratio']:.4f}", f"{ref[3]:.4f}",
                     f"{fin['force_ratio_paper_d']:.3f}", f"{ref[2]:.2f}", f"{fin['presliding_displacement'] * 1e9:.3f}"])
    ax1.set_xlabel(r"$F_x / (\mu F_0^+)$  ($F_0^+$ of each state)")
    ax1.set_ylabel(r"$A_{stick} / A_{contact}$")
    ax1.set_xlim(0, 1.0)
    ax1.set_ylim(bottom=0)
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=8)
    ax1.set_title("(a) stick ratio along the ramp (finest ramp grid);\n"
                  "dotted: Paper D's onset (0.969-0.970)", fontsize=9)
    ax2.axhspan(0.9685, 0.9700, color="0.8", alpha=0.6, label="Paper D Table 1")
    ax2.set_xlabel("cell size dx (nm)")
    ax2.set_ylabel(r"gross-slip onset $F_x / (\mu F_0^+)$")
    ax2.set_xlim(left=0)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    grids = ", ".join(str(n) for n in sorted(ramps["n"].unique()))
    ax2.set_ylim(0.90, 0.975)
    ax2.set_title(f"(b) resolution study of the onset: n = {grids}\n(right to left) cells per side "
                  "on $\\pm 2 c_0$ ($\\pm 2 a$ for $\\mu_T$ = 0)", fontsize=9)
    ax4.axhline(1.0, color="0.5", lw=0.8)
    ax4.set_xlabel("cell size dx (nm)")
    ax4.set_ylabel(r"$F_0^- / F_0^-$(Maugis-Dugdale)  at $F_x$ = 0")
    ax4.set_xlim(left=0)
    ax4.grid(alpha=0.3)
    ax4.legend(fontsize=8)
    ax4.set_title("(c) adhesive force vs grid (labels: (c - a)/dx);\n"
                  "stars at dx = 0: Paper D's F0- over MD", fontsize=9)
    ax3.axis("off")
    header = ["mu_T", "n", "dx nm", "a/dx", "(c-a)/dx", "F0- uN", "F0- (finest n)", "MD F0- uN", "Paper D F0-",
              "F0+ uN", "Paper D F0+", "stick(Fx=0)", "onset ratio", "Paper D", "Fx/(mu F0)", "Paper D F_nr",
              "pre-slide nm"]
    tab = ax3.table(cellText=rows, colLabels=header, loc="center", cellLoc="center")
    tab.auto_set_font_size(False)
    tab.set_fontsize(7.5)
    tab.scale(1.0, 1.3)
    ax3.set_title("(d) finest ramp grid beside Paper D Table 1 (MD: Maugis-Dugdale at F0, integral of p < 0; "
                  "onset ratio: F_x / (mu F0+) with F0+ of the onset state)", fontsize=9)
    fig.suptitle("Paper D Table 1: rigid ball R = 10 um on E = 130 GPa, nu = 0.3; F0 = 10 uN, mu = 0.2, z0 = 0.2 nm; "
                 "tangential force ramp ('total' slip), coupling loop, free-boundary operator", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def publish(csv: Path, png: Path) -> None:
    """Copy the table and the figure to docs/data/paper_d_table1.csv, docs/figures/paper_d_table1.png."""
    (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
    (ROOT / "docs" / "figures").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(csv, ROOT / "docs" / "data" / "paper_d_table1.csv")
    shutil.copyfile(png, ROOT / "docs" / "figures" / "paper_d_table1.png")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "paper_d", help="output folder (default results/paper_d)")
    ap.add_argument("--quick", action="store_true", help=f"mu_T = {QUICK_TABOR}, n = {QUICK_GRIDS} (seconds)")
    ap.add_argument("--publish", action="store_true",
                    help="copy the table and figure to docs/data/paper_d_table1.csv and docs/figures/paper_d_table1.png")
    ap.add_argument("--tabor", type=float, nargs="+", default=None, help=f"Tabor parameters (default {TABOR})")
    ap.add_argument("--grids", type=int, nargs="+", default=None, help=f"cells per side (default {FULL_GRIDS})")
    ap.add_argument("--zero-grids", type=int, nargs="*", default=None,
                    help=f"grids of the F_x = 0 states alone (default {FULL_ZERO_GRIDS})")
    ap.add_argument("--half-width", type=float, default=2.0, help="domain half-width / c0 (default 2)")
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the figure from the CSV files already in --out (with --publish: copy them)")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the full study into docs/: not with --quick")
    tabor = args.tabor or (QUICK_TABOR if args.quick else TABOR)
    grids = args.grids or (QUICK_GRIDS if args.quick else FULL_GRIDS)
    zero_grids = args.zero_grids if args.zero_grids is not None else (QUICK_ZERO_GRIDS if args.quick else FULL_ZERO_GRIDS)
    suffix = "_quick" if args.quick else ""
    out = args.out
    csv = out / f"paper_d_table1{suffix}.csv"
    png = out / f"paper_d_table1{suffix}.png"
    if args.replot:
        import pandas as pd

        plot(pd.read_csv(csv), pd.read_csv(out / f"paper_d_table1{suffix}_curves.csv"), png)
        if args.publish:
            publish(csv, png)
        print(f"wrote {png}" + (" (and copied the table and figure to docs/)" if args.publish else ""))
        return 0

    def progress(c):
        if not args.quiet:
            print(f"  mu_T = {c.tabor:g}, n = {c.n}: onset F_x/(mu F0+) = {c.onset_ratio:.4f} "
                  f"(bracket {c.bracket_width:.1e} mu F0+), "
                  f"F0- = {c.adhesive_force * 1e6:.3f} uN, stick(0) = {c.zero_stick_ratio:.3f}, "
                  f"a/dx = {c.cells_across_contact:.1f}, (c-a)/dx = {c.cells_across_cohesive_zone:.2f}, "
                  f"converged {c.converged}; {c.wall_time:.0f} s wall, {c.cpu_time:.0f} s CPU", flush=True)

    t0, c0 = time.perf_counter(), time.process_time()
    cases = paper_d_table1(tabor, grids, half_width=args.half_width, progress=progress)
    zeros = []
    for t in (t for t in tabor if t > 0):
        for n in zero_grids:
            z = zero_state(t, n, half_width=args.half_width)
            zeros.append(z)
            if not args.quiet:
                print(f"  F_x = 0 state, mu_T = {t:g}, n = {n}: F0- = {z['adhesive_force'] * 1e6:.3f} uN "
                      f"(MD {z['md']['adhesive_force'] * 1e6:.3f}), F0+ = {z['repulsive_force'] * 1e6:.3f} uN "
                      f"(normal problem alone {z['normal_only_repulsive_force'] * 1e6:.3f}), stick(0) = "
                      f"{z['zero_stick_ratio']:.3f}, (c-a)/dx = {z['cells_across_cohesive_zone']:.2f}; "
                      f"{z['wall_time']:.0f} s wall", flush=True)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0

    out.mkdir(parents=True, exist_ok=True)
    table = study_table(cases, zeros)
    curves = curves_table(cases)
    table.to_csv(csv, index=False)
    curves.to_csv(out / f"paper_d_table1{suffix}_curves.csv", index=False)
    plot(table, curves, png)
    if args.publish:
        publish(csv, png)

    if not args.quiet:
        print("\nmu_T  n    dx(nm)  a/dx  (c-a)/dx  F0-(uN)  MD F0-  PaperD F0-  F0+(uN)  PaperD F0+  stick(0)  "
              "onset  PaperD  Fx/(muF0)  presl.(nm)")
        for c in cases:
            ref = PAPER_D_TABLE1.get(c.tabor, (np.nan,) * 4)
            print(f"{c.tabor:4g}  {c.n:3d}  {c.dx * 1e9:6.2f}  {c.cells_across_contact:4.1f}  "
                  f"{c.cells_across_cohesive_zone:8.2f}  {c.adhesive_force * 1e6:7.3f}  {c.md['adhesive_force'] * 1e6:6.3f}  "
                  f"{ref[0]:10.3f}  {c.repulsive_force * 1e6:7.3f}  {ref[1]:10.3f}  {c.zero_stick_ratio:8.4f}  "
                  f"{c.onset_ratio:.4f}  {ref[3]:.4f}  {c.force_ratio_paper_d:9.4f}  {c.presliding_displacement * 1e9:10.4f}")
        for r in resolution_summary(cases):
            print(f"mu_T = {r['tabor']:g}: onset ratio "
                  + ", ".join(f"{o:.4f} (n = {n})" for o, n in zip(r["onset_ratio"], r["n"]))
                  + f"; two finest differ by {r['finest_change']:.4f} (<= 0.005: {r['converged']})")
        print(f"wall {wall:.0f} s, CPU {cpu:.0f} s; wrote {csv} and {png}" + (" (and copied to docs/)" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
