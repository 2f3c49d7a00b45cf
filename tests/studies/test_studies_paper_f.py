"""The Paper F study (studies.paper_f) and its example scenario: the cases, the smooth-ball
references, the roughness scaling, and one tiny case end to end (32^2, one cycle)."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from studies import paper_f as pf
from tribobem.data import topography_path
from tribobem.errors import InputError

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "hysteresis_paper_f_pom.toml"
#: The measured confocal scan shipped with tribobem (tribobem.data; no skip: it is always there).
PLU = topography_path("plu-1.plu")


def test_cases_follow_tables_1_and_2():
    cs = pf.cases()
    assert len(cs) == 6 and {c.material for c in cs} == {"HDPE", "POM"}
    pom75 = next(c for c in cs if c.material == "POM" and c.load_mN == 75)
    assert (pom75.stroke, pom75.mu, pom75.E, pom75.nu, pom75.rms) == (4.264e-6, 0.099, 1.38e9, 0.5, 0.67e-6)
    hdpe25 = next(c for c in cs if c.material == "HDPE" and c.load_mN == 25)
    assert (hdpe25.stroke, hdpe25.mu, hdpe25.rms, hdpe25.force) == (2.805e-6, 0.153, 3.17e-6, 0.025)
    with pytest.raises(InputError, match="material"):
        pf.cases(materials=("PTFE",))
    with pytest.raises(InputError, match="Table 1"):
        pf.cases(loads=(40,))


def test_smooth_ball_references():
    c = pf.cases(("POM",), (50,))[0]
    G = [c.E / (2 * (1 + c.nu)), 130e9 / (2 * 1.28)]
    k = (2 - 0.5) / G[0] + (2 - 0.28) / G[1]
    assert pf.compliance(c) == pytest.approx(k, rel=1e-12)
    Es = 1 / ((1 - 0.25) / 1.38e9 + (1 - 0.28**2) / 130e9)
    a = (3 * 0.05 * 5e-3 / (4 * Es)) ** (1 / 3)
    assert pf.hertz_radius(c) == pytest.approx(a, rel=1e-12) and 40e-6 < a < 50e-6
    K0 = 8 * a / k
    muP = c.mu * c.force
    assert pf.mindlin_branch_stiffness(c, -muP) == pytest.approx(K0)
    assert pf.mindlin_branch_stiffness(c, muP) == pytest.approx(0.0, abs=1e-9)
    assert pf.mindlin_branch_stiffness(c, 0.0) == pytest.approx(K0 * 0.5 ** (1 / 3))
    assert pf.eq6_stiffness(c, 0.0) == pytest.approx(K0)
    assert pf.eq6_stiffness(c, -0.5 * muP) == pytest.approx(pf.eq6_stiffness(c, 0.5 * muP))
    # Paper F Eq. 6 with Eq. 4's delta0 (the ball alone) is the same slope within the wafer's 1 %
    d0_f = 3 * muP * (2 - 0.5) * (1 + 0.5) / (8 * a * c.E)
    assert 3 * muP / (2 * d0_f) == pytest.approx(K0, rel=0.015)
    # loop energy of a sliding Mindlin-Deresiewicz loop: 2 mu P (d_s - 1.6 delta0), by quadrature
    d0 = pf.mindlin_delta0(c)
    x = np.linspace(0, 2 * d0, 20001)
    corner = np.trapezoid(2 * muP - 2 * muP * (1 - (1 - x / (2 * d0)) ** 1.5), x)
    assert pf.mindlin_loop_energy(c) == pytest.approx(2 * muP * c.stroke - 2 * corner, rel=1e-6)


def test_mindlin_references_match_the_analytic_module():
    from tribobem.analytic import mindlin  # our own module: an ImportError fails, not skips
    c = pf.cases(("HDPE",), (75,))[0]
    a, k, muP = pf.hertz_radius(c), pf.compliance(c), c.mu * c.force
    assert pf.mindlin_delta0(c) == pytest.approx(mindlin.mindlin_delta0(P=c.force, a=a, mu=c.mu, k=k))
    for F in (-0.5 * muP, 0.0, 0.5 * muP):
        ref = mindlin.mindlin_reloading_stiffness(F, muP, P=c.force, a=a, mu=c.mu, k=k)
        assert pf.mindlin_branch_stiffness(c, F) == pytest.approx(float(ref), rel=1e-9)


def test_roughness_scaling_and_scenario():
    full = pf.full_scan_rms(PLU)
    assert 15e-9 < full < 22e-9  # the flattened scan (README's 2.83 um is the tilt and the form)
    r = pf.window_rms(PLU, 64, 240e-6, 0.67e-6)
    assert 0.6 * 0.67e-6 < r < 0.67e-6
    c = pf.cases(("POM",), (50,))[0]
    sc = pf.scenario(c, n=64, topography=PLU)
    from tribobem.scenario import parse_scenario

    s = parse_scenario(sc)
    assert s.kind == "hysteresis" and s.body2.roughness.detrend == "curvature"
    assert s.body2.roughness.rms == pytest.approx(r) and s.grid.lengths == (240e-6, 240e-6)
    assert s.friction.path.control == "displacement" and s.friction.path.stroke == pytest.approx(3.37e-6)
    assert s.body1.roughness.kind == "none" and s.body2.shape.radius == 5e-3


def test_example_scenario_is_the_study_case():
    """examples/hysteresis_paper_f_pom.toml is the POM 50 mN case at 64^2 with the study's scaling."""
    from tribobem.scenario import load_scenario

    sc, _ = load_scenario(EXAMPLE)
    c = pf.cases(("POM",), (50,))[0]
    assert sc.kind == "hysteresis" and sc.grid.shape == (64, 64) and not sc.grid.periodic
    assert sc.load.force == pytest.approx(c.force) and sc.friction.coefficient == pytest.approx(c.mu)
    assert sc.friction.path.stroke == pytest.approx(c.stroke) and sc.friction.path.control == "displacement"
    assert sc.body2.E == pytest.approx(c.E) and sc.body1.E == pytest.approx(130e9)
    assert sc.body2.roughness.rms == pytest.approx(pf.window_rms(PLU, 64, sc.grid.lengths[0], c.rms), rel=1e-3)
    assert "4" in str(sc.friction.path.cycles)
    assert tomllib.loads(EXAMPLE.read_text())["grid"]["size"] == "240 um"


