"""The validation tiers (quick / ci / full), the CI gate and the published-number case."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from tribobem import InputError
from tribobem.validation import CASES, LEVELS, PHYSICS, PHYSICS_CASES, run_validation

ROOT = Path(__file__).resolve().parents[2]


def test_physics_partition_the_cases():
    assert LEVELS == ("quick", "ci", "full")
    assert tuple(PHYSICS_CASES) == PHYSICS and "studies" in PHYSICS
    names = [c for p in PHYSICS for c in PHYSICS_CASES[p]]
    assert names == list(CASES)                      # every case in exactly one physics, in order
    assert PHYSICS_CASES["studies"] == ("bisinusoidal_resolution",)


def test_gate_entries_name_existing_cases_and_cover_the_published_numbers():
    from tribobem.validation.gate import GATE

    assert set(GATE) <= set(CASES)
    for name in ("maugis_dugdale", "md_pull_off", "bisinusoidal_resolution", "cattaneo_mindlin", "spence",
                 "mindlin_deresiewicz", "paper_e"):
        assert GATE[name] != "quick", name            # protected at the gate's resolution


def test_level_and_physics_selection():
    rows = run_validation(level="ci", cases=["hertz", "force_balance"], physics=["normal"])
    assert {r.case.split()[0] for r in rows} == {"hertz", "force"}
    assert any("512^2" in r.case for r in rows)        # the gate runs Hertz at the full 512^2
    assert all(r.passed for r in rows)
    assert run_validation(level="quick", cases=["hertz"], physics=["adhesion"]) == []  # intersection
    with pytest.raises(InputError, match="validate.physics"):
        run_validation(physics=["plasma"])
    with pytest.raises(InputError, match="validate.level"):
        run_validation(level="medium", cases=["hertz"])


def test_md_gate_resolution_for_lambda_5():
    from tribobem.validation import maugis_dugdale_problem
    from tribobem.validation.gate import MD_GATE_CELLS, MD_GATE_TOL

    full = maugis_dugdale_problem(5.0)
    gate = maugis_dugdale_problem(5.0, cells_cohesive=MD_GATE_CELLS)
    assert gate.grid.nx < full.grid.nx and gate.grid.lx == pytest.approx(full.grid.lx)
    for F in gate.force_points():                      # the cohesive zone keeps its stated cells
        ref = gate.reference(force=F)
        assert (ref.cohesive_radius - ref.contact_radius) / gate.grid.dx >= MD_GATE_CELLS
    assert all(0 < t <= 0.08 for t in MD_GATE_TOL)


def test_published_corners_are_the_published_table():
    from tribobem.validation.studies import PUBLISHED_CORNERS, RESOLUTION_CORNERS

    with open(ROOT / "docs" / "data" / "bisinusoidal_pulloff.csv", newline="") as fh:
        table = {tuple(round(float(r[k]), 15) for k in ("dgamma", "R_c", "E_star", "k")): float(r["pull_off_force"])
                 for r in csv.DictReader(fh)}
    assert len(table) == 625 and len(PUBLISHED_CORNERS) == 16
    for dg, R, E, k, F in PUBLISHED_CORNERS:
        assert table[(round(dg, 15), round(R, 15), round(E, 15), round(k, 15))] == F
    assert {PUBLISHED_CORNERS[i][3] for i in RESOLUTION_CORNERS} == {0.1, 0.9}


def test_bisinusoidal_quick_reproduces_the_published_values():
    rows = run_validation(quick=True, cases=["bisinusoidal_resolution"])
    assert len(rows) == 2 and all(r.passed for r in rows), rows
    assert all(r.tolerance == 0.05 for r in rows)


def test_bisinusoidal_rows_fail_for_a_changed_solver(monkeypatch):
    """A solver whose pull-off is 6 % stronger fails every reproduction row, one 2 % stronger
    the mean; one whose grid error does not fall with the cell fails the resolution rows."""
    import tribobem.validation.studies as st

    true = {c[:4]: c[4] for c in st.PUBLISHED_CORNERS}
    monkeypatch.setattr(st, "_pull_off", lambda dg, R, E, k, n: 1.06 * true[(dg, R, E, k)])
    rows = st.bisinusoidal_resolution_rows(quick=False)
    reproduction = [r for r in rows if "published table" in r.quantity]
    assert len(reproduction) == 17 and not any(r.passed for r in reproduction)
    monkeypatch.setattr(st, "_pull_off", lambda dg, R, E, k, n: 1.02 * true[(dg, R, E, k)])
    rows = st.bisinusoidal_resolution_rows(quick=False)
    assert [r.passed for r in rows if "published table" in r.quantity] == [True] * 16 + [False]  # the mean
    assert not [r for r in rows if "grid-error ratio" in r.quantity][0].passed    # no grid dependence at all
    # first-order convergence from above, as measured: every row passes
    monkeypatch.setattr(st, "_pull_off", lambda dg, R, E, k, n: true[(dg, R, E, k)] * (1 + 8.0 / n))
    rows = st.bisinusoidal_resolution_rows(quick=False)
    assert all(r.passed for r in rows if "published table" not in r.quantity)
    assert math.isclose([r for r in rows if "grid-error ratio" in r.quantity][0].computed, 2.0)


def test_ci_script_installs_runs_the_readme_command_and_gates_every_physics():
    script = (ROOT / ".ci" / "run").read_text()
    readme = (ROOT / "README.md").read_text()
    assert 'pip install --quiet ".[test]"' in script and "venv --clear" in script
    assert "python -m pytest" in readme and "python -m pytest -q 2>&1" in script
    assert "tribobem validate --ci --physics" in script and "from tribobem.validation import PHYSICS" in script
    assert "-m slow" in script
