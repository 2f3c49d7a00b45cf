"""Stick/slip figures of the tangential kinds (partial_slip, hysteresis): the stick/slip maps
with traction arrows (humid runs: the meniscus edge outlined), the stick ratio and displacement
against F_x/(mu F0+), and the stick ratio along a normal-load path.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...units import ZERO_FRACTION, display_unit, format_value
from ..plotting import map_extent, new_figure, save_png
from ..plotting import finite as _num
from ..plotting import friction_coefficient as _friction_coefficient
from ..run_kind import run_view



_STICKSLIP_COLORS = ("#eef0f2", "#ffe3a3", "#f08a7e", "#5b9bd5")  # no contact, p < 0, slip, stick
_BRANCH_COLORS = {"loading": "#1f77b4", "unloading": "#d62728", "reloading": "#2ca02c"}
_OTHER_COLORS = ("#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f")
_ARROWS_PER_DIAMETER = 22


def _tangential_step_indices(ds) -> list[int]:
    """Steps of the dataset that hold a tangential solution."""
    if ds is None or "shear_x" not in ds or "tangential_force_x" not in ds.coords:
        return []
    fx = np.asarray(ds["tangential_force_x"].values, dtype=float)
    return [int(i) for i in np.nonzero(np.isfinite(fx))[0]]


def _step_number(ds, step: int) -> int | None:
    """The summary.json index of a dataset step; None for a state that is not a summary.json
    step (e.g. the refined gross-slip onset), which figures name by its label instead."""
    if "summary_step" in ds.coords:
        k = int(ds["summary_step"].values[step])
        return k if k >= 0 else None
    return int(step)


def _step_name(ds, step: int) -> str:
    """How a figure names a dataset step: ``step k`` (k its summary.json index) or its label
    (``onset``: the refined gross-slip onset, not a summary.json step)."""
    k = _step_number(ds, step)
    return f"step {k}" if k is not None else str(ds["label"].values[step])


def stickslip_steps(ds) -> list[int]:
    """Dataset steps the stick/slip maps show: the first tangential step (usually F_x = 0),
    the last one that still has stick nodes, and the one half-way between them (in step order).
    Empty when the dataset has no tangential fields.

    Three maps, not one per step: they show how the stick zone shrinks under the ramp without
    drowning the report in maps.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).

    Returns
    -------
    list of int
        Dataset step positions (at most three, distinct, increasing).
    """
    steps = _tangential_step_indices(ds)
    if not steps:
        return []
    stick = np.asarray(ds["stick"].values)
    with_stick = [i for i in steps if stick[i].any()]
    last = with_stick[-1] if with_stick else steps[-1]
    between = [i for i in steps if steps[0] <= i <= last]
    mid = between[len(between) // 2]
    out = []
    for i in (steps[0], mid, last):
        if i not in out:
            out.append(i)
    return out


def _repulsive_force(ds, step: int) -> float:
    p = np.asarray(ds["pressure"].values[step])
    return float(np.sum(p[p > 0])) * float(ds.attrs.get("dx", 1.0)) * float(ds.attrs.get("dy", 1.0))


def _zoom_window(ds, active, lf):
    """Square window (display units) around the active nodes with a margin, inside the domain."""
    x = np.asarray(ds["x"].values) / lf
    y = np.asarray(ds["y"].values) / lf
    dx = abs(x[1] - x[0]) if len(x) > 1 else 1.0
    ext = map_extent(ds, lf)
    if not active.any():
        return ext[:2], ext[2:]
    ix = np.nonzero(active.any(axis=1))[0]
    iy = np.nonzero(active.any(axis=0))[0]
    x0, x1, y0, y1 = x[ix[0]], x[ix[-1]], y[iy[0]], y[iy[-1]]
    half = 0.5 * max(x1 - x0, y1 - y0) * 1.18 + 2.5 * dx
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    xl = (max(cx - half, ext[0]), min(cx + half, ext[1]))
    yl = (max(cy - half, ext[2]), min(cy + half, ext[3]))
    return xl, yl


def stickslip_figure(ds, step: int, path, *, mu: float | None = None, qmax: float | None = None) -> Path:
    """Stick/slip map of one step: compressive contact coloured by stick / slip, the tensile
    zone (cohesive zone and contact with p < 0, where no shear acts) in pale amber, no contact
    in grey, and arrows of the traction q on body 1 (about 22 per contact diameter).

    Parameters
    ----------
    ds : xarray.Dataset
        Fields with the tangential variables.
    step : int
        Dataset step.
    path : path-like
    mu : float, optional
        Friction coefficient, for the title's F_x/(mu F0+).
    qmax : float, optional
        Traction (Pa) of the longest arrow; the step's own maximum when omitted (give a common
        value to compare the maps of several steps).

    Returns
    -------
    Path
        The written PNG file.
    """
    fig = new_figure(5.6, 5.6)
    ax = fig.add_subplot()
    handles = _stickslip_axes(ax, ds, step, mu=mu, qmax=qmax)
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8, frameon=False)
    return save_png(fig, path)


_MENISCUS_EDGE = "#00a087"  # the meniscus outline: a teal apart from the stick/slip/tensile colours


def meniscus_mask(ds, step: int):
    """The wetted region of a humid state: active meniscus (outside contact) or contact.

    Its edge is the meniscus's outer edge; the contact is included so that the outline does not
    also trace the contact edge (the meniscus field excludes the contact).

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc); humid runs carry the step field ``meniscus``.
    step : int
        Dataset step.

    Returns
    -------
    ndarray of bool or None
        Grid-shaped mask; None when the dataset has no ``meniscus`` field (a dry run).
    """
    if ds is None or "meniscus" not in ds:
        return None
    men = np.asarray(ds["meniscus"].values[step]).astype(bool)
    if not men.any():
        return men
    return men | np.asarray(ds["contact"].values[step]).astype(bool)


def _stickslip_masks(ds, step: int):
    p = np.asarray(ds["pressure"].values[step])
    comp = p > 0
    stick = np.asarray(ds["stick"].values[step]).astype(bool) & comp
    slip = comp & ~stick
    tensile = np.asarray(ds["adhesive"].values[step]).astype(bool) | (np.asarray(ds["contact"].values[step]).astype(bool) & ~comp)
    tensile &= ~comp
    return comp, stick, slip, tensile


def _stickslip_axes(ax, ds, step: int, *, mu=None, qmax=None, window=None, letter=None) -> list:
    """Draw the stick/slip map of ``step`` into ``ax``; returns the legend handles.

    ``window``: (xl, yl, lf, ll), a common zoom (display units) for several panels; ``letter``:
    a point name (Paper E: A, D, D' ...) that leads a compact two-line title."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    comp, stick, slip, tensile = _stickslip_masks(ds, step)
    wet = meniscus_mask(ds, step)
    code = np.where(stick, 3, np.where(slip, 2, np.where(tensile, 1, 0)))
    qx = np.nan_to_num(np.asarray(ds["shear_x"].values[step], dtype=float))
    qy = np.nan_to_num(np.asarray(ds["shear_y"].values[step], dtype=float))
    qabs = np.hypot(qx, qy)

    x = np.asarray(ds["x"].values)
    y = np.asarray(ds["y"].values)
    if window is None:
        active = comp | tensile
        if wet is not None:  # the zoom keeps the meniscus outline in view
            active = active | wet
        lf0, _ = display_unit(np.abs(x) * 2, "length")
        xl, yl = _zoom_window(ds, active, lf0)
        lf, ll = display_unit([max(abs(v) for v in (*xl, *yl)) * lf0 * 1.0001], "length")
        xl, yl = tuple(v * lf0 / lf for v in xl), tuple(v * lf0 / lf for v in yl)
    else:
        xl, yl, lf, ll = window

    ax.imshow(code.T, origin="lower", extent=map_extent(ds, lf), cmap=ListedColormap(list(_STICKSLIP_COLORS)),
              norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4), interpolation="nearest")
    if comp.any() and 0 < comp.sum() < comp.size:
        ax.contour(x / lf, y / lf, comp.T.astype(float), levels=[0.5], colors="0.25", linewidths=0.6)
    if wet is not None and 0 < wet.sum() < wet.size:
        ax.contour(x / lf, y / lf, wet.T.astype(float), levels=[0.5], colors=_MENISCUS_EDGE, linewidths=1.6,
                   zorder=2.5)

    # traction arrows, ~22 per contact diameter, on a lattice centred on the contact
    qkey = None
    qtop = float(qmax) if qmax is not None and qmax > 0 else float(qabs[comp].max()) if comp.any() else 0.0
    if comp.any() and qtop > 0 and np.any(qabs[comp] > 1e-12 * qtop):
        ix = np.nonzero(comp.any(axis=1))[0]
        iy = np.nonzero(comp.any(axis=0))[0]
        diam = max(ix[-1] - ix[0], iy[-1] - iy[0]) + 1
        per = _ARROWS_PER_DIAMETER if letter is None else 15
        stride = max(1, int(round(diam / per)))
        cx, cy = (ix[0] + ix[-1]) // 2, (iy[0] + iy[-1]) // 2
        sel = np.zeros_like(comp)
        sel[cx % stride::stride, cy % stride::stride] = True
        sel &= comp
        dxl = abs(float(x[1] - x[0])) / lf if len(x) > 1 else 1.0
        scale = qtop / (0.9 * stride * dxl)  # Pa per display length: the longest arrow spans 0.9 strides
        X, Y = np.meshgrid(x / lf, y / lf, indexing="ij")
        qv = ax.quiver(X[sel], Y[sel], qx[sel], qy[sel], angles="xy", scale_units="xy", scale=scale,
                       color="#1b1b1b", width=0.0042 if letter is None else 0.0055, headwidth=3.6, headlength=4.0,
                       headaxislength=3.6, pivot="middle", zorder=3)
        qf, ql = display_unit([qtop], "pressure")
        qkey = ax.quiverkey(qv, 0.04 if letter is None else 0.1, 0.955, qtop, f"|q| = {qtop / qf:.3g} {ql}",
                            labelpos="E", coordinates="axes", fontproperties={"size": 8 if letter is None else 7})
        qkey.set_zorder(4)

    cell = float(ds.attrs.get("dx", 1.0)) * float(ds.attrs.get("dy", 1.0))
    n_comp = int(comp.sum())
    total = max(n_comp, 1) * cell
    af, al = display_unit([total], "area")
    if total / af >= 100 and al.startswith("n"):  # 4.39e+04 nm^2 reads better as 0.0439 um^2
        af, al = display_unit([1e-12], "area")

    def area(mask):
        share = f" ({100.0 * mask.sum() / n_comp:.0f} %)" if n_comp else ""
        return f"{mask.sum() * cell / af:.3g} {al}{share}"

    if letter is None:
        handles = [Patch(color=_STICKSLIP_COLORS[3], label=f"stick: {area(stick)}"),
                   Patch(color=_STICKSLIP_COLORS[2], label=f"slip: {area(slip)}")]
    else:
        handles = [Patch(color=_STICKSLIP_COLORS[3], label="stick"), Patch(color=_STICKSLIP_COLORS[2], label="slip")]
    if np.any(np.asarray(ds["adhesive"].values)):
        handles.append(Patch(color=_STICKSLIP_COLORS[1], label="tensile zone, p < 0 (no shear)"))
    handles.append(Patch(facecolor=_STICKSLIP_COLORS[0], edgecolor="0.6", label="no contact"))
    if wet is not None and wet.any():
        from matplotlib.lines import Line2D

        handles.append(Line2D([], [], color=_MENISCUS_EDGE, lw=1.8, label="meniscus edge"))

    ax.set_xlim(*xl)
    ax.set_ylim(*yl)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({ll})")
    ax.set_ylabel(f"y ({ll})")

    fx = _num(ds["tangential_force_x"].values[step])
    fy = _num(ds["tangential_force_y"].values[step]) or 0.0
    fn = float(ds["normal_force"].values[step])
    ratio = n_comp and float(np.count_nonzero(stick)) / n_comp
    f0 = _repulsive_force(ds, step)
    # round-off of a state solved at zero tangential force (1e-22 N) prints as 0, and is no
    # direction either (a y component of noise made the title read |F_t|)
    zero = ZERO_FRACTION * max(mu * f0 if mu else 0.0, abs(fn))
    if fx is not None and abs(fx) <= zero:
        fx = 0.0
    if abs(fy) <= zero:
        fy = 0.0
    if letter is not None:  # compact: "D'  step 7: F_x/(mu F0+) = 0.773" / "F_x = 2.32 N, stick 1.000"
        ax.text(0.97, 0.96, f"$\\mathbf{{{_tex_letter(letter)}}}$", transform=ax.transAxes, ha="right", va="top",
                fontsize=15, fontweight="bold", zorder=6,
                bbox={"boxstyle": "round,pad=0.2", "fc": "w", "ec": "0.6", "alpha": 0.9})
        line1 = _step_name(ds, step)
        if mu is not None and f0 > 0 and fx is not None:
            line1 += rf": $F_x/(\mu F_0^+)$ = {fx / (mu * f0):.3f}"
        line2 = f"$F_x$ = {format_value(fx, 'force', 3)}, " if fx is not None else ""
        line2 += f"stick ratio {ratio:.3f}" if n_comp else "no compressive contact"
        ax.set_title(f"{line1}\n{line2}", fontsize=9)
        return handles
    line1 = f"{_step_name(ds, step)}: $F$ = {format_value(fn, 'force', 3)}"
    if fx is not None:
        line1 += f", $F_x$ = {format_value(fx, 'force', 3)}"
    if mu is not None and f0 > 0 and fx is not None:
        if abs(fy) > 1e-9 * max(abs(fx), 1e-300):
            line2 = rf"$|F_t|/(\mu F_0^+)$ = {np.hypot(fx, fy) / (mu * f0):.3f}"
        else:
            line2 = rf"$F_x/(\mu F_0^+)$ = {fx / (mu * f0):.3f}"
    else:
        line2 = ""
    line2 += ("," if line2 else "") + f" stick ratio {ratio:.3f}" if n_comp else " no compressive contact"
    ax.set_title(f"{line1}\n{line2.strip()}", fontsize=10)
    return handles


