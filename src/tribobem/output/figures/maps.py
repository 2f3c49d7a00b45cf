"""Maps of one state (pressure, contact, profile along the row through the largest pressure)
and the topography.

Every function takes the fields dataset (:mod:`tribobem.output.fields`), so ``tribobem plot
RESULT`` re-makes the figures from the files alone; units are chosen from the data.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...units import display_unit, format_value
from ..plotting import CONTACT_COLORS, map_axes, map_extent, new_figure, profile_row, save_png
from ..plotting import step_title


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


def subsurface_figure(ds, path) -> Path | None:
    """The von Mises stress below the surface: per elastic body, a section through the largest
    value (x against depth at its y, for its state) and the depth profile of the plane maxima
    and of the maximum shear stress.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run, with ``von_mises_body1/2`` (``[output] stresses``).
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
        The written PNG file; None without stress fields.
    """
    bodies = [b for b in ("body1", "body2") if f"von_mises_{b}" in ds]
    if not bodies:
        return None
    z = np.asarray(ds["depth"].values, dtype=float)
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    zf, zl = display_unit(z, "length")
    fig = new_figure(11.0, 4.0 * len(bodies))
    axes = fig.subplots(len(bodies), 2, squeeze=False)
    for row, b in zip(axes, bodies):
        vm = np.asarray(ds[f"von_mises_{b}"].values, dtype=float)
        ts = np.asarray(ds[f"max_shear_{b}"].values, dtype=float)
        s, k, i, j = np.unravel_index(int(np.argmax(vm)), vm.shape)
        sf, sl = display_unit(vm[s], "pressure")
        x = np.asarray(ds["x"].values, dtype=float)
        sec = vm[s, :, :, j]
        ax = row[0]
        im = ax.pcolormesh(x / lf, z / zf, sec / sf, cmap="inferno", shading="nearest")
        ax.invert_yaxis()
        ax.plot([x[i] / lf], [z[k] / zf], marker="+", color="c", markersize=12, mew=2)
        ax.set_xlabel(f"x ({ll})")
        ax.set_ylabel(f"depth ({zl})")
        yv = float(np.asarray(ds["y"].values)[j])
        ax.set_title(f"{b}: von Mises, section y = {format_value(yv / lf, 3)} {ll} ({step_title(ds, s)})")
        fig.colorbar(im, ax=ax, shrink=0.85, label=f"von Mises ({sl})")
        ax = row[1]
        ax.plot(vm[s].max(axis=(1, 2)) / sf, z / zf, label="von Mises, plane maximum")
        ax.plot(ts[s].max(axis=(1, 2)) / sf, z / zf, label="max shear (s1 - s3)/2, plane maximum")
        ax.invert_yaxis()
        ax.set_xlabel(f"stress ({sl})")
        ax.set_ylabel(f"depth ({zl})")
        ax.set_title(f"{b}: largest {format_value(vm[s, k, i, j] / sf, 3)} {sl} at {format_value(z[k] / zf, 3)} {zl}")
        ax.legend(loc="lower right")
    return save_png(fig, path)


def plastic_figure(ds, step: int, path) -> Path | None:
    """The permanent (plastic) surface displacement after state ``step``, with the plastic
    nodes of that state outlined (a hardness cap).

    Parameters
    ----------
    ds : xarray.Dataset
        The fields of the run (with ``plastic_displacement`` and ``plastic``).
    step : int
        Position along the dataset's ``step`` dimension.
    path : path-like
        The PNG file to write (atomically).

    Returns
    -------
    Path or None
        The written PNG file; None when nothing yielded.
    """
    if "plastic_displacement" not in ds:
        return None
    d = np.asarray(ds["plastic_displacement"].values[step], dtype=float)
    if not np.any(d > 0):
        return None
    df, dl = display_unit(d, "length")
    lf, ll = display_unit(np.abs(np.asarray(ds["x"].values)) * 2, "length")
    fig = new_figure()
    ax = fig.add_subplot()
    im = ax.imshow(d.T / df, origin="lower", extent=map_extent(ds, lf), cmap="viridis", interpolation="nearest")
    fig.colorbar(im, ax=ax, shrink=0.85, label=f"plastic displacement ({dl})")
    mask = np.asarray(ds["plastic"].values[step]).astype(float)
    if mask.any():
        x = np.asarray(ds["x"].values) / lf
        y = np.asarray(ds["y"].values) / lf
        ax.contour(x, y, mask.T, levels=[0.5], colors="w", linewidths=0.8)
    map_axes(ax, ds, lf, ll)
    ax.set_title(f"flattening so far ({step_title(ds, step)}); white: p = H now")
    return save_png(fig, path)
