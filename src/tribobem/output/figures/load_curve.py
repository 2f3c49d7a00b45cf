"""The force-approach curve (loading, unloading and reloading branches, pull-off and jumps).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...units import display_unit, format_value
from ..plotting import COLORS, new_figure, save_png


def force_curve_figure(summary: dict, path) -> Path | None:
    """Force-approach curve: loading and unloading branches, pull-off and jumps marked.
    None (nothing written) when the run has fewer than two steps.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json), its ``steps`` rows in particular.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
        The written PNG file, or None when nothing was drawn.
    """
    steps = [s for s in summary.get("steps", []) if s.get("normal_force") is not None and s.get("approach") is not None]
    if len(steps) < 2:
        return None
    d = np.array([s["approach"] for s in steps], dtype=float)
    f = np.array([s["normal_force"] for s in steps], dtype=float)
    branch = np.array([s.get("branch", "loading") for s in steps])
    conv = np.array([bool(s.get("converged", True)) for s in steps])
    extra_f = [summary.get("pull_off_force")] if summary.get("pull_off_force") is not None else []
    df, dl = display_unit(d, "length")
    ff, fl = display_unit(np.concatenate([f, np.asarray(extra_f, dtype=float)]), "force")
    fig = new_figure(6.4, 4.6)
    ax = fig.add_subplot()
    for name, marker in (("loading", "o"), ("unloading", "s")):
        m = branch == name
        if m.any():
            ax.plot(d[m] / df, f[m] / ff, marker=marker, ms=3.5, lw=1.3, color=COLORS[name], label=name)
    if (~conv).any():
        ax.plot(d[~conv] / df, f[~conv] / ff, "x", color="k", ms=7, label="not converged")
    ax.axhline(0.0, color="0.5", lw=0.6)
    po = summary.get("pull_off_force")
    pa = summary.get("pull_off_approach")
    if po is not None and pa is not None and po < 0:
        ax.plot([pa / df], [po / ff], marker="*", ms=14, color="#e9c46a", mec="k", ls="none",
                label=f"pull-off {format_value(po, 'force', 3)}", zorder=5)
    seen = set()
    for j in summary.get("jumps") or []:
        if j.get("approach") is None or j.get("force") is None:
            continue
        kind = j.get("kind", "jump")
        ax.plot([j["approach"] / df], [j["force"] / ff], marker="^" if kind == "jump-in" else "v", ms=9,
                mfc="none", mec="k", ls="none", label=None if kind in seen else kind)
        seen.add(kind)
    ax.set_xlabel(f"approach \u03b4 ({dl})")
    ax.set_ylabel(f"normal force F ({fl}), > 0 compressive")
    ax.grid(alpha=0.3)
    fmax = float(np.nanmax(np.abs(f))) if f.size else 0.0
    if po is not None and pa is not None and po < 0 and fmax > 0 and abs(po) < 0.1 * fmax:
        _pull_off_inset(ax, d, f, branch, po, pa, df)
        ax.legend(fontsize=8, loc="lower right")
    else:
        ax.legend(fontsize=8, loc="best")
    ax.set_title(f"force-approach curve ({summary.get('kind', '')})", fontsize=10)
    return save_png(fig, path)


def _pull_off_inset(ax, d, f, branch, po, pa, df):
    """Zoom on the tensile part of the curve when pull-off is small against the preload."""
    band = np.abs(f) <= 3.0 * abs(po)
    if band.sum() < 2:
        return
    ffi, fli = display_unit([po], "force")
    ins = ax.inset_axes([0.1, 0.5, 0.42, 0.4])
    for name, marker in (("loading", "o"), ("unloading", "s")):
        m = (branch == name) & band
        if m.any():
            ins.plot(d[m] / df, f[m] / ffi, marker=marker, ms=3, lw=1.0, color=COLORS[name])
    ins.plot([pa / df], [po / ffi], marker="*", ms=11, color="#e9c46a", mec="k", ls="none")
    ins.axhline(0.0, color="0.5", lw=0.6)
    ins.set_ylim(1.4 * po / ffi, 2.0 * abs(po) / ffi)
    ins.set_title(f"near pull-off (F in {fli})", fontsize=7)
    ins.tick_params(labelsize=7)
    ins.grid(alpha=0.3)
