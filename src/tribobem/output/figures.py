"""PNG figures of a run (matplotlib, Agg, no pyplot state): topography, pressure map, contact
map, centre-line profile, force-approach curve.

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
           "profile_figure", "force_curve_figure"]

#: File stems of the figures, in report order.
FIGURE_NAMES = ("force_curve", "pressure", "contact", "profile", "pressure_pulloff", "contact_pulloff", "topography")

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
    fc = force_curve_figure(summary, outdir / "force_curve.png")
    if fc is not None:
        out["force_curve"] = fc
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
    return {k: out[k] for k in FIGURE_NAMES if k in out}
