"""Paper A section 6 study: geometry, a tiny pull-off, and the fit of Eq. 35."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tribobem import Grid
from tribobem.errors import InputError
from tribobem.studies.bisinusoidal import (
    PAPER_A_TABLE1,
    bisinusoidal_cell,
    bisinusoidal_gap,
    bisinusoidal_pull_off,
    fit_pull_off,
    pull_off_point,
)


def test_cell_gives_the_crest_radius_and_ratio():
    S = 5e-9
    for R_c, k in ((100e-6, 0.1), (500e-6, 0.9), (300e-6, 1.0)):
        lx, ly = bisinusoidal_cell(R_c, k, S)
        Rx, Ry = lx**2 / (4 * math.pi**2 * S), ly**2 / (4 * math.pi**2 * S)  # Paper A Eq. 33
        assert math.sqrt(Rx * Ry) == pytest.approx(R_c, rel=1e-12) and ly / lx == pytest.approx(k)
    with pytest.raises(InputError, match="k"):
        bisinusoidal_cell(1e-4, 1.5)


def test_gap_has_two_crests_on_nodes_with_the_right_curvature():
    S, R_c, k = 5e-9, 200e-6, 0.5
    lx, ly = bisinusoidal_cell(R_c, k, S)
    g = Grid(64, 32, lx, ly, periodic=True)
    h = bisinusoidal_gap(g, S)
    assert h[0, 0] == 0.0 and h[32, 16] == pytest.approx(0.0, abs=1e-24) and h.max() == pytest.approx(2 * S)
    assert np.count_nonzero(h < 1e-6 * S) == 2
    # second difference at the crest: 1 / Rx along x
    curv_x = (h[1, 0] - 2 * h[0, 0] + h[-1, 0]) / g.dx**2
    assert curv_x == pytest.approx(4 * math.pi**2 * S / lx**2, rel=2e-3)


def test_tiny_pull_off_is_between_two_jkr_and_three_dmt_crests():
    d = pull_off_point(0.05, 200e-6, 100e9, 0.5, n=32, n_steps=20, refine=4)
    ratio = d["normalised_pull_off"]
    # two crests per cell; a coarse grid overestimates (cohesive-zone pinning), so allow some room
    assert 2 * 1.5 * math.pi < ratio < 3 * 2 * math.pi
    assert d["pull_off_force"] < 0 and d["converged"] and 0.1 < d["maugis"] < 5
    assert bisinusoidal_pull_off(0.05, 200e-6, 100e9, 0.5, n=32, n_steps=20, refine=4) == pytest.approx(
        -d["pull_off_force"])
    with pytest.raises(InputError, match="even"):
        bisinusoidal_pull_off(0.05, 200e-6, 100e9, 0.5, n=33)


def test_fit_recovers_known_constants_and_beta0_fit():
    rng = np.random.default_rng(0)
    grid = np.array(np.meshgrid(*PAPER_A_TABLE1.values(), indexing="ij")).reshape(4, -1)
    dg, R, E, k = grid
    a, b, beta = 3.0e-2, 0.05, 0.1
    F = a * E**beta * R ** (1 + beta) * dg ** (1 - beta) * k**b
    fit = fit_pull_off({"dgamma": dg, "R_c": R, "E_star": E, "k": k, "F": F})
    assert tuple(fit) == pytest.approx((a, b, beta), rel=1e-8)
    assert fit.r2 == pytest.approx(1.0) and fit.rms_rel < 1e-10 and fit.n == 625
    F0 = 10.39 * R * dg * k**0.041 * np.exp(rng.normal(0, 0.01, R.size))  # Paper A Table 2 + 1% noise
    fit0 = fit_pull_off({"dgamma": dg, "R_c": R, "E_star": E, "k": k, "pull_off_force": -F0})
    assert abs(fit0.beta) < 0.01 and fit0.a0 == pytest.approx(10.39, rel=0.01) and fit0.b0 == pytest.approx(0.041, abs=0.005)
    assert fit0.r2_beta0 > 0.99 and fit0.rms_rel_beta0 < 0.02
    assert fit0.predict(dg, R, E, k, beta0=True) == pytest.approx(fit0.a0 * R * dg * k**fit0.b0)


def test_quick_example_sweep_runs(tmp_path):
    from pathlib import Path

    from tribobem.sweep import run_sweep

    toml = Path(__file__).resolve().parents[1] / "examples" / "studies" / "bisinusoidal_quick.toml"
    res = run_sweep(toml, tmp_path, scheduler="synchronous", progress=False)
    assert res.complete and res.n_points == 4
    ds = res.dataset
    assert ds["pull_off_force"].dims == ("dgamma", "k") and (ds["pull_off_force"].values < 0).all()
    assert ds.coords["dgamma"].values.tolist() == pytest.approx([0.03, 0.07])
