"""The interface laws of a two-scale run (``[two_scale]``): the micro windows' mean gap and real
contact fraction against nominal pressure, with the pressures the macro solve used, and (ramps
and loops) their slip and stick fraction against the shear."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...units import display_unit
from ..plotting import COLORS, new_figure, save_png


def interface_law_figure(summary: dict, path) -> Path | None:
    """Two panels: mean gap g(p) (with +-1 standard deviation over the realisations) and real
    contact fraction against nominal pressure, with the largest load's mean and largest
    nominal pressure marked.
    None (nothing written) without a two-scale table in the summary.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json); its ``two_scale.law`` table.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
    """
    law = (summary.get("two_scale") or {}).get("law")
    if not law:
        return None
    p = np.asarray(law["pressures"], dtype=float)
    g = np.asarray(law["gaps"], dtype=float)
    sd = np.asarray(law.get("gap_spread", np.zeros_like(g)), dtype=float)
    frac = np.asarray(law["contact_fractions"], dtype=float)
    pf, pl = display_unit(p, "pressure")
    gf, gl = display_unit(np.concatenate([g, [law["touch_gap"]]]), "length")
    fig = new_figure(10.0, 4.2)
    ax1, ax2 = fig.subplots(1, 2)
    ax1.fill_between(p / pf, (g - sd) / gf, (g + sd) / gf, color=COLORS["loading"], alpha=0.25, lw=0,
                     label=f"+-1 s.d. over {law.get('realisations', 1)} realisation(s)")
    ax1.plot(p / pf, g / gf, "o-", color=COLORS["loading"], ms=3, label="mean gap of the windows")
    ax1.axhline(law["touch_gap"] / gf, color="0.4", ls="--", lw=1, label="first touch g(0)")
    ax2.plot(p / pf, frac, "o-", color=COLORS["unloading"], ms=3)
    steps = [s for s in summary.get("steps", []) if s.get("max_nominal_pressure")]
    if steps:
        last = steps[-1]  # the largest load: its mean and largest nominal pressure
        mean_p = float(last["normal_force"]) / max(float(last.get("nominal_contact_area") or 0.0), 1e-300)
        for ax in (ax1, ax2):
            ax.axvline(mean_p / pf, color="0.3", ls=":", lw=1.2, label="macro: mean pressure" if ax is ax1 else None)
            ax.axvline(float(last["max_nominal_pressure"]) / pf, color="0.3", ls="-.", lw=1.2,
                       label="macro: largest pressure" if ax is ax1 else None)
    for ax in (ax1, ax2):
        ax.set_xscale("log")
        ax.set_xlabel(f"nominal pressure ({pl})")
        ax.grid(True, which="both", alpha=0.3)
    ax1.set_ylabel(f"mean gap of the mean planes ({gl})")
    ax2.set_yscale("log")
    ax2.set_ylabel("real contact fraction A_r/A")
    ax1.set_title("interface law (micro windows)")
    ax2.set_title("real contact fraction")
    ax1.legend(fontsize=10, loc="lower left")
    return save_png(fig, path)


def slip_law_figure(summary: dict, path) -> Path | None:
    """The tangential law of the windows (a two-scale ramp or loop): their slip against the shear
    fraction f = tau / capacity (mu p dry, mu p_rep with menisci) and their stick fraction, at
    four of the tabulated pressures.  None (nothing written) without a slip table.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json); its ``two_scale.slip_law`` table.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
    """
    law = (summary.get("two_scale") or {}).get("slip_law")
    if not law:
        return None
    p = np.asarray(law["pressures"], dtype=float)
    f = np.concatenate([[0.0], np.asarray(law["fractions"], dtype=float)])
    slips = np.asarray(law["slips"], dtype=float)
    stick = np.asarray(law["stick_ratios"], dtype=float)
    rows = sorted(set(np.linspace(0, p.size - 1, 4).round().astype(int).tolist()))
    pf, pl = display_unit(p, "pressure")
    sf, sl = display_unit(slips[rows], "length")
    fig = new_figure(10.0, 4.2)
    ax1, ax2 = fig.subplots(1, 2)
    palette = ("#1f77b4", "#2ca02c", "#ff7f0e", "#d62728")
    for c, i in zip(palette, rows):
        label = f"p = {p[i] / pf:.3g} {pl}"
        ax1.plot(f, np.concatenate([[0.0], slips[i]]) / sf, "o-", ms=3, color=c, label=label)
        ax2.plot(f, np.concatenate([[1.0], stick[i]]), "o-", ms=3, color=c, label=label)
    bound = "mu p_rep (menisci)" if law.get("capacities") else "mu p"
    for ax in (ax1, ax2):
        ax.set_xlabel(f"shear fraction tau / ({bound})")
        ax.grid(True, alpha=0.3)
    ax1.set_ylabel(f"interface slip s ({sl})")
    ax2.set_ylabel("stick fraction of the real contact")
    ax1.set_title(f"slip law (micro windows, mu = {law.get('friction_coefficient', float('nan')):g})")
    ax2.set_title("stick fraction")
    ax1.legend(fontsize=10, loc="upper left")
    return save_png(fig, path)
