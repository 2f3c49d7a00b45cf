"""tribobem.runs.settings: one solver-settings object per run, built from ``[solver]`` and the
kind, handed to every solver call and recorded in summary.json; no runner reads a constant from
another kind's module or writes into the built problem."""

from __future__ import annotations

import ast
import copy
import tomllib
from pathlib import Path

import pytest

from tribobem.runs import KINDS
from tribobem.runs import settings as S
from tribobem.runs.settings import SolverSettings
from tribobem.scenario import run_scenario
from tribobem.scenario.build import build_problem
from tribobem.scenario.schema import parse_scenario
from tribobem.solvers import coupling

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
RUNS = ROOT / "src" / "tribobem" / "runs"

#: A small normal scenario (Hertz sphere on a half-space, 16^2).
NORMAL = {"kind": "normal", "grid": {"n": 16, "size": "0.5 um"}, "body1": {"E": "130 GPa", "nu": 0.28},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
          "load": {"force": "2 uN"}, "output": {"fields": "none", "figures": False, "report": False}}
DUGDALE = {"model": "dugdale", "work_of_adhesion": "50 mJ/m^2", "z0": "0.5 nm"}


def _example(name: str) -> dict:
    with open(EXAMPLES / f"{name}.toml", "rb") as f:
        return tomllib.load(f)


def _scenario(d: dict):
    return parse_scenario(copy.deepcopy(d))


def _partial_slip(tolerance: float | None = None) -> dict:
    d = _example("partial_slip_paper_d")
    d["grid"]["n"] = 16
    d["friction"]["tangential_forces"] = ["0 uN", "0.5 uN"]
    d["output"] = {"fields": "none", "figures": False, "report": False}
    if tolerance is not None:
        d["solver"] = {"tolerance": tolerance}
    return d


# ----------------------------------------------------------------------------- the values
@pytest.mark.parametrize("tol, tangential", [(1e-10, 1e-7), (1e-12, 1e-7), (1e-6, 1e-6), (1e-7, 1e-7)])
def test_the_coupled_kinds_floor_the_tangential_tolerance_and_fix_the_coupling_one(tol, tangential):
    st = SolverSettings.from_scenario(_scenario(_partial_slip(tol)))
    assert st.kind == "partial_slip" and st.tolerance == tol and st.max_iterations == 10000
    assert st.tangential_tolerance == tangential == max(tol, S.TANGENTIAL_TOLERANCE)
    assert st.coupling_tolerance == 1e-6 == S.COUPLING_TOLERANCE
    assert st.onset_tolerance == 1e-3 == S.ONSET_TOLERANCE
    # the coupling loop's own inexact tolerances, recorded read-only
    assert st.predictor_tolerance == max(tangential, coupling.PREDICTOR_TOL) == 1e-3
    assert st.inexact_tangential_tolerance == coupling.INEXACT_TANGENTIAL == 1e-4
    assert st.inexact_normal_tolerance == coupling.INEXACT_NORMAL
    assert st.film_tolerance is None  # no [humidity]
    assert st.coupled_kw() == {"tol": tol, "max_iterations": 10000, "tangential_tol": tangential,
                               "coupling_tol": 1e-6, "normal_method": "normcg"}


@pytest.mark.parametrize("name", sorted(p.stem for p in EXAMPLES.glob("*.toml")))
def test_every_example_gets_the_documented_values_of_its_kind(name):
    sc = _scenario(_example(name))
    st = SolverSettings.from_scenario(sc)
    tol = sc.solver.tolerance
    assert st.kind == sc.kind and st.tolerance == tol and st.max_iterations == sc.solver.max_iterations
    assert st.method == sc.solver.method
    coupled = sc.kind in ("partial_slip", "hysteresis")
    assert st.coupled is coupled
    assert st.tangential_tolerance == (max(tol, 1e-7) if coupled else None)
    assert st.coupling_tolerance == (1e-6 if coupled else None)
    assert st.onset_tolerance == (1e-3 if sc.kind == "partial_slip" else None)
    assert st.film_tolerance == (max(tol, 1e-12) if sc.humidity is not None else None)
    adhesive = sc.adhesion.enabled or sc.humidity is not None
    if sc.kind == "pulloff" and sc.humidity is None:
        # the dry pull-off path picks its normal solver itself: no method to pass or record
        assert st.normal_method is None
        with pytest.raises(ValueError, match="takes no normal solver"):
            st.normal_kw()
    elif sc.solver.method == "auto":
        assert st.normal_method == ("polonsky_keer" if adhesive else "normcg")
    else:
        assert st.normal_method == sc.solver.method
    if not coupled:
        with pytest.raises(ValueError, match="does not solve the coupled problem"):
            st.coupled_kw()


