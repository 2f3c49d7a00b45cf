"""Figures of the capillary kinds (``capillary``, and ``pulloff`` with ``[humidity]``).

* ``capillary_forces``: the adhesive force components against RH (F_cap, F_ss, F_ws and their
  sum, Paper B Fig. 13) and the areas (contact, meniscus) and active island count;
* ``pulloff_rh``: the humid pull-off against RH, with the unloading curves it comes from;
* ``meniscus``: meniscus/island maps at chosen RH (Paper B Fig. 12): contact, Dugdale zone,
  meniscus (active islands outside contact), dry cross-cut islands (below the cut height but
  without a seed) and free nodes;
* ``films``: the levelled film thickness of each body whose film is not uniform, at chosen RH.

The chosen RH (:func:`chosen_steps`): the first and the last RH of fields.nc, the one of the
most tensile capillary force and one in between (at most four).  Every function reads the
fields dataset and/or the summary only, so ``tribobem plot`` re-makes them from the files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..units import display_unit, format_value
from .plotting import map_axes, map_extent, new_figure, save_png
from .run_kind import run_view

__all__ = ["FIGURE_NAMES"]

#: Figure names of this module, in report order.
FIGURE_NAMES = ("capillary_forces", "pulloff_rh", "meniscus", "films")

#: free, dry cross-cut island, meniscus, Dugdale zone, contact
_MENISCUS_COLORS = ("#eef0f2", "#cfe3f3", "#2b7bba", "#f4a261", "#1d2d3a")
_LABELS = ("free", "dry cross-cut (no seed)", "meniscus (dP_cap)", "Dugdale zone", "contact")


def _rows(summary: dict | None) -> list[dict]:
    return [r for r in (summary or {}).get("steps", []) if isinstance(r, dict) and r.get("rh") is not None]


def _rh_of(ds) -> np.ndarray | None:
    if ds is None or "rh" not in ds.coords or ds.sizes.get("step", 0) == 0:
        return None
    return np.asarray(ds["rh"].values, dtype=float)


def capillary_step(ds, summary: dict | None) -> int | None:
    """The dataset step of the most tensile capillary force (the peak of Paper B Fig. 13).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The run's fields (:func:`~tribobem.output.fields.read_fields`), with an ``rh``
        coordinate along ``step``.
    summary : dict or None
        A run's summary (:func:`~tribobem.output.summary.read_summary`).

    Returns
    -------
    int or None
        Index along ``step`` (matched to the summary's steps by RH); the last step when no
        capillary force is known; None without RH steps.
    """
    rh = _rh_of(ds)
    if rh is None:
        return None
    rows = _rows(summary)
    by_rh = {round(float(r["rh"]), 12): r.get("capillary_force") for r in rows}
    f = np.array([by_rh.get(round(float(v), 12)) if by_rh.get(round(float(v), 12)) is not None else np.nan
                  for v in rh], dtype=float)
    if not np.any(np.isfinite(f)):
        return int(len(rh) - 1)
    return int(np.nanargmin(f))


def chosen_steps(ds, summary: dict | None, at_most: int = 4) -> list[int]:
    """Dataset steps to map: first, peak capillary force, last, and one in between (sorted by RH).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The run's fields (:func:`~tribobem.output.fields.read_fields`), with an ``rh``
        coordinate along ``step``.
    summary : dict or None
        A run's summary (:func:`~tribobem.output.summary.read_summary`).
    at_most : int
        Most steps returned (the lowest RH first).

    Returns
    -------
    list of int
        Distinct indices along ``step``, in increasing RH; empty without RH steps.
    """
    rh = _rh_of(ds)
    if rh is None:
        return []
    n = len(rh)
    order = list(np.argsort(rh, kind="stable"))
    picks = [order[0], order[-1]]
    pk = capillary_step(ds, summary)
    if pk is not None:
        picks.append(pk)
    if n >= 3:
        picks.append(order[n // 2])
    out = []
    for i in sorted(set(int(i) for i in picks), key=lambda i: (rh[i], i)):
        if len(out) < at_most:
            out.append(i)
    return out


# ----------------------------------------------------------------------------- force components
def capillary_forces_figure(summary: dict, path) -> Path | None:
    """F_cap, F_ss, F_ws and their sum against RH (left); contact and meniscus areas and the
    active island count (right).

    Parameters
    ----------
    summary : dict
        A ``capillary`` run's summary.
    path : path-like
        The PNG file to write.

    Returns
    -------
    pathlib.Path or None
        The written file; None without an RH step with a capillary force, or for a humid
        pull-off run (:func:`pulloff_rh_figure` draws that one).
    """
    rows = [r for r in _rows(summary) if r.get("capillary_force") is not None]
    if not rows or run_view(summary).humid_pulloff:
        return None
    rows = sorted(rows, key=lambda r: r["rh"])
    rh = np.array([r["rh"] for r in rows], dtype=float) * 100.0
    comp = {k: np.array([r.get(k) if r.get(k) is not None else np.nan for r in rows], dtype=float)
            for k in ("capillary_force", "solid_solid_force", "water_solid_force", "contact_area", "wetted_area",
                      "island_count")}
    total = comp["capillary_force"] + comp["solid_solid_force"] + comp["water_solid_force"]
    ok = np.array([bool(r.get("converged")) for r in rows])
    ff, fl = display_unit(np.concatenate([total, comp["capillary_force"]]), "force")
    fig = new_figure(11.0, 4.3)
    ax, ax2 = fig.subplots(1, 2)
    for key, lab, color, mk in (("capillary_force", "F$_{cap}$ (capillary)", "#2b7bba", "o"),
                                ("solid_solid_force", "F$_{ss}$ (solid-solid, Dugdale)", "#f4a261", "s"),
                                ("water_solid_force", "F$_{ws}$ (water-solid vdW)", "#2a9d8f", "^")):
        ax.plot(rh, comp[key] / ff, marker=mk, ms=4, color=color, label=lab)
    ax.plot(rh, total / ff, color="k", lw=1.6, label="total adhesive F$_{cap}$+F$_{ss}$+F$_{ws}$")
    if not ok.all():
        ax.plot(rh[~ok], total[~ok] / ff, ls="none", marker="x", ms=9, color="#d62728", label="not converged")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("relative humidity RH (%)")
    ax.set_ylabel(f"force ({fl}), < 0 tensile")
    load = summary.get("inputs", {}).get("load", {}) or {}
    what = (f"F = {format_value(load['force'], 'force', 3)}" if load.get("force") is not None else
            f"approach {format_value(load['approach'], 'length', 3)}" if load.get("approach") is not None else "")
    ax.set_title(f"adhesive force components ({what})", fontsize=10)
    ax.legend(fontsize=8, loc="best")
    g = summary.get("problem", {}).get("grid") or {}
    nominal = float(g.get("lx", np.nan)) * float(g.get("ly", np.nan))
    ax2.plot(rh, 100.0 * comp["wetted_area"] / nominal, marker="o", ms=4, color="#2b7bba", label="meniscus area")
    ax2.plot(rh, 100.0 * comp["contact_area"] / nominal, marker="s", ms=4, color="#1d2d3a", label="contact area")
    ax2.set_xlabel("relative humidity RH (%)")
    ax2.set_ylabel("area (% of the nominal area)")
    ax3 = ax2.twinx()
    ax3.plot(rh, comp["island_count"], marker="^", ms=4, ls="--", color="#e76f51", label="active islands")
    ax3.set_ylabel("active meniscus islands", color="#e76f51")
    lines = ax2.get_lines() + ax3.get_lines()
    ax2.legend(lines, [ln.get_label() for ln in lines], fontsize=8, loc="upper left")
    ax2.set_title("meniscus and contact areas", fontsize=10)
    return save_png(fig, path)


def pulloff_rh_figure(summary: dict, path) -> Path | None:
    """Humid pull-off against RH (left; the capillary part at pull-off dashed) and the unloading
    curves F(delta) it comes from (right).

    Parameters
    ----------
    summary : dict
        A humid pull-off run's summary (``steps`` per RH, ``unloading_curves``).
    path : path-like
        The PNG file to write.

    Returns
    -------
    pathlib.Path or None
        The written file; None for another kind of run or without RH steps.
    """
    if not run_view(summary).humid_pulloff:
        return None
    rows = sorted(_rows(summary), key=lambda r: r["rh"])
    if not rows:
        return None
    rh = np.array([r["rh"] for r in rows], dtype=float) * 100.0
    po = np.array([r.get("pull_off_force") if r.get("pull_off_force") is not None else np.nan for r in rows])
    cap = np.array([r.get("capillary_force") if r.get("capillary_force") is not None else np.nan for r in rows])
    curves = summary.get("unloading_curves") or []
    allf = np.concatenate([po, cap] + [np.asarray(c.get("force") or [], dtype=float) for c in curves])
    ff, fl = display_unit(allf[np.isfinite(allf)] if np.any(np.isfinite(allf)) else np.array([1.0]), "force")
    fig = new_figure(11.0, 4.3)
    ax, ax2 = fig.subplots(1, 2)
    ax.plot(rh, po / ff, marker="o", color="k", label="pull-off force")
    ax.plot(rh, cap / ff, marker="s", ms=4, ls="--", color="#2b7bba", label="F$_{cap}$ at pull-off")
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xlabel("relative humidity RH (%)")
    ax.set_ylabel(f"force ({fl}), < 0 tensile")
    ax.set_title("humid pull-off", fontsize=10)
    ax.legend(fontsize=8)
    if curves:
        import matplotlib as mpl

        cmap = mpl.colormaps["viridis"]
        d_all = np.concatenate([np.asarray(c.get("approach") or [], dtype=float) for c in curves])
        d_all = d_all[np.isfinite(d_all)]
        df, dl = display_unit(d_all if d_all.size else np.array([1e-9]), "length")
        rhs = [float(c.get("rh", np.nan)) for c in curves]
        lo, hi = np.nanmin(rhs), np.nanmax(rhs)
        for c in curves:
            d = np.asarray(c.get("approach") or [], dtype=float)
            f = np.asarray(c.get("force") or [], dtype=float)
            if d.size == 0:
                continue
            t = 0.5 if hi <= lo else (float(c["rh"]) - lo) / (hi - lo)
            ax2.plot(d / df, f / ff, color=cmap(0.1 + 0.8 * t), lw=1.2, label=f"RH {100 * float(c['rh']):.3g} %")
        ax2.axhline(0.0, color="0.5", lw=0.6)
        ax2.set_xlabel(f"approach \u03b4 ({dl})")
        ax2.set_ylabel(f"force ({fl})")
        ax2.set_title("unloading curves (menisci recomputed at every step)", fontsize=10)
        ax2.legend(fontsize=7, ncols=2)
    else:
        ax2.set_visible(False)
    return save_png(fig, path)


# ----------------------------------------------------------------------------- maps
def _category(ds, i: int, h0: float | None) -> np.ndarray:
    contact = np.asarray(ds["contact"].values[i]).astype(bool)
    labels = np.asarray(ds["island_labels"].values[i])
    active = np.asarray(ds["island_active"].values[i]).astype(bool) if "island_active" in ds else labels > 0
    gap = np.asarray(ds["gap"].values[i])
    # the Dugdale zone wins over the meniscus (the precedence of the capillary law); "adhesive" in fields.nc is
    # every tensile node outside contact, which the water-solid terms make nearly all of them
    adhesive = (gap < h0) & ~contact if h0 else np.zeros(contact.shape, dtype=bool)
    men = np.asarray(ds["meniscus"].values[i]).astype(bool) & ~contact & ~adhesive
    dry = (labels > 0) & ~active & ~contact & ~adhesive
    code = np.zeros(contact.shape, dtype=int)
    code[dry] = 1
    code[men] = 2
    code[adhesive] = 3
    code[contact] = 4
    return code


def _panel_grid(n: int):
    ncol = min(n, 4 if n != 3 else 3)
    nrow = -(-n // ncol)
    return nrow, ncol


def meniscus_figure(ds, steps, path, h0: float | None = None) -> Path | None:
    """Meniscus/island maps at the dataset ``steps`` (one panel each, common legend).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The run's fields (:func:`~tribobem.output.fields.read_fields`), with an ``rh``
        coordinate along ``step``.
    steps : sequence of int
        Indices along ``step`` (e.g. :func:`chosen_steps`).
    path : path-like
        The PNG file to write.
    h0 : float, optional
        The Dugdale range (m) when the run has one: its zone is drawn over the meniscus (the
        solver's precedence).

    Returns
    -------
    pathlib.Path or None
        The written file; None without steps or without the meniscus fields.
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    if ds is None or not steps or "meniscus" not in ds or "island_labels" not in ds:
        return None
    rh = _rh_of(ds)
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    cell = float(ds.attrs.get("dx", 1.0)) * float(ds.attrs.get("dy", 1.0))
    total = ds.sizes["x"] * ds.sizes["y"] * cell
    nrow, ncol = _panel_grid(len(steps))
    fig = new_figure(3.7 * ncol + 0.4, 3.8 * nrow + 0.6)
    axes = fig.subplots(nrow, ncol, squeeze=False)
    cmap = ListedColormap(list(_MENISCUS_COLORS))
    norm = BoundaryNorm(np.arange(-0.5, 5.0, 1.0), 5)
    for ax, i in zip(axes.flat, steps):
        code = _category(ds, i, h0)
        ax.imshow(code.T, origin="lower", extent=map_extent(ds, lf), cmap=cmap, norm=norm, interpolation="nearest")
        map_axes(ax, ds, lf, ll)
        men = float((code == 2).sum() * cell)
        con = float((code == 4).sum() * cell)
        title = f"RH {100 * rh[i]:.3g} %" if rh is not None else str(ds["label"].values[i])
        ax.set_title(f"{title}: meniscus {100 * men / total:.3g} %, contact {100 * con / total:.3g} %", fontsize=9)
    for ax in list(axes.flat)[len(steps):]:
        ax.set_visible(False)
    handles = [Patch(facecolor=c, edgecolor="0.6", label=lab) for k, (c, lab) in enumerate(zip(_MENISCUS_COLORS, _LABELS))
               if k != 3 or h0]
    fig.legend(handles=handles, loc="outside lower center", ncols=5, fontsize=8, frameon=False)
    return save_png(fig, path)


def films_figure(ds, steps, path) -> Path | None:
    """Film thickness maps of the bodies that carry a film, at the dataset ``steps``
    (rows: bodies; columns: RH; one colour scale per panel: the levelling is a small
    modulation of a mean thickness that grows with RH).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The run's fields (:func:`~tribobem.output.fields.read_fields`), with an ``rh``
        coordinate along ``step``.
    steps : sequence of int
        Indices along ``step``.
    path : path-like
        The PNG file to write.

    Returns
    -------
    pathlib.Path or None
        The written file; None when no body has a film that varies over the grid (a dry
        body, a smooth flat or uniform levelling: no map worth showing).
    """
    if ds is None or not steps:
        return None
    def varies(b):  # a uniform film (a dry body, a smooth flat, levelling "uniform") has no map worth showing
        if f"film_thickness_{b}" not in ds:
            return False
        e = np.asarray(ds[f"film_thickness_{b}"].values)[list(steps)]
        return bool(np.any(e > 0) and np.any(np.ptp(e.reshape(len(steps), -1), axis=1) > 1e-3 * e.mean()))

    bodies = [b for b in (1, 2) if varies(b)]
    if not bodies:
        return None
    rh = _rh_of(ds)
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    ncol = len(steps)
    fig = new_figure(4.1 * ncol + 0.4, 3.6 * len(bodies) + 0.4)
    axes = fig.subplots(len(bodies), ncol, squeeze=False)
    for r, b in enumerate(bodies):
        for c, i in enumerate(steps):
            ax = axes[r, c]
            e = np.asarray(ds[f"film_thickness_{b}"].values[i]) * 1e9  # nm: films are a few nm thick
            im = ax.imshow(e.T, origin="lower", extent=map_extent(ds, lf), cmap="Blues", interpolation="nearest")
            map_axes(ax, ds, lf, ll)
            title = f"RH {100 * rh[i]:.3g} %" if rh is not None else str(ds["label"].values[i])
            ax.set_title(f"body {b}, {title}: mean {e.mean():.3g} nm", fontsize=9)
            fig.colorbar(im, ax=ax, shrink=0.8, label=f"e{b} (nm)")
    return save_png(fig, path)


def capillary_figures(ds, summary: dict, outdir) -> dict:
    """The capillary figures that apply (name -> Path), in :data:`FIGURE_NAMES` order.

    A figure that fails on unexpected data is left out instead of failing the run.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The run's fields (:func:`~tribobem.output.fields.read_fields`), with an ``rh``
        coordinate along ``step``.
    summary : dict
        The run's summary.
    outdir : path-like
        Folder of the PNG files (``<name>.png``).

    Returns
    -------
    dict
        Figure name -> path of the written file.
    """
    outdir = Path(outdir)
    out = {}
    safe = (KeyError, TypeError, ValueError, IndexError)
    for name, func in (("capillary_forces", capillary_forces_figure), ("pulloff_rh", pulloff_rh_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except safe:  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
    steps = chosen_steps(ds, summary)
    h0 = ((summary or {}).get("problem") or {}).get("h0")
    for name, func, kw in (("meniscus", meniscus_figure, {"h0": h0}), ("films", films_figure, {})):
        try:
            fig = func(ds, steps, outdir / f"{name}.png", **kw)
        except safe:
            fig = None
        if fig is not None:
            out[name] = fig
    return out
