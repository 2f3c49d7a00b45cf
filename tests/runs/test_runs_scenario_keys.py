"""The solver boundary: solvers raise errors naming their own arguments (``"<function>.<argument>"``),
the runners translate them into scenario keys (``tribobem.runs.common.SCENARIO_KEYS``), so that a
scenario user reads the key and the message they always did."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import tribobem
from tribobem.errors import InputError
from tribobem.runs import KINDS
from tribobem.runs.common import SCENARIO_KEYS, scenario_errors, scenario_keys, translate_error
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.normal_paths import pull_off
from tribobem.solvers.tangential import GrossSlipError, solve_tangential
from tribobem.validation.tangential import cattaneo_problem

SRC = Path(tribobem.__file__).parent
#: The scenario sections a solver's key must not start with.
SECTIONS = ("solver", "load", "friction", "humidity", "film", "adhesion")
#: Keys still raised under a scenario section, and why: the operator factories run when the
#: scenario is built (scenario/build.py, outside the runners); GrossSlipError reports a physical
#: outcome of the load (beyond mu P), not a bad argument; the bare sections name no argument
#: (``give exactly one of force or displacement``).
KEPT = {"solver.fft", "solver.backend", "solver.kernel", "friction.tangential_force", "friction.path.amplitude",
        "load", "friction", "humidity", "adhesion"}


def _raised_keys(path: Path) -> set[str]:
    text = path.read_text()
    keys = set(re.findall(r'(?:Input|GrossSlip)Error\(\s*f?"([^"{]+)"', text))
    keys |= set(re.findall(r'_as_pair\([^,]+,\s*"([^"]+)"\)', text))
    return keys


def _solver_files():
    files = [p for p in (SRC / "solvers").glob("*.py") if p.name != "window.py"]
    return files + list((SRC / "elasticity").glob("*.py")) + [SRC / "interactions" / "films.py"]


def test_solvers_raise_no_scenario_key():
    bad = {}
    for p in _solver_files():
        for k in _raised_keys(p):
            if k.split(".")[0] in SECTIONS and k not in KEPT:
                bad.setdefault(p.name, []).append(k)
    assert not bad, f"solver errors named by scenario keys (name the argument, translate in runs/): {bad}"


def test_every_translated_key_is_raised_by_a_solver():
    raised = set().union(*(_raised_keys(p) for p in _solver_files()))
    raised |= {f"film_thickness.{n}" for n in ("duration", "steady_tolerance", "step_tolerance", "viscosity")}
    stale = set(SCENARIO_KEYS) - raised
    assert not stale, f"SCENARIO_KEYS entries no solver raises: {sorted(stale)}"
    assert all(k.count(".") == 1 for k in SCENARIO_KEYS), "solver keys are <function>.<argument>"


def test_translate_error_renames_the_field_and_quoted_errors_in_place():
    inner = InputError("solve_normal.force", "must be > 0 N without adhesion, got 0.0")
    outer = InputError("pull_off.preload", f"the preload cannot be reached: {inner}")
    got = translate_error(outer)
    assert got is outer and type(got) is InputError
    assert outer.field == "load.preload"
    assert str(outer) == "load.preload: the preload cannot be reached: load.force: must be > 0 N without adhesion, got 0.0"
    assert outer.reason == "the preload cannot be reached: load.force: must be > 0 N without adhesion, got 0.0"
    # unknown keys and text that merely mentions a key stay
    other = InputError("gap", "see solve_normal.force (not quoted as an error)")
    assert str(translate_error(other)) == "gap: see solve_normal.force (not quoted as an error)"


def test_translation_keeps_the_subclass_and_its_attributes():
    err = GrossSlipError("friction.tangential_force", "too large", 2.0)
    with pytest.raises(GrossSlipError) as got:
        with scenario_keys({"friction.tangential_force": "friction.path.amplitude"}):
            raise err
    assert got.value is err and got.value.field == "friction.path.amplitude"
    assert str(got.value) == "friction.path.amplitude: too large" and got.value.max_force == 2.0


@pytest.fixture(scope="module")
def catt():
    grid, gap, op, pair, a = cattaneo_problem(16)
    return op, gap, solve_normal(op, gap, force=10.0, tol=1e-10)


@pytest.mark.parametrize("kw,library,scenario,text", [
    ({"method": "newton"}, "solve_tangential.method", "solver.tangential_method",
     "must be 'tangcg' or 'fista', got 'newton'"),
    ({"preconditioner": "ilu"}, "solve_tangential.preconditioner", "solver.tangential_preconditioner",
     "must be 'diagonal' or 'fft', got 'ilu'"),
    ({"tol": 0.0}, "solve_tangential.tol", "solver.tolerance", "must be a finite value > 0, got 0.0"),
    ({"friction_coefficient": -1.0}, "solve_tangential.friction_coefficient", "friction.coefficient",
     "must be a finite number >= 0, got -1.0"),
])
def test_solve_tangential_names_its_argument_and_a_runner_the_scenario_key(catt, kw, library, scenario, text):
    op, gap, nr = catt
    args = dict(friction_coefficient=0.3, force=(1.0, 0.0)) | kw
    with pytest.raises(InputError) as lib:
        solve_tangential(op, nr.pressure, nr.contact, **args)
    assert lib.value.field == library and lib.value.reason == text
    with pytest.raises(InputError) as sc:
        with scenario_keys():
            solve_tangential(op, nr.pressure, nr.contact, **args)
    assert sc.value.field == scenario and str(sc.value) == f"{scenario}: {text}"


def test_solve_normal_method_and_a_decorated_runner(catt):
    op, gap, _ = catt

    @scenario_errors
    def run(pb, bar):
        """A runner."""
        return solve_normal(op, gap, force=1.0, method="newton")

    with pytest.raises(InputError, match=r"^solve_normal\.method: must be 'auto'"):
        solve_normal(op, gap, force=1.0, method="newton")
    with pytest.raises(InputError, match=r"^solver\.method: must be 'auto', 'polonsky_keer' or 'normcg', got 'newton'$"):
        run(None, None)
    assert run.__doc__ == "A runner."


@pytest.mark.parametrize("kw,text", [
    ({"tol": -1.0}, "solver.tolerance: must be a finite value > 0, got -1.0"),
    ({"preload": -1.0}, "load.preload: must be > 0 N (or left out: zero external load), got -1.0"),
])
def test_a_load_path_error_reads_as_before_in_a_scenario(catt, kw, text):
    """pull_off's own key and that of the normal solve under it: the scenario messages of old."""
    from tribobem.interactions import DugdaleAdhesion

    op, gap, _ = catt
    law = DugdaleAdhesion(work_of_adhesion=0.05, z0=1e-9)
    args = {"preload": 1.0, "control": "force", "start": "force"} | kw
    with pytest.raises(InputError) as exc:
        with scenario_keys():
            pull_off(op, gap, law, **args)
    assert str(exc.value) == text


def test_every_kind_runner_translates():
    for name, kind in KINDS.items():
        assert getattr(kind.run, "__wrapped__", None) is not None, f"kind {name!r}: runner not @scenario_errors"
