"""Scenario schema (file-contract keys, clear errors), scenario -> problem, and runs of each kind."""

import copy
import math

import numpy as np
import pytest

from tribobem.data import topography_path
from tribobem.errors import InputError, TopographyError
from tribobem.scenario import (
    IMPLEMENTED_KINDS,
    KINDS,
    NotImplementedKindError,
    ScenarioError,
    build_problem,
    load_scenario,
    parse_scenario,
    run_scenario,
)

#: The measured Park AFM scan shipped with tribobem (tribobem.data; no skip: it is always there).
PARK = topography_path("example_ps.tiff")

BASE = {
    "kind": "normal",
    "grid": {"n": 16, "size": "0.5 um", "periodic": False},
    "body1": {"E": "130 GPa", "nu": 0.28},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
    "load": {"force": "1 uN"},
}


def scenario(**changes):
    d = copy.deepcopy(BASE)
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


# ----------------------------------------------------------------------------- the 9.1 key set
FULL_91 = """
kind = "normal"
[grid]
n = 16
size = "2 um"
periodic = false
[body1]
E = "130 GPa"
nu = 0.28
roughness = { kind = "gaussian", rms = "1 nm", correlation_length = "50 nm", seed = 1 }
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[load]
force = "10 uN"
[adhesion]
model = "dugdale"
work_of_adhesion = "50 mJ/m^2"
z0 = "0.2 nm"
[friction]
coefficient = 0.2
tangential_forces = ["0 uN", "1 uN"]
path = { control = "force", amplitude = 0.999, cycles = 3, steps = 80 }
[humidity]
rh = [0.3, 0.5, 0.7, 0.9]
[solver]
tolerance = 1e-10
max_iterations = 10000
"""


def test_every_91_key_is_accepted_and_converted_to_si():
    import tomllib

    from tribobem.scenario.schema import Scenario

    # Every key of the file format in one document: each section validates on its own (no one
    # kind reads them all, so the whole is checked section by section).
    data = tomllib.loads(FULL_91)
    sc = Scenario.model_construct(**{name: Scenario.model_fields[name].annotation.__args__[0].model_validate(value)
                                     if name in ("friction", "humidity") else
                                     Scenario.model_fields[name].annotation.model_validate(value)
                                     for name, value in data.items() if name != "kind"})
    assert sc.grid.shape == (16, 16) and sc.grid.lengths == (2e-6, 2e-6)
    assert sc.body1.E == 130e9 and sc.body1.roughness.rms == 1e-9
    assert sc.body2.rigid and sc.body2.shape.radius == 1e-5
    assert sc.load.force == 1e-5
    assert sc.adhesion.work_of_adhesion == pytest.approx(0.05) and sc.adhesion.z0 == pytest.approx(2e-10)
    assert sc.friction.tangential_forces == [0.0, 1e-6] and sc.friction.path.cycles == 3
    assert sc.humidity.rh == [0.3, 0.5, 0.7, 0.9]
    assert sc.solver.tolerance == 1e-10 and sc.solver.max_iterations == 10000


@pytest.mark.parametrize("kind", KINDS)
def test_a_kind_refuses_what_it_does_not_read(kind):
    """Each section and key of the 9.1 set that a kind does not read is an error naming it (never
    silently dropped); the keys it reads pass that check."""
    import tomllib

    from tribobem.runs import KINDS as REGISTRY

    reads = REGISTRY[kind].reads()
    full = tomllib.loads(FULL_91)
    for section in ("load", "adhesion", "friction", "humidity", "solver"):
        if section not in reads:
            d = scenario(kind=kind, **KIND_EXTRAS.get(kind, {}))
            d[section] = full[section]
            with pytest.raises(ScenarioError) as exc:
                parse_scenario(d)
            assert exc.value.field == section
            assert f"kind = {kind!r} does not use [{section}]" in str(exc.value)
    for body in ("body1", "body2"):
        for key, value in (("film", {"isotherm": "SiO2"}), ("hamaker", "6.5e-20 J")):
            if key not in reads[body]:
                with pytest.raises(ScenarioError) as exc:
                    parse_scenario(scenario(kind=kind, **KIND_EXTRAS.get(kind, {}), **{f"{body}__{key}": value}))
                assert exc.value.field == f"{body}.{key}" and "does not use it" in str(exc.value)
    if "preload" not in reads["load"]:  # an ignored key among used ones
        with pytest.raises(ScenarioError) as exc:
            parse_scenario(scenario(kind=kind, **KIND_EXTRAS.get(kind, {}), load__preload="1 uN"))
        assert exc.value.field == "load.preload" and f"kind = {kind!r} does not use it" in str(exc.value)