def test_keep_states_restores_the_runner():
    from tribobem.runs import hysteresis as runner

    original = runner.hysteresis_loop
    with pytest.raises(RuntimeError):
        with pf._keep_states():
            assert runner.hysteresis_loop is not original
            raise RuntimeError("boom")
    assert runner.hysteresis_loop is original


def test_tiny_case_end_to_end(tmp_path):
    """HDPE 50 mN at 32^2 (10 um cells), 48 steps, one cycle: the workflow runs, K_L is fitted,
    falls from A to C and lies near the smooth-ball Mindlin-Deresiewicz slope; the record is
    read back on a second call; tables and figures are written."""
    c = pf.cases(("HDPE",), (50,))[0]
    rec = pf.run_case(c, tmp_path, n=32, steps=48, cycles=1, topography=PLU, figures=False)
    assert rec["converged"] and rec["fit"] and rec["fit"]["points"] >= 5 and rec["fit"]["sliding"]
    k = {s["point"]: s["stiffness"] for s in rec["stiffness"]}
    assert k["A"] > k["B"] > k["C"] > 0
    for s in rec["stiffness"]:
        assert 0.3 < s["ratio_to_mindlin"] < 1.2, s
        assert s["eq6_stiffness"] > 0 and s["mindlin_stiffness"] > 0
    assert rec["sliding_ratio"] == pytest.approx(1.0, abs=2e-3)
    assert rec["loop_energy"] == pytest.approx(rec["mindlin_loop_energy"], rel=0.1)
    assert rec["edge_margin_cells"] >= 1 and rec["contact_cells"] > 3
    folder = Path(rec["result_folder"])
    assert (folder / "summary.json").is_file() and (folder / "maps.npz").is_file()
    with np.load(folder / "maps.npz") as z:
        assert {"pressure_start", "shear_ratio_A", "stick_C"} <= set(z.files)
        sr = z["shear_ratio_B"]
        assert np.nanmax(sr) <= 1.0 + 1e-6
    again = pf.run_case(c, tmp_path, n=32, steps=48, cycles=1, topography=PLU, figures=False)
    assert again == json.loads(json.dumps(rec))
    rows = pf.stiffness_table([rec])
    assert [r["point"] for r in rows] == ["A", "B", "C"]
    csv = pf.write_csv(rows, tmp_path / "k.csv")
    assert csv.read_text().splitlines()[0].startswith("material,F0_mN")
    f = pf.findings([rec])
    assert f["all_fall"] is True and f["all_POM_stiffer"] is None
    assert pf.plot_loops([rec], tmp_path / "loops.png").stat().st_size > 20_000
    assert pf.plot_maps([rec], tmp_path / "maps.png").stat().st_size > 10_000
    from tribobem.analysis.loops import fit_branch, loop_from_summary

    fit = fit_branch(loop_from_summary(folder))
    assert fit.c1 == pytest.approx(rec["fit"]["c1"])
    assert not math.isnan(rec["fit"]["n"])
