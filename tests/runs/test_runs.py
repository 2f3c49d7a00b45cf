"""tribobem.runs: the registry kind -> runner."""

import tomllib
from pathlib import Path

import pytest

from tribobem.errors import InputError
from tribobem.runs import RUNNERS, NotImplementedKindError, get_runner
from tribobem.scenario import IMPLEMENTED_KINDS, KINDS
from tribobem.scenario import run as run_module
from tribobem.scenario import run_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _example_dict(name: str) -> dict:
    with open(EXAMPLES / f"{name}.toml", "rb") as f:
        return tomllib.load(f)


def test_every_runner_is_a_schema_kind_and_implemented_kinds_follow_the_registry():
    assert set(RUNNERS) <= set(KINDS)
    assert set(IMPLEMENTED_KINDS) == set(RUNNERS)
    assert {"normal", "pulloff"} <= set(RUNNERS)


def test_get_runner():
    from tribobem.runs import normal, pulloff

    assert get_runner("normal") is normal.run and get_runner("pulloff") is pulloff.run
    with pytest.raises(NotImplementedKindError) as exc:
        get_runner("sliding")
    assert isinstance(exc.value, InputError) and exc.value.field == "kind"
    assert "not implemented yet" in str(exc.value)
    for kind in RUNNERS:
        assert kind in str(exc.value)


def test_public_names_stay_where_they_were():
    assert run_module.NotImplementedKindError is NotImplementedKindError
    for name in ("RunResult", "load_scenario", "read_scenario_file", "run_scenario"):
        assert hasattr(run_module, name)


def test_tangential_results_travel_with_the_selected_fields(monkeypatch):
    """A runner's optional ``tangential`` list is selected together with "results" and handed to
    build_fields; the normal kinds pass nothing."""
    import tribobem.output.fields as fields_module
    from tribobem.runs import normal
    from tribobem.scenario import run_scenario

    seen = {}
    original = fields_module.build_fields

    def spy(*args, **kw):
        seen["tangential"] = kw.pop("tangential", None)
        return original(*args, **kw)

    def with_tangential(pb, bar, settings=None):
        out = normal.run(pb, bar, settings)
        out.tangential = [f"T{i}" for i in range(len(out.results))]
        return out

    monkeypatch.setattr(run_module, "build_fields", spy)  # what run_scenario calls
    sc = {"grid": {"n": 16, "size": "0.5 um"}, "body1": {"E": "130 GPa", "nu": 0.28},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
          "load": {"forces": ["2 uN", "3 uN", "1 uN"]}, "output": {"fields": "last", "figures": False}}
    r = run_scenario(sc, progress=False)
    assert seen["tangential"] is None and r.tangential == []
    monkeypatch.setitem(RUNNERS, "normal", with_tangential)
    r = run_scenario(sc, progress=False)
    assert seen["tangential"] == ["T1"] and r.tangential == ["T1"]  # the most loaded step, as for fields
    assert float(r.fields["normal_force"].values[0]) == pytest.approx(3e-6)
    r = run_scenario(dict(sc, output={"fields": "all"}), progress=False)
    assert seen["tangential"] == ["T0", "T1", "T2"] and len(r.results) == 3


def _hertz_scenario(method=None, **load):
    sc = {"grid": {"n": 64, "size": "1.2 um", "periodic": False}, "body1": {"E": "130 GPa", "nu": 0.28},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
          "load": load, "output": {"fields": "none", "figures": False, "report": False}}
    if method is not None:
        sc["solver"] = {"method": method}
    return sc


@pytest.mark.parametrize("load", [{"force": "200 uN"}, {"forces": ["50 uN", "200 uN"]}])
def test_solver_method_normcg_for_kind_normal_matches_polonsky_keer_and_hertz(load, monkeypatch):
    """[solver] method = "normcg" runs kind normal with Vollebregt's CG: the same contact nodes
    as Polonsky-Keer, and the Hertz contact radius (0.22 um, 11.7 cells) within 3 % (measured
    0.9 %, the area's staircase)."""
    from tribobem.analytic.hertz import hertz
    from tribobem.scenario import run_scenario
    from tribobem.runs import normal as runs_normal  # the kind's runner calls solve_normal
    from tribobem.solvers import normal as normal_module

    calls = []
    original = normal_module.solve_normal

    def spy(*args, **kw):
        calls.append(kw.get("method", "polonsky_keer"))
        return original(*args, **kw)

    pk = run_scenario(_hertz_scenario(**load), progress=False)
    import tribobem.solvers.normal_paths as paths_module

    monkeypatch.setattr(normal_module, "solve_normal", spy)
    monkeypatch.setattr(paths_module, "solve_normal", spy)
    monkeypatch.setattr(runs_normal, "solve_normal", spy)
    cg = run_scenario(_hertz_scenario("normcg", **load), progress=False)
    assert calls and set(calls) == {"normcg"}
    for a, b in zip(pk.summary["steps"], cg.summary["steps"]):
        assert b["converged"]
        assert b["contact_area"] == a["contact_area"]
        assert b["normal_force"] == pytest.approx(a["normal_force"], rel=1e-9)
    E_star = 130e9 / (1 - 0.28 ** 2)
    ref = hertz(force=200e-6, radius=10e-6, E_star=E_star)
    a_num = (cg.summary["steps"][-1]["contact_area"] / 3.141592653589793) ** 0.5
    assert a_num == pytest.approx(ref.contact_radius, rel=0.03)


