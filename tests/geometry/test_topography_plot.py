"""Figures of a topography (tribobem.output.topography): four PNGs and a self-contained HTML page."""

import base64
import re

import numpy as np
import pytest

from tribobem.geometry import gaussian_surface
from tribobem.grid import Grid
from tribobem.output.topography import (
    LABEL_PT,
    TICK_PT,
    TOPOGRAPHY_FIGURES,
    topography_figures,
    write_topography_plots,
)

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def surface():
    g = Grid(64, 48, 4e-6, 3e-6)   # a 4 um x 3 um scan
    h = gaussian_surface(g, 20e-9, 0.4e-6, seed=2)
    return h, g


def test_figures_readable_with_si_prefixed_units(surface):
    h, g = surface
    figs = topography_figures(h, g, "scan.di")
    assert set(figs) == set(TOPOGRAPHY_FIGURES)
    assert TICK_PT >= 10 and LABEL_PT >= 10
    labels = {}
    for name, fig in figs.items():
        for ax in fig.axes:
            for t in ax.get_xticklabels() + ax.get_yticklabels():
                assert t.get_fontsize() >= 10, (name, t.get_text())
            assert ax.xaxis.label.get_fontsize() >= 10 and ax.yaxis.label.get_fontsize() >= 10
        ax = fig.axes[0]
        labels[name] = (ax.get_xlabel(), ax.get_ylabel(), ax.get_xscale(), ax.get_yscale())
    # lateral lengths in um (the scan is 4 um), heights in nm (rms 20 nm)
    assert labels["height_map"][:2] == ("x (\u00b5m)", "y (\u00b5m)")
    assert figs["height_map"].axes[1].get_ylabel() == "height (nm)"        # the colour bar
    assert labels["height_distribution"][0] == "height (nm)"
    assert labels["psd"] == ("wavevector q (rad/\u00b5m)", "PSD C(q) (\u00b5m\u2074)", "log", "log")
    assert labels["acf"][0] == "lag r (\u00b5m)"
    # the plotted data are in those units: the ACF starts at 1 and spans half the shorter side
    (line,) = [ln for ln in figs["acf"].axes[0].get_lines() if ln.get_label() == "R(r)/R(0)"]
    x, y = line.get_data()
    assert y[0] == pytest.approx(1.0) and x[-1] == pytest.approx(1.5, rel=0.02)
    # the height histogram is a density (per nm): it integrates to 1 (no point outside the view here)
    (stairs,) = figs["height_distribution"].axes[0].patches
    dens, edges = stairs.get_data()[:2]
    assert np.sum(dens * np.diff(edges)) == pytest.approx(1.0, rel=1e-12)


def test_write_plots_png_and_self_contained_html(surface, tmp_path):
    h, g = surface
    paths = write_topography_plots(h, g, tmp_path / "plots", title="scan.di", detrend="height")
    assert set(paths) == set(TOPOGRAPHY_FIGURES) | {"html"}
    for name, file in TOPOGRAPHY_FIGURES.items():
        p = paths[name]
        assert p == tmp_path / "plots" / file and p.is_file()
        data = p.read_bytes()
        assert data[:8] == PNG and len(data) > 10_000, (name, len(data))
    page = paths["html"].read_text(encoding="utf-8")
    imgs = re.findall(r"<img [^>]*src='data:image/png;base64,([A-Za-z0-9+/=]+)'", page)
    assert len(imgs) == 4
    # each embedded image is the PNG written beside it, byte for byte
    assert sorted(base64.b64decode(i) for i in imgs) == sorted(paths[n].read_bytes() for n in TOPOGRAPHY_FIGURES)
    assert "http://" not in page and "https://" not in page and "<script" not in page
    assert "scan.di" in page and "height" in page and "correlation length" in page


def test_outliers_do_not_wash_out_the_map(surface):
    """One deep pit: the colour scale and the histogram keep the central 99.9 % of the heights."""
    h, g = surface
    h = h.copy()
    h[5, 5] = -2e-6   # 100 rms deep
    figs = topography_figures(h, g)
    im = figs["height_map"].axes[0].images[0]
    lo, hi = im.get_clim()
    assert -200 < lo < -40 and 40 < hi < 200   # nm, not -2000
    xlo, xhi = figs["height_distribution"].axes[0].get_xlim()
    assert xlo > -200
    # the extremes are named (the pit, about -2000 nm about the mean)
    texts = " ".join(t.get_text() for t in figs["height_distribution"].axes[0].get_legend().get_texts())
    assert re.search(r"min -(1999|2000) nm", texts), texts
