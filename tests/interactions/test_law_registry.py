"""The stress-law registry (interactions/registry.py): a law is its module, its spec and one
registry line.

The law below exists only in this file (a uniform tension t on every node outside the contact)
and runs end to end through ``tribobem run`` without any other change to the package.  On a
periodic grid the mean pressure carries no displacement (the operator's q = 0 mode is 0), so the
contact under that law at a force F is the non-adhesive contact at F + t A (A the cell's area)
with every pressure lowered by t: the test checks the run against that independent solve.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Literal

import pytest
from typer.testing import CliRunner

from tribobem.cli import app
from tribobem.interactions.base import NoInteraction, law_result_checks, law_summary_info, law_windowable
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.interactions.registry import LAWS, get_law, register_law, unregister_law
from tribobem.scenario.schema import AdhesionSpec, Quantity, ScenarioError, parse_scenario

TENSION = 1.0e6  # Pa
SIDE = 1.0e-6  # m: the periodic cell


# ----------------------------------------------------------------------------- the test-only law
@dataclass(frozen=True)
class UniformTension:
    """A tension ``t`` (Pa) on every non-contact node, whatever its gap (its limit at 0+ too)."""

    tension: float

    report_rows = (("uniform_tension", "uniform tension t", "pressure"),)

    @classmethod
    def from_spec(cls, spec, context=None) -> "UniformTension":
        return cls(spec.tension)

    @property
    def floor(self) -> float:
        return -self.tension

    def outside_stress(self, gap, xp):
        return xp.full_like(gap, -self.tension)

    def summary_info(self, radius=None, effective_modulus=None) -> dict:
        return {"uniform_tension": self.tension}


class UniformTensionSpec(AdhesionSpec):
    """``[adhesion] model = "test_tension"``: ``tension`` (Pa, > 0)."""

    model: Literal["test_tension"] = "test_tension"
    tension: Quantity("pressure", gt=0)


@pytest.fixture
def tension_law():
    entry = register_law("test_tension", UniformTensionSpec, UniformTension)  # the one registry line
    yield entry
    unregister_law("test_tension")


# ----------------------------------------------------------------------------- scenario helpers
def _scenario(path, force: float, adhesion: str) -> None:
    path.write_text(f"""
