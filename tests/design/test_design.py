"""Design studies (tribobem.design, ``tribobem design``): the chain per point on the sweep
machinery, the table and report, the ranking, resuming, failing points."""

from __future__ import annotations

import json
import math

import pytest

from tribobem.design import (ChainOptions, DesignSpec, Target, pareto_front, point_scenario, rank_rows, run_design,
                             stage_scenario)
from tribobem.errors import InputError
from tribobem.runs import KINDS

BASE = {
    "name": "tiny design",
    "grid": {"n": 16, "size": "1.6 um"},
    "body1": {"name": "flat", "E": "70 GPa", "nu": 0.3},
    "body2": {"name": "ball", "rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
    "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "1 nm"},
    "load": {"force": "10 uN", "steps": 8, "refine": 2},
    "friction": {"coefficient": 0.3},
    "solver": {"tolerance": 1e-8},
}


def _design(radii, targets=None, chain=None):
    data = {"name": "tiny", "base": BASE, "parameters": {"body2.shape.radius": radii},
            "chain": chain if chain is not None else {"hysteresis": {"amplitude": 0.9, "steps": 8}},
            "targets": targets if targets is not None else {
                "static_friction_force": {"min": "3.2 uN"}, "pull_off_force": {"max": "0.5 uN"},
                "hardness": "5 GPa"}}
    return DesignSpec.from_dict(data)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """A 2-point design plus one invalid point, run once (synchronously)."""
    out = tmp_path_factory.mktemp("design")
    design = _design(["10 um", "20 um", "-1 um"])
    res = run_design(design, out, scheduler="synchronous", progress=False, quiet=True)
    return design, out, res


def test_stage_scenarios_are_accepted_by_each_kind():
    sc, notes = point_scenario({**BASE, "body1": {**BASE["body1"], "roughness": {
        "kind": "gaussian", "rms": "1 nm", "correlation_length": "0.2 um"}}}, {})
    assert sc["body1"]["roughness"]["seed"] == 0 and notes  # one surface for every stage
    for kind in ("normal", "pulloff", "partial_slip", "hysteresis"):
        st = stage_scenario(sc, kind)
        reads = KINDS[kind].reads()
        assert st["kind"] == kind
        assert set(st) - {"kind", "name"} <= set(reads)
    assert "friction" not in stage_scenario(sc, "normal")
    po = stage_scenario(sc, "pulloff", load={"preload": "1 uN"})["load"]
    assert "force" not in po and po["preload"] == "1 uN" and po["steps"] == 8
    dry, _ = point_scenario({**BASE, "humidity": {"rh": 0.5}, "body1": {**BASE["body1"], "film": {"isotherm": "Si"}}},
                            {"humidity.rh": "dry"})
    assert "humidity" not in dry and "film" not in dry["body1"]
    with pytest.raises(InputError, match="one RH"):
        point_scenario({**BASE, "humidity": {"rh": [0.3, 0.5]}}, {})


def test_design_file_checks():
    with pytest.raises(InputError, match="targets.friction"):
        _design(["10 um"], targets={"friction": {"min": 1}})
    with pytest.raises(InputError, match="force"):
        _design(["10 um"], targets={"static_friction_force": {"min": "3 nm"}})
    with pytest.raises(InputError, match="chain.bogus"):
        _design(["10 um"], chain={"bogus": 1})
    with pytest.raises(InputError, match="design.parameters"):
        DesignSpec.from_dict({"base": BASE})
    with pytest.raises(InputError, match="design.extra"):
        DesignSpec.from_dict({"base": BASE, "parameters": {"grid.n": [16]}, "extra": 1})
    ch = ChainOptions.from_dict({"tangential_forces": {"start": 0, "stop": "2 uN", "num": 3}, "hysteresis": False})
    assert ch.tangential_forces == pytest.approx([0, 1e-6, 2e-6]) and ch.hysteresis is None


def test_targets_hash_and_pareto():
    t = Target("pull_off_force", None, 1e-6)
    assert t.evaluate(-0.5e-6)[0] and not t.evaluate(-2e-6)[0]  # on the magnitude
    assert t.evaluate(-2e-6)[1] == pytest.approx(1.0)
    assert not Target("contact_area", 1.0, None).evaluate(math.nan)[0]
    a, b = _design(["10 um"]), _design(["10 um"], targets={})
    assert a.sweep().tasks() == b.sweep().tasks()  # targets never recompute a point
    c = _design(["10 um"], chain={"hysteresis": False})
    assert a.sweep().tasks()[0][0] != c.sweep().tasks()[0][0]  # chain options do
    front = pareto_front([1, 2, 3, 2], [3, 2, 1, 1], "max", "max")
    assert front.tolist() == [True, True, True, False]
    assert pareto_front([1, 2], [1, 2], "min", "min").tolist() == [True, False]


def test_tiny_design_runs_writes_and_ranks(tiny):
    design, out, res = tiny
    assert res.sweep.n_points == 3 and res.sweep.n_ok == 2 and res.sweep.n_failed == 1
    assert res.exit_code == 1
    for name in ("design.nc", "design.csv", "design_report.html"):
        assert (out / name).is_file()
    ok = [r for r in res.rows if r["status"] == "ok"]
    assert len(ok) == 2
    for r in ok:
        assert 0 < r["static_friction_force"] < 1.2 * 0.3 * 1.5e-5
        assert r["pull_off_force"] < 0
        assert r["contact_area"] > 0 and r["max_pressure"] > 0 and r["peak_pressure"] >= r["max_pressure"]
        assert all(r[f"lateral_stiffness_{p}"] > 0 for p in "ABC")
        assert r["exceeds_hardness"] is False
        assert r["warnings"] and all(isinstance(w, str) for w in r["warnings"])  # 16^2: grid warnings
        assert set(r["stages"]) == {"normal", "pulloff", "ramp", "hysteresis"}
    # ranking: the failed point last, the computed ones by targets met then distance
    ranks = {r["point"]["body2.shape.radius"]: r["rank"] for r in res.rows}
    assert ranks["-1 um"] == 3 and sorted(ranks.values()) == [1, 2, 3]
    best = res.ranking[0]
    assert best["targets_met"] >= res.ranking[1]["targets_met"]
    # the table files
    import xarray as xr

    with xr.open_dataset(out / "design.nc") as ds:
        assert ds.sizes["point"] == 3
        assert list(ds["body2.shape.radius"].values) == pytest.approx([1e-5, 2e-5, -1e-6])
        assert set(ds["status"].values) == {"ok", "failed"}
        assert int(ds["rank"].values[2]) == 3
        assert "exceeds_hardness" in ds and "warnings" in ds
    csv_text = (out / "design.csv").read_text()
    assert csv_text.splitlines()[0].startswith("rank,hash,status,body2.shape.radius,static_friction_force")
    html = (out / "design_report.html").read_text()
    assert "Pareto" in html and html.count("data:image/png;base64,") == 2
    assert "must be &gt; 0" in html or "must be > 0" in html  # the failed point's message
    assert "cohesive_zone" in html  # the warnings of every point


def test_failing_point_is_recorded_and_the_sweep_goes_on(tiny):
    design, out, res = tiny
    bad = next(r for r in res.rows if r["point"]["body2.shape.radius"] == "-1 um")
    assert bad["status"] == "failed"
    assert "stage normal failed" in bad["message"] and "body2.shape.radius" in bad["message"]
    assert bad["stages"]["pulloff"]["status"] == "skipped"
    rec = json.loads((out / "points" / f"{bad['hash']}.json").read_text())
    assert rec["status"] == "failed" and "body2.shape.radius" in rec["error"]


def test_resume_recomputes_only_missing_or_changed_points(tiny, monkeypatch):
    design, out, res = tiny
    import tribobem.design.chain as chain

    calls = []
    real = chain.run_chain

    def counting(scenario, ch, base_dir=None):
        calls.append(scenario["body2"]["shape"]["radius"])
        return real(scenario, ch, base_dir)

    monkeypatch.setattr(chain, "run_chain", counting)
    again = run_design(design, out, scheduler="synchronous", progress=False, quiet=True)
    assert calls == ["-1 um"]  # only the failed point is retried
    assert again.sweep.n_done_before == 2
    # a new point and a changed target: only the new point runs; the old ones are re-ranked
    calls.clear()
    more = _design(["10 um", "20 um", "-1 um", "5 um"], targets={"static_friction_force": {"min": "1 uN"}})
    res2 = run_design(more, out, scheduler="synchronous", progress=False, quiet=True)
    assert sorted(calls) == ["-1 um", "5 um"]
    assert res2.sweep.n_ok == 3
    assert all(r["n_targets"] == 1 for r in res2.rows)
    old = {r["hash"]: r["static_friction_force"] for r in res.rows if r["status"] == "ok"}
    for r in res2.rows:
        if r["hash"] in old:
            assert r["static_friction_force"] == old[r["hash"]]


def test_rank_rows_orders_by_targets_then_distance():
    rows = [{"index": i, "status": s, "static_friction_force": v} for i, (s, v) in
            enumerate([("ok", 1.0), ("ok", 3.0), ("failed", math.nan), ("ok", 2.5)])]
    rank_rows(rows, [Target("static_friction_force", 2.0, None)])
    assert [r["rank"] for r in rows] == [3, 1, 4, 2]
    assert rows[0]["distance"] == pytest.approx(0.5)


def test_cli_design(tmp_path):
    from typer.testing import CliRunner

    from tribobem.cli import app

    f = tmp_path / "d.toml"
    f.write_text("""
[base]
kind = "normal"
[base.grid]
n = 16
size = "1.6 um"
[base.body1]
E = "70 GPa"
nu = 0.3
[base.body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[base.load]
force = "10 uN"
[base.friction]
coefficient = 0.3
[parameters]
"load.force" = ["5 uN"]
[chain]
hysteresis = false
[targets]
static_friction_force = { min = "1 uN" }
""")
    r = CliRunner().invoke(app, ["design", str(f), "-o", str(tmp_path / "out"), "--scheduler", "synchronous", "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["n_ok"] == 1 and d["ranking"][0]["targets_met"] == 1
    assert 0.85 * 0.3 * 5e-6 < d["ranking"][0]["static_friction_force"] <= 1.001 * 0.3 * 5e-6  # coupling, 16^2
    assert d["ranking"][0]["pull_off_force"] == 0.0  # no adhesion, no humidity: the pull-off stage is skipped
    assert (tmp_path / "out" / "design_report.html").is_file()
    r = CliRunner().invoke(app, ["design", str(tmp_path / "missing.toml")])
    assert r.exit_code == 2


# --------------------------------------------------------------------------- humid points
HUMID_BASE = {
    "name": "burl on wafer, humid",
    "grid": {"n": 32, "size": "1.6 um"},
    "body1": {"name": "Si wafer", "E": "130 GPa", "nu": 0.28, "film": {"isotherm": "Si"},
              "roughness": {"kind": "gaussian", "rms": "0.5 nm", "correlation_length": "0.1 um", "seed": 7}},
    "body2": {"name": "SiC burl", "E": "410 GPa", "nu": 0.14, "film": {"isotherm": "SiO2"},
              "shape": {"kind": "burl", "radius": "0.3 um", "edge_radius": "10 um"}},
    "load": {"force": "2 uN"},
    "friction": {"coefficient": 0.3},
    "humidity": {"rh": 0.5, "van_der_waals": False},
}


@pytest.fixture(scope="module")
def humid(tmp_path_factory):
    """Two humid points (RH 0.3, 0.7) and a dry one on a 32^2 burl, with the ramp summaries
    the chain saw (stage scenario's RH -> summary), run once."""
    import tribobem.design.chain as chain

    out = tmp_path_factory.mktemp("humid")
    design = DesignSpec.from_dict({"name": "humid", "base": HUMID_BASE,
                                   "parameters": {"humidity.rh": [0.3, 0.7, "dry"]},
                                   "chain": {"hysteresis": False}})
    ramps, real = {}, chain._run

    def recording(sc, base_dir):
        s = real(sc, base_dir)
        if sc["kind"] == "partial_slip":  # the last ramp of a point is the one it reads
            ramps[sc["humidity"]["rh"] if "humidity" in sc else "dry"] = s
        return s

    mp = pytest.MonkeyPatch()
    mp.setattr(chain, "_run", recording)
    try:
        res = run_design(design, out, scheduler="synchronous", progress=False, quiet=True)
    finally:
        mp.undo()
    return res, ramps, out


def test_humid_columns_hold_the_humid_state_at_zero_tangential_load(humid):
    res, ramps, out = humid
    rows = {r["point"]["humidity.rh"]: r for r in res.rows}
    assert all(r["status"] == "ok" for r in rows.values())
    for rh in (0.3, 0.7):
        r, step0 = rows[rh], ramps[rh]["steps"][0]
        assert step0["rh"] == rh and abs(step0["tangential_force_x"]) < 1e-15  # the ramp's F_t = 0 state
        for k in ("contact_area", "max_pressure", "repulsive_force", "capillary_force"):
            assert r[k] == pytest.approx(step0[k], rel=1e-12, abs=0), (rh, k)
        # the menisci pull: F0+ exceeds the 2 uN clamp load by at least 90 % of the meniscus force
        assert r["capillary_force"] < -1e-6
        assert r["repulsive_force"] > 2e-6 + 0.9 * abs(r["capillary_force"])
        assert r["contact_area"] > 3 * rows["dry"]["contact_area"]  # 32^2: 18x (RH 0.7) and 28x (RH 0.3)
    a, b = rows[0.3], rows[0.7]
    assert abs(a["contact_area"] - b["contact_area"]) > 0.1 * b["contact_area"]
    assert abs(a["repulsive_force"] - b["repulsive_force"]) > 0.1 * b["repulsive_force"]
    # the dry point: its normal stage at the clamp load, no menisci
    d = rows["dry"]
    assert d["capillary_force"] == 0.0 and d["repulsive_force"] == pytest.approx(2e-6, rel=1e-6, abs=0)
    # the table files and the report carry the columns
    header = (out / "design.csv").read_text().splitlines()[0].split(",")
    assert "capillary_force" in header and "repulsive_force" in header
    import re

    html = (out / "design_report.html").read_text()
    assert re.search(r"<th[^>]*>\s*F_cap", html) and "first state of its humid tangential ramp" in html
    # the automatic ramp's first pass (to 1.2 mu x clamp load) ends short of the menisci's F0+: its
    # "no gross slip" note is superseded by the second pass, which reaches gross slip
    for rh in (0.3, 0.7):
        r = rows[rh]
        if r["static_friction_force"] == r["static_friction_force"]:  # the second pass reached gross slip
            assert "no gross slip" not in (r.get("warnings") or ""), r.get("warnings")


def test_humid_point_with_a_ramp_not_starting_at_zero_still_has_its_zero_load_state(humid, tmp_path):
    res, _, _ = humid
    ref = next(r for r in res.rows if r["point"]["humidity.rh"] == 0.7)
    design = DesignSpec.from_dict({"name": "humid list", "base": HUMID_BASE, "parameters": {"humidity.rh": [0.7]},
                                   "chain": {"hysteresis": False, "pulloff": False,
                                             "tangential_forces": ["2 uN", "4 uN"]}})
    r = run_design(design, tmp_path, scheduler="synchronous", progress=False, quiet=True).rows[0]
    assert r["status"] == "ok"
    for k in ("contact_area", "max_pressure", "repulsive_force", "capillary_force"):
        assert r[k] == pytest.approx(ref[k], rel=1e-6, abs=0), k
    assert r["ramp_max_force"] == pytest.approx(4e-6, rel=1e-12, abs=0)


def test_cli_design_progress_off_a_terminal_is_one_line_per_point(tmp_path):
    import re

    from typer.testing import CliRunner

    from tribobem.cli import app

    f = tmp_path / "d.toml"
    f.write_text("""
[base]
grid = { n = 16, size = "1.6 um" }
body1 = { E = "70 GPa", nu = 0.3 }
body2 = { rigid = true, shape = { kind = "sphere", radius = "10 um" } }
load = { force = "10 uN" }
friction = { coefficient = 0.3 }
[parameters]
"load.force" = ["5 uN", "8 uN"]
[chain]
hysteresis = false
""")
    args = ["design", str(f), "-o", str(tmp_path / "out"), "--scheduler", "synchronous"]
    r = CliRunner().invoke(app, args)  # output captured: not a terminal
    assert r.exit_code == 0, r.output
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("point ")]
    assert len(lines) == 2, r.stderr
    for k, (ln, force) in enumerate(zip(lines, ("5 uN", "8 uN")), start=1):
        assert re.fullmatch(rf"point {k} of 2 done: load\.force = {force} \(\d+\.\d s\)", ln), ln
    assert "0 of 2 points done, running 2" in r.stderr
    r = CliRunner().invoke(app, [*args[:3], str(tmp_path / "out2"), *args[4:], "--quiet"])
    assert r.exit_code == 0 and r.stderr == "", r.stderr  # --quiet: no progress, no messages


TWO_SCALE_BASE = {
    "name": "two-scale burl",
    "grid": {"n": 48, "size": "16 um"},
    "body1": {"E": "130 GPa", "nu": 0.28,
              "roughness": {"kind": "gaussian", "rms": "1.5 nm", "correlation_length": "50 nm", "seed": 3}},
    "body2": {"E": "410 GPa", "nu": 0.14, "shape": {"kind": "burl", "radius": "4 um", "edge_radius": "100 um"}},
    "load": {"force": "2 mN"},
    "friction": {"coefficient": 0.2},
    "two_scale": {"window": "1 um", "window_n": 32, "realisations": 1, "min_pressure": "10 kPa",
                  "max_pressure": "2 GPa"},
}


def test_a_two_scale_design_shares_its_micro_tables_and_ranks_by_stiffness(tmp_path, monkeypatch):
    monkeypatch.setenv("TRIBOBEM_CACHE", str(tmp_path / "cache"))
    design = DesignSpec.from_dict({"name": "two-scale", "base": TWO_SCALE_BASE,
                                   "parameters": {"body2.shape.radius": ["3 um", "6 um"]},
                                   "chain": {"hysteresis": {"amplitude": 0.9, "steps": 16}},
                                   "targets": {"lateral_stiffness": {"min": "1 N/m"}}})
    res = run_design(design, tmp_path / "out", scheduler="synchronous", progress=False, quiet=True)
    rows = {r["point"]["body2.shape.radius"]: r for r in res.rows}
    assert all(r["status"] == "ok" for r in rows.values())
    small, big = rows["3 um"], rows["6 um"]
    for r in (small, big):
        # every window slides at its own mu p, so the burl at mu F; dry: no pull-off run
        assert r["static_friction_force"] == pytest.approx(0.2 * 2e-3, rel=1e-9)
        assert r["pull_off_force"] == 0.0
    # a wider top is stiffer (the full-stick stiffness 8 a G* grows with the top radius a)
    assert big["lateral_stiffness_B"] > 1.3 * small["lateral_stiffness_B"]
    assert big["presliding_displacement"] < small["presliding_displacement"]
    # the two points (and the three stages of each) use one normal and one slip table
    assert len(list((tmp_path / "cache" / "two_scale").glob("*.json"))) == 2


def test_a_humid_two_scale_design_point_runs_its_pull_off_and_ramp_at_two_scales(tmp_path, monkeypatch):
    from tribobem.design.chain import run_chain

    monkeypatch.setenv("TRIBOBEM_CACHE", str(tmp_path / "cache"))
    sc = {**TWO_SCALE_BASE, "humidity": {"rh": 0.5, "van_der_waals": False},
          "body1": {**TWO_SCALE_BASE["body1"], "film": {"isotherm": "Si"}}}
    out = run_chain(sc, {"pulloff": True, "hysteresis": None, "tangential_forces": [0.0, 1e-4]})
    # the pull-off unloads the windows' tensile law (their menisci): it pulls, and less than the
    # menisci pull at the clamp load
    assert out["stages"]["pulloff"]["status"] == "ok"
    po = out["values"]["pull_off_force"]
    assert po < 0 and abs(po) < abs(out["values"]["capillary_force"])
    # the humid ramp runs at two scales: the menisci pull the burl on, F0+ = F + |F_cap|, F_s = mu F0+
    assert out["stages"]["ramp"]["status"] == "ok"
    v = out["values"]
    assert v["capillary_force"] < 0 and v["repulsive_force"] == pytest.approx(2e-3 - v["capillary_force"], rel=0.02)
    assert v["static_friction_force"] == pytest.approx(0.2 * v["repulsive_force"], rel=1e-6)