def test_solver_method_normcg_on_a_dry_pulloff_is_a_scenario_error():
    from tribobem.scenario.schema import ScenarioError, parse_scenario

    sc = _hertz_scenario("normcg", force="200 uN")
    sc["kind"] = "pulloff"
    sc["load"] = {}
    sc["adhesion"] = {"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"}
    with pytest.raises(ScenarioError, match="normcg is not available here: the dry pull-off path") as exc:
        parse_scenario(sc)
    assert exc.value.field == "solver.method"


def test_solver_method_auto_is_normcg_without_adhesion_only():
    """``auto`` (the default) stands for NormCG without adhesion and Polonsky-Keer with it."""
    from tribobem.runs.common import normal_method
    from tribobem.scenario.schema import parse_scenario

    dry = parse_scenario(_hertz_scenario(force="200 uN"))
    assert dry.solver.method == "auto" and normal_method(dry) == "normcg"
    sticky = parse_scenario(dict(_hertz_scenario(force="200 uN"), adhesion={"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"}))
    assert normal_method(sticky) == "polonsky_keer"
    forced = parse_scenario(dict(_hertz_scenario("polonsky_keer", force="200 uN")))
    assert normal_method(forced) == "polonsky_keer"


def _burl_capillary(method: str) -> dict:
    """A rigid crowned burl (b = 10 um) at 0.5 mN on a rough Si wafer (2 nm rms) with SiO2 films
    at RH 0.5 and Dugdale adhesion: menisci and Dugdale zones on many asperity spots."""
    return {"kind": "capillary", "grid": {"n": 64, "size": "23 um", "periodic": False},
            "body1": {"E": "130 GPa", "nu": 0.28, "film": {"isotherm": "SiO2"},
                      "roughness": {"kind": "self_affine", "rms": "2 nm", "hurst": 0.8, "rolloff": "1 um",
                                    "short_cutoff": "0.3 um", "seed": 20}},
            "body2": {"rigid": True, "film": {"isotherm": "SiO2"},
                      "shape": {"kind": "burl", "radius": "10 um", "edge_radius": "20 um", "crown": "50 mm"}},
            "adhesion": {"model": "dugdale", "work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"},
            "load": {"force": "0.5 mN"}, "humidity": {"rh": [0.5]}, "solver": {"method": method},
            "output": {"fields": "none", "figures": False, "report": False}}


def test_capillary_normcg_converges_on_a_rough_burl(monkeypatch):
    """[solver] method = "normcg" solves the island fixed point's normal problems with NormCG.
    On a rough burl its deferred update of the smooth capillary law converges every solve (with
    the outside stresses applied at every iteration, as before, 7 of 7 solves failed); the
    capillary force is Polonsky-Keer's to the non-uniqueness of the adhesive equilibrium (0.6 %)."""
    import tribobem.solvers.capillary as cap

    calls = []
    orig = cap.solve_normal

    def spy(*a, **k):
        r = orig(*a, **k)
        calls.append((k.get("method"), r.converged))
        return r

    monkeypatch.setattr(cap, "solve_normal", spy)
    out = {}
    for method in ("polonsky_keer", "normcg"):
        calls.clear()
        out[method] = run_scenario(_burl_capillary(method), progress=False, quiet=True).summary
        assert calls and {m for m, _ in calls} == {method} and all(ok for _, ok in calls)
        assert out[method]["converged"] is True
    a, b = out["polonsky_keer"]["steps"][0], out["normcg"]["steps"][0]
    assert b["capillary_force"] == pytest.approx(a["capillary_force"], rel=0.02)
    assert b["contact_area"] == pytest.approx(a["contact_area"], rel=0.02)