kind = "normal"
[grid]
n = 32
size = {SIDE!r}
periodic = true
[body1]
E = "1 GPa"
nu = 0.3
shape = {{ kind = "bisinusoidal", amplitude = "10 nm" }}
[body2]
rigid = true
[load]
force = {force!r}
{adhesion}
[solver]
method = "polonsky_keer"
tolerance = 1e-12
[output]
fields = "none"
figures = false
report = true
""", encoding="utf-8")


def _run(tmp_path, name: str, force: float, adhesion: str = "") -> dict:
    toml = tmp_path / f"{name}.toml"
    _scenario(toml, force, adhesion)
    out = tmp_path / name
    r = CliRunner().invoke(app, ["run", str(toml), "--out", str(out), "--quiet"])
    assert r.exit_code == 0, r.output
    return json.loads((out / "summary.json").read_text(encoding="utf-8")) | {"_out": str(out)}


# ----------------------------------------------------------------------------- tests
def test_a_law_defined_in_a_test_runs_through_tribobem_run(tmp_path, tension_law):
    force = 2.0e-6  # N
    law = _run(tmp_path, "tension", force, f'[adhesion]\nmodel = "test_tension"\ntension = "{TENSION:g} Pa"')
    # the reference: no stress law, the force raised by the tension on the whole cell
    ref = _run(tmp_path, "reference", force + TENSION * SIDE**2)

    assert law["inputs"]["adhesion"] == {"model": "test_tension", "tension": TENSION}
    assert law["problem"]["uniform_tension"] == TENSION  # its summary_info
    assert "sigma0" not in law["problem"] and "h0" not in law["problem"]
    s, r = law["steps"][-1], ref["steps"][-1]
    assert s["converged"] and r["converged"]
    assert 0.05 < r["contact_area"] / SIDE**2 < 0.9  # a partial contact: the check means something
    assert s["contact_area"] == pytest.approx(r["contact_area"], rel=1e-12)
    assert s["approach"] == pytest.approx(r["approach"], rel=1e-7)
    assert s["max_pressure"] == pytest.approx(r["max_pressure"] - TENSION, rel=1e-7)
    # its report row, declared by the law alone
    html = (tmp_path / "tension" / "report.html").read_text(encoding="utf-8")
    assert "uniform tension t" in html


def test_an_unknown_model_names_the_registered_laws(tension_law):
    data = {"grid": {"n": 16, "size": "1 um", "periodic": True}, "body1": {"E": "1 GPa", "nu": 0.3},
            "body2": {"rigid": True}, "load": {"force": "1 nN"}, "adhesion": {"model": "morse"}}
    with pytest.raises(ScenarioError) as err:
        parse_scenario(data)
    assert err.value.errors == [("adhesion.model", "must be one of 'none', 'dugdale', 'exponential', 'lennard_jones' "
                                                   "or 'test_tension', got 'morse'")]
    with pytest.raises(KeyError, match="'none', 'dugdale', 'exponential', 'lennard_jones' or 'test_tension'"):
        get_law("morse")


def test_the_registered_law_parses_with_its_own_keys(tension_law):
    base = {"grid": {"n": 16, "size": "1 um", "periodic": True}, "body1": {"E": "1 GPa", "nu": 0.3},
            "body2": {"rigid": True}, "load": {"force": "1 nN"}}
    sc = parse_scenario({**base, "adhesion": {"model": "test_tension", "tension": "2 kPa"}})
    assert isinstance(sc.adhesion, UniformTensionSpec) and sc.adhesion.tension == 2000.0 and sc.adhesion.enabled
    with pytest.raises(ScenarioError) as err:
        parse_scenario({**base, "adhesion": {"model": "test_tension", "z0": "1 nm"}})
    assert ("adhesion.z0", "unknown key; allowed keys in [adhesion]: model, tension") in err.value.errors
    with pytest.raises(ScenarioError) as err:
        parse_scenario({**base, "adhesion": {"model": "test_tension"}})
    assert err.value.errors == [("adhesion.tension", "required")]


def test_unregistered_laws_are_gone_and_the_builtins_stay():
    assert list(LAWS)[:2] == ["none", "dugdale"] and "test_tension" not in LAWS
    with pytest.raises(ValueError, match="registered already"):
        register_law("dugdale", LAWS["dugdale"].spec, DugdaleAdhesion)
    with pytest.raises(ValueError, match="Literal"):
        register_law("mismatch", UniformTensionSpec, UniformTension)
    assert "mismatch" not in LAWS


def test_the_builtin_laws_declare_their_capabilities():
    ad = DugdaleAdhesion(0.05, 0.3e-9)
    assert law_windowable(ad) and law_windowable(NoInteraction()) and law_windowable(None)
    assert not law_windowable(UniformTension(1.0))  # a law that does not say: no window
    assert law_result_checks(ad) == {"cohesive_zone", "cohesive_range", "cohesive_edge"}
    assert law_result_checks(None) == law_result_checks(NoInteraction()) == law_result_checks(UniformTension(1.0)) == set()
    info = law_summary_info(ad, 1e-6, 1e9)
    assert list(info) == ["sigma0", "h0", "tabor_parameter", "maugis_parameter"]
    assert info["sigma0"] == ad.sigma0 and info["maugis_parameter"] == ad.maugis_parameter(1e-6, 1e9)
    assert list(law_summary_info(ad, None, 1e9)) == ["sigma0", "h0"] and law_summary_info(None) == {}
    # the dugdale builder and the none law's (no law at all)
    spec = parse_scenario({"grid": {"n": 16, "size": "1 um"}, "body1": {"E": "1 GPa", "nu": 0.3},
                           "body2": {"rigid": True}, "load": {"force": "1 nN"},
                           "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"}}).adhesion
    assert get_law(spec.model).build(spec, None) == DugdaleAdhesion(0.05, 0.3e-9)
    assert get_law("none").build(parse_scenario({"grid": {"n": 16, "size": "1 um"},
                                                 "body1": {"E": "1 GPa", "nu": 0.3}, "body2": {"rigid": True},
                                                 "load": {"force": "1 nN"}}).adhesion, None) is None
