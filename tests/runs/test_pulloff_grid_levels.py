"""``[load] grid_levels`` of kind pulloff: the pull-off again on finer grids, and the change.

Reference: the Maugis-Dugdale sphere of examples/pulloff_sphere.toml on 32^2 and 64^2 (2 and 4
cells across the cohesive zone): the finer level is closer to Maugis-Dugdale, the change between
the levels is what summary.json reports, and a change above 5 % warns.
"""

import copy
import tomllib
import warnings
from pathlib import Path

import pytest

from tribobem.errors import InputError
from tribobem.scenario import parse_scenario
from tribobem.scenario.run import run_scenario

REPO = Path(__file__).resolve().parents[2]


def _sphere(n, levels):
    sc = tomllib.loads((REPO / "examples" / "pulloff_sphere.toml").read_text())
    sc.pop("expected")
    sc = copy.deepcopy(sc)
    sc["grid"]["n"] = n
    sc["load"]["grid_levels"] = levels
    sc["output"] = {"figures": False, "report": False, "fields": "none"}
    return sc


def test_levels_are_reported_and_approach_maugis_dugdale():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run_scenario(_sphere(32, 1), outdir=None, progress=False)
    lv = r.summary["grid_levels"]
    assert [x["n"] for x in lv["levels"]] == [32, 64]
    f0, f1 = (x["pull_off_force"] for x in lv["levels"])
    assert f0 == pytest.approx(r.summary["pull_off_force"], rel=1e-12)
    assert lv["change"] == pytest.approx((f1 - f0) / abs(f0), rel=1e-12)
    md = -0.25e-6
    assert abs(f1 / md - 1) < abs(f0 / md - 1)
    # the 64^2 level alone gives the same number as its level here
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r64 = run_scenario(_sphere(64, 0), outdir=None, progress=False)
    assert r64.summary["pull_off_force"] == pytest.approx(f1, rel=1e-9)
    assert "grid_levels" not in r64.summary
    # a change above 5 % warns, naming the key
    if abs(lv["change"]) > 0.05:
        assert any("grid_levels" in w for w in r.summary["warnings"])


def test_grid_levels_are_refused_where_they_do_not_apply():
    sc = _sphere(32, 1)
    sc["kind"] = "normal"
    sc["load"] = {"force": "0.1 uN", "grid_levels": 1}
    with pytest.raises(InputError, match="grid_levels"):
        parse_scenario(sc)
    sc = _sphere(32, 1)
    sc["humidity"] = {"rh": 0.5}
    with pytest.raises(InputError, match="grid_levels"):
        parse_scenario(sc)