@pytest.mark.parametrize("adhesion, method, expected", [
    (None, "auto", "normcg"), (DUGDALE, "auto", "polonsky_keer"),
    (None, "polonsky_keer", "polonsky_keer"), (DUGDALE, "normcg", "normcg")])
def test_the_normal_method_is_what_auto_stands_for(adhesion, method, expected):
    d = dict(NORMAL, solver={"method": method, "tolerance": 1e-9, "max_iterations": 500})
    if adhesion is not None:
        d["adhesion"] = adhesion
    st = SolverSettings.from_scenario(_scenario(d))
    assert st.normal_method == expected
    assert st.normal_kw() == {"tol": 1e-9, "max_iterations": 500, "method": expected}
    assert st.path_kw() == {"tol": 1e-9, "max_iterations": 500}
    assert st.tangential_tolerance is None and st.coupling_tolerance is None and st.predictor_tolerance is None


def test_the_settings_are_frozen_and_the_summary_holds_what_applies():
    st = SolverSettings.from_scenario(_scenario(NORMAL))
    with pytest.raises(AttributeError):
        st.tolerance = 1.0
    assert st.summary() == {"tolerance": 1e-10, "max_iterations": 10000, "method": "auto", "normal_method": "normcg",
                            "precision": "auto"}
    coupled = SolverSettings.from_scenario(_scenario(_partial_slip())).summary()
    assert coupled == {"tolerance": 1e-10, "max_iterations": 10000, "method": "auto", "normal_method": "normcg",
                       "tangential_tolerance": 1e-7, "coupling_tolerance": 1e-6, "onset_tolerance": 1e-3,
                       "predictor_tolerance": 1e-3, "inexact_tangential_tolerance": 1e-4,
                       "inexact_normal_tolerance": coupling.INEXACT_NORMAL}


# ----------------------------------------------------------------------------- carried to the solvers
class _Stop(Exception):
    pass


def _spy(monkeypatch, module, name, seen):
    def spy(*args, **kw):
        seen.append(kw)
        raise _Stop

    monkeypatch.setattr(module, name, spy)


class _Bar:
    def phase(self, *a):
        pass

    def __call__(self, *a):
        pass


def test_the_partial_slip_ramp_gets_the_settings_values(monkeypatch):
    from tribobem.runs import partial_slip

    pb = build_problem(_scenario(_partial_slip(1e-12)))
    settings = SolverSettings.from_scenario(pb.scenario)
    seen: list = []
    _spy(monkeypatch, partial_slip, "tangential_ramp", seen)
    with pytest.raises(_Stop):
        partial_slip.run(pb, _Bar(), settings)
    kw = seen[0]
    assert kw["tol"] == 1e-12 and kw["tangential_tol"] == 1e-7 and kw["coupling_tol"] == 1e-6
    assert kw["refine_tol"] == 1e-3 and kw["normal_method"] == "normcg" and kw["max_iterations"] == 10000
    assert "normal_method" not in pb.info  # nothing written into the built problem


def test_the_hysteresis_loop_gets_the_settings_values(monkeypatch):
    from tribobem.runs import hysteresis

    d = _example("hysteresis_mindlin")
    d["grid"]["n"] = 16
    d["solver"] = {"tolerance": 1e-6, "method": "polonsky_keer"}
    pb = build_problem(_scenario(d))
    seen: list = []
    _spy(monkeypatch, hysteresis, "hysteresis_loop", seen)
    with pytest.raises(_Stop):
        hysteresis.run(pb, _Bar())  # without settings: built from the scenario
    kw = seen[0]
    assert kw["tol"] == 1e-6 and kw["tangential_tol"] == 1e-6 and kw["coupling_tol"] == 1e-6
    assert kw["normal_method"] == "polonsky_keer" and "refine_tol" not in kw
    assert "normal_method" not in pb.info


def test_the_dry_pulloff_path_gets_no_method(monkeypatch):
    from tribobem.runs import pulloff

    d = _example("pulloff_sphere")
    d["grid"]["n"] = 16
    pb = build_problem(_scenario(d))
    seen: list = []
    _spy(monkeypatch, pulloff, "pull_off", seen)
    with pytest.raises(_Stop):
        pulloff.run(pb, _Bar(), SolverSettings.from_scenario(pb.scenario))
    assert seen[0]["tol"] == 1e-9 and seen[0]["max_iterations"] == 10000 and "method" not in seen[0]


def test_run_scenario_builds_the_settings_once_and_hands_them_to_the_runner(monkeypatch):
    from tribobem.runs import RUNNERS, normal

    got = []

    def runner(pb, bar, settings=None):
        got.append(settings)
        return normal.run(pb, bar, settings)

    monkeypatch.setitem(RUNNERS, "normal", runner)
    r = run_scenario(NORMAL, progress=False, warn=False)
    assert len(got) == 1 and got[0] == SolverSettings.from_scenario(r.problem.scenario)
    assert "normal_method" not in r.problem.info  # the runner wrote nothing into the problem


