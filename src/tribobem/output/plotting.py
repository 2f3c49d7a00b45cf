"""Plotting helpers shared by the figure modules (:mod:`.figures`, :mod:`.capillary`,
:mod:`.humid`): a matplotlib Figure without pyplot state, the atomic PNG write, the axes of a map
in the grid's coordinates (m, shown in the unit the caller chose), and the summary readings the
friction figures share (a finite number, mu, whether a run is a hysteresis run).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..units import format_quantity
from .atomic import atomic_write_bytes

__all__ = ["DPI", "COLORS", "CONTACT_COLORS", "new_figure", "save_png", "map_extent", "map_axes", "step_title",
           "finite", "friction_coefficient", "is_hysteresis"]

#: Resolution of the PNG figures (dots per inch).
DPI = 110
#: Line colours of the loading and unloading branches.
COLORS = {"loading": "#1f77b4", "unloading": "#d62728"}
#: Map colours: free, cohesive zone, contact.
CONTACT_COLORS = ("#e9ecef", "#f4a261", "#264653")  # free, cohesive zone, contact


def new_figure(w=5.6, h=4.4):
    """A constrained-layout Figure of ``w`` x ``h`` inches (no pyplot state: thread-safe).

    pyplot keeps global state; a bare Figure does not, so figures can be made in worker
    threads (sweeps) and are freed with their last reference.

    Parameters
    ----------
    w, h : float
        Width and height (inches).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(w, h), layout="constrained")
    return fig


def save_png(fig, path) -> Path:
    """Write ``fig`` to ``path`` as PNG, atomically, at :data:`DPI`.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : path-like
        The PNG file.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    return atomic_write_bytes(path, buf.getvalue())


def map_extent(ds, factor):
    """imshow extent of the grid of dataset ``ds`` (cell edges), in m / ``factor``.

    Parameters
    ----------
    ds : xarray.Dataset
        A fields dataset with cell-centre coordinates ``x``, ``y`` (m).
    factor : float
        Display unit in m (e.g. 1e-6 for um), from :func:`~tribobem.units.display_unit`.

    Returns
    -------
    list of float
        ``[left, right, bottom, top]`` in the display unit.
    """
    x, y = np.asarray(ds["x"].values), np.asarray(ds["y"].values)
    dx = float(x[1] - x[0]) if len(x) > 1 else 1.0
    dy = float(y[1] - y[0]) if len(y) > 1 else 1.0
    return [(x[0] - dx / 2) / factor, (x[-1] + dx / 2) / factor, (y[0] - dy / 2) / factor, (y[-1] + dy / 2) / factor]


def map_axes(ax, ds, lf, ll, active=None):
    """Labels, equal aspect, and a zoom on the active region when it is small.

    The zoom (a square window 1.5 x the region's larger extent plus two cells on each side,
    applied when it is under 60 % of the domain) keeps a small contact visible on a large
    domain.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The map's axes.
    ds : xarray.Dataset
        The fields dataset (coordinates ``x``, ``y`` in m).
    lf : float
        Display unit in m.
    ll : str
        Its label (e.g. ``"µm"``).
    active : ndarray of bool, optional
        The region to zoom on (grid-shaped); None: no zoom.
    """
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


def step_title(ds, step) -> str:
    """``label, F = ...`` of step ``step`` of dataset ``ds``.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields dataset (``label`` and ``normal_force`` per step).
    step : int
        Index along ``step``.

    Returns
    -------
    str
        The step's label and its normal force in a readable unit.
    """
    label = str(ds["label"].values[step])
    f = float(ds["normal_force"].values[step])
    return f"{label}, F = {format_quantity(f, 'force', 3)}"


def finite(v):
    """``v`` as a finite float, else None.

    Parameters
    ----------
    v : object
        A summary value (a number, None, a string ...), in its own units.

    Returns
    -------
    float or None
        The value in the same units; None for a non-number or a non-finite value.
    """
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if np.isfinite(f) else None


def friction_coefficient(summary: dict | None, ds=None):
    """mu from the summary (run-level, else the scenario echo), else the fields' attribute.

    Parameters
    ----------
    summary : dict or None
        The run summary (summary.json).
    ds : xarray.Dataset, optional
        The fields (fields.nc), whose ``friction_coefficient`` attribute is the last resort.

    Returns
    -------
    float or None
        The friction coefficient (dimensionless), None when unknown or not positive.
    """
    s = summary or {}
    mu = finite(s.get("friction_coefficient"))
    if mu is None:
        fr = (s.get("inputs") or {}).get("friction") or {}
        mu = finite(fr.get("coefficient")) if isinstance(fr, dict) else None
    if mu is None and ds is not None:
        mu = finite(ds.attrs.get("friction_coefficient"))
    return mu if mu is not None and mu > 0 else None


def is_hysteresis(summary: dict | None) -> bool:
    """True for a hysteresis run: ``kind`` says so, or the step rows carry a ``cycle``.

    Parameters
    ----------
    summary : dict or None
        The run summary (summary.json); None gives False.

    Returns
    -------
    bool
    """
    s = summary or {}
    if s.get("kind") == "hysteresis":
        return True
    return any(isinstance(r, dict) and "cycle" in r for r in s.get("steps") or [])
