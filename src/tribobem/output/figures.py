"""PNG figures of a run (matplotlib, Agg, no pyplot state): topography, pressure map, contact
map, profile along the row through the largest pressure, force-approach curve; for the
tangential kinds (partial_slip, hysteresis) stick/slip maps with traction arrows, stick ratio and displacement against
F_x/(mu F0+), and stick ratio against the normal force of a normal-load path (humid runs: the
meniscus edge outlined on the maps, and the curves per RH in :mod:`.humid`); for hysteresis
the loop F_x - delta_x with Paper E's points (A, D, D', H ...), the lateral stiffness at Paper
F's points A, B, C, the last cycle's dissipation and accumulated-slip maps, and the stick/slip
maps at Paper E's points in one figure.

Every function takes the fields dataset (:mod:`tribobem.output.fields`) and/or the summary
dict, so ``tribobem plot RESULT`` re-makes the figures from the files alone.  Units are
chosen from the data (nm / µm, kPa / MPa / GPa, nN / µN).  Files are written atomically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..units import display_unit, format_value
from .fields import representative_step
from .plotting import COLORS, CONTACT_COLORS, keep_inside, map_axes, map_extent, new_figure, profile_row, save_png
from .plotting import step_title
from .plotting import finite as _num
from .plotting import friction_coefficient as _friction_coefficient
from .plotting import is_hysteresis
from .capillary import capillary_figures, capillary_step, is_capillary
from .humid import humid_friction_figures, is_humid_friction, rh_label, rh_summary

__all__ = ["FIGURE_NAMES", "make_figures", "topography_figure", "pressure_figure", "contact_figure",
           "profile_figure", "force_curve_figure", "stickslip_figure", "stickslip_steps", "stick_ratio_figure",
           "stick_normal_figure", "is_hysteresis", "turning_point_letters", "mindlin_reference",
           "loop_reference", "kl_reference",
           "hysteresis_loop_figure", "lateral_stiffness_figure", "dissipation_figure", "loop_map_steps",
           "loop_stickslip_figure", "hysteresis_figures", "FIGURE_SETS", "load_curve_figures", "friction_figures",
           "hysteresis_run_figures", "capillary_run_figures", "map_figures", "meniscus_mask",
           "humid_stickslip_steps", "humid_stickslip_figure", "humid_friction_run_figures"]

#: File stems of the figures, in report order.  ``stickslip`` stands for the stick/slip maps,
#: one per shown step, named ``stickslip_step<k>`` (k: the step's index in summary.json), or,
#: for a hysteresis run, one multi-panel ``stickslip_loop`` at Paper E's points (A, D, D' ...),
#: for a humid partial-slip run one multi-panel ``stickslip_rh`` (a map per RH);
#: ``dissipation`` for ``dissipation_cycle<k>`` (hysteresis: maps of the last cycle).
FIGURE_NAMES = ("hysteresis_loop", "humid_friction_rh", "humid_friction_curve", "capillary_forces", "pulloff_rh",
                "force_curve", "stick_ratio", "stick_normal",
                "stickslip", "lateral_stiffness", "dissipation", "meniscus", "films", "pressure", "contact", "profile",
                "pressure_pulloff", "contact_pulloff", "topography")

def topography_figure(ds, path) -> Path:
    """Initial gap and the bodies' roughness (when present), as maps.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path
        The written PNG file.
    """
    panels = [("initial_gap", "initial gap h")]
    for name in ("roughness_body1", "roughness_body2"):
        if name in ds and np.any(np.asarray(ds[name].values) != 0):
            panels.append((name, f"roughness of body {name[-1]}"))
    fig = new_figure(4.6 * len(panels), 4.2)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    for ax, (name, title) in zip(axes, panels):
        h = np.asarray(ds[name].values)
        hf, hl = display_unit(h, "length")
        im = ax.imshow(h.T / hf, origin="lower", extent=map_extent(ds, lf), cmap="cividis", interpolation="nearest")
        map_axes(ax, ds, lf, ll)
        ax.set_title(title)
        fig.colorbar(im, ax=ax, shrink=0.85, label=f"height ({hl})")
    return save_png(fig, path)


def pressure_figure(ds, step: int, path) -> Path:
    """Pressure map; diverging colours centred on 0 when tensile stresses exist, with the
    contact and cohesive zones outlined.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    step : int
        Position along the dataset's ``step`` dimension (not the summary.json row).
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path
        The written PNG file.
    """
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.lines import Line2D

    p = np.asarray(ds["pressure"].values[step])
    pf, pl = display_unit(p, "pressure")
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    fig = new_figure()
    ax = fig.add_subplot()
    pmin, pmax = float(p.min()), float(p.max())
    if pmin < 0:
        top = pmax if pmax > 0 else 1e-3 * abs(pmin)
        norm = TwoSlopeNorm(vmin=pmin / pf, vcenter=0.0, vmax=top / pf)
        im = ax.imshow(p.T / pf, origin="lower", extent=map_extent(ds, lf), cmap="RdBu_r", norm=norm,
                       interpolation="nearest")
    else:
        im = ax.imshow(p.T / pf, origin="lower", extent=map_extent(ds, lf), cmap="magma_r", interpolation="nearest")
    fig.colorbar(im, ax=ax, shrink=0.85, label=f"pressure p ({pl}), > 0 compressive")
    x = np.asarray(ds["x"].values) / lf
    y = np.asarray(ds["y"].values) / lf
    handles = []
    edge = "#ffb703" if pmin < 0 else "#1f77b4"
    for name, color, text in (("contact", edge, "contact edge"), ("adhesive", "k", "cohesive zone edge")):
        mask = np.asarray(ds[name].values[step]).astype(float)
        if 0 < mask.sum() < mask.size:
            ax.contour(x, y, mask.T, levels=[0.5], colors=color, linewidths=0.8)
            handles.append(Line2D([], [], color=color, lw=1, label=text))
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.8)
    map_axes(ax, ds, lf, ll, active=p != 0)
    ax.set_title(f"pressure ({step_title(ds, step)})", fontsize=10)
    return save_png(fig, path)


def contact_figure(ds, step: int, path) -> Path:
    """Contact (g = 0), cohesive zone (adhesive stress outside contact) and free nodes.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    step : int
        Position along the dataset's ``step`` dimension (not the summary.json row).
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path
        The written PNG file.
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    contact = np.asarray(ds["contact"].values[step]).astype(bool)
    adhesive = np.asarray(ds["adhesive"].values[step]).astype(bool) & ~contact
    code = np.where(contact, 2, np.where(adhesive, 1, 0))
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    cell = float(ds.attrs.get("dx", 1.0)) * float(ds.attrs.get("dy", 1.0))
    fig = new_figure()
    ax = fig.add_subplot()
    cmap = ListedColormap(list(CONTACT_COLORS))
    ax.imshow(code.T, origin="lower", extent=map_extent(ds, lf), cmap=cmap,
              norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3), interpolation="nearest")
    handles = [Patch(color=CONTACT_COLORS[2], label=f"contact: {format_value(contact.sum() * cell, 'area', 3)}")]
    if np.any(np.asarray(ds["adhesive"].values)):  # adhesive run: show the cohesive zone even when empty
        handles.append(Patch(color=CONTACT_COLORS[1],
                             label=f"cohesive zone: {format_value(adhesive.sum() * cell, 'area', 3)}"))
    handles.append(Patch(facecolor=CONTACT_COLORS[0], edgecolor="0.6", label="free"))
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.85)
    map_axes(ax, ds, lf, ll, active=code > 0)
    ax.set_title(f"contact map ({step_title(ds, step)})", fontsize=10)
    return save_png(fig, path)


