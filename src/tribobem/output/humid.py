"""Outputs of humid friction runs (kinds ``partial_slip`` and ``hysteresis`` with ``[humidity]``).

Such a run does one ramp (partial_slip) or one loop (hysteresis) per RH, in the order given,
after a dry reference run (:mod:`tribobem.runs.humid_friction`).  Its summary holds every step
of every RH in one ``steps`` list (each row with its ``rh``), the run-level values as lists in
RH order, and the dry reference's values under ``dry``.  Drawn as one line through all the
steps, the friction curve and the loops of several RHs tangle; this module splits them:

* :func:`rh_groups`, :func:`per_rh`, :func:`rh_summary`: the rows and run-level values of each
  RH (``rh_summary`` makes a dry-looking summary of one RH, so the dry figures and report
  tables can show it);
* ``humid_friction_rh``: static friction force and presliding displacement (partial_slip), or
  the lateral stiffness at Paper F's points A, B, C, the dissipated energy of the last cycle and
  the static friction / sliding force when reached (hysteresis), against RH, each with the dry
  value as a dashed line; and the capillary force of the zero-load state;
* ``humid_friction_curve``: F_x against delta_x, one curve (or loop) per RH coloured by RH,
  with the stick ratio below;
* the per-RH stick/slip maps (``stickslip_rh``, partial_slip: one per RH on a common zoom and
  traction scale) are :mod:`.figures`' (:func:`~tribobem.output.figures.humid_stickslip_figure`),
  which outlines the meniscus edge on every stick/slip map of a dataset with the ``meniscus``
  field.

Every function reads the summary and/or the fields dataset only, so ``tribobem plot`` re-makes
the figures from the files.  A dry run (a friction kind without ``[humidity]``,
:func:`~tribobem.output.run_kind.run_view`) gets nothing from here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..units import display_unit, format_value
from .plotting import finite as _num
from .plotting import friction_coefficient as _friction_coefficient
from .plotting import new_figure, save_png
from .run_kind import run_view

__all__ = ["FIGURE_NAMES", "rh_groups", "per_rh", "rh_summary"]

#: Figure names of this module, in report order.
FIGURE_NAMES = ("humid_friction_rh", "humid_friction_curve")

#: Run-level keys whose dry form is itself a list (per cycle, per point, a bracket): in a humid
#: run they are per RH only as a list of lists (or None), one per RH.
_LIST_SHAPED = ("dissipated_energy", "dissipation_work", "lateral_stiffness", "failed_steps", "onset_bracket",
                "solve_window", "ramp_message")
_DRY_STYLE = {"color": "0.35", "ls": "--", "lw": 1.2}


def rh_label(rh) -> str:
    """``"RH 30 %"`` for ``rh`` = 0.3 (a fraction, 0..1).

    Parameters
    ----------
    rh : float
        Relative humidity (fraction, dimensionless).

    Returns
    -------
    str
    """
    return f"RH {100.0 * float(rh):.3g} %"


def rh_groups(summary: dict) -> list[tuple[float, int, list[dict]]]:
    """The step rows of each RH, in run order.

    The rows of one RH are contiguous (one ramp or loop per RH), so a new group starts wherever
    ``rh`` changes; grouping by value instead would merge an RH given twice.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a humid friction run.

    Returns
    -------
    list of (float, int, list of dict)
        (RH as a fraction, index of the group's first row in ``steps``, its rows).
    """
    out: list[tuple[float, int, list[dict]]] = []
    for i, r in enumerate(summary.get("steps") or []):
        rh = _num(r.get("rh")) if isinstance(r, dict) else None
        if rh is None:
            continue
        if not out or out[-1][0] != rh or out[-1][1] + len(out[-1][2]) != i:
            out.append((rh, i, []))
        out[-1][2].append(r)
    return out


#: Summary keys that are never per RH (lists of their own whose length may equal the RH count).
_RUN_WIDE = frozenset(("steps", "rh", "dry", "warnings", "jumps", "inputs", "problem", "versions", "timings",
                       "expected", "files"))


def _per_rh_list(key: str, value, n: int) -> bool:
    """True when run-level ``value`` holds one entry per RH (see :data:`_LIST_SHAPED`)."""
    if key in _RUN_WIDE or not isinstance(value, (list, tuple)) or len(value) != n:
        return False
    if key in _LIST_SHAPED:
        return all(v is None or isinstance(v, (list, tuple, str)) for v in value)
    return True


def per_rh(summary: dict, key: str) -> list:
    """Run-level ``key`` for each RH of ``summary["rh"]``: the list's entries, or the one shared
    value repeated (a value equal at every RH stays a scalar in summary.json).

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a humid friction run.
    key : str
        A run-level key (e.g. ``"static_friction_force"``, N).

    Returns
    -------
    list
        One entry per RH (None where absent), in the units of the key.
    """
    n = len(summary.get("rh") or [])
    v = summary.get(key)
    return list(v) if _per_rh_list(key, v, n) else [v] * n


def rh_summary(summary: dict, index: int) -> tuple[dict, int]:
    """A summary of one RH of a humid friction run, shaped like a dry run's.

    The per-RH run-level lists become that RH's values, ``steps`` that RH's rows, ``rh`` the
    scalar RH (so its :func:`~tribobem.output.run_kind.run_view` is not ``humid_friction``) and ``dry`` is dropped: the dry
    figures and report tables can then show one RH.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a humid friction run.
    index : int
        Position in ``summary["rh"]`` (negative counts from the end).

    Returns
    -------
    (dict, int)
        The one-RH summary and the index of its first row in the full ``steps`` list (to map
        fields.nc ``summary_step`` values onto its rows).
    """
    rhs = list(summary.get("rh") or [])
    n = len(rhs)
    index = index % n
    groups = rh_groups(summary)
    rows, offset = [], 0
    if len(groups) == n:
        _, offset, rows = groups[index]
    else:  # the groups do not line up with the RH list: match by value
        match = [g for g in groups if g[0] == float(rhs[index])]
        if match:
            _, offset, rows = match[-1]
    sub = {}
    for k, v in summary.items():
        if k in ("rh", "dry", "steps"):
            continue
        sub[k] = v[index] if _per_rh_list(k, v, n) else v  # warnings, inputs ... stay whole
    sub["steps"] = list(rows)
    sub["rh"] = float(rhs[index])
    return sub, offset


def zero_load_row(rows: list[dict]) -> dict | None:
    """The row of least |F_x| (the state at zero tangential load; the first such row).

    Parameters
    ----------
    rows : list of dict
        Step rows of one RH.

    Returns
    -------
    dict or None
        None for no rows.
    """
    best, low = None, np.inf
    for r in rows:
        fx = _num(r.get("tangential_force_x"))
        if fx is not None and abs(fx) < low:
            best, low = r, abs(fx)
    return best if best is not None else (rows[0] if rows else None)


def rh_colors(rhs) -> list:
    """One colour per RH (viridis from the lowest to the highest RH), so that the curves of
    every figure of a run share their colours.

    Parameters
    ----------
    rhs : sequence of float
        The RH values (fractions).

    Returns
    -------
    list of RGBA tuples
    """
    import matplotlib as mpl

    cmap = mpl.colormaps["viridis"]
    r = np.asarray(list(rhs), dtype=float)
    if r.size == 0:
        return []
    lo, hi = float(np.min(r)), float(np.max(r))
    t = (r - lo) / (hi - lo) if hi > lo else np.zeros_like(r)
    # 0.05..0.85: the yellow end of viridis is hard to see on white
    return [cmap(0.05 + 0.8 * float(v)) for v in t]


def _capillary_at_zero(summary: dict) -> list:
    """Capillary force (N) of each RH's zero-load state: the run-level list, else its rows."""
    vals = per_rh(summary, "capillary_force")
    if any(_num(v) is not None for v in vals):
        return vals
    groups = rh_groups(summary)
    if len(groups) != len(summary.get("rh") or []):
        return vals
    return [(zero_load_row(rows) or {}).get("capillary_force") for _, _, rows in groups]


def _last_cycle(values) -> float | None:
    """The last finite entry of a per-cycle list (J), or the value itself."""
    if isinstance(values, (list, tuple)):
        for v in reversed(values):
            if _num(v) is not None:
                return float(v)
        return None
    return _num(values)


def _stiffness_at(table, point: str) -> float | None:
    """K_L (N/m) of Paper F's ``point`` (A, B or C) in one lateral_stiffness table."""
    for t in table or []:
        if isinstance(t, dict) and t.get("point") == point:
            return _num(t.get("stiffness"))
    return None


def _stiffness_unit(values):
    a = np.abs(np.asarray([v for v in values if v is not None], dtype=float))
    a = a[np.isfinite(a) & (a > 0)]
    peak = float(a.max()) if a.size else 1.0
    for label, f in (("N/\u00b5m", 1e6), ("N/mm", 1e3), ("N/m", 1.0)):
        if peak >= f:
            return f, label
    return 1.0, "N/m"


def _panel(ax, x, series, dry, ylabel_dim, title, *, unit=None):
    """One against-RH panel: ``series`` [(label, values, colour, marker)], ``dry`` [(value,
    colour)] drawn as dashed lines; ``unit`` a (factor, label) pair for a dimension that
    :func:`~tribobem.units.display_unit` does not know (stiffness)."""
    allv = [v for _, vals, _, _ in series for v in vals if v is not None]
    allv += [v for v, _ in dry if v is not None]
    if unit is None:
        f, lab = display_unit(allv or [1.0], ylabel_dim)
    else:
        f, lab = unit
    for label, vals, color, marker in series:
        y = np.array([np.nan if _num(v) is None else float(v) for v in vals]) / f
        if np.isfinite(y).any():
            ax.plot(x, y, marker=marker, ms=6, lw=1.4, color=color, label=label, zorder=3)
    dry_drawn = False
    for v, color in dry:
        if _num(v) is not None:
            ax.axhline(float(v) / f, **{**_DRY_STYLE, "color": color}, zorder=2)
            dry_drawn = True
    if dry_drawn:
        from matplotlib.lines import Line2D

        handles, labels = ax.get_legend_handles_labels()
        handles.append(Line2D([], [], **_DRY_STYLE))
        labels.append("dry")
        ax.legend(handles, labels, fontsize=8, loc="best", framealpha=0.9)
    elif len(series) > 1:
        ax.legend(fontsize=8, loc="best", framealpha=0.9)
    ax.set_xlabel("relative humidity RH (%)")
    ax.set_ylabel(f"{title} ({lab})" if lab else title)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.margins(x=0.12, y=0.15)


def humid_rh_figure(summary: dict, path) -> Path | None:
    """Friction values against RH with the dry (Dugdale) reference as dashed lines.

    partial_slip: the static friction force (with mu F0+ at the onset, the most the contact
    carries), the presliding displacement; hysteresis: the lateral stiffness K_L at Paper F's
    points A, B, C, the dissipated energy (loop area) of the last cycle, and the static friction
    and sliding forces when a loop reached them; both: the capillary force of the zero-load
    state.  None (nothing written) for a run that is not a humid friction run.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json): its run-level lists in RH order and ``dry``.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
        The written PNG file, or None when nothing was drawn.
    """
    if not run_view(summary).humid_friction:
        return None
    rhs = [float(v) for v in summary["rh"]]
    x = 100.0 * np.asarray(rhs)
    dry = summary.get("dry") or {}
    mu = _friction_coefficient(summary)
    panels = []  # (title, dimension, series, dry lines, unit)
    if run_view(summary).hysteresis:
        tables = per_rh(summary, "lateral_stiffness")
        colors = {"A": "#1f77b4", "B": "#d62728", "C": "#2ca02c"}
        series = [(f"K$_L$ at {p}", [_stiffness_at(t, p) for t in tables], c, "o") for p, c in colors.items()]
        drylines = [(_stiffness_at(dry.get("lateral_stiffness"), p), c) for p, c in colors.items()]
        if any(v is not None for _, vals, _, _ in series for v in vals):
            allk = [v for _, vals, _, _ in series for v in vals] + [v for v, _ in drylines]
            panels.append(("lateral stiffness $K_L$", None, series, drylines, _stiffness_unit(allk)))
        energy = [_last_cycle(v) for v in per_rh(summary, "dissipated_energy")]
        if any(v is not None for v in energy):
            panels.append(("dissipated energy, last cycle", "energy",
                           [("loop area \u222e F$_x$ d\u03b4$_x$", energy, "#6a4c93", "o")],
                           [(_last_cycle(dry.get("dissipated_energy")), "0.35")], None))
        sff, sld = per_rh(summary, "static_friction_force"), per_rh(summary, "sliding_force")
        if any(_num(v) is not None for v in sff + sld + [dry.get("static_friction_force"), dry.get("sliding_force")]):
            panels.append(("static friction and sliding force", "force",
                           [("static friction", sff, "#e76f51", "o"), ("sliding force", sld, "#264653", "s")],
                           [(dry.get("static_friction_force"), "#e76f51"), (dry.get("sliding_force"), "#264653")],
                           None))
    else:
        sff = per_rh(summary, "static_friction_force")
        series = [("static friction force", sff, "#e76f51", "o")]
        f0 = per_rh(summary, "onset_repulsive_force")
        if mu is not None and any(_num(v) is not None for v in f0):
            series.append(("\u03bc F$_0^+$ at the onset", [mu * v if _num(v) is not None else None for v in f0],
                           "0.55", "s"))
        panels.append(("static friction force", "force", series, [(dry.get("static_friction_force"), "0.35")], None))
        pre = per_rh(summary, "presliding_displacement")
        if any(_num(v) is not None for v in pre) or _num(dry.get("presliding_displacement")) is not None:
            panels.append(("presliding displacement", "length", [("presliding displacement", pre, "#2a9d8f", "o")],
                           [(dry.get("presliding_displacement"), "0.35")], None))
    cap = _capillary_at_zero(summary)
    if any(_num(v) is not None for v in cap):
        # the dry reference has no meniscus: no dry line (its capillary force is zero)
        panels.append(("capillary force at $F_x$ = 0", "force", [("F$_{cap}$ (< 0 tensile)", cap, "#2b7bba", "o")],
                       [], None))
    if not panels:
        return None
    n = len(panels)
    ncol = 2 if n in (2, 4) else min(n, 3)
    nrow = -(-n // ncol)
    fig = new_figure(4.6 * ncol, 3.9 * nrow + 0.3)
    axes = fig.subplots(nrow, ncol, squeeze=False)
    for ax, (title, dim, series, drylines, unit) in zip(axes.flat, panels):
        _panel(ax, x, series, drylines, dim, title, unit=unit)
        if dim == "force" and "capillary" in title:
            ax.axhline(0.0, color="0.6", lw=0.6)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(f"humid friction against RH ({summary.get('kind', '')}, \u03bc = {mu:g})" if mu is not None
                 else f"humid friction against RH ({summary.get('kind', '')})", fontsize=11)
    return save_png(fig, path)


def humid_curve_figure(summary: dict, path) -> Path | None:
    """F_x against delta_x, one curve (partial_slip: the ramp, its gross-slip onset starred) or
    loop (hysteresis: cycle 0, the initial loading, dashed) per RH, coloured by RH; below, the
    stick ratio per RH against F_x/(mu F0+) (partial_slip) or along each loop's steps
    (hysteresis).  The dry reference keeps no steps: its static friction force, when known, is
    a dashed line.  None for a run that is not a humid friction run.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a humid friction run.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
        The written PNG file, or None when nothing was drawn.
    """
    if not run_view(summary).humid_friction:
        return None
    groups = [(rh, [r for r in rows if _num(r.get("tangential_force_x")) is not None
                    and _num(r.get("displacement_x")) is not None]) for rh, _, rows in rh_groups(summary)]
    groups = [(rh, rows) for rh, rows in groups if len(rows) >= 2]
    if not groups:
        return None
    hyst = run_view(summary).hysteresis
    mu = _friction_coefficient(summary)
    colors = rh_colors([rh for rh, _ in groups])
    F = np.concatenate([[float(r["tangential_force_x"]) for r in rows] for _, rows in groups])
    D = np.concatenate([[float(r["displacement_x"]) for r in rows] for _, rows in groups])
    dry = summary.get("dry") or {}
    dry_sff = _num(dry.get("static_friction_force"))
    ff, fl = display_unit(np.concatenate([F, [dry_sff] if dry_sff is not None else []]), "force")
    df, dl = display_unit(D, "length")
    sff = per_rh(summary, "static_friction_force")
    pre = per_rh(summary, "presliding_displacement")
    ratio = per_rh(summary, "static_friction_ratio")
    rhs = [float(v) for v in summary["rh"]]
    has_sr = all(_num(r.get("stick_ratio")) is not None for _, rows in groups for r in rows)

    fig = new_figure(6.8, 8.2 if has_sr else 5.0)
    if has_sr:
        ax, ax2 = fig.subplots(2, 1, height_ratios=[1.6, 1.0])
    else:
        ax, ax2 = fig.add_subplot(), None
    for (rh, rows), color in zip(groups, colors):
        f = np.array([float(r["tangential_force_x"]) for r in rows])
        d = np.array([float(r["displacement_x"]) for r in rows])
        ms = 3.5 if len(rows) <= 60 else 0
        if hyst:
            cyc = np.array([int(_num(r.get("cycle")) or 0) for r in rows])
            first = cyc == 0
            # the initial loading (cycle 0) dashed, then the cycles solid, joined at the turn
            if first.any():
                k = int(np.nonzero(first)[0][-1])
                ax.plot(d[:k + 1] / df, f[:k + 1] / ff, color=color, lw=1.2, ls="--", alpha=0.8)
                d, f = d[k:], f[k:]
            ax.plot(d / df, f / ff, color=color, lw=1.5, label=rh_label(rh))
        else:
            ax.plot(d / df, f / ff, color=color, lw=1.5, marker="o", ms=ms, label=rh_label(rh))
            i = rhs.index(rh) if rh in rhs else None
            if i is not None and _num(sff[i]) is not None and _num(pre[i]) is not None:
                zero = zero_load_row(rows)
                d0 = float(zero["displacement_x"]) if zero is not None else 0.0
                ax.plot([(d0 + float(pre[i])) / df], [float(sff[i]) / ff], marker="*", ms=13, color=color, mec="k",
                        ls="none", zorder=5)
        bad = [j for j, r in enumerate(rows) if not r.get("converged", True)]
        if bad:
            fb = np.array([float(rows[j]["tangential_force_x"]) for j in bad])
            db = np.array([float(rows[j]["displacement_x"]) for j in bad])
            ax.plot(db / df, fb / ff, "x", color="k", ms=7, zorder=6)
    if dry_sff is not None:
        ax.axhline(dry_sff / ff, **_DRY_STYLE, label=f"dry static friction {format_value(dry_sff, 'force', 3)}")
    ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.6", lw=0.6, zorder=0)
    handles, labels = ax.get_legend_handles_labels()
    from matplotlib.lines import Line2D

    if not hyst and any(_num(v) is not None for v in sff):
        handles.append(Line2D([], [], marker="*", ms=11, color="0.5", mec="k", ls="none"))
        labels.append("gross-slip onset")
    if hyst:
        handles.append(Line2D([], [], color="0.4", lw=1.2, ls="--"))
        labels.append("cycle 0 (initial loading)")
    if any(not r.get("converged", True) for _, rows in groups for r in rows):
        handles.append(Line2D([], [], marker="x", color="k", ls="none"))
        labels.append("not converged")
    ax.legend(handles, labels, fontsize=8, loc="upper left" if hyst else "lower right", framealpha=0.9)
    ax.set_xlabel(f"tangential displacement $\\delta_x$ ({dl})")
    ax.set_ylabel(f"tangential force $F_x$ ({fl})")
    ax.grid(alpha=0.3)
    ax.margins(x=0.06, y=0.08)
    ax.set_title("friction hysteresis loops per RH" if hyst else "friction curve per RH", fontsize=10)

    if ax2 is not None:
        for (rh, rows), color in zip(groups, colors):
            sr = np.array([float(r["stick_ratio"]) for r in rows])
            if hyst:
                ax2.plot(np.arange(len(rows)), sr, color=color, lw=1.3, label=rh_label(rh))
                continue
            f0 = np.array([_num(r.get("repulsive_force")) or np.nan for r in rows])
            f = np.array([float(r["tangential_force_x"]) for r in rows])
            if mu is not None and np.all(f0 > 0):
                xv = f / (mu * f0)
            else:
                xv = f / ff
            ax2.plot(xv, sr, color=color, lw=1.4, marker="o", ms=3.5 if len(rows) <= 60 else 0,
                     label=rh_label(rh))
            i = rhs.index(rh) if rh in rhs else None
            if i is not None and mu is not None and _num(ratio[i]) is not None:
                ax2.axvline(float(ratio[i]), color=color, ls=":", lw=1.1)
        if hyst:
            ax2.set_xlabel("step of the RH's loop")
            ax2.set_title("stick ratio along each loop", fontsize=9)
        else:
            all_f0 = all((_num(r.get("repulsive_force")) or 0) > 0 for _, rows in groups for r in rows)
            ax2.set_xlabel(r"$F_x\,/\,(\mu F_0^+)$ ($F_0^+$ of each step; dotted: the onset)" if mu and all_f0
                           else f"tangential force $F_x$ ({fl})")
            ax2.set_title("stick ratio along each ramp", fontsize=9)
        ax2.set_ylabel(r"stick ratio $A_\mathrm{stick}/A_\mathrm{c}$")
        ax2.set_ylim(-0.03, 1.05)
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize=8, loc="best", framealpha=0.9)
    return save_png(fig, path)


def humid_friction_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``humid_friction``: ``humid_friction_rh`` and ``humid_friction_curve``
    (:func:`humid_rh_figure`, :func:`humid_curve_figure`); nothing for a dry run.

    The per-RH stick/slip maps (``stickslip_rh``) belong to the ``friction`` set, which draws
    the stick/slip maps of every tangential run.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); unused (both figures come from the summary), taken
        for the figure-set signature.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty for a dry run.
    """
    if not run_view(summary).humid_friction:
        return {}
    outdir = Path(outdir)
    out = {}
    for name, func in (("humid_friction_rh", humid_rh_figure), ("humid_friction_curve", humid_curve_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except (KeyError, TypeError, ValueError, IndexError):  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
    return out
