"""tribobem.runs: the registry kind -> runner."""

import pytest

from tribobem.errors import InputError
from tribobem.runs import RUNNERS, NotImplementedKindError, get_runner
from tribobem.scenario import IMPLEMENTED_KINDS, KINDS
from tribobem.scenario import run as run_module


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
    """A runner's optional "tangential" list is selected together with "results" and handed to
    build_fields; the normal kinds pass nothing."""
    import tribobem.output.fields as fields_module
    from tribobem.runs import normal
    from tribobem.scenario import run_scenario

    seen = {}
    original = fields_module.build_fields

    def spy(*args, **kw):
        seen["tangential"] = kw.pop("tangential", None)
        return original(*args, **kw)

    def with_tangential(pb, bar):
        out = normal.run(pb, bar)
        out["tangential"] = [f"T{i}" for i in range(len(out["results"]))]
        return out

    monkeypatch.setattr(fields_module, "build_fields", spy)
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