def profile_figure(ds, step: int, path) -> Path:
    """Gap and pressure along the row y = const through the largest pressure of the state
    (:func:`~tribobem.output.plotting.profile_row`; the centre line when there is no pressure);
    the title says which y.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc, :mod:`tribobem.output.fields`).
    step : int
        Position along the dataset's ``step`` dimension (not the summary.json row).
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path
        The written PNG file.
    """
    y = np.asarray(ds["y"].values)
    iy, through = profile_row(ds["pressure"].values[step], y)
    x = np.asarray(ds["x"].values)
    g = np.asarray(ds["gap"].values[step])[:, iy]
    h = np.asarray(ds["initial_gap"].values)[:, iy]
    p = np.asarray(ds["pressure"].values[step])[:, iy]
    lf, ll = display_unit(np.abs(x) * 2, "length")
    gf, gl = display_unit(np.concatenate([g, h]), "length")
    pf, pl = display_unit(p, "pressure")
    fig = new_figure(6.4, 4.2)
    ax = fig.add_subplot()
    ax.plot(x / lf, h / gf, color="0.6", lw=1, ls="--", label="initial gap h")
    ax.plot(x / lf, g / gf, color="#1f77b4", lw=1.4, label="gap g")
    ax.set_xlabel(f"x ({ll})")
    ax.set_ylabel(f"gap ({gl})", color="#1f77b4")
    ax2 = ax.twinx()
    ax2.plot(x / lf, p / pf, color="#d62728", lw=1.4, label="pressure p")
    ax2.axhline(0.0, color="#d62728", lw=0.5, alpha=0.5)
    ax2.set_ylabel(f"pressure ({pl})", color="#d62728")
    if not np.any(p):  # no pressure on the line: a readable empty axis, not matplotlib's +-0.04
        ax2.set_ylim(-1.0, 1.0)
    lines = ax.get_lines()[:2] + ax2.get_lines()[:1]
    # below the axes: inside, it hides the curves of a contact that fills the line
    fig.legend(lines, [ln.get_label() for ln in lines], loc="outside lower center", ncols=3, frameon=False)
    where = "centre line" if through == "centre line" else f"row through the {through}"
    ax.set_title(f"{step_title(ds, step)}\nalong y = {y[iy] / lf:.3g} {ll} ({where})", fontsize=10)
    return save_png(fig, path)


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


