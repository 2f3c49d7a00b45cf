"""Fit Paper A Eq. 35 to the 625 bisinusoidal pull-off forces and compare with Table 2.

    F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b        (Paper A: a = 10.39, b = 0.041, beta = 0)

Usage::

    tribobem sweep examples/studies/bisinusoidal_pulloff.toml --out results/bisinusoidal --workers 1
    python examples/studies/bisinusoidal_fit.py results/bisinusoidal     # sweep folder or results.csv
    python examples/studies/bisinusoidal_fit.py                          # the stored docs/data CSV

Given a sweep folder (or its results.csv) it first writes the compact table
docs/data/bisinusoidal_pulloff.csv (SI columns); then it fits, prints the constants against
Paper A and saves docs/figures/bisinusoidal_pulloff.png.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

from tribobem.studies.bisinusoidal import PAPER_A_FIT, fit_pull_off
from tribobem.sweep import atomic_path, atomic_write_text, to_si

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "data" / "bisinusoidal_pulloff.csv"
FIGURE = ROOT / "docs" / "figures" / "bisinusoidal_pulloff.png"
COLUMNS = ["dgamma", "R_c", "E_star", "k", "pull_off_force", "normalised_pull_off", "tabor", "maugis",
           "lx", "ly", "nx", "ny", "zone_cells_x", "zone_cells_y", "contact_cells_x", "contact_cells_y",
           "iterations", "n_solves", "converged", "elapsed"]


def read_table(path: Path) -> dict[str, np.ndarray]:
    """Columns of a results.csv (sweep) or of the compact data CSV, in SI floats."""
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    rows = [r for r in rows if r.get("status", "ok") == "ok"]
    table = {}
    for name in rows[0]:
        if name in ("hash", "status", "error"):
            continue
        vals = []
        for r in rows:
            v = to_si(r[name]) if r[name] != "" else float("nan")
            vals.append(v if isinstance(v, (int, float)) else float("nan"))
        table[name] = np.asarray(vals, dtype=float)
    return table


def write_compact(table: dict[str, np.ndarray], path: Path = DATA) -> None:
    cols = [c for c in COLUMNS if c in table]
    lines = [",".join(cols)]
    for i in range(len(table[cols[0]])):
        lines.append(",".join(f"{table[c][i]:.10g}" for c in cols))
    atomic_write_text(path, "\n".join(lines) + "\n")
    print(f"wrote {path} ({len(lines) - 1} rows)")


def main(argv: list[str]) -> int:
    src = Path(argv[1]) if len(argv) > 1 else DATA
    if src.is_dir():
        src = src / "results.csv"
    table = read_table(src)
    if src != DATA:
        write_compact(table)
    bad = table["converged"] < 0.5 if "converged" in table else np.zeros(len(table["k"]), bool)
    if bad.any():
        print(f"{int(bad.sum())} case(s) with a non-converged solve on the unloading curve are left out of "
              "the fit (marked x in the figure):")
        for i in np.flatnonzero(bad):
            print(f"  dgamma {table['dgamma'][i]:g} J/m^2, R_c {table['R_c'][i]:g} m, E* {table['E_star'][i]:g} Pa, "
                  f"k {table['k'][i]:g}: F/(R_c dgamma) = {abs(table['pull_off_force'][i]) / (table['R_c'][i] * table['dgamma'][i]):.3f}")
    all_table = table
    table = {key: v[~bad] for key, v in table.items()}
    F = np.abs(table["pull_off_force"])
    fit = fit_pull_off({"dgamma": table["dgamma"], "R_c": table["R_c"], "E_star": table["E_star"],
                        "k": table["k"], "F": F})
    a_p, b_p, beta_p = PAPER_A_FIT["a"], PAPER_A_FIT["b"], PAPER_A_FIT["beta"]
    print(f"{fit.n} cases, Maugis lambda {table['maugis'].min():.2f}-{table['maugis'].max():.2f}"
          if "maugis" in table else f"{fit.n} cases")
    print(f"{'':24s}{'a':>10s}{'b':>9s}{'beta':>9s}{'R^2(lnF)':>10s}{'rms rel':>9s}{'max rel':>9s}")
    print(f"{'Paper A Table 2':24s}{a_p:10.3f}{b_p:9.3f}{beta_p:9.3f}")
    print(f"{'tribobem, free beta':24s}{fit.a:10.4g}{fit.b:9.3f}{fit.beta:9.4f}{fit.r2:10.4f}"
          f"{fit.rms_rel:9.3%}{fit.max_rel:9.3%}")
    print(f"{'tribobem, beta = 0':24s}{fit.a0:10.3f}{fit.b0:9.3f}{0.0:9.3f}{fit.r2_beta0:10.4f}"
          f"{fit.rms_rel_beta0:9.3%}{fit.max_rel_beta0:9.3%}")
    print(f"standard errors: beta {fit.stderr['beta']:.4f}, b {fit.stderr['b']:.4f}, b0 {fit.stderr['b0']:.4f}")
    print(f"per crest (beta = 0, k = 1): a0/2 = {fit.a0 / 2:.2f}  (JKR 3 pi/2 = 4.71, DMT 2 pi = 6.28; "
          f"Paper A a/2 = {a_p / 2:.2f})")
    p_paper = a_p * table["R_c"] * table["dgamma"] * table["k"] ** b_p
    print(f"Paper A's formula vs these forces: mean ratio {np.mean(p_paper / F):.3f}, "
          f"rms rel. diff {np.sqrt(np.mean((p_paper / F - 1) ** 2)):.2%}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    norm = F / (table["R_c"] * table["dgamma"])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    sc = ax1.scatter(table["k"] + (table["E_star"] - 100e9) / 40e9 * 0.03, norm, c=table["maugis"] if "maugis" in table
                     else None, s=10, cmap="viridis", alpha=0.8)
    if "maugis" in table:
        fig.colorbar(sc, ax=ax1, label="Maugis parameter $\\lambda$")
    if bad.any():
        ax1.plot(all_table["k"][bad], np.abs(all_table["pull_off_force"][bad]) / (all_table["R_c"][bad] *
                 all_table["dgamma"][bad]), "kx", ms=6, label="not converged (left out)")
    kk = np.linspace(0.08, 1.0, 200)
    ax1.plot(kk, fit.a0 * kk**fit.b0, "C3-", lw=2, label=f"fit ($\\beta$=0): {fit.a0:.2f} $k^{{{fit.b0:.3f}}}$")
    ax1.plot(kk, a_p * kk**b_p, "k--", lw=2, label=f"Paper A: {a_p} $k^{{{b_p}}}$")
    for n_, lab in ((1.5 * np.pi, "2 x JKR"), (2 * np.pi, "2 x DMT")):
        ax1.axhline(2 * n_, color="0.6", lw=0.8, ls=":")
        ax1.text(0.09, 2 * n_ * 1.005, lab, fontsize=8, color="0.4", va="bottom")
    ax1.set_xlabel("wavelength ratio $k = \\lambda_y/\\lambda_x$ (points spread by $E^*$)")
    ax1.set_ylabel("$F_{pull-off} / (R_c\\, \\Delta\\gamma)$ per cell (2 crests)")
    ax1.set_title(f"Bisinusoidal pull-off (Paper A sec. 6), {fit.n} cases")
    ax1.legend(fontsize=8, loc="lower right")
    ax1.grid(alpha=0.3)
    pred = fit.predict(table["dgamma"], table["R_c"], table["E_star"], table["k"])
    lim = [F.min() * 0.9e6, F.max() * 1.1e6]
    ax2.plot(F * 1e6, pred * 1e6, ".", ms=4, label=f"fit (free $\\beta$={fit.beta:.3f}), $R^2$={fit.r2:.4f}")
    ax2.plot(F * 1e6, p_paper * 1e6, "x", ms=3, color="0.5", label="Paper A Table 2")
    ax2.plot(lim, lim, "k-", lw=0.8)
    ax2.set_xlabel("computed $|F|$ ($\\mu$N)")
    ax2.set_ylabel("predicted $|F|$ ($\\mu$N)")
    ax2.set_title("predicted vs computed")
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    ax2.set_aspect("equal", adjustable="box")
    fig.tight_layout()
    with atomic_path(FIGURE) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    print(f"saved {FIGURE}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
