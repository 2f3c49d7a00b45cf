"""Every example scenario states what it produces, and produces it (issue 9 item 2).

Each ``examples/*.toml`` carries ``expected = {<summary key> = value, reference, tolerance}``:
the test runs it and checks every stated value within the stated tolerance.  A resolved example
raises no result-check warning at all; one that cannot be resolved lists the checks it raises in
``expected.warnings`` (the Park AFM scan pull-off, the Gaussian rough ball, the CI-sized Paper F
loop), and the test requires them.  Also: the ``expected`` schema, and the pull-off scenario
without a preload.
"""

from __future__ import annotations

import time
import tomllib
import warnings
from pathlib import Path

import pytest

from tribobem import ConvergenceWarning
from tribobem.output.checks import warning_names
from tribobem.scenario import parse_scenario, run_scenario
from tribobem.scenario.schema import ScenarioError

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((REPO / "examples").glob("*.toml"))

#: Examples over ~20 s of CPU on a shared 2-core machine run with the slow tests.
SLOW = {"partial_slip_paper_d", "pulloff_afm_park_levels", "normal_coated_paper_c"}


def _params():
    return [pytest.param(p, id=p.stem, marks=[pytest.mark.slow] if p.stem in SLOW else []) for p in EXAMPLES]


def _run(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return run_scenario(path, outdir=None, progress=False)


def test_there_are_examples_and_each_states_its_expectation():
    assert len(EXAMPLES) >= 8
    for path in EXAMPLES:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
        assert "expected" in data, f"{path.name} states no expected value"
        exp = parse_scenario(data, str(path)).expected
        assert exp.reference.strip()
        assert exp.values or exp.warnings


@pytest.mark.parametrize("path", _params())
def test_example_meets_its_expectation(path):
    t0 = time.process_time()
    r = _run(path)
    cpu = time.process_time() - t0
    s = r.summary
    assert r.converged, s["warnings"]
    exp = s["expected"]
    assert exp is not None
    for row in exp["values"]:
        assert row["within"], (f"{path.name}: {row['key']} ({row['where']}) computed {row['computed']!r}, expected "
                               f"{row['expected']!r} +- {100 * exp['tolerance']:g} % ({exp['reference']})")
    fired = warning_names(s["warnings"])
    stated = [w["name"] for w in exp["warnings"]]
    if stated:
        # an example that cannot be resolved says which checks fire, and they do
        missing = [w for w in stated if w not in fired]
        assert not missing, f"{path.name}: expected warnings {missing} did not fire (fired: {fired})"
    else:
        assert fired == [], f"{path.name} is not resolved: {s['warnings']}"
    assert exp["met"]
    if path.stem not in SLOW:
        assert cpu < 60, f"{path.name} took {cpu:.0f} s of CPU"


def test_unresolved_examples_say_so_in_their_comments():
    for path in EXAMPLES:
        data = tomllib.loads(path.read_text())
        if data["expected"].get("warnings"):
            assert "resolved" in path.read_text().lower(), path.name


# ----------------------------------------------------------------------------- the expected schema
BASE = {"kind": "pulloff", "grid": {"n": 32, "size": "0.16 um"}, "body1": {"E": "5 GPa", "nu": 0.0},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}},
        "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.5 nm"}}


@pytest.mark.parametrize("expected, field, text", [
    ({"pull_off_force": "-0.25 um", "reference": "MD", "tolerance": "3 %"}, "expected.pull_off_force", "force"),
    ({"pull_off_force": "-0.25 uN", "reference": "MD"}, "expected.tolerance", "required"),
    ({"pull_off_force": "-0.25 uN", "tolerance": "3 %"}, "expected.reference", "required"),
    ({"reference": "MD"}, "expected", "at least one"),
    ({"pull_off_forces": "-0.25 uN", "reference": "MD", "tolerance": 0.03}, "expected.pull_off_forces", "unknown"),
    ({"warnings": ["edges"], "reference": "q"}, "expected.warnings[0]", "must be one of"),
    ({"pull_off_force": "-0.25 uN", "reference": "MD", "tolerance": "300 %"}, "expected.tolerance", "(0, 1)"),
])
def test_expected_is_validated(expected, field, text):
    with pytest.raises(ScenarioError) as err:
        parse_scenario(dict(BASE, expected=expected))
    assert err.value.field == field and text in str(err.value)


def test_expected_values_are_converted_to_si():
    sc = parse_scenario(dict(BASE, expected={"pull_off_force": "-0.25 uN", "contact_area": "2e4 nm^2", "step": -2,
                                             "reference": "MD", "tolerance": "3 %"}))
    assert sc.expected.values == {"pull_off_force": pytest.approx(-2.5e-7), "contact_area": pytest.approx(2e-14)}
    assert sc.expected.tolerance == pytest.approx(0.03) and sc.expected.step == -2
    assert parse_scenario(BASE).expected is None


# ----------------------------------------------------------------------------- pull-off without a preload
def test_pulloff_without_preload_starts_at_zero_external_load():
    """load.preload left out: the unloading starts from the adhesive equilibrium at F = 0 (the
    summary says so), and on a sphere (one contact branch) the pull-off is the one from a
    compressive preload, to 1 %: examples/pulloff_sphere.toml with and without its preload."""
    with open(REPO / "examples" / "pulloff_sphere.toml", "rb") as fh:
        data = tomllib.load(fh)
    pre = _run(dict(data)).summary
    load = dict(data["load"])
    del load["preload"]
    zero = _run(dict(data, load=load)).summary
    assert pre["preload_source"] == "load.preload" and pre["preload"] == pytest.approx(0.3e-6, rel=1e-3)
    assert zero["preload_source"].startswith("zero external load") and abs(zero["preload"]) < 1e-3 * 0.3e-6
    assert zero["pull_off_force"] == pytest.approx(pre["pull_off_force"], rel=0.01)
    assert zero["expected"]["met"] and zero["warnings"] == []
    # the unloading curve starts at the preload state
    first = [st for st in zero["steps"] if st["branch"] == "unloading"][0]
    assert first["normal_force"] == pytest.approx(zero["preload"], abs=1e-15)
