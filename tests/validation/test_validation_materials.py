"""The materials physics of ``tribobem validate``: registered, gated, and passing at its quick tier."""

import pytest

from tribobem.validation import PHYSICS, PHYSICS_CASES, run_validation
from tribobem.validation.gate import GATE
from tribobem.validation.materials import CASES


def test_materials_is_a_physics_with_gated_cases():
    assert "materials" in PHYSICS
    assert set(PHYSICS_CASES["materials"]) == set(CASES) == {"hardness_hertz", "hardness_sphere",
                                                           "hardness_rigid_plastic", "hardness_pulloff",
                                                           "subsurface_hertz", "subsurface_sliding",
                                                           "subsurface_equilibrium", "layer_limits", "layer_fem",
                                                           "layer_sphere"}
    assert all(name in GATE for name in CASES)


@pytest.mark.slow  # (the CI gate runs the materials physics at its full tier)
def test_quick_tier_passes_with_finite_tolerances():
    rows = run_validation(level="quick", physics=["materials"])
    assert len(rows) >= 14
    failed = [r for r in rows if not r.passed]
    assert not failed, failed
    # every bar is one a wrong cap would fail: approach bars of 5e-4, the area within 0.3 % of F / H
    assert max(r.tolerance for r in rows if "approach" in r.quantity) <= 2e-3
    assert min(r.tolerance for r in rows if "F / H" in r.quantity) <= 3e-3
