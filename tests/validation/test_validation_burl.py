"""The burl validation physics (tribobem.validation.burl): its quick tier passes, every row has
a finite tolerance derived from the grid, and it is registered in PHYSICS and the CI gate."""

from __future__ import annotations

import math

import pytest

from tribobem.validation import PHYSICS, PHYSICS_CASES, run_validation
from tribobem.validation.burl import CASES, disc_area_bound
from tribobem.validation.gate import GATE


def test_burl_is_a_physics_with_gated_cases():
    assert "burl" in PHYSICS
    assert set(PHYSICS_CASES["burl"]) == set(CASES) == {"rounded_punch", "flat_punch", "burl_stiffness", "kendall",
                                                        "texture_cell"}
    assert all(GATE[c] == "full" for c in CASES)


@pytest.mark.parametrize("case", ["rounded_punch", "flat_punch", "burl_stiffness", "texture_cell", "kendall"])
def test_quick_rows_pass_with_finite_tolerances(case):
    rows = run_validation(level="quick", cases=[case])
    assert rows
    for r in rows:
        assert math.isfinite(r.tolerance) and 0 < r.tolerance <= 0.1, r
        assert math.isfinite(r.computed), r
        assert r.passed, r


def test_disc_bound_holds_for_sampled_discs():
    import numpy as np

    from tribobem.grid import Grid

    for n, r in ((64, 0.13), (128, 0.31), (96, 0.2)):
        g = Grid.square(n, 1.0)
        X, Y = g.meshgrid()
        for c in ((0.0, 0.0), (0.3 * g.dx, 0.1 * g.dx)):
            area = np.count_nonzero(np.hypot(X - c[0], Y - c[1]) < r) * g.dx**2
            assert abs(area / (math.pi * r * r) - 1) <= disc_area_bound(r, g.dx)
