"""Figures of the hysteresis kind (Papers E and F): the loop F_x - delta_x with Paper E's
points (A, D, D', H ...) and the analytic loop of the geometry
(:mod:`tribobem.analytic.friction_loops`), the lateral stiffness at Paper F's points A, B, C,
the last cycle's dissipation and accumulated-slip maps, and the stick/slip maps at Paper E's
points in one figure.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...units import display_unit, format_value
from ..plotting import keep_inside, map_extent, new_figure, save_png
from ..plotting import finite as _num
from ..plotting import friction_coefficient as _friction_coefficient
from ...analytic.friction_loops import kl_reference, kl_reference_values, loop_reference, loop_rows
from ...analytic.friction_loops import reference_branches
from .stickslip import _common_map_window, _segments, _stickslip_axes
from .stickslip import _tangential_step_indices, _zoom_window



_CYCLE_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
_BRANCH_MARKERS = {"start": "o", "loading": "o", "unloading": "v", "reloading": "^"}
#: Paper E's names of the turning points, in order (A is the start; the step after a point is
#: primed: A', D', H' ...).
_TURNING_LETTERS = "DHLPTX"
_MAX_LOOP_MAPS = 6


def turning_point_letters(rows: list) -> dict:
    """Paper E's names of the summary rows: the start A (F_x = 0, row 0), the turning points
    D, H, L, P, T, X (then TP7, TP8 ...) -- the last row of each branch -- and the row right
    after each of them primed (A', D', H' ...).

    Returns
    -------
    dict
        Row index -> letter.

    Parameters
    ----------
    rows : list of dict
        The summary.json step rows of a hysteresis run (with ``cycle`` and ``branch``).
    """
    out = {}
    n = len(rows)
    if n == 0:
        return out
    out[0] = "A"
    if n > 1:
        out[1] = "A'"
    k = 0
    for i in range(1, n):
        b = rows[i].get("branch")
        if b == "start":
            continue
        key = (b, rows[i].get("cycle"))
        nxt = (rows[i + 1].get("branch"), rows[i + 1].get("cycle")) if i + 1 < n else None
        if nxt != key:
            k += 1
            name = _TURNING_LETTERS[k - 1] if k <= len(_TURNING_LETTERS) else f"TP{k}"
            out[i] = name
            if i + 1 < n:
                out[i + 1] = name + "'"
    return out


def _cycle_of(r) -> int:
    c = _num(r.get("cycle"))
    return int(c) if c is not None else 0




def hysteresis_loop_figure(summary: dict, path) -> Path | None:
    """Friction hysteresis loop F_x against delta_x, one colour per cycle (cycle 0, the initial
    loading, dashed), Paper E's points marked (A, A', turning points D, H, L ... and D', H' ...),
    the analytic loop of the geometry overlaid when there is one (:func:`loop_reference`); below,
    the stick ratio along the path against the step index, markers by branch.  None when the
    rows lack F_x or delta_x.

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
    rows = loop_rows(summary)
    if not rows:
        return None
    F = np.array([float(r["tangential_force_x"]) for r in rows])
    D = np.array([float(r["displacement_x"]) for r in rows])
    if not np.any(F != 0):
        return None
    cyc = np.array([_cycle_of(r) for r in rows])
    branch = [str(r.get("branch") or "") for r in rows]
    sr = np.array([_num(r.get("stick_ratio")) if _num(r.get("stick_ratio")) is not None else np.nan for r in rows])
    letters = turning_point_letters(rows)
    ref = loop_reference(summary)
    extra_d = [D.min(), D.max()]
    ff, fl = display_unit(F, "force")
    df, dl = display_unit(np.concatenate([D - D[0], extra_d]), "length")
    has_sr = np.isfinite(sr).sum() >= 2

    fig = new_figure(6.6, 8.4 if has_sr else 5.4)
    if has_sr:
        ax, ax2 = fig.subplots(2, 1, height_ratios=[1.7, 1.0])
    else:
        ax, ax2 = fig.add_subplot(), None
    ms = 3.5 if len(rows) <= 120 else 0
    segs = _segments(rows)
    seen = set()
    for b, idx in segs:
        c = int(cyc[idx[-1]])
        color = _CYCLE_COLORS[c % len(_CYCLE_COLORS)]
        lab = None
        if c not in seen:
            lab = "cycle 0 (initial loading)" if c == 0 else f"cycle {c}"
            seen.add(c)
        ax.plot(D[idx] / df, F[idx] / ff, color=color, lw=1.5, ls="--" if c == 0 else "-",
                marker=_BRANCH_MARKERS.get(b, "o") if ms else None, ms=ms, label=lab, zorder=2)
    if ref is not None:
        for k, (q, d) in enumerate(reference_branches(ref)):
            ax.plot(d / df, q / ff, color="0.55", lw=6, alpha=0.35, solid_capstyle="round", zorder=1,
                    label=f"{ref['name']} (analytic)" if k == 0 else None)
    conv = np.array([bool(r.get("converged", True)) for r in rows])
    if (~conv).any():
        ax.plot(D[~conv] / df, F[~conv] / ff, "x", color="k", ms=8, mew=1.5, label="not converged", zorder=4)
    ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.6", lw=0.6, zorder=0)
    ax.margins(x=0.1, y=0.1)
    names = _label_points(ax, D / df, F / ff, letters)
    ax.set_xlabel(f"tangential displacement $\\delta_x$ ({dl})")
    ax.set_ylabel(f"tangential force $F_x$ ({fl})")
    ax.grid(alpha=0.3)
    mu = _friction_coefficient(summary)
    f0p = _num(summary.get("repulsive_force")) or _num(rows[0].get("repulsive_force"))
    if mu is not None and f0p is not None and f0p > 0:
        sec = ax.secondary_yaxis("right", functions=(lambda v, s=ff / (mu * f0p): v * s,
                                                     lambda v, s=ff / (mu * f0p): v / s))
        sec.set_ylabel(r"$F_x\,/\,(\mu F_0^+)$")
    handles, labels = ax.get_legend_handles_labels()
    if ms and len(set(branch) - {"start"}) > 1:
        from matplotlib.lines import Line2D

        for b, m in (("unloading", "v"), ("reloading", "^")):
            if b in branch:
                handles.append(Line2D([], [], color="0.3", marker=m, ls="none", ms=5))
                labels.append(b)
    # below the panels, not inside: a loop fills a corner or the centre depending on its shape
    # (lens or rectangle), and the colours and markers are those of the stick-ratio panel too
    fig.legend(handles, labels, fontsize=10, loc="outside lower center", ncols=min(len(labels), 3), frameon=False)
    title = "friction hysteresis loop"
    if _num(summary.get("rh")) is not None:  # one RH of a humid run
        title += f" at RH {100 * float(summary['rh']):.3g} %"
    peak = _num(summary.get("peak_force"))
    if peak is not None and mu is not None and f0p:
        title += f", $F^*$ = {format_value(peak, 'force', 3)} = {peak / (mu * f0p):.3g} $\\mu F_0^+$"
    else:
        path_in = (((summary.get("inputs") or {}).get("friction") or {}).get("path") or {})
        stroke = _num(path_in.get("stroke")) if isinstance(path_in, dict) else None
        if stroke is not None:
            title += f", displacement control, stroke {format_value(stroke, 'length', 3)}"
    ax.set_title(title, fontsize=10)

    if ax2 is not None:
        # one RH of a humid run holds that RH's rows only: number them as summary.json does
        k0 = int(_num(rows[0].get("index")) or 0) if _num(summary.get("rh")) is not None else 0
        k = np.arange(len(rows)) + k0
        for b, idx in segs:
            c = int(cyc[idx[-1]])
            color = _CYCLE_COLORS[c % len(_CYCLE_COLORS)]
            ax2.plot(k[idx], sr[idx], color=color, lw=1.4, ls="--" if c == 0 else "-",
                     marker=_BRANCH_MARKERS.get(b, "o") if ms else None, ms=ms)
        # turning points (and A): a dotted line, the name along the top; primed points: beside them
        names2 = []
        for i, name in letters.items():
            if name.endswith("'"):
                if np.isfinite(sr[i]):
                    names2.append(ax2.annotate(name, (k[i], sr[i]), xytext=(5, 0), textcoords="offset points",
                                               fontsize=10, fontweight="bold", ha="left", va="center", color="0.15"))
                continue
            if name != "A":
                ax2.axvline(k[i], color="0.5", lw=0.7, ls=":", zorder=0)
            names2.append(ax2.annotate(name, (k[i], 1.075), xytext=(0, 0), textcoords="offset points", ha="center",
                                       va="center", fontsize=10, fontweight="bold", color="0.15"))
        ax2.set_ylim(-0.03, 1.13)
        ax2.set_xlim(k0 - 0.04 * len(rows) - 0.5, k0 + 1.02 * len(rows) - 0.5)
        ax2.set_xlabel("step (summary.json index)")
        ax2.set_ylabel(r"stick ratio $A_\mathrm{stick}/A_\mathrm{c}$")
        ax2.grid(alpha=0.3)
        ax2.set_title("stick ratio along the path (\u25bc unloading, \u25b2 reloading)" if ms
                      else "stick ratio along the path", fontsize=10)
    # the names beside points at the ends of the range: inside the frame, off the tick labels
    keep_inside(ax, names)
    if ax2 is not None:
        keep_inside(ax2, names2)
    return save_png(fig, path)