def test_humid_partial_slip_takes_normcg():
    """With [humidity], method = "normcg" reaches the meniscus fixed point's normal solves (it was
    refused before) and the humid example's static friction stays within its stated 2 %."""
    sc = _example_dict("partial_slip_humid_sphere")
    sc.setdefault("solver", {})["method"] = "normcg"
    sc["humidity"]["rh"] = [0.7]
    r = run_scenario(sc, progress=False, quiet=True)
    assert r.summary["problem"]["normal_method"] == "normcg"
    humid = [st for st in r.summary["steps"] if st.get("rh") == 0.7]
    assert humid and all(st["converged"] for st in humid)
    assert r.summary["static_friction_force"][0] == pytest.approx(0.798e-6, rel=0.02)


@pytest.mark.parametrize("kind", ["partial_slip", "hysteresis"])
def test_coupled_kinds_with_normcg_match_polonsky_keer(kind, monkeypatch):
    """Kinds partial_slip and hysteresis solve every coupling pass with the chosen normal solver:
    NormCG and Polonsky-Keer give the same run values within the coupling loop's tolerance
    (relative pressure error 1e-6; the Paper D example at 128^2 agreed to 7e-8 on the pre-sliding
    displacement and 1e-8 on the rest), and NormCG was really used."""
    from tribobem.scenario import run_scenario
    from tribobem.solvers import coupling

    used = []
    original = coupling.solve_normal

    def spy(*args, **kw):
        used.append(kw.get("method"))
        return original(*args, **kw)

    monkeypatch.setattr(coupling, "solve_normal", spy)
    name = "partial_slip_paper_d" if kind == "partial_slip" else "hysteresis_mindlin"
    out = {}
    for method in ("polonsky_keer", "normcg"):
        used.clear()
        sc = _example_dict(name)
        sc["grid"]["n"] = 32
        sc["solver"] = dict(sc.get("solver", {}), method=method)
        sc["output"] = {"fields": "none", "figures": False, "report": False}
        out[method] = run_scenario(sc, outdir=None, progress=False, quiet=True, base_dir=EXAMPLES)
        assert used and set(used) == {method}
        assert out[method].summary["problem"]["normal_method"] == method
    a, b = out["polonsky_keer"], out["normcg"]
    assert len(a.summary["steps"]) == len(b.summary["steps"])
    keys = ["approach", "displacement_x", "tangential_force_x", "max_pressure", "stick_ratio"]
    # relative to each value's largest magnitude along the run (a zero-force step's round-off
    # displacement of 1e-20 m is no value to compare relatively)
    scale = {k: max(abs(st.get(k) or 0.0) for st in a.summary["steps"]) for k in keys}
    for sa, sb in zip(a.summary["steps"], b.summary["steps"]):
        for k in keys:
            if k in sa and sa[k] is not None:
                assert sb[k] == pytest.approx(sa[k], rel=1e-5, abs=1e-5 * scale[k]), k
    for k in ("static_friction_ratio", "presliding_displacement"):
        if k in a.summary:
            assert b.summary[k] == pytest.approx(a.summary[k], rel=1e-5), k


def test_run_output_checks_alignment():
    """A runner's results, labels, indices and tangential states are aligned one-to-one."""
    from tribobem.runs import RunOutput

    RunOutput(rows=[], results=[1, 2], labels=["a", "b"], indices=[0, 1], run={})
    with pytest.raises(ValueError, match="aligned"):
        RunOutput(rows=[], results=[1, 2], labels=["a"], indices=[0, 1], run={})
    with pytest.raises(ValueError, match="tangential"):
        RunOutput(rows=[], results=[1, 2], labels=["a", "b"], indices=[0, 1], run={}, tangential=["t"])


def test_each_kind_declares_known_figure_sets_and_report_sections():
    """A kind is a plug-in: its figure sets and report sections are names the output package
    knows (an unknown name is an error, not silently nothing)."""
    from tribobem.output.figures import FIGURE_SETS, make_figures
    from tribobem.output.report import REPORT_SECTIONS, render_report
    from tribobem.runs import KINDS as REGISTRY

    for name, kind in REGISTRY.items():
        assert kind.figures and set(kind.figures) <= set(FIGURE_SETS), name
        assert set(kind.report_sections) <= set(REPORT_SECTIONS), name
        assert kind.summary, name
    with pytest.raises(ValueError, match="unknown figure set"):
        make_figures(None, {"kind": "normal", "steps": []}, "/nonexistent-not-created", sets=("plots",))
    with pytest.raises(ValueError, match="unknown report section"):
        render_report({"kind": "normal", "steps": []}, {}, sections=("extras",))