# ----------------------------------------------------------------------------- summary.json
def test_summary_records_the_effective_values(tmp_path):
    import json

    r = run_scenario(_partial_slip(1e-12), outdir=tmp_path, progress=False, warn=False)
    written = json.loads((tmp_path / "summary.json").read_text())
    for s in (r.summary, written):
        assert s["solver"]["tolerance"] == 1e-12
        assert s["solver"]["tangential_tolerance"] == 1e-7 and s["solver"]["coupling_tolerance"] == 1e-6
        assert s["solver"]["onset_tolerance"] == 1e-3 and s["solver"]["predictor_tolerance"] == 1e-3
        assert s["solver"]["normal_method"] == "normcg"
        assert s["problem"]["normal_method"] == "normcg"  # where summaries always had it


def test_summary_of_a_dry_pulloff_names_no_normal_method():
    d = _example("pulloff_sphere")
    d["grid"]["n"] = 32
    d["load"].update(steps=4, refine=1)
    d["output"] = {"fields": "none", "figures": False, "report": False}
    s = run_scenario(d, progress=False, warn=False).summary
    assert "normal_method" not in s["problem"] and "normal_method" not in s["solver"]
    assert s["solver"] == {"tolerance": 1e-9, "max_iterations": 10000, "method": "auto"}


# ----------------------------------------------------------------------------- the structure
def _kind_modules() -> set[str]:
    """runs/*.py modules that define a run kind (``KIND = RunKind(...)``)."""
    out = set()
    for p in RUNS.glob("*.py"):
        tree = ast.parse(p.read_text(encoding="utf-8"))
        if any(isinstance(n, ast.Assign) and any(getattr(t, "id", None) == "KIND" for t in n.targets)
               for n in tree.body):
            out.add(p.stem)
    return out


def test_the_kind_modules_are_found():
    assert _kind_modules() == set(KINDS)


def test_no_runs_module_imports_a_constant_from_another_kinds_module():
    """A constant (an UPPER_CASE name) that two kinds share lives in a module of no kind
    (runs.settings, runs.common, runs.kind), never in one kind's module read by another."""
    kinds = _kind_modules()
    bad = []
    for p in RUNS.glob("*.py"):
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom):
                continue
            mod = (node.module or "").rsplit(".", 1)[-1]
            local = node.level == 1 or (node.module or "").startswith("tribobem.runs.")
            if not local or mod not in kinds or mod == p.stem:
                continue
            bad += [f"runs/{p.name}: {a.name} from runs/{mod}.py" for a in node.names if a.name.isupper()]
    assert not bad, "constants imported across run kinds: " + "; ".join(bad)


def test_no_runner_writes_into_the_built_problem():
    """What a run did is in its RunOutput and its settings; the built Problem (``pb``) is read
    only: no assignment to ``pb.<attribute>`` or ``pb.<attribute>[...]`` and no mutating call on
    ``pb.info`` in runs/."""
    bad = []
    for p in RUNS.glob("*.py"):
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            targets = []
            if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in (
                    "update", "setdefault", "pop", "clear", "__setitem__"):
                targets = [node.func.value]
            for t in targets:
                while isinstance(t, (ast.Subscript, ast.Attribute)):
                    base = t.value
                    if isinstance(base, ast.Name) and base.id == "pb":
                        bad.append(f"runs/{p.name}:{node.lineno}")
                        break
                    t = base
    assert not bad, "runners write into the built problem at " + ", ".join(bad)


# ----------------------------------------------------------------------------- [solver] precision
def test_precision_reaches_the_normal_solves_and_single_is_refused_elsewhere(monkeypatch):
    from tribobem.errors import InputError
    from tribobem.solvers import normal as normal_mod

    d = copy.deepcopy(NORMAL)
    d["solver"] = {"precision": "single"}
    sc = _scenario(d)
    st = SolverSettings.from_scenario(sc)
    assert st.normal_run_kw()["precision"] == "single" and st.summary()["precision"] == "single"
    seen: list = []
    real = normal_mod.solve_normal

    def spy(*a, **kw):
        seen.append(kw)
        return real(*a, **kw)

    monkeypatch.setattr("tribobem.runs.normal.solve_normal", spy)
    m = run_scenario(sc, progress=False)
    assert seen and seen[0]["precision"] == "single"
    assert m.summary["solver"]["precision"] == "single"
    with pytest.raises(InputError, match="solver.precision"):
        _scenario({**d, "adhesion": DUGDALE})
    pull = _example("pulloff_sphere")
    pull["solver"] = {"precision": "single"}
    with pytest.raises(InputError, match="solver.precision"):
        _scenario(pull)
