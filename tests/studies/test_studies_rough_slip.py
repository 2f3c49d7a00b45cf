"""The rough-ball slip study (Paper D section 3.2) on a tiny grid: the flat, the sweep over the
study's base scenario, the gathered table and the figure."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from studies.rough_slip import (
    flat_surface,
    gather,
    paper_d_checks,
    plot_study,
    study_table,
    tabor_parameter,
    window_ratio,
    work_of_adhesion,
    write_flat,
)
from tribobem.sweep import run_sweep

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "studies" / "rough_ball_slip_base.toml"
SWEEP = ROOT / "examples" / "studies" / "rough_ball_slip.toml"


def test_work_of_adhesion_matches_the_sweep_file():
    # The values written (with units) in the sweep file are DugdaleAdhesion.from_tabor's.
    for mu_t, dg in ((0.5, 14.2857e-3), (1.0, 40.4061e-3), (2.0, 114.286e-3)):
        assert work_of_adhesion(mu_t) == pytest.approx(dg, rel=1e-5)
        assert tabor_parameter(dg) == pytest.approx(mu_t, rel=1e-5)
    text = SWEEP.read_text(encoding="utf-8")
    for s in ("14.2857 mJ/m^2", "40.4061 mJ/m^2", "114.286 mJ/m^2"):
        assert s in text


def test_flat_surface_statistics():
    h, info = flat_surface(n=128, size=10e-6)
    assert h.shape == (128, 128)
    assert np.std(h) == pytest.approx(5e-9, rel=1e-9)
    assert abs(np.mean(h)) < 1e-20
    assert info["rms_slope"] == pytest.approx(0.113, rel=1e-3)
    crop = {"x0": 3.75e-6, "y0": 3.75e-6, "lx": 2.5e-6, "ly": 2.5e-6}
    assert 0.5 < window_ratio(h, (10e-6, 10e-6), crop) < 1.5


@pytest.fixture(scope="module")
def tiny_study(tmp_path_factory):
    """The study's base scenario on 48^2 cells (the flat on 192^2 over 10 um, dx = 52 nm, the
    same 2.5 um window), non-adhesive, flat rms 0 and 5 nm, a coarse ramp."""
    tmp = tmp_path_factory.mktemp("rough_slip")
    flat = tmp / "flat.npy"
    write_flat(flat, n=192)
    base = tomllib.loads(BASE.read_text(encoding="utf-8"))
    base["grid"]["n"] = 48
    base["body1"]["roughness"]["path"] = str(flat)
    base["output"] = {"fields": "last", "figures": False, "report": False}
    h = np.load(flat)
    ratio = window_ratio(h, (10e-6, 10e-6), {"x0": 3.75e-6, "y0": 3.75e-6, "lx": 2.5e-6, "ly": 2.5e-6})
    ramp = ["0 uN", "1 uN", "1.6 uN", "1.9 uN", "2.05 uN"]
    spec = {"name": "tiny", "base": base, "keep_runs": True,
            "outputs": ["static_friction_ratio", "presliding_displacement", "repulsive_force"],
            "points": [{"adhesion.model": "none", "body1.roughness.rms": f"{r * ratio:.9g} nm",
                        "friction.tangential_forces": ramp} for r in (0.0, 5.0)]}
    out = tmp / "out"
    res = run_sweep(spec, out, scheduler="synchronous", progress=False)
    assert res.n_ok == 2, res.failed
    table, curves = gather(spec, out)
    return table, curves, tmp


def test_gathered_table(tiny_study):
    table, curves, _ = tiny_study
    tab = study_table(table)
    for col in ("tabor", "rms", "rms_window", "repulsive_force", "adhesive_force", "static_friction_ratio",
                "presliding_displacement", "zero_force_stick_ratio", "contact_radius", "interaction_extent",
                "edge_margin_cells", "status", "elapsed"):
        assert col in tab.columns, col
    assert len(tab) == 2
    assert list(tab["status"]) == ["ok", "ok"]
    assert np.allclose(tab["tabor"], 0.0)
    assert tab["rms"].values == pytest.approx([0.0, 5e-9], rel=1e-6)
    # non-adhesive: F0+ = F0, F0- = 0
    assert tab["repulsive_force"].values == pytest.approx([10e-6, 10e-6], rel=1e-6)
    assert np.all(tab["adhesive_force"].values == 0.0)
    # the onset lies at or below mu F0+ (a one-node contact slips at mu F0+), the pre-sliding
    # is a fraction of a nm
    r = tab["static_friction_ratio"].values
    assert np.all((r > 0.7) & (r < 1.0 + 2e-3))  # midpoint of the 1e-3 bracket
    d = tab["presliding_displacement"].values
    assert np.all((d > 1e-12) & (d < 1e-8))
    s0 = tab["zero_force_stick_ratio"].values
    # smooth: a stuck centre and a slip annulus at F_x = 0 (the coupling; Spence); rough: a
    # stick zone too (the micro-contacts of this 48^2 grid are a few cells each, too small for an
    # annulus: measured all stick)
    assert 0 < s0[0] < 1 and s0[1] > 0
    # the contact stays inside the window
    assert np.all(tab["edge_margin_cells"].values > 2)
    assert not any(tab["touches_edge"])
    # the curves: stick ratio from F = 0 on, not increasing along the ramp, force ratio < 1
    for h in tab["hash"]:
        c = curves[(curves["hash"] == h) & (curves["step"] >= 0) & (~curves["gross_slip"])]
        assert len(c) >= 2
        assert c["force_ratio"].iloc[0] == pytest.approx(0.0, abs=1e-9)
        # the table's F_x = 0 stick ratio is the curve's first step
        assert c["stick_ratio"].iloc[0] == pytest.approx(
            float(tab.loc[tab["hash"] == h, "zero_force_stick_ratio"].iloc[0]), rel=1e-12)
        assert np.all(np.diff(c["stick_ratio"].values) <= 1e-12)
        assert np.all(c["force_ratio"].values < 1.0)
        assert np.all(np.diff(c["displacement_x"].values) > 0)
    checks = paper_d_checks(table, curves)
    assert {c["verdict"] for c in checks} <= {"reproduced", "partly", "not reproduced", "missing data"}


def test_figure(tiny_study):
    table, curves, tmp = tiny_study
    path = tmp / "fig.png"
    plot_study(table, curves, path)
    assert path.stat().st_size > 10_000
    assert math.isfinite(table.attrs["dx"])