@pytest.mark.parametrize("kind, extra", [("partial_slip", {}), ("hysteresis", {"friction__path": {
    "control": "force", "amplitude": 0.5, "cycles": 1, "steps": 8}})])
def test_humidity_under_a_friction_kind_is_humid_friction(kind, extra):
    """[humidity] and films on a friction kind are read (humid friction), not ignored; without
    rh the section is refused by name."""
    d = scenario(kind=kind, friction={"coefficient": 0.3}, humidity={"rh": [0.3, 0.7]},
                 body1__film={"isotherm": "SiO2"}, **extra)
    sc = parse_scenario(d)
    assert sc.humidity.rh == [0.3, 0.7] and sc.body1.film is not None
    d["humidity"] = {"van_der_waals": False}
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(d)
    assert exc.value.field == "humidity.rh"


@pytest.mark.parametrize(
    "rough, parsed",
    [
        ({"kind": "none"}, {}),
        ({"kind": "self_affine", "hurst": 0.8, "rms": "1 nm", "rolloff": "100 nm", "short_cutoff": "10 nm", "seed": 2},
         {"hurst": 0.8, "rms": 1e-9, "rolloff": 1e-7, "short_cutoff": 1e-8, "seed": 2, "rms_slope": None}),
        ({"kind": "self_affine", "hurst": 0.8, "rms_slope": 0.1}, {"hurst": 0.8, "rms_slope": 0.1, "rms": None}),
        ({"kind": "file", "path": "x.tiff", "detrend": "height", "crop": {"x0": 0, "y0": 0, "lx": "0.5 um", "ly": "0.5 um"}},
         {"path": "x.tiff", "detrend": "height", "crop.x0": 0.0, "crop.y0": 0.0, "crop.lx": 5e-7, "crop.ly": 5e-7}),
        ({"kind": "array", "path": "h.npy", "size": "1 um"}, {"path": "h.npy", "size": 1e-6}),
    ],
)
def test_roughness_kinds_validate(rough, parsed):
    r = parse_scenario(scenario(body1__roughness=rough)).body1.roughness
    assert r.kind == rough["kind"]
    for key, value in parsed.items():  # in SI units
        obj = r
        for part in key.split("."):
            obj = getattr(obj, part)
        assert obj == (pytest.approx(value, rel=1e-12) if isinstance(value, float) else value), key


@pytest.mark.parametrize(
    "shape, parsed",
    [
        ({"kind": "flat"}, {}),
        ({"kind": "sphere", "radius": "1 um", "exact": True}, {"radius": 1e-6, "exact": True}),
        ({"kind": "cylinder", "radius": "1 um", "axis": "x"}, {"radius": 1e-6, "axis": "x"}),
        ({"kind": "wavy_sphere", "radius": "1 um", "amplitude": "1 nm", "wavelength": "50 nm"},
         {"radius": 1e-6, "amplitude": 1e-9, "wavelength": 5e-8}),
        ({"kind": "bisinusoidal", "amplitude": "1 nm", "wavelength_x": "0.5 um", "wavelength_y": "0.5 um"},
         {"amplitude": 1e-9, "wavelength_x": 5e-7, "wavelength_y": 5e-7}),
    ],
)
def test_shape_kinds_validate(shape, parsed):
    sh = parse_scenario(scenario(body2__shape=shape)).body2.shape
    assert sh.kind == shape["kind"]
    for key, value in parsed.items():  # in SI units
        got = getattr(sh, key)
        assert got == (pytest.approx(value, rel=1e-12) if isinstance(value, float) else value), key