def _label_points(ax, x, y, letters: dict) -> list:
    """Mark and name Paper E's points on the loop: A a square, turning points filled, primed
    points open.  Turning points are named away from the loop's centre; a primed point (on the
    next branch, just after its turning point) outside that branch: below right after a
    maximum, above left after a minimum.  Points drawn at the same place share one name
    ("D, L").  Returns the name annotations."""
    xs = np.ptp(x) or 1.0
    ys = np.ptp(y) or 1.0
    cy = 0.5 * (y.max() + y.min())
    groups = []  # [(index, [names])], merged when within 1 % of the loop's size
    for i, name in sorted(letters.items()):
        for g in groups:
            j = g[0]
            if (abs(x[i] - x[j]) < 0.05 * xs and abs(y[i] - y[j]) < 0.05 * ys
                    and g[1][0].endswith("'") == name.endswith("'")):
                g[1].append(name)
                g[2].append(i)
                break
        else:
            groups.append((i, [name], [i]))
    out = []
    for i, names, members in groups:
        name = names[0]
        prime = name.endswith("'")
        if name == "A":
            ax.plot(x[i], y[i], "s", ms=7, mfc="w", mec="k", mew=1.2, zorder=5)
        elif prime:
            ax.plot(x[members], y[members], "o", ms=6, mfc="w", mec="k", mew=1.0, ls="none", zorder=5)
        else:
            ax.plot(x[members], y[members], "o", ms=6, mfc="k", mec="k", ls="none", zorder=5)
        up = y[i] >= cy
        if name == "A":
            off, ha = (0, -13), "center"
        elif name == "A'":
            off, ha = (-8, 9), "right"
        elif prime:
            off, ha = ((9, -9), "left") if up else ((-9, 9), "right")
        else:  # above a maximum, below a minimum
            off, ha = ((0, 12), "center") if up else ((0, -12), "center")
        out.append(ax.annotate(", ".join(names), (x[i], y[i]), xytext=off, textcoords="offset points", fontsize=10,
                               fontweight="bold", ha=ha, va="center", zorder=6,
                               bbox={"boxstyle": "round,pad=0.1", "fc": "w", "ec": "none", "alpha": 0.7}))
    return out


