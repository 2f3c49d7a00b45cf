"""The hardness cap in every kind that takes it: normal (with unloading), pulloff, partial_slip,
hysteresis and capillary; refused with [two_scale] and on a rigid body."""

import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.scenario import parse_scenario, run_scenario
from tribobem.scenario.schema import ScenarioError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _run(name, hardness, edit=None, body="body1"):
    d = tomllib.loads((EXAMPLES / f"{name}.toml").read_text())
    d.pop("expected", None)
    d[body]["hardness"] = hardness
    if edit:
        edit(d)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_scenario(parse_scenario(d, source=name), outdir=None, progress=False, base_dir=EXAMPLES)


def test_normal_unloading_sees_the_flattened_surface():
    r = _run("rough_periodic", "2 GPa", lambda d: d["load"].update(unload=True))
    steps = r.summary["steps"]
    assert r.summary["problem"]["hardness"] == 2e9
    assert all(s["max_pressure"] <= 2e9 * (1 + 1e-12) for s in steps)
    up = {s["normal_force"]: s for s in steps if s["branch"] == "loading"}
    down = [s for s in steps if s["branch"] == "unloading"]
    first = min(up)
    back = min(down, key=lambda s: abs(s["normal_force"] - first))
    assert back["normal_force"] == pytest.approx(first, rel=1e-6)
    assert back["contact_area"] > up[first]["contact_area"]  # the flattened tips carry the load wider
    assert back["plastic_area"] == 0.0 and back["yielded_area"] > 0  # no new yield on unloading
    assert "plastic_displacement" in r.fields and "plastic" in r.fields
    d = np.asarray(r.fields["plastic_displacement"].values)
    assert np.all(np.diff(d.reshape(d.shape[0], -1).max(axis=1)) >= -1e-18)  # never shrinks


def test_partial_slip_friction_on_plastic_nodes_is_mu_h():
    H = 0.5e9
    r = _run("partial_slip_auto", "0.5 GPa")
    mu = r.summary["friction_coefficient"]
    seen = 0
    for t, state in zip(r.tangential, r.results):
        if t is None or state.plastic is None:
            continue
        q = np.hypot(*t.shear)
        assert q.max() <= mu * H * (1 + 1e-6)
        slip_plastic = state.plastic & ~t.stick & (state.pressure > 0)
        if slip_plastic.any():
            assert np.allclose(q[slip_plastic], mu * H, rtol=1e-6)
            seen += int(slip_plastic.sum())
    assert seen > 100  # (measured: 1054 slipping plastic nodes over the ramp)
    assert max(s["plastic_area"] for s in r.summary["steps"]) > 0


@pytest.mark.slow  # (10 s; the default run's budget: normal and partial_slip above cover the cap's path)
def test_hysteresis_and_pulloff_and_capillary_take_the_cap():
    r = _run("hysteresis_mindlin", "0.4 GPa")
    assert r.summary["converged"]
    assert max(s["max_plastic_displacement"] for s in r.summary["steps"]) > 0
    r = _run("pulloff_sphere", "0.08 GPa")
    assert r.summary["converged"] and r.summary["pull_off_force"] < 0
    assert max(s["max_plastic_displacement"] for s in r.summary["steps"]) > 0
    r = _run("capillary_rough_sio2", "3 GPa")
    assert all(s["max_pressure"] <= 3e9 * (1 + 1e-12) for s in r.summary["steps"])


def test_refusals():
    with pytest.raises(InputError, match="two_scale"):
        _run("two_scale_burl", "5 GPa")
    d = tomllib.loads((EXAMPLES / "rough_periodic.toml").read_text())
    d["body2"]["hardness"] = "1 GPa"
    with pytest.raises(ScenarioError, match="rigid body does not yield"):
        parse_scenario(d)
