"""Fit Paper A Eq. 35 to bisinusoidal pull-off forces and compare with Table 2.

    F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b        (Paper A: a = 10.39, b = 0.041, beta = 0)

Usage::

    tribobem sweep examples/studies/bisinusoidal_pulloff.toml --out results/bisinusoidal --workers 1
    python examples/studies/bisinusoidal_fit.py results/bisinusoidal                 # -> results/bisinusoidal_fit/
    python examples/studies/bisinusoidal_fit.py results/bisinusoidal --publish       # ... and docs/ (625 cases only)
    python examples/studies/bisinusoidal_fit.py                                      # refit the published table

    tribobem sweep examples/studies/bisinusoidal_quick.toml --out results/bisinusoidal_quick --scheduler synchronous
    python examples/studies/bisinusoidal_fit.py results/bisinusoidal_quick --out results/bisinusoidal_quick_fit

The source is a sweep folder (``results.csv`` and ``sweep.json``), a sweep's ``results.csv``, or
a compact table (default: the published ``docs/data/bisinusoidal_pulloff.csv``, read only).  A
partial sweep works: the finished, converged points are fitted (the script says how many of
the sweep's points that is), the parameters a sweep keeps fixed (e.g. R_c and E* of the
4-point quick sweep) come from its base in ``sweep.json``.  The fit needs at least 3 such
points and two values of k (for b); the free exponent beta needs two values of
E* R_c / dgamma, otherwise only the beta = 0 fit is made (and said so).

Writes ``<out>/bisinusoidal_pulloff.csv`` (the compact table, SI columns),
``<out>/bisinusoidal_pulloff.png`` and ``<out>/bisinusoidal_fit.json`` (the constants);
``<out>`` defaults to ``results/bisinusoidal_fit``.  The repository's published files
(``docs/data/bisinusoidal_pulloff.csv``, ``docs/figures/bisinusoidal_pulloff.png``) are
written only with ``--publish``, and only from a sweep that holds all 625 cases of Paper A
Table 1.
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the paper studies: the package `studies` at the repository root
    sys.path.insert(0, str(ROOT))

from studies.bisinusoidal import PAPER_A_FIT, PAPER_A_TABLE1, fit_pull_off
from tribobem.output.atomic import atomic_path, atomic_write_text
from tribobem.units import si_value

#: The published table and figure (written only with --publish).
DATA = ROOT / "docs" / "data" / "bisinusoidal_pulloff.csv"
FIGURE = ROOT / "docs" / "figures" / "bisinusoidal_pulloff.png"
#: Default output folder (under results/, which git ignores).
OUT = ROOT / "results" / "bisinusoidal_fit"
COLUMNS = ["dgamma", "R_c", "E_star", "k", "pull_off_force", "normalised_pull_off", "tabor", "maugis",
           "lx", "ly", "nx", "ny", "zone_cells_x", "zone_cells_y", "contact_cells_x", "contact_cells_y",
           "iterations", "n_solves", "converged", "elapsed"]
#: The parameters of Eq. 35: swept, or fixed in the sweep's base.
PARAMETERS = ("dgamma", "R_c", "E_star", "k")
#: Exit code when the source cannot give a fit (what it needs is printed).
EXIT_NEEDS = 2


class NeedsMore(Exception):
    """The source cannot give the fit; the message says what it needs."""


def _si(v) -> float:
    if v is None or v == "":
        return float("nan")
    v = si_value(v)
    return float(v) if isinstance(v, (int, float)) else float("nan")


def read_table(path: Path) -> tuple[dict[str, np.ndarray], dict]:
    """Columns (SI floats) of a sweep's results.csv or of a compact table, and what was read.

    Returns the table of the finished (status ok) rows and a dict ``info`` with ``source``,
    ``n_points`` (rows in the file, finished or not), ``n_ok`` and, for a sweep, the base's
    fixed parameters that were added as constant columns (``fixed``).
    """
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    info = {"source": str(path), "n_points": len(rows), "fixed": {}}
    rows = [r for r in rows if r.get("status", "ok") == "ok"]
    info["n_ok"] = len(rows)
    table: dict[str, np.ndarray] = {}
    if rows:
        for name in rows[0]:
            if name in ("hash", "status", "error"):
                continue
            table[name] = np.asarray([_si(r[name]) for r in rows], dtype=float)
    manifest = path.parent / "sweep.json"
    if manifest.is_file():  # a sweep: the parameters it keeps fixed are in its base
        base = json.loads(manifest.read_text(encoding="utf-8")).get("base") or {}
        for name in PARAMETERS:
            if name not in table and name in base:
                value = _si(base[name])
                table[name] = np.full(len(rows), value)
                info["fixed"][name] = value
    return table, info


def check_fittable(table: dict[str, np.ndarray], info: dict) -> dict[str, np.ndarray]:
    """The converged rows of ``table``; raises :class:`NeedsMore` saying what is missing."""
    missing = [p for p in PARAMETERS if p not in table] + ([] if "pull_off_force" in table else ["pull_off_force"])
    if missing:
        raise NeedsMore(f"{info['source']}: no column or fixed value for {', '.join(missing)}; the fit needs "
                        f"dgamma, R_c, E_star, k (swept, or fixed in the sweep's base: sweep.json next to "
                        f"results.csv) and pull_off_force")
    good = np.isfinite(table["pull_off_force"]) & (table["pull_off_force"] != 0)
    if "converged" in table:
        good &= table["converged"] >= 0.5
    if int(good.sum()) < 3:
        raise NeedsMore(f"{info['source']}: {int(good.sum())} finished, converged point(s) of {info['n_points']}; "
                        "the fit has 3 constants (a, b, beta) and needs at least 3 (run more points of the sweep)")
    if np.unique(table["k"][good]).size < 2:
        raise NeedsMore(f"{info['source']}: every fitted point has k = {table['k'][good][0]:g}; the exponent b "
                        "needs at least two wavelength ratios k")
    return good


def write_compact(table: dict[str, np.ndarray], path: Path) -> None:
    cols = [c for c in COLUMNS if c in table]
    lines = [",".join(cols)]
    for i in range(len(table[cols[0]])):
        lines.append(",".join(f"{table[c][i]:.10g}" for c in cols))
    atomic_write_text(path, "\n".join(lines) + "\n")


def is_full_table1(table: dict[str, np.ndarray]) -> bool:
    """True when the table holds every one of the 625 combinations of Paper A Table 1."""
    have = {tuple(np.round([table[p][i] for p in PARAMETERS], 12)) for i in range(len(table["k"]))}
    want = {tuple(np.round(c, 12)) for c in np.array(np.meshgrid(*PAPER_A_TABLE1.values(), indexing="ij"))
            .reshape(4, -1).T}
    return want <= have


def plot(table, all_table, bad, fit, beta_free: bool, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = np.abs(table["pull_off_force"])
    a_p, b_p = PAPER_A_FIT["a"], PAPER_A_FIT["b"]
    p_paper = a_p * table["R_c"] * table["dgamma"] * table["k"] ** b_p
    norm = F / (table["R_c"] * table["dgamma"])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4))
    sc = ax1.scatter(table["k"] + (table["E_star"] - 100e9) / 40e9 * 0.03, norm,
                     c=table["maugis"] if "maugis" in table else None, s=10, cmap="viridis", alpha=0.8)
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
    pred = fit.predict(table["dgamma"], table["R_c"], table["E_star"], table["k"], beta0=not beta_free)
    lim = [F.min() * 0.9e6, F.max() * 1.1e6]
    label = (f"fit (free $\\beta$={fit.beta:.3f}), $R^2$={fit.r2:.4f}" if beta_free
             else f"fit ($\\beta$ = 0), $R^2$={fit.r2_beta0:.4f}")
    ax2.plot(F * 1e6, pred * 1e6, ".", ms=4, label=label)
    ax2.plot(F * 1e6, p_paper * 1e6, "x", ms=3, color="0.5", label="Paper A Table 2")
    ax2.plot(lim, lim, "k-", lw=0.8)
    ax2.set_xlabel("computed $|F|$ ($\\mu$N)")
    ax2.set_ylabel("predicted $|F|$ ($\\mu$N)")
    ax2.set_title("predicted vs computed")
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    ax2.set_aspect("equal", adjustable="box")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", type=Path, nargs="?", default=DATA,
                    help="sweep folder, its results.csv, or a compact table (default: the published table, read only)")
    ap.add_argument("--out", type=Path, default=OUT, help="output folder (default results/bisinusoidal_fit)")
    ap.add_argument("--publish", action="store_true",
                    help="also write docs/data/bisinusoidal_pulloff.csv and docs/figures/bisinusoidal_pulloff.png "
                         "(a sweep with all 625 cases of Paper A Table 1 only)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    say = (lambda *a: None) if args.quiet else print

    src = args.source / "results.csv" if args.source.is_dir() else args.source
    if not src.is_file():
        print(f"{src} not found: give a sweep folder (with results.csv), a results.csv or a compact table",
              file=sys.stderr)
        return EXIT_NEEDS
    all_table, info = read_table(src)
    try:
        good = check_fittable(all_table, info)
    except NeedsMore as exc:
        print(f"cannot fit: {exc}", file=sys.stderr)
        return EXIT_NEEDS
    publish_refused = False
    if args.publish:
        if src.resolve() == DATA.resolve():
            ap.error("--publish needs a sweep folder as the source, not the published table itself")
        if not is_full_table1(all_table):
            print(f"not published: {src} holds {info['n_ok']} finished point(s) of {info['n_points']}, not all 625 "
                  "cases of Paper A Table 1 (docs/ keeps the published table); the outputs are in "
                  f"{args.out}", file=sys.stderr)
            args.publish, publish_refused = False, True
    if info["n_ok"] < info["n_points"]:
        say(f"partial sweep: {info['n_ok']} of {info['n_points']} points finished; fitting those")
    if info["fixed"]:
        say("fixed in the sweep's base: " + ", ".join(f"{k} = {v:g}" for k, v in info["fixed"].items()))

    bad = ~good
    if bad.any():
        say(f"{int(bad.sum())} case(s) with a non-converged solve on the unloading curve are left out of "
            "the fit (marked x in the figure):")
        for i in np.flatnonzero(bad):
            say(f"  dgamma {all_table['dgamma'][i]:g} J/m^2, R_c {all_table['R_c'][i]:g} m, "
                f"E* {all_table['E_star'][i]:g} Pa, k {all_table['k'][i]:g}")
    table = {key: v[good] for key, v in all_table.items()}
    F = np.abs(table["pull_off_force"])
    fit = fit_pull_off({"dgamma": table["dgamma"], "R_c": table["R_c"], "E_star": table["E_star"],
                        "k": table["k"], "F": F})
    # beta multiplies ln(E* R_c / dgamma): with one value of it beta is not determined.
    beta_free = np.unique(np.round(np.log(table["E_star"] * table["R_c"] / table["dgamma"]), 12)).size >= 2
    a_p, b_p, beta_p = PAPER_A_FIT["a"], PAPER_A_FIT["b"], PAPER_A_FIT["beta"]
    say(f"{fit.n} cases" + (f", Maugis lambda {table['maugis'].min():.2f}-{table['maugis'].max():.2f}"
                            if "maugis" in table else ""))
    say(f"{'':24s}{'a':>10s}{'b':>9s}{'beta':>9s}{'R^2(lnF)':>10s}{'rms rel':>9s}{'max rel':>9s}")
    say(f"{'Paper A Table 2':24s}{a_p:10.3f}{b_p:9.3f}{beta_p:9.3f}")
    if beta_free:
        say(f"{'tribobem, free beta':24s}{fit.a:10.4g}{fit.b:9.3f}{fit.beta:9.4f}{fit.r2:10.4f}"
            f"{fit.rms_rel:9.3%}{fit.max_rel:9.3%}")
    else:
        say(f"{'tribobem, free beta':24s}  not determined: E* R_c / dgamma takes one value in these points")
    say(f"{'tribobem, beta = 0':24s}{fit.a0:10.3f}{fit.b0:9.3f}{0.0:9.3f}{fit.r2_beta0:10.4f}"
        f"{fit.rms_rel_beta0:9.3%}{fit.max_rel_beta0:9.3%}")
    say(f"per crest (beta = 0, k = 1): a0/2 = {fit.a0 / 2:.2f}  (JKR 3 pi/2 = 4.71, DMT 2 pi = 6.28; "
        f"Paper A a/2 = {a_p / 2:.2f})")
    p_paper = a_p * table["R_c"] * table["dgamma"] * table["k"] ** b_p
    say(f"Paper A's formula vs these forces: mean ratio {np.mean(p_paper / F):.3f}, "
        f"rms rel. diff {np.sqrt(np.mean((p_paper / F - 1) ** 2)):.2%}")

    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    write_compact(all_table, out / "bisinusoidal_pulloff.csv")
    record = {"source": str(src), "n_points": info["n_points"], "n_finished": info["n_ok"], "n_fitted": fit.n,
              "fixed": info["fixed"], "beta_determined": bool(beta_free), **fit.as_dict(),
              "paper_a": dict(PAPER_A_FIT)}
    if not beta_free:
        record.update(a=None, beta=None, b=None, r2=None, rms_rel=None, max_rel=None)
    atomic_write_text(out / "bisinusoidal_fit.json", json.dumps(record, indent=1) + "\n")
    plot(table, all_table, bad, fit, beta_free, out / "bisinusoidal_pulloff.png")
    say(f"wrote {out / 'bisinusoidal_pulloff.csv'}, {out / 'bisinusoidal_fit.json'}, {out / 'bisinusoidal_pulloff.png'}")
    if args.publish:
        DATA.parent.mkdir(parents=True, exist_ok=True)
        FIGURE.parent.mkdir(parents=True, exist_ok=True)
        for src_file, dest in ((out / "bisinusoidal_pulloff.csv", DATA), (out / "bisinusoidal_pulloff.png", FIGURE)):
            with atomic_path(dest) as tmp:  # readers of docs/ never see a half-written file
                shutil.copyfile(src_file, tmp)
        say(f"published {DATA} and {FIGURE}")
    return EXIT_NEEDS if publish_refused else 0


if __name__ == "__main__":
    sys.exit(main())
