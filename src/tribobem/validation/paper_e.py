"""Validation of the friction hysteresis of Paper E section 3.2: qualitative facts of the
thesis and the analytic F0+, not a reproduction of its figures.

Cases
-----
``paper_e``
    Rigid ball R = 50 um on an elastic flat E = 70 GPa, nu = 0.3, F0 = 10 uN, mu = 0.2, Dugdale
    adhesion dgamma = 0, 50, 100 mJ/m^2 with z0 = 0.2 nm (not in Paper E; Paper D's value),
    domain +-2a (a the analytic contact radius), force-controlled cycles to F* = 0.999 x the
    gross-slip onset of the first loading (:func:`tribobem.validation.paper_e_model.paper_e_loop`),
    1 + 2 cycles.  Quick: 48^2, 12 steps per cycle; full: 96^2, 16 steps per cycle.

    Per dgamma: the slip annulus at A (indicator 0 < stick ratio < 1), the re-stick at A'
    (indicator: stick ratio at A' above that at A), the full slip at D (stick ratio within 0.05
    of 0), the almost full stick at D' (within 0.2 of 1; the first step after a reversal is
    1.7-3.4 % of the force range with 12-16 steps per cycle), the stationary loop (largest
    change of delta(+-F*) between cycles 1 and 2, over the loop width, within 0.01), the
    symmetric slip development after the first cycle (stick ratio of the unloading branch at F
    against the reloading branch at -F in cycle 2, within 0.05), the point symmetry of the
    last loop about its centre (within 0.02 of the width), and Paper E's horizontal shift of
    the loop by the first loading (sign of the loop centre: +1, toward the first load); with
    adhesion F0+ of the F_x = 0 state alone on a finer grid (128^2 quick, 256^2 = Paper E's
    full) against Maugis-Dugdale at F0 (15 % quick, 8 % full: the cohesive zone c - a spans
    1.8-3.4 and 3.4-6.6 cells there, and F0+ converges to Maugis-Dugdale from above, about
    linearly in dx: +5.6 % and +2.4 % at 50 mJ/m^2, +12.8 % and +7.6 % at 100 mJ/m^2), in full
    mode also against Paper E's 29.165 uN at the same 256^2 (6 %; ours is 30.62 uN, above
    Maugis-Dugdale's 29.91 uN while Paper E's is below it), and without adhesion the half
    width of the steady loop against the Mindlin-Deresiewicz delta* at F* (k = (2 - nu)/G of
    the flat, a numerical; 10 %: the coupling changes the slip development, Paper E Fig. 7).

    Across dgamma 0 < 50 < 100 mJ/m^2 (indicators): F0+, the static friction (F* and the onset
    of the first loading), the pre-sliding displacement (delta(D) - delta(A) and delta at the
    onset) all increase; and per dgamma the onset over mu F0 against F0+/F0 (Paper E: the static
    friction is controlled by the contact repulsive force), 5 %.

    The analytic Maugis-Dugdale F0+ at dgamma = 50 mJ/m^2 against Paper E's smooth 29.165 uN
    (3 %: Paper E says the case "fits" Maugis-Dugdale).
"""

from __future__ import annotations

import math

import numpy as np

from .common import _row
from .paper_e_model import WORKS, loop_metrics, md_state, paper_e_loop, start_state
from .references import PAPER_E_SMOOTH_REPULSIVE_FORCE

__all__ = ["CASES", "paper_e_rows"]


def _indicator(case: str, quantity: str, ok: bool):
    return _row(case, quantity, 1.0, 1.0 if ok else 0.0, 0.0, scale=1.0)