def _stiffness_unit(values):
    a = np.abs(np.asarray(values, dtype=float))
    a = a[np.isfinite(a) & (a > 0)]
    peak = float(a.max()) if a.size else 1.0
    for label, f in (("N/\u00b5m", 1e6), ("N/mm", 1e3), ("N/m", 1.0)):
        if peak >= f:
            return f, label
    return 1.0, "N/m"


def _stiffness_table(summary: dict) -> list[dict]:
    out = []
    for t in (summary or {}).get("lateral_stiffness") or []:
        if isinstance(t, dict) and _num(t.get("force_ratio")) is not None and _num(t.get("stiffness")) is not None:
            out.append(t)
    return out


def _last_reloading_branch(summary: dict):
    """(F, delta) of the last reloading branch from its turning point (the fit's data, N and m,
    both from the turning point: F[0] = -F*), or None."""
    rows = loop_rows(summary)
    idx = [i for i, r in enumerate(rows) if r.get("branch") == "reloading"]
    if not idx:
        return None
    last = max(_cycle_of(rows[i]) for i in idx)
    br = [i for i in idx if _cycle_of(rows[i]) == last]
    if br[0] == 0:
        return None
    sel = [br[0] - 1] + br
    F = np.array([float(rows[i]["tangential_force_x"]) for i in sel])
    D = np.array([float(rows[i]["displacement_x"]) for i in sel])
    return F, D