#: What each kind needs on top of BASE to be a complete scenario.
KIND_EXTRAS = {
    "pulloff": {"load": {"preload": "1 uN"}, "adhesion": {"work_of_adhesion": 0.05, "z0": 3e-10}},
    "partial_slip": {"friction": {"coefficient": 0.2}},
    "hysteresis": {"friction": {"coefficient": 0.2, "path": {"control": "force", "cycles": 1, "steps": 8}}},
    "capillary": {"humidity": {"rh": [0.5]}},
}


@pytest.mark.parametrize("kind", KINDS)
def test_all_kinds_are_accepted(kind):
    extra = KIND_EXTRAS.get(kind, {})
    assert parse_scenario(scenario(kind=kind, **extra)).kind == kind


def test_ranges_and_lists():
    sc = parse_scenario(scenario(load__force=None, load__forces={"start": "1 uN", "stop": "3 uN", "num": 3}))
    assert sc.load.forces == [1e-6, 2e-6, 3e-6]
    sc = parse_scenario(scenario(grid__n=None, grid__nx=16, grid__ny=32, grid__size=None, grid__lx=1e-6, grid__ly=2e-6))
    assert sc.grid.shape == (16, 32) and sc.grid.lengths == (1e-6, 2e-6)
    assert parse_scenario(scenario(body1__E="inf", body2={"E": "1 GPa", "nu": 0.5})).body1.rigid


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize(
    "changes, field, words",
    [
        ({"grid__foo": 1}, "grid.foo", ["unknown key", "allowed keys in [grid]", "n, nx, ny, size, lx, ly, periodic"]),
        ({"colour": "red"}, "colour", ["unknown key", "kind", "grid", "body1"]),
        ({"body1__roughness": {"kind": "gaussian", "rms": "1 nm", "correlation_length": "5 nm", "sed": 1}},
         "body1.roughness.sed", ["unknown key", "seed"]),
        ({"load__force": "3 nm"}, "load.force", ["expected a force (N), got '3 nm'"]),
        ({"body2__shape": {"kind": "sphere", "radius": "2 GPa"}}, "body2.shape.radius", ["expected a length"]),
        ({"body1__nu": 0.7}, "body1.nu", ["(-1, 0.5]", "0.7"]),
        ({"body1__E": "-3 GPa"}, "body1.E", ["> 0 Pa"]),
        ({"body1__E": None}, "body1.E", ["required", "rigid = true"]),
        ({"body1__nu": None}, "body1.nu", ["required"]),
        ({"grid__n": 4}, "grid.n", [">= 8"]),
        ({"grid__n": 8.5}, "grid.n", ["integer"]),
        ({"grid__periodic": "yes"}, "grid.periodic", ["true or false"]),
        ({"humidity": {"rh": [0.5, 1.5]}}, "humidity.rh[1]", ["(0, 1]"]),
        ({"kind": "sliding"}, "kind", ["normal", "pulloff"]),
        ({"body1__roughness": {"kind": "fractal"}}, "body1.roughness.kind", ["gaussian", "self_affine"]),
        ({"load__force": -1e-6}, "load.force", ["> 0 N without adhesion"]),
        ({"load__approach": 1e-9}, "load", ["exactly one of force, approach"]),
        ({"load__forces": [1e-6, "2 uN", "1 nm"]}, "load.forces", ["item 2", "expected a force"]),
        ({"adhesion": {"model": "dugdale", "z0": "0.3 nm"}}, "adhesion.work_of_adhesion", ["required"]),
        ({"kind": "pulloff", "load": {}}, "adhesion.model", ["needs adhesion"]),
        ({"body1": {"rigid": True}}, "body2.rigid", ["both bodies are rigid"]),
        ({"solver": {"tolerance": 0}}, "solver.tolerance", ["(0, 1)"]),
        ({"grid": 64}, "grid", ["table"]),
    ],
)
def test_schema_errors_name_the_key(changes, field, words):
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(**changes), source="s.toml")
    msg = str(exc.value)
    assert exc.value.field.startswith(field), msg
    for w in words:
        assert w in msg, msg
    assert "\n" not in msg
    assert isinstance(exc.value, InputError)