# ---------------------------------------------------------------------------------------------
# tangential kinds (partial_slip, hysteresis)

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
    if letter is not None:  # compact: "D'  step 7: F_x/(mu F0+) = 0.773" / "F_x = 2.32 N, stick 1.000"
        ax.text(0.97, 0.96, f"$\\mathbf{{{_tex_letter(letter)}}}$", transform=ax.transAxes, ha="right", va="top",
                fontsize=15, fontweight="bold", zorder=6,
                bbox={"boxstyle": "round,pad=0.2", "fc": "w", "ec": "0.6", "alpha": 0.9})
        line1 = _step_name(ds, step)
        if fx is not None and abs(fx) <= 1e-9 * max(mu * f0 if mu else 0.0, abs(fn), 1e-300):
            fx = 0.0  # round-off at the start (F_x = 0)
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
    if is_hysteresis(summary):  # the start (F_x = 0) opens the initial loading: no line of its own
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


# ---------------------------------------------------------------------------------------------
# hysteresis (Papers E and F)

_CYCLE_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
_BRANCH_MARKERS = {"start": "o", "loading": "o", "unloading": "v", "reloading": "^"}
#: Paper E's names of the turning points, in order (A is the start; the step after a point is
#: primed: A', D', H' ...).
_TURNING_LETTERS = "DHLPTX"
_MAX_LOOP_MAPS = 6


def _tex_letter(letter: str) -> str:
    """A point name for mathtext (which renders ' as a prime)."""
    return letter.replace("_", r"\_")


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


def _hysteresis_rows(summary: dict) -> list[dict]:
    rows = _rows_with(summary, "tangential_force_x", "displacement_x")
    return rows if len(rows) >= 3 else []


def _cycle_of(r) -> int:
    c = _num(r.get("cycle"))
    return int(c) if c is not None else 0


def _shear_moduli(summary: dict):
    """(1/G, nu) per body from the scenario echo; 1/G = 0 for a rigid body; None when unknown."""
    inp = (summary or {}).get("inputs") or {}
    out = []
    for name in ("body1", "body2"):
        b = inp.get(name)
        if not isinstance(b, dict):
            return None
        if b.get("rigid"):
            out.append((0.0, 0.5))
            continue
        E, nu = _num(b.get("E")), _num(b.get("nu"))
        if E is None or nu is None or E <= 0:
            return None
        out.append((2.0 * (1.0 + nu) / E, nu))
    return out