def lateral_stiffness_figure(summary: dict, path) -> Path | None:
    """Lateral stiffness K_L against F_x/(mu F0+) at Paper F's points A, B, C (on the last
    branch from -F* to +F*): the fit of Paper F Eq. 3 (markers, and the fitted curve along the
    branch), the slope of the geometry's analytic branch through the same turning point and its
    virgin-curve value (a sphere: Mindlin-Deresiewicz and Paper F Eq. 6; a burl: the rounded
    punch of Ciavarella-Jaeger; none for other geometries, :func:`kl_reference`).  None without
    ``summary["lateral_stiffness"]``.

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
    table = _stiffness_table(summary)
    if not table:
        return None
    xr = np.array([float(t["force_ratio"]) for t in table])
    kfit = np.array([float(t["stiffness"]) for t in table])
    ref_name, _ = kl_reference(summary)
    refs = np.array([kl_reference_values(t) if ref_name else (np.nan, np.nan) for t in table], float).reshape(-1, 2)
    kmd, kvir = refs[:, 0], refs[:, 1]
    sphere = ref_name == "Mindlin-Deresiewicz"
    mu = _friction_coefficient(summary)
    f0p = _num(summary.get("repulsive_force"))
    if f0p is None:
        rows = loop_rows(summary)
        f0p = _num(rows[0].get("repulsive_force")) if rows else None
    curves = {}
    branch = _last_reloading_branch(summary)
    fit = summary.get("lateral_stiffness_fit") or {}
    if branch is not None and mu is not None and f0p and all(_num(fit.get(k)) is not None for k in ("c1", "c2", "n")):
        c1, c2, n = float(fit["c1"]), float(fit["c2"]), float(fit["n"])
        Fb, Db = branch
        Ft = float(Fb[0])
        # K of the fit at the branch's own displacement for each force (as the table's points)
        f = np.linspace(Fb.min(), Fb.max(), 200)
        order = np.argsort(Fb)
        d = np.interp(f, Fb[order], Db[order]) - Db[0]
        base = np.clip(1.0 - c2 * d, 1e-12, None)
        curves["fit"] = (f / (mu * f0p), c1 * c2 * n * base ** (n - 1.0))
        # exact branch slope and virgin-curve slope: the sphere's laws from their K0 (taken from
        # the table), another geometry's from its reference
        fs = -Ft
        mp = mu * f0p
        grid = np.linspace(-fs, fs, 200) / mp
        if sphere:
            for key, vals, law in (("mindlin", kmd, lambda r: np.clip(1.0 - (fs / mp + r) / 2.0, 0, None) ** (1 / 3)),
                                   ("virgin", kvir, lambda r: np.clip(1.0 - np.abs(r), 0, None) ** (1 / 3))):
                ok = np.isfinite(vals) & (law(xr) > 1e-6)
                if ok.any():
                    k0 = float(np.median(vals[ok] / law(xr[ok])))
                    curves[key] = (grid, k0 * law(grid))
        elif ref_name:
            from ...analytic.tangential_axisymmetric import lateral_reference
            from ...errors import InputError

            try:
                model, _ = lateral_reference(summary.get("inputs") or {}, f0p, mu)
                if model is not None:
                    curves["mindlin"] = (grid, model.reloading_stiffness(grid * mp, fs))
                    curves["virgin"] = (grid, model.virgin_stiffness(grid * mp))
            except (InputError, TypeError, ValueError, KeyError):  # F* beyond mu F0+, an unreadable echo
                curves.pop("mindlin", None)
    allk = np.concatenate([kfit, kmd, kvir] + [c[1] for c in curves.values()])
    kf, kl = _stiffness_unit(allk)
    fig = new_figure(6.2, 4.6)
    ax = fig.add_subplot()
    handles, labels = [], []
    pts = ax.plot(xr, kfit / kf, "o", ms=9, color="#1f77b4", mec="k", zorder=5)[0]
    if "fit" in curves:
        line = ax.plot(curves["fit"][0], curves["fit"][1] / kf, color="#1f77b4", lw=1.0, alpha=0.7)[0]
        handles.append((line, pts))
    else:
        handles.append(pts)
    labels.append("fit of the simulated branch (Paper F Eq. 3)")
    if np.isfinite(kmd).any():
        if "mindlin" in curves:
            ax.plot(curves["mindlin"][0], curves["mindlin"][1] / kf, color="#d62728", lw=1.4,
                    label=f"{ref_name} branch slope")
            ax.plot(xr, kmd / kf, "D", ms=5, color="#d62728", zorder=4)
        else:
            ax.plot(xr, kmd / kf, "-D", ms=5, color="#d62728", lw=1.4, label=f"{ref_name} branch slope")
    virgin_label = "virgin curve (Paper F Eq. 6)" if sphere else f"virgin curve, {ref_name}"
    if np.isfinite(kvir).any():
        if "virgin" in curves:
            ax.plot(curves["virgin"][0], curves["virgin"][1] / kf, color="#2a9d8f", lw=1.2, ls="--",
                    label=virgin_label)
            ax.plot(xr, kvir / kf, "s", ms=5, mfc="w", mec="#2a9d8f", mew=1.3, zorder=4)
        else:
            ax.plot(xr, kvir / kf, "--s", ms=5, color="#2a9d8f", mfc="w", lw=1.2, label=virgin_label)
    top = np.nanmax(allk / kf)
    for t, x, k in zip(table, xr, kfit):
        ax.annotate(str(t.get("point", "")), (x, k / kf), xytext=(0, 11), textcoords="offset points",
                    ha="center", fontsize=11, fontweight="bold")
    ax.set_ylim(0, top * 1.18)
    ax.set_xlabel(r"$F_x\,/\,(\mu F_0^+)$ on the last branch from $-F^*$ to $+F^*$")
    ax.set_ylabel(f"lateral stiffness $K_L$ ({kl})")
    ax.grid(alpha=0.3)
    h2, l2 = ax.get_legend_handles_labels()
    ax.legend(handles + h2, labels + l2, fontsize=8, loc="lower left", framealpha=0.9)
    rh = _num(summary.get("rh"))
    ax.set_title("lateral stiffness at Paper F's points A, B, C" + (f" (RH {100 * rh:.3g} %)" if rh is not None else ""),
                 fontsize=10)
    return save_png(fig, path)


def _cycle_maps(ds):
    if ds is None or "dissipation" not in ds or "cycle" not in ds["dissipation"].dims:
        return None
    if ds.sizes.get("cycle", 0) == 0:
        return None
    return ds


def dissipation_figure(ds, path, cycle_index: int = -1, *, work: float | None = None,
                       rh: float | None = None) -> Path | None:
    """Frictional dissipation (J/m^2) and accumulated slip (nm) of one cycle, zoomed to the
    contact (nodes that never carried compressive contact are blank).  None when the fields
    have no per-cycle maps.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of a hysteresis run, with the per-cycle maps ``dissipation`` (J/m^2) and
        ``accumulated_slip`` (m).
    path : path-like
        The PNG file to write (atomically).
    cycle_index : int
        Position along the dataset's ``cycle`` dimension (default: the last cycle, the one closest
        to the stationary loop).
    work : float, optional
        The cycle's traction work (J), quoted in the title.
    rh : float, optional
        The RH (fraction) of the maps, quoted in the title (a humid run keeps the per-cycle maps
        of its last RH).

    Returns
    -------
    Path or None
        The written PNG file, or None when nothing was drawn.
    """
    if _cycle_maps(ds) is None:
        return None
    w = np.asarray(ds["dissipation"].values[cycle_index], dtype=float)
    s = np.asarray(ds["accumulated_slip"].values[cycle_index], dtype=float) if "accumulated_slip" in ds else None
    cyc = int(ds["cycle"].values[cycle_index]) if "cycle" in ds.coords else cycle_index
    x = np.asarray(ds["x"].values)
    y = np.asarray(ds["y"].values)
    contact = np.zeros(w.shape, dtype=bool)
    if "pressure" in ds and ds.sizes.get("step", 0):
        contact = np.any(np.asarray(ds["pressure"].values) > 0, axis=0)
    contact |= w > 0
    lf0, _ = display_unit(np.abs(x) * 2, "length")
    xl, yl = _zoom_window(ds, contact, lf0)
    lf, ll = display_unit([max(abs(v) for v in (*xl, *yl)) * lf0 * 1.0001], "length")
    xl, yl = tuple(v * lf0 / lf for v in xl), tuple(v * lf0 / lf for v in yl)
    wmax = float(np.max(np.where(contact, w, 0.0))) if contact.any() else 0.0
    wf, wl = next(((f, u) for f, u in ((1.0, "J/m$^2$"), (1e-3, "mJ/m$^2$"), (1e-6, "\u00b5J/m$^2$"))
                   if wmax >= f), (1e-9, "nJ/m$^2$"))
    if wmax <= 0:
        wf, wl = 1.0, "J/m$^2$"
    panels = [("dissipation", np.where(contact, np.clip(w, 0, None), np.nan), wf, wl, "inferno_r",
               "frictional dissipation $-\\sum\\, q\\cdot\\Delta s$")]
    if s is not None:
        smax = float(np.nanmax(np.where(contact, s, np.nan))) if contact.any() else 0.0
        sf, sl = (1e-9, "nm") if smax < 1e-5 else (1e-6, "\u00b5m")
        panels.append(("slip", np.where(contact, s, np.nan), sf, sl, "viridis",
                       "accumulated slip $\\sum |\\Delta s|$"))
    fig = new_figure(5.0 * len(panels), 4.6)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    for ax, (_, data, f, unit, cmap, title) in zip(axes, panels):
        im = ax.imshow(data.T / f, origin="lower", extent=map_extent(ds, lf), cmap=cmap, interpolation="nearest")
        if contact.any() and contact.sum() < contact.size:
            ax.contour(x / lf, y / lf, contact.T.astype(float), levels=[0.5], colors="0.3", linewidths=0.6)
        ax.set_xlim(*xl)
        ax.set_ylim(*yl)
        ax.set_aspect("equal")
        ax.set_xlabel(f"x ({ll})")
        ax.set_ylabel(f"y ({ll})")
        ax.set_title(title, fontsize=10)
        fig.colorbar(im, ax=ax, shrink=0.85, label=f"({unit})")
    head = f"cycle {cyc}" + (f" at RH {100 * rh:.3g} %" if rh is not None else "")
    if work is not None:
        head += f": dissipated energy {format_value(work, 'energy', 3)} (traction work)"
    fig.suptitle(head, fontsize=10)
    return save_png(fig, path)


def loop_map_steps(ds, summary: dict, offset: int = 0) -> list[tuple[int, str]]:
    """The dataset steps of a hysteresis run to show as stick/slip maps, with Paper E's names:
    at most six, A, D, D' and the last turning points (for one cycle: A, D, D', H, H', L).
    Empty when the dataset steps cannot be named (no ``summary_step``, no rows).

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    summary : dict
        The run summary (summary.json), its ``steps`` rows in particular.
    offset : int
        Index in the dataset's ``summary_step`` of ``summary``'s first row: a one-RH summary of
        a humid run (:func:`tribobem.output.humid.rh_summary`) holds only that RH's rows.

    Returns
    -------
    list of (int, str)
        (dataset step position, Paper E name) pairs, in path order.
    """
    steps = _tangential_step_indices(ds) if ds is not None else []
    rows = (summary or {}).get("steps") or []
    if not steps or not rows or "summary_step" not in ds.coords:
        return []
    letters = turning_point_letters(rows)
    named = []
    for i in steps:
        k = int(ds["summary_step"].values[i])
        if k >= 0 and k - offset in letters:
            named.append((i, letters[k - offset]))
    if len(named) <= _MAX_LOOP_MAPS:
        return named
    head = [p for p in named if p[1] in ("A", "D", "D'")][:3]
    rest = [p for p in named if p not in head]
    return head + rest[-(_MAX_LOOP_MAPS - len(head)):]


def loop_stickslip_figure(ds, picks, path, *, mu=None, title=None) -> Path:
    """Stick/slip maps at Paper E's points (``picks``: (dataset step, name)), one panel each
    (up to three per row), on a common zoom and a common traction scale.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    picks : sequence of (int, str)
        (dataset step position, name) of each panel, e.g. from :func:`loop_map_steps`.
    path : path-like
        The PNG file to write (atomically).
    mu : float, optional
        Friction coefficient, for the panels' F_x/(mu F0+).
    title : str, optional
        A title over the panels (a humid run: the RH of the maps).

    Returns
    -------
    Path
        The written PNG file.
    """
    xl, yl, lf, ll, qmax = _common_map_window(ds, picks)
    ncol = min(3, len(picks))
    nrow = -(-len(picks) // ncol)
    fig = new_figure(3.9 * ncol, 3.9 * nrow + 0.5)
    axes = fig.subplots(nrow, ncol, squeeze=False)
    handles = []
    for ax, (i, name) in zip(axes.flat, picks):
        handles = _stickslip_axes(ax, ds, i, mu=mu, qmax=qmax or None, window=(xl, yl, lf, ll), letter=name)
    for ax in list(axes.flat)[len(picks):]:
        ax.set_visible(False)
    for r in range(nrow):
        for c in range(ncol):
            if c > 0:
                axes[r, c].set_ylabel("")
            if r < nrow - 1 and (r + 1) * ncol + c < len(picks):
                axes[r, c].set_xlabel("")
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=9, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    return save_png(fig, path)



def hysteresis_figures(ds, summary: dict, outdir) -> dict:
    """The hysteresis figures that apply: ``hysteresis_loop``, ``lateral_stiffness``,
    ``dissipation_cycle<k>`` (last cycle) and ``stickslip_loop`` (maps at Paper E's points;
    that one is added by :func:`hysteresis_run_figures`, which calls this function).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; only the figures that apply (a figure that
        fails to draw is left out: a figure never fails a run).
    """
    outdir = Path(outdir)
    out = {}
    safe = (KeyError, TypeError, ValueError, IndexError)
    for name, func in (("hysteresis_loop", hysteresis_loop_figure), ("lateral_stiffness", lateral_stiffness_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except safe:  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
    if _cycle_maps(ds) is not None:
        cyc = int(ds["cycle"].values[-1]) if "cycle" in ds.coords else ds.sizes["cycle"] - 1
        works = (summary or {}).get("dissipation_work") or []
        work = _num(works[-1]) if works else None
        try:
            fig = dissipation_figure(ds, outdir / f"dissipation_cycle{cyc}.png", -1, work=work,
                                     rh=_num((summary or {}).get("rh")))
        except safe:
            fig = None
        if fig is not None:
            out[f"dissipation_cycle{cyc}"] = fig
    return out