def test_several_errors_are_listed_together():
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(grid__foo=1, body1__nu=2.0))
    assert len(exc.value.errors) == 2
    assert "grid.foo" in str(exc.value) and "body1.nu" in str(exc.value)


def test_invalid_toml_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("kind = \n")
    with pytest.raises(InputError, match="not valid TOML"):
        load_scenario(bad)
    with pytest.raises(FileNotFoundError):
        load_scenario(tmp_path / "nope.toml")


# ----------------------------------------------------------------------------- build
def test_build_sphere_gap_and_operator():
    sc = parse_scenario(scenario(adhesion={"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"}))
    pb = build_problem(sc)
    assert pb.grid.shape == (16, 16) and not pb.grid.periodic
    assert pb.gap.min() == 0.0 and pb.gap.shape == (16, 16)
    assert pb.pair.effective_modulus == pytest.approx(130e9 / (1 - 0.28**2))
    assert pb.interaction is not None and pb.info["tabor_parameter"] > 0
    assert "DC-FFT" in pb.operator.kind


def test_roughness_closes_the_gap_on_either_body():
    rough = {"kind": "gaussian", "rms": "1 nm", "correlation_length": "50 nm", "seed": 3}
    g1 = build_problem(parse_scenario(scenario(body2__shape={"kind": "flat"}, body1__roughness=rough))).gap
    g2 = build_problem(parse_scenario(scenario(body2__shape={"kind": "flat"}, body2__roughness=rough))).gap
    np.testing.assert_allclose(g1, g2)  # heights are "toward the counter-surface" on both bodies
    assert g1.std() == pytest.approx(1e-9, rel=1e-6)


def test_array_roughness_relative_to_the_scenario_file(tmp_path):
    rng = np.random.default_rng(0)
    np.save(tmp_path / "h.npy", rng.normal(size=(16, 16)))  # in nm
    path = tmp_path / "s.toml"
    path.write_text(
        '[grid]\nn = 16\nperiodic = true\n'
        '[body1]\nE = "70 GPa"\nnu = 0.17\nroughness = { kind = "array", path = "h.npy", size = "1 um", unit = "nm" }\n'
        '[body2]\nrigid = true\n[load]\napproach = "1 nm"\n'
    )
    sc, base = load_scenario(path)
    assert base == tmp_path.resolve()
    pb = build_problem(sc, base)
    assert pb.grid.lx == pytest.approx(1e-6)  # size taken from the array section
    assert 1e-10 < pb.roughness1.std() < 1e-8
    with pytest.raises(FileNotFoundError, match="body1.roughness.path"):
        build_problem(parse_scenario(scenario(body1__roughness={"kind": "array", "path": "missing.npy", "size": 1e-6})), tmp_path)


def test_grid_size_is_required_without_a_file():
    with pytest.raises(InputError, match="grid.size"):
        build_problem(parse_scenario(scenario(grid__size=None)))


def test_file_roughness_from_the_park_scan():
    sc = parse_scenario(scenario(grid__size=None, body1__roughness={"kind": "file", "path": str(PARK)}))
    pb = build_problem(sc)
    assert pb.grid.lx == pytest.approx(1e-6)  # the scan's size
    assert pb.info["files"]["body1.roughness"]["scan_grid"] == [512, 512]
    assert 1e-9 < pb.roughness1.std() < 1e-8