def _rows_with(summary: dict, *keys) -> list[dict]:
    return [r for r in (summary or {}).get("steps", []) or [] if isinstance(r, dict)
            and all(_num(r.get(k)) is not None for k in keys)]


def _segments(rows: list[dict]):
    """Contiguous runs of rows with the same (branch, cycle): (branch, [row indices]); each run
    after the first starts at the previous run's last row so that the curve stays connected."""
    out = []
    prev = None
    for i, r in enumerate(rows):
        key = (r.get("branch"), r.get("cycle"))
        if key != prev:
            start = [out[-1][1][-1]] if out else []
            out.append((r.get("branch"), start))
            prev = key
        out[-1][1].append(i)
    return out


def _branch_colors(segments) -> dict:
    colors, k = {}, 0
    for b, _ in segments:
        if b not in colors:
            if b in _BRANCH_COLORS:
                colors[b] = _BRANCH_COLORS[b]
            else:
                colors[b] = _OTHER_COLORS[k % len(_OTHER_COLORS)]
                k += 1
    return colors


def _plot_branches(ax, xv, yv, rows, *, color=None, label=None, ls="-", marker="o"):
    """Draw ``yv`` against ``xv`` as one line per (branch, cycle) run, coloured by branch."""
    segs = _segments(rows)
    branches = {b for b, _ in segs}
    several = len(branches) > 1
    colors = _branch_colors(segs)
    ms = 3.5 if len(rows) <= 60 else 0
    seen = set()
    for b, idx in segs:
        c = colors[b] if several else (color or "#1f77b4")
        if several:
            lab = None if b in seen else (f"{label}, {b}" if label else str(b))
        else:
            lab = None if seen else label
        seen.add(b)
        ax.plot(xv[idx], yv[idx], color=c, lw=1.4, ls=ls, marker=marker if ms else None, ms=ms, label=lab)
    conv = np.array([bool(r.get("converged", True)) for r in rows])
    if (~conv).any():
        ax.plot(xv[~conv], yv[~conv], "x", color="k", ms=7, label="not converged" if label is None or ls == "-" else None)


