"""Paper A section 6 study: geometry, a tiny pull-off, and the fit of Eq. 35."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from studies.bisinusoidal import (
    PAPER_A_TABLE1,
    bisinusoidal_cell,
    bisinusoidal_gap,
    bisinusoidal_pull_off,
    fit_pull_off,
    pull_off_point,
)
from tribobem import Grid
from tribobem.errors import InputError


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


ROOT = Path(__file__).resolve().parents[2]
QUICK = ROOT / "examples" / "studies" / "bisinusoidal_quick.toml"
PUBLISHED = [ROOT / "docs" / "data" / "bisinusoidal_pulloff.csv", ROOT / "docs" / "figures" / "bisinusoidal_pulloff.png"]


@pytest.fixture(scope="module")
def quick_sweep(tmp_path_factory):
    """The 4-point quick sweep (32^2), run once: (folder, SweepResult)."""
    from tribobem.sweep import run_sweep

    out = tmp_path_factory.mktemp("bisinusoidal_quick")
    return out, run_sweep(QUICK, out, scheduler="synchronous", progress=False)


def test_quick_example_sweep_runs(quick_sweep):
    _, res = quick_sweep
    assert res.complete and res.n_points == 4
    ds = res.dataset
    assert ds["pull_off_force"].dims == ("dgamma", "k") and (ds["pull_off_force"].values < 0).all()
    assert ds.coords["dgamma"].values.tolist() == pytest.approx([0.03, 0.07])


def _fit_script():
    import importlib.util

    spec = importlib.util.spec_from_file_location("example_bisinusoidal_fit", ROOT / "examples" / "studies" /
                                                  "bisinusoidal_fit.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _stamps():
    return [p.stat().st_mtime_ns if p.exists() else None for p in PUBLISHED]


def test_fit_script_on_the_quick_sweep_writes_to_out_only(quick_sweep, tmp_path, capsys):
    """Item 4: the fit works on the 4-point sweep (R_c and E* fixed in its base), writes into
    --out, and leaves docs/ alone; --publish of a partial sweep is refused."""
    import json

    import pandas as pd

    folder, res = quick_sweep
    before = _stamps()
    mod = _fit_script()
    out = tmp_path / "fit"
    assert mod.main([str(folder), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "R_c = 0.0002" in text and "E_star = 1e+11" in text       # from sweep.json's base
    table = pd.read_csv(out / "bisinusoidal_pulloff.csv")
    assert len(table) == 4 and set(table["R_c"]) == {200e-6} and set(table["E_star"]) == {100e9}
    F = res.dataset["pull_off_force"].values.ravel()
    assert sorted(table["pull_off_force"]) == pytest.approx(sorted(F), rel=1e-9)
    rec = json.loads((out / "bisinusoidal_fit.json").read_text())
    ref = fit_pull_off(table)
    assert rec["n_fitted"] == 4 and rec["beta_determined"]   # dgamma varies: E* R_c / dgamma takes 2 values
    # the compact table keeps 10 significant digits
    assert (rec["a0"], rec["b0"], rec["beta"]) == pytest.approx((ref.a0, ref.b0, ref.beta), rel=1e-6)
    # F / (R_c dgamma) at 32^2 lies between two JKR and two DMT crests times the coarse-grid excess
    assert 2 * 1.5 * math.pi < rec["a0"] < 3 * 2 * math.pi
    assert (out / "bisinusoidal_pulloff.png").stat().st_size > 10_000
    assert _stamps() == before
    assert mod.main([str(folder), "--out", str(tmp_path / "pub"), "--publish"]) == 2
    assert "not all 625 cases" in capsys.readouterr().err
    assert (tmp_path / "pub" / "bisinusoidal_fit.json").is_file() and _stamps() == before


def test_fit_script_on_a_partial_sweep_says_what_it_needs(quick_sweep, tmp_path, capsys):
    import shutil

    import pandas as pd

    folder, _ = quick_sweep
    part = tmp_path / "part"
    shutil.copytree(folder, part)
    csv_path = part / "results.csv"
    rows = pd.read_csv(csv_path, dtype=str, keep_default_na=False)
    rows.loc[3, "status"] = "missing"                        # 3 of 4 finished: still a fit
    rows.to_csv(csv_path, index=False)
    mod = _fit_script()
    assert mod.main([str(part), "--out", str(tmp_path / "f3")]) == 0
    assert "partial sweep: 3 of 4 points finished" in capsys.readouterr().out
    rows.loc[2, "status"] = "failed"                          # 2 of 4: too few for 3 constants
    rows.to_csv(csv_path, index=False)
    assert mod.main([str(part), "--out", str(tmp_path / "f2")]) == 2
    err = capsys.readouterr().err
    assert "2 finished, converged point(s) of 4" in err and "at least 3" in err
    assert not (tmp_path / "f2").exists()
    rows.loc[2, "status"] = "ok"
    rows.loc[[0, 2], "k"] = rows.loc[1, "k"]                  # 3 points with one k: no exponent b
    rows.to_csv(csv_path, index=False)
    assert mod.main([str(part), "--out", str(tmp_path / "fk")]) == 2
    assert "two wavelength ratios" in capsys.readouterr().err
    (part / "sweep.json").unlink()                             # R_c and E* nowhere
    assert mod.main([str(part), "--out", str(tmp_path / "fb")]) == 2
    assert "R_c, E_star" in capsys.readouterr().err
