"""Scenario schema of the tangential kinds (file-contract: kind partial_slip and hysteresis, [friction])."""

import copy
import tomllib

import pytest

from tribobem.errors import InputError
from tribobem.scenario import ScenarioError, parse_scenario

HEAD = """
[grid]
n = 16
size = "2 um"
[body1]
E = "130 GPa"
nu = 0.28
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
"""

BASE = {
    "kind": "partial_slip",
    "grid": {"n": 16, "size": "2 um"},
    "body1": {"E": "130 GPa", "nu": 0.28},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
    "load": {"force": "10 uN"},
    "friction": {"coefficient": 0.2},
}

HYST = {"kind": "hysteresis",
        "friction": {"coefficient": 0.2, "path": {"control": "force", "amplitude": 0.999, "cycles": 3, "steps": 80}}}


def scenario(base=None, **changes):
    """BASE (or ``base`` merged over it) with ``section__key=value`` changes; None removes a key."""
    d = copy.deepcopy(BASE)
    for k, v in copy.deepcopy(base or {}).items():
        d[k] = v
    for dotted, value in changes.items():
        *path, key = dotted.split("__")
        node = d
        for p in path:
            node = node.setdefault(p, {})
        if value is None:
            node.pop(key, None)
        else:
            node[key] = value
    return d


def error_of(data) -> ScenarioError:
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(data, source="s.toml")
    assert isinstance(exc.value, InputError)
    assert "\n" not in str(exc.value)
    return exc.value


def check_error(data, field, words):
    err = error_of(data)
    assert err.field == field, str(err)
    for w in words:
        assert w in str(err), str(err)


# ----------------------------------------------------------------------------- the file-contract blocks
def test_spec_partial_slip_block():
    sc = parse_scenario(tomllib.loads('kind = "partial_slip"\n' + HEAD + """
[load]
force = "10 uN"
[friction]
coefficient = 0.2
tangential_forces = ["0 uN", "1 uN"]
direction = 0.0
slip = "total"
"""))
    fr = sc.friction
    assert sc.kind == "partial_slip" and sc.load.force == 1e-5
    assert fr.coefficient == 0.2 and fr.tangential_forces == [0.0, 1e-6]
    assert fr.direction == 0.0 and fr.slip == "total" and fr.tangential_displacements is None


def test_spec_hysteresis_blocks():
    force = parse_scenario(tomllib.loads('kind = "hysteresis"\n' + HEAD + """
[load]
force = "10 uN"
[friction]
coefficient = 0.2
path = { control = "force", amplitude = 0.999, cycles = 3, steps = 80 }
"""))
    p = force.friction.path
    assert (p.control, p.amplitude, p.cycles, p.steps, p.stroke) == ("force", 0.999, 3, 80, None)
    disp = parse_scenario(tomllib.loads('kind = "hysteresis"\n' + HEAD + """
[load]
force = "10 uN"
[friction]
coefficient = 0.2
path = { control = "displacement", stroke = "3 um", cycles = 4, steps = 80 }
"""))
    p = disp.friction.path
    assert (p.control, p.stroke, p.cycles, p.amplitude) == ("displacement", 3e-6, 4, None)


# ----------------------------------------------------------------------------- [friction] keys
def test_friction_defaults_and_units():
    sc = parse_scenario(scenario())
    assert sc.friction.direction == 0.0 and sc.friction.slip == "total"
    assert sc.friction.tangential_forces is None and sc.friction.tangential_displacements is None
    sc = parse_scenario(scenario(friction__tangential_forces={"start": "-1 uN", "stop": "1 uN", "num": 3}))
    assert sc.friction.tangential_forces == [-1e-6, 0.0, 1e-6]  # negative forces are allowed
    sc = parse_scenario(scenario(friction__tangential_displacements=["0 nm", "5 nm", -1e-9]))
    assert sc.friction.tangential_displacements == [0.0, 5e-9, -1e-9]
    sc = parse_scenario(scenario(friction__tangential_displacements={"start": 0, "stop": "2 nm", "num": 3}))
    assert sc.friction.tangential_displacements == [0.0, 1e-9, 2e-9]


def test_frictionless_is_allowed():
    assert parse_scenario(scenario(friction__coefficient=0)).friction.coefficient == 0.0


@pytest.mark.parametrize("raw, deg", [(30, 30.0), (-45.5, -45.5), ("30", 30.0), ("30 deg", 30.0),
                                      ("90°", 90.0), (f"{3.141592653589793 / 2} rad", 90.0)])
def test_direction_is_in_degrees(raw, deg):
    assert parse_scenario(scenario(friction__direction=raw)).friction.direction == pytest.approx(deg)


