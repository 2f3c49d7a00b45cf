"""PNG figures of a run (matplotlib, Agg, no pyplot state): topography, pressure map, contact
map, centre-line profile, force-approach curve; for the tangential kinds (partial_slip,
hysteresis) stick/slip maps with traction arrows, stick ratio and displacement against
F_x/(mu F0+), and stick ratio against the normal force of a normal-load path.

Every function takes the fields dataset (:mod:`tribobem.output.fields`) and/or the summary
dict, so ``tribobem plot RESULT`` re-makes the figures from the files alone.  Units are
chosen from the data (nm / µm, kPa / MPa / GPa, nN / µN).  Files are written atomically.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..units import display_unit, format_quantity
from .fields import representative_step
from .summary import atomic_write_bytes

__all__ = ["FIGURE_NAMES", "make_figures", "topography_figure", "pressure_figure", "contact_figure",
           "profile_figure", "force_curve_figure", "stickslip_figure", "stickslip_steps", "stick_ratio_figure",
           "stick_normal_figure"]

#: File stems of the figures, in report order.  ``stickslip`` stands for the stick/slip maps,
#: one per shown step, named ``stickslip_step<k>`` (k: the step's index in summary.json).
FIGURE_NAMES = ("force_curve", "stick_ratio", "stick_normal", "stickslip", "pressure", "contact", "profile",
                "pressure_pulloff", "contact_pulloff", "topography")

_DPI = 110
_COLORS = {"loading": "#1f77b4", "unloading": "#d62728"}
_CONTACT_COLORS = ("#e9ecef", "#f4a261", "#264653")  # free, cohesive zone, contact


def _figure(w=5.6, h=4.4):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(w, h), layout="constrained")
    return fig


def _save(fig, path) -> Path:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=_DPI)
    return atomic_write_bytes(path, buf.getvalue())


def _extent(ds, factor):
    x, y = np.asarray(ds["x"].values), np.asarray(ds["y"].values)
    dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
    dy = float(y[1] - y[0]) if len(y) > 1 else 1.0
    return [(x[0] - dx / 2) / factor, (x[-1] + dx / 2) / factor, (y[0] - dy / 2) / factor, (y[-1] + dy / 2) / factor]


def _map_axes(ax, ds, lf, ll, active=None):
    """Labels, equal aspect, and a zoom on the active region when it is small."""
    ax.set_xlabel(f"x ({ll})")
    ax.set_ylabel(f"y ({ll})")
    ax.set_aspect("equal")
    if active is not None and active.any():
        x = np.asarray(ds["x"].values) / lf
        y = np.asarray(ds["y"].values) / lf
        ix = np.nonzero(active.any(axis=1))[0]
        iy = np.nonzero(active.any(axis=0))[0]
        x0, x1, y0, y1 = x[ix[0]], x[ix[-1]], y[iy[0]], y[iy[-1]]
        half = 0.5 * max(x1 - x0, y1 - y0) * 1.5 + 2 * abs(x[1] - x[0] if len(x) > 1 else 1.0)
        span_x, span_y = x[-1] - x[0], y[-1] - y[0]
        if 2 * half < 0.6 * min(span_x, span_y):
            cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            ax.set_xlim(cx - half, cx + half)
            ax.set_ylim(cy - half, cy + half)


def _step_title(ds, step) -> str:
    label = str(ds["label"].values[step])
    f = float(ds["normal_force"].values[step])
    return f"{label}, F = {format_quantity(f, 'force', 3)}"


def topography_figure(ds, path) -> Path:
    """Initial gap and the bodies' roughness (when present), as maps."""
    panels = [("initial_gap", "initial gap h")]
    for name in ("roughness_body1", "roughness_body2"):
        if name in ds and np.any(np.asarray(ds[name].values) != 0):
            panels.append((name, f"roughness of body {name[-1]}"))
    fig = _figure(4.6 * len(panels), 4.2)
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    for ax, (name, title) in zip(axes, panels):
        h = np.asarray(ds[name].values)
        hf, hl = display_unit(h, "length")
        im = ax.imshow(h.T / hf, origin="lower", extent=_extent(ds, lf), cmap="cividis", interpolation="nearest")
        _map_axes(ax, ds, lf, ll)
        ax.set_title(title)
        fig.colorbar(im, ax=ax, shrink=0.85, label=f"height ({hl})")
    return _save(fig, path)


