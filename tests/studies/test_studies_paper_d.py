"""Paper D Table 1 study (smooth adhesive ball, tangential ramp to gross slip), a small-grid run."""

from __future__ import annotations

import math

import numpy as np
import pytest

from studies.paper_d import PAPER_D_TABLE1, md_reference, paper_d_case, resolution_summary, study_table

F0 = 10e-6
MU = 0.2


@pytest.fixture(scope="module")
def case():
    # mu_T = 1 on 48^2 over +-2 c0 (dx = 11.5 nm, a/dx ~ 10): coarse, but every quantity is defined.
    return paper_d_case(1.0, 48)


def test_forces_balance_and_adhesion(case):
    assert case.converged
    assert not case.edge_contact
    # F0+ + F0- = F0 (force control), F0- < 0 with adhesion, F0+ > F0.
    assert math.isclose(case.repulsive_force + case.adhesive_force, F0, rel_tol=1e-6)
    assert case.adhesive_force < 0 < F0 < case.repulsive_force
    # Within a factor ~1.5 of the Maugis-Dugdale adhesive force at the same load (coarse grid).
    md = case.md["adhesive_force"]
    assert md < 0 and 0.6 < case.adhesive_force / md < 1.6


def test_onset_bracket_and_ratios(case):
    assert case.gross_slip
    lo, hi = case.onset_bracket
    assert lo < case.onset_force < hi
    assert hi - lo <= 1e-3 * MU * case.onset_repulsive_force * (1 + 1e-9)
    assert 0 < case.bracket_width <= 1e-3 * (1 + 1e-9)
    assert 0.8 < case.onset_ratio < 1.0
    # F_nr = F_x/(mu F0) = onset ratio x F0+/F0 (F0+ at the onset state).
    assert math.isclose(case.force_ratio_paper_d, case.onset_force / (MU * F0), rel_tol=1e-12)
    assert math.isclose(case.onset_ratio * case.onset_repulsive_force / F0, case.force_ratio_paper_d, rel_tol=1e-9)
    assert case.force_ratio_paper_d > 1.0  # adhesion: F0+ > F0
    assert case.presliding_displacement > 0


def test_ramp_curve(case):
    fr, st = case.force_ratios, case.stick_ratios
    assert abs(fr[0]) < 1e-9 and np.all(np.diff(fr) > 0)
    # dissimilar bodies: a slip annulus already at F_x = 0; the stick ratio falls along the ramp
    assert 0 < case.zero_stick_ratio < 1 and st[0] == case.zero_stick_ratio
    assert np.all(st > 0) and st[-1] < st[0]
    assert np.all(np.diff(case.displacements) > 0)
    # the curve ends at the last state with stick of the bisection, normalised by its own F0+
    assert math.isclose(case.forces[-1], case.onset_bracket[0], rel_tol=1e-9)
    assert math.isclose(fr[-1] * MU * case.repulsive_forces[-1], case.onset_bracket[0], rel_tol=1e-9)
    assert math.isclose(case.repulsive_forces[0], case.repulsive_force, rel_tol=1e-9)
    assert fr[-1] < case.onset_ratio < fr[-1] + 1.1e-3


def test_table_and_summary(case):
    df = study_table([case])
    assert len(df) == 1 and df["paper_d_onset_ratio"].iloc[0] == PAPER_D_TABLE1[1.0][3]
    assert df["cells_across_cohesive_zone"].iloc[0] > 0
    s = resolution_summary([case])
    assert s[0]["tabor"] == 1.0 and math.isnan(s[0]["finest_change"]) and not s[0]["converged"]


def test_md_reference():
    E_star = 130e9 / (1 - 0.3**2)
    h = md_reference(0.0, 10e-6, E_star, 0.2e-9, F0)
    assert h["adhesive_force"] == 0.0 and math.isclose(h["contact_radius"], 80.67e-9, rel_tol=1e-3)
    r = md_reference(1.0, 10e-6, E_star, 0.2e-9, F0)
    assert r["cohesive_radius"] > r["contact_radius"]
    # the tensile rim inside the contact adds to the annulus
    assert r["adhesive_force"] < r["annulus_force"] < 0
    assert math.isclose(r["repulsive_force"] + r["adhesive_force"], F0, rel_tol=1e-12)


def test_example_script_quick(tmp_path):
    """The CLI on a tiny grid writes its table, curves and figure into --out only."""
    import importlib.util
    from pathlib import Path

    import pandas as pd

    root = Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("example_paper_d_table1", root / "examples" / "studies" / "paper_d_table1.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    docs = root / "docs" / "data" / "paper_d_table1.csv"
    before = docs.stat().st_mtime_ns if docs.exists() else None
    assert mod.main(["--quick", "--out", str(tmp_path), "--grids", "32", "--zero-grids", "40", "--quiet"]) == 0
    table = pd.read_csv(tmp_path / "paper_d_table1_quick.csv")
    assert list(table["ramp"]) == [True, False] and list(table["n"]) == [32, 40]
    assert table["onset_ratio"].iloc[0] > 0.8 and math.isnan(table["onset_ratio"].iloc[1])
    curves = pd.read_csv(tmp_path / "paper_d_table1_quick_curves.csv")
    assert len(curves) >= 3 and curves["stick_ratio"].iloc[0] > 0
    assert (tmp_path / "paper_d_table1_quick.png").stat().st_size > 10_000
    assert (docs.stat().st_mtime_ns if docs.exists() else None) == before
    with pytest.raises(SystemExit):
        mod.main(["--quick", "--publish", "--out", str(tmp_path)])