def test_unreadable_topography_names_the_key(tmp_path):
    bad = tmp_path / "bad.tiff"
    bad.write_bytes(b"not a tiff at all")
    sc = parse_scenario(scenario(body1__roughness={"kind": "file", "path": "bad.tiff"}))
    with pytest.raises(TopographyError, match="body1.roughness"):
        build_problem(sc, tmp_path)


def test_memory_budget_is_checked_before_allocating():
    from tribobem.errors import MemoryBudgetError

    with pytest.raises(MemoryBudgetError):
        build_problem(parse_scenario(scenario(grid__n=2**17)))


# ----------------------------------------------------------------------------- runs
STEP_KEYS = ("normal_force", "approach", "contact_area", "repulsive_force", "adhesive_force", "adhesive_area",
             "max_pressure", "mean_gap", "iterations", "residual", "converged")


def test_run_single_force_hertz_like():
    r = run_scenario(scenario(grid__n=32), progress=False)
    assert r.outdir is None and r.converged
    (step,) = r.steps
    assert set(STEP_KEYS) <= set(step)
    assert step["normal_force"] == pytest.approx(1e-6, rel=1e-6)
    # Hertz contact radius to a few cells on this coarse grid
    a_hertz = (3 * 1e-6 * 1e-5 / (4 * r.problem.pair.effective_modulus)) ** (1 / 3)
    assert math.sqrt(step["contact_area"] / math.pi) == pytest.approx(a_hertz, rel=0.15)
    assert r.fields.sizes == {"step": 1, "x": 32, "y": 32}


def test_run_approach_list_with_unloading_and_progress_callback():
    calls = []
    sc = scenario(grid__periodic=True, body2__shape={"kind": "flat"}, load__force=None,
                  body1__roughness={"kind": "gaussian", "rms": "1 nm", "correlation_length": "60 nm", "seed": 1},
                  load__approaches=["0.5 nm", "1 nm", "2 nm"], load__unload=True)
    r = run_scenario(sc, progress=lambda d, t: calls.append((d, t)))
    assert [s["branch"] for s in r.steps] == ["loading"] * 3 + ["unloading"] * 3
    assert calls and calls[-1][0] == calls[-1][1] == 6
    f = [s["normal_force"] for s in r.steps]
    assert f[0] < f[1] < f[2]
    assert "hysteresis_energy" in r.summary
    assert list(r.fields["label"].values[:2]) == ["loading 0", "loading 1"]


def test_run_pulloff_smooth_sphere():
    sc = {
        "kind": "pulloff",
        "grid": {"n": 32, "size": "0.4 um"},
        "body1": {"E": "5 GPa", "nu": 0.0},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}},
        "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.5 nm"},
        "load": {"preload": "0.3 uN", "steps": 10, "refine": 2},
        "solver": {"tolerance": 1e-8},
    }
    r = run_scenario(sc, progress=False)
    po = r.summary["pull_off_force"]
    # Maugis-Dugdale (lambda ~ 1.07): -0.25 uN; the coarse grid overestimates the cohesive zone
    assert -0.5e-6 < po < -0.15e-6
    assert {s["branch"] for s in r.steps} == {"loading", "unloading"}
    assert list(r.fields["label"].values) == ["preload", "pull-off"]
    assert r.summary["problem"]["maugis_parameter"] == pytest.approx(1.07, rel=0.01)


def test_run_pulloff_force_control_labels_the_unloading_branch():
    sc = {
        "kind": "pulloff",
        "grid": {"n": 24, "size": "0.4 um"},
        "body1": {"E": "5 GPa", "nu": 0.0},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}},
        "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.5 nm"},
        "load": {"preload": "0.3 uN", "steps": 8, "control": "force", "loading": False},
    }
    r = run_scenario(sc, progress=False)
    assert {s["branch"] for s in r.steps} == {"unloading"}
    assert r.summary["pull_off_force"] < 0 and r.summary["pull_off_control"] == "force"
    assert any(j["kind"] == "jump-off" for j in r.summary["jumps"])