def _smooth(summary: dict) -> bool:
    inp = (summary or {}).get("inputs") or {}
    for name in ("body1", "body2"):
        r = (inp.get(name) or {}).get("roughness") or {}
        if isinstance(r, dict) and r.get("kind", "none") not in ("none", None):
            return False
    return True


def mindlin_reference(summary: dict) -> dict | None:
    """The Mindlin-Deresiewicz loop of the run, when it applies: a sphere (paraboloid) on a
    flat or a sphere (:func:`tribobem.analytic.tangential_axisymmetric.reference_geometry`), smooth bodies with
    no normal-tangential coupling (identical materials, or beta = 0), a peak force below
    mu F0+, F0+ and the compressive contact area of the start row known.  Other shapes (a
    burl: :func:`loop_reference`) get None.

    Returns
    -------
    dict or None
        ``delta0`` (m), ``mu_p`` (mu F0+, N), ``peak`` (Q*, N), ``offset`` (delta_x of the start,
        m), ``radius`` (a, m), ``compliance`` (k = sum (2 - nu)/G, 1/Pa) and ``energy`` (the loop
        area per cycle, J).

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.
    """
    from ..analytic.tangential_axisymmetric import reference_geometry

    rows = _hysteresis_rows(summary)
    mu = _friction_coefficient(summary)
    bodies = _shear_moduli(summary)
    if not rows or mu is None or bodies is None or not _smooth(summary):
        return None
    if reference_geometry((summary or {}).get("inputs") or {})[0] != "sphere":
        return None  # a sphere's loop applied to a punch is wrong by up to a factor of several in K_L
    (c1, n1), (c2, n2) = bodies
    beta = (1.0 - 2.0 * n1) * c1 - (1.0 - 2.0 * n2) * c2
    k = (2.0 - n1) * c1 + (2.0 - n2) * c2
    if k <= 0 or abs(beta) > 1e-6 * k:
        return None
    start = rows[0]
    P = _num(start.get("repulsive_force"))
    area = _num(start.get("contact_area_compressive")) or _num(start.get("contact_area"))
    if P is None or area is None or P <= 0 or area <= 0:
        return None
    a = float(np.sqrt(area / np.pi))
    mu_p = mu * P
    peak = _num(summary.get("peak_force"))
    if peak is None:
        peak = float(max(abs(float(r["tangential_force_x"])) for r in rows))
    if not (0 < peak < mu_p * (1 - 1e-9)):
        return None
    r = peak / mu_p
    energy = 9.0 * mu**2 * P**2 * k / (10.0 * a) * (1.0 - (1.0 - r) ** (5.0 / 3.0)
                                                     - 5.0 * r / 6.0 * (1.0 + (1.0 - r) ** (2.0 / 3.0)))
    return {"delta0": 3.0 * mu_p * k / (16.0 * a), "mu_p": mu_p, "peak": peak,
            "offset": float(start["displacement_x"]), "radius": a, "compliance": k, "energy": energy}


def _mindlin_branches(ref: dict, n: int = 120):
    """(F, delta) of the Mindlin-Deresiewicz initial loading, unloading and reloading (m, N)."""
    d0, mp, qs, off = ref["delta0"], ref["mu_p"], ref["peak"], ref["offset"]
    base = (1.0 - qs / mp) ** (2.0 / 3.0)
    q = np.linspace(0.0, qs, n)
    load = d0 * (1.0 - (1.0 - q / mp) ** (2.0 / 3.0))
    qu = np.linspace(qs, -qs, 2 * n)
    unload = d0 * (2.0 * (1.0 - (qs - qu) / (2.0 * mp)) ** (2.0 / 3.0) - base - 1.0)
    reload = -d0 * (2.0 * (1.0 - (qs + qu[::-1]) / (2.0 * mp)) ** (2.0 / 3.0) - base - 1.0)
    return [(q, load + off), (qu, unload + off), (qu[::-1], reload + off)]


