"""The window-versus-whole study (studies.burl_windows) in its quick mode: a 2 um burl on 96^2
cells.  It runs, resumes from its records without recomputing a point, its windows are the
whole map's cells, and its table carries one row per window size, position and boundary."""

from __future__ import annotations

import math

import numpy as np
import pytest

from studies import burl_windows as bw


def test_window_cells_sit_on_the_burl():
    cfg = bw.config()
    n, dx, b = cfg["n"], cfg["dx"], cfg["radius"]
    for size in cfg["windows"]:
        for coarse in (False, True):
            k = cfg["coarse"] if coarse else 1
            ix0, iy0, m = bw.window_cells(cfg, size, "centre", coarse)
            assert m % 2 == 0 and abs(m * dx * k - size) <= dx * k
            assert ix0 + m // 2 == n // (2 * k) and iy0 + m // 2 == n // (2 * k)  # centred on the axis
            ix0, iy0, m = bw.window_cells(cfg, size, "edge", coarse)
            # the outer side on the rim r = b, the window inside the top
            assert (ix0 + m - n // (2 * k)) * dx * k == pytest.approx(b, abs=dx * k)
    with pytest.raises(ValueError):
        bw.window_cells(cfg, 1e-6, "corner")


def test_coarse_map_is_the_block_mean():
    h = np.arange(16.0).reshape(4, 4)
    c = bw.coarsen(h, 2)
    assert c.shape == (2, 2) and c[0, 0] == pytest.approx(np.mean([0, 1, 4, 5]))


def test_full_study_is_the_documented_one(tmp_path):
    from tribobem.scenario.schema import parse_scenario
    from tribobem.sweep import load_sweep

    cfg = bw.config()
    paths = {"fine": str(tmp_path / "f.npy"), "coarse": str(tmp_path / "c.npy")}
    np.save(paths["fine"], np.zeros((4, 4)))  # parsing reads no heights
    np.save(paths["coarse"], np.zeros((4, 4)))
    spec = load_sweep(bw.whole_spec(paths, cfg))
    kinds = {}
    for _, o in spec.tasks():
        sc = parse_scenario(spec.scenario_for(o))
        kinds[o["name"]] = sc
    # the whole burl's capillary pull-off runs with NormCG (Polonsky-Keer does not finish on the
    # full map: module docstring); every other point with the default solver
    assert set(kinds) == {"whole_fine/normal", "whole/normal", "whole/pulloff", "whole/friction", "whole/capillary"}
    assert kinds["whole/capillary"].solver.method == "normcg" and kinds["whole/capillary"].humidity is not None
    assert all(kinds[k].solver.method == "auto" for k in kinds if k != "whole/capillary")
    sc = kinds["whole_fine/normal"]
    assert sc.grid.shape == (768, 768) and sc.grid.lengths[0] == pytest.approx(768 * 30e-9) and not sc.grid.periodic
    assert sc.body1.E == 130e9 and sc.body1.nu == 0.28 and sc.body2.rigid
    assert sc.body2.shape.kind == "burl" and sc.body2.shape.radius == pytest.approx(10e-6)
    assert sc.load.force == pytest.approx(50e6 * math.pi * 1e-10, rel=1e-5)
    assert kinds["whole/friction"].grid.shape == (384, 384)
    assert cfg["whole_capillary"] and cfg["capillary_windows"] == (2e-6, 5e-6, 10e-6)
    assert sc.adhesion.work_of_adhesion == 0.05 and sc.adhesion.z0 == pytest.approx(0.3e-9)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("burl_windows")
    ws, wsp, res = bw.run_study(out, quick=True)
    assert wsp is not None
    for r in res:
        assert r.n_ok == r.n_points and r.n_run == r.n_points, r.failed
    return out, ws, wsp, res


def test_quick_study_resumes_without_recomputing(quick):
    out, ws, wsp, res = quick
    stamps = {p: p.stat().st_mtime_ns for d in ("whole", "windows") for p in (out / d / "points").glob("*.json")}
    _, _, again = bw.run_study(out, quick=True)
    for r, r0 in zip(again, res):
        assert (r.n_done_before, r.n_run, r.n_ok) == (r0.n_points, 0, r0.n_points)
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps


def test_windows_are_crops_of_the_whole_map(quick):
    import xarray as xr

    out, ws, wsp, _ = quick
    cfg = bw.config(quick=True)
    runs = bw._run_dirs(wsp, out / "windows")
    h = np.load(out / "surface.npy")
    for pos in bw.POSITIONS:
        ix0, iy0, m = bw.window_cells(cfg, 1.6e-6, pos)
        f = bw._fields_of(runs, f"w1.6um-{pos}-free-fine/normal")
        with xr.open_dataset(f) as ds:
            w = ds["roughness_body1"].values
        crop = h[ix0:ix0 + m, iy0:iy0 + m]
        # the same cells (the build may shift the heights by a constant)
        assert w.shape == crop.shape
        assert np.allclose(w - w.mean(), crop - crop.mean(), rtol=0, atol=1e-15)


def test_quick_table_one_row_per_window(quick, tmp_path):
    out, *_ = quick
    table, whole = bw.gather(out, quick=True)
    cfg = bw.config(quick=True)
    assert len(table) == len(cfg["windows"]) * len(bw.POSITIONS) * len(bw.BOUNDARIES)
    assert set(zip(table["size"], table["position"], table["boundary"])) == {
        (s, p, b) for s in cfg["windows"] for p in bw.POSITIONS for b in bw.BOUNDARIES}
    for col in ("nominal_pressure", "contact_fraction", "contact_fraction_fine", "mean_gap", "mean_gap_fine",
                "pull_off_stress", "friction_coefficient_static", "presliding_displacement",
                "whole_contact_fraction", "err_contact_fraction", "err_friction_coefficient_static"):
        assert np.isfinite(table[col].to_numpy(float)).all(), col
    # the capillary pull-off only where asked
    cap = table["capillary_pull_off_stress"].to_numpy(float)
    small = np.isclose(table["size"].to_numpy(float), cfg["capillary_windows"][0])
    assert np.isfinite(cap[small]).all() and np.isnan(cap[~small]).all()
    # each window holds the nominal load the whole solve gives over it
    assert (table["nominal_pressure"] > 0).all()
    w = whole.iloc[0]
    assert w["mean_pressure"] == pytest.approx(bw.PRESSURE, rel=1e-5)
    assert w["pull_off_stress"] > 0 and w["capillary_pull_off_stress"] > w["pull_off_stress"]
    assert 0 < w["friction_coefficient_static"] < 1 and w["presliding_displacement"] > 0
    # the errors are window / whole - 1
    r = table.iloc[0]
    assert r["err_mean_gap"] == pytest.approx(r["mean_gap"] / r["whole_mean_gap"] - 1)
    md = bw.markdown_table(table, whole)
    assert md.count("\n") == len(table) + 2
    png = bw.plot_study(table, whole, None, tmp_path / "fig.png")
    assert png.stat().st_size > 10_000
