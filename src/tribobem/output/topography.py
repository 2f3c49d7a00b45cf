"""Figures of a topography: the height map, the height distribution, the isotropic PSD and the
radial autocorrelation function, as PNG files, plus one self-contained HTML page that embeds
them (base64 PNGs, no external reference). ``tribobem info FILE --plot`` writes them.

Lengths are shown in SI-prefixed units chosen from the data (:func:`tribobem.units.display_unit`):
lateral lengths in the unit of the scan size, heights in the unit of the largest height, the
wavevector in rad per lateral unit and the PSD in (lateral unit)^4. Tick labels are
:data:`TICK_PT` points, axis labels :data:`LABEL_PT`.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

import numpy as np

from ..geometry import stats as _stats
from ..grid import Grid
from ..units import display_unit, format_quantity
from .atomic import atomic_write_text
from .plotting import new_figure, save_png

__all__ = ["TOPOGRAPHY_FIGURES", "TICK_PT", "LABEL_PT", "topography_figures", "write_topography_plots"]

#: Figure names and their PNG files, in the order of the HTML page.
TOPOGRAPHY_FIGURES = {
    "height_map": "height_map.png",
    "height_distribution": "height_distribution.png",
    "psd": "psd.png",
    "acf": "acf.png",
}
#: Name of the HTML page.
HTML_NAME = "topography.html"
#: Font size of tick labels (pt).
TICK_PT = 11
#: Font size of axis labels and titles (pt).
LABEL_PT = 12

_CAPTIONS = {
    "height_map": "Height map (after detrending), seen from above; x along the first array index.",
    "height_distribution": "Distribution of the heights (probability density), with the Gaussian of the same "
                           "rms height.",
    "psd": "Isotropic power spectral density C(q) (radial mean over the Fourier modes), up to the Nyquist "
           "wavevector pi/max(dx, dy).",
    "acf": "Radial height autocorrelation R(r)/R(0) up to half the scan; the correlation length is where it "
           "first falls below 10 %.",
}


def _style(ax, xlabel: str, ylabel: str, title: str | None = None) -> None:
    ax.set_xlabel(xlabel, fontsize=LABEL_PT)
    ax.set_ylabel(ylabel, fontsize=LABEL_PT)
    ax.tick_params(labelsize=TICK_PT)
    if title:
        ax.set_title(title, fontsize=LABEL_PT)


def topography_figures(heights, grid: Grid, title: str = "") -> dict:
    """The four figures of a topography, as matplotlib Figures (no pyplot state).

    Parameters
    ----------
    heights : array_like, shape (nx, ny)
        Heights (m), indexed ``[ix, iy]``, as detrended by the caller.
    grid : Grid
        Their grid (cell sizes in m).
    title : str
        Shown above the height map (e.g. the file name).

    Returns
    -------
    dict
        ``{name: matplotlib.figure.Figure}`` for the names of :data:`TOPOGRAPHY_FIGURES`.
    """
    h = np.asarray(heights, dtype=float)
    d = h - h.mean()
    lf, ll = display_unit(max(grid.lx, grid.ly), "length")
    # the height unit from the bulk of the heights, not from an outlier (a pit, a grain)
    hf, hl = display_unit(np.percentile(np.abs(d), 99.9), "length")
    figs = {}

    # height map: x horizontal, y up (the array is [ix, iy], so imshow gets its transpose)
    # figure sized to the map's aspect (plus room for labels and the colour bar), so that the
    # colour bar spans the map's height
    aspect = grid.ly / grid.lx
    wmap = 4.6 if aspect <= 1 else max(1.5, 4.6 / aspect)
    fig = new_figure(wmap + 2.3, max(2.5, wmap * aspect) + 1.0)
    ax = fig.add_subplot()
    extent = [-grid.lx / 2 / lf, grid.lx / 2 / lf, -grid.ly / 2 / lf, grid.ly / 2 / lf]
    # colours over the central 99.9 % of the heights, so that a pit or a grain does not wash
    # out the rest of the map (the colour bar's arrows mark the clipped ends)
    vlo, vhi = (float(v) for v in np.percentile(d / hf, [0.05, 99.95]))
    ends = {(False, False): "neither", (True, False): "min", (False, True): "max", (True, True): "both"}
    extend = ends[(bool(d.min() / hf < vlo), bool(d.max() / hf > vhi))]
    im = ax.imshow(d.T / hf, origin="lower", extent=extent, cmap="viridis", interpolation="nearest",
                   vmin=vlo if vhi > vlo else None, vmax=vhi if vhi > vlo else None)
    ax.set_aspect("equal")
    _style(ax, f"x ({ll})", f"y ({ll})", title or "height map")
    cb = fig.colorbar(im, ax=ax, extend=extend)
    cb.set_label(f"height ({hl})", fontsize=LABEL_PT)
    cb.ax.tick_params(labelsize=TICK_PT)
    figs["height_map"] = fig

    # height distribution
    fig = new_figure(5.6, 4.4)
    ax = fig.add_subplot()
    z = d.ravel() / hf
    rms = float(np.sqrt(np.mean(z**2)))
    # A few outliers (a pit, a dust grain) would squeeze the distribution into a few bins of a
    # wide axis: bin and show the central 99.9 % (density still per all points) and say where
    # the extremes are.
    lo, hi = (float(v) for v in np.percentile(z, [0.05, 99.95]))
    pad = 0.1 * (hi - lo)
    clipped = bool(z.min() < lo - pad or z.max() > hi + pad)
    xlo, xhi = (lo - pad, hi + pad) if clipped else (float(z.min()), float(z.max()))
    if not xhi > xlo:  # a flat surface
        xlo, xhi = xlo - 1.0, xhi + 1.0
    nb = int(min(200, max(20, math.sqrt(z.size) / 2)))
    edges = np.linspace(xlo, xhi, nb + 1)
    counts, _ = np.histogram(z, edges)
    dens = counts / (z.size * (edges[1] - edges[0]))
    ax.stairs(dens, edges, fill=True, color="#4c72b0", alpha=0.75, label="heights")
    if rms > 0:
        zz = np.linspace(xlo, xhi, 400)
        ax.plot(zz, np.exp(-0.5 * (zz / rms) ** 2) / (rms * math.sqrt(2 * math.pi)), "k--", lw=1.4,
                label=f"Gaussian, rms {rms:.4g} {hl}")
    if clipped:
        ax.set_xlim(xlo, xhi)
        ax.plot([], [], " ", label=f"central 99.9 % shown;\nmin {z.min():.4g} {hl}, max {z.max():.4g} {hl}")
    peak = max(float(dens.max()), 1.0 / (rms * math.sqrt(2 * math.pi)) if rms > 0 else 0.0)
    ax.set_ylim(0.0, 1.45 * peak if peak > 0 else 1.0)  # head room for the legend
    ax.legend(fontsize=TICK_PT - 1, loc="upper right")
    _style(ax, f"height ({hl})", f"probability density (1/{hl})", "height distribution")
    figs["height_distribution"] = fig

    # isotropic PSD, log-log, up to the Nyquist circle (beyond it only the spectrum's corners
    # fill an annulus: see tribobem.geometry.stats.psd)
    fig = new_figure(5.6, 4.4)
    ax = fig.add_subplot()
    q, C = _stats.psd(d, grid)
    qny = math.pi / max(grid.dx, grid.dy)
    keep = (q <= qny * (1 + 1e-12)) & (C > 0)
    ax.loglog(q[keep] * lf, C[keep] / lf**4, "-", color="#4c72b0", lw=1.4)
    _style(ax, f"wavevector q (rad/{ll})", f"PSD C(q) ({ll}\u2074)", "isotropic power spectral density")
    ax.grid(True, which="major", alpha=0.3)
    figs["psd"] = fig

    # radial ACF, normalised, with the correlation length (10 % level)
    fig = new_figure(5.6, 4.4)
    ax = fig.add_subplot()
    r, R = _stats.acf(d, grid)
    rho = R / R[0] if R[0] > 0 else np.zeros_like(R)
    ax.plot(r / lf, rho, "-", color="#4c72b0", lw=1.4, label="R(r)/R(0)")
    ax.axhline(0.1, color="0.4", ls=":", lw=1.2, label="10 % level")
    ax.axhline(0.0, color="0.7", lw=0.8)
    corr = _stats.correlation_length(d, grid)
    if math.isfinite(corr):
        ax.axvline(corr / lf, color="#d62728", ls="--", lw=1.2,
                   label=f"correlation length {format_quantity(corr, 'length')}")
    ax.legend(fontsize=TICK_PT, loc="upper right")
    _style(ax, f"lag r ({ll})", "normalised autocorrelation", "radial height autocorrelation")
    figs["acf"] = fig
    return figs


def _stats_rows(h, grid: Grid) -> list[tuple[str, str]]:
    s = _stats.summary(h, grid)
    corr = s["correlation_length"]
    return [
        ("grid", f"{grid.nx} x {grid.ny} points"),
        ("physical size", f"{format_quantity(grid.lx, 'length')} x {format_quantity(grid.ly, 'length')}"),
        ("pixel size", f"{format_quantity(grid.dx, 'length')} x {format_quantity(grid.dy, 'length')}"),
        ("rms height", format_quantity(s["rms_height"], "length")),
        ("rms slope", f"{s['rms_slope']:.4g}"),
        ("skewness", f"{s['skewness']:.4g}"),
        ("kurtosis", f"{s['kurtosis']:.4g}"),
        ("correlation length (ACF 10 %)", format_quantity(corr, "length") if math.isfinite(corr) else "none within "
                                                                                               "half the scan"),
        ("peak to valley", format_quantity(s["peak_to_valley"], "length")),
    ]


def write_topography_plots(heights, grid: Grid, outdir, title: str = "", detrend: str = "") -> dict:
    """Write the four PNGs of :func:`topography_figures` and an HTML page embedding them.

    Parameters
    ----------
    heights : array_like, shape (nx, ny)
        Heights (m), as detrended by the caller.
    grid : Grid
        Their grid.
    outdir : path-like
        Folder (created if missing); files of the same names are replaced.
    title : str
        Title of the figures and of the page (e.g. the file name).
    detrend : str
        The detrending applied, shown on the page.

    Returns
    -------
    dict
        ``{name: pathlib.Path}``: the names of :data:`TOPOGRAPHY_FIGURES` and ``"html"``.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    figs = topography_figures(heights, grid, title)
    paths = {}
    for name, fig in figs.items():
        paths[name] = save_png(fig, outdir / TOPOGRAPHY_FIGURES[name])
    e = html.escape
    head = title or "topography"
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{e(head)}</title>",
        "<style>body{font-family:sans-serif;max-width:1200px;margin:1em auto;padding:0 1em}"
        "table{border-collapse:collapse}td{padding:2px 10px;border-bottom:1px solid #ddd}"
        "figure{display:inline-block;margin:0.5em;vertical-align:top;max-width:560px}"
        "img{max-width:100%}figcaption{font-size:0.9em;color:#444}</style></head><body>",
        f"<h1>{e(head)}</h1>",
    ]
    rows = ([("detrend", detrend)] if detrend else []) + _stats_rows(np.asarray(heights, dtype=float), grid)
    parts.append("<table>" + "".join(f"<tr><td>{e(a)}</td><td>{e(b)}</td></tr>" for a, b in rows) + "</table>")
    for name in TOPOGRAPHY_FIGURES:
        data = base64.b64encode(paths[name].read_bytes()).decode("ascii")
        parts.append(f"<figure><img alt='{e(name)}' src='data:image/png;base64,{data}'>"
                     f"<figcaption>{e(_CAPTIONS[name])}</figcaption></figure>")
    parts.append("</body></html>\n")
    paths["html"] = atomic_write_text(outdir / HTML_NAME, "".join(parts))
    return paths