def test_output_fields_last_keeps_the_most_loaded_step():
    r = run_scenario(scenario(load__force=None, load__forces=["2 uN", "3 uN", "1 uN"], output={"fields": "last"}),
                     progress=False)
    assert r.fields.sizes["step"] == 1
    assert float(r.fields["normal_force"].values[0]) == pytest.approx(3e-6)
    assert int(r.fields["summary_step"].values[0]) == 1


def test_kinds_come_from_the_registry():
    """The schema's kinds are the registry's: a kind is accepted exactly when it can run."""
    from tribobem.runs import KINDS as REGISTRY

    assert KINDS == tuple(REGISTRY) == IMPLEMENTED_KINDS
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(kind="sliding"))
    assert exc.value.field == "kind" and all(k in str(exc.value) for k in REGISTRY)
    with pytest.raises(NotImplementedKindError, match="not implemented yet in this version"):
        from tribobem.runs import get_runner

        get_runner("sliding")


def test_nonconvergence_is_reported_not_silent():
    sc = scenario(grid__n=32, solver={"max_iterations": 2, "tolerance": 1e-14})
    with pytest.warns(Warning, match="did not converge"):
        r = run_scenario(sc, progress=False)
    assert r.summary["converged"] is False
    assert r.summary["warnings"]
    assert r.steps[0]["converged"] is False


def test_values_that_would_be_ignored_are_refused():
    # rigid = true with a Poisson ratio: nu would be dropped
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(body2__nu=0.3))
    assert exc.value.field == "body2.nu" and "rigid" in str(exc.value)
    # a spectral kernel on a free-boundary grid: the free grid always uses influence coefficients
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(solver__kernel="spectral"))
    assert exc.value.field == "solver.kernel" and "periodic" in str(exc.value)
    assert parse_scenario(scenario(solver__kernel="influence")).solver.kernel == "influence"
    assert parse_scenario(scenario(grid__periodic=True, solver__kernel="spectral")).solver.kernel == "spectral"
    # a single load with unload = true: no unloading branch to trace
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(load__unload=True))
    assert exc.value.field == "load.unload"
    # a humid pull-off under force control: it unloads under displacement control only
    def humid(**changes):
        return scenario(kind="pulloff", load={"preload": "1 uN"}, humidity={"rh": [0.5]}, **changes)

    with pytest.raises(ScenarioError) as exc:
        parse_scenario(humid(load__control="force"))
    assert exc.value.field == "load.control"
    assert parse_scenario(humid(load__loading=False)).load.loading is False
    with pytest.raises(ScenarioError) as exc:  # films on a dry pull-off
        parse_scenario(scenario(kind="pulloff", load={"preload": "1 uN"},
                                adhesion={"work_of_adhesion": 0.05, "z0": 3e-10}, body1__film={"isotherm": "SiO2"}))
    assert exc.value.field == "body1.film" and "humid pull-off only" in str(exc.value)


def test_an_expected_value_the_kind_does_not_produce_is_refused():
    """expected keys come from what each kind declares it produces; one the kind never writes
    could never be compared, so it is an error naming it, not a silent 'not computed'."""
    exp = {"static_friction_ratio": 0.9, "reference": "Paper D", "tolerance": "1 %"}
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(scenario(expected=exp))
    assert exc.value.field == "expected.static_friction_ratio"
    assert "kind = 'normal' does not produce it" in str(exc.value) and "'partial_slip'" in str(exc.value)
    ok = parse_scenario(scenario(kind="partial_slip", friction={"coefficient": 0.2}, expected=exp))
    assert ok.expected.values == {"static_friction_ratio": 0.9}
    # a step key every kind writes
    parse_scenario(scenario(expected={"contact_area": "1 um^2", "reference": "Hertz", "tolerance": "3 %"}))
