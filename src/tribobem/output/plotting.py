"""Plotting helpers shared by the figure modules (:mod:`.figures`, :mod:`.capillary`,
:mod:`.humid`): a matplotlib Figure without pyplot state, the atomic PNG write, the axes of a map
in the grid's coordinates (m, shown in the unit the caller chose), and the summary readings the
friction figures share (a finite number, mu, whether a run is a hysteresis run).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from ..units import format_value
from .atomic import atomic_write_bytes

__all__ = ["DPI", "COLORS", "MIN_FONT", "save_png", "legible",
           "spread_labels", "step_title", "profile_row", "finite",
           "friction_coefficient"]

#: Resolution of the PNG figures (dots per inch).
DPI = 110
#: Line colours of the loading and unloading branches.
COLORS = {"loading": "#1f77b4", "unloading": "#d62728"}
#: Map colours: free, cohesive zone, contact.
CONTACT_COLORS = ("#e9ecef", "#f4a261", "#264653")  # free, cohesive zone, contact
#: Smallest font size (pt) of any text of a figure (tick labels, legends, titles, annotations).
#: The report shows a 6.4 in figure about 520 px wide (0.74 of its 110 dpi pixels): 10 pt reads as
#: about 11 px there, 8 pt as 9 px, too small to read.
MIN_FONT = 10.0
#: Smallest font size (pt) inside an inset axes (a zoom drawn over a quarter of its parent).
MIN_INSET_FONT = 8.0


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
    legible(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    return atomic_write_bytes(path, buf.getvalue())


def _tick_size(axis) -> float:
    """Font size (pt) of an axis' tick labels (what new ticks will get)."""
    ticks = axis.get_major_ticks()
    return float(ticks[0].label1.get_fontsize()) if ticks else 0.0


def legible(fig, min_size: float = MIN_FONT, min_inset: float = MIN_INSET_FONT):
    """Raise every text of ``fig`` to at least ``min_size`` pt (inset axes: ``min_inset``).

    Every figure passes through here (:func:`save_png`), so no figure leaves with tick labels,
    legends, titles or annotations smaller than the report can show, whatever size its code
    asked for; larger sizes are kept.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (changed in place).
    min_size, min_inset : float
        Smallest font sizes (pt) outside and inside inset axes.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``.
    """
    from matplotlib.text import Text

    def walk(axes, inset):
        for ax in axes:
            yield ax, inset
            # inset axes (Axes.inset_axes) and secondary axes are children of their parent;
            # a secondary axis is a full-size axis, an inset a zoom
            for child in getattr(ax, "child_axes", []):
                yield from walk([child], inset or type(child).__name__ != "SecondaryAxis")

    floors = {}
    for ax, inset in walk(fig.axes, False):
        floor = min_inset if inset else min_size
        floors[id(ax)] = floor
        for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y")):
            # tick_params, not only the Text objects: ticks are re-made at draw from these settings
            for which in ("major", "minor"):
                ax.tick_params(axis=name, which=which, labelsize=max(floor, _tick_size(axis)))
    # every other text (titles, axis labels, legends, annotations, suptitle), by its axes' floor;
    # a quiver key's label is not among its axes' children
    texts = list(fig.findobj(Text, include_self=False))
    for ax, _ in walk(fig.axes, False):
        texts += [c.text for c in ax.get_children() if type(c).__name__ == "QuiverKey"]
    for t in texts:
        floor = floors.get(id(t.axes), min_size) if t.axes is not None else min_size
        if t.get_text() and t.get_fontsize() < floor:
            t.set_fontsize(floor)
    return fig


def keep_inside(ax, texts, pad: float = 2.0) -> None:
    """Shift annotations (offset in points) so that each lies inside ``ax``'s frame.

    A label placed beside a point near the frame (a turning point at the end of the loop's
    range) otherwise runs over the frame into the tick labels.  The texts are taken out of the
    layout (constrained layout would shrink the axes to make room for them, then the frame
    moves); the figure is drawn once here to measure them, at its final font sizes
    (:func:`legible`).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes the annotations belong to.
    texts : list of matplotlib.text.Annotation
        Annotations with ``textcoords="offset points"``.
    pad : float
        Distance (pt) kept from the frame.
    """
    texts = [t for t in texts if t is not None]
    if not texts:
        return
    fig = ax.figure
    legible(fig)
    for t in texts:
        t.set_in_layout(False)
    fig.draw_without_rendering()
    box = ax.get_window_extent()
    px = fig.dpi / 72.0  # pixels per point
    for t in texts:
        bb = t.get_window_extent()
        bbox = t.get_bbox_patch()
        if bbox is not None:
            bb = bbox.get_window_extent()
        dx = max(0.0, box.x0 + pad * px - bb.x0) - max(0.0, bb.x1 - (box.x1 - pad * px))
        dy = max(0.0, box.y0 + pad * px - bb.y0) - max(0.0, bb.y1 - (box.y1 - pad * px))
        if dx or dy:
            ox, oy = t.xyann
            t.xyann = (ox + dx / px, oy + dy / px)