@pytest.mark.parametrize(
    "changes, field, words",
    [
        ({"friction__coefficient": -0.1}, "friction.coefficient", [">= 0", "-0.1"]),
        ({"friction__coefficient": "inf"}, "friction.coefficient", ["finite"]),
        ({"friction__tangential_forces": ["1 uN", "2 nm"]}, "friction.tangential_forces", ["item 1", "expected a force (N)"]),
        ({"friction__tangential_forces": {"start": 0, "stop": 1e-6}}, "friction.tangential_forces", ["start, stop, num"]),
        ({"friction__tangential_displacements": ["1 uN"]}, "friction.tangential_displacements",
         ["item 0", "expected a length (m)"]),
        ({"friction__direction": "inf"}, "friction.direction", ["finite"]),
        ({"friction__direction": "nan"}, "friction.direction", ["finite"]),
        ({"friction__direction": "3 nm"}, "friction.direction", ["angle in degrees"]),
        ({"friction__direction": "30 %"}, "friction.direction", ["angle in degrees"]),
        ({"friction__direction": True}, "friction.direction", ["angle in degrees"]),
        ({"friction__slip": "partial"}, "friction.slip", ["'total'", "'incremental'", "partial"]),
        ({"friction__mu": 0.2}, "friction.mu", ["unknown key", "coefficient", "tangential_displacements", "direction", "slip"]),
    ],
)
def test_friction_key_errors(changes, field, words):
    check_error(scenario(**changes), field, words)


@pytest.mark.parametrize(
    "path, field, words",
    [
        ({"control": "force", "amplitude": 0}, "friction.path.amplitude", ["(0, 1]"]),
        ({"control": "force", "amplitude": 1.5}, "friction.path.amplitude", ["(0, 1]", "1.5"]),
        ({"control": "force", "stroke": "3 um"}, "friction.path.stroke", ["control = 'displacement'", "amplitude in (0, 1]"]),
        ({"control": "displacement"}, "friction.path.stroke", ["required", "> 0 m"]),
        ({"control": "displacement", "stroke": "-3 um"}, "friction.path.stroke", ["> 0 m"]),
        ({"control": "displacement", "stroke": "3 uN"}, "friction.path.stroke", ["expected a length"]),
        ({"control": "displacement", "stroke": "3 um", "amplitude": 0.5}, "friction.path.amplitude",
         ["control = 'force'", "stroke > 0 m"]),
        ({"control": "force", "cycles": 0}, "friction.path.cycles", [">= 1"]),
        ({"control": "force", "steps": 1}, "friction.path.steps", [">= 2"]),
        ({"control": "velocity"}, "friction.path.control", ["'force'", "'displacement'"]),
        ({"control": "force", "turns": 3}, "friction.path.turns", ["unknown key", "amplitude, stroke, cycles, steps"]),
    ],
)
def test_path_errors(path, field, words):
    check_error(scenario(HYST, friction__path=path), field, words)


def test_path_defaults():
    sc = parse_scenario(scenario(HYST, friction__path={"control": "force"}))
    p = sc.friction.path
    assert (p.amplitude, p.cycles, p.steps) == (0.999, 1, 40)
    assert parse_scenario(scenario(HYST, friction__path={"stroke": "1 um", "control": "displacement"})
                          ).friction.path.stroke == 1e-6


# ----------------------------------------------------------------------------- kind = partial_slip
def test_partial_slip_load_variants():
    # a normal force held during a force ramp or a displacement ramp
    parse_scenario(scenario(friction__tangential_forces=["0 uN", "1 uN", "2 uN"]))
    parse_scenario(scenario(friction__tangential_displacements=["0 nm", "1 nm"]))
    # no tangential list: F_x = 0
    parse_scenario(scenario())
    # a normal-load path with friction (incremental), with or without a paired tangential list
    sc = parse_scenario(scenario(load={"forces": ["1 uN", "2 uN", "3 uN"]}, friction__slip="incremental",
                                 friction__tangential_forces=["0 uN", "0.1 uN", "0.2 uN"]))
    assert sc.load.forces == [1e-6, 2e-6, 3e-6] and len(sc.friction.tangential_forces) == 3
    parse_scenario(scenario(load={"forces": ["1 uN", "2 uN"]}, friction__slip="incremental"))
    with pytest.raises(ScenarioError, match="pairs with tangential_forces only"):
        parse_scenario(scenario(load={"forces": ["1 uN", "2 uN"]}, friction__slip="incremental",
                                friction__tangential_displacements=["0 nm", "1 nm"]))
    # one normal force in a list: the total criterion is fine (no history needed)
    parse_scenario(scenario(load={"forces": ["1 uN"]}, friction__tangential_forces=["0.1 uN"]))
    # with adhesion a tensile normal force is allowed
    parse_scenario(scenario(load__force="-0.1 uN", adhesion={"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"}))