def loop_reference(summary: dict) -> dict | None:
    """The analytic loop matching the run's geometry, when there is one: Mindlin-Deresiewicz for
    a sphere (:func:`mindlin_reference`), the rounded punch of Ciavarella-Jaeger for a smooth
    burl of uncoupled bodies (:func:`tribobem.analytic.tangential_axisymmetric.lateral_reference`); None otherwise
    (:func:`kl_reference` says why).

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.

    Returns
    -------
    dict or None
        ``name`` (for legends and tables), ``mu_p`` (mu F0+, N), ``peak`` (Q*, N), ``offset``
        (delta_x of the start, m), ``energy`` (loop area per cycle, J) and, but for the sphere,
        ``model`` (:class:`~tribobem.analytic.tangential_axisymmetric.AxisymmetricPartialSlip`);
        the sphere's also has the keys of :func:`mindlin_reference`.
    """
    from ..analytic.tangential_axisymmetric import lateral_reference, reference_geometry
    from ..errors import InputError

    inp = (summary or {}).get("inputs") or {}
    if reference_geometry(inp)[0] == "sphere":
        ref = mindlin_reference(summary)
        return None if ref is None else dict(ref, name="Mindlin-Deresiewicz")
    rows = _hysteresis_rows(summary)
    mu = _friction_coefficient(summary)
    if not rows or mu is None:
        return None
    P = _num(rows[0].get("repulsive_force"))
    try:
        model, _ = lateral_reference(inp, P, mu)
    except (InputError, TypeError, ValueError, KeyError):  # an echo this reader cannot use
        return None
    if model is None:
        return None
    peak = _num(summary.get("peak_force"))
    if peak is None:
        peak = float(max(abs(float(r["tangential_force_x"])) for r in rows))
    if not (0 < peak < model.mu_p * (1 - 1e-9)):
        return None
    return {"name": model.name, "model": model, "mu_p": model.mu_p, "peak": peak,
            "offset": float(rows[0]["displacement_x"]), "energy": model.loop_energy(peak)}


def _reference_branches(ref: dict, n: int = 120):
    """(F, delta) of the reference's initial loading, unloading and reloading (N, m)."""
    model = ref.get("model")
    if model is None:
        return _mindlin_branches(ref, n)
    qs, off = ref["peak"], ref["offset"]
    q = np.linspace(0.0, qs, n)
    qu = np.linspace(qs, -qs, 2 * n)
    return [(q, model.virgin_displacement(q) + off), (qu, model.unloading_displacement(qu, qs) + off),
            (qu[::-1], model.reloading_displacement(qu[::-1], qs) + off)]


def kl_reference(summary: dict) -> tuple[str | None, str]:
    """Name of the analytic reference beside the fitted K_L of ``summary["lateral_stiffness"]``
    (its rows' ``reference_stiffness`` and ``reference_virgin_stiffness``), or None and why.

    Summaries written before the reference matched the geometry carry the sphere's law in
    ``mindlin_stiffness``: it is shown for a sphere only.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.

    Returns
    -------
    (str or None, str)
        The reference's name ("Mindlin-Deresiewicz", "rounded punch (Ciavarella-Jaeger)") and
        an empty note, or None and a one-line note.
    """
    from ..analytic.tangential_axisymmetric import reference_geometry

    s = summary or {}
    if "lateral_stiffness_reference" in s:
        name = s.get("lateral_stiffness_reference")
        return (name, "") if name else (None, str(s.get("lateral_stiffness_reference_note")
                                                   or "no analytic reference for this geometry"))
    kind, _, note = reference_geometry(s.get("inputs") or {})
    if kind == "sphere":
        return "Mindlin-Deresiewicz", ""
    return None, note or ("no analytic reference in this summary: its K_L reference is a sphere's, not this "
                          "geometry's (rerun the scenario for the rounded punch's)")


