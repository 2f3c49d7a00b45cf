"""The analytic friction loop of a hysteresis run's summary (:mod:`tribobem.analytic.friction_loops`):
the Mindlin-Deresiewicz values from the summary's rows and scenario echo agree with
:mod:`tribobem.analytic.mindlin`, other geometries get the rounded punch or nothing, and the
figures and the report use these functions (no second copy in :mod:`tribobem.output`)."""

from __future__ import annotations

import math

import pytest

from tribobem.analytic import friction_loops
from tribobem.analytic.friction_loops import kl_reference, loop_reference, loop_rows, mindlin_reference
from tribobem.analytic.mindlin import mindlin_compliance_k, mindlin_delta0, mindlin_loop_energy

E, NU, MU, P, AREA, PEAK = 210e9, 0.3, 0.3, 10.0, 2.3e-8, 2.4


def _summary(shape=None, rows=3, **inputs):
    body2 = {"E": E, "nu": NU, "shape": shape or {"kind": "sphere", "radius": 0.01}}
    steps = [{"tangential_force_x": f, "displacement_x": 1e-7 * f, "repulsive_force": P,
              "contact_area_compressive": AREA, "branch": b}
             for f, b in [(0.0, "start"), (PEAK, "loading"), (-PEAK, "unloading"), (PEAK, "reloading")][:rows]]
    return {"kind": "hysteresis", "friction_coefficient": MU, "peak_force": PEAK, "steps": steps,
            "inputs": {"body1": {"E": E, "nu": NU}, "body2": body2, **inputs}}


def test_mindlin_reference_matches_the_closed_forms():
    ref = mindlin_reference(_summary())
    a = math.sqrt(AREA / math.pi)
    k = mindlin_compliance_k(E, NU, E, NU)
    assert ref["radius"] == pytest.approx(a, rel=1e-15)
    assert ref["compliance"] == pytest.approx(k, rel=1e-12)
    assert ref["delta0"] == pytest.approx(mindlin_delta0(P=P, a=a, mu=MU, k=k), rel=1e-12)
    assert ref["energy"] == pytest.approx(mindlin_loop_energy(PEAK, P=P, a=a, mu=MU, k=k), rel=1e-12)
    assert ref["mu_p"] == MU * P and ref["peak"] == PEAK and ref["offset"] == 0.0
    assert loop_reference(_summary())["name"] == "Mindlin-Deresiewicz"
    assert kl_reference(_summary()) == ("Mindlin-Deresiewicz", "")


def test_no_reference_where_it_does_not_apply():
    assert loop_rows(_summary(rows=2)) == [] and mindlin_reference(_summary(rows=2)) is None
    rough = _summary()
    rough["inputs"]["body1"]["roughness"] = {"kind": "gaussian", "rms": 1e-9}
    assert mindlin_reference(rough) is None
    dissimilar = _summary()
    dissimilar["inputs"]["body1"]["E"] = 70e9
    assert mindlin_reference(dissimilar) is None  # Dundurs' beta != 0
    beyond = dict(_summary(), peak_force=MU * P)
    assert mindlin_reference(beyond) is None  # gross slip: no partial-slip loop
    flat = _summary(shape={"kind": "flat"})
    assert loop_reference(flat) is None and kl_reference(flat)[0] is None


def test_the_outputs_use_these_functions():
    import tribobem.output.figures as figures
    import tribobem.output.report as report

    for name in ("mindlin_reference", "loop_reference", "kl_reference", "kl_reference_values"):
        assert getattr(figures, name) is getattr(friction_loops, name)
    assert report.kl_reference is friction_loops.kl_reference