@pytest.mark.parametrize(
    "changes, field, words",
    [
        ({"friction": None}, "friction.coefficient", ["required for kind = 'partial_slip'", "mu >= 0", "[friction]"]),
        ({"friction__coefficient": None, "friction__tangential_forces": [0, 1e-6]}, "friction.coefficient",
         ["required", "mu >= 0"]),
        ({"friction__tangential_forces": [0, 1e-6], "friction__tangential_displacements": [0, 1e-9]},
         "friction.tangential_displacements", ["at most one of tangential_forces", "tangential_displacements"]),
        ({"load": {"approach": "1 nm"}}, "load.approach", ["approach-controlled", "not supported", "load.force", "load.forces"]),
        ({"load": {"approaches": ["1 nm", "2 nm"]}}, "load.approaches", ["approach-controlled", "not supported"]),
        ({"load": {}}, "load.force", ["required for kind = 'partial_slip'", "load.forces"]),
        ({"load": {"force": "1 uN", "forces": ["1 uN", "2 uN"]}, "friction__slip": "incremental"}, "load.forces",
         ["one of load.force", "not both"]),
        ({"load": {"forces": ["1 uN", "2 uN"]}}, "friction.slip", ["'incremental'", "2 forces", "no history"]),
        ({"load": {"forces": ["1 uN", "2 uN"]}, "friction__slip": "total",
          "friction__tangential_forces": [0, 1e-7]}, "friction.slip", ["'incremental'", "no history"]),
        ({"load": {"forces": ["1 uN", "2 uN", "3 uN"]}, "friction__slip": "incremental",
          "friction__tangential_forces": [0, 1e-7]}, "friction.tangential_forces",
         ["paired step by step", "same length", "2 against 3"]),
        ({"load": {"forces": ["1 uN", "2 uN"]}, "friction__slip": "incremental",
          "friction__tangential_displacements": {"start": 0, "stop": 1e-9, "num": 5}},
         "friction.tangential_displacements", ["pairs with tangential_forces only"]),
        ({"friction__path": {"control": "force"}}, "friction.path",
         ["kind = 'partial_slip' does not use it", "used by kind 'hysteresis'"]),
        ({"load__force": "-1 uN"}, "load.force", ["> 0 N without adhesion"]),
        ({"load": {"forces": ["1 uN", "-1 uN"]}, "friction__slip": "incremental"}, "load.forces",
         ["> 0 N without adhesion"]),
    ],
)
def test_partial_slip_errors(changes, field, words):
    check_error(scenario(**changes), field, words)


# ----------------------------------------------------------------------------- kind = hysteresis
def test_hysteresis_variants():
    sc = parse_scenario(scenario(HYST))
    assert sc.kind == "hysteresis" and sc.friction.coefficient == 0.2
    p = sc.friction.path
    assert (p.control, p.amplitude, p.stroke, p.cycles, p.steps) == ("force", 0.999, None, 3, 80)
    assert parse_scenario(scenario(HYST, friction__slip="incremental")).friction.slip == "incremental"
    # frictionless under displacement control: a valid (trivial) loop
    sc = parse_scenario(scenario(HYST, friction__coefficient=0,
                                 friction__path={"control": "displacement", "stroke": "3 um", "cycles": 1, "steps": 4}))
    p = sc.friction.path
    assert sc.friction.coefficient == 0
    assert (p.control, p.amplitude, p.cycles, p.steps) == ("displacement", None, 1, 4)
    assert p.stroke == pytest.approx(3e-6, rel=1e-12)


@pytest.mark.parametrize(
    "changes, field, words",
    [
        ({"friction": None}, "friction.coefficient", ["required for kind = 'hysteresis'", "mu >= 0"]),
        ({"friction__coefficient": None}, "friction.coefficient", ["required for kind = 'hysteresis'"]),
        ({"friction__path": None}, "friction.path", ["required for kind = 'hysteresis'", "control"]),
        ({"load": {}}, "load.force", ["required for kind = 'hysteresis'", "> 0 N"]),
        ({"load": {"forces": ["1 uN", "2 uN"]}}, "load.forces", ["one normal force, load.force"]),
        ({"load": {"approach": "1 nm"}}, "load.approach", ["one normal force, load.force"]),
        ({"load__force": "-1 uN"}, "load.force", ["> 0 N without adhesion"]),
        ({"friction__tangential_forces": [0, 1e-6]}, "friction.tangential_forces",
         ["kind = 'hysteresis' does not use it", "friction.path"]),
        ({"friction__tangential_displacements": [0, 1e-9]}, "friction.tangential_displacements", ["does not use it"]),
        ({"friction__slip": "total"}, "friction.slip", ["'incremental'", "history"]),
        ({"friction__coefficient": 0}, "friction.coefficient", ["> 0 for a force-controlled path", "mu F0+"]),
    ],
)
def test_hysteresis_errors(changes, field, words):
    check_error(scenario(HYST, **changes), field, words)


# ----------------------------------------------------------------------------- other kinds
def test_a_friction_section_under_a_frictionless_kind_is_refused():
    # it used to be accepted and ignored: a user believed friction was applied
    for kind, extra in (("normal", {}), ("capillary", {"humidity": {"rh": [0.5]}})):
        with pytest.raises(ScenarioError, match=rf"friction: kind = '{kind}' does not use \[friction\]"):
            parse_scenario(scenario(kind=kind, friction={"tangential_forces": [0, 1e-6], "slip": "incremental"},
                                    **extra))
    assert parse_scenario(scenario(kind="normal", friction=None)).friction is None
