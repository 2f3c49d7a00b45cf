"""The Paper B 4.2 study (studies.paper_b, examples/studies/paper_b.py) on its quick
cell: the sweep file is the library's, the quick sweep runs and gathers, the findings table
and the figure are written, and the script keeps the published data untouched.  Also the
Paper C study's sweep (spots, rms scaling) without running it."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from studies import paper_b
from tribobem.sweep import load_sweep, run_sweep

ROOT = Path(__file__).resolve().parents[2]
SWEEP = ROOT / "examples" / "studies" / "paper_b.toml"
VERDICTS = {"reproduced", "partly", "not reproduced", "missing"}


def test_sweep_file_is_the_library_sweep():
    a, b = load_sweep(SWEEP), load_sweep(paper_b.sweep_spec())
    assert [h for h, _ in a.tasks()] == [h for h, _ in b.tasks()]
    names = [p["name"] for p in b.points]
    assert len(names) == len(set(names)) == 14
    # Paper B 4.2: 10 x 10 um, 256^2, rms 5 nm, L_ac/L = 0.02, 0.05, 0.1, 500 uN, SiO2 on a rigid dry flat
    from tribobem.scenario import parse_scenario

    sc = parse_scenario(b.scenario_for(b.points[2]))
    assert sc.grid.shape == (256, 256) and sc.grid.lengths == (10e-6, 10e-6) and sc.grid.periodic
    assert sc.body1.E == 64e9 and sc.body1.nu == 0.17 and sc.body1.roughness.rms == pytest.approx(5e-9)
    assert sc.body1.roughness.correlation_length == pytest.approx(0.1 * 10e-6)
    assert sc.body2.rigid and sc.body2.film is None and sc.load.force == pytest.approx(500e-6)
    assert max(sc.humidity.rh) == 0.99


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper_b")
    spec = paper_b.sweep_spec(quick=True)
    res = run_sweep(spec, out, scheduler="synchronous", progress=False)
    assert res.n_ok == len(spec["points"]), res.failed
    return spec, out, paper_b.gather(spec, out)


def test_quick_study_gathers_every_case_and_rh(quick):
    spec, out, curves = quick
    assert set(curves["case"]) == {p["name"] for p in spec["points"]}
    assert len(curves) == len(spec["points"]) * len(paper_b.QUICK_RH)
    assert curves["converged"].all()
    area = paper_b.QUICK_SIZE**2
    for r in curves.itertuples():
        # dP_cap times the meniscus area, bounded by the non-contact area: |F_cap| <= |dP| A (1 - contact)
        dp = abs(8.314462618 * 295.0 * math.log(r.rh) / 18.05e-6)
        assert abs(r.capillary_force) <= dp * area * (1 - r.contact_fraction) * (1 + 1e-12)
        assert 0 <= r.wetted_fraction <= 1 - r.contact_fraction + 1e-12
        assert r.adhesive_total == pytest.approx(r.capillary_force + r.solid_solid_force + r.water_solid_force)
    # the 500 uN cases carry the scaled load; the 5000 uN case ten times it
    f = curves.groupby("case")["force"].first()
    assert f["load 5000 uN lac 0.02"] == pytest.approx(10 * f["lac 0.02"])
    # at 99 % RH the Laplace pressure is 1/10 of that at 90 %: F_cap must have fallen from its peak
    for c in ("lac 0.02", "lac 0.05", "lac 0.1"):
        rh, fcap, _ = paper_b._curve(curves, c)
        assert abs(fcap[rh == 0.99][0]) < abs(fcap.min())


def test_findings_table_and_figure(quick, tmp_path):
    _, _, curves = quick
    table = paper_b.findings(curves)
    assert [t["key"] for t in table] == [k for k, _ in paper_b.FINDINGS]
    assert all(t["verdict"] in VERDICTS for t in table)
    by = {t["key"]: t for t in table}
    assert by["rms"]["verdict"] == "missing" and by["realisations"]["verdict"] == "missing"  # not in the quick sweep
    assert by["rise_fall"]["verdict"] != "missing" and "peak" in by["rise_fall"]["ours"]
    png = paper_b.plot_study(curves, tmp_path / "b.png")
    assert png.stat().st_size > 10_000


def test_script_quick_run_writes_to_out_only(tmp_path, monkeypatch):
    sys.path.insert(0, str(ROOT / "examples" / "studies"))
    try:
        import paper_b as script
    finally:
        sys.path.pop(0)
    docs = ROOT / "docs" / "data" / "paper_b.csv"
    before = docs.stat().st_mtime if docs.exists() else None
    with pytest.raises(SystemExit):
        script.main(["--quick", "--publish", "--out", str(tmp_path)])
    # --no-run on an empty folder: gathers nothing, still writes its files, never docs/
    assert script.main(["--quick", "--no-run", "--quiet", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "paper_b.csv").is_file() and (tmp_path / "paper_b_findings.csv").is_file()
    assert (docs.stat().st_mtime if docs.exists() else None) == before


def test_paper_c_sweep_spots_and_rms():
    from tribobem.scenario import parse_scenario
    from studies import paper_c

    assert paper_c.PARK_SCAN.is_file()  # shipped with tribobem (tribobem.data)
    sw = paper_c.spot_windows()
    assert len(sw["spots"]) == 5 and sw["cells"] == 170
    spec = load_sweep(paper_c.sweep_spec())
    assert len(spec.points) == 20
    seen = {}
    for _, o in spec.tasks():
        sc = parse_scenario(spec.scenario_for(o))
        sub = sc.name.split()[0]
        humid = sc.humidity is not None
        assert sc.body2.shape.radius == pytest.approx(2.5e-6) and sc.body2.E == 64e9
        assert sc.adhesion.work_of_adhesion == pytest.approx(0.088) and sc.load.preload == pytest.approx(100e-9)
        if humid:
            assert sc.humidity.rh == [0.35] and sc.humidity.contribution == "linear_30_60"
            assert sc.body1.film.isotherm == sub and sc.body2.film.isotherm == "SiO2"
        else:
            assert sc.body1.film is None and sc.body2.film is None
        seen.setdefault(sub, []).append(sc.body1.roughness.rms)
    # every spot of one substrate is the scan scaled by the same factor to Paper C's rms
    for sub, target in (("Si", 0.46e-9), ("SiO2", 0.74e-9)):
        spot_rms = np.array([s["rms"] for s in sw["spots"]] * 2)
        np.testing.assert_allclose(np.array(seen[sub]) / spot_rms, target / sw["scan_rms"], rtol=1e-5)
