"""tribobem.validation: the cases behind ``tribobem validate``."""

from __future__ import annotations

import dataclasses

import pytest

from tribobem import InputError
from tribobem.validation import CASES, ValidationRow, run_validation


def test_cases_listed():
    for name in ("hertz", "westergaard", "bisinusoidal_small_load", "bisinusoidal_near_full", "force_balance",
                 "periodic_vs_free", "maugis_dugdale", "md_pull_off", "guduru"):
        assert name in CASES


def test_cheap_cases_pass():
    calls = []
    rows = run_validation(quick=True, cases=["hertz", "westergaard"],
                          progress=lambda done, total, name: calls.append((done, total, name)))
    assert calls == [(1, 2, "hertz"), (2, 2, "westergaard")]
    assert {r.case.split()[0] for r in rows} == {"hertz", "westergaard"}
    assert len(rows) == 5
    for r in rows:
        assert isinstance(r, ValidationRow)
        assert [f.name for f in dataclasses.fields(r)] == ["case", "quantity", "reference", "computed",
                                                           "rel_error", "tolerance", "passed"]
        assert r.passed, r
        assert r.rel_error == pytest.approx(abs(r.computed - r.reference) / abs(r.reference))
        assert 0 <= r.rel_error <= r.tolerance
    hertz = [r for r in rows if r.case.startswith("hertz")]
    assert {r.quantity for r in hertz} == {"contact radius", "max pressure p0", "approach"}
    assert all(r.tolerance == 0.03 for r in hertz)       # quick: 128^2, 3%


def test_force_balance_case():
    rows = run_validation(quick=True, cases=["force_balance"])
    assert rows and all(r.passed for r in rows)
    assert max(r.rel_error for r in rows) < 1e-8


def test_unknown_case():
    with pytest.raises(InputError) as err:
        run_validation(cases=["hertz", "no_such_case"])
    assert err.value.field == "validate.cases"
    assert "no_such_case" in str(err.value) and "hertz" in str(err.value)


def test_md_grid_band_case():
    """The grid band of Dugdale equilibria against the solvers' spread (lambda = 1, 160^2):
    both solvers' F0+ within 1.5 bands of Maugis-Dugdale (measured 0.7 / 0.9), their spread
    within 75 % of two bands (measured 0.80)."""
    rows = run_validation(quick=True, cases=["md_grid_band"])
    assert len(rows) == 3 and all(r.passed for r in rows), rows
    pk, cg, spread = rows
    assert pk.computed > pk.reference > cg.computed  # the two sides of the analytic force
    assert 0.6 < spread.computed / spread.reference < 1.0
