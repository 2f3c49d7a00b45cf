"""The tribobem command line (Typer), driven through typer.testing.CliRunner."""

import json
import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tribobem.cli import app

REPO = Path(__file__).resolve().parents[1]
DATA_DIR = Path(os.environ.get("TRIBOBEM_DATA_DIR") or REPO.parent / "shared/data/topographies")
PARK = DATA_DIR / "example_ps.tiff"
needs_park = pytest.mark.skipif(not PARK.is_file(), reason="shared topography folder not present")
EXAMPLES = sorted((REPO / "examples").glob("*.toml"))

runner = CliRunner()


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


def _one_line_error(result):
    out = result.output.strip()
    assert result.exit_code == 2, out
    assert "Traceback" not in out
    assert len(out.splitlines()) == 1, out
    assert out.startswith("error:") or out.startswith("memory:"), out
    return out


def test_help_lists_the_commands():
    r = invoke("--help")
    assert r.exit_code == 0
    for cmd in ("demo", "run", "sweep", "validate", "info", "plot"):
        assert cmd in r.output


def test_demo_small(tmp_path):
    out = tmp_path / "demo"
    r = invoke("demo", "--small", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    assert (out / "report.html").is_file() and (out / "summary.json").is_file() and (out / "fields.nc").is_file()
    assert str(out / "report.html") in r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["kind"] == "pulloff" and s["pull_off_force"] is not None and s["pull_off_force"] <= 0
    assert s["inputs"]["grid"]["n"] == 32


def test_demo_falls_back_to_a_generated_surface(monkeypatch):
    import tribobem.cli as cli

    monkeypatch.setattr(cli, "find_data_dir", lambda: None)
    sc, where = cli.demo_scenario(small=True)
    assert sc["body1"]["roughness"]["kind"] == "gaussian" and "generated" in where
    from tribobem.scenario import parse_scenario

    parse_scenario(sc)


@needs_park
def test_demo_uses_the_park_scan():
    import tribobem.cli as cli

    sc, where = cli.demo_scenario()
    assert sc["body1"]["roughness"]["kind"] == "file"
    assert Path(sc["body1"]["roughness"]["path"]).name == "example_ps.tiff"


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD = """
kind = "normal"
[grid]
n = 16
size = "0.5 um"
[body1]
E = "130 GPa"
nu = 0.28
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[load]
forces = ["1 uN", "2 uN"]
[output]
figures = false
"""


def test_run_json_and_outputs(tmp_path):
    p = _write(tmp_path, GOOD)
    out = tmp_path / "res"
    r = runner.invoke(app, ["run", str(p), "--out", str(out), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["kind"] == "normal" and len(s["steps"]) == 2 and s["converged"] is True
    assert (out / "summary.json").is_file() and (out / "fields.nc").is_file()


def test_run_prints_a_table(tmp_path):
    p = _write(tmp_path, GOOD)
    r = invoke("run", p, "--out", tmp_path / "res2")
    assert r.exit_code == 0, r.output
    assert "tribobem normal run" in r.output and "report" in r.output


@pytest.mark.parametrize(
    "text, words",
    [
        (GOOD.replace('n = 16', 'n = 16\ncolour = "red"'), ["grid.colour", "unknown key", "allowed keys"]),
        (GOOD.replace('forces = ["1 uN", "2 uN"]', 'force = "3 nm"'), ["load.force", "expected a force (N)", "3 nm"]),
        (GOOD.replace("nu = 0.28", "nu = 0.8"), ["body1.nu", "(-1, 0.5]"]),
        (GOOD.replace('kind = "normal"', 'kind = "capillary"').replace(
            'forces = ["1 uN", "2 uN"]', 'force = "1 uN"\n[humidity]\nrh = [0.5]'),
         ["not implemented yet in this version"]),
        ("kind = \n", ["not valid TOML"]),
        (GOOD.replace("n = 16", "n = 131072"), ["GiB"]),
    ],
)
def test_bad_scenarios_exit_2_with_one_line(tmp_path, text, words):
    p = _write(tmp_path, text)
    msg = _one_line_error(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "res")]))
    for w in words:
        assert w in msg, msg


def test_missing_files_exit_2(tmp_path):
    assert "not found" in _one_line_error(runner.invoke(app, ["run", str(tmp_path / "nope.toml")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["info", str(tmp_path / "nope.tiff")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["plot", str(tmp_path / "nope")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["sweep", str(tmp_path / "nope.toml")]))
    p = _write(tmp_path, GOOD.replace('[body2]', '[body2]\nroughness = { kind = "file", path = "missing.tiff" }'))
    assert "missing.tiff" in _one_line_error(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "r")]))


def test_unreadable_topography_exits_2(tmp_path):
    bad = tmp_path / "bad.tiff"
    bad.write_bytes(b"\x00not an image")
    msg = _one_line_error(runner.invoke(app, ["info", str(bad)]))
    assert "bad.tiff" in msg


@needs_park
def test_info_on_the_park_scan():
    r = invoke("info", PARK, "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["grid"] == [512, 512]
    assert d["physical_size"][0] == pytest.approx(1e-6)
    assert d["rms_height"] == pytest.approx(3.933e-9, rel=0.01)  # shared/data README
    assert d["rms_slope"] == pytest.approx(0.385, rel=0.05)
    for key in ("skewness", "kurtosis", "correlation_length", "unit"):
        assert key in d
    r = invoke("info", PARK)
    assert r.exit_code == 0 and "rms height" in r.output and "correlation length" in r.output


def test_plot_remakes_the_report(tmp_path):
    p = _write(tmp_path, GOOD.replace("figures = false", "figures = true"))
    out = tmp_path / "res"
    assert invoke("run", p, "--out", out, "--quiet").exit_code == 0
    (out / "report.html").unlink()
    r = invoke("plot", out)
    assert r.exit_code == 0, r.output
    assert (out / "report.html").is_file() and "pressure" in r.output


class _Row:
    def __init__(self, case, passed):
        self.case, self.quantity, self.reference, self.computed = case, "a", 1.0, 1.0 if passed else 1.5
        self.rel_error, self.tolerance, self.passed = (0.0 if passed else 0.5), 0.01, passed


@pytest.fixture
def fake_validation(monkeypatch):
    import sys
    import types

    mod = types.ModuleType("tribobem.validation")
    state = {"rows": [_Row("hertz", True)]}
    mod.run_validation = lambda quick=True, cases=None: state["rows"]
    monkeypatch.setitem(sys.modules, "tribobem.validation", mod)
    return state


def test_validate_table_json_and_exit_codes(fake_validation):
    r = invoke("validate", "--quick")
    assert r.exit_code == 0 and "hertz" in r.output and "pass" in r.output
    r = runner.invoke(app, ["validate", "--json"])
    assert r.exit_code == 0 and json.loads(r.stdout)["rows"][0]["case"] == "hertz"
    fake_validation["rows"].append(_Row("jkr", False))
    r = invoke("validate", "--full")
    assert r.exit_code == 1 and "FAIL" in r.output


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.stem for e in EXAMPLES])
def test_every_example_runs(example):
    if "shared/data" in example.read_text() and not PARK.is_file():
        pytest.skip("shared topography folder not present")
    from tribobem.scenario import run_scenario

    r = run_scenario(example, outdir=None, progress=False)
    assert r.converged, r.summary["warnings"]
    assert r.steps


def test_examples_exist():
    names = {e.stem for e in EXAMPLES}
    assert {"hertz_free_boundary", "rough_periodic", "afm_park_normal", "pulloff_sphere"} <= names
