"""Paper E section 3.2: friction hysteresis loops of a smooth rigid ball (R = 50 um) on an elastic
flat (E = 70 GPa, nu = 0.3), F0 = 10 uN, mu = 0.2, Dugdale adhesion dgamma = 0, 50, 100 mJ/m^2
(z0 = 0.2 nm: not given by Paper E, Paper D's value), domain +-2a, 1 + 2 force cycles
(thesis Paper E Figs. 6, 7, 9).

    python examples/studies/paper_e.py                      # full study into results/paper_e
    python examples/studies/paper_e.py --quick              # 48^2, 12 steps per cycle (a minute)
    python examples/studies/paper_e.py --publish            # also into docs/
    python examples/studies/paper_e.py --literal            # also Paper E's literal F* = 0.999 mu F0+

Writes into ``<out>`` (default ``results/paper_e``; ``--quick`` adds ``_quick`` to the names):
``paper_e_loops.csv`` (every step of every loop: point label, cycle, branch, F_x, F_x/(mu F0),
delta_x, stick ratio, F0+), ``paper_e_summary.csv`` (one row per loop: F0+, F0-, static
friction, pre-sliding displacement, stick ratios at the named points, loop width, centre and
symmetry measures, loop energies, resolution; Maugis-Dugdale and Paper E's 29.165 uN beside),
``paper_e_start_states.csv`` (the F_x = 0 state alone on finer grids, 256^2 = Paper E's, for the
grid convergence of F0+) and ``paper_e_loops.png``.  ``--publish`` copies the loops table and the
figure to ``docs/data/paper_e_loops.csv`` and ``docs/figures/paper_e_loops.png``.

F* is 0.999 x the gross-slip onset of the first loading (``peak = "onset"``, see
:func:`studies.paper_e.paper_e_loop`): in this model the stick zone vanishes at
~0.97 mu F0+ and, with adhesion, mu F0+ of A is not carried at all (the shear lowers F0+);
``--literal`` adds loops at Paper E's F* = 0.999 mu F0+ (adapted just below the largest carried
force), whose turning points are in full slip.
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

from studies.paper_e import (
    PAPER_E_SMOOTH_REPULSIVE_FORCE, WORKS, loop_metrics, loops_table, paper_e_loop, start_state, summary_table,
)

FULL = {"n": 128, "steps": 32, "start_grids": [256, 384, 512]}
QUICK = {"n": 48, "steps": 12, "start_grids": [96]}
COLORS = {0.0: "k", 0.05: "C0", 0.1: "C3"}


def plot(loops, starts, path: Path, literal=()) -> None:
    """(a) the loops F_x/(mu F0) against delta_x (Paper E Fig. 9), (b) the stick ratio along the
    path with the named points, (c) the numbers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(15.5, 8.8))
    gs = fig.add_gridspec(2, 2, height_ratios=[3, 1.25], width_ratios=[1, 1.25])
    ax1 = fig.add_subplot(gs[0, 0])
    ax2 = fig.add_subplot(gs[0, 1])
    ax3 = fig.add_subplot(gs[1, :])
    for lp in loops:
        col = COLORS.get(lp.work_of_adhesion, None)
        f = lp.forces / (lp.friction_coefficient * lp.normal_force)
        d = lp.displacements * 1e9
        lab = (rf"$\Delta\gamma$ = {lp.work_of_adhesion * 1e3:g} mJ/m$^2$, "
               rf"$F_0^+$ = {lp.repulsive_force * 1e6:.2f} $\mu$N")
        ax1.plot(d, f, "-", color=col, lw=1.2, label=lab)
        ax1.plot(d, f, ".", color=col, ms=3)
        for name in ("A", "D", "D'", "H", "L"):
            k = lp.points.get(name)
            if k is not None:
                ax1.annotate(name, (d[k], f[k]), textcoords="offset points", xytext=(4, -10 if f[k] > 0 else 4),
                             fontsize=7, color=col)
        ax2.plot(np.arange(len(lp.stick_ratios)), lp.stick_ratios, "o-", ms=2.5, lw=1, color=col,
                 label=rf"$\Delta\gamma$ = {lp.work_of_adhesion * 1e3:g} mJ/m$^2$")
    for lp in literal:
        col = COLORS.get(lp.work_of_adhesion, None)
        ax1.plot(lp.displacements * 1e9, lp.forces / (lp.friction_coefficient * lp.normal_force), ":", color=col,
                 lw=0.9, alpha=0.7)
    ref = loops[0]
    for name, k in ref.points.items():
        ax2.axvline(k, color="0.85", lw=0.6, zorder=0)
        ax2.text(k + 0.15, 1.01, name, fontsize=7, ha="left", va="bottom", color="0.3")
    ax1.axhline(0, color="0.7", lw=0.6)
    ax1.axvline(0, color="0.7", lw=0.6)
    ax1.set_xlabel(r"tangential displacement $\delta_x$ (nm)")
    ax1.set_ylabel(r"$F_x / (\mu F_0)$")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=8, loc="lower right")
    ax1.set_title("(a) friction hysteresis loops (Paper E Fig. 9): initial loading + 2 cycles,\n"
                  r"$F^*$ = 0.999 x the gross-slip onset of the first loading"
                  + ("; dotted: Paper E's literal $F^*$ = 0.999 $\\mu F_0^+$" if literal else ""), fontsize=9)
    ax2.set_xlabel("step along the path (A = 0)")
    ax2.set_ylabel(r"$A_{stick} / A_{contact}$")
    ax2.set_ylim(0, 1.07)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8, loc="center right")
    ax2.set_title("(b) stick ratio along the path (Paper E Fig. 7(b)); named points of Paper E Fig. 3", fontsize=9)
    ax3.axis("off")
    header = ["dgamma\nmJ/m2", "n", "a/dx", "(c-a)/dx", "F0+\nuN", "MD F0+\nuN", "F0+ finest\nF_x=0 state",
              "F0-\nuN", "onset /\n(mu F0+)", "F*\nuN", "F* /\n(mu F0)", "pre-slide\nnm", "stick\nA", "stick\nA'",
              "stick\nD", "stick\nD'", "loop width\nnm", "centre /\nwidth", "loop\nchange", "wall\ns"]
    rows = []
    for lp in loops:
        m = loop_metrics(lp)
        fin = [s for s in starts if s["work_of_adhesion"] == lp.work_of_adhesion]
        fin = max(fin, key=lambda s: s["n"]) if fin else None
        rows.append([f"{lp.work_of_adhesion * 1e3:g}", f"{lp.n}", f"{m['cells_across_contact']:.1f}",
                     f"{m['cells_across_cohesive_zone']:.1f}", f"{m['repulsive_force'] * 1e6:.3f}",
                     f"{m['md_repulsive_force'] * 1e6:.3f}",
                     f"{fin['repulsive_force'] * 1e6:.3f} (n={fin['n']})" if fin else "-",
                     f"{m['adhesive_force'] * 1e6:.3f}", f"{m['onset_ratio']:.4f}", f"{m['static_friction'] * 1e6:.3f}",
                     f"{m['static_friction_over_mu_f0']:.3f}", f"{m['presliding_displacement'] * 1e9:.3f}",
                     f"{m['stick_A']:.3f}", f"{m['stick_A1']:.3f}", f"{m['stick_D']:.3f}", f"{m['stick_D1']:.3f}",
                     f"{m['width_2'] * 1e9:.3f}", f"{m['offset_2'] / m['width_2']:+.3f}", f"{m['loop_change']:.1e}",
                     f"{m['wall_time']:.0f}"])
    tab = ax3.table(cellText=rows, colLabels=header, loc="center", cellLoc="center")
    tab.auto_set_font_size(False)
    tab.set_fontsize(7.5)
    tab.scale(1.0, 1.6)
    for (r, _), cell in tab.get_celld().items():
        if r == 0:
            cell.set_height(cell.get_height() * 1.8)
    ax3.set_title(f"(c) Paper E's smooth F0+ at 50 mJ/m2: {PAPER_E_SMOOTH_REPULSIVE_FORCE * 1e6:.3f} uN; "
                  "MD: Maugis-Dugdale at F0 (z0 = 0.2 nm); (c-a)/dx < 3: cohesive zone under-resolved", fontsize=9)
    fig.suptitle("Paper E 3.2: rigid ball R = 50 um on E = 70 GPa, nu = 0.3; F0 = 10 uN, mu = 0.2, Dugdale z0 = 0.2 nm; "
                 "domain +-2a, incremental slip with the coupling loop", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "paper_e", help="output folder (default results/paper_e)")
    ap.add_argument("--quick", action="store_true", help=f"{QUICK['n']}^2, {QUICK['steps']} steps per cycle")
    ap.add_argument("--publish", action="store_true",
                    help="copy the loops table and the figure to docs/data/paper_e_loops.csv and docs/figures/paper_e_loops.png")
    ap.add_argument("--n", type=int, default=None, help=f"cells per side of the loops (default {FULL['n']})")
    ap.add_argument("--steps", type=int, default=None, help=f"steps per cycle (default {FULL['steps']})")
    ap.add_argument("--works", type=float, nargs="+", default=None, help="works of adhesion in J/m^2 (default 0 0.05 0.1)")
    ap.add_argument("--start-grids", type=int, nargs="*", default=None,
                    help=f"grids of the F_x = 0 states alone (default {FULL['start_grids']})")
    ap.add_argument("--literal", action="store_true", help="also run Paper E's literal F* = 0.999 mu F0+")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    if args.publish and args.quick:
        ap.error("--publish writes the full study into docs/: not with --quick")
    cfg = QUICK if args.quick else FULL
    n = args.n or cfg["n"]
    steps = args.steps or cfg["steps"]
    works = args.works or list(WORKS)
    grids = args.start_grids if args.start_grids is not None else cfg["start_grids"]
    suffix = "_quick" if args.quick else ""

    def say(msg):
        if not args.quiet:
            print(msg, flush=True)

    t0, c0 = time.perf_counter(), time.process_time()
    loops, literal, starts = [], [], []
    for w in works:
        lp = paper_e_loop(w, n, steps=steps, cycles=2)
        loops.append(lp)
        m = loop_metrics(lp)
        say(f"dgamma = {w * 1e3:g} mJ/m^2, n = {n}: F0+ = {m['repulsive_force'] * 1e6:.3f} uN (MD "
            f"{m['md_repulsive_force'] * 1e6:.3f}), onset {m['onset_ratio']:.4f} mu F0+, F* = "
            f"{m['static_friction'] * 1e6:.3f} uN = {m['static_friction_over_mu_f0']:.3f} mu F0, pre-slide "
            f"{m['presliding_displacement'] * 1e9:.4f} nm, stick A {m['stick_A']:.3f} A' {m['stick_A1']:.3f} "
            f"D {m['stick_D']:.3f} D' {m['stick_D1']:.3f}, width {m['width_2'] * 1e9:.4f} nm, centre/width "
            f"{m['offset_2'] / m['width_2']:+.3f}, loop change {m['loop_change']:.2e}, (c-a)/dx "
            f"{m['cells_across_cohesive_zone']:.2f}; {lp.wall_time:.0f} s wall, {lp.cpu_time:.0f} s CPU")
        if args.literal:
            ll = paper_e_loop(w, n, steps=steps, cycles=2, peak="repulsive")
            literal.append(ll)
            ml = loop_metrics(ll)
            say(f"  literal F* = {ll.amplitude:.4f} mu F0+ (limit {ll.amplitude_limit:.4f}): stick D {ml['stick_D']:.3f} "
                f"H {ml['stick_H']:.3f} L {ml['stick_L']:.3f}, pre-slide {ml['presliding_displacement'] * 1e9:.4f} nm, "
                f"loop change {ml.get('loop_change', float('nan')):.2e}; {ll.wall_time:.0f} s wall")
    for w in works:
        for g in grids:
            s = start_state(w, g)
            starts.append(s)
            say(f"F_x = 0 state, dgamma = {w * 1e3:g} mJ/m^2, n = {g}: F0+ = {s['repulsive_force'] * 1e6:.3f} uN "
                f"(MD {s['md_repulsive_force'] * 1e6:.3f}), stick ratio {s['stick_ratio']:.3f}, (c-a)/dx "
                f"{s['cells_across_cohesive_zone']:.2f}; {s['wall_time']:.0f} s wall")
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0

    import pandas as pd

    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    csv = out / f"paper_e_loops{suffix}.csv"
    png = out / f"paper_e_loops{suffix}.png"
    table = loops_table(loops)
    table.insert(2, "peak", "onset")
    summ = summary_table(loops)
    summ.insert(2, "peak", "onset")
    if literal:
        lt = loops_table(literal)
        lt.insert(2, "peak", "repulsive")
        table = pd.concat([table, lt], ignore_index=True)
        ls = summary_table(literal)
        ls.insert(2, "peak", "repulsive")
        summ = pd.concat([summ, ls], ignore_index=True)
    table.to_csv(csv, index=False)
    summ.to_csv(out / f"paper_e_summary{suffix}.csv", index=False)
    pd.DataFrame(starts).to_csv(out / f"paper_e_start_states{suffix}.csv", index=False)
    plot(loops, starts, png, literal)
    if args.publish:
        (ROOT / "docs" / "data").mkdir(parents=True, exist_ok=True)
        (ROOT / "docs" / "figures").mkdir(parents=True, exist_ok=True)
        shutil.copyfile(csv, ROOT / "docs" / "data" / "paper_e_loops.csv")
        shutil.copyfile(png, ROOT / "docs" / "figures" / "paper_e_loops.png")
    say(f"wall {wall:.0f} s, CPU {cpu:.0f} s; wrote {csv}, {png} and the summary into {out}"
        + (" (and copied to docs/)" if args.publish else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