def stick_ratio_figure(summary: dict, path) -> Path | None:
    """Stick ratio and tangential displacement delta_x against F_nr = F_x/(mu F0+) (F0+ of
    each step), the gross-slip onset and the presliding displacement marked; one line per
    branch.  Against F_x itself when mu is unknown.  None when the rows lack the data.

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
    rows = _rows_with(summary, "tangential_force_x", "stick_ratio")
    if len(rows) < 2:
        return None
    if run_view(summary).hysteresis:  # the start (F_x = 0) opens the initial loading: no line of its own
        rows = [dict(r, branch="loading") if r.get("branch") == "start" else r for r in rows]
    fx = np.array([float(r["tangential_force_x"]) for r in rows])
    if not np.any(fx != 0):
        return None
    mu = _friction_coefficient(summary)
    f0 = np.array([_num(r.get("repulsive_force")) or np.nan for r in rows])
    normalised = mu is not None and np.all(np.isfinite(f0)) and np.all(f0 > 0)
    if normalised:
        xv = fx / (mu * f0)
        xlabel = r"$F_x\,/\,(\mu F_0^+)$"
        xf = 1.0
    else:
        xf, xl = display_unit(fx, "force")
        xv = fx / xf
        xlabel = f"tangential force $F_x$ ({xl})"
    sr = np.array([float(r["stick_ratio"]) for r in rows])
    has_d = all(_num(r.get("displacement_x")) is not None for r in rows)

    fig = new_figure(5.8, 6.6 if has_d else 4.0)
    axes = fig.subplots(2 if has_d else 1, 1, sharex=True, squeeze=False)[:, 0]
    ax = axes[0]
    _plot_branches(ax, xv, sr, rows, color="#1f77b4")
    ax.set_ylabel(r"stick ratio $A_\mathrm{stick}/A_\mathrm{c}$")
    ax.set_ylim(-0.03, 1.05)
    ax.grid(alpha=0.3)

    onset = None
    if normalised:
        onset = _num(summary.get("static_friction_ratio"))
    else:
        sff = _num(summary.get("static_friction_force"))
        onset = sff / xf if sff is not None else None
    onset_text = None
    if onset is not None:
        onset_text = (f"gross-slip onset {onset:.3f}" if normalised else
                      f"gross-slip onset {format_value(onset * xf, 'force', 3)}")
        for a in axes:
            a.axvline(onset, color="#e76f51", ls="--", lw=1.2, label=onset_text if a is ax else None)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="best")
    ax.set_title(f"stick ratio and tangential displacement ({summary.get('kind', '')})" if has_d
                 else f"stick ratio ({summary.get('kind', '')})", fontsize=10)

    if has_d:
        d = np.array([float(r["displacement_x"]) for r in rows])
        pre = _num(summary.get("presliding_displacement"))
        zero = np.nonzero(fx == 0)[0]
        d0 = d[zero[0]] if zero.size else d[0]
        df, dl = display_unit(np.concatenate([d, [d0 + pre] if pre is not None else []]), "length")
        ax2 = axes[1]
        _plot_branches(ax2, xv, d / df, rows, color="#2a9d8f")
        if pre is not None:
            ax2.axhline((d0 + pre) / df, color="#6a4c93", ls=":", lw=1.2,
                        label=f"presliding displacement {format_value(pre, 'length', 3)}")
            if onset is not None:
                ax2.plot([onset], [(d0 + pre) / df], marker="*", ms=13, color="#e9c46a", mec="k", ls="none",
                         zorder=5)
        ax2.set_ylabel(f"tangential displacement $\\delta_x$ ({dl})")
        ax2.grid(alpha=0.3)
        if ax2.get_legend_handles_labels()[0]:
            ax2.legend(fontsize=8, loc="best")
    axes[-1].set_xlabel(xlabel)
    return save_png(fig, path)


def stick_normal_figure(summary: dict, path) -> Path | None:
    """Stick ratio (and ``stick_radius_ratio`` when the rows have it) against the normal force
    of a normal-load path with friction (no tangential force).  None when the rows are not
    such a path.

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
    rows = _rows_with(summary, "normal_force", "stick_ratio")
    if len(rows) < 2:
        return None
    fn = np.array([float(r["normal_force"]) for r in rows])
    if np.ptp(fn) <= 1e-9 * max(np.max(np.abs(fn)), 1e-300):
        return None
    ft = [abs(_num(r.get(k)) or 0.0) for r in rows for k in ("tangential_force_x", "tangential_force_y")]
    if max(ft, default=0.0) > 1e-9 * np.max(np.abs(fn)):
        return None
    ff, fl = display_unit(fn, "force")
    fig = new_figure(6.0, 4.4)
    ax = fig.add_subplot()
    _plot_branches(ax, fn / ff, np.array([float(r["stick_ratio"]) for r in rows]), rows, color="#1f77b4",
                   label=r"stick ratio $A_\mathrm{stick}/A_\mathrm{c}$")
    if all(_num(r.get("stick_radius_ratio")) is not None for r in rows):
        _plot_branches(ax, fn / ff, np.array([float(r["stick_radius_ratio"]) for r in rows]), rows,
                       color="#e76f51", label="stick radius ratio $c/a$", ls="--", marker="s")
    ax.set_xlabel(f"normal force $F$ ({fl})")
    ax.set_ylabel("ratio")
    ax.set_ylim(-0.03, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"stick zone along the normal-load path ({summary.get('kind', '')})", fontsize=10)
    return save_png(fig, path)


