"""The stick/slip maps of a humid partial-slip run: one state per RH on a common zoom and
traction scale (``stickslip_rh``), the meniscus edge outlined.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plotting import new_figure, save_png
from ..humid import rh_label
from .stickslip import _common_map_window, _stickslip_axes



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