def spread_labels(ax, texts, pad: float = 1.0, max_rounds: int = 50) -> None:
    """Shift annotations (offset in points) up until no two overlap, and keep them inside ``ax``.

    Labels of points that lie close together (a cluster of design points) are drawn over each
    other otherwise.  Each label, taken bottom to top, is moved up just past any label below it
    that it overlaps; then :func:`keep_inside` keeps them in the frame.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes of the annotations.
    texts : list of matplotlib.text.Annotation
        Annotations with ``textcoords="offset points"``.
    pad : float
        Gap (pt) kept between two labels.
    max_rounds : int
        Passes at most (a label moved can meet another).
    """
    texts = [t for t in texts if t is not None]
    if len(texts) < 2:
        keep_inside(ax, texts)
        return
    fig = ax.figure
    legible(fig)
    for t in texts:
        t.set_in_layout(False)
    px = fig.dpi / 72.0
    for _ in range(max_rounds):
        fig.draw_without_rendering()
        boxes = [t.get_window_extent() for t in texts]
        order = sorted(range(len(texts)), key=lambda k: (boxes[k].y0, boxes[k].x0))
        moved = False
        for n, k in enumerate(order):
            for j in order[:n]:
                a, b = boxes[k], boxes[j]
                if a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 + pad * px and b.y0 < a.y1:
                    dy = b.y1 + pad * px - a.y0
                    ox, oy = texts[k].xyann
                    texts[k].xyann = (ox, oy + dy / px)
                    boxes[k] = boxes[k].translated(0, dy)
                    moved = True
        if not moved:
            break
    keep_inside(ax, texts)


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

    The force is rounded before its unit is chosen (``1 µN``, not ``1e+03 nN``) and prints as 0
    when it is solver noise (:func:`~tribobem.units.format_value`) against the run's force scale:
    the largest |normal force| of the dataset's steps and the step's repulsive force (the sum of
    its compressive pressures x cell area), so that a state solved at zero external load reads
    ``F = 0 N``.

    Parameters
    ----------
    ds : xarray.Dataset
        The fields dataset (``label`` and ``normal_force`` (N) per step, ``pressure`` (Pa)).
    step : int
        Index along ``step``.

    Returns
    -------
    str
        The step's label and its normal force in a readable unit.
    """
    label = str(ds["label"].values[step])
    f = float(ds["normal_force"].values[step])
    scale = [float(np.nanmax(np.abs(np.asarray(ds["normal_force"].values, dtype=float))))]
    if "pressure" in ds and "x" in ds and "y" in ds and len(ds["x"]) > 1 and len(ds["y"]) > 1:
        cell = abs(float(ds["x"].values[1] - ds["x"].values[0]) * float(ds["y"].values[1] - ds["y"].values[0]))
        p = np.asarray(ds["pressure"].values[step], dtype=float)
        scale.append(float(np.nansum(np.clip(p, 0.0, None))) * cell)
    return f"{label}, F = {format_value(f, 'force', 3, scale=scale)}"


def profile_row(pressure, y) -> tuple[int, str]:
    """The row (index along y) a profile of a state is drawn along, and what it is.

    The row through the largest compressive pressure (of several equal maxima, the one nearest
    y = 0), else through the largest |pressure| (a state held by adhesive stresses only), else
    the centre line (no pressure: the bodies apart).  A centre line misses the contact of a
    rough spot, whose patches lie anywhere.

    Parameters
    ----------
    pressure : array_like
        The pressure map (Pa, shape (nx, ny), > 0 compressive).
    y : array_like
        Cell-centre y coordinates (m, length ny).

    Returns
    -------
    (int, str)
        The row index and a short description ("maximum pressure", "maximum |pressure|",
        "centre line").
    """
    p = np.asarray(pressure, dtype=float)
    y = np.asarray(y, dtype=float)
    p = np.where(np.isfinite(p), p, 0.0)
    for what, v in (("maximum pressure", p), ("maximum |pressure|", np.abs(p))):
        top = float(v.max()) if v.size else 0.0
        if top > 0.0:
            rows = np.nonzero((v >= top * (1.0 - 1e-12)).any(axis=0))[0]
            return int(rows[np.argmin(np.abs(y[rows]))]), what
    return int(np.argmin(np.abs(y))), "centre line"


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