def _tex_letter(letter: str) -> str:
    """A point name for mathtext (which renders ' as a prime)."""
    return letter.replace("_", r"\_")


def _common_map_window(ds, picks):
    """The zoom window (x and y limits in display units, the unit's factor and label) that holds
    the compressive, tensile and meniscus nodes of every picked state, and the largest |q| among
    them (Pa): one window and one traction scale for a multi-panel stick/slip figure."""
    x = np.asarray(ds["x"].values)
    active = np.zeros((ds.sizes["x"], ds.sizes["y"]), dtype=bool)
    for i, _ in picks:
        comp, _s, _sl, tensile = _stickslip_masks(ds, i)
        wet = meniscus_mask(ds, i)
        active |= comp | tensile | (wet if wet is not None else False)
    lf0, _ = display_unit(np.abs(x) * 2, "length")
    xl, yl = _zoom_window(ds, active, lf0)
    lf, ll = display_unit([max(abs(v) for v in (*xl, *yl)) * lf0 * 1.0001], "length")
    xl, yl = tuple(v * lf0 / lf for v in xl), tuple(v * lf0 / lf for v in yl)
    qmax = max(float(np.nanmax(np.hypot(np.nan_to_num(ds["shear_x"].values[i]),
                                        np.nan_to_num(ds["shear_y"].values[i])))) for i, _ in picks)
    return xl, yl, lf, ll, qmax
