"""Run kind ``partial_slip`` (file-contract): small copies of examples/partial_slip_paper_d.toml.

* A tangential ramp written to disk: the summary.json step and run-level keys, the fields.nc
  friction variables, the stick/slip figures and the report.
* The example file itself: it validates, and (slow) its run-level values are consistent.
* A normal-load path with incremental friction, a ramp through a force beyond mu F0+, a single
  force beyond mu F0+, a displacement-controlled ramp.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from tribobem.scenario import parse_scenario, run_scenario
from tribobem.solvers.coupling import solve_coupled

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "partial_slip_paper_d.toml"
MU = 0.2
F0 = 10e-6  # normal force of the example (N)
CAP = MU * F0  # mu F0+ without adhesion (N)

STEP_KEYS = ("tangential_force_x", "tangential_force_y", "displacement_x", "displacement_y", "stick_area",
             "slip_area", "stick_ratio", "coupling_iterations", "tangential_iterations")
RUN_KEYS = ("friction_coefficient", "static_friction_force", "static_friction_ratio", "presliding_displacement")


def example() -> dict:
    return tomllib.loads(EXAMPLE.read_text())


def scenario(n=32, **changes) -> dict:
    """The example with grid n and changes given as section__key=value (None deletes)."""
    sc = copy.deepcopy(example())
    sc["grid"]["n"] = n
    for k, v in changes.items():
        sec, key = k.split("__")
        if v is None:
            sc[sec].pop(key, None)
        else:
            sc[sec][key] = v
    return sc


# ----------------------------------------------------------------------------- files
@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("partial_slip")
    # 32^2 (16 cells across a) keeps the run to a few seconds; the example itself is 128^2
    sc = scenario(32, friction__tangential_forces={"start": "0 uN", "stop": "2 uN", "num": 5})
    r = run_scenario(sc, outdir=out, progress=False)
    return r, out


def test_summary_keys(written):
    r, out = written
    s = json.loads((out / "summary.json").read_text())
    assert s["kind"] == "partial_slip" and s["converged"] is True
    # 0, 0.5, 1, 1.5 uN solved; 2 uN = mu F0+ has no equilibrium (gross slip, not an error)
    assert len(s["steps"]) == 4
    for st in s["steps"]:
        assert set(STEP_KEYS) <= set(st), set(STEP_KEYS) - set(st)
        assert st["stick_area"] + st["slip_area"] == pytest.approx(st["contact_area_compressive"], rel=1e-12)
        assert st["coupling_iterations"] > 1 and st["tangential_iterations"] > 0
    fx = [st["tangential_force_x"] for st in s["steps"]]
    np.testing.assert_allclose(fx, [0.0, 0.5e-6, 1e-6, 1.5e-6], rtol=1e-9, atol=1e-15)
    assert all(abs(st["tangential_force_y"]) < 1e-15 for st in s["steps"])
    dx = [st["displacement_x"] for st in s["steps"]]
    assert np.all(np.diff(dx) > 0)
    # the stick zone shrinks along the ramp, from the F = 0 slip annulus
    ratios = [st["stick_ratio"] for st in s["steps"]]
    assert 0 < ratios[-1] < ratios[0] < 0.5
    for k in RUN_KEYS:
        assert k in s, k
    assert s["friction_coefficient"] == MU
    assert s["gross_slip"] is True
    assert 0.85 < s["static_friction_ratio"] < 1.0
    assert 1.5e-6 < s["static_friction_force"] < CAP
    assert s["presliding_displacement"] > 0
    lo, hi = s["onset_bracket"]
    assert 0 < hi - lo <= 1e-3 * MU * s["onset_repulsive_force"]
    assert s["max_tangential_force"] == pytest.approx(CAP, rel=1e-9)


def test_fields_figures_report(written):
    r, out = written
    import xarray as xr

    with xr.open_dataset(out / "fields.nc") as ds:
        for v in ("shear_x", "shear_y", "slip_x", "slip_y", "stick"):
            assert v in ds.data_vars, v
        assert ds.sizes["x"] == ds.sizes["y"] == 32
        labels = [str(x) for x in ds["label"].values]
        assert labels[-1] == "onset" and len(labels) == 5
        # the stored shear integrates to the step's force
        cell = r.problem.grid.cell_area
        fx = float(ds["shear_x"].isel(step=2).sum()) * cell
        assert fx == pytest.approx(1e-6, rel=1e-6)
        # stick nodes are compressive contact nodes
        stick = ds["stick"].values.astype(bool)
        assert stick.any()
    names = {p.name for p in out.iterdir()}
    assert {"summary.json", "fields.nc", "report.html", "stick_ratio.png"} <= names
    assert any(n.startswith("stickslip_step") and n.endswith(".png") for n in names)
    html = (out / "report.html").read_text()
    assert "gross slip" in html


# ----------------------------------------------------------------------------- the example
def test_example_validates():
    sc = parse_scenario(example(), source=str(EXAMPLE))
    assert sc.kind == "partial_slip"
    assert sc.friction.coefficient == MU and sc.friction.slip == "total"
    assert sc.load.force == pytest.approx(F0)
    forces = sc.friction.tangential_forces
    assert len(forces) == 11 and forces[0] == 0.0
    # the ramp ends at mu F0 (the most a non-adhesive contact can carry): gross slip is reached
    assert forces[-1] == pytest.approx(CAP, rel=1e-12)
    assert np.all(np.diff(forces) > 0)


@pytest.mark.slow
def test_example_full_run(tmp_path):
    r = run_scenario(EXAMPLE, outdir=tmp_path, progress=False)
    s = r.summary
    assert s["converged"] and s["gross_slip"]
    assert len(s["steps"]) == 10
    # 128^2, 32 cells across a: the onset below Paper D's 0.97
    assert 0.85 < s["static_friction_ratio"] < 0.97
    assert s["static_friction_force"] == pytest.approx(s["static_friction_ratio"] * MU * s["onset_repulsive_force"],
                                                       rel=1e-12)
    lo, hi = s["onset_bracket"]
    assert lo < s["static_friction_force"] < hi and hi - lo <= 1e-3 * MU * s["onset_repulsive_force"]
    assert s["presliding_displacement"] > 0
    assert s["zero_force_stick_ratio"] < 0.5
    assert s["max_tangential_force"] == pytest.approx(CAP, rel=1e-9)
    last = s["steps"][-1]
    assert last["tangential_force_x"] < s["static_friction_force"]
    assert (tmp_path / "report.html").exists()


# ----------------------------------------------------------------------------- other paths
def test_normal_load_path_incremental():
    sc = scenario(32, load__force=None, load__forces=["2.5 uN", "5 uN", "7.5 uN", "10 uN"],
                  friction__tangential_forces=None, friction__slip="incremental")
    r = run_scenario(sc, progress=False)
    assert r.converged
    steps = r.steps
    assert len(steps) == 4
    assert [s["branch"] for s in steps] == ["normal_path"] * 4
    np.testing.assert_allclose([s["normal_force"] for s in steps], [2.5e-6, 5e-6, 7.5e-6, 1e-5], rtol=1e-9)
    for s in steps:
        assert 0 < s["stick_radius_ratio"] <= 1
        assert s["stick_radius_ratio"] == pytest.approx(math.sqrt(s["stick_ratio"]), rel=1e-12)
        assert abs(s["tangential_force_x"]) < 1e-15
    # history: the incremental path keeps a much larger stick zone than the one-shot (total)
    # solve at the final load (Spence: the stick zone grows with the contact)
    pb = r.problem
    one_shot = solve_coupled(pb.operator, pb.gap, friction_coefficient=MU, normal_force=F0)
    assert steps[-1]["stick_ratio"] > 2 * one_shot.tangential.stick_ratio
    assert len(r.tangential) == 4 and r.tangential[-1].mode == "incremental"
    assert r.tangential[0].mode == "total"  # the first step has no history


@pytest.fixture(scope="module")
def beyond():
    """A force ramp [0, 1 uN, 3 uN]: the last force exceeds mu F0+ = 2 uN."""
    return run_scenario(scenario(32, friction__tangential_forces=["0 uN", "1 uN", "3 uN"]), progress=False)


def test_force_beyond_capacity_in_a_ramp(beyond):
    s = beyond.summary
    assert s["converged"]
    assert s["gross_slip"] is True
    assert len(s["steps"]) == 2
    msg = s["ramp_message"]
    assert "gross slip at step 2" in msg and "mu F0+" in msg
    assert s["max_tangential_force"] == pytest.approx(CAP, rel=1e-9)
    # the onset is still located between the last step with stick (1 uN) and mu F0+
    assert 1e-6 < s["static_friction_force"] < CAP
    assert 0.85 < s["static_friction_ratio"] < 1.0
    assert s["presliding_displacement"] > 0
    assert list(beyond.fields["label"].values) == ["ramp 0", "ramp 1", "onset"]


def test_single_force_beyond_capacity_is_reported():
    r = run_scenario(scenario(32, friction__tangential_forces=["3 uN"]), progress=False)
    s = r.summary
    assert s["gross_slip"] is True
    assert "mu F0+" in s["ramp_message"] and "gross slip at step 0" in s["ramp_message"]
    assert s["max_tangential_force"] == pytest.approx(CAP, rel=1e-9)
    # no onset to report; the F_t = 0 state is the one row (and field)
    assert s["static_friction_force"] is None and s["presliding_displacement"] is None
    assert [st["branch"] for st in s["steps"]] == ["zero_force"]
    assert abs(s["steps"][0]["tangential_force_x"]) < 1e-15
    assert len(r.tangential) == len(r.results) == 1


def test_displacement_controlled_ramp(beyond):
    sc = scenario(32, friction__tangential_forces=None,
                  friction__tangential_displacements=["0 nm", "0.1 nm", "0.5 nm"])
    r = run_scenario(sc, progress=False)
    s = r.summary
    assert s["converged"] and s["gross_slip"] is True
    steps = s["steps"]
    assert len(steps) == 3
    np.testing.assert_allclose([st["displacement_x"] for st in steps], [0.0, 1e-10, 5e-10], rtol=1e-12, atol=0)
    f = [st["tangential_force_x"] for st in steps]
    # zero by symmetry, to the solver tolerances (tangential 1e-7 relative: 1e-8 mu F0 is tight)
    assert f[0] == pytest.approx(0.0, abs=1e-8 * CAP) and 0 < f[1] < f[2]
    # 0.5 nm slides grossly: no stick node, the force at (about) the friction limit
    assert steps[-1]["gross_slip"] and steps[-1]["stick_area"] == 0.0
    assert 0.95 * CAP < f[2] <= CAP * (1 + 1e-9)
    assert "gross slip at step 2" in s["ramp_message"]
    # same onset and pre-sliding distance as the force-controlled ramp (observed 0.1%)
    fb = beyond.summary
    assert s["static_friction_force"] == pytest.approx(fb["static_friction_force"], rel=0.005)
    assert s["presliding_displacement"] == pytest.approx(fb["presliding_displacement"], rel=0.01)
    lo, hi = s["onset_bracket"]
    assert 1e-10 <= lo < hi <= 5e-10 and hi - lo <= 1e-3 * 5e-10