def _kl_reference_values(row: dict) -> tuple[float, float]:
    """(branch slope, virgin slope) of the reference at one of the points A, B, C (N/m; nan when absent)."""
    def val(*keys):
        for key in keys:
            v = _num(row.get(key))
            if v is not None:
                return v
        return np.nan
    return val("reference_stiffness", "mindlin_stiffness"), val("reference_virgin_stiffness", "virgin_stiffness")


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
    rows = _hysteresis_rows(summary)
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
        for k, (q, d) in enumerate(_reference_branches(ref)):
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
    rows = _hysteresis_rows(summary)
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
    refs = np.array([_kl_reference_values(t) if ref_name else (np.nan, np.nan) for t in table], float).reshape(-1, 2)
    kmd, kvir = refs[:, 0], refs[:, 1]
    sphere = ref_name == "Mindlin-Deresiewicz"
    mu = _friction_coefficient(summary)
    f0p = _num(summary.get("repulsive_force"))
    if f0p is None:
        rows = _hysteresis_rows(summary)
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
            from ..analytic.tangential_axisymmetric import lateral_reference
            from ..errors import InputError

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


#: Most stick/slip maps of the per-RH figure of a humid run: more panels get too small to read.
_MAX_RH_MAPS = 4


def humid_stickslip_steps(ds, at_most: int = _MAX_RH_MAPS) -> list[tuple[int, float]]:
    """Dataset steps of the per-RH stick/slip maps: for each RH (at most ``at_most``: the first,
    the last and evenly in between) its kept tangential state half-way (in kept states) from the
    first to the last one that still has stick nodes: a developed slip annulus around a stick
    zone that is still large enough to see (the last one is often all but gross slip).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc) with the ``rh`` step coordinate.
    at_most : int
        Most maps.

    Returns
    -------
    list of (int, float)
        (dataset step position, RH as a fraction), in RH order of the run.
    """
    if ds is None or "rh" not in ds.coords or "shear_x" not in ds or "tangential_force_x" not in ds.coords:
        return []
    rh = np.asarray(ds["rh"].values, dtype=float)
    fx = np.asarray(ds["tangential_force_x"].values, dtype=float)
    stick = np.asarray(ds["stick"].values) if "stick" in ds else None
    order = []
    for v in rh:
        if np.isfinite(v) and v not in order:
            order.append(float(v))
    picks = []
    for v in order:
        steps = [i for i in range(len(rh)) if rh[i] == v and np.isfinite(fx[i])]
        if not steps:
            continue
        with_stick = [i for i in steps if stick is not None and stick[i].any()]
        last = (with_stick or steps)[-1]
        between = [i for i in steps if i <= last]
        picks.append((between[len(between) // 2], v))
    if len(picks) > at_most:
        keep = sorted({int(round(k)) for k in np.linspace(0, len(picks) - 1, at_most)})
        picks = [picks[k] for k in keep]
    return picks


def humid_stickslip_figure(ds, picks, path, *, mu=None) -> Path | None:
    """Stick/slip maps of one state per RH (``picks`` from :func:`humid_stickslip_steps`), on a
    common zoom (contact, tensile zone and meniscus of every panel) and a common traction scale,
    each tagged with its RH; the meniscus edge outlined.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (fields.nc) with the tangential variables.
    picks : sequence of (int, float)
        (dataset step position, RH as a fraction) of each panel.
    path : path-like
        The PNG file to write (atomically).
    mu : float, optional
        Friction coefficient, for the panels' F_x/(mu F0+).

    Returns
    -------
    Path or None
        The written PNG file; None without picks.
    """
    if not picks:
        return None
    xl, yl, lf, ll, qmax = _common_map_window(ds, picks)
    ncol = 2 if len(picks) == 4 else min(3, len(picks))
    nrow = -(-len(picks) // ncol)
    fig = new_figure(4.6 * ncol, 4.6 * nrow + 0.6)
    axes = fig.subplots(nrow, ncol, squeeze=False)
    handles = []
    for ax, (i, rh) in zip(axes.flat, picks):
        handles = _stickslip_axes(ax, ds, i, mu=mu, qmax=qmax or None, window=(xl, yl, lf, ll))
        ax.text(0.97, 0.04, rh_label(rh), transform=ax.transAxes, ha="right", va="bottom", fontsize=11,
                fontweight="bold", zorder=6, bbox={"boxstyle": "round,pad=0.25", "fc": "w", "ec": "0.6", "alpha": 0.9})
    for ax in list(axes.flat)[len(picks):]:
        ax.set_visible(False)
    for h in handles:  # the areas in the labels are the last panel's: name the colours only
        h.set_label(h.get_label().split(":")[0])
    fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 5), fontsize=9, frameon=False)
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


def _constant_normal_force(summary: dict) -> bool:
    """True for a tangential run at a fixed normal force (the force curve says nothing)."""
    rows = _rows_with(summary, "normal_force")
    if not rows or not any("tangential_force_x" in r for r in rows):
        return False
    fn = np.array([float(r["normal_force"]) for r in rows])
    return bool(np.ptp(fn) <= 1e-6 * max(np.max(np.abs(fn)), 1e-300))


def load_curve_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``load_curve``: the force-approach curve (not for a tangential run at a fixed
    normal force, nor for RH steps: there the curve says nothing).

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
        Figure name -> Path of the PNG written; empty when the set does not apply.
    """
    if _constant_normal_force(summary) or is_capillary(summary):
        return {}
    fc = force_curve_figure(summary, Path(outdir) / "force_curve.png")
    return {"force_curve": fc} if fc is not None else {}


def friction_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``friction``: stick ratio against F_x/(mu F0+) (or against the normal force
    of a normal-load path) and the stick/slip maps of the shown steps (a hysteresis run shows
    its maps at Paper E's points instead: set ``hysteresis``).  A humid run: the stick/slip
    maps of one state per RH (``stickslip_rh``) only; its curves per RH are set
    ``humid_friction``'s.

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
        Figure name -> Path of the PNG written; empty when the set does not apply.
    """
    outdir = Path(outdir)
    out = {}
    if is_humid_friction(summary):
        # one ramp or loop per RH: the curves per RH are set humid_friction's (one line through
        # every RH tangles); the maps: one per RH (partial_slip), Paper E's points (hysteresis)
        if ds is None or is_hysteresis(summary):
            return out
        fig = humid_stickslip_figure(ds, humid_stickslip_steps(ds), outdir / "stickslip_rh.png",
                                     mu=_friction_coefficient(summary, ds))
        return {"stickslip_rh": fig} if fig is not None else out
    for name, func in (("stick_normal", stick_normal_figure), ("stick_ratio", stick_ratio_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except (KeyError, TypeError, ValueError, IndexError):  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
            break  # a normal-load path has no F_x axis: one or the other
    if ds is None or (is_hysteresis(summary) and loop_map_steps(ds, summary)):
        return out
    maps = stickslip_steps(ds)
    if maps:
        mu = _friction_coefficient(summary, ds)
        qmax = max(float(np.nanmax(np.hypot(np.nan_to_num(ds["shear_x"].values[i]),
                                            np.nan_to_num(ds["shear_y"].values[i])))) for i in maps)
        names = set()
        for i in maps:
            k = _step_number(ds, i)
            # a summary.json step by its index; another state (the onset) by its label
            name = (f"stickslip_step{k}" if k is not None
                    else "stickslip_" + "".join(c if c.isalnum() else "_" for c in _step_name(ds, i)))
            name = name if name not in names else f"stickslip_field{i}"
            names.add(name)
            out[name] = stickslip_figure(ds, i, outdir / f"{name}.png", mu=mu, qmax=qmax or None)
    return out


def hysteresis_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``hysteresis``: the loop, the lateral stiffness, the last cycle's dissipation
    and the stick/slip maps at Paper E's points (:func:`hysteresis_figures`).

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
        Figure name -> Path of the PNG written; empty for a run that is not a hysteresis run.
    """
    if not is_hysteresis(summary):
        return {}
    offset, title = 0, None
    if is_humid_friction(summary):
        # the loop of the last RH, whose per-cycle maps fields.nc keeps; every RH's loop: set
        # humid_friction
        summary, offset = rh_summary(summary, -1)
        title = f"stick and slip at Paper E's points, RH {100 * summary['rh']:.3g} %"
    out = hysteresis_figures(ds, summary, outdir)
    picks = loop_map_steps(ds, summary, offset) if ds is not None else []
    if picks:
        out["stickslip_loop"] = loop_stickslip_figure(ds, picks, Path(outdir) / "stickslip_loop.png",
                                                      mu=_friction_coefficient(summary, ds), title=title)
    return out


def humid_friction_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``humid_friction``: friction values against RH with the dry reference, and the
    friction curve or loops one per RH (:func:`tribobem.output.humid.humid_friction_figures`).

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
        Figure name -> Path of the PNG written; empty for a dry run.
    """
    return humid_friction_figures(ds, summary, outdir)


def capillary_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``capillary``: the force components against RH, the humid pull-off, the
    meniscus and film maps (:func:`tribobem.output.capillary.capillary_figures`), for RH steps.

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
        Figure name -> Path of the PNG written; empty without RH steps.
    """
    return capillary_figures(ds, summary, outdir) if is_capillary(summary) else {}


def map_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``maps``: pressure, contact and profile of the representative state (a pull-off
    run: the most loaded state and the state at pull-off; RH steps: the peak capillary force),
    and the topography.

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
        Figure name -> Path of the PNG written; empty without fields.
    """
    if ds is None:
        return {}
    outdir = Path(outdir)
    out = {}
    capillary = is_capillary(summary)
    step = representative_step(ds)
    if capillary and step is not None and capillary_step(ds, summary) is not None:
        step = capillary_step(ds, summary)  # the maps at the peak capillary force
    if step is not None:
        labels = [str(v) for v in ds["label"].values]
        po = labels.index("pull-off") if "pull-off" in labels else None
        f = np.asarray(ds["normal_force"].values, dtype=float)
        loaded = int(np.nanargmax(f)) if np.any(np.isfinite(f)) else step
        if po is not None and loaded != po:
            # pull-off runs: maps of the most loaded state, and of the state at pull-off
            out["pressure"] = pressure_figure(ds, loaded, outdir / "pressure.png")
            out["contact"] = contact_figure(ds, loaded, outdir / "contact.png")
            out["profile"] = profile_figure(ds, po, outdir / "profile.png")
            out["pressure_pulloff"] = pressure_figure(ds, po, outdir / "pressure_pulloff.png")
            out["contact_pulloff"] = contact_figure(ds, po, outdir / "contact_pulloff.png")
        else:
            out["pressure"] = pressure_figure(ds, step, outdir / "pressure.png")
            if not capillary:  # the meniscus maps show contact, Dugdale zone and menisci instead
                out["contact"] = contact_figure(ds, step, outdir / "contact.png")
            out["profile"] = profile_figure(ds, step, outdir / "profile.png")
    out["topography"] = topography_figure(ds, outdir / "topography.png")
    return out


#: The figure sets a run kind names (:attr:`tribobem.runs.kind.RunKind.figures`): name -> a
#: function ``(ds, summary, outdir) -> {figure name: Path}`` that draws what applies.
FIGURE_SETS = {
    "load_curve": load_curve_figures,
    "friction": friction_figures,
    "hysteresis": hysteresis_run_figures,
    "capillary": capillary_run_figures,
    "humid_friction": humid_friction_run_figures,
    "maps": map_figures,
}


def make_figures(ds, summary: dict, outdir, sets=None) -> dict:
    """Draw the figures of a run into ``outdir``.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields (fields.nc); None: only the figures drawn from the summary.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder for the PNG files (created).
    sets : sequence of str, optional
        The figure sets to draw (keys of :data:`FIGURE_SETS`), as the run kind declares them;
        default: every set (each draws only what the summary and fields hold).

    Returns
    -------
    dict
        Figure name -> Path, in :data:`FIGURE_NAMES` order.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    names = tuple(FIGURE_SETS) if sets is None else tuple(sets)
    unknown = [n for n in names if n not in FIGURE_SETS]
    if unknown:
        raise ValueError(f"unknown figure set(s) {unknown}; known: {', '.join(FIGURE_SETS)}")
    out = {}
    for name in names:
        out.update(FIGURE_SETS[name](ds, summary, outdir))
    ordered = {}
    for k in FIGURE_NAMES:
        if k in ("stickslip", "dissipation"):
            ordered.update({n: p for n, p in out.items() if n.startswith(k + "_")})
        elif k in out:
            ordered[k] = out[k]
    return ordered
