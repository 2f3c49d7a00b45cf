"""Validation physics ``humid_friction`` (src/tribobem/validation/humid_friction.py) and the
reliability checks of humid friction: RH = 1 with an open equilibrium film, mu = 0."""

from __future__ import annotations

import math

import pytest

from tribobem.errors import InputError
from tribobem.scenario import run_scenario
from tribobem.validation import PHYSICS, PHYSICS_CASES, run_validation
from tribobem.validation import humid_friction as hf
from tribobem.validation.gate import GATE

CASES = tuple(hf.CASES)


def test_registered_and_gated():
    assert "humid_friction" in PHYSICS and PHYSICS_CASES["humid_friction"] == CASES
    assert all(GATE[name] == "full" for name in CASES)


@pytest.mark.parametrize("name", CASES)
def test_quick_rows_pass(name):
    """Every quick row passes and states a finite, explicit tolerance (inf only on the report
    rows of the coupled onset)."""
    rows = run_validation(cases=[name], level="quick")
    assert rows
    for r in rows:
        assert r.passed, (r.case, r.quantity, r.reference, r.computed, r.rel_error, r.tolerance)
        if name != "humid_coupled_onset":
            assert math.isfinite(r.tolerance), r.quantity


def test_dry_limit_is_sharp():
    """The 1e-9 rows compare two ramps that really differ when the law differs: with the
    capillary pressure on (contribution "none") the onset moves by far more than 1e-9."""
    from tribobem.runs.humid_friction import capillary_model

    pb = hf.problem(hf.scenario("partial_slip", 32, rh=[0.2], films=False, adhesion=True))
    model, _, _ = capillary_model(pb, 0.2, 1e-10)
    assert model.options["contribution"] == 1.0
    dry = hf.ramp(pb, pb.interaction)
    hum = hf.ramp(pb, model)
    assert abs(hum.onset - dry.onset) / dry.onset > 1e-3


def test_loop_balance_catches_a_wrong_work():
    """The exact discrete balance T = D + dU + path fails when the traction work misses a cycle's
    step (a bookkeeping error of the kind it guards)."""
    from tribobem.runs.humid_friction import capillary_model
    from tribobem.solvers.hysteresis import hysteresis_loop

    d = hf.scenario("hysteresis", 32, nu=0.5, rh=[0.5])
    pb = hf.problem(d)
    model, _, _ = capillary_model(pb, 0.5, 1e-10)
    run = hf._quiet(hysteresis_loop, pb.operator, pb.gap, normal_force=hf.FORCE, friction_coefficient=hf.MU,
                    amplitude=0.9, cycles=1, steps=16, interaction=model, tol=1e-10, tangential_tol=1e-8,
                    coupling_tol=1e-6)
    (b,) = hf.loop_balance(run, pb.operator)
    assert abs(b["area"] - (b["work"] + b["dU"] + b["path"])) <= 1e-9 * b["work"]
    assert b["path"] < 0  # q opposes the slip: the trapezoid loop area is below the traction work
    run.dissipation[1] = run.dissipation[1] * (15.0 / 16.0)  # one step's worth missing
    (bad,) = hf.loop_balance(run, pb.operator)
    assert abs(bad["area"] - (bad["work"] + bad["dU"] + bad["path"])) > 1e-3 * bad["work"]


# ------------------------------------------------------------------------------- reliability
def _rh1(kind: str) -> dict:
    d = hf.scenario(kind, 16, rh=[1.0])
    if kind == "capillary":
        d.pop("friction")
        d["load"] = {"force": "1 uN"}
    return d


@pytest.mark.parametrize("kind", ["partial_slip", "hysteresis"])
def test_rh1_open_film_is_the_capillary_error(kind):
    """RH = 1 with an open-system equilibrium film: the same InputError on humidity.rh as kind
    capillary, before any solve."""
    with pytest.raises(InputError) as ref:
        run_scenario(_rh1("capillary"), outdir=None, progress=False, quiet=True)
    with pytest.raises(InputError) as exc:
        run_scenario(_rh1(kind), outdir=None, progress=False, quiet=True)
    assert ref.value.field == exc.value.field == "humidity.rh"
    assert str(exc.value) == str(ref.value) and "RH = 1" in str(exc.value)


def test_mu0_partial_slip_is_frictionless_capillary_contact():
    """mu = 0 with [humidity] on partial_slip runs (no crash), and its F_t = 0 state's capillary
    force is kind capillary's at the same load and RH (1e-6)."""
    rh = 0.5
    d = hf.scenario("partial_slip", 32, rh=[rh])
    d["friction"] = {"coefficient": 0.0, "tangential_forces": [0.0, 0.1e-6]}
    s = run_scenario(d, outdir=None, progress=False, quiet=True).summary
    humid = [st for st in s["steps"] if st.get("rh") == rh]
    assert humid and humid[0]["tangential_force_x"] == 0.0
    cap = hf.scenario("partial_slip", 32, rh=[rh])
    cap["kind"] = "capillary"
    cap.pop("friction")
    c = run_scenario(cap, outdir=None, progress=False, quiet=True).summary
    ref = c["steps"][0]["capillary_force"]
    assert ref < 0
    assert humid[0]["capillary_force"] == pytest.approx(ref, rel=1e-6)
    assert humid[0]["normal_force"] == pytest.approx(hf.FORCE, rel=1e-8)