def pressure_figure(ds, step: int, path) -> Path:
    """Pressure map; diverging colours centred on 0 when tensile stresses exist, with the
    contact and cohesive zones outlined."""
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.lines import Line2D

    p = np.asarray(ds["pressure"].values[step])
    pf, pl = display_unit(p, "pressure")
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    fig = _figure()
    ax = fig.add_subplot()
    pmin, pmax = float(p.min()), float(p.max())
    if pmin < 0:
        top = pmax if pmax > 0 else 1e-3 * abs(pmin)
        norm = TwoSlopeNorm(vmin=pmin / pf, vcenter=0.0, vmax=top / pf)
        im = ax.imshow(p.T / pf, origin="lower", extent=_extent(ds, lf), cmap="RdBu_r", norm=norm,
                       interpolation="nearest")
    else:
        im = ax.imshow(p.T / pf, origin="lower", extent=_extent(ds, lf), cmap="magma_r", interpolation="nearest")
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
    _map_axes(ax, ds, lf, ll, active=p != 0)
    ax.set_title(f"pressure ({_step_title(ds, step)})", fontsize=10)
    return _save(fig, path)


def contact_figure(ds, step: int, path) -> Path:
    """Contact (g = 0), cohesive zone (adhesive stress outside contact) and free nodes."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    contact = np.asarray(ds["contact"].values[step]).astype(bool)
    adhesive = np.asarray(ds["adhesive"].values[step]).astype(bool) & ~contact
    code = np.where(contact, 2, np.where(adhesive, 1, 0))
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    cell = float(ds.attrs.get("dx", 1.0)) * float(ds.attrs.get("dy", 1.0))
    fig = _figure()
    ax = fig.add_subplot()
    cmap = ListedColormap(list(_CONTACT_COLORS))
    ax.imshow(code.T, origin="lower", extent=_extent(ds, lf), cmap=cmap,
              norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3), interpolation="nearest")
    handles = [Patch(color=_CONTACT_COLORS[2], label=f"contact: {format_quantity(contact.sum() * cell, 'area', 3)}")]
    if np.any(np.asarray(ds["adhesive"].values)):  # adhesive run: show the cohesive zone even when empty
        handles.append(Patch(color=_CONTACT_COLORS[1],
                             label=f"cohesive zone: {format_quantity(adhesive.sum() * cell, 'area', 3)}"))
    handles.append(Patch(facecolor=_CONTACT_COLORS[0], edgecolor="0.6", label="free"))
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.85)
    _map_axes(ax, ds, lf, ll, active=code > 0)
    ax.set_title(f"contact map ({_step_title(ds, step)})", fontsize=10)
    return _save(fig, path)


def profile_figure(ds, step: int, path) -> Path:
    """Gap and pressure along the centre line y = 0 (the row nearest to it)."""
    y = np.asarray(ds["y"].values)
    iy = int(np.argmin(np.abs(y)))
    x = np.asarray(ds["x"].values)
    g = np.asarray(ds["gap"].values[step])[:, iy]
    h = np.asarray(ds["initial_gap"].values)[:, iy]
    p = np.asarray(ds["pressure"].values[step])[:, iy]
    lf, ll = display_unit(np.abs(x) * 2, "length")
    gf, gl = display_unit(np.concatenate([g, h]), "length")
    pf, pl = display_unit(p, "pressure")
    fig = _figure(6.4, 4.2)
    ax = fig.add_subplot()
    ax.plot(x / lf, h / gf, color="0.6", lw=1, ls="--", label="initial gap h")
    ax.plot(x / lf, g / gf, color="#1f77b4", lw=1.4, label="gap g")
    ax.set_xlabel(f"x ({ll})")
    ax.set_ylabel(f"gap ({gl})", color="#1f77b4")
    ax2 = ax.twinx()
    ax2.plot(x / lf, p / pf, color="#d62728", lw=1.4, label="pressure p")
    ax2.axhline(0.0, color="#d62728", lw=0.5, alpha=0.5)
    ax2.set_ylabel(f"pressure ({pl})", color="#d62728")
    lines = ax.get_lines()[:2] + ax2.get_lines()[:1]
    ax.legend(lines, [ln.get_label() for ln in lines], loc="upper center", fontsize=8)
    ax.set_title(f"centre line y = {y[iy] / lf:.3g} {ll} ({_step_title(ds, step)})", fontsize=10)
    return _save(fig, path)


def force_curve_figure(summary: dict, path) -> Path | None:
    """Force-approach curve: loading and unloading branches, pull-off and jumps marked.
    None (nothing written) when the run has fewer than two steps."""
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
    fig = _figure(6.4, 4.6)
    ax = fig.add_subplot()
    for name, marker in (("loading", "o"), ("unloading", "s")):
        m = branch == name
        if m.any():
            ax.plot(d[m] / df, f[m] / ff, marker=marker, ms=3.5, lw=1.3, color=_COLORS[name], label=name)
    if (~conv).any():
        ax.plot(d[~conv] / df, f[~conv] / ff, "x", color="k", ms=7, label="not converged")
    ax.axhline(0.0, color="0.5", lw=0.6)
    po = summary.get("pull_off_force")
    pa = summary.get("pull_off_approach")
    if po is not None and pa is not None and po < 0:
        ax.plot([pa / df], [po / ff], marker="*", ms=14, color="#e9c46a", mec="k", ls="none",
                label=f"pull-off {format_quantity(po, 'force', 3)}", zorder=5)
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
    return _save(fig, path)


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
            ins.plot(d[m] / df, f[m] / ffi, marker=marker, ms=3, lw=1.0, color=_COLORS[name])
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


def _num(v):
    """``v`` as a finite float, else None."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if np.isfinite(f) else None


