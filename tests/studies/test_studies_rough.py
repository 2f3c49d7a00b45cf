"""Rough-ball rms study (Paper A section 7) and AFM spot pull-off (Paper C), quick versions.

The quick rough-ball run uses the full study's cell size (dx = 39 nm) on a 2.5 um domain
(64^2) with rms/z0 = 0, 2, 20, so its physics is that of the full study near the ball's centre.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from tribobem.data import topography_path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "studies"
#: The measured Park AFM scan shipped with tribobem (tribobem.data; no skip: it is always there).
PARK = topography_path("example_ps.tiff")


def _docs_stamps() -> dict:
    """Modification times of the published files (docs/data, docs/figures)."""
    return {p: p.stat().st_mtime_ns for folder in ("data", "figures") for p in (ROOT / "docs" / folder).rglob("*") if p.is_file()}


def _load_example(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def quick_rough(tmp_path_factory):
    """The example script's --quick run (64^2 on 2.5 um; rms/z0 = 0, 2, 20; mu_T = 1, 2)."""
    import xarray as xr

    out = tmp_path_factory.mktemp("rough_ball")
    mod = _load_example("rough_ball_study")
    before = _docs_stamps()
    assert mod.main(["--quick", "--out", str(out), "--quiet"]) == 0
    assert _docs_stamps() == before  # the published docs/ files are not touched
    assert (out / "data" / "rough_ball_quick.csv").is_file()
    assert (out / "figures" / "rough_ball_pulloff_quick.png").stat().st_size > 10_000
    with xr.open_dataset(out / "data" / "rough_ball_quick.nc") as ds:
        return ds.load()


def test_rough_ball_quick_converged_and_balanced(quick_rough):
    ds = quick_rough
    assert bool(ds["converged"].all())
    # F0+ + F0- = F0 at every point (force control), and F0- <= 0 <= F0+.
    total = ds["repulsive_force"] + ds["adhesive_force"]
    np.testing.assert_allclose(total.values, ds.attrs["force"], rtol=1e-6)
    assert float(ds["adhesive_force"].max()) <= 0.0
    assert np.all(ds["pull_off_force"].values < 0)
    # the same asperity layout: rms slope proportional to rms
    s = ds["rms_slope"].values
    r = ds["rms"].values
    np.testing.assert_allclose(s[1:] / r[1:], s[-1] / r[-1], rtol=1e-9)


def test_smooth_ball_pull_off_between_dmt_and_jkr(quick_rough):
    ds = quick_rough.sel(rms=0.0)
    for mu in ds["tabor"].values:
        f = -float(ds["pull_off_force"].sel(tabor=mu))
        dmt = -float(ds["dmt_pull_off"].sel(tabor=mu))
        jkr = -float(ds["jkr_pull_off"].sel(tabor=mu))
        assert 0.95 * jkr <= f <= 1.05 * dmt, (mu, f, jkr, dmt)
        # smooth contact radius at F0 within 10 % of Maugis-Dugdale (about 10-14 cells)
        a, a_md = float(ds["smooth_contact_radius"].sel(tabor=mu)), float(ds["md_contact_radius"].sel(tabor=mu))
        assert abs(a / a_md - 1) < 0.1


def test_roughness_kills_pull_off_at_large_rms(quick_rough):
    ds = quick_rough
    for mu in ds["tabor"].values:
        po = -ds["pull_off_force"].sel(tabor=mu).values
        assert po[-1] < 0.1 * po[0]          # rms = 20 z0: a few asperities only
        assert po[-1] < po[1] <= 1.05 * po[0]  # falls with rms beyond the (possible) rise
        # contact area at F0 falls with rms
        a = ds["contact_area"].sel(tabor=mu).values
        assert np.all(np.diff(a) < 0)


def test_small_roughness_raises_adhesion_share(quick_rough):
    """The robust part of Paper A Fig. 11 at rms = 2 z0 on this grid: the area ratio
    A(p < 0)/A_c rises above the smooth value for both mu_T (the contact shrinks faster than
    the area under tension), and for mu_T = 2 the adhesive force F0- itself rises (the rise
    of Fig. 11a).  For mu_T = 1 the F0- rise happens at smaller rms (< 2 z0), not asserted."""
    ds = quick_rough
    i_small = 1  # rms = 2 z0
    for mu in ds["tabor"].values:
        ar = ds["area_ratio"].sel(tabor=mu).values
        assert ar[i_small] > ar[0]
    fa = -ds["adhesive_force"].sel(tabor=2.0).values
    assert fa[i_small] >= fa[0]


