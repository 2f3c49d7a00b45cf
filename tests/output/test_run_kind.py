"""The outputs follow the run kind: figures, report and the CLI's step table read summary.json's
``kind`` and the sections the run used (:mod:`tribobem.output.run_kind`), and the columns the
:class:`~tribobem.runs.kind.RunKind` declares, never the step rows' keys; ``tribobem plot``
keeps working on result folders whose summary lacks the scenario echo (earlier or hand-made)."""

from __future__ import annotations

import copy
import json
import re
import shutil
import tomllib
from pathlib import Path

import pytest

from tribobem.output.run_kind import FRICTION_KINDS, run_view, used_humidity
from tribobem.runs import KINDS

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src" / "tribobem"
EXAMPLES = ROOT / "examples"

#: What deciding the kind from the step rows looked like (the old predicates included).
SNIFFING = (
    re.compile(r"""["'](tangential_force_x|capillary_force|cycle|rh)["']\s+in\s+(s|r|row|step)\b"""),
    re.compile(r"\bis_(hysteresis|humid_friction|capillary|humid_pulloff)\("),
)


def _output_sources():
    yield from sorted((SRC / "output").rglob("*.py"))
    yield SRC / "cli.py"


def test_no_output_module_guesses_the_kind_from_step_keys():
    found = []
    for path in _output_sources():
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if any(p.search(line) for p in SNIFFING):
                found.append(f"{path.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not found, "outputs deciding the kind from step keys:\n" + "\n".join(found)


# --------------------------------------------------------------------------- run_view
def test_run_view_reads_the_kind_and_the_humidity_echo():
    dry = {"kind": "partial_slip", "inputs": {"humidity": None}, "steps": [{"rh": 0.3}]}
    assert run_view(dry).friction and not run_view(dry).humid and not run_view(dry).humid_friction
    humid = {"kind": "hysteresis", "inputs": {"humidity": {"rh": [0.3, 0.5]}}, "rh": [0.3, 0.5], "steps": []}
    v = run_view(humid)
    assert v.hysteresis and v.humid and v.humid_friction and v.rh_steps and not v.capillary
    one_rh = dict(humid, rh=0.5)  # tribobem.output.humid.rh_summary's one-RH view
    assert run_view(one_rh).hysteresis and not run_view(one_rh).humid_friction
    pulloff = {"kind": "pulloff", "inputs": {"humidity": {"rh": [0.3]}}}
    assert run_view(pulloff).humid_pulloff and run_view(pulloff).capillary
    assert not run_view({"kind": "pulloff", "inputs": {"humidity": None}}).capillary
    assert run_view({"kind": "capillary"}).capillary and run_view({"kind": "capillary"}).rh_steps
    assert run_view(None).kind is None and not run_view(None).humid
    assert set(FRICTION_KINDS) <= set(KINDS)


def test_used_humidity_without_the_scenario_echo():
    """A summary without ``inputs``: the humidity inputs of ``problem`` or a run-level RH list."""
    assert used_humidity({"problem": {"humidity": {"water": "x"}}})
    assert used_humidity({"rh": [0.3, 0.7]})
    assert not used_humidity({"rh": 0.3}) and not used_humidity({}) and not used_humidity(None)
    # the echo wins where it is there
    assert not used_humidity({"inputs": {"humidity": None}, "rh": [0.3]})


# --------------------------------------------------------------------------- declared columns
def _tiny(example: str, **changes) -> dict:
    """An example scenario on a 16 x 16 grid with few steps and no files (a few seconds)."""
    sc = tomllib.loads((EXAMPLES / f"{example}.toml").read_text(encoding="utf-8"))
    sc.pop("expected", None)
    sc["grid"]["n"] = 16
    sc["output"] = {"figures": False, "report": False, "fields": "none"}
    for key, value in changes.items():
        section, _, name = key.partition("__")
        sc.setdefault(section, {})[name] = value
    return sc


def _humid_hysteresis() -> dict:
    sc = _tiny("partial_slip_humid_sphere")
    sc["kind"] = "hysteresis"
    fr = sc["friction"]
    sc["friction"] = {"coefficient": fr["coefficient"], "path": {"control": "force", "amplitude": 0.6, "cycles": 1,
                                                                 "steps": 6}}
    sc["humidity"]["rh"] = sc["humidity"]["rh"][:1]
    return sc


#: (kind, with [humidity]) -> a tiny scenario of it.
TINY = {
    ("normal", False): lambda: _tiny("hertz_free_boundary", load__forces=["1 uN", "5 uN"]),
    ("pulloff", False): lambda: _tiny("pulloff_sphere", load__steps=4, load__refine=0),
    ("pulloff", True): lambda: _tiny("pulloff_humid_sphere", load__steps=4, load__refine=0, humidity__rh=[0.5]),
    ("partial_slip", False): lambda: _tiny("partial_slip_paper_d",
                                           friction__tangential_forces={"start": "0 uN", "stop": "1 uN", "num": 3}),
    ("partial_slip", True): lambda: _tiny("partial_slip_humid_sphere"),
    ("hysteresis", False): lambda: _tiny("hysteresis_mindlin", friction__path={"control": "force", "amplitude": 0.8,
                                                                               "cycles": 1, "steps": 6}),
    ("hysteresis", True): _humid_hysteresis,
    ("capillary", True): lambda: _tiny("capillary_rough_sio2", humidity__rh=[0.5, 0.9]),
}


def test_every_kind_has_a_tiny_run_here():
    kinds = {k for k, _ in TINY}
    assert kinds == set(KINDS), "add a tiny scenario of each new kind to TINY"


@pytest.mark.filterwarnings("ignore")  # the tiny grids resolve nothing: their resolution warnings say so
@pytest.mark.parametrize("kind, humid", list(TINY), ids=[f"{k}{'-humid' if h else ''}" for k, h in TINY])
def test_declared_columns_are_in_every_row(kind, humid):
    """Each column the kind declares for the CLI's step table is a key of every step row."""
    from tribobem.cli import _step_table_columns
    from tribobem.scenario import run_scenario

    sc = TINY[(kind, humid)]()
    if not humid:
        sc.pop("humidity", None)
    summary = run_scenario(sc, progress=False, quiet=True).summary
    view = run_view(summary)
    assert view.kind == kind and view.humid == humid
    columns = KINDS[kind].step_columns(humid)
    assert [c[0] for c in _step_table_columns(summary)] == list(columns)
    rows = summary["steps"]
    assert rows
    missing = {c: [r.get("index") for r in rows if c not in r] for c in columns}
    assert not any(missing.values()), f"declared columns missing from rows: {missing}"


def test_step_columns_per_kind():
    """The CLI columns of each kind, as before the kind declared them (ids of the old branches)."""
    from tribobem.runs.kind import CAPILLARY_COLUMNS, NORMAL_COLUMNS, TANGENTIAL_COLUMNS

    assert KINDS["normal"].step_columns(False) == NORMAL_COLUMNS
    assert KINDS["pulloff"].step_columns(False) == NORMAL_COLUMNS
    assert KINDS["pulloff"].step_columns(True) == CAPILLARY_COLUMNS
    for k in FRICTION_KINDS:
        assert KINDS[k].step_columns(False) == TANGENTIAL_COLUMNS
        assert KINDS[k].step_columns(True) == ("rh",) + TANGENTIAL_COLUMNS
    assert KINDS["capillary"].step_columns(True) == CAPILLARY_COLUMNS


# --------------------------------------------------------------------------- older result folders
def _old_shape(summary: dict) -> dict:
    """The summary as a version without the scenario echo's ``humidity`` wrote it."""
    s = copy.deepcopy(summary)
    (s.get("inputs") or {}).pop("humidity", None)
    return s


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("kind, humid", [("partial_slip", True), ("pulloff", True), ("hysteresis", False)],
                         ids=["partial_slip-humid", "pulloff-humid", "hysteresis"])
def test_plot_remakes_an_older_folder(tmp_path, kind, humid):
    """``tribobem plot`` on a folder whose summary lacks ``inputs.humidity`` makes the same figures."""
    from typer.testing import CliRunner

    from tribobem.cli import app
    from tribobem.scenario import run_scenario

    sc = TINY[(kind, humid)]()
    sc["output"] = {"figures": True, "report": True, "fields": "all"}
    new = tmp_path / "new"
    run_scenario(sc, outdir=new, progress=False, quiet=True)
    old = tmp_path / "old"
    shutil.copytree(new, old)
    summary = json.loads((old / "summary.json").read_text(encoding="utf-8"))
    (old / "summary.json").write_text(json.dumps(_old_shape(summary)), encoding="utf-8")
    for png in old.glob("*.png"):
        png.unlink()
    (old / "report.html").unlink()

    result = CliRunner().invoke(app, ["plot", str(old), "--quiet"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in old.glob("*.png")) == sorted(p.name for p in new.glob("*.png"))
    assert (old / "report.html").is_file()