def _friction_coefficient(summary: dict | None, ds=None):
    """mu from the summary (run-level, else the scenario echo), else the fields' attribute."""
    s = summary or {}
    mu = _num(s.get("friction_coefficient"))
    if mu is None:
        fr = (s.get("inputs") or {}).get("friction") or {}
        mu = _num(fr.get("coefficient")) if isinstance(fr, dict) else None
    if mu is None and ds is not None:
        mu = _num(ds.attrs.get("friction_coefficient"))
    return mu if mu is not None and mu > 0 else None


def _tangential_step_indices(ds) -> list[int]:
    """Steps of the dataset that hold a tangential solution."""
    if ds is None or "shear_x" not in ds or "tangential_force_x" not in ds.coords:
        return []
    fx = np.asarray(ds["tangential_force_x"].values, dtype=float)
    return [int(i) for i in np.nonzero(np.isfinite(fx))[0]]


def _step_number(ds, step: int) -> int:
    """The summary.json index of a dataset step (the dataset index when not listed)."""
    if "summary_step" in ds.coords:
        k = int(ds["summary_step"].values[step])
        if k >= 0:
            return k
    return int(step)


def stickslip_steps(ds) -> list[int]:
    """Dataset steps the stick/slip maps show: the first tangential step (usually F_x = 0),
    the last one that still has stick nodes, and the one half-way between them (in step order).
    Empty when the dataset has no tangential fields."""
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
    ext = _extent(ds, lf)
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
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    p = np.asarray(ds["pressure"].values[step])
    comp = p > 0
    stick = np.asarray(ds["stick"].values[step]).astype(bool) & comp
    slip = comp & ~stick
    tensile = np.asarray(ds["adhesive"].values[step]).astype(bool) | (np.asarray(ds["contact"].values[step]).astype(bool) & ~comp)
    tensile &= ~comp
    code = np.where(stick, 3, np.where(slip, 2, np.where(tensile, 1, 0)))
    qx = np.nan_to_num(np.asarray(ds["shear_x"].values[step], dtype=float))
    qy = np.nan_to_num(np.asarray(ds["shear_y"].values[step], dtype=float))
    qabs = np.hypot(qx, qy)

    x = np.asarray(ds["x"].values)
    y = np.asarray(ds["y"].values)
    active = comp | tensile
    lf0, _ = display_unit(np.abs(x) * 2, "length")
    xl, yl = _zoom_window(ds, active, lf0)
    lf, ll = display_unit([max(abs(v) for v in (*xl, *yl)) * lf0 * 1.0001], "length")
    xl, yl = tuple(v * lf0 / lf for v in xl), tuple(v * lf0 / lf for v in yl)

    fig = _figure(5.6, 5.6)
    ax = fig.add_subplot()
    ax.imshow(code.T, origin="lower", extent=_extent(ds, lf), cmap=ListedColormap(list(_STICKSLIP_COLORS)),
              norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], 4), interpolation="nearest")
    if comp.any() and 0 < comp.sum() < comp.size:
        ax.contour(x / lf, y / lf, comp.T.astype(float), levels=[0.5], colors="0.25", linewidths=0.6)

    # traction arrows, ~22 per contact diameter, on a lattice centred on the contact
    qkey = None
    qtop = float(qmax) if qmax is not None and qmax > 0 else float(qabs[comp].max()) if comp.any() else 0.0
    if comp.any() and qtop > 0 and np.any(qabs[comp] > 1e-12 * qtop):
        ix = np.nonzero(comp.any(axis=1))[0]
        iy = np.nonzero(comp.any(axis=0))[0]
        diam = max(ix[-1] - ix[0], iy[-1] - iy[0]) + 1
        stride = max(1, int(round(diam / _ARROWS_PER_DIAMETER)))
        cx, cy = (ix[0] + ix[-1]) // 2, (iy[0] + iy[-1]) // 2
        sel = np.zeros_like(comp)
        sel[cx % stride::stride, cy % stride::stride] = True
        sel &= comp
        dxl = abs(float(x[1] - x[0])) / lf if len(x) > 1 else 1.0
        scale = qtop / (0.9 * stride * dxl)  # Pa per display length: the longest arrow spans 0.9 strides
        X, Y = np.meshgrid(x / lf, y / lf, indexing="ij")
        qv = ax.quiver(X[sel], Y[sel], qx[sel], qy[sel], angles="xy", scale_units="xy", scale=scale,
                       color="#1b1b1b", width=0.0042, headwidth=3.6, headlength=4.0, headaxislength=3.6,
                       pivot="middle", zorder=3)
        qf, ql = display_unit([qtop], "pressure")
        qkey = ax.quiverkey(qv, 0.04, 0.955, qtop, f"|q| = {qtop / qf:.3g} {ql}", labelpos="E", coordinates="axes",
                            fontproperties={"size": 8})
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

    handles = [Patch(color=_STICKSLIP_COLORS[3], label=f"stick: {area(stick)}"),
               Patch(color=_STICKSLIP_COLORS[2], label=f"slip: {area(slip)}")]
    if np.any(np.asarray(ds["adhesive"].values)):
        handles.append(Patch(color=_STICKSLIP_COLORS[1], label="tensile zone, p < 0 (no shear)"))
    handles.append(Patch(facecolor=_STICKSLIP_COLORS[0], edgecolor="0.6", label="no contact"))
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8, frameon=False)

    ax.set_xlim(*xl)
    ax.set_ylim(*yl)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({ll})")
    ax.set_ylabel(f"y ({ll})")

    fx = _num(ds["tangential_force_x"].values[step])
    fy = _num(ds["tangential_force_y"].values[step]) or 0.0
    fn = float(ds["normal_force"].values[step])
    ratio = n_comp and float(np.count_nonzero(stick)) / n_comp
    line1 = f"step {_step_number(ds, step)}: $F$ = {format_quantity(fn, 'force', 3)}"
    if fx is not None:
        line1 += f", $F_x$ = {format_quantity(fx, 'force', 3)}"
    f0 = _repulsive_force(ds, step)
    if mu is not None and f0 > 0 and fx is not None:
        if abs(fy) > 1e-9 * max(abs(fx), 1e-300):
            line2 = rf"$|F_t|/(\mu F_0^+)$ = {np.hypot(fx, fy) / (mu * f0):.3f}"
        else:
            line2 = rf"$F_x/(\mu F_0^+)$ = {fx / (mu * f0):.3f}"
    else:
        line2 = ""
    line2 += ("," if line2 else "") + f" stick ratio {ratio:.3f}" if n_comp else " no compressive contact"
    ax.set_title(f"{line1}\n{line2.strip()}", fontsize=10)
    return _save(fig, path)


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
    branch.  Against F_x itself when mu is unknown.  None when the rows lack the data."""
    rows = _rows_with(summary, "tangential_force_x", "stick_ratio")
    if len(rows) < 2:
        return None
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

    fig = _figure(5.8, 6.6 if has_d else 4.0)
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
                      f"gross-slip onset {format_quantity(onset * xf, 'force', 3)}")
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
                        label=f"presliding displacement {format_quantity(pre, 'length', 3)}")
            if onset is not None:
                ax2.plot([onset], [(d0 + pre) / df], marker="*", ms=13, color="#e9c46a", mec="k", ls="none",
                         zorder=5)
        ax2.set_ylabel(f"tangential displacement $\\delta_x$ ({dl})")
        ax2.grid(alpha=0.3)
        if ax2.get_legend_handles_labels()[0]:
            ax2.legend(fontsize=8, loc="best")
    axes[-1].set_xlabel(xlabel)
    return _save(fig, path)


def stick_normal_figure(summary: dict, path) -> Path | None:
    """Stick ratio (and ``stick_radius_ratio`` when the rows have it) against the normal force
    of a normal-load path with friction (no tangential force).  None when the rows are not
    such a path."""
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
    fig = _figure(6.0, 4.4)
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
    return _save(fig, path)


def _constant_normal_force(summary: dict) -> bool:
    """True for a tangential run at a fixed normal force (the force curve says nothing)."""
    rows = _rows_with(summary, "normal_force")
    if not rows or not any("tangential_force_x" in r for r in rows):
        return False
    fn = np.array([float(r["normal_force"]) for r in rows])
    return bool(np.ptp(fn) <= 1e-6 * max(np.max(np.abs(fn)), 1e-300))


def make_figures(ds, summary: dict, outdir) -> dict:
    """Draw every figure that applies into ``outdir``.

    Returns
    -------
    dict
        Figure name -> Path, in :data:`FIGURE_NAMES` order.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    out = {}
    fc = None if _constant_normal_force(summary) else force_curve_figure(summary, outdir / "force_curve.png")
    if fc is not None:
        out["force_curve"] = fc
    for name, func in (("stick_normal", stick_normal_figure), ("stick_ratio", stick_ratio_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except (KeyError, TypeError, ValueError, IndexError):  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
            break  # a normal-load path has no F_x axis: one or the other
    maps = stickslip_steps(ds) if ds is not None else []
    if maps:
        mu = _friction_coefficient(summary, ds)
        qmax = max(float(np.nanmax(np.hypot(np.nan_to_num(ds["shear_x"].values[i]),
                                            np.nan_to_num(ds["shear_y"].values[i])))) for i in maps)
        names = set()
        for i in maps:
            k = _step_number(ds, i)
            name = f"stickslip_step{k}" if f"stickslip_step{k}" not in names else f"stickslip_field{i}"
            names.add(name)
            out[name] = stickslip_figure(ds, i, outdir / f"{name}.png", mu=mu, qmax=qmax or None)
    step = representative_step(ds) if ds is not None else None
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
            out["contact"] = contact_figure(ds, step, outdir / "contact.png")
            out["profile"] = profile_figure(ds, step, outdir / "profile.png")
    if ds is not None:
        out["topography"] = topography_figure(ds, outdir / "topography.png")
    ordered = {}
    for k in FIGURE_NAMES:
        if k == "stickslip":
            ordered.update({n: p for n, p in out.items() if n.startswith("stickslip_")})
        elif k in out:
            ordered[k] = out[k]
    return ordered