def paper_e_rows(quick: bool) -> list:
    """Rows of ``paper_e`` (module docstring).

    Parameters
    ----------
    quick : bool
        48^2 and 12 steps per cycle, F0+ on 128^2 (else 96^2, 16 steps, F0+ on 256^2 and
        the comparison with Paper E's published F0+).

    Returns
    -------
    list of ValidationRow
    """
    n, steps = (48, 12) if quick else (96, 16)
    n_start, tol_md = (128, 0.15) if quick else (256, 0.08)
    rows = []
    metrics = []
    for w in WORKS:
        lp = paper_e_loop(w, n, steps=steps, cycles=2)
        m = loop_metrics(lp)
        metrics.append(m)
        case = f"paper_e dgamma={w * 1e3:g} mJ/m^2 {n}^2"
        rows.append(_indicator(case, f"slip annulus at A (1: 0 < stick ratio {m['stick_A']:.3f} < 1)",
                               0.0 < m["stick_A"] < 1.0))
        rows.append(_indicator(case, f"re-stick at A' (1: stick ratio {m['stick_A1']:.3f} > {m['stick_A']:.3f} at A)",
                               m["stick_A1"] > m["stick_A"]))
        rows.append(_row(case, "stick ratio at D (full slip)", 0.0, m["stick_D"], 0.05, scale=1.0))
        rows.append(_row(case, "stick ratio at D' (almost full stick)", 1.0, m["stick_D1"], 0.2, scale=1.0))
        rows.append(_row(case, "change of delta(+-F*) from cycle 1 to 2 over the loop width", 0.0,
                         m.get("loop_change", math.nan), 0.01, scale=1.0))
        rows.append(_row(case, "stick ratio, unloading at F vs reloading at -F (cycle 2), largest difference", 0.0,
                         m.get("stick_branch_asymmetry", math.nan), 0.05, scale=1.0))
        rows.append(_row(case, "point symmetry of loop 2 about its centre (largest deviation over the width)", 0.0,
                         m.get("branch_point_asymmetry", math.nan), 0.02, scale=1.0))
        off = m.get("offset_2", math.nan)
        rows.append(_row(case, f"sign of the loop centre (shifted by the first loading; centre/width "
                               f"{off / m.get('width_2', math.nan):+.3f})", 1.0,
                         float(np.sign(off)) if math.isfinite(off) else math.nan, 0.0, scale=1.0))
        rows.append(_row(case, "onset of the first loading over mu F0 vs F0+/F0", m["f0p_over_f0"],
                         m["onset_over_mu_f0"], 0.05))
        if w > 0:
            z = start_state(w, n_start)
            rows.append(_row(f"paper_e dgamma={w * 1e3:g} mJ/m^2 F_x=0 state {n_start}^2",
                             f"F0+ at A vs Maugis-Dugdale at F0 ((c - a)/dx = {z['cells_across_cohesive_zone']:.1f})",
                             m["md_repulsive_force"], z["repulsive_force"], tol_md))
            if not quick and math.isclose(w, 0.05):
                rows.append(_row(f"paper_e dgamma=50 mJ/m^2 F_x=0 state {n_start}^2",
                                 "F0+ at A vs Paper E's smooth 29.165 uN (same grid)",
                                 PAPER_E_SMOOTH_REPULSIVE_FORCE, z["repulsive_force"], 0.06))
        else:
            rows.append(_row(case, "half width of loop 2 vs Mindlin-Deresiewicz delta* at F*", m["mindlin_delta_star"],
                             m["half_width"], 0.10))
    case = f"paper_e ordering dgamma 0 < 50 < 100 mJ/m^2 {n}^2"

    def inc(key):
        v = [mm[key] for mm in metrics]
        return all(b > a for a, b in zip(v, v[1:])), v

    for key, label, unit, scale in (
        ("repulsive_force", "F0+ at A", "uN", 1e6),
        ("static_friction", "static friction F* (at D)", "uN", 1e6),
        ("onset_force", "static friction (gross-slip onset of the first loading)", "uN", 1e6),
        ("presliding_displacement", "pre-sliding displacement delta(D) - delta(A)", "nm", 1e9),
        ("onset_presliding_displacement", "pre-sliding displacement at the onset", "nm", 1e9),
    ):
        ok, v = inc(key)
        rows.append(_indicator(case, f"{label} increases ({', '.join(f'{x * scale:.4g}' for x in v)} {unit})", ok))
    md50 = md_state(0.05)["repulsive_force"]
    rows.append(_row("paper_e Maugis-Dugdale dgamma=50 mJ/m^2, z0=0.2 nm", "analytic F0+ vs Paper E's smooth 29.165 uN",
                     PAPER_E_SMOOTH_REPULSIVE_FORCE, md50, 0.03))
    return rows


#: name -> rows(quick)
CASES = {"paper_e": paper_e_rows}
