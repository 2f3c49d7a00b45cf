"""Kinds partial_slip and hysteresis with [humidity] (humid friction), run from scenario dicts:
the file contract (rh on every step, capillary keys, run-level lists in RH order, the dry
reference), warm starts that do not change results, non-settling islands flagged, and the
counterface's film moving under gross sliding."""

import copy
import warnings

import numpy as np
import pytest

from tribobem.errors import ConvergenceWarning
from tribobem.scenario import run_scenario

BASE = {
    "kind": "partial_slip",
    "grid": {"n": 32, "size": "0.3 um"},
    "body1": {"E": "130 GPa", "nu": 0.28, "film": {"isotherm": "Si"}},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}, "film": {"isotherm": "SiO2"}},
    "load": {"force": "1 uN"},
    "friction": {"coefficient": 0.3, "tangential_forces": {"start": "0 uN", "stop": "1.5 uN", "num": 6},
                 "slip": "total"},
    "humidity": {"rh": [0.3, 0.7], "van_der_waals": False},
}
LOOP = {"coefficient": 0.3, "path": {"control": "force", "amplitude": 0.8, "cycles": 2, "steps": 12}}


def _run(d):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return run_scenario(d, outdir=None, progress=False, quiet=True).summary


@pytest.fixture(scope="module")
def ramp():
    return _run(BASE)


def test_humid_ramp_file_contract(ramp):
    s = ramp
    assert s["rh"] == [0.3, 0.7]
    for key in ("static_friction_force", "static_friction_ratio", "presliding_displacement",
                "onset_repulsive_force", "onset_adhesive_force"):
        assert isinstance(s[key], list) and len(s[key]) == 2, key
    rhs = [r["rh"] for r in s["steps"]]
    assert rhs == sorted(rhs) and set(rhs) == {0.3, 0.7}  # every step carries its RH, in the order given
    for r in s["steps"]:
        for key in ("capillary_force", "solid_solid_force", "water_solid_force", "wetted_area", "island_count"):
            assert key in r, key
        assert r["capillary_force"] < 0 and r["island_count"] >= 1
    dry = s["dry"]
    assert dry["onset_adhesive_force"] == 0.0  # no [adhesion]: the dry run is Hertz-Mindlin-like
    # the meniscus adds |F_cap| to the repulsive force; static friction follows mu F0+
    for k in range(2):
        f0p = s["onset_repulsive_force"][k]
        assert abs(f0p - (1e-6 - s["onset_adhesive_force"][k])) < 1e-9 * f0p
        assert s["static_friction_force"][k] > 2 * dry["static_friction_force"]
        assert abs(s["static_friction_force"][k] / (0.3 * f0p) - s["static_friction_ratio"][k]) < 1e-12


def test_warm_start_from_the_previous_rh_does_not_change_the_result(ramp):
    alone = _run({**copy.deepcopy(BASE), "humidity": {"rh": [0.7], "van_der_waals": False}})
    a, b = ramp["static_friction_force"][1], alone["static_friction_force"][0]
    # the onset is bisected to 1e-3 mu F0+: a different warm start may move it by one bracket
    assert abs(a - b) <= 1e-3 * 0.3 * alone["onset_repulsive_force"][0]
    assert abs(ramp["onset_repulsive_force"][1] / alone["onset_repulsive_force"][0] - 1) < 1e-6


def test_humid_loop_lists_per_rh():
    d = copy.deepcopy(BASE)
    d.update(kind="hysteresis", friction=LOOP)
    s = _run(d)
    assert len(s["dissipated_energy"]) == 2 and all(len(e) == 2 for e in s["dissipated_energy"])
    assert len(s["lateral_stiffness"]) == 2
    assert [p["point"] for p in s["lateral_stiffness"][0]] == ["A", "B", "C"]
    # a larger F0+ (meniscus) at the same amplitude fraction: a wider loop, more energy than dry
    assert min(s["dissipated_energy"][0]) > max(s["dry"]["dissipated_energy"])
    assert s["converged"]


def test_islands_that_cycle_flag_the_steps_and_the_run_goes_on(monkeypatch):
    import tribobem.solvers.capillary as capmod

    real = capmod.island_fixed_point

    def cycling(islands, step, max_outer):
        state, used, outer, _, history = real(islands, step, max_outer)
        return state, used, outer, "cycle", history

    monkeypatch.setattr(capmod, "island_fixed_point", cycling)
    d = copy.deepcopy(BASE)
    d["humidity"]["rh"] = [0.5]
    s = _run(d)
    assert not s["converged"]
    assert all(r["islands_converged"] is False and r["converged"] is False for r in s["steps"])
    assert any("did not converge" in w for w in s["warnings"])
    assert len(s["steps"]) >= 2  # the ramp went on


def test_counterface_film_moves_under_gross_sliding(monkeypatch):
    """Displacement cycles beyond the pre-sliding range: body 2 (the sphere and its film) moves by
    the accumulated gross-sliding offset."""
    from tribobem.solvers.capillary import CapillaryModel

    seen = []
    real = CapillaryModel.moved

    def spy(self, offset):
        seen.append(tuple(offset))
        return real(self, offset)

    monkeypatch.setattr(CapillaryModel, "moved", spy)
    d = copy.deepcopy(BASE)
    d["humidity"]["rh"] = [0.5]
    d.update(kind="hysteresis", friction={"coefficient": 0.3, "path": {"control": "displacement", "stroke": "2 nm",
                                                                         "cycles": 1, "steps": 12}})
    s = _run(d)
    assert s["counterface_offset_max"] > 0
    assert seen and max(np.hypot(*o) for o in seen) == pytest.approx(s["counterface_offset_max"], rel=1e-12)