def test_rough_ball_study_api_and_table():
    from studies.rough_ball import calibrate_correlation_length, peak_summary, rough_ball_study, study_table
    from tribobem.errors import InputError
    from tribobem.geometry import gaussian_surface, rms_slope
    from tribobem.grid import Grid

    g = Grid.square(64, 2.5e-6)
    beta = calibrate_correlation_length(g)
    assert abs(rms_slope(gaussian_surface(g, 5e-9, beta, seed=1), g) - 0.113) < 1e-3
    ds = rough_ball_study([0.0, 1e-9], tabor_values=[1], n=32, size=2.5e-6, correlation_length=beta,
                          n_steps=12, refine=2)
    df = study_table(ds)
    assert len(df) == 2 and {"pull_off_over_smooth", "area_ratio", "adhesive_force_ratio"} <= set(df.columns)
    assert peak_summary(ds)[0]["tabor"] == 1.0
    with pytest.raises(InputError):
        rough_ball_study([-1e-9])


def test_afm_spots_on_park_scan():
    from studies.afm_pulloff import afm_pull_off_spots, spot_origins

    # five non-overlapping windows: corners and centre of a 3 x 3 lattice
    o = spot_origins((512, 512), (170, 170), 5)
    assert len(o) == 5 and len(set(o)) == 5
    res = afm_pull_off_spots(PARK, n_spots=3, window=0.1e-6, n=32, n_steps=16, refine=3)
    f = res.table["pull_off_force"].to_numpy()
    assert len(f) == 3 and np.all(np.isfinite(f)) and np.all(f < 0)
    assert bool(res.table["converged"].all())
    # a rough spot adheres much less than the smooth probe on the same grid
    assert np.all(-f < -res.smooth)
    assert res.mean == pytest.approx(f.mean()) and res.std == pytest.approx(f.std(ddof=1))
    # references: DMT 2 pi R dgamma = 1.38 uN, JKR 1.04 uN, MD in between
    assert res.dmt == pytest.approx(-2 * math.pi * 2.5e-6 * 0.088)
    assert res.dmt < res.maugis_dugdale < res.jkr
    # the scan is 1 um: windows that do not fit are an error naming the window
    from tribobem.errors import InputError

    with pytest.raises(InputError, match="window"):
        afm_pull_off_spots(PARK, n_spots=5, window=0.6e-6)


def test_afm_example_quick(tmp_path):
    mod = _load_example("afm_pulloff")
    before = _docs_stamps()
    assert mod.main(["--quick", "--out", str(tmp_path), "--quiet", "--data", str(PARK.parent)]) == 0
    assert _docs_stamps() == before  # the published docs/ files are not touched
    import pandas as pd

    t = pd.read_csv(tmp_path / "data" / "afm_pulloff_quick.csv")
    assert len(t) == 10 and np.all(t["pull_off_force"] < 0)
    s = pd.read_csv(tmp_path / "data" / "afm_pulloff_summary_quick.csv")
    assert len(s) == 2 and list(s["case"]) == list(dict.fromkeys(t["case"]))
    # each case's summary is the statistics of its spots in the per-spot table (sample std,
    # ddof = 1); the spots differ, so the spread is positive and within the range
    for _, row in s.iterrows():
        f = t.loc[t["case"] == row["case"], "pull_off_force"].to_numpy()
        assert row["n_spots"] == len(f) == 5
        assert row["mean"] == pytest.approx(f.mean(), rel=1e-9)
        assert row["std"] == pytest.approx(f.std(ddof=1), rel=1e-9)
        assert row["min"] == pytest.approx(f.min(), rel=1e-12) and row["max"] == pytest.approx(f.max(), rel=1e-12)
        assert 0 < row["std"] < row["max"] - row["min"]
    assert (tmp_path / "figures" / "afm_pulloff_quick.png").is_file()