def test_a_kind_draws_its_own_figure_sets(tmp_path):
    """A partial-slip ramp draws the friction set and no force curve (constant normal force);
    the same summary with only the kind's sets gives the same figures as all sets."""
    from tribobem.output import replot
    from tribobem.runs import KINDS as REGISTRY
    from tribobem.scenario import run_scenario

    sc = {"kind": "partial_slip", "grid": {"n": 32, "size": "0.32 um"},
          "body1": {"E": "130 GPa", "nu": 0.3}, "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
          "load": {"force": "10 uN"}, "friction": {"coefficient": 0.2, "tangential_forces": ["0 uN", "1 uN"]}}
    r = run_scenario(sc, outdir=tmp_path / "a", progress=False)
    figs = {k for k in r.files if k not in ("fields", "report", "summary")}
    assert "stick_ratio" in figs and any(k.startswith("stickslip_step") for k in figs)
    assert "force_curve" not in figs and "hysteresis_loop" not in figs
    kind = REGISTRY["partial_slip"]
    again = replot(tmp_path / "a", figure_sets=kind.figures, report_sections=kind.report_sections)
    every = replot(tmp_path / "a")
    assert set(again) == set(every) == figs | {"report"}
    assert "<h2>Friction</h2>" in (tmp_path / "a" / "report.html").read_text()


def test_an_approach_beyond_full_contact_of_a_periodic_cell_is_refused():
    """Found by the fuzz tests: such a step used to stall ("near an instability there may be no
    equilibrium"). A periodic cell in full contact sits at approach = its mean initial gap (the
    mean displacement is fixed), so beyond it there is no equilibrium: refused naming the key."""
    import numpy as np

    from tribobem.scenario import build_problem, load_scenario, run_scenario

    sc = {"grid": {"n": 32, "size": "0.25 um", "periodic": True}, "body1": {"E": "70 GPa", "nu": 0.3},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "5 um"}},
          "load": {"approach": "1.125 nm"}, "output": {"fields": "none", "figures": False, "report": False}}
    mean_gap = float(np.mean(build_problem(load_scenario(sc)[0]).gap))
    assert mean_gap < 1.125e-9
    with pytest.raises(InputError) as exc:
        run_scenario(sc, progress=False)
    assert exc.value.field == "load.approach" and "full contact of the periodic cell" in str(exc.value)
    with pytest.raises(InputError) as exc:
        run_scenario(dict(sc, load={"approaches": [0.2e-9, 1.125e-9]}), progress=False)
    assert exc.value.field == "load.approaches"
    ok = run_scenario(dict(sc, load={"approach": 0.5 * mean_gap}), progress=False)
    assert ok.summary["converged"]


def test_stick_slip_figures_name_summary_steps_or_the_onset(tmp_path):
    """A stick/slip map is named after its summary.json step, or after its label for the refined
    onset (not a summary.json step): no figure names a step summary.json does not have."""
    from tribobem.scenario import run_scenario

    sc = {"kind": "partial_slip", "grid": {"n": 48, "size": "0.32 um"},
          "body1": {"E": "130 GPa", "nu": 0.3}, "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
          "load": {"force": "10 uN"},
          "friction": {"coefficient": 0.2, "tangential_forces": {"start": "0 uN", "stop": "2 uN", "num": 6}}}
    r = run_scenario(sc, outdir=tmp_path / "ps", progress=False)
    n = len(r.summary["steps"])
    maps = [k for k in r.files if k.startswith("stickslip_")]
    assert "stickslip_onset" in maps and r.summary["gross_slip"]
    for k in maps:
        if k.startswith("stickslip_step"):
            assert int(k[len("stickslip_step"):]) < n, (k, n)
    assert "the onset state" in (tmp_path / "ps" / "report.html").read_text()


def test_report_says_which_solver_and_backend_ran(tmp_path):
    """What ``method = "auto"`` (and the backend) stood for is in summary.json and the report."""
    from tribobem.scenario import run_scenario

    sc = _hertz_scenario(force="200 uN")
    sc["output"] = {"fields": "none", "figures": False, "report": True}
    rr = run_scenario(sc, outdir=tmp_path, progress=False, quiet=True)
    assert rr.summary["problem"]["normal_method"] == "normcg" and rr.summary["problem"]["backend"] == "numpy"
    # the FFT engine of the NumPy backend (runs on different engines differ by round-off)
    from tribobem.elasticity.backend import default_fft

    assert rr.summary["problem"]["fft"] == default_fft()
    # (a single-load normal run also says the precision NormCG ran in: summary.json "solve")
    assert rr.summary["solve"]["precision"] == "double"
    assert (f"solver</th><td class='l'>normal solver normcg; double precision; backend numpy, FFT engine {default_fft()}<"
            in (tmp_path / "report.html").read_text())
